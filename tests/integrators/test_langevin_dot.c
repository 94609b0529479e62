/* The Davidchack-Ouldridge-Tretyakov Langevin thermostat (RL_THERMO_LANGEVIN_DOT, O in the middle
 * of the drift; RL_THERMO_LANGEVIN_DOT_OBABO, O in the middle of the kick), with its own
 * rotational friction time tau_rot:
 *  - free bodies (points, asymmetric tops, dipoles): the Ornstein-Uhlenbeck step is exact and the
 *    free motion keeps the Maxwell law, so the translational temperature per lab axis and the
 *    rotational one per principal axis are T0 at a small and at a large step (h |Omega| ~ 1);
 *  - from a cold start the rotational kinetic energy of free tops relaxes as
 *    1 - exp(-2 t / tau_rot) and the translational one as 1 - exp(-2 t / tau): each friction is
 *    the one given (a thermostat that used tau for rotation fails);
 *  - a harmonic trap at h omega = 1 tells the placements apart by their known exact laws: B A O A B
 *    samples the positions exactly, <x^2> = kT/k, so its configurational temperature
 *    <|F|^2>/<lap U> is T0; O B A B O samples the on-step momenta exactly and the positions at
 *    <x^2> = kT / (k (1 - h^2 omega^2/4)) = 4/3 kT/k;
 *  - orientations in a field U = -a b.z (a nearly harmonic libration, h omega = 0.5): the
 *    rotational configurational temperature <|tau|^2> / <sum_c d2U/dphi_c^2> = <a^2 (1 - b_z^2)> /
 *    <2 a b_z> is T0 under B A O A B for every rotating kind; under O B A B O it is the harmonic
 *    libration's 1 / (1 - h^2 omega^2/4) = 1.067 for the bodies with equal moments about x and y
 *    (dipole, symmetric top). */
#include "../testutil.h"
#include "fields.h"

#include <stdlib.h>


static const rl_thermostat schemes[2] = {RL_THERMO_LANGEVIN_DOT, RL_THERMO_LANGEVIN_DOT_OBABO};

static rl_integrator *dot_integrator(rl_system *s, rl_thermostat t, double h, double tau, double tau_rot,
                                     unsigned long seed, rl_force_provider fp)
{
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = h;
  p.thermostat = t;
  p.T0 = 1.0;
  p.tau = tau;
  p.tau_rot = tau_rot;
  p.seed = seed;
  rl_integrator *in = rl_integrator_alloc(s, &p, fp);
  assert_non_null(in);
  assert_int_equal(rl_integrator_init(in), RL_OK);
  return in;
}

/* 60 points, 100 asymmetric tops, 60 dipoles, free, in LJ units (kT = 1) */
static const double top_J[3] = {0.3, 0.5, 0.7};
enum { NPT = 60, NTOP = 100, NDIP = 60 };

static rl_system *free_bodies(double T, unsigned long seed)
{
  rl_system *s = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc pt = {.name = "a", .kind = RL_KIND_POINT, .mass = 1.0};
  rl_species_desc top = {.name = "t", .kind = RL_KIND_ASYMMETRIC, .mass = 2.0};
  memcpy(top.inertia, top_J, sizeof top.inertia);
  rl_species_desc dip = {.name = "d", .kind = RL_KIND_DIPOLE, .mass = 1.0, .inertia = {0.025, 0.025, 0.025}};
  assert_int_equal(rl_system_add_species(s, &pt, NPT, NULL), RL_OK);
  assert_int_equal(rl_system_add_species(s, &top, NTOP, NULL), RL_OK);
  assert_int_equal(rl_system_add_species(s, &dip, NDIP, NULL), RL_OK);
  const double L[3] = {12, 12, 12};
  assert_int_equal(rl_system_lattice(s, L, RL_LATTICE_SC, 1, seed), RL_OK);
  assert_int_equal(rl_system_maxwell_boltzmann(s, T, seed + 1), RL_OK);
  return s;
}

/* Per-axis temperatures of the stored v and l: T[0..2] m v_c^2 over every body, T[3..5]
 * L_a^2 / J_a of the tops (body frame L = A l), T[6] |l|^2 / (2 J) of the dipoles. */
static void axis_temperatures(const rl_system *s, double T[7])
{
  memset(T, 0, 7 * sizeof *T);
  for (int i = 0; i < NPT + NTOP + NDIP; i++) {
    double v[3], m = i >= NPT && i < NPT + NTOP ? 2.0 : 1.0;
    rl_system_get_velocity(s, i, v);
    for (int c = 0; c < 3; c++) T[c] += m * v[c] * v[c] / (NPT + NTOP + NDIP);
    if (i < NPT) continue;
    double l[3];
    rl_system_get_angmom(s, i, l);
    if (i >= NPT + NTOP) {
      T[6] += (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]) / (2.0 * 0.025) / NDIP;
      continue;
    }
    double A[9];
    rl_system_get_orientation(s, i, A);
    for (int a = 0; a < 3; a++) {
      double La = A[3 * a] * l[0] + A[3 * a + 1] * l[1] + A[3 * a + 2] * l[2];
      T[3 + a] += La * La / top_J[a] / NTOP;
    }
  }
}

static void free_bodies_per_axis(void **state)
{
  (void)state;
  static const char *const label[7] = {"v_x", "v_y", "v_z", "L_1", "L_2", "L_3", "dipole l"};
  /* |Omega| ~ sqrt(kT/J) ~ 1.2-2 for the tops: h |Omega| ~ 1 at h = 0.5, ~ 0.5 at 0.25.  The
   * Ornstein-Uhlenbeck step is exact, but the free rotation between two of them is the leapfrog's:
   * with O B A B O it turns the bodies over the whole h after the O, and at h = 0.5 the tops' L_2
   * then reads 2 % cold and L_1, L_3 1 % hot (their sum stays at 3 T0); B A O A B turns them by
   * h/2 after the O and reads 0.5 % on L_2 at h = 0.5, about a quarter.  So O B A B O is checked
   * at h |Omega| ~ 0.5 */
  const double hs[2][2] = {{0.005, 0.5}, {0.005, 0.25}};
  for (int sc = 0; sc < 2; sc++)
    for (int k = 0; k < 2; k++) {
      rl_system *s = free_bodies(3.0, 21 + (unsigned long)(2 * k + sc)); /* start hot */
      const double h = hs[sc][k];
      rl_integrator *in = dot_integrator(s, schemes[sc], h, 2.0 * h, 3.0 * h, 5, (rl_force_provider){no_forces, NULL});
      const long N = 4000, skip = 200;
      double sum[7] = {0};
      for (long t = 0; t < N; t++) {
        assert_int_equal(rl_integrator_step(in, NULL), RL_OK);
        if (t < skip) continue;
        double T[7];
        axis_temperatures(s, T);
        for (int a = 0; a < 7; a++) sum[a] += T[a] / (double)(N - skip);
      }
      /* each mean: 100 tops x 3800 steps correlated over ~tau_rot/h = 3 steps, ~1.3e5 independent
       * values of a chi-squared(1) (variance 2), 1 sigma 0.4 % (translation: 220 bodies, 0.25 %;
       * the dipoles' chi-squared(2)/2, 60 bodies: 0.3 %); the bounds are about 5 sigma */
      printf("info  DOT %s free, h = %g: T/T0 per axis v %.4f %.4f %.4f, tops L %.4f %.4f %.4f, dipoles %.4f\n",
             sc ? "OBABO" : "BAOAB", h, sum[0], sum[1], sum[2], sum[3], sum[4], sum[5], sum[6]);
      for (int a = 0; a < 7; a++) {
        char name[120];
        snprintf(name, sizeof name, "DOT %s free, h = %g: %s T/T0 - 1", sc ? "OBABO" : "BAOAB", h, label[a]);
        CHECK_LE(name, fabs(sum[a] - 1.0), a == 6 ? 0.015 : a < 3 ? 0.012 : 0.02);
      }
      rl_integrator_free(in);
      rl_system_free(s);
    }
}

/* From v = l = 0, free tops, tau_rot = 4 tau: after t, the mean kinetic energy per dof is
 * kT/2 (1 - exp(-2 t / tau_x)) for each part. */
static void friction_times(void **state)
{
  (void)state;
  for (int sc = 0; sc < 2; sc++) {
    rl_system *s = free_bodies(1.0, 41);
    const double zero[3] = {0, 0, 0};
    for (int i = 0; i < NPT + NTOP + NDIP; i++) {
      assert_int_equal(rl_system_set_velocity(s, i, zero), RL_OK);
      if (i >= NPT) assert_int_equal(rl_system_set_angmom(s, i, zero), RL_OK);
    }
    const double h = 0.01, tau = 0.1, tau_rot = 0.4;
    rl_integrator *in = dot_integrator(s, schemes[sc], h, tau, tau_rot, 9 + (unsigned long)sc, (rl_force_provider){no_forces, NULL});
    const int steps = 10; /* t = 0.1: 1 - e^-2 = 0.865 (trans), 1 - e^-0.5 = 0.393 (rot) */
    /* 200 independent repetitions of the 10 steps from the cold start */
    double Kt = 0.0, Kr = 0.0;
    const int reps = 200;
    for (int r = 0; r < reps; r++) {
      for (int i = 0; i < NPT + NTOP + NDIP; i++) {
        assert_int_equal(rl_system_set_velocity(s, i, zero), RL_OK);
        if (i >= NPT) assert_int_equal(rl_system_set_angmom(s, i, zero), RL_OK);
      }
      for (int t = 0; t < steps; t++) assert_int_equal(rl_integrator_step(in, NULL), RL_OK);
      double T[7];
      axis_temperatures(s, T);
      Kt += (T[0] + T[1] + T[2]) / 3.0 / reps;
      Kr += (T[3] + T[4] + T[5]) / 3.0 / reps;
    }
    const double want_t = -expm1(-2.0 * steps * h / tau), want_r = -expm1(-2.0 * steps * h / tau_rot);
    printf("info  %s: T_trans/T0 = %.4f (want %.4f), tops' T_rot/T0 = %.4f (want %.4f)\n", sc ? "OBABO" : "BAOAB", Kt,
           want_t, Kr, want_r);
    /* 220 bodies x 3 x 200 (1 sigma 0.2 %) and 100 tops x 3 x 200 (0.3 % of the value); 5 sigma */
    CHECK_LE(sc ? "DOT OBABO from rest: |T_trans/T0 / (1 - exp(-2t/tau)) - 1|" : "DOT BAOAB from rest: |T_trans/T0 / (1 - exp(-2t/tau)) - 1|",
             fabs(Kt / want_t - 1.0), 0.012);
    CHECK_LE(sc ? "DOT OBABO from rest: |T_rot/T0 / (1 - exp(-2t/tau_rot)) - 1|" : "DOT BAOAB from rest: |T_rot/T0 / (1 - exp(-2t/tau_rot)) - 1|",
             fabs(Kr / want_r - 1.0), 0.02);
    rl_integrator_free(in);
    rl_system_free(s);
  }
}

static void harmonic_placements(void **state)
{
  (void)state;
  for (int sc = 0; sc < 2; sc++) {
    rl_system *s = rl_system_alloc(RL_UNITS_LJ);
    rl_species_desc pt = {.name = "a", .kind = RL_KIND_POINT, .mass = 1.0};
    const int n = 100;
    assert_int_equal(rl_system_add_species(s, &pt, n, NULL), RL_OK);
    const double zero[3] = {0, 0, 0};
    for (int i = 0; i < n; i++) assert_int_equal(rl_system_set_position(s, i, zero), RL_OK);
    assert_int_equal(rl_system_maxwell_boltzmann(s, 1.0, 5), RL_OK);
    double kspring = 1.0; /* omega = 1, h omega = 1, gamma h = 1 */
    rl_integrator *in = dot_integrator(s, schemes[sc], 1.0, 1.0, 0.0, 17, (rl_force_provider){harmonic_trap, &kspring});
    const long N = 20000, skip = 500;
    double x2 = 0.0, ton = 0.0;
    for (long k = 0; k < N; k++) {
      rl_step_info info;
      assert_int_equal(rl_integrator_step(in, &info), RL_OK);
      if (k < skip) continue;
      ton += info.t_trans / (double)(N - skip);
      for (int i = 0; i < n; i++) {
        double r[3];
        rl_system_get_position(s, i, r);
        x2 += (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) / (3.0 * n * (double)(N - skip));
      }
    }
    /* T_conf = <|F|^2> / <lap U> = k^2 <x^2> / k = k <x^2>; 300 oscillators x 19500 steps,
     * correlated over <= 2 steps: 1 sigma <= 0.2 %, the bounds ~5 sigma */
    printf("info  DOT %s trap, h omega = 1: T_conf/T0 = k<x^2>/kT = %.4f, on-step T/T0 = %.4f\n", sc ? "OBABO" : "BAOAB",
           x2, ton);
    if (sc == 0) {
      CHECK_LE("DOT BAOAB harmonic trap, h omega = 1: |T_conf/T0 - 1|", fabs(x2 - 1.0), 0.01);
    } else {
      CHECK_LE("DOT OBABO harmonic trap, h omega = 1: |k<x^2>/kT - 4/3|", fabs(x2 - 4.0 / 3.0), 0.015);
      CHECK_LE("DOT OBABO harmonic trap: |on-step T/T0 - 1| (momenta exact)", fabs(ton - 1.0), 0.01);
    }
    rl_integrator_free(in);
    rl_system_free(s);
  }
}

static void orientations_tconf(void **state)
{
  (void)state;
  struct { rl_kind kind; double J[3]; const char *name; } kinds[] = {
      {RL_KIND_DIPOLE, {0.025, 0.025, 0.025}, "dipole"},
      {RL_KIND_SYMMETRIC, {0.3, 0.3, 0.6}, "symmetric"},
      {RL_KIND_ASYMMETRIC, {0.3, 0.5, 0.7}, "asymmetric"}};
  const double a = 20.0;
  for (int sc = 0; sc < 2; sc++)
    for (size_t k = 0; k < sizeof kinds / sizeof *kinds; k++) {
      rl_system *s = rl_system_alloc(RL_UNITS_LJ);
      rl_species_desc d = {.name = "m", .kind = kinds[k].kind, .mass = 1.0};
      memcpy(d.inertia, kinds[k].J, sizeof d.inertia);
      const int n = 200;
      assert_int_equal(rl_system_add_species(s, &d, n, NULL), RL_OK);
      const double L[3] = {20, 20, 20};
      assert_int_equal(rl_system_lattice(s, L, RL_LATTICE_SC, 1, 11), RL_OK);
      assert_int_equal(rl_system_maxwell_boltzmann(s, 1.0, 12), RL_OK);
      const double omega = sqrt(a / fmin(kinds[k].J[0], kinds[k].J[1]));
      const double h = 0.5 / omega;
      double aa = a;
      rl_integrator *in = dot_integrator(s, schemes[sc], h, 5.0 * h, 3.0 * h, 13, (rl_force_provider){axis_field, &aa});
      const long N = 5000, skip = 500;
      double num = 0.0, den = 0.0;
      for (long t = 0; t < N; t++) {
        assert_int_equal(rl_integrator_step(in, NULL), RL_OK);
        if (t < skip) continue;
        for (int i = 0; i < n; i++) {
          double b[3];
          rl_system_get_axis(s, i, b);
          num += a * a * (1.0 - b[2] * b[2]);
          den += 2.0 * a * b[2];
        }
      }
      /* |tau|^2 = a^2 (1 - b_z^2) has a relative sd ~ 1 (2 dof, exponential-like), 200 bodies x
       * 4500 steps correlated over ~3-5 steps: ~2e5 values, 1 sigma ~ 0.3 %; the bound 2 % leaves
       * room for the O(h^2) error of the anharmonic libration at h omega = 0.5 */
      char name[120];
      const double want = sc ? 1.0 / (1.0 - 0.25 * 0.25) : 1.0;
      printf("info  DOT %s field, %s: T_conf,rot/T0 = %.4f\n", sc ? "OBABO" : "BAOAB", kinds[k].name, num / den);
      snprintf(name, sizeof name, "DOT %s field, %s, h omega = 0.5: |T_conf,rot/T0 - %.3f|", sc ? "OBABO" : "BAOAB",
               kinds[k].name, want);
      if (sc == 0 || kinds[k].kind != RL_KIND_ASYMMETRIC) CHECK_LE(name, fabs(num / den - want), 0.02);
      rl_integrator_free(in);
      rl_system_free(s);
    }
}

/* A negative tau_rot is refused by name; 0 means tau. */
static void bad_tau_rot(void **state)
{
  (void)state;
  rl_system *s = free_bodies(1.0, 3);
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = 0.01;
  p.thermostat = RL_THERMO_LANGEVIN_DOT;
  p.T0 = 1.0;
  p.tau = 0.1;
  p.tau_rot = -1.0;
  rl_integrator *in = rl_integrator_alloc(s, &p, (rl_force_provider){no_forces, NULL});
  printf("info  %s\n", rl_last_error());
  CHECK_LE("DOT: tau_rot < 0 refused, naming tau_rot", (in != NULL) + (strstr(rl_last_error(), "tau_rot") == NULL), 0);
  rl_integrator_free(in);
  rl_system_free(s);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(free_bodies_per_axis), cmocka_unit_test(friction_times),
                                     cmocka_unit_test(harmonic_placements), cmocka_unit_test(orientations_tconf),
                                     cmocka_unit_test(bad_tau_rot)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
