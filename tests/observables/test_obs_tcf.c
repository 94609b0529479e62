/* Observables: time correlation functions and diffusion.  P1 / P2 of an axis rotating at constant
 * angular velocity against cos(w t) and (3 cos^2(w t) - 1)/2; the VACF of free particles is
 * constant; ballistic MSD = v^2 t^2; Brownian walks recover D from the MSD; Green-Kubo of an
 * exponential VACF; lab angular velocities of a system against their definitions; unwrapping. */
#include "../testutil.h"

#include <rotleap/observables.h>

static void legendre_rotation(void **state)
{
  (void)state;
  const int n = 20, frames = 400;
  const double dt = 0.01, w = 3.0;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 1);
  /* each body: a random fixed axis e, an axis u perpendicular to it, rotating at w about e */
  double e[20][3], u0[20][3], u[20][3];
  for (int i = 0; i < n; i++) {
    double A[9];
    random_rotation(rng, A);
    for (int d = 0; d < 3; d++) {
      e[i][d] = A[d];
      u0[i][d] = A[3 + d];
    }
  }
  rl_vec_series *s = rl_vec_series_alloc(n);
  for (int f = 0; f < frames; f++) {
    double c = cos(w * f * dt), sn = sin(w * f * dt);
    for (int i = 0; i < n; i++) {
      double exu[3] = {e[i][1] * u0[i][2] - e[i][2] * u0[i][1], e[i][2] * u0[i][0] - e[i][0] * u0[i][2],
                       e[i][0] * u0[i][1] - e[i][1] * u0[i][0]};
      for (int d = 0; d < 3; d++) u[i][d] = 2.5 * (c * u0[i][d] + sn * exu[d]); /* not unit: P1 normalises */
    }
    assert_int_equal(rl_vec_series_add(s, (const double(*)[3])u), RL_OK);
  }
  const long maxlag = 200;
  double c1[201], c2[201], e1 = 0.0, e2 = 0.0;
  assert_int_equal(rl_tcf_compute(s, RL_TCF_P1, maxlag, 1, c1), RL_OK);
  assert_int_equal(rl_tcf_compute(s, RL_TCF_P2, maxlag, 3, c2), RL_OK);
  for (long k = 0; k <= maxlag; k++) {
    double x = cos(w * k * dt);
    e1 = fmax(e1, fabs(c1[k] - x));
    e2 = fmax(e2, fabs(c2[k] - 0.5 * (3 * x * x - 1)));
  }
  CHECK_LE("P1 of constant rotation vs cos(w t)", e1, 1e-12);
  CHECK_LE("P2 of constant rotation vs (3 cos^2 - 1)/2 (stride 3)", e2, 1e-12);
  assert_int_equal(rl_tcf_compute(s, RL_TCF_P1, frames, 1, c1), RL_EINVAL);
  assert_int_equal(rl_tcf_compute(s, RL_TCF_P1, 10, 0, c1), RL_EINVAL);
  CHECK_NEAR("frames stored", (double)rl_vec_series_frames(s), frames, 0.0);
  rl_vec_series_free(s);
  rl_vec_series_free(NULL);
  gsl_rng_free(rng);
}

static void free_particles(void **state)
{
  (void)state;
  const int n = 50, frames = 100;
  const double dt = 0.5;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 2);
  double v[50][3], r0[50][3], r[50][3], v2 = 0.0;
  for (int i = 0; i < n; i++)
    for (int d = 0; d < 3; d++) {
      v[i][d] = gsl_ran_gaussian(rng, 1.0);
      r0[i][d] = 10 * gsl_rng_uniform(rng);
      v2 += v[i][d] * v[i][d] / n;
    }
  rl_vec_series *sv = rl_vec_series_alloc(n), *sr = rl_vec_series_alloc(n);
  for (int f = 0; f < frames; f++) {
    for (int i = 0; i < n; i++)
      for (int d = 0; d < 3; d++) r[i][d] = r0[i][d] + v[i][d] * f * dt;
    rl_vec_series_add(sv, (const double(*)[3])v);
    rl_vec_series_add(sr, (const double(*)[3])r);
  }
  double c[60], msd[60], ev = 0.0, em = 0.0;
  assert_int_equal(rl_tcf_compute(sv, RL_TCF_DOT, 59, 1, c), RL_OK);
  assert_int_equal(rl_tcf_compute(sr, RL_TCF_MSD, 59, 1, msd), RL_OK);
  for (int k = 0; k < 60; k++) {
    ev = fmax(ev, fabs(c[k] - v2) / v2);
    em = fmax(em, fabs(msd[k] - v2 * k * k * dt * dt) / (v2 * (k * k + 1) * dt * dt));
  }
  CHECK_LE("VACF of free particles constant = <v^2> (relative)", ev, 1e-13);
  CHECK_LE("ballistic MSD = <v^2> t^2 (relative)", em, 1e-13);
  /* a part of the bodies (a species of a mixture): over all of them it is the whole, bit for
   * bit; bodies 10..29 have the MSD <v^2>_part t^2 of their own velocities; a window outside
   * the bodies is refused */
  double all[60], part[60], v2p = 0.0, ep = 0.0;
  for (int i = 10; i < 30; i++) v2p += (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]) / 20;
  assert_int_equal(rl_tcf_compute_bodies(sr, 0, frames, 0, n, RL_TCF_MSD, 59, 1, all), RL_OK);
  assert_int_equal(rl_tcf_compute_bodies(sr, 0, frames, 10, 20, RL_TCF_MSD, 59, 1, part), RL_OK);
  for (int k = 1; k < 60; k++) ep = fmax(ep, fabs(part[k] - v2p * k * k * dt * dt) / (v2p * k * k * dt * dt));
  CHECK_LE("rl_tcf_compute_bodies over every body = rl_tcf_compute, bit for bit (bytes differing)",
           memcmp(all, msd, sizeof msd) != 0, 0);
  CHECK_LE("bodies 10..29: MSD = <v^2 of those bodies> t^2 (relative)", ep, 1e-13);
  CHECK_LE("bodies 40..59 of 50 refused (0: RL_EINVAL)",
           rl_tcf_compute_bodies(sr, 0, frames, 40, 20, RL_TCF_MSD, 5, 1, part) != RL_EINVAL, 0);
  rl_vec_series_free(sv);
  rl_vec_series_free(sr);
  gsl_rng_free(rng);
}

/* Brownian walkers: steps N(0, 2 D dt) per component, MSD = 6 D t.  Einstein fit over the
 * documented window (10 % .. 50 % of the lags).  Expected relative error of D: about
 * sqrt(2/(3 n)) x O(1) over the window, with n = 500 walkers and multiple origins ~ 2 %; tol 6 %. */
static void brownian(void **state)
{
  (void)state;
  const int n = 500, frames = 2000;
  const double D = 0.37, dt = 0.02, L[3] = {3.0, 3.0, 3.0};
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 9);
  double(*x)[3] = calloc((size_t)n, sizeof(double[3]));
  double(*w)[3] = calloc((size_t)n, sizeof(double[3]));
  double(*u)[3] = calloc((size_t)n, sizeof(double[3]));
  rl_vec_series *s = rl_vec_series_alloc(n);
  double maxun = 0.0;
  for (int f = 0; f < frames; f++) {
    /* store the wrapped positions' unwrapped images, as a run in a periodic box would */
    for (int i = 0; i < n; i++)
      for (int d = 0; d < 3; d++) w[i][d] = x[i][d] - L[d] * floor(x[i][d] / L[d]);
    if (f == 0)
      memcpy(u, w, sizeof(double[3]) * n);
    else
      rl_unwrap(L, (const double(*)[3])u, (const double(*)[3])w, n, u);
    for (int i = 0; i < n; i++) /* x(0) = 0 lies in the box, so u must equal x */
      for (int d = 0; d < 3; d++) maxun = fmax(maxun, fabs(u[i][d] - x[i][d]));
    rl_vec_series_add(s, (const double(*)[3])u);
    for (int i = 0; i < n; i++)
      for (int d = 0; d < 3; d++) x[i][d] += gsl_ran_gaussian(rng, sqrt(2 * D * dt));
  }
  CHECK_LE("unwrapped positions of walkers crossing the box = true positions", maxun, 1e-12);
  const long maxlag = 400;
  double *msd = malloc(sizeof(double) * (maxlag + 1)), Dfit, Derr;
  assert_int_equal(rl_tcf_compute(s, RL_TCF_MSD, maxlag, 10, msd), RL_OK);
  assert_int_equal(rl_diffusion_einstein(msd, maxlag + 1, dt, maxlag / 10, maxlag / 2, &Dfit, &Derr), RL_OK);
  printf("info  Brownian: D = %.4f +- %.4f (fit), true %.4f\n", Dfit, Derr, D);
  CHECK_NEAR("Brownian walkers: Einstein D / true D (tol 6%)", Dfit / D, 1.0, 0.06);
  assert_int_equal(rl_diffusion_einstein(msd, maxlag + 1, dt, 5, 5, &Dfit, NULL), RL_EINVAL);
  free(msd);
  free(x);
  free(w);
  free(u);
  rl_vec_series_free(s);
  gsl_rng_free(rng);
}

static void unwrap(void **state)
{
  (void)state;
  const double L[3] = {2.0, 3.0, 4.0};
  double prev[2][3] = {{1.9, 2.9, 3.9}, {-5.1, 0.2, 7.9}}, x[2][3] = {{0.05, 0.1, 0.2}, {0.8, 0.3, 0.1}}, out[2][3];
  const double want[2][3] = {{2.05, 3.1, 4.2}, {-5.2, 0.3, 8.1}};
  rl_unwrap(L, (const double(*)[3])prev, (const double(*)[3])x, 2, out);
  CHECK_LE("unwrap: nearest image of the previous unwrapped position", max_abs_diff(&out[0][0], &want[0][0], 6), 1e-14);
}

/* Green-Kubo on <v(0).v(t)> = 3 (kT/m) exp(-t/tau): D = kT tau / m. */
static void green_kubo(void **state)
{
  (void)state;
  const double kTm = 1.7, tau = 0.4, dt = 0.001;
  const long nlag = 12001;
  double *c = malloc(sizeof(double) * nlag), D;
  for (long k = 0; k < nlag; k++) c[k] = 3 * kTm * exp(-k * dt / tau);
  assert_int_equal(rl_diffusion_green_kubo(c, nlag, dt, &D), RL_OK);
  CHECK_NEAR("Green-Kubo of 3 kT/m exp(-t/tau): D / (kT tau/m)", D / (kTm * tau), 1.0, 1e-5);
  free(c);
}

/* Lab angular velocities from a system: matrix bodies obey A^T J A w = l; axis bodies w . rho = 0
 * and J w = l - (l.rho) rho; point bodies 0.  Sum w.l / 2 is the rotational kinetic energy. */
static void angular_velocity(void **state)
{
  (void)state;
  const char *names[3] = {"tip4p", "co2", "ch4"};
  rl_molecule m[3];
  rl_system *sys = rl_system_alloc(RL_UNITS_REAL);
  for (int k = 0; k < 3; k++) {
    assert_int_equal(rl_model_build(rl_catalog_find(names[k]), NULL, 0, &m[k]), RL_OK);
    rl_species_desc d;
    rl_molecule_species(&m[k], &d);
    assert_int_equal(rl_system_add_species(sys, &d, 4, NULL), RL_OK);
  }
  rl_species_desc pd = {"atom", RL_KIND_POINT, 40.0, {0, 0, 0}, 0, NULL};
  assert_int_equal(rl_system_add_species(sys, &pd, 2, NULL), RL_OK);
  const double L[3] = {2, 2, 2};
  assert_int_equal(rl_system_lattice(sys, L, RL_LATTICE_SC, 1, 4), RL_OK);
  assert_int_equal(rl_system_maxwell_boltzmann(sys, 300.0, 5), RL_OK);
  int n = rl_system_count(sys);
  double(*w)[3] = malloc(sizeof(double[3]) * n);
  rl_system_angular_velocities(sys, w);
  double emat = 0.0, eax = 0.0, epoint = 0.0;
  for (int i = 0; i < n; i++) {
    rl_kind kind = rl_system_species_kind(sys, rl_system_species_of(sys, i));
    double l[3], J[3], A[9];
    rl_system_get_angmom(sys, i, l);
    rl_system_inertia(sys, i, J);
    rl_system_get_orientation(sys, i, A);
    if (kind == RL_KIND_POINT) {
      epoint = fmax(epoint, norm3d(w[i]));
    } else if (kind == RL_KIND_LINEAR || kind == RL_KIND_DIPOLE) {
      double rho[3] = {A[6], A[7], A[8]}, lr = l[0] * rho[0] + l[1] * rho[1] + l[2] * rho[2];
      for (int d = 0; d < 3; d++) eax = fmax(eax, fabs(J[0] * w[i][d] - (l[d] - lr * rho[d])) / norm3d(l));
      eax = fmax(eax, fabs(w[i][0] * rho[0] + w[i][1] * rho[1] + w[i][2] * rho[2]) * J[0] / norm3d(l));
    } else {
      double Ob[3], back[3];
      for (int a = 0; a < 3; a++) Ob[a] = J[a] * (A[3 * a] * w[i][0] + A[3 * a + 1] * w[i][1] + A[3 * a + 2] * w[i][2]);
      for (int d = 0; d < 3; d++) back[d] = A[d] * Ob[0] + A[3 + d] * Ob[1] + A[6 + d] * Ob[2];
      emat = fmax(emat, max_abs_diff(back, l, 3) / norm3d(l));
    }
  }
  CHECK_LE("matrix bodies (tip4p, ch4): |A^T J A w - l| / |l|", emat, 1e-13);
  CHECK_LE("axis bodies (co2): J w = l_perp, w . rho = 0 (relative)", eax, 1e-13);
  CHECK_LE("point bodies: w = 0", epoint, 0.0);
  /* the other samplers */
  double(*a)[3] = malloc(sizeof(double[3]) * n), (*v)[3] = malloc(sizeof(double[3]) * n);
  rl_system_axes(sys, a);
  rl_system_velocities(sys, v);
  rl_system_positions(sys, w);
  double ax[3], vv[3], rr[3];
  rl_system_get_axis(sys, 5, ax);
  rl_system_get_velocity(sys, 5, vv);
  rl_system_get_position(sys, 5, rr);
  CHECK_LE("samplers: axes / velocities / positions match the getters",
           max_abs_diff(ax, a[5], 3) + max_abs_diff(vv, v[5], 3) + max_abs_diff(rr, w[5], 3), 0.0);
  free(a);
  free(v);
  free(w);
  rl_system_free(sys);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(legendre_rotation), cmocka_unit_test(free_particles),
                                     cmocka_unit_test(brownian),          cmocka_unit_test(unwrap),
                                     cmocka_unit_test(green_kubo),        cmocka_unit_test(angular_velocity)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
