/* Bad input through the public API gets a return code and a message naming the problem. */
#include "expect_error.h"

static int zero_forces(void *ctx, const rl_system *sys, rl_forces *out)
{
  (void)ctx; (void)sys; (void)out;
  return RL_OK;
}

static int failing_forces(void *ctx, const rl_system *sys, rl_forces *out)
{
  (void)ctx; (void)sys; (void)out;
  return rl_error(RL_EINVAL, "sites 3 and 7 overlap");
}

static int nan_forces(void *ctx, const rl_system *sys, rl_forces *out)
{
  (void)ctx; (void)sys;
  out->f[0][1] = NAN;
  return RL_OK;
}

static rl_system *one_body(const double J[3], rl_kind kind)
{
  rl_system *s = rl_system_alloc(RL_UNITS_REAL);
  rl_species_desc d = {.name = "b", .kind = kind, .mass = 18.0, .inertia = {J[0], J[1], J[2]}};
  assert_int_equal(rl_system_add_species(s, &d, 1, NULL), RL_OK);
  return s;
}

static void bad_time_step(void **state)
{
  (void)state;
  const double J[3] = {0.6, 1.2, 1.7};
  rl_system *s = one_body(J, RL_KIND_ASYMMETRIC);
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  const double bad[3] = {0.0, -0.002, NAN};
  for (int k = 0; k < 3; k++) {
    p.h = bad[k];
    rl_integrator *in = rl_integrator_alloc(s, &p, (rl_force_provider){zero_forces, NULL});
    assert_null(in);
    EXPECT_ERROR(RL_EINVAL, RL_EINVAL, "time step h");
  }
  p.h = 0.002;
  p.thermostat = RL_THERMO_ISOKINETIC;
  p.T0 = -5;
  assert_null(rl_integrator_alloc(s, &p, (rl_force_provider){zero_forces, NULL}));
  EXPECT_ERROR(RL_EINVAL, RL_EINVAL, "positive target temperature");
  p.thermostat = RL_THERMO_BUSSI;
  p.T0 = 300;
  p.tau = 0.0;
  assert_null(rl_integrator_alloc(s, &p, (rl_force_provider){zero_forces, NULL}));
  EXPECT_ERROR(RL_EINVAL, RL_EINVAL, "positive relaxation time tau");
  rl_system_free(s);
}

static void bad_inertia(void **state)
{
  (void)state;
  rl_system *s = rl_system_alloc(RL_UNITS_REAL);
  rl_species_desc d = {.name = "bad", .kind = RL_KIND_ASYMMETRIC, .mass = 18.0, .inertia = {0.6, -1.0, 1.7}};
  EXPECT_ERROR(rl_system_add_species(s, &d, 1, NULL), RL_EINVAL, "J[1] = -1");
  d.inertia[1] = NAN;
  EXPECT_ERROR(rl_system_add_species(s, &d, 1, NULL), RL_EINVAL, "J[1] = nan");
  d.inertia[1] = 0.0;
  EXPECT_ERROR(rl_system_add_species(s, &d, 1, NULL), RL_EINVAL, "positive principal moments");
  d.inertia[0] = 0.1; d.inertia[1] = 0.2; d.inertia[2] = 1.0;
  EXPECT_ERROR(rl_system_add_species(s, &d, 1, NULL), RL_EINVAL, "triangle inequality");
  d.inertia[0] = 0.6; d.inertia[1] = 1.2; d.inertia[2] = 1.7; d.mass = 0.0;
  EXPECT_ERROR(rl_system_add_species(s, &d, 1, NULL), RL_EINVAL, "mass 0");
  d.mass = 1.0; d.kind = RL_KIND_LINEAR;
  EXPECT_ERROR(rl_system_add_species(s, &d, 1, NULL), RL_EINVAL, "linear molecule needs moments J, J, 0");
  assert_int_equal(rl_system_count(s), 0);
  rl_system_free(s);
}

static void bad_orientation(void **state)
{
  (void)state;
  const double J[3] = {0.6, 1.2, 1.7};
  rl_system *s = one_body(J, RL_KIND_ASYMMETRIC);
  double A[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  A[1] = 1e-9; /* not orthonormal to 1e-10 */
  EXPECT_ERROR(rl_system_set_orientation(s, 0, A), RL_EORTHO, "not orthonormal");
  A[1] = 1e-12; /* within 1e-10: accepted */
  assert_int_equal(rl_system_set_orientation(s, 0, A), RL_OK);
  double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, -1};
  EXPECT_ERROR(rl_system_set_orientation(s, 0, R), RL_EORTHO, "reflection");
  R[8] = NAN;
  EXPECT_ERROR(rl_system_set_orientation(s, 0, R), RL_ENONFINITE, "non-finite");
  EXPECT_ERROR(rl_system_set_orientation(s, 5, A), RL_EINVAL, "body 5 out of range");
  const double v[3] = {INFINITY, 0, 0};
  EXPECT_ERROR(rl_system_set_velocity(s, 0, v), RL_ENONFINITE, "body 0");
  rl_system_free(s);
}

static void force_errors(void **state)
{
  (void)state;
  const double J[3] = {0.6, 1.2, 1.7};
  rl_system *s = one_body(J, RL_KIND_ASYMMETRIC);
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = 0.002;
  rl_integrator *in = rl_integrator_alloc(s, &p, (rl_force_provider){failing_forces, NULL});
  EXPECT_ERROR(rl_integrator_step(in, NULL), RL_ESTATE, "rl_integrator_init first");
  EXPECT_ERROR(rl_integrator_init(in), RL_EFORCE, "sites 3 and 7 overlap");
  rl_integrator_free(in);
  in = rl_integrator_alloc(s, &p, (rl_force_provider){nan_forces, NULL});
  EXPECT_ERROR(rl_integrator_init(in), RL_ENONFINITE, "non-finite force on body 0");
  rl_integrator_free(in);
  rl_integrator_free(NULL);
  rl_system_free(s);
  rl_system_free(NULL);
}

/* Overflow: angular momenta or steps so large that h|omega| or the kinetic energy leave the range
 * of doubles.  rl_integrator_step may fail, but never with RL_OK and a NaN or Inf in the state
 * or the report; where the kinetic energy itself overflows it says so.  Every rotating kind, and
 * a translation whose drift overflows the position. */
static void overflow_errors(void **state)
{
  (void)state;
  const struct { rl_kind kind; double J[3]; } kinds[] = {
      {RL_KIND_SPHERICAL, {1, 1, 1}},  {RL_KIND_SYMMETRIC, {1, 1, 1.5}}, {RL_KIND_LINEAR, {1, 1, 0}},
      {RL_KIND_DIPOLE, {1, 1, 1}},     {RL_KIND_ASYMMETRIC, {0.6, 1, 1.4}}};
  const double mags[] = {1e100, 1e150, 1e153, 1e155, 1e160};
  int ok_steps = 0, errors = 0, bad = 0;
  for (size_t k = 0; k < sizeof kinds / sizeof *kinds; k++)
    for (size_t m = 0; m < sizeof mags / sizeof *mags; m++) {
      rl_system *s = rl_system_alloc(RL_UNITS_LJ);
      rl_species_desc d = {.name = "x", .kind = kinds[k].kind, .mass = 1.0,
                           .inertia = {kinds[k].J[0], kinds[k].J[1], kinds[k].J[2]}};
      assert_int_equal(rl_system_add_species(s, &d, 1, NULL), RL_OK);
      rl_system_set_removed_dof(s, 0);
      const double l[3] = {mags[m], 0.3 * mags[m], 0.0};
      assert_int_equal(rl_system_set_angmom(s, 0, l), RL_OK);
      rl_integrator_params p;
      rl_integrator_params_default(&p);
      p.h = 1.0;
      rl_integrator *in = rl_integrator_alloc(s, &p, (rl_force_provider){zero_forces, NULL});
      assert_int_equal(rl_integrator_init(in), RL_OK);
      rl_step_info info;
      int st = rl_integrator_step(in, &info);
      double A[9];
      rl_system_get_orientation(s, 0, A);
      int finite = 1;
      for (int c = 0; c < 9; c++) finite &= isfinite(A[c]) != 0;
      if (st == RL_OK) {
        ok_steps++;
        finite &= isfinite(info.ke_rot) && isfinite(info.temperature) && rl_orthonormality_error(A) < 1e-14;
        bad += !finite;
      } else {
        errors++;
      }
      /* |l| = 1e155 and more: J Omega^2 / 2 is beyond 1e308 */
      if (mags[m] >= 1e155) bad += !(st == RL_ENONFINITE && strstr(rl_last_error(), "kinetic energy"));
      printf("info  %-10s |l| = %g: %s%s%s\n", rl_kind_name(kinds[k].kind), mags[m], rl_strerror(st),
             st ? ": " : "", st ? rl_last_error() : "");
      rl_integrator_free(in);
      rl_system_free(s);
    }
  printf("info  %d steps returned RL_OK, %d returned an error\n", ok_steps, errors);
  CHECK_LE("huge l: steps with RL_OK and a non-finite state, or overflow not reported", bad, 0);
  /* the drift: v = 1e150 with h = 1e160 puts r beyond 1e308 */
  rl_system *s = one_body((const double[3]){1, 1, 1}, RL_KIND_SPHERICAL);
  rl_system_set_removed_dof(s, 0);
  assert_int_equal(rl_system_set_velocity(s, 0, (const double[3]){1e150, 0, 0}), RL_OK);
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = 1e160;
  rl_integrator *in = rl_integrator_alloc(s, &p, (rl_force_provider){zero_forces, NULL});
  assert_int_equal(rl_integrator_init(in), RL_OK);
  EXPECT_ERROR(rl_integrator_step(in, NULL), RL_ENONFINITE, "non-finite position of body 0");
  rl_integrator_free(in);
  rl_system_free(s);
}

static void dof_and_kinds(void **state)
{
  (void)state;
  rl_system *s = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc pt = {.name = "atom", .kind = RL_KIND_POINT, .mass = 1.0};
  rl_species_desc dip = {.name = "dip", .kind = RL_KIND_AUTO, .mass = 1.0, .inertia = {0.025, 0.025, 0.0}};
  rl_species_desc sph = {.name = "sph", .kind = RL_KIND_AUTO, .mass = 1.0, .inertia = {1, 1, 1}};
  rl_species_desc sym = {.name = "sym", .kind = RL_KIND_AUTO, .mass = 1.0, .inertia = {1, 1, 1.5}};
  rl_species_desc asy = {.name = "asy", .kind = RL_KIND_AUTO, .mass = 1.0, .inertia = {1, 1.2, 1.5}};
  assert_int_equal(rl_system_add_species(s, &pt, 2, NULL), RL_OK);
  assert_int_equal(rl_system_add_species(s, &dip, 3, NULL), RL_OK);
  assert_int_equal(rl_system_add_species(s, &sph, 1, NULL), RL_OK);
  assert_int_equal(rl_system_add_species(s, &sym, 1, NULL), RL_OK);
  assert_int_equal(rl_system_add_species(s, &asy, 1, NULL), RL_OK);
  assert_int_equal(rl_system_species_kind(s, 1), RL_KIND_LINEAR);
  assert_int_equal(rl_system_species_kind(s, 2), RL_KIND_SPHERICAL);
  assert_int_equal(rl_system_species_kind(s, 3), RL_KIND_SYMMETRIC);
  assert_int_equal(rl_system_species_kind(s, 4), RL_KIND_ASYMMETRIC);
  /* 8 bodies: 3N = 24 translational - 3; rotational 3*2 + 3*3 = 15 */
  int g = rl_system_dof(s);
  printf("check %-58s %d == 36 %s\n", "degrees of freedom (2 points, 3 linear, 3 tops)", g, g == 36 ? "ok" : "FAIL");
  assert_int_equal(g, 36);
  assert_int_equal(rl_system_nrot(s), 6);
  assert_int_equal(rl_system_rot_index(s, 0), -1);
  assert_int_equal(rl_system_rot_index(s, 2), 0);
  rl_system_free(s);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(bad_time_step), cmocka_unit_test(bad_inertia),
                                     cmocka_unit_test(bad_orientation), cmocka_unit_test(force_errors),
                                     cmocka_unit_test(overflow_errors), cmocka_unit_test(dof_and_kinds)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
