/* Finite-difference checks of forces and torques for every kernel (LJ in each truncation, RF
 * Coulomb, dipole-dipole RF and SF, charge-dipole RF and SF, quadrupole-quadrupole) on every
 * body kind (point, dipole, linear, spherical, symmetric, asymmetric) and both cutoff schemes;
 * Newton's third law and zero net torque + moment for isolated pairs; translation and rotation
 * invariance of cluster energies.
 *
 * FD: central differences with one Richardson step (h = 1e-4 nm, 1e-4 rad); translation of a
 * centre along e_c gives -dU/dx_c = f_c, a lab rotation by exp(eps [e_c]x) (A <- A R^T,
 * rho <- R rho) gives -dU/deps = k_c.  Relative error per body |fd - f| / max(|f|, floor) with
 * floor = 1e-3 of the largest body force (torque) of the scene, so that a body that hardly
 * interacts is not judged on the round-off of the total energy. */
#include "ff_testutil.h"
#include "ff_scenes.h"

static double norm3(const double a[3]) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/* FD-check every body of the scene; one line per body kind and force/torque. */
static void fd_check(scene *s, const rl_ff_params *p, const char *label)
{
  rl_forcefield *ff = rl_forcefield_alloc(s->sys, p, s->sff, s->nsp);
  if (!ff) fprintf(stderr, "%s\n", rl_last_error());
  assert_non_null(ff);
  ff_result res;
  ff_result_compute(&res, ff, s->sys);
  {
    /* the kernels under test are active in this scene (not a vacuous check) */
    rl_ff_energies en;
    rl_forcefield_energies(ff, &en);
    int ok = en.lj != 0.0;
    if (strstr(label, "RF") || strstr(label, "charge")) ok = ok && en.coulomb != 0.0;
    if (strstr(label, "dipole")) ok = ok && en.dipolar != 0.0;
    if (strstr(label, "quadrupole")) ok = ok && en.quadrupolar != 0.0;
    char nm[200];
    snprintf(nm, sizeof nm, "fd %s: terms active (LJ %.3g, C %.3g, D %.3g, Q %.3g)", label, en.lj,
             en.coulomb, en.dipolar, en.quadrupolar);
    FF_CHECK_TRUE(nm, ok);
  }
  int n = rl_system_count(s->sys);
  double fbig = 0.0, kmax = 0.0;
  for (int i = 0; i < n; i++) {
    fbig = fmax(fbig, norm3(res.f[i]));
    int ri = rl_system_rot_index(s->sys, i);
    if (ri >= 0) kmax = fmax(kmax, norm3(res.k[ri]));
  }
  double errf[6] = {0}, errk[6] = {0};
  int seen[6] = {0};
  for (int i = 0; i < n; i++) {
    rl_kind kind = rl_system_species_kind(s->sys, rl_system_species_of(s->sys, i));
    double fd[3], d[3];
    for (int c = 0; c < 3; c++) fd[c] = -ff_fd_derivative(ff, s->sys, i, 0, c, 1e-4);
    for (int c = 0; c < 3; c++) d[c] = fd[c] - res.f[i][c];
    errf[kind] = fmax(errf[kind], norm3(d) / fmax(norm3(res.f[i]), 1e-3 * fbig));
    seen[kind] = 1;
    int ri = rl_system_rot_index(s->sys, i);
    if (ri >= 0) {
      for (int c = 0; c < 3; c++) fd[c] = -ff_fd_derivative(ff, s->sys, i, 1, c, 1e-4);
      for (int c = 0; c < 3; c++) d[c] = fd[c] - res.k[ri][c];
      errk[kind] = fmax(errk[kind], norm3(d) / fmax(norm3(res.k[ri]), 1e-3 * kmax));
    }
  }
  for (int kind = 0; kind < 6; kind++) {
    if (!seen[kind]) continue;
    char name[160];
    snprintf(name, sizeof name, "fd %s: %s force", label, rl_kind_name((rl_kind)kind));
    FF_CHECK_LE(name, errf[kind], 1e-6);
    if (kind != RL_KIND_POINT) {
      snprintf(name, sizeof name, "fd %s: %s torque", label, rl_kind_name((rl_kind)kind));
      FF_CHECK_LE(name, errk[kind], 1e-6);
    }
  }
  ff_result_free(&res);
  rl_forcefield_free(ff);
}

static const char *scheme_name[] = {"site", "molecule"};

/* Every force-field case of scene `which` (ff_scene_case) on the scene from `seed`. */
static void fd_scene(int which, unsigned long seed)
{
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, seed);
  scene s;
  scene_build(&s, which, rng);
  rl_ff_params p;
  char label[128];
  for (int k = 0; ff_scene_case(which, k, &p, label, sizeof label); k++) fd_check(&s, &p, label);
  rl_system_free(s.sys);
  gsl_rng_free(rng);
}

static void test_fd_lj_coulomb(void **state)
{
  (void)state;
  fd_scene(SCENE_CHARGES, 11);
}

static void test_fd_dipoles(void **state)
{
  (void)state;
  fd_scene(SCENE_DIPOLES, 12);
}

static void test_fd_quadrupoles(void **state)
{
  (void)state;
  fd_scene(SCENE_QUADS, 13);
}

/* ------------------------------------------------------------- Newton and invariance */

static void cross(const double a[3], const double b[3], double c[3])
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

static void pair_check(const ff_test_species *a, const ff_test_species *b, rl_dipole_method dm,
                       const char *label, gsl_rng *rng)
{
  scene s;
  memset(&s, 0, sizeof s);
  s.sys = rl_system_alloc(RL_UNITS_REAL);
  assert_int_equal(rl_system_set_box(s.sys, fd_box), RL_OK);
  scene_add(&s, a, 1);
  scene_add(&s, b, 1);
  for (int k = 0; k < 2; k++) s.sff[k] = ff_test_species_ff(&s.sp[k]);
  double r0[3] = {2.0, 2.1, 1.9}, r1[3] = {2.25, 2.3, 2.05};
  rl_system_set_position(s.sys, 0, r0);
  rl_system_set_position(s.sys, 1, r1);
  ff_random_orientation(s.sys, 0, rng);
  ff_random_orientation(s.sys, 1, rng);
  rl_ff_params p;
  base_params(&p);
  p.dipole_method = dm;
  rl_forcefield *ff = rl_forcefield_alloc(s.sys, &p, s.sff, 2);
  assert_non_null(ff);
  ff_result res;
  ff_result_compute(&res, ff, s.sys);
  double fsum[3], net[3] = {0, 0, 0}, scale = 0.0;
  for (int c = 0; c < 3; c++) fsum[c] = res.f[0][c] + res.f[1][c];
  for (int i = 0; i < 2; i++) {
    double r[3], m[3];
    rl_system_get_position(s.sys, i, r);
    cross(r, res.f[i], m);
    for (int c = 0; c < 3; c++) net[c] += m[c];
    scale += norm3(m);
    int ri = rl_system_rot_index(s.sys, i);
    if (ri >= 0) {
      for (int c = 0; c < 3; c++) net[c] += res.k[ri][c];
      scale += norm3(res.k[ri]);
    }
  }
  char name[160];
  snprintf(name, sizeof name, "newton %s: |f_i + f_j| / |f_i|", label);
  FF_CHECK_LE(name, norm3(fsum) / norm3(res.f[0]), 1e-12);
  snprintf(name, sizeof name, "newton %s: |sum k + r x f| / sum |.|", label);
  FF_CHECK_LE(name, norm3(net) / scale, 1e-12);
  ff_result_free(&res);
  rl_forcefield_free(ff);
  rl_system_free(s.sys);
}

static void test_newton_pairs(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 21);
  ff_test_species a, b;
  ff_water(&a); ff_water(&b);
  pair_check(&a, &b, RL_DIPOLE_RF, "water-water (asymmetric, LJ + RF)", rng);
  ff_symtop(&a); ff_stockmayer(&b, 0.04);
  pair_check(&a, &b, RL_DIPOLE_RF, "symtop-stockmayer (dipole RF, charge-dipole)", rng);
  pair_check(&a, &b, RL_DIPOLE_SF, "symtop-stockmayer (dipole SF, charge-dipole)", rng);
  ff_ion(&a, 1.0); ff_co2(&b);
  pair_check(&a, &b, RL_DIPOLE_RF, "ion-co2 (point, linear)", rng);
  ff_2cljq(&a, 0.012); ff_2cljq(&b, -0.01);
  pair_check(&a, &b, RL_DIPOLE_RF, "2cljq-2cljq (quadrupole)", rng);
  ff_tetra(&a); ff_stockmayer(&b, 0.05);
  pair_check(&a, &b, RL_DIPOLE_RF, "tetra-stockmayer (spherical, dipole)", rng);
  gsl_rng_free(rng);
}

static void test_invariance(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 31);
  static const char *names[] = {"charges", "dipoles", "quadrupoles"};
  for (int which = 0; which < 3; which++)
    for (int sc = 0; sc < 2; sc++) {
      scene s;
      scene_build(&s, which, rng);
      rl_ff_params p;
      base_params(&p);
      p.scheme = (rl_cutoff_scheme)sc;
      p.lj_truncation = RL_LJ_SWITCHED;
      rl_forcefield *ff = rl_forcefield_alloc(s.sys, &p, s.sff, s.nsp);
      assert_non_null(ff);
      double e0 = ff_energy(ff, s.sys);
      rl_ff_energies en;
      rl_forcefield_energies(ff, &en);
      double scale = fabs(en.lj) + fabs(en.coulomb) + fabs(en.dipolar) + fabs(en.quadrupolar);
      int n = rl_system_count(s.sys);
      /* translate */
      double shift[3] = {0.31, -0.47, 0.23};
      for (int i = 0; i < n; i++) {
        double r[3];
        rl_system_get_position(s.sys, i, r);
        for (int c = 0; c < 3; c++) r[c] += shift[c];
        rl_system_set_position(s.sys, i, r);
      }
      double e1 = ff_energy(ff, s.sys);
      char name[160];
      snprintf(name, sizeof name, "invariance %s, %s cutoff: translation |dE|/sum|E_term|",
               names[which], scheme_name[sc]);
      FF_CHECK_LE(name, fabs(e1 - e0) / scale, 1e-12);
      /* rotate about (2, 2, 2) + shift */
      double axis[3] = {0.3, -0.5, 0.8}, R[9], c0[3];
      double an = norm3(axis);
      for (int c = 0; c < 3; c++) { axis[c] /= an; c0[c] = 2.0 + shift[c]; }
      ff_rotation(axis, 1.1, R);
      for (int i = 0; i < n; i++) {
        double r[3], d[3];
        rl_system_get_position(s.sys, i, r);
        for (int c = 0; c < 3; c++) d[c] = r[c] - c0[c];
        for (int a = 0; a < 3; a++)
          r[a] = c0[a] + R[3 * a] * d[0] + R[3 * a + 1] * d[1] + R[3 * a + 2] * d[2];
        rl_system_set_position(s.sys, i, r);
        ff_rotate_body(s.sys, i, R);
      }
      double e2 = ff_energy(ff, s.sys);
      snprintf(name, sizeof name, "invariance %s, %s cutoff: rotation |dE|/sum|E_term|",
               names[which], scheme_name[sc]);
      FF_CHECK_LE(name, fabs(e2 - e0) / scale, 1e-12);
      rl_forcefield_free(ff);
      rl_system_free(s.sys);
    }
  gsl_rng_free(rng);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_fd_lj_coulomb),
      cmocka_unit_test(test_fd_dipoles),
      cmocka_unit_test(test_fd_quadrupoles),
      cmocka_unit_test(test_newton_pairs),
      cmocka_unit_test(test_invariance),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
