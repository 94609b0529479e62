/* Observables: block averages on AR(1) series with known mean and integrated autocorrelation
 * time, fixed blocks, calE / running calE, heat capacities from synthetic canonical and
 * microcanonical samples, and bad input. */
#include "../testutil.h"

#include <rotleap/observables.h>

/* AR(1): x_t = mu + phi (x_{t-1} - mu) + xi, xi ~ N(0, 1).  var x = 1/(1 - phi^2),
 * tau_int = (1/2)(1 + phi)/(1 - phi), sem^2 = 2 tau var / n (asymptotically exact in n / tau). */
static void ar1_blocking(void **state)
{
  (void)state;
  const double mu = 5.0;
  const double phis[3] = {0.0, 0.5, 0.9};
  const long n = 1L << 20;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 7);
  rl_series *s = rl_series_alloc();
  assert_non_null(s);
  for (int p = 0; p < 3; p++) {
    double phi = phis[p], x = mu + gsl_ran_gaussian(rng, 1.0) / sqrt(1.0 - phi * phi);
    rl_series_reset(s);
    for (long t = 0; t < n; t++) {
      assert_int_equal(rl_series_add(s, x), RL_OK);
      x = mu + phi * (x - mu) + gsl_ran_gaussian(rng, 1.0);
    }
    rl_block_result r;
    assert_int_equal(rl_series_block_average(s, &r), RL_OK);
    double var = 1.0 / (1.0 - phi * phi), tau = 0.5 * (1.0 + phi) / (1.0 - phi);
    double sem = sqrt(2.0 * tau * var / (double)n);
    char name[96];
    printf("info  phi = %.1f: mean %.5f sd %.4f sem %.3e (+- %.1e, level %d, converged %d), analytic %.3e, tau %.2f (analytic %.2f)\n",
           phi, r.mean, r.sd, r.sem, r.sem_err, r.level, r.converged, sem, r.tau, tau);
    snprintf(name, sizeof name, "AR(1) phi=%.1f: blocked sem / analytic sem (tol 10%%)", phi);
    CHECK_NEAR(name, r.sem / sem, 1.0, 0.10);
    snprintf(name, sizeof name, "AR(1) phi=%.1f: |mean - mu| / analytic sem", phi);
    CHECK_LE(name, fabs(r.mean - mu) / sem, 4.0);
    snprintf(name, sizeof name, "AR(1) phi=%.1f: sd / analytic sd (tol 1%%)", phi);
    CHECK_NEAR(name, r.sd / sqrt(var), 1.0, 0.01);
    snprintf(name, sizeof name, "AR(1) phi=%.1f: blocking converged", phi);
    CHECK_NEAR(name, r.converged, 1.0, 0.0);
    /* the naive error bar underestimates by sqrt(2 tau) */
    snprintf(name, sizeof name, "AR(1) phi=%.1f: tau estimate / analytic (tol 20%%)", phi);
    CHECK_NEAR(name, r.tau / tau, 1.0, 0.20);
  }
  /* the level table: level 0 is the naive error */
  rl_block_level lv[RL_BLOCK_MAX_LEVELS];
  int m = rl_series_block_levels(s, lv, RL_BLOCK_MAX_LEVELS);
  CHECK_NEAR("block levels of 2^20 samples", m, 20.0, 0.0);
  CHECK_NEAR("level 19 has 2 blocks", (double)lv[19].nblocks, 2.0, 0.0);
  rl_series_free(s);
  rl_series_free(NULL);
  gsl_rng_free(rng);
}

static void fixed_blocks(void **state)
{
  (void)state;
  const double phi = 0.9;
  const size_t n = 1u << 20;
  double *x = malloc(sizeof(double) * n);
  assert_non_null(x);
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 11);
  double v = gsl_ran_gaussian(rng, 1.0) / sqrt(1.0 - phi * phi);
  for (size_t t = 0; t < n; t++) {
    x[t] = v;
    v = phi * v + gsl_ran_gaussian(rng, 1.0);
  }
  double mean, sem, sem_a = sqrt((1.0 + phi) / (1.0 - phi) / (1.0 - phi * phi) / (double)n);
  assert_int_equal(rl_block_fixed(x, n, 64, &mean, &sem), RL_OK);
  /* 64 blocks: relative uncertainty of sem ~ 1/sqrt(126) = 9 %; 3 sigma */
  CHECK_NEAR("64 fixed blocks: sem / analytic (tol 27%)", sem / sem_a, 1.0, 0.27);
  assert_int_equal(rl_block_fixed(x, 10, 20, &mean, &sem), RL_EINVAL);
  assert_int_equal(rl_block_fixed(x, n, 1, &mean, &sem), RL_EINVAL);
  gsl_rng_free(rng);
  free(x);
}

static void rel_fluct(void **state)
{
  (void)state;
  /* x_k = 10 +- 1 alternating: after an even count sd = 1, mean = 10, calE = 0.1 */
  enum { N = 101 };
  double x[N], run[N];
  rl_series *s = rl_series_alloc();
  double maxdiff = 0.0, maxbrute = 0.0;
  for (int k = 0; k < N; k++) x[k] = 10.0 + ((k % 2) ? -1.0 : 1.0);
  assert_int_equal(rl_running_rel_fluct(x, N, run), RL_OK);
  for (int k = 0; k < N; k++) {
    assert_int_equal(rl_series_add(s, x[k]), RL_OK);
    maxdiff = fmax(maxdiff, fabs(rl_series_rel_fluct(s) - run[k]));
    double m = 0.0, q = 0.0;
    for (int j = 0; j <= k; j++) m += x[j];
    m /= k + 1;
    for (int j = 0; j <= k; j++) q += (x[j] - m) * (x[j] - m);
    maxbrute = fmax(maxbrute, fabs(sqrt(q / (k + 1)) / fabs(m) - run[k]));
  }
  CHECK_NEAR("calE after 100 samples of 10 +- 1", run[99], 0.1, 1e-14);
  CHECK_LE("running calE: array vs two-pass brute force", maxbrute, 1e-14);
  CHECK_LE("running calE: on-line series vs array", maxdiff, 1e-14);
  /* calU of a negative series uses |<U>| */
  rl_series_reset(s);
  for (int k = 0; k < 100; k++) rl_series_add(s, -200.0 + ((k % 2) ? -3.0 : 3.0));
  CHECK_NEAR("calU of -200 +- 3", rl_series_rel_fluct(s), 0.015, 1e-14);
  /* huge offset, tiny fluctuation: Welford keeps the relative sd */
  rl_series_reset(s);
  for (int k = 0; k < 1000; k++) rl_series_add(s, -1.0e4 + ((k % 2) ? -1e-4 : 1e-4));
  CHECK_NEAR("calE of -1e4 +- 1e-4 (1e-8), relative error", rl_series_rel_fluct(s) / 1e-8, 1.0, 1e-6);
  assert_int_equal(rl_series_add(s, NAN), RL_ENONFINITE);
  CHECK_NEAR("NaN sample rejected, count unchanged", (double)rl_series_count(s), 1000.0, 0.0);
  rl_series_reset(s);
  rl_block_result r;
  assert_int_equal(rl_series_block_average(s, &r), RL_EINVAL);
  assert_true(isnan(rl_series_rel_fluct(s)));
  rl_series_free(s);
}

/* Heat capacities.  NVT: f kinetic + g harmonic potential degrees of freedom at kT:
 * K ~ Gamma(f/2, kT), U ~ Gamma(g/2, kT) => C_V = (f + g) kB / 2.
 * NVE: at fixed E, K / E ~ Beta(f/2, g/2); Lebowitz-Percus-Verlet then gives
 * a kB (a + b + 1)/(a + 1) with a = f/2, b = g/2, which is (f + g)/2 up to O(1/N). */
static void heat_capacity(void **state)
{
  (void)state;
  const int f = 600, g = 600;
  const double kB = RL_KB_KJMOL, T = 300.0, kT = kB * T;
  const long n = 400000;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 3);
  rl_series *E = rl_series_alloc(), *U = rl_series_alloc(), *K = rl_series_alloc();
  for (long t = 0; t < n; t++) {
    double k = gsl_ran_gamma(rng, 0.5 * f, kT), u = gsl_ran_gamma(rng, 0.5 * g, kT);
    rl_series_add(E, k + u - 1000.0);
    rl_series_add(U, u - 1000.0);
  }
  double cv, sdE = rl_series_sd(E), sdU = rl_series_sd(U), exact = 0.5 * (f + g) * kB;
  /* relative sampling error of a variance: sqrt(2/n) ~ 0.22 % */
  assert_int_equal(rl_heat_capacity_nvt(sdE * sdE, T, kB, &cv), RL_OK);
  CHECK_NEAR("NVT C_V from <dE^2> / ((f+g) kB/2) (tol 1%)", cv / exact, 1.0, 0.01);
  assert_int_equal(rl_heat_capacity_isokinetic(sdU * sdU, T, f, kB, &cv), RL_OK);
  CHECK_NEAR("isokinetic C_V = f kB/2 + <dU^2>/kT^2 (tol 1%)", cv / exact, 1.0, 0.01);

  const double E0 = 0.5 * (f + g) * kT;
  for (long t = 0; t < n; t++) rl_series_add(K, E0 * gsl_ran_beta(rng, 0.5 * f, 0.5 * g));
  double mK = rl_series_mean(K), sK = rl_series_sd(K), a = 0.5 * f, b = 0.5 * g;
  assert_int_equal(rl_heat_capacity_nve(mK, sK * sK, f, kB, &cv), RL_OK);
  printf("info  NVE LPV: C_V = %.5f, exact-for-Beta %.5f, (f+g)kB/2 = %.5f, T = %.2f\n", cv,
         kB * a * (a + b + 1) / (a + 1), exact, 2 * mK / (f * kB));
  /* relative error of C_V: d cv / cv = x/(1-x) d var/var with x = 1/2 here: ~ 0.22 %  */
  CHECK_NEAR("NVE LPV C_V / exact-for-Beta (tol 1.5%)", cv / (kB * a * (a + b + 1) / (a + 1)), 1.0, 0.015);
  CHECK_NEAR("NVE LPV C_V / ((f+g) kB/2) (tol 2%)", cv / exact, 1.0, 0.02);
  /* ideal gas NVE: K constant -> f kB / 2 exactly */
  assert_int_equal(rl_heat_capacity_nve(E0, 0.0, f, kB, &cv), RL_OK);
  CHECK_NEAR("NVE ideal gas (no K fluctuation): C_V / (f kB/2)", cv / (0.5 * f * kB), 1.0, 1e-14);
  /* canonical K fluctuations (var = 2 <K>^2 / f) are not microcanonical: error */
  assert_int_equal(rl_heat_capacity_nve(E0, 2.0 * E0 * E0 / f, f, kB, &cv), RL_EINVAL);
  printf("info  message: %s\n", rl_last_error());
  assert_int_equal(rl_heat_capacity_nvt(-1.0, T, kB, &cv), RL_EINVAL);
  assert_int_equal(rl_heat_capacity_isokinetic(1.0, 0.0, f, kB, &cv), RL_EINVAL);
  rl_series_free(E);
  rl_series_free(U);
  rl_series_free(K);
  gsl_rng_free(rng);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(ar1_blocking), cmocka_unit_test(fixed_blocks),
                                     cmocka_unit_test(rel_fluct), cmocka_unit_test(heat_capacity)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
