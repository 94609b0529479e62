/* Reaction-field Coulomb + LJ against OpenMM 7.7 NonbondedForce.CutoffPeriodic (Reference
 * platform, double precision).  Reference energies from
 *     /usr/bin/python3 validate/openmm_rf_intramolecular.py
 * (lines "rotleap-reference ...: excluded E"; the H1 values are that script's "H1" formula, the
 * GROMACS-style excluded-pair term, checked for the intramolecular_rf = 1 option).
 * Configurations are built exactly as in the script. */
#include "ff_testutil.h"

/* The default Coulomb constant must be OpenMM 7.7's ONE_4PI_EPS0 (CODATA 2018). */
#define KC_OPENMM77 138.93545764438198

static const double openmm_box[3] = {3.0, 3.0, 3.0}; /* the script's periodic cell, nm */
static const double centres[3][3] = {{1.00, 1.10, 0.90}, {1.27, 1.05, 1.12}, {0.85, 1.33, 1.20}};
static const double axes[3][3] = {{0.3, -0.5, 0.8}, {-0.6, 0.2, 0.4}, {0.1, 0.9, -0.3}};
static const double angles[3] = {0.7, 2.1, -1.3};

static void place(rl_system *sys, int i, const double c[3], const double ax[3], double angle)
{
  double n = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
  double u[3] = {ax[0] / n, ax[1] / n, ax[2] / n}, R[9], A[9];
  ff_rotation(u, angle, R);
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) A[3 * a + b] = R[3 * b + a];
  assert_int_equal(rl_system_set_position(sys, i, c), RL_OK);
  assert_int_equal(rl_system_set_orientation(sys, i, A), RL_OK);
}

/* The energy with coulomb_constant set explicitly to kc.  A test compares it, bit for bit, with
 * the energy under the default (coulomb_constant = 0): the default must be OpenMM 7.7's
 * ONE_4PI_EPS0, through the code path the force field takes, not as a constant compared with
 * itself. */
static double energy_with_kc(rl_system *sys, const rl_ff_params *p0, const rl_species_ff *sff,
                             int nspecies, double kc)
{
  rl_ff_params p = *p0;
  p.coulomb_constant = kc;
  rl_forcefield *ff = rl_forcefield_alloc(sys, &p, sff, nspecies);
  assert_non_null(ff);
  double e = ff_energy(ff, sys);
  rl_forcefield_free(ff);
  return e;
}

static void test_tip3p_waters(void **state)
{
  (void)state;
  const double th = 104.52 * (M_PI / 180.0), roh = 0.09572, mo = 15.9994, mh = 1.008;
  double hx = roh * sin(th / 2), hz = roh * cos(th / 2), zc = 2 * mh * hz / (mo + 2 * mh);
  ff_test_species w;
  ff_species_init(&w, "tip3p", RL_KIND_ASYMMETRIC, mo + 2 * mh, 0.6, 1.2, 1.5, 3);
  ff_site(&w, 0, 0, 0, -zc, 0.315061, 0.6364, -0.834);
  ff_site(&w, 1, hx, 0, hz - zc, 1.0, 0.0, 0.417);
  ff_site(&w, 2, -hx, 0, hz - zc, 1.0, 0.0, 0.417);
  rl_system *sys = rl_system_alloc(RL_UNITS_REAL);
  assert_int_equal(rl_system_set_box(sys, openmm_box), RL_OK);
  assert_int_equal(rl_system_add_species(sys, &w.desc, 3, NULL), RL_OK);
  for (int i = 0; i < 3; i++) place(sys, i, centres[i], axes[i], angles[i]);
  rl_species_ff sff = ff_test_species_ff(&w);
  static const double eps[3] = {78.3, 1.0, INFINITY};
  static const double ref_excl[3] = {-4.156065803692, -3.951199574520, -4.160041215642};
  static const double ref_h1[3] = {319.437540290426, 213.482930574396, 321.493580582458};
  for (int k = 0; k < 3; k++)
    for (int nl = 0; nl < 2; nl++) {
      rl_ff_params p;
      rl_ff_params_default(&p);
      p.cutoff = 1.0;
      p.eps_rf = eps[k];
      p.neighbor_list = nl;
      rl_forcefield *ff = rl_forcefield_alloc(sys, &p, &sff, 1);
      assert_non_null(ff);
      double e = ff_energy(ff, sys);
      assert_true(e == energy_with_kc(sys, &p, &sff, 1, KC_OPENMM77));
      char name[160];
      snprintf(name, sizeof name, "openmm 3 TIP3P, eps_rf %g, %s: |E - E_openmm| / |E_openmm|",
               eps[k], nl ? "Verlet list" : "brute force");
      FF_CHECK_LE(name, fabs(e - ref_excl[k]) / fabs(ref_excl[k]), 1e-11);
      rl_forcefield_free(ff);
      p.intramolecular_rf = 1;
      ff = rl_forcefield_alloc(sys, &p, &sff, 1);
      assert_non_null(ff);
      e = ff_energy(ff, sys);
      snprintf(name, sizeof name, "openmm 3 TIP3P, eps_rf %g, %s: intramolecular_rf=1 vs H1",
               eps[k], nl ? "Verlet list" : "brute force");
      FF_CHECK_LE(name, fabs(e - ref_h1[k]) / fabs(ref_h1[k]), 1e-11);
      rl_forcefield_free(ff);
    }
  rl_system_free(sys);
}

/* Two-site molecules whose own charges are further apart than the cutoff. */
static void test_stretched(void **state)
{
  (void)state;
  ff_test_species a, b;
  ff_species_init(&a, "long", RL_KIND_LINEAR, 10.0, 1.0, 1.0, 0.0, 2);
  ff_site(&a, 0, 0, 0, -0.35, 1.0, 0.0, 0.5);
  ff_site(&a, 1, 0, 0, 0.35, 1.0, 0.0, -0.5);
  ff_species_init(&b, "short", RL_KIND_LINEAR, 10.0, 1.0, 1.0, 0.0, 2);
  ff_site(&b, 0, 0, 0, -0.2, 1.0, 0.0, 0.4);
  ff_site(&b, 1, 0, 0, 0.2, 1.0, 0.0, -0.4);
  rl_system *sys = rl_system_alloc(RL_UNITS_REAL);
  assert_int_equal(rl_system_set_box(sys, openmm_box), RL_OK);
  assert_int_equal(rl_system_add_species(sys, &a.desc, 1, NULL), RL_OK);
  assert_int_equal(rl_system_add_species(sys, &b.desc, 1, NULL), RL_OK);
  double r0[3] = {1.0, 1.0, 1.35}, r1[3] = {1.3, 1.2, 1.3};
  assert_int_equal(rl_system_set_position(sys, 0, r0), RL_OK);
  assert_int_equal(rl_system_set_position(sys, 1, r1), RL_OK);
  rl_species_ff sff[2] = {ff_test_species_ff(&a), ff_test_species_ff(&b)};
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = 0.5;
  for (int intra = 0; intra < 2; intra++) {
    p.intramolecular_rf = intra;
    rl_forcefield *ff = rl_forcefield_alloc(sys, &p, sff, 2);
    assert_non_null(ff);
    double e = ff_energy(ff, sys), ref = intra ? 98.860805334241 : 9.793162347143;
    assert_true(e == energy_with_kc(sys, &p, sff, 2, KC_OPENMM77));
    FF_CHECK_LE(intra ? "openmm stretched pair (r_intra 0.7 > rc 0.5): intramolecular_rf=1 vs H1"
                      : "openmm stretched pair (r_intra 0.7 > rc 0.5): |E - E_openmm| / |E|",
                fabs(e - ref) / fabs(ref), 1e-11);
    rl_forcefield_free(ff);
  }
  rl_system_free(sys);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_tip3p_waters),
      cmocka_unit_test(test_stretched),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
