/* Observables: dipoles and the static dielectric constant.  The reaction-field formula inverts its
 * own forward map for every boundary; eps_rf -> infinity meets the tin-foil formula; the reduced
 * and SI forms agree; synthetic Gaussian total-dipole samples of known variance recover eps;
 * molecular dipoles of TIP4P (2.18 D) and Stockmayer (mu* = sqrt 3) systems. */
#include "../testutil.h"

#include <rotleap/observables.h>

static void formula(void **state)
{
  (void)state;
  const double V = 125.0, T = 1.35, eps_rfs[5] = {1.0, 2.0, 78.3, 1e6, INFINITY};
  double worst = 0.0, eps;
  for (int k = 0; k < 5; k++)
    for (double e = 1.0; e < 200.0; e = 1.0 + 1.7 * (e - 1.0) + 0.3) {
      double dM2 = rl_dielectric_fluct(e, V, T, eps_rfs[k], RL_UNITS_LJ, 0.0);
      assert_int_equal(rl_dielectric_constant(dM2, V, T, eps_rfs[k], RL_UNITS_LJ, 0.0, &eps), RL_OK);
      worst = fmax(worst, fabs(eps - e) / e);
    }
  CHECK_LE("RF formula inverts its forward map (eps_rf = 1, 2, 78.3, 1e6, inf)", worst, 1e-12);
  /* tin foil, reduced units: eps = 1 + 4 pi <dM^2> / (3 V T) */
  const double dM2 = 40.0;
  assert_int_equal(rl_dielectric_constant(dM2, V, T, INFINITY, RL_UNITS_LJ, 0.0, &eps), RL_OK);
  CHECK_NEAR("tin foil (lj): eps = 1 + 4 pi <dM^2>/(3 V T)", eps, 1.0 + 4.0 * M_PI * dM2 / (3.0 * V * T), 1e-12);
  double eps_big;
  assert_int_equal(rl_dielectric_constant(dM2, V, T, 1e9, RL_UNITS_LJ, 0.0, &eps_big), RL_OK);
  CHECK_LE("eps_rf = 1e9 vs tin foil (relative)", fabs(eps_big - eps) / eps, 1e-7);
  /* the conducting limit without overflow: 2 eps_rf + 1 is inf at eps_rf = 1e308 (issue 30 item 9) */
  double eps_huge, back;
  assert_int_equal(rl_dielectric_constant(dM2, V, T, 1e308, RL_UNITS_LJ, 0.0, &eps_huge), RL_OK);
  CHECK_NEAR("eps_rf = 1e308 is tin foil to round-off", eps_huge, eps, 1e-14 * eps);
  back = rl_dielectric_fluct(eps, V, T, 1e308, RL_UNITS_LJ, 0.0);
  CHECK_NEAR("and its inverse at eps_rf = 1e308 gives <dM^2> back", back, dM2, 1e-12 * dM2);
  /* vacuum boundary eps_rf = 1: Clausius-Mossotti form (eps - 1)/(eps + 2) = y/3 */
  double y = 4.0 * M_PI * 5.0 / (3.0 * V * T), e1;
  assert_int_equal(rl_dielectric_constant(5.0, V, T, 1.0, RL_UNITS_LJ, 0.0, &e1), RL_OK);
  CHECK_NEAR("eps_rf = 1: (eps - 1)/(eps + 2) = y/3", (e1 - 1.0) / (e1 + 2.0), y / 3.0, 1e-14);
  /* real units against SI: <dM^2> / (3 eps0 V kB T) */
  const double Vr = 6.0, Tr = 298.0, dMr = 2.0; /* nm^3, K, (e nm)^2 */
  double er, eC = 1.602176634e-19, eps0 = 8.8541878128e-12, kB = 1.380649e-23;
  double ysi = dMr * (eC * 1e-9) * (eC * 1e-9) / (3.0 * eps0 * Vr * 1e-27 * kB * Tr);
  assert_int_equal(rl_dielectric_constant(dMr, Vr, Tr, INFINITY, RL_UNITS_REAL, 0.0, &er), RL_OK);
  CHECK_NEAR("real units vs SI: (eps - 1) / y_SI", (er - 1.0) / ysi, 1.0, 1e-8);
  /* bad input: fluctuation too large for the boundary, negative volume, eps_rf < 1 */
  assert_int_equal(rl_dielectric_constant(1e6, V, T, 1.0, RL_UNITS_LJ, 0.0, &eps), RL_EINVAL);
  printf("info  message: %s\n", rl_last_error());
  assert_int_equal(rl_dielectric_constant(dM2, -1.0, T, 1.0, RL_UNITS_LJ, 0.0, &eps), RL_EINVAL);
  assert_int_equal(rl_dielectric_constant(dM2, V, T, 0.5, RL_UNITS_LJ, 0.0, &eps), RL_EINVAL);
}

/* M ~ <M> + N(0, s^2) per component: <dM^2> = 3 s^2.  s chosen for eps = 60 under eps_rf = 78.3
 * and under tin foil.  n = 200000: relative error of <dM^2> ~ sqrt(2/(3n)) = 0.18 %, of eps - 1
 * about the same times d ln(eps-1)/d ln y (<= 2.5 here); tolerance 2 %. */
static void synthetic(void **state)
{
  (void)state;
  const double V = 300.0, T = 1.2, target = 60.0, eps_rfs[2] = {78.3, INFINITY};
  const long n = 200000;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 21);
  for (int k = 0; k < 2; k++) {
    double dM2 = rl_dielectric_fluct(target, V, T, eps_rfs[k], RL_UNITS_LJ, 0.0), s = sqrt(dM2 / 3.0);
    rl_dipole_acc *acc = rl_dipole_acc_alloc();
    for (long t = 0; t < n; t++) {
      double M[3] = {3.0 + gsl_ran_gaussian(rng, s), -1.0 + gsl_ran_gaussian(rng, s), gsl_ran_gaussian(rng, s)};
      assert_int_equal(rl_dipole_acc_add(acc, M), RL_OK);
    }
    double mean[3], eps;
    double fl = rl_dipole_acc_fluct(acc, mean);
    assert_int_equal(rl_dielectric_constant(fl, V, T, eps_rfs[k], RL_UNITS_LJ, 0.0, &eps), RL_OK);
    char name[96];
    snprintf(name, sizeof name, "synthetic M, eps_rf = %g: eps / 60 (tol 2%%)", eps_rfs[k]);
    CHECK_NEAR(name, eps / target, 1.0, 0.02);
    snprintf(name, sizeof name, "synthetic M, eps_rf = %g: <M_x> (3 sigma)", eps_rfs[k]);
    CHECK_NEAR(name, mean[0], 3.0, 3.0 * s / sqrt((double)n));
    rl_dipole_acc_free(acc);
  }
  /* the same fluctuation read with the wrong boundary gives a different eps: consistency */
  double dM2 = rl_dielectric_fluct(target, V, T, 78.3, RL_UNITS_LJ, 0.0), e_tf;
  assert_int_equal(rl_dielectric_constant(dM2, V, T, INFINITY, RL_UNITS_LJ, 0.0, &e_tf), RL_OK);
  printf("info  <dM^2> of eps = 60 under eps_rf = 78.3 read as tin foil gives eps = %.2f\n", e_tf);
  CHECK_LE("RF and tin-foil readings differ for eps_rf = 78.3 (eps_tf < eps)", e_tf, target - 1.0);
  rl_dipole_acc_free(NULL);
  gsl_rng_free(rng);
}

static rl_system *build(const char *model, int n, int random, rl_molecule *m)
{
  const rl_model *md = rl_catalog_find(model);
  assert_non_null(md);
  assert_int_equal(rl_model_build(md, NULL, 0, m), RL_OK);
  rl_system *sys = rl_system_alloc(md->units);
  rl_species_desc d;
  rl_molecule_species(m, &d);
  assert_int_equal(rl_system_add_species(sys, &d, n, NULL), RL_OK);
  const double L[3] = {3.0, 3.0, 3.0};
  assert_int_equal(rl_system_lattice(sys, L, RL_LATTICE_SC, random, 8), RL_OK);
  return sys;
}

static void molecular_dipoles(void **state)
{
  (void)state;
  rl_molecule m;
  rl_system *sys = build("tip4p", 27, 1, &m);
  rl_species_ff ff = rl_molecule_ff(&m);
  double mu[27][3], M[3], S[3] = {0, 0, 0}, dmax = 0.0, dmin = 1e9;
  assert_int_equal(rl_system_dipoles(sys, &ff, 1, mu, M), RL_OK);
  for (int i = 0; i < 27; i++) {
    double a = norm3d(mu[i]) / RL_DEBYE_E_NM;
    dmax = fmax(dmax, a);
    dmin = fmin(dmin, a);
    for (int d = 0; d < 3; d++) S[d] += mu[i][d];
  }
  printf("info  TIP4P |mu| = %.4f D\n", dmax);
  CHECK_NEAR("TIP4P molecular dipole (D), Jorgensen 1983: 2.18", dmax, 2.18, 0.01);
  CHECK_LE("TIP4P |mu| equal for all orientations (D)", dmax - dmin, 1e-12);
  CHECK_LE("M = sum of molecular dipoles", max_abs_diff(M, S, 3), 1e-14);
  /* TIP4P's dipole lies along its C2 axis, which is not body Z (the largest moment, normal to the
     plane): a dipole-axis ACF of water must use mu_i, not rl_system_get_axis. */
  double ax[3];
  rl_system_get_axis(sys, 0, ax);
  double c = fabs(ax[0] * mu[0][0] + ax[1] * mu[0][1] + ax[2] * mu[0][2]) / norm3d(mu[0]);
  CHECK_LE("TIP4P: mu is perpendicular to body Z (|cos|)", c, 1e-12);
  rl_system_free(sys);

  sys = build("stockmayer", 27, 0, &m);
  ff = rl_molecule_ff(&m);
  assert_int_equal(rl_system_dipoles(sys, &ff, 1, NULL, M), RL_OK);
  const double want[3] = {0.0, 0.0, 27.0 * sqrt(3.0)};
  CHECK_LE("Stockmayer aligned: M = N mu* z", max_abs_diff(M, want, 3), 1e-12);
  /* wrong species data */
  rl_species_ff bad = ff;
  bad.nsites = 2;
  assert_int_equal(rl_system_dipoles(sys, &bad, 1, NULL, M), RL_EINVAL);
  assert_int_equal(rl_system_dipoles(sys, &ff, 2, NULL, M), RL_EINVAL);
  rl_system_free(sys);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(formula), cmocka_unit_test(synthetic),
                                     cmocka_unit_test(molecular_dipoles)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
