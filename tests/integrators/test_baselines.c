/* The baseline integrators of issue 7 (RL_ROT_HYBRID, RL_ROT_FINCHAM, RL_ROT_NOSQUISH): second
 * order on the free asymmetric top against rk8pd, energy-fluctuation order on the chaotic
 * cluster, NO_SQUISH's norm, rigidity and reversibility, Fincham's iteration counts and its
 * clean failure, the hybrid's derived deviation from the matrix scheme, the isokinetic
 * composition, bit-for-bit resume, and the refusal of axis-only species. */
#include "../cluster_util.h"
#include "../free_top_ref.h"

#define NMETH 3
static const rl_rot_method METHODS[NMETH] = {RL_ROT_HYBRID, RL_ROT_FINCHAM, RL_ROT_NOSQUISH};

/* One free body of any matrix kind. */
static top make_body(rl_kind kind, const double J[3], const double L[3], double h,
                     rl_rot_method m, rl_thermostat th, double T0)
{
  top t;
  t.sys = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc d = {.name = "body", .kind = kind, .mass = 1.0, .inertia = {J[0], J[1], J[2]}};
  assert_int_equal(rl_system_add_species(t.sys, &d, 1, NULL), RL_OK);
  rl_system_set_removed_dof(t.sys, 0);
  assert_int_equal(rl_system_set_angmom(t.sys, 0, L), RL_OK);
  t.in = start_integrator(t.sys, h, m, th, T0, zero_forces);
  return t;
}

/* Rotation angle and unit axis of the rotation matrix R (row-major). */
static double rotation_angle(const double R[9], double axis[3])
{
  double w[3] = {0.5 * (R[7] - R[5]), 0.5 * (R[2] - R[6]), 0.5 * (R[3] - R[1])};
  double s = norm3d(w), c = 0.5 * (R[0] + R[4] + R[8] - 1.0);
  for (int k = 0; k < 3; k++) axis[k] = s > 0.0 ? w[k] / s : 0.0;
  return atan2(s, c);
}

/* R = A B^T */
static void mul_abt(const double A[9], const double B[9], double R[9])
{
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      R[3 * i + j] = A[3 * i] * B[3 * j] + A[3 * i + 1] * B[3 * j + 1] + A[3 * i + 2] * B[3 * j + 2];
}

/* Each baseline converges at second order to the rk8pd solution.  Fincham: the trapezoidal rule
 * with the exact l~(t+h) (no torque), its rescaling of q is an O(h^3) change; NO_SQUISH: a
 * symmetric composition of exact flows; hybrid: see hybrid_vs_matrix. */
static void free_top_convergence(void **state)
{
  (void)state;
  free_top_order(RL_ROT_HYBRID, "hybrid", 0.05);
  free_top_order(RL_ROT_FINCHAM, "fincham", 0.05);
  free_top_order(RL_ROT_NOSQUISH, "no-squish", 0.05);
}

/* Total-energy fluctuation over T = 4 on the chaotic cluster at h = 0.04 ... 0.005: order 2 +-
 * 0.2, the bound test_cluster sets for the revised leapfrog. */
static void cluster_energy_order(void **state)
{
  (void)state;
  const double hs[4] = {0.04, 0.02, 0.01, 0.005};
  for (int m = 0; m < NMETH; m++) {
    double sd[4];
    for (int k = 0; k < 4; k++) sd[k] = cluster_energy_sd(METHODS[m], hs[k], 4.0);
    for (int k = 0; k < 3; k++) {
      char name[96];
      snprintf(name, sizeof name, "%s: energy sd order h=%g->%g (%.2e->%.2e)",
               rl_rot_method_name(METHODS[m]), hs[k], hs[k + 1], sd[k], sd[k + 1]);
      CHECK_NEAR(name, log2(sd[k] / sd[k + 1]), 2.0, 0.2);
    }
  }
  double ref = cluster_energy_sd(RL_ROT_CUBIC, 0.01, 4.0);
  printf("info  energy sd at h = 0.01: rl %.3e", ref);
  for (int m = 0; m < NMETH; m++)
    printf(", %s %.3e", rl_rot_method_name(METHODS[m]), cluster_energy_sd(METHODS[m], 0.01, 4.0));
  printf("\n");
}

/* NO_SQUISH over 10^5 steps of a fast free top (h|Omega| ~ 0.1): |q| = 1 and A^T A = I to
 * round-off (each sub-rotation is an exact plane rotation of q), the lab l untouched, and the
 * rotational energy bounded (symplectic: no drift, printed). */
static void nosquish_long(void **state)
{
  (void)state;
  const double L[3] = {3.0, -2.0, 1.5};
  top t = make_body(RL_KIND_ASYMMETRIC, J0, L, 0.05, RL_ROT_NOSQUISH, RL_THERMO_NONE, 0.0);
  double worst_q = 0.0, worst_A = 0.0, ke0 = 0.0, kemin = INFINITY, kemax = -INFINITY;
  for (long s = 0; s < 100000; s++) {
    rl_step_info info;
    assert_int_equal(rl_integrator_step(t.in, &info), RL_OK);
    if (s == 0) ke0 = info.ke_rot;
    kemin = fmin(kemin, info.ke_rot);
    kemax = fmax(kemax, info.ke_rot);
    double q[4], A[9];
    assert_int_equal(rl_integrator_quaternion(t.in, 0, q), RL_OK);
    rl_system_get_orientation(t.sys, 0, A);
    worst_q = fmax(worst_q, fabs(sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) - 1.0));
    worst_A = fmax(worst_A, rl_orthonormality_error(A));
  }
  double l[3];
  rl_system_get_angmom(t.sys, 0, l);
  printf("info  no-squish 10^5 steps: KE_rot in [%.6f, %.6f], KE_0 %.6f\n", kemin, kemax, ke0);
  CHECK_LE("no-squish 10^5 steps: max ||q| - 1|", worst_q, 1e-14);
  CHECK_LE("no-squish 10^5 steps: max |A^T A - I|", worst_A, 1e-14);
  CHECK_LE("no-squish 10^5 steps: max |l - l0| (lab l exact)", max_abs_diff(l, L, 3), 0.0);
  CHECK_LE("no-squish 10^5 steps: (KE max - min) / KE_0 (bounded)", (kemax - kemin) / ke0, 1e-2);
  free_top(&t);
}

/* Reversibility: NO_SQUISH is a symmetric composition of exact flows between reversible kicks,
 * so 1000 steps out and back return to round-off (2000 steps at h|Omega| ~ 0.16 accumulate
 * ~1e-12), on the free top and on the chaotic cluster (400 steps, as test_cluster).  The hybrid
 * is not reversible: the reversed step solves eq. 28 from A' = R(dphi) D A rather than D A
 * (dphi of hybrid_vs_matrix), so Omega' = -Omega + O(dphi |Omega|) and each step leaves an
 * O(h |Omega| dphi) = O((h|Omega|)^4) residue, which then propagates: at h|Omega| ~ 0.16 over
 * 2 x 1000 steps that is of order 0.1 (measured 0.23). */
static void reversibility(void **state)
{
  (void)state;
  const double L[3] = {3.0, -2.0, 1.5};
  double eA, el;
  free_top_reverse_error(RL_ROT_NOSQUISH, L, 0.0, &eA, &el);
  CHECK_LE("no-squish free top reversal: max |A_back - A_0|", eA, 1e-11);
  CHECK_LE("no-squish free top reversal: |l_back + l_0|", el, 1e-13);
  free_top_reverse_error(RL_ROT_HYBRID, L, 0.0, &eA, &el);
  printf("check %-58s %.3e >= 1.0e-02 %s\n", "hybrid free top reversal error (not reversible)", eA,
         eA >= 1e-2 ? "ok" : "FAIL");
  assert_true(eA >= 1e-2);

  double worst_r, worst_A;
  cluster_reversal_error(RL_ROT_NOSQUISH, &worst_r, &worst_A);
  CHECK_LE("no-squish cluster reversal: max |r_back - r_0|", worst_r, 1e-10);
  CHECK_LE("no-squish cluster reversal: max |A_back - A_0|", worst_A, 1e-10);
}

/* Fincham: the fixed-point iteration's contraction factor grows with h|Omega|, so the mean
 * iterations per step must grow with h; the norm defect it leaves (removed by the rescaling) is
 * a local O(h^3) error; at an absurd step it must fail with RL_ENOCONV naming body and step, and
 * leave the orientation as it was (finite). */
static void fincham_iterations(void **state)
{
  (void)state;
  const double hs[4] = {0.01, 0.04, 0.16, 0.64}; /* h|Omega| ~ h */
  double per[4], defect[4];
  for (int k = 0; k < 4; k++) {
    top t = make_body(RL_KIND_ASYMMETRIC, J0, L0, hs[k], RL_ROT_FINCHAM, RL_THERMO_NONE, 0.0);
    long it = 0;
    int maxit = 0;
    defect[k] = 0.0;
    for (int s = 0; s < 200; s++) {
      rl_step_info info;
      assert_int_equal(rl_integrator_step(t.in, &info), RL_OK);
      it += info.quat_iterations;
      maxit = info.quat_max_iterations > maxit ? info.quat_max_iterations : maxit;
      defect[k] = fmax(defect[k], info.quat_norm_defect);
    }
    assert_int_equal(rl_integrator_quat_iterations(t.in), it);
    per[k] = it / 200.0;
    printf("info  fincham h = %.2f: %.2f iterations per step (max %d), max norm defect %.2e\n",
           hs[k], per[k], maxit, defect[k]);
    free_top(&t);
  }
  for (int k = 0; k < 3; k++) {
    char name[96];
    snprintf(name, sizeof name, "fincham: iterations grow, h=%g->%g (%.2f->%.2f)", hs[k], hs[k + 1],
             per[k], per[k + 1]);
    printf("check %-58s %s\n", name, per[k + 1] > per[k] ? "ok" : "FAIL");
    assert_true(per[k + 1] > per[k]);
  }
  CHECK_NEAR("fincham: norm defect order h=0.01->0.04 (log4 ratio)",
             log(defect[1] / defect[0]) / log(4.0), 3.0, 0.2);

  /* h|Omega| = 1.7: the iteration still contracts, too slowly for quat_maxit = 100 */
  top slow = make_body(RL_KIND_ASYMMETRIC, J0, L0, 1.5, RL_ROT_FINCHAM, RL_THERMO_NONE, 0.0);
  assert_int_equal(rl_integrator_step(slow.in, NULL), RL_ENOCONV);
  printf("info  fincham at h = 1.5: \"%s\"\n", rl_last_error());
  assert_non_null(strstr(rl_last_error(), "Fincham: body 0 at step 0"));
  assert_non_null(strstr(rl_last_error(), "did not converge"));
  free_top(&slow);

  /* h|Omega| = 6.7: the iterates run away */
  top t = make_body(RL_KIND_ASYMMETRIC, J0, L0, 6.0, RL_ROT_FINCHAM, RL_THERMO_NONE, 0.0);
  double A0[9], A[9];
  rl_system_get_orientation(t.sys, 0, A0);
  int st = rl_integrator_step(t.in, NULL);
  rl_system_get_orientation(t.sys, 0, A);
  printf("info  fincham at h = 6: status %s, \"%s\"\n", rl_strerror(st), rl_last_error());
  assert_int_equal(st, RL_ENOCONV);
  assert_non_null(strstr(rl_last_error(), "Fincham: body 0 at step 0"));
  assert_non_null(strstr(rl_last_error(), "diverged"));
  CHECK_LE("fincham failure at h = 6 leaves A as it was", max_abs_diff(A, A0, 9), 0.0);
  free_top(&t);
}

/* The hybrid, derived: both it and the matrix scheme solve the same eq. 28 for Omega(t+h/2) and
 * rotate about its axis; the matrix Cayley D of eq. 24 turns by 2 atan(y/2), the quaternion
 * Cayley G of eq. 23 by 4 atan(y/4), y = h|Omega| (eq. 25).  So one step from the same state
 * differs by the rotation about Omega by dphi = 4 atan(y/4) - 2 atan(y/2) = y^3/16 + O(y^5):
 * a local O(h^3) difference, of the order of the schemes' own truncation error, hence a global
 * O(h^2) deviation (second order kept, but a different and non-reversible trajectory).  Checked
 * to round-off for one step, for every matrix kind (so the fast paths are bypassed), then the
 * h^2 scaling of the deviation after T = 4. */
static void hybrid_vs_matrix(void **state)
{
  (void)state;
  const double Js[3][3] = {{1.0, 1.6, 2.3}, {1.0, 1.0, 1.7}, {1.3, 1.3, 1.3}};
  const rl_kind kinds[3] = {RL_KIND_ASYMMETRIC, RL_KIND_SYMMETRIC, RL_KIND_SPHERICAL};
  const double L[3] = {1.2, -0.9, 0.7}, h = 0.4;
  for (int k = 0; k < 3; k++) {
    top a = make_body(kinds[k], Js[k], L, h, RL_ROT_HYBRID, RL_THERMO_NONE, 0.0);
    top b = make_body(kinds[k], Js[k], L, h, RL_ROT_CUBIC, RL_THERMO_NONE, 0.0);
    rl_step_info ia, ib;
    assert_int_equal(rl_integrator_step(a.in, &ia), RL_OK);
    assert_int_equal(rl_integrator_step(b.in, &ib), RL_OK);
    double Aa[9], Ab[9], R[9], axis[3], th[3], Om[3];
    rl_system_get_orientation(a.sys, 0, Aa);
    rl_system_get_orientation(b.sys, 0, Ab);
    mul_abt(Aa, Ab, R);
    double dphi = rotation_angle(R, axis);
    for (int c = 0; c < 3; c++) th[c] = L[c] / Js[k][c]; /* A(0) = I */
    assert_int_equal(rl_omega_exact(Js[k], th, h, Om, NULL), RL_OK);
    double y = h * norm3d(Om), expect = 4.0 * atan(y / 4.0) - 2.0 * atan(y / 2.0);
    double cosax = fabs(axis[0] * Om[0] + axis[1] * Om[1] + axis[2] * Om[2]) / norm3d(Om);
    char name[96];
    snprintf(name, sizeof name, "hybrid one step (%s): |dphi/(4atan(y/4)-2atan(y/2)) - 1|",
             rl_kind_name(kinds[k]));
    CHECK_LE(name, fabs(dphi / expect - 1.0), 1e-9);
    snprintf(name, sizeof name, "hybrid one step (%s): 1 - |axis . Omega^|", rl_kind_name(kinds[k]));
    CHECK_LE(name, 1.0 - cosax, 1e-12);
    free_top(&a);
    free_top(&b);
  }
  /* global deviation from the matrix scheme after T = 4: ~h^2, far above round-off */
  const double T = 4.0, hs[3] = {0.04, 0.02, 0.01};
  double dev[3];
  for (int k = 0; k < 3; k++) {
    top a = make_top(hs[k], RL_ROT_HYBRID, NULL), b = make_top(hs[k], RL_ROT_CUBIC, NULL);
    for (long s = 0; s < lround(T / hs[k]); s++) {
      assert_int_equal(rl_integrator_step(a.in, NULL), RL_OK);
      assert_int_equal(rl_integrator_step(b.in, NULL), RL_OK);
    }
    double Aa[9], Ab[9];
    rl_system_get_orientation(a.sys, 0, Aa);
    rl_system_get_orientation(b.sys, 0, Ab);
    dev[k] = frob_diff(Aa, Ab);
    free_top(&a);
    free_top(&b);
  }
  printf("check %-58s %.3e >= 1.0e-06 %s\n", "hybrid - matrix at T = 4, h = 0.01 (not round-off)",
         dev[2], dev[2] >= 1e-6 ? "ok" : "FAIL");
  assert_true(dev[2] >= 1e-6);
  for (int k = 0; k < 2; k++) {
    char name[96];
    snprintf(name, sizeof name, "hybrid - matrix deviation order h=%g->%g", hs[k], hs[k + 1]);
    CHECK_NEAR(name, log2(dev[k] / dev[k + 1]), 2.0, 0.05);
  }
}

/* Free-top rotational energy: exact for rl (implicit midpoint rule); for the hybrid each step
 * changes it by O(h |Omega| dphi) = O(h^4) (hybrid_vs_matrix), so over a fixed time T = 100 the
 * worst deviation scales as h^3 (measured ratios ~8). */
static void hybrid_energy(void **state)
{
  (void)state;
  const double hs[3] = {0.04, 0.02, 0.01};
  double dev[3];
  for (int k = 0; k < 3; k++) {
    top t = make_top(hs[k], RL_ROT_HYBRID, NULL);
    double ke0 = 0.0;
    dev[k] = 0.0;
    for (long s = 0; s < lround(100.0 / hs[k]); s++) {
      rl_step_info info;
      assert_int_equal(rl_integrator_step(t.in, &info), RL_OK);
      if (s == 0) ke0 = info.ke_rot;
      dev[k] = fmax(dev[k], fabs(info.ke_rot - ke0) / ke0);
    }
    free_top(&t);
  }
  for (int k = 0; k < 2; k++) {
    char name[96];
    snprintf(name, sizeof name, "hybrid free-top KE deviation order h=%g->%g (%.2e->%.2e)", hs[k],
             hs[k + 1], dev[k], dev[k + 1]);
    CHECK_NEAR(name, log2(dev[k] / dev[k + 1]), 3.0, 0.2);
  }
}

/* The isokinetic scheme (eqs. 17-18) holds the on-step T at T0 under every baseline. */
static void isokinetic(void **state)
{
  (void)state;
  for (int m = 0; m < NMETH; m++) {
    char name[96];
    snprintf(name, sizeof name, "%s isokinetic: on-step T = T0 (relative)", rl_rot_method_name(METHODS[m]));
    CHECK_LE(name, cluster_isokinetic_error(METHODS[m], 200), 1e-13);
  }
}

/* Fincham composes with the thermostat through the thermostatted l'(t) = beta l(t) and
 * l'(t+h/2) = (2 beta - 1) l(t) (no torque).  A free body at T = T0 / 0.64 (beta = 0.8): its
 * trapezoidal step turns by h |Omega'(t) + Omega~(t+h)|/2 = 0.7 h |Omega(t)| to O(h^2); the
 * mid-step schemes turn by h |Omega'(t+h/2)| = 0.6 h |Omega(t)|.  Had Fincham used the
 * unthermostatted l(t) (or l'(t+h/2) - h/2 k), the ratio would be 1.0 (or 0.6). */
static void fincham_isokinetic(void **state)
{
  (void)state;
  const double h = 1e-3, expect[NMETH] = {0.6, 0.7, 0.6};
  for (int m = 0; m < NMETH; m++) {
    top t = make_body(RL_KIND_ASYMMETRIC, J0, L0, h, METHODS[m], RL_THERMO_NONE, 0.0);
    rl_step_info info;
    assert_int_equal(rl_integrator_step(t.in, &info), RL_OK); /* for the on-step temperature */
    double T = info.temperature;
    free_top(&t);
    t = make_body(RL_KIND_ASYMMETRIC, J0, L0, h, METHODS[m], RL_THERMO_ISOKINETIC, 0.64 * T);
    double A0[9], A1[9], R[9], axis[3];
    rl_system_get_orientation(t.sys, 0, A0);
    assert_int_equal(rl_integrator_step(t.in, &info), RL_OK);
    rl_system_get_orientation(t.sys, 0, A1);
    mul_abt(A1, A0, R);
    double om = hypot(hypot(L0[0] / J0[0], L0[1] / J0[1]), L0[2] / J0[2]);
    char name[96];
    snprintf(name, sizeof name, "%s isokinetic beta=%.3f: angle / (h|Omega(t)|)",
             rl_rot_method_name(METHODS[m]), info.beta);
    CHECK_NEAR(name, rotation_angle(R, axis) / (h * om), expect[m], 0.005);
    free_top(&t);
  }
}

/* rl_integrator_resume continues bit for bit: 300 steps in one go against 200 + resume on a
 * clone + 100, across the orientation polish at step 256. */
static void resume_bitwise(void **state)
{
  (void)state;
  for (int m = 0; m < NMETH; m++) {
    cluster a = make_cluster(0.02, METHODS[m], RL_THERMO_NONE, 0.0);
    for (int s = 0; s < 200; s++) assert_int_equal(rl_integrator_step(a.in, NULL), RL_OK);
    rl_system *sys2 = rl_system_clone(a.sys);
    assert_non_null(sys2);
    rl_integrator_params p;
    rl_integrator_params_default(&p);
    p.h = 0.02;
    p.method = METHODS[m];
    rl_integrator *in2 = rl_integrator_alloc(sys2, &p, (rl_force_provider){smooth_forces, NULL});
    assert_non_null(in2);
    assert_int_equal(rl_integrator_resume(in2, rl_integrator_steps(a.in), rl_integrator_time(a.in)), RL_OK);
    for (int s = 0; s < 100; s++) {
      assert_int_equal(rl_integrator_step(a.in, NULL), RL_OK);
      assert_int_equal(rl_integrator_step(in2, NULL), RL_OK);
    }
    int same = 1;
    for (int i = 0; i < NB; i++) {
      double A1[9], A2[9], l1[3], l2[3], r1[3], r2[3];
      rl_system_get_orientation(a.sys, i, A1);
      rl_system_get_orientation(sys2, i, A2);
      rl_system_get_angmom(a.sys, i, l1);
      rl_system_get_angmom(sys2, i, l2);
      rl_system_get_position(a.sys, i, r1);
      rl_system_get_position(sys2, i, r2);
      same &= !memcmp(A1, A2, sizeof A1) && !memcmp(l1, l2, sizeof l1) && !memcmp(r1, r2, sizeof r1);
    }
    printf("check %-58s %s\n", rl_rot_method_name(METHODS[m]), same ? "ok" : "FAIL");
    assert_true(same);
    rl_integrator_free(in2);
    rl_system_free(sys2);
    free_cluster(&a);
  }
}

/* Point dipoles and linear molecules store only an axis: the baselines refuse them at alloc,
 * naming the species. */
static void axis_species_refused(void **state)
{
  (void)state;
  rl_system *sys = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc d = {.name = "stock", .kind = RL_KIND_DIPOLE, .mass = 1.0, .inertia = {0.1, 0.1, 0.1}};
  assert_int_equal(rl_system_add_species(sys, &d, 2, NULL), RL_OK);
  rl_system_set_axis(sys, 1, (const double[3]){1.0, 0.0, 0.0});
  for (int m = 0; m < NMETH; m++) {
    rl_integrator_params p;
    rl_integrator_params_default(&p);
    p.h = 0.01;
    p.method = METHODS[m];
    rl_integrator *in = rl_integrator_alloc(sys, &p, (rl_force_provider){zero_forces, NULL});
    printf("info  %s with a dipole species: \"%s\"\n", rl_rot_method_name(METHODS[m]), rl_last_error());
    assert_null(in);
    assert_non_null(strstr(rl_last_error(), "'stock'"));
  }
  rl_system_free(sys);
}

int main(void)
{
  gsl_set_error_handler_off();
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(free_top_convergence), cmocka_unit_test(cluster_energy_order),
      cmocka_unit_test(nosquish_long),        cmocka_unit_test(reversibility),
      cmocka_unit_test(fincham_iterations),   cmocka_unit_test(hybrid_vs_matrix),
      cmocka_unit_test(hybrid_energy),
      cmocka_unit_test(isokinetic),           cmocka_unit_test(fincham_isokinetic),
      cmocka_unit_test(resume_bitwise),       cmocka_unit_test(axis_species_refused)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
