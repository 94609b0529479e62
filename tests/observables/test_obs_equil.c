/* Stored series (rl_trace), jackknife helpers and automated equilibration detection: the
 * statistical inefficiency against a hand computation, Chodera's detection on exponential
 * relaxations plus AR(1) noise (the start lands where the transient has decayed to the noise),
 * the trace's moments, blocking and groups against direct computations, and the RDF's and
 * correlation functions' starts within a run. */
#include "../testutil.h"

#include <gsl/gsl_sort.h>
#include <stdlib.h>

/* x_t = A exp(-t / tau) + y_t, y an AR(1) series of unit variance and coefficient phi. */
static void transient(gsl_rng *rng, double *x, long n, double A, double tau, double phi)
{
  double y = gsl_ran_gaussian(rng, 1.0);
  for (long t = 0; t < n; t++) {
    if (t) y = phi * y + gsl_ran_gaussian(rng, sqrt(1.0 - phi * phi));
    x[t] = A * exp(-(double)t / tau) + y;
  }
}

/* ------------------------------------------------------------------ statistical inefficiency */

static void inefficiency_by_hand(void **state)
{
  (void)state;
  /* x = 0 1 2 3 4 4 3 2 1 0 0 1 (n = 12): mean 7/4, dx = x - 7/4, sigma^2 = sum dx^2 / 12 = 97/48.
   * Lag sums S(t) = sum_{i < 12 - t} dx_i dx_{i+t}: S(1) = 287/16, S(2) = 53/8, S(3) = -79/16,
   * S(4) = -13; C(t) = S(t) / ((12 - t) sigma^2): C(1) = 861/1067, C(2) = 159/485,
   * C(3) = -79/291 (negative, but t = 3 is not > 3: it is summed), C(4) = -78/97 (stop).
   * g = 1 + 2 [C(1) 11/12 + C(2) 10/12 + C(3) 9/12] = 254/97. */
  const double x[12] = {0, 1, 2, 3, 4, 4, 3, 2, 1, 0, 0, 1};
  double g = 0.0;
  assert_int_equal(rl_statistical_inefficiency(x, 12, &g), RL_OK);
  CHECK_LE("g of the hand-computed series vs 254/97", fabs(g - 254.0 / 97.0), 1e-14);
  /* by hand again, as the formula reads */
  const double C1 = 861.0 / 1067.0, C2 = 159.0 / 485.0, C3 = -79.0 / 291.0;
  CHECK_LE("254/97 = 1 + 2 sum C(t)(1 - t/n)", fabs(254.0 / 97.0 - (1.0 + 2.0 * (C1 * 11 + C2 * 10 + C3 * 9) / 12.0)),
           1e-14);
  /* an alternating series has C(1) < 0 at once: g = 1 + 2 sum ... < 1 is set to 1 */
  const double alt[10] = {1, 2, 4, 5, 4, 2, 1, 2, 4, 5};
  assert_int_equal(rl_statistical_inefficiency(alt, 10, &g), RL_OK);
  CHECK_NEAR("g below 1 is set to 1 (x = 1 2 4 5 4 2 1 2 4 5: -6/11 by hand)", g, 1.0, 0.0);
  const double flat[4] = {3, 3, 3, 3};
  assert_int_equal(rl_statistical_inefficiency(flat, 4, &g), RL_EINVAL);
  /* AR(1): g = (1 + phi) / (1 - phi) */
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 3);
  const long n = 200000;
  double *y = malloc(sizeof *y * (size_t)n);
  transient(rng, y, n, 0.0, 1.0, 0.8);
  assert_int_equal(rl_statistical_inefficiency(y, n, &g), RL_OK);
  printf("check AR(1) phi = 0.8: g = %.3f (exact 9)\n", g);
  CHECK_LE("AR(1) g vs (1 + phi)/(1 - phi) = 9, relative", fabs(g - 9.0) / 9.0, 0.05);
  free(y);
  gsl_rng_free(rng);
}

/* ------------------------------------------------------------------ detection */

static void detection_on_transients(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 11);
  /* A = 20 noise sds relaxing with tau = 100 samples, AR(1) noise phi = 0.8 (g = 9).  Where the
   * start should land: after the transient has decayed to about the noise (tau ln A = 300
   * samples), never keeping a transient above 1.5 noise sds, and, as N_eff(t0) is flat beyond
   * the transient and g is estimated with some 15 % noise, anywhere within a few hundred samples
   * after that (numpy's version of pymbar's algorithm on 12 such series: 299 to 500).  Over 12
   * series: the transient each start leaves biases the mean by less than its standard error
   * (Chodera's trade of bias against samples), no start discards half the run, and the median
   * lies where the transient is 0.02 to 1.5 noise sds (t0 = 259 to 690). */
  const long n = 4000;
  const double A = 20.0, tau = 100.0;
  double *x = malloc(sizeof *x * (size_t)n), raw[12], coarse[12];
  for (int s = 0; s < 12; s++) {
    transient(rng, x, n, A, tau, 0.8);
    long t0 = -1;
    double g = 0.0, neff = 0.0;
    assert_int_equal(rl_detect_equilibration(x, n, 1, n / 2, &t0, &g, &neff), RL_OK);
    CHECK_LE("N_eff = (n - t0) / g", fabs(neff - (n - t0) / g), 1e-9 * neff);
    /* the trace's version: means of 4 samples, starts up to half the run */
    rl_trace *tr = rl_trace_alloc(0);
    for (long t = 0; t < n; t++) assert_int_equal(rl_trace_add(tr, x[t]), RL_OK);
    long t1 = -1, len = 0;
    int limit = 1;
    assert_int_equal(rl_trace_equilibration(tr, 1000, 0.5, &t1, &len, NULL, NULL, &limit), RL_OK);
    assert_int_equal(len, 4);
    assert_false(limit);
    rl_trace_free(tr);
    printf("check transient %2d: t0 = %4ld (transient there %.3f noise sds, g = %5.2f, N_eff = %.1f); in means of 4: "
           "t0 = %4ld (%.3f)\n", s, t0, A * exp(-t0 / tau), g, neff, t1, A * exp(-t1 / tau));
    /* the transient left after a start biases the mean by A tau e^{-t0/tau} / (n - t0) */
    const long ts[2] = {t0, t1};
    for (int k = 0; k < 2; k++) {
      const double bias = A * tau * exp(-ts[k] / tau) / (double)(n - ts[k]), sem = sqrt(9.0 / (double)(n - ts[k]));
      assert_true(bias < sem && ts[k] < n / 2);
    }
    raw[s] = (double)t0;
    coarse[s] = (double)t1;
  }
  gsl_sort(raw, 1, 12);
  gsl_sort(coarse, 1, 12);
  const double med = 0.5 * (raw[5] + raw[6]), medc = 0.5 * (coarse[5] + coarse[6]);
  CHECK_NEAR("median t0 of 12 transients (259 to 690: 0.02 to 1.5 noise sds left)", med, 474.5, 215.5);
  CHECK_NEAR("the same in means of 4 samples", medc, 474.5, 215.5);
  /* a stationary series: almost nothing to discard */
  transient(rng, x, n, 0.0, 1.0, 0.8);
  long t0 = -1;
  assert_int_equal(rl_detect_equilibration(x, n, 1, -1, &t0, NULL, NULL), RL_OK);
  printf("check stationary AR(1): t0 = %ld\n", t0);
  CHECK_LE("stationary AR(1): t0 below a tenth of the run", (double)t0, n / 10.0);
  /* a relaxation that outlasts half the run (10 noise sds decaying over 1000 samples: the
   * transient reaches the noise at 2300 of 4000): the search stops at half and says so */
  transient(rng, x, n, 10.0, 1000.0, 0.8);
  rl_trace *tr = rl_trace_alloc(0);
  for (long t = 0; t < n; t++) assert_int_equal(rl_trace_add(tr, x[t]), RL_OK);
  int limit = 0;
  double neff = 0.0;
  assert_int_equal(rl_trace_equilibration(tr, 1000, 0.5, &t0, NULL, NULL, &neff, &limit), RL_OK);
  printf("check relaxation to 2300 of 4000: t0 = %ld, at the limit %d, N_eff %.1f\n", t0, limit, neff);
  assert_true(limit);
  CHECK_NEAR("its start: in the last tenth of the search (1796 to 1996)", (double)t0, 1896.0, 100.0);
  rl_trace_free(tr);
  /* a run that is all relaxation (200 noise sds over 1000 samples): every window is dominated
   * by the drift, g is about the window's length, N_eff about 3 for every start and the first
   * wins: the detection cannot see an equilibrated part, and N_eff says so (rotleap run warns
   * below 10) */
  transient(rng, x, n, 200.0, 1000.0, 0.8);
  tr = rl_trace_alloc(0);
  for (long t = 0; t < n; t++) assert_int_equal(rl_trace_add(tr, x[t]), RL_OK);
  assert_int_equal(rl_trace_equilibration(tr, 1000, 0.5, &t0, NULL, NULL, &neff, &limit), RL_OK);
  printf("check all relaxation: t0 = %ld, N_eff %.2f\n", t0, neff);
  CHECK_LE("all relaxation: N_eff", neff, 5.0);
  rl_trace_free(tr);
  /* a constant series: N_eff = 1 everywhere, the first start wins */
  for (long t = 0; t < 100; t++) x[t] = 2.0;
  assert_int_equal(rl_detect_equilibration(x, 100, 1, -1, &t0, NULL, NULL), RL_OK);
  assert_int_equal(t0, 0);
  free(x);
  gsl_rng_free(rng);
}

/* A long series: the detection runs on at most 1000 means (here of 256 samples). */
static void detection_long_series(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 5);
  const long n = 1L << 18;
  const double tau = 8000.0;
  double *x = malloc(sizeof *x * (size_t)n);
  transient(rng, x, n, 20.0, tau, 0.99);
  rl_trace *tr = rl_trace_alloc(0);
  for (long t = 0; t < n; t++) assert_int_equal(rl_trace_add(tr, x[t]), RL_OK);
  long t0 = -1, len = 0;
  double g = 0.0;
  assert_int_equal(rl_trace_equilibration(tr, 1000, 0.5, &t0, &len, &g, NULL, NULL), RL_OK);
  printf("check 2^18 samples (B = %ld): t0 = %ld (%.2f tau, transient there %.3f), means of %ld, g %.2f means\n",
         rl_trace_block(tr), t0, t0 / tau, 20.0 * exp(-t0 / tau), len, g);
  assert_int_equal(len, (n / rl_trace_block(tr) + 999) / 1000 * rl_trace_block(tr));
  CHECK_NEAR("t0 / tau around ln A = 3", t0 / tau, 3.5, 1.5);
  free(x);
  rl_trace_free(tr);
  gsl_rng_free(rng);
}

/* ------------------------------------------------------------------ rl_trace */

static void trace_against_direct(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 7);
  const long n = 1000;
  double x[1000];
  transient(rng, x, n, 0.0, 1.0, 0.5);
  for (long t = 0; t < n; t++) x[t] += 1e4; /* a large mean: the moments must not cancel */
  rl_trace *small = rl_trace_alloc(16), *big = rl_trace_alloc(0);
  rl_series *s = rl_series_alloc();
  for (long t = 0; t < n; t++) {
    assert_int_equal(rl_trace_add(small, x[t]), RL_OK);
    assert_int_equal(rl_trace_add(big, x[t]), RL_OK);
    rl_series_add(s, x[t]);
  }
  assert_int_equal(rl_trace_add(small, NAN), RL_ENONFINITE);
  assert_int_equal(rl_trace_count(small), n);
  /* 1000 samples in at most 16 blocks: B = 64, 15 full blocks and 40 samples waiting */
  assert_int_equal(rl_trace_block(small), 64);
  assert_int_equal(rl_trace_align(small, 100), 128);
  assert_int_equal(rl_trace_align(small, 961), n);
  for (long from = 0; from < n; from += 64) {
    double mu = 0.0, m2 = 0.0;
    for (long t = from; t < n; t++) mu += x[t];
    mu /= (double)(n - from);
    for (long t = from; t < n; t++) m2 += (x[t] - mu) * (x[t] - mu);
    const rl_moments m = rl_trace_moments(small, from);
    assert_int_equal(m.n, n - from);
    if (fabs(m.mean - mu) > 1e-12 * fabs(mu) || fabs(m.m2 - m2) > 1e-9 * m2)
      fail_msg("moments from %ld: %.17g %.17g vs %.17g %.17g", from, m.mean, m.m2, mu, m2);
  }
  printf("check trace moments from every block start: ok\n");
  /* B = 1: the blocking is rl_series's */
  rl_block_result a, b;
  assert_int_equal(rl_trace_block_average(big, 0, &a), RL_OK);
  assert_int_equal(rl_series_block_average(s, &b), RL_OK);
  CHECK_LE("trace (B = 1) vs rl_series: blocked error, relative", fabs(a.sem - b.sem) / b.sem, 1e-10);
  assert_int_equal(a.level, b.level);
  assert_int_equal(a.converged, b.converged);
  /* compacted: levels from 64 up; the chosen block is never shorter than B */
  assert_int_equal(rl_trace_block_average(small, 0, &a), RL_OK);
  printf("check compacted trace: level %d, sem %.3g (B = 1: %.3g)\n", a.level, a.sem, b.sem);
  assert_true(a.level >= 6);
  /* groups and the jackknife of the mean: equal groups give the standard error of their means */
  rl_moments g[16], loo[16];
  const long m = rl_trace_groups(big, 0, 100, g, 16);
  assert_int_equal(m, 10);
  assert_int_equal(rl_moments_leave_one_out(g, m, loo), RL_OK);
  double theta[16], gm = 0.0, v = 0.0;
  for (long k = 0; k < m; k++) {
    theta[k] = loo[k].mean;
    gm += g[k].mean / (double)m;
  }
  for (long k = 0; k < m; k++) v += (g[k].mean - gm) * (g[k].mean - gm);
  const double want = sqrt(v / (double)(m * (m - 1)));
  CHECK_LE("jackknife error of the mean = standard error of the group means", fabs(rl_jackknife_error(theta, m) - want) / want,
           1e-9);
  /* leave-one-out moments against a direct merge of the others */
  rl_moments other = {0, 0.0, 0.0};
  for (long k = 0; k < m; k++)
    if (k != 3) other = rl_moments_merge(other, g[k]);
  CHECK_LE("leave-one-out m2 vs a direct merge", fabs(loo[3].m2 - other.m2) / other.m2, 1e-12);
  rl_trace_free(small);
  rl_trace_free(big);
  rl_series_free(s);
  gsl_rng_free(rng);
}

/* ------------------------------------------------------------------ later starts of RDFs and TCFs */

static void rdf_and_tcf_from(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 13);
  const double L[3] = {5.0, 5.0, 5.0};
  enum { NP = 30, FRAMES = 700 };
  static double frames[FRAMES][NP][3];
  for (int f = 0; f < FRAMES; f++)
    for (int i = 0; i < NP; i++)
      for (int d = 0; d < 3; d++) frames[f][i][d] = gsl_rng_uniform(rng) * L[d] * (f < 100 ? 0.5 : 1.0);
  rl_rdf *all = rl_rdf_alloc(2.5, 50);
  for (int f = 0; f < FRAMES; f++) assert_int_equal(rl_rdf_add(all, L, frames[f], NP, NULL, frames[f], NP, NULL), RL_OK);
  /* 700 frames and 256 marks: marks every 4 frames */
  static const long firsts[] = {0, 100, 101, 640};
  for (size_t c = 0; c < sizeof firsts / sizeof firsts[0]; c++) {
    long used = -1;
    double g1[50], g2[50];
    assert_int_equal(rl_rdf_get_from(all, firsts[c], NULL, g1, &used), RL_OK);
    assert_int_equal(used, (firsts[c] + 3) / 4 * 4);
    rl_rdf *part = rl_rdf_alloc(2.5, 50);
    for (long f = used; f < FRAMES; f++) rl_rdf_add(part, L, frames[f], NP, NULL, frames[f], NP, NULL);
    assert_int_equal(rl_rdf_get(part, NULL, g2), RL_OK);
    double d = 0.0;
    for (int b = 0; b < 50; b++) d = fmax(d, fabs(g1[b] - g2[b]) / fmax(fabs(g2[b]), 1.0));
    printf("check rdf from frame %ld (used %ld): max |g - g of those frames alone| / max(g, 1) = %.2e\n", firsts[c],
           used, d);
    CHECK_LE("rdf from a mark vs the frames after it alone (totals minus the mark's)", d, 1e-12);
    rl_rdf_free(part);
  }
  long used;
  assert_int_equal(rl_rdf_get_from(all, 699, NULL, NULL, &used), RL_ESTATE);
  /* a correlation function of frames [first, first + count) is that of a series of those frames */
  rl_vec_series *s = rl_vec_series_alloc(NP), *sub = rl_vec_series_alloc(NP);
  for (int f = 0; f < 200; f++) assert_int_equal(rl_vec_series_add(s, frames[f]), RL_OK);
  for (int f = 50; f < 150; f++) assert_int_equal(rl_vec_series_add(sub, frames[f]), RL_OK);
  double c1[40], c2[40];
  for (int kind = RL_TCF_DOT; kind <= RL_TCF_MSD; kind++) {
    assert_int_equal(rl_tcf_compute_range(s, 50, 100, (rl_tcf_kind)kind, 39, 1, c1), RL_OK);
    assert_int_equal(rl_tcf_compute(sub, (rl_tcf_kind)kind, 39, 1, c2), RL_OK);
    CHECK_LE("tcf of frames 50..149 vs a series of them", max_abs_diff(c1, c2, 40), 0.0);
  }
  assert_int_equal(rl_tcf_compute_range(s, 150, 100, RL_TCF_DOT, 5, 1, c1), RL_EINVAL);
  rl_vec_series_free(s);
  rl_vec_series_free(sub);
  rl_rdf_free(all);
  gsl_rng_free(rng);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(inefficiency_by_hand), cmocka_unit_test(detection_on_transients),
                                     cmocka_unit_test(detection_long_series), cmocka_unit_test(trace_against_direct),
                                     cmocka_unit_test(rdf_and_tcf_from)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
