/* A free asymmetric top through the public API: second-order convergence of the orientation
 * against a gsl_odeiv2 reference, 10^6-step rigidity and conservation, time reversibility, and
 * the quaternion variant. */
#include "../free_top_ref.h"

#include <gsl/gsl_fit.h>
#include <gsl/gsl_statistics_double.h>

static void convergence(void **state)
{
  (void)state;
  free_top_order(RL_ROT_CUBIC, "cubic", 0.05);
  free_top_order(RL_ROT_EXACT, "exact", 0.05);
  /* "converges to the same trajectory as h -> 0": the quaternion variant converges to the
   * same reference solution at second order */
  free_top_order(RL_ROT_QUATERNION, "quaternion", 0.05);
}

/* 10^6 steps: rigidity to round-off, l exactly constant, no drift of the rotational energy.
 * For a free top the revised scheme is the implicit midpoint rule for L_body = A l
 * (L(t+h) - L(t) = h W(Omega) L_mid, Omega = J^-1 L_mid), which conserves the quadratic
 * invariant L^T J^-1 L exactly: the on-step KE_rot may differ from its start by round-off only.
 * So rather than a loose drift bound, the check is that it never leaves 1e-12 of KE_0. */
static void long_run(void **state)
{
  (void)state;
  const long N = 1000000;
  const double h = 0.02; /* h|Omega| ~ 0.02 */
  top t = make_top(h, RL_ROT_CUBIC, NULL);
  double *ke = malloc(sizeof(double) * (size_t)N), *tt = malloc(sizeof(double) * (size_t)N);
  double worst_orth = 0.0, ke0 = 0.0, worst_ke = 0.0;
  for (long s = 0; s < N; s++) {
    rl_step_info info;
    assert_int_equal(rl_integrator_step(t.in, &info), RL_OK);
    ke[s] = info.ke_rot;
    if (s == 0) ke0 = info.ke_rot;
    worst_ke = fmax(worst_ke, fabs(info.ke_rot - ke0) / ke0);
    tt[s] = info.t;
    if (s % 1000 == 999) {
      double A[9];
      rl_system_get_orientation(t.sys, 0, A);
      worst_orth = fmax(worst_orth, rl_orthonormality_error(A));
    }
  }
  double l[3];
  rl_system_get_angmom(t.sys, 0, l);
  double dl[3] = {l[0] - L0[0], l[1] - L0[1], l[2] - L0[2]};
  double c0, c1, cov00, cov01, cov11, sumsq;
  gsl_fit_linear(tt, 1, ke, 1, (size_t)N, &c0, &c1, &cov00, &cov01, &cov11, &sumsq);
  double sd = gsl_stats_sd(ke, 1, (size_t)N), mean = gsl_stats_mean(ke, 1, (size_t)N);
  double drift = fabs(c1) * (tt[N - 1] - tt[0]);
  printf("info  KE_rot mean %.10f, sd %.3e, fitted drift over run %.3e\n", mean, sd, drift);
  CHECK_LE("10^6 steps: max |A^T A - I|", worst_orth, 1e-13);
  CHECK_LE("10^6 steps: |l - l0| / |l0|", norm3d(dl) / norm3d(L0), 1e-13);
  CHECK_LE("10^6 steps: max |KE_rot - KE_0| / KE_0", worst_ke, 1e-12);
  CHECK_LE("10^6 steps: fitted KE_rot drift over run / KE_0", drift / ke0, 1e-12);
  free(ke);
  free(tt);
  free_top(&t);
}

/* N steps, reverse the momenta, N steps: back to the start.  The matrix scheme is reversible
 * to round-off.  The quaternion variant is reversible only up to its iteration tolerance (each
 * step stops ~quat_tol short of the implicit solution, in a direction that does not reverse),
 * so it is run here at quat_tol = 1e-15; at the default 1e-12 the loss after 2 x 1000 steps
 * is ~4e-10 (printed for information). */
static void reversibility(void **state)
{
  (void)state;
  const double L[3] = {3.0, -2.0, 1.5}; /* h|Omega| ~ 0.1 per step: a demanding rotation */
  const char *nm[3] = {"cubic", "exact", "quaternion"};
  for (int m = 0; m < 3; m++) {
    double eA, el;
    free_top_reverse_error((rl_rot_method)m, L, 1e-15, &eA, &el);
    char name[96];
    snprintf(name, sizeof name, "reversibility (%s): max |A_back - A_0|", nm[m]);
    CHECK_LE(name, eA, 1e-10);
    snprintf(name, sizeof name, "reversibility (%s): |l_back + l_0|", nm[m]);
    CHECK_LE(name, el, 1e-10);
  }
  double eA, el;
  free_top_reverse_error(RL_ROT_QUATERNION, L, 1e-12, &eA, &el);
  printf("info  reversibility (quaternion, quat_tol 1e-12): max |A_back - A_0| = %.2e\n", eA);
}

/* Quaternion variant: |q| = 1 to 1e-13 over 10^6 steps; iterations counted. */
static void quaternion_norm(void **state)
{
  (void)state;
  top t = make_top(0.02, RL_ROT_QUATERNION, NULL);
  double worst = 0.0;
  for (long s = 0; s < 1000000; s++) {
    assert_int_equal(rl_integrator_step(t.in, NULL), RL_OK);
    if (s % 97 == 0) {
      double q[4];
      assert_int_equal(rl_integrator_quaternion(t.in, 0, q), RL_OK);
      worst = fmax(worst, fabs(sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) - 1.0));
    }
  }
  double per = (double)rl_integrator_quat_iterations(t.in) / 1000000.0;
  printf("info  quaternion iterations per step: %.2f\n", per);
  CHECK_LE("quaternion: max ||q| - 1| over 10^6 steps", worst, 1e-13);
  assert_true(per >= 1.0);
  free_top(&t);
}

/* RL_ROT_QUATERNION moves only general-path bodies by q; spherical and symmetric tops keep their
 * fast paths and must come out exactly as under RL_ROT_CUBIC, also across the periodic polish
 * at step 256 (which once rebuilt every A from the never-advanced q of such bodies). */
static void quaternion_fast_paths(void **state)
{
  (void)state;
  const double Js[2][3] = {{1.0, 1.0, 1.7}, {1.3, 1.3, 1.3}};
  const rl_kind kinds[2] = {RL_KIND_SYMMETRIC, RL_KIND_SPHERICAL};
  for (int k = 0; k < 2; k++) {
    double A[2][9];
    for (int m = 0; m < 2; m++) {
      rl_system *sys = rl_system_alloc(RL_UNITS_LJ);
      rl_species_desc d = {.name = "top", .kind = kinds[k], .mass = 1.0,
                           .inertia = {Js[k][0], Js[k][1], Js[k][2]}};
      assert_int_equal(rl_system_add_species(sys, &d, 1, NULL), RL_OK);
      assert_int_equal(rl_system_set_angmom(sys, 0, L0), RL_OK);
      rl_integrator_params p;
      rl_integrator_params_default(&p);
      p.h = 0.02;
      p.method = m ? RL_ROT_QUATERNION : RL_ROT_CUBIC;
      rl_integrator *in = rl_integrator_alloc(sys, &p, (rl_force_provider){zero_forces, NULL});
      assert_non_null(in);
      assert_int_equal(rl_integrator_init(in), RL_OK);
      for (int s = 0; s < 300; s++) assert_int_equal(rl_integrator_step(in, NULL), RL_OK);
      rl_system_get_orientation(sys, 0, A[m]);
      rl_integrator_free(in);
      rl_system_free(sys);
    }
    char name[96];
    snprintf(name, sizeof name, "quaternion method, %s top, 300 steps: |A - A_cubic|", rl_kind_name(kinds[k]));
    CHECK_LE(name, max_abs_diff(A[0], A[1], 9), 0.0);
  }
}

/* rl_integrator_quaternion returns a q with A(q) = A for every matrix body under RL_ROT_QUATERNION:
 * the iterated q of the general path (asymmetric, and any top with force_general), the q of A for
 * the spherical and symmetric fast paths (it once returned their q(0) forever: |A - A(q)| = 0.8
 * after 100 steps).  Checked after 300 steps, past the polish at step 256.  Bodies without an
 * orientation matrix, and the methods without quaternions, are refused with RL_ESTATE. */
static void quaternion_of_every_kind(void **state)
{
  (void)state;
  const struct { rl_kind kind; double J[3]; int general; } bodies[] = {
      {RL_KIND_SPHERICAL, {1.3, 1.3, 1.3}, 0}, {RL_KIND_SYMMETRIC, {1.0, 1.0, 1.7}, 0},
      {RL_KIND_SYMMETRIC, {1.7, 1.0, 1.0}, 0}, {RL_KIND_ASYMMETRIC, {0.6, 1.2, 1.7}, 0},
      {RL_KIND_SPHERICAL, {1.3, 1.3, 1.3}, 1}, {RL_KIND_SYMMETRIC, {1.0, 1.0, 1.7}, 1}};
  double worst = 0.0, turned = 1.0;
  for (size_t k = 0; k < sizeof bodies / sizeof *bodies; k++) {
    rl_system *sys = rl_system_alloc(RL_UNITS_LJ);
    rl_species_desc d = {.name = "top", .kind = bodies[k].kind, .mass = 1.0,
                         .inertia = {bodies[k].J[0], bodies[k].J[1], bodies[k].J[2]}};
    assert_int_equal(rl_system_add_species(sys, &d, 1, NULL), RL_OK);
    assert_int_equal(rl_system_set_angmom(sys, 0, L0), RL_OK);
    rl_integrator_params p;
    rl_integrator_params_default(&p);
    p.h = 0.02;
    p.method = RL_ROT_QUATERNION;
    p.force_general = bodies[k].general;
    rl_integrator *in = rl_integrator_alloc(sys, &p, (rl_force_provider){zero_forces, NULL});
    assert_int_equal(rl_integrator_init(in), RL_OK);
    for (int s = 0; s < 300; s++) assert_int_equal(rl_integrator_step(in, NULL), RL_OK);
    double q[4], A[9], Aq[9];
    assert_int_equal(rl_integrator_quaternion(in, 0, q), RL_OK);
    rl_quat_to_matrix(q, Aq);
    rl_system_get_orientation(sys, 0, A);
    worst = fmax(worst, max_abs_diff(A, Aq, 9));
    const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    turned = fmin(turned, max_abs_diff(A, I, 9)); /* the body has moved away from A(0) = I */
    rl_integrator_free(in);
    rl_system_free(sys);
  }
  printf("info  smallest max |A - I| after 300 steps: %.3f\n", turned);
  assert_true(turned > 0.1);
  CHECK_LE("rl-quaternion, every matrix kind: max |A - A(rl_integrator_quaternion)|", worst, 1e-14);
  /* refusals */
  rl_system *sys = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc lin = {.name = "rod", .kind = RL_KIND_LINEAR, .mass = 1.0, .inertia = {1, 1, 0}};
  rl_species_desc top = {.name = "top", .kind = RL_KIND_ASYMMETRIC, .mass = 1.0, .inertia = {0.6, 1.2, 1.7}};
  assert_int_equal(rl_system_add_species(sys, &lin, 1, NULL), RL_OK);
  assert_int_equal(rl_system_add_species(sys, &top, 1, NULL), RL_OK);
  for (int m = 0; m < 2; m++) {
    rl_integrator_params p;
    rl_integrator_params_default(&p);
    p.h = 0.02;
    p.method = m ? RL_ROT_CUBIC : RL_ROT_QUATERNION;
    rl_integrator *in = rl_integrator_alloc(sys, &p, (rl_force_provider){zero_forces, NULL});
    assert_int_equal(rl_integrator_init(in), RL_OK);
    double q[4];
    int st0 = rl_integrator_quaternion(in, 0, q), st1 = rl_integrator_quaternion(in, 1, q);
    int ok = st0 == RL_ESTATE && (m ? st1 == RL_ESTATE : st1 == RL_OK);
    printf("check %-58s %s\n", m ? "rl: no body has a quaternion" : "rl-quaternion: the linear body has none, the top has one",
           ok ? "ok" : "FAIL");
    assert_true(ok);
    assert_int_equal(rl_integrator_quaternion(in, 2, q), RL_EINVAL);
    rl_integrator_free(in);
  }
  rl_system_free(sys);
}

/* The asymmetric bodies' rotation solves run on rl_integrator_params.threads OpenMP threads;
 * bodies are independent and report only a count and a maximum, so 1, 2 and 3 threads must
 * give the same orientations bit for bit, the same fallback count and the same max h|Omega|.
 * 300 random tops spinning at h|Omega| up to about 2.5, by the cubic (which then falls back to
 * Newton for some) and by the exact solve. */
static void threaded_rotations(void **state)
{
  (void)state;
  const int n = 300;
  const rl_rot_method methods[2] = {RL_ROT_CUBIC, RL_ROT_EXACT};
  for (int m = 0; m < 2; m++) {
    double *A[3];
    long fb[3];
    double hw[3];
    for (int t = 0; t < 3; t++) {
      gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
      gsl_rng_set(r, 31);
      rl_system *sys = rl_system_alloc(RL_UNITS_LJ);
      rl_species_desc d = {.name = "top", .kind = RL_KIND_ASYMMETRIC, .mass = 1.0,
                           .inertia = {1.0, 1.6, 2.3}};
      assert_int_equal(rl_system_add_species(sys, &d, n, NULL), RL_OK);
      for (int i = 0; i < n; i++) {
        double R[9], l[3];
        random_rotation(r, R);
        assert_int_equal(rl_system_set_orientation(sys, i, R), RL_OK);
        for (int c = 0; c < 3; c++) l[c] = gsl_ran_gaussian(r, 1.0 + 40.0 * (i % 7 == 0));
        assert_int_equal(rl_system_set_angmom(sys, i, l), RL_OK);
      }
      rl_integrator_params p;
      rl_integrator_params_default(&p);
      p.h = 0.02;
      p.method = methods[m];
      p.threads = t + 1;
      rl_integrator *in = rl_integrator_alloc(sys, &p, (rl_force_provider){zero_forces, NULL});
      assert_non_null(in);
      assert_int_equal(rl_integrator_init(in), RL_OK);
      hw[t] = 0.0;
      for (int s = 0; s < 300; s++) {
        rl_step_info info;
        assert_int_equal(rl_integrator_step(in, &info), RL_OK);
        if (info.max_h_omega > hw[t]) hw[t] = info.max_h_omega;
      }
      fb[t] = rl_integrator_fallbacks(in);
      A[t] = malloc(sizeof(double) * 9 * (size_t)n);
      for (int i = 0; i < n; i++) rl_system_get_orientation(sys, i, A[t] + 9 * i);
      rl_integrator_free(in);
      rl_system_free(sys);
      gsl_rng_free(r);
    }
    for (int t = 1; t < 3; t++) {
      char name[128];
      snprintf(name, sizeof name, "%s, %d threads against 1, 300 steps: max |A - A_1|",
               m ? "exact" : "cubic", t + 1);
      CHECK_LE(name, max_abs_diff(A[0], A[t], 9 * n), 0.0);
      snprintf(name, sizeof name, "%s, %d threads: |fallbacks - 1's| + |max h|Omega| - 1's|",
               m ? "exact" : "cubic", t + 1);
      CHECK_LE(name, fabs((double)(fb[t] - fb[0])) + fabs(hw[t] - hw[0]), 0.0);
    }
    printf("%s: %ld fallbacks to Newton over 300 steps, max h|Omega| = %.2f\n", m ? "exact" : "cubic",
           fb[0], hw[0]);
    for (int t = 0; t < 3; t++) free(A[t]);
  }
  /* a negative count is refused with a message naming it */
  rl_system *sys = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc d = {.name = "top", .kind = RL_KIND_ASYMMETRIC, .mass = 1.0, .inertia = {1.0, 1.6, 2.3}};
  assert_int_equal(rl_system_add_species(sys, &d, 2, NULL), RL_OK);
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = 0.02;
  p.threads = -1;
  rl_integrator *bad = rl_integrator_alloc(sys, &p, (rl_force_provider){zero_forces, NULL});
  CHECK_LE("threads = -1: an integrator is made (1 = yes)", bad != NULL, 0);
  printf("  message: %s\n", rl_last_error());
  CHECK_LE("  the message does not name the threads (1 = so)", strstr(rl_last_error(), "threads") == NULL, 0);
  rl_system_free(sys);
}

/* Forces for threaded_body_loops: each centre tethered to the origin, each axis pulled towards z. */
static int tether(void *ctx, const rl_system *sys, rl_forces *out)
{
  (void)ctx;
  for (int i = 0; i < rl_system_count(sys); i++) {
    double r[3], u[3];
    rl_system_get_position(sys, i, r);
    rl_system_get_axis(sys, i, u);
    for (int c = 0; c < 3; c++) out->f[i][c] = -r[c];
    out->energy += 0.5 * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) - u[2];
    const int ri = rl_system_rot_index(sys, i);
    if (ri >= 0) { /* u x z */
      out->k[ri][0] += u[1];
      out->k[ri][1] -= u[0];
    }
  }
  return RL_OK;
}

/* The per-body loops of a step (kick, drift, kinetic sums, the dipoles' and rods' rotations)
 * on 1, 2 and 3 threads: bit for bit the same trajectory.  Enough bodies of each species to
 * take the threads (RL_THREAD_MIN_BODIES, 512) and to span several summation blocks with a
 * partial last one; the Bussi thermostat makes the trajectory depend on the kinetic sums'
 * rounding. */
static void threaded_body_loops(void **state)
{
  (void)state;
  const int nd = 3000, nl = 2500, n = nd + nl, steps = 40;
  double *X[3], T[3][40];
  for (int t = 0; t < 3; t++) {
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 5);
    rl_system *sys = rl_system_alloc(RL_UNITS_LJ);
    rl_species_desc d = {.name = "stock", .kind = RL_KIND_DIPOLE, .mass = 1.0,
                         .inertia = {0.1, 0.1, 0.1}};
    rl_species_desc rod = {.name = "rod", .kind = RL_KIND_LINEAR, .mass = 2.0,
                           .inertia = {0.5, 0.5, 0.0}};
    assert_int_equal(rl_system_add_species(sys, &d, nd, NULL), RL_OK);
    assert_int_equal(rl_system_add_species(sys, &rod, nl, NULL), RL_OK);
    for (int i = 0; i < n; i++) {
      double x[3], v[3], u[3], l[3];
      for (int c = 0; c < 3; c++) {
        x[c] = gsl_ran_gaussian(r, 1.0);
        v[c] = gsl_ran_gaussian(r, 1.0);
        l[c] = gsl_ran_gaussian(r, 0.5);
      }
      gsl_ran_dir_3d(r, u, u + 1, u + 2);
      assert_int_equal(rl_system_set_position(sys, i, x), RL_OK);
      assert_int_equal(rl_system_set_velocity(sys, i, v), RL_OK);
      assert_int_equal(rl_system_set_axis(sys, i, u), RL_OK);
      double lu = l[0] * u[0] + l[1] * u[1] + l[2] * u[2]; /* no spin about the axis */
      for (int c = 0; c < 3; c++) l[c] -= lu * u[c];
      assert_int_equal(rl_system_set_angmom(sys, i, l), RL_OK);
    }
    rl_integrator_params p;
    rl_integrator_params_default(&p);
    p.h = 0.01;
    p.thermostat = RL_THERMO_BUSSI;
    p.T0 = 0.5;
    p.tau = 0.05;
    p.seed = 9;
    p.threads = t + 1;
    rl_integrator *in = rl_integrator_alloc(sys, &p, (rl_force_provider){tether, NULL});
    assert_non_null(in);
    assert_int_equal(rl_integrator_init(in), RL_OK);
    for (int s = 0; s < steps; s++) {
      rl_step_info info;
      assert_int_equal(rl_integrator_step(in, &info), RL_OK);
      T[t][s] = info.temperature + info.t_trans_mid + info.t_rot_mid;
    }
    X[t] = malloc(sizeof(double) * 9 * (size_t)n);
    for (int i = 0; i < n; i++) {
      rl_system_get_position(sys, i, X[t] + 9 * i);
      rl_system_get_velocity(sys, i, X[t] + 9 * i + 3);
      rl_system_get_axis(sys, i, X[t] + 9 * i + 6);
    }
    rl_integrator_free(in);
    rl_system_free(sys);
    gsl_rng_free(r);
  }
  for (int t = 1; t < 3; t++) {
    char name[128];
    snprintf(name, sizeof name, "dipoles and rods, %d threads against 1, %d Bussi steps: max |(r, v, "
             "rho) - 1's|", t + 1, steps);
    CHECK_LE(name, max_abs_diff(X[0], X[t], 9 * n), 0.0);
    snprintf(name, sizeof name, "  temperatures (on-step, mid-step) - 1's");
    CHECK_LE(name, max_abs_diff(T[0], T[t], steps), 0.0);
  }
  for (int t = 0; t < 3; t++) free(X[t]);
}

int main(void)
{
  gsl_set_error_handler_off();
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(convergence), cmocka_unit_test(long_run), cmocka_unit_test(reversibility),
      cmocka_unit_test(quaternion_norm), cmocka_unit_test(quaternion_fast_paths),
      cmocka_unit_test(quaternion_of_every_kind),
      cmocka_unit_test(threaded_rotations), cmocka_unit_test(threaded_body_loops)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
