/* The rotation kernels: guarded quasi-analytic solve of eq. 28 against the exact solve, at
 * thermal water conditions and at the numerical extremes; the Cayley evolution; quaternions. */
#include "../testutil.h"

#include <float.h>

#include <rotleap/units.h>

/* TIP4P principal moments (amu nm^2): O-H 0.09572 nm, H-O-H 104.52 deg, m_H = 1.008,
 * m_O = 15.9994, about the centre of mass; X in-plane perpendicular to the C2 axis... computed
 * here from the geometry rather than typed in. */
static void tip4p_moments(double J[3])
{
  double mO = 15.9994, mH = 1.008, b = 0.09572, half = 0.5 * 104.52 * M_PI / 180.0;
  double hx = b * sin(half), hz = b * cos(half);          /* H at (+-hx, 0, hz), O at 0 */
  double zc = 2.0 * mH * hz / (mO + 2.0 * mH);            /* centre of mass on z */
  double Ixx = mO * zc * zc + 2.0 * mH * (hz - zc) * (hz - zc); /* y^2 + z^2 */
  double Iyy = Ixx + 2.0 * mH * hx * hx;                  /* x^2 + z^2 */
  double Izz = 2.0 * mH * hx * hx;                        /* x^2 + y^2 */
  J[0] = Izz; J[1] = Ixx; J[2] = Iyy;                     /* ascending */
}

/* Guarded vs exact for water at h <= 5 fs with thermal angular momenta at 298 K, including the
 * 3-sigma tails of each component.  Tolerance 2e-15 (about 10 ulp): both solve the same equation,
 * so they may differ only by round-off amplified by the conditioning of eq. 28 (close to 1 for
 * h Omega << 1).  The guard on the residual alone left up to 1e-13 here. */
static void water_thermal(void **state)
{
  (void)state;
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, 11);
  double J[3], kT = RL_KB_KJMOL * 298.0;
  tip4p_moments(J);
  double worst = 0.0, worst_res = 0.0;
  long fallbacks = 0, n = 0;
  for (int hfs = 1; hfs <= 5; hfs++) {
    double h = hfs * RL_FS;
    for (int trial = 0; trial < 20000; trial++) {
      double L[3], th[3], Og[3], Oe[3];
      for (int a = 0; a < 3; a++) {
        double sd = sqrt(kT * J[a]);
        /* every 4th trial: a component at +-3 sigma exactly, others Gaussian */
        double g = (trial % 4 == 0 && a == trial / 4 % 3) ? (trial % 8 ? 3.0 : -3.0)
                                                          : gsl_ran_gaussian(r, 1.0);
        L[a] = sd * g;
        th[a] = L[a] / J[a];
      }
      rl_omega_info gi, ei;
      assert_int_equal(rl_omega_guarded(J, th, h, 0.0, Og, &gi), RL_OK);
      assert_int_equal(rl_omega_exact(J, th, h, Oe, &ei), RL_OK);
      double d[3] = {Og[0] - Oe[0], Og[1] - Oe[1], Og[2] - Oe[2]};
      worst = fmax(worst, norm3d(d) / norm3d(Oe));
      worst_res = fmax(worst_res, gi.residual);
      fallbacks += gi.path >= RL_OMEGA_PATH_NEWTON;
      n++;
    }
  }
  printf("info  water thermal: %ld solves, %ld fallbacks\n", n, fallbacks);
  CHECK_LE("water h<=5fs 3-sigma: |Omega_guarded - Omega_exact|/|Omega|", worst, 2e-15);
  CHECK_LE("water h<=5fs 3-sigma: eq. 28 residual of guarded solve", worst_res, 1e-12);
  gsl_rng_free(r);
}

/* The extremes: J_X/J_Z down to 1e-4, h|Omega| up to 2, near-symmetric and near-spherical
 * bodies.  The guarded solve must satisfy eq. 28 to 1e-12 and return finite numbers.  Cardano's
 * negative discriminant (three real roots) does not occur for h|Omega| <= 2 with these bodies (a
 * scan finds it from h|Omega| ~ 2.4, theta mostly along the middle axis), so a second band with
 * h|Omega| in [2, 6] makes sure that case is met and handled too. */
static void extremes(void **state)
{
  (void)state;
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, 12);
  const double bodies[][3] = {
      {1e-4, 1.0, 1.0 + 0.5e-4}, {1e-3, 0.5, 0.5005}, {1e-2, 0.7, 0.705}, {0.3, 0.6, 0.9},
      {1.0, 1.0 + 1e-9, 1.0 + 2e-9}, {1.0, 1.0, 1.0 + 1e-7}, {0.5, 0.5 + 1e-8, 1.0},
      {1.0, 2.0, 2.9}, {0.2, 1.0, 1.1}, {1.0, 1.0, 2.0}};
  const int nb = sizeof bodies / sizeof bodies[0];
  double worst = 0.0;
  long n = 0, nonfinite = 0, three_real = 0, fallbacks = 0, off_branch = 0;
  for (int k = 0; k < nb; k++) {
    const double *J = bodies[k];
    for (int trial = 0; trial < 20000; trial++) {
      double th[3], Om[3];
      for (int a = 0; a < 3; a++) th[a] = gsl_ran_gaussian(r, 1.0);
      /* target h|theta| spread over (0, 2] */
      double hw = 2.0 * gsl_rng_uniform_pos(r);
      if (trial % 10 == 0) hw = 2.0;
      if (trial % 4 == 1) hw = 2.0 + 4.0 * gsl_rng_uniform(r); /* negative-discriminant band */
      double h = hw / norm3d(th);
      rl_omega_info gi;
      int st = rl_omega_guarded(J, th, h, 0.0, Om, &gi);
      if (!isfinite(Om[0]) || !isfinite(Om[1]) || !isfinite(Om[2])) nonfinite++;
      assert_int_equal(st, RL_OK);
      worst = fmax(worst, gi.residual);
      three_real += gi.three_real;
      fallbacks += gi.path >= RL_OMEGA_PATH_NEWTON;
      off_branch += gi.off_branch;
      n++;
    }
  }
  printf("info  extremes: %ld solves, %ld with three real roots, %ld fallbacks, %ld fast roots off "
         "the branch (replaced)\n", n, three_real, fallbacks, off_branch);
  CHECK_LE("extremes: non-finite results", (double)nonfinite, 0.0);
  CHECK_LE("extremes: max eq. 28 residual (relative), h|Omega| <= 6", worst, 1e-12);
  printf("check %-58s %ld > 0 %s\n", "extremes: negative discriminant met", three_real,
         three_real > 0 ? "ok" : "FAIL");
  assert_true(three_real > 0);
  gsl_rng_free(r);
}

/* The cubic's small root, including three real roots (negative discriminant). */
static void cubic_root(void **state)
{
  (void)state;
  /* (d - 1e-3)(d - 2)(d + 5) = d^3 + (3 - 1e-3) d^2 + ... : three real roots, smallest 1e-3 */
  double r1 = 1e-3, r2 = 2.0, r3 = -5.0;
  double a3 = 1.0, a2 = -(r1 + r2 + r3), a1 = r1 * r2 + r1 * r3 + r2 * r3, a0 = -r1 * r2 * r3;
  int three;
  double d = rl_cubic_small_root(a0, a1, a2, a3, &three);
  /* conditioning: the root is found as a difference of O(max|root|) numbers */
  CHECK_LE("cubic, three real roots: |root - 1e-3| / max|root|", fabs(d - r1) / 5.0, 4e-16);
  assert_int_equal(three, 1);
  /* one real root, small a3 (the small-h regime): the root near -a0/a1.  The root is computed
   * as y - a2/(3 a3), so its absolute error is a few ulp of a2/(3 a3) (= 2/3 Omega_Z in the
   * solve, where that is round-off relative to |Omega|). */
  d = rl_cubic_small_root(1e-9, 1.0, 1e-6, 1e-8, &three);
  double f = 1e-8 * d * d * d + 1e-6 * d * d + d + 1e-9;
  CHECK_LE("cubic, one real root: |p(root)| / (a2/(3 a3))", fabs(f) / (1e-6 / 3e-8), 4e-16);
  assert_int_equal(three, 0);
  assert_true(isnan(rl_cubic_small_root(1.0, 1.0, 1.0, 0.0, NULL)));
}

/* The exact root of eq. 28 also zeroes the paper's quintic (eqs. 30-31): checks the transcribed
 * coefficients a0..a3 through the guarded solve's agreement, and the symmetric closed form. */
static void symmetric_and_linear(void **state)
{
  (void)state;
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, 13);
  double worst_sym = 0.0, worst_lin = 0.0;
  for (int trial = 0; trial < 5000; trial++) {
    double th[3], Os[3], Oe[3], h = 0.3 * gsl_rng_uniform_pos(r);
    for (int a = 0; a < 3; a++) th[a] = gsl_ran_gaussian(r, 1.0);
    const double Js[3] = {1.0, 1.0, 1.7}; /* oblate symmetric top */
    rl_omega_symmetric(Js, th, h, Os);
    assert_int_equal(rl_omega_exact(Js, th, h, Oe, NULL), RL_OK);
    double d[3] = {Os[0] - Oe[0], Os[1] - Oe[1], Os[2] - Oe[2]};
    worst_sym = fmax(worst_sym, norm3d(d) / norm3d(Oe));
    const double Jl[3] = {0.6, 1.0, 1.0}; /* prolate: the two largest equal, eq. 28 linear */
    rl_omega_info gi;
    assert_int_equal(rl_omega_guarded(Jl, th, h, 0.0, Os, &gi), RL_OK);
    assert_int_equal(gi.path, RL_OMEGA_PATH_LINEAR);
    assert_int_equal(rl_omega_exact(Jl, th, h, Oe, NULL), RL_OK);
    double e[3] = {Os[0] - Oe[0], Os[1] - Oe[1], Os[2] - Oe[2]};
    worst_lin = fmax(worst_lin, norm3d(e) / norm3d(Oe));
  }
  CHECK_LE("symmetric closed form vs exact (relative)", worst_sym, 1e-13);
  CHECK_LE("two equal largest moments: linear solve vs exact", worst_lin, 1e-13);
  gsl_rng_free(r);
}

/* Rotation about w by angle phi (Rodrigues), in the convention of W (eq. 3). */
static void rodrigues(const double w[3], double phi, double R[9])
{
  double wn = norm3d(w), k[3] = {w[0] / wn, w[1] / wn, w[2] / wn};
  double K[9] = {0, k[2], -k[1], -k[2], 0, k[0], k[1], -k[0], 0};
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double K2 = K[3 * i] * K[j] + K[3 * i + 1] * K[3 + j] + K[3 * i + 2] * K[6 + j];
      R[3 * i + j] = (i == j) + sin(phi) * K[3 * i + j] + (1.0 - cos(phi)) * K2;
    }
}

/* D of eq. 24 is orthogonal, equals the Rodrigues rotation by 2 atan(h w/2), and the quaternion
 * form (eq. 23) generates the same rotation through eq. 4. */
static void cayley_and_quaternions(void **state)
{
  (void)state;
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, 14);
  double worst_orth = 0.0, worst_rod = 0.0, worst_q = 0.0, worst_rt = 0.0, worst_ax = 0.0;
  for (int trial = 0; trial < 2000; trial++) {
    double w[3], D[9], h = 3.0 * gsl_rng_uniform_pos(r);
    for (int a = 0; a < 3; a++) w[a] = gsl_ran_gaussian(r, 1.0);
    rl_cayley(w, h, D);
    worst_orth = fmax(worst_orth, rl_orthonormality_error(D));
    /* Rodrigues: D = I + sin(phi) K + (1 - cos(phi)) K^2, K = W(w)/|w|, phi = 2 atan(h|w|/2) */
    double wn = norm3d(w), R[9];
    rodrigues(w, 2.0 * atan(0.5 * h * wn), R);
    worst_rod = fmax(worst_rod, max_abs_diff(D, R, 9));
    /* quaternion route: A(G q) = R(phi_q) A(q), the rotation about Omega by the quaternion
     * Cayley angle phi_q = 4 atan(h|w|/4) (eq. 25: 2 arcsin[(h w/2)/(1 + h^2 w^2/16)]), which
     * differs from the matrix angle 2 atan(h|w|/2) at O(h^3): the two variants are distinct
     * second-order schemes. */
    double A[9], q[4], Aq[9], DA[9], RA[9], Rq[9];
    rodrigues(w, 4.0 * atan(0.25 * h * wn), Rq);
    random_rotation(r, A);
    assert_int_equal(rl_matrix_to_quat(A, q), RL_OK);
    rl_quat_to_matrix(q, Aq);
    worst_rt = fmax(worst_rt, max_abs_diff(A, Aq, 9));
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++)
        RA[3 * i + j] = Rq[3 * i] * A[j] + Rq[3 * i + 1] * A[3 + j] + Rq[3 * i + 2] * A[6 + j];
    rl_quat_rotate(q, w, h);
    rl_quat_to_matrix(q, Aq);
    worst_q = fmax(worst_q, max_abs_diff(RA, Aq, 9));
    memcpy(DA, A, sizeof DA);
    rl_rotate_matrix(DA, w, h);
    /* axis rotation: row Z of A D-rotated from the right by omega in the lab */
    double rho[3] = {A[6], A[7], A[8]}, lab[3];
    /* lab w for the same rotation: w_lab = A^T w */
    for (int c = 0; c < 3; c++) lab[c] = A[c] * w[0] + A[3 + c] * w[1] + A[6 + c] * w[2];
    rl_rotate_axis(rho, lab, h);
    worst_ax = fmax(worst_ax, max_abs_diff(rho, DA + 6, 3));
  }
  CHECK_LE("Cayley D orthonormality (h|w| up to ~10)", worst_orth, 4e-15);
  CHECK_LE("Cayley D = Rodrigues exp map with phi = 2 atan(h w/2)", worst_rod, 1e-14);
  CHECK_LE("A -> q -> A round trip", worst_rt, 1e-14);
  CHECK_LE("quaternion G (eq. 23) = rotation by 4 atan(h w/4) via eq. 4", worst_q, 1e-14);
  CHECK_LE("axis rotation = third row of D A", worst_ax, 1e-14);
  gsl_rng_free(r);
}

/* dA/dt = W(Omega) A with dq/dt = Q(Omega) q (eqs. 2, 4, 5): the conventions agree. */
static void quaternion_convention(void **state)
{
  (void)state;
  double q[4] = {0.3, -0.5, 0.2, 0.7}, n = 0.0;
  for (int k = 0; k < 4; k++) n += q[k] * q[k];
  for (int k = 0; k < 4; k++) q[k] /= sqrt(n);
  double Om[3] = {0.8, -1.3, 0.4}, eps = 1e-6, A[9], qp[4], qm[4], Ap[9], Am[9];
  rl_quat_to_matrix(q, A);
  memcpy(qp, q, sizeof qp); rl_quat_rotate(qp, Om, eps);
  memcpy(qm, q, sizeof qm); rl_quat_rotate(qm, Om, -eps);
  rl_quat_to_matrix(qp, Ap); rl_quat_to_matrix(qm, Am);
  double W[9] = {0, Om[2], -Om[1], -Om[2], 0, Om[0], Om[1], -Om[0], 0}, err = 0.0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double dA = (Ap[3 * i + j] - Am[3 * i + j]) / (2 * eps);
      double WA = W[3 * i] * A[j] + W[3 * i + 1] * A[3 + j] + W[3 * i + 2] * A[6 + j];
      err = fmax(err, fabs(dA - WA));
    }
  CHECK_LE("dA/dt from quaternions = W(Omega) A", err, 1e-8);
}

/* Huge h|w|: the Cayley maps divide through by x^2 once x = h|w|/2 (h|w|/4 for G) exceeds 1, so
 * they stay finite and orthogonal up to the largest doubles and keep turning by 2 atan(h|w|/2),
 * which tends to pi (the plain form gave NaN from h|w| ~ 1.3e154 on).  The guarded solve of eq.
 * 28, which overflows far earlier, reports RL_ENOCONV with a finite Omega. */
static void cayley_overflow(void **state)
{
  (void)state;
  /* (h, |w|): h|w| = 2.5, 1e10, 1e150, 1e155, 1e200, 1e300, 1e308 and 1e318 (beyond the doubles:
   * the rotation by pi) */
  const double hw[][2] = {{1, 2.5},     {1, 1e10},      {1, 1e150},     {1, 1e155},
                          {1e100, 1e100}, {1e10, 1e290}, {1e10, 1e298}, {1e20, 1e298}};
  const double u[3] = {0.48, -0.6, 0.64}; /* unit */
  double worst_rod = 0.0, worst_orth = 0.0, worst_ax = 0.0, worst_q = 0.0;
  for (size_t k = 0; k < sizeof hw / sizeof *hw; k++) {
    const double h = hw[k][0], x = h * hw[k][1]; /* x = Inf for the last */
    double w[3] = {u[0] * hw[k][1], u[1] * hw[k][1], u[2] * hw[k][1]}, D[9], R[9], A[9];
    rl_cayley(w, h, D);
    rodrigues(u, 2.0 * atan(0.5 * x), R);
    worst_rod = fmax(worst_rod, max_abs_diff(D, R, 9));
    worst_orth = fmax(worst_orth, rl_orthonormality_error(D));
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 40 + k);
    random_rotation(r, A);
    gsl_rng_free(r);
    double rho[3] = {A[6], A[7], A[8]}, lab[3], DA[9], q[4], Aq[9], Rq[9], RA[9];
    memcpy(DA, A, sizeof DA);
    rl_rotate_matrix(DA, w, h);
    for (int c = 0; c < 3; c++) lab[c] = A[c] * w[0] + A[3 + c] * w[1] + A[6 + c] * w[2];
    rl_rotate_axis(rho, lab, h);
    worst_ax = fmax(worst_ax, max_abs_diff(rho, DA + 6, 3));
    assert_int_equal(rl_matrix_to_quat(A, q), RL_OK);
    rl_quat_rotate(q, w, h);
    rl_quat_to_matrix(q, Aq);
    rodrigues(u, 4.0 * atan(0.25 * x), Rq);
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++)
        RA[3 * i + j] = Rq[3 * i] * A[j] + Rq[3 * i + 1] * A[3 + j] + Rq[3 * i + 2] * A[6 + j];
    worst_q = fmax(worst_q, max_abs_diff(RA, Aq, 9));
  }
  CHECK_LE("Cayley D at h|w| = 2.5 .. 1e308: |D - Rodrigues(2 atan(h w/2))|", worst_rod, 1e-14);
  CHECK_LE("Cayley D at h|w| = 2.5 .. 1e308: orthonormality", worst_orth, 4e-15);
  CHECK_LE("axis rotation at h|w| = 2.5 .. 1e308 = third row of D A", worst_ax, 1e-14);
  CHECK_LE("quaternion G at h|w| = 2.5 .. 1e308 = rotation by 4 atan(h w/4)", worst_q, 1e-14);
  const double J[3] = {0.6, 1.0, 1.4};
  int finite = 1, enoconv = 0;
  for (double m = 1e50; m < 1e300; m *= 1e10) {
    const double th[3] = {0.3 * m, -0.8 * m, 0.52 * m};
    double Om[3];
    int st = rl_omega_guarded(J, th, 1.0, 0.0, Om, NULL);
    finite &= isfinite(Om[0]) && isfinite(Om[1]) && isfinite(Om[2]);
    enoconv += st == RL_ENOCONV;
  }
  printf("info  guarded solve at h|theta| = 1e50 .. 1e290: %d RL_ENOCONV\n", enoconv);
  CHECK_LE("guarded solve at h|theta| up to 1e290: a non-finite Omega", !finite, 0);
  assert_true(enoconv > 0);
}

/* The solution of eq. 28 is the one that continues from Omega = theta at h = 0 (the auditor's
 * test, shortened).  Reference: that branch followed in long double by 3-D Newton over 400 equal
 * steps of h from 0.  At h|theta| >= 3, Cardano's three real roots or the Newton polish used to
 * land on another solution (1-4 % of the solves at h|theta| = 3.5-6 for these bodies); the guarded
 * and the exact solves must now both return the branch, and the test makes sure such cases were
 * met (off_branch). */
static int ref_newton(const double J[3], const double th[3], double h, long double x[3])
{
  const long double r0 = (J[1] - J[2]) / (2.0L * J[0]), r1 = (J[2] - J[0]) / (2.0L * J[1]),
                    r2 = (J[0] - J[1]) / (2.0L * J[2]);
  for (int it = 0; it < 60; it++) {
    long double g[3] = {x[0] - th[0] - h * r0 * x[1] * x[2], x[1] - th[1] - h * r1 * x[2] * x[0],
                        x[2] - th[2] - h * r2 * x[0] * x[1]};
    long double M[9] = {1, -h * r0 * x[2], -h * r0 * x[1], -h * r1 * x[2], 1, -h * r1 * x[0],
                        -h * r2 * x[1], -h * r2 * x[0], 1};
    long double det = M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
                      M[2] * (M[3] * M[7] - M[4] * M[6]);
    if (!(det > 1e-12L)) return 0; /* det M > 0 on the branch; near 0: a fold */
    long double inv[9] = {M[4] * M[8] - M[5] * M[7], M[2] * M[7] - M[1] * M[8], M[1] * M[5] - M[2] * M[4],
                          M[5] * M[6] - M[3] * M[8], M[0] * M[8] - M[2] * M[6], M[2] * M[3] - M[0] * M[5],
                          M[3] * M[7] - M[4] * M[6], M[1] * M[6] - M[0] * M[7], M[0] * M[4] - M[1] * M[3]};
    long double d2 = 0;
    for (int i = 0; i < 3; i++) {
      long double d = (inv[3 * i] * g[0] + inv[3 * i + 1] * g[1] + inv[3 * i + 2] * g[2]) / det;
      x[i] -= d;
      d2 += d * d;
    }
    if (d2 <= 1e-36L * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2])) return 1;
  }
  return 1;
}

static void branch_from_zero(void **state)
{
  (void)state;
  const double bodies[][3] = {{0.3, 0.6, 0.9}, {1.0, 2.0, 2.9}, {0.2, 1.0, 1.1},
                              {1e-2, 0.7, 0.705}, {0.5, 0.8, 1.2}, {0.61, 1.0, 1.6}};
  const double hws[] = {2.5, 3.0, 3.5, 4.0, 6.0};
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, 7);
  long n = 0, folds = 0, wrong_g = 0, wrong_e = 0, errors = 0, off = 0;
  double worst = 0.0;
  for (size_t b = 0; b < sizeof bodies / sizeof *bodies; b++)
    for (size_t k = 0; k < sizeof hws / sizeof *hws; k++)
      for (int trial = 0; trial < 120; trial++) {
        double th[3], h = hws[k];
        gsl_ran_dir_3d(r, th, th + 1, th + 2);
        long double x[3] = {th[0], th[1], th[2]};
        int ok = 1;
        for (int s = 1; s <= 400 && ok; s++) ok = ref_newton(bodies[b], th, h * s / 400.0, x);
        if (!ok) { folds++; continue; }
        const double xr[3] = {(double)x[0], (double)x[1], (double)x[2]};
        double Og[3], Oe[3];
        rl_omega_info gi, ei;
        errors += rl_omega_guarded(bodies[b], th, h, 0.0, Og, &gi) != RL_OK;
        errors += rl_omega_exact(bodies[b], th, h, Oe, &ei) != RL_OK;
        const double dg = max_abs_diff(Og, xr, 3) / norm3d(xr), de = max_abs_diff(Oe, xr, 3) / norm3d(xr);
        wrong_g += dg > 1e-8;
        wrong_e += de > 1e-8;
        if (dg <= 1e-8) worst = fmax(worst, dg);
        off += gi.off_branch;
        n++;
      }
  gsl_rng_free(r);
  printf("info  %ld solves at h|theta| = 2.5-6 (%ld reference folds skipped): %ld fast roots off the "
         "branch, replaced\n", n, folds, off);
  CHECK_LE("branch from h = 0: guarded solves on another root", wrong_g, 0);
  CHECK_LE("branch from h = 0: exact solves on another root", wrong_e, 0);
  CHECK_LE("branch from h = 0: solves returning an error", errors, 0);
  CHECK_LE("branch from h = 0: max relative distance to the reference", worst, 1e-12);
  CHECK_LE("branch from h = 0: reference folds (the test needs the branch)", folds, 0);
  printf("check %-58s %ld > 0 %s\n", "branch from h = 0: off-branch fast roots met", off, off > 0 ? "ok" : "FAIL");
  assert_true(off > 0);
}

/* The guard bounds the root's error, not the residual of eq. 28.  Against eq. 28 solved in long
 * double (3-D Newton from rl_omega_exact's root), the guarded root must be exact to round-off,
 * i.e. within a few ulp times the condition number ||M^-1|| of eq. 28 at the root
 * (M = I - h dP/dOmega), for near-linear bodies (J_X/J_Z = 1e-3, 1e-4), the other extremes of
 * `extremes`, and water, at h|theta| = 0.5, 1, 2 and 4, with theta isotropic, thermal (component
 * a ~ 1/sqrt(J_a)) and along each axis.  A guard on the residual (1e-13) left errors of 1e-13
 * (60 ulp times the condition number) there. */
static double cond28(const double J[3], double h, const double x[3])
{
  const double r0 = (J[1] - J[2]) / (2.0 * J[0]), r1 = (J[2] - J[0]) / (2.0 * J[1]),
               r2 = (J[0] - J[1]) / (2.0 * J[2]);
  const double M[9] = {1, -h * r0 * x[2], -h * r0 * x[1], -h * r1 * x[2], 1, -h * r1 * x[0],
                       -h * r2 * x[1], -h * r2 * x[0], 1};
  const double det = M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
                     M[2] * (M[3] * M[7] - M[4] * M[6]);
  const double inv[9] = {M[4] * M[8] - M[5] * M[7], M[2] * M[7] - M[1] * M[8], M[1] * M[5] - M[2] * M[4],
                         M[5] * M[6] - M[3] * M[8], M[0] * M[8] - M[2] * M[6], M[2] * M[3] - M[0] * M[5],
                         M[3] * M[7] - M[4] * M[6], M[1] * M[6] - M[0] * M[7], M[0] * M[4] - M[1] * M[3]};
  double f = 0.0;
  for (int i = 0; i < 9; i++) f += inv[i] * inv[i];
  return fmax(1.0, sqrt(f) / fabs(det)); /* Frobenius, >= the 2-norm */
}

static void root_error_bound(void **state)
{
  (void)state;
  double Jw[3];
  tip4p_moments(Jw);
  const double bodies[][3] = {
      {1e-3, 1.0, 1.0 + 0.5e-3}, {1e-4, 1.0, 1.0 + 0.5e-4}, {1e-2, 0.7, 0.705}, {0.3, 0.6, 0.9},
      {1.0, 1.0 + 1e-9, 1.0 + 2e-9}, {1.0, 1.0, 1.0 + 1e-7}, {0.5, 0.5 + 1e-8, 1.0},
      {1.0, 2.0, 2.9}, {0.2, 1.0, 1.1}, {Jw[0], Jw[1], Jw[2]}};
  const double hws[] = {0.5, 1.0, 2.0, 4.0};
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, 15);
  double worst_g = 0.0, worst_e = 0.0, worst_rel = 0.0, worst_nl = 0.0;
  long n = 0, fallbacks = 0, folds = 0;
  for (size_t b = 0; b < sizeof bodies / sizeof *bodies; b++)
    for (size_t k = 0; k < sizeof hws / sizeof *hws; k++)
      for (int trial = 0; trial < 1500; trial++) {
        const double *J = bodies[b];
        double th[3];
        for (int a = 0; a < 3; a++) th[a] = gsl_ran_gaussian(r, 1.0);
        const int mode = trial % 5; /* 0 isotropic, 1 thermal, 2-4 mostly along axis X, Y, Z */
        for (int a = 0; a < 3; a++) th[a] *= mode == 1 ? 1.0 / sqrt(J[a]) : mode >= 2 && a != mode - 2 ? 0.05 : 1.0;
        const double h = hws[k] / norm3d(th);
        double Og[3], Oe[3];
        rl_omega_info gi;
        assert_int_equal(rl_omega_guarded(J, th, h, 0.0, Og, &gi), RL_OK);
        assert_int_equal(rl_omega_exact(J, th, h, Oe, NULL), RL_OK);
        long double x[3] = {Oe[0], Oe[1], Oe[2]};
        if (!ref_newton(J, th, h, x)) { folds++; continue; }
        const double xr[3] = {(double)x[0], (double)x[1], (double)x[2]}, c = cond28(J, h, xr);
        const double dg[3] = {Og[0] - xr[0], Og[1] - xr[1], Og[2] - xr[2]};
        const double de[3] = {Oe[0] - xr[0], Oe[1] - xr[1], Oe[2] - xr[2]};
        const double eg = norm3d(dg) / norm3d(xr), ee = norm3d(de) / norm3d(xr);
        worst_g = fmax(worst_g, eg / c);
        worst_e = fmax(worst_e, ee / c);
        worst_rel = fmax(worst_rel, eg);
        if (b < 2 && k < 3) worst_nl = fmax(worst_nl, eg);
        fallbacks += gi.path == RL_OMEGA_PATH_NEWTON || gi.path == RL_OMEGA_PATH_BRACKET;
        n++;
      }
  gsl_rng_free(r);
  printf("info  root error: %ld solves, %ld polished by Newton (the cubic's correction above the "
         "guard), %ld reference folds skipped; max |Omega - exact|/|Omega| %.2e (near-linear, "
         "h|theta| <= 2: %.2e)\n", n, fallbacks, folds, worst_rel, worst_nl);
  CHECK_LE("root error: guarded |dOmega|/(|Omega| cond) in ulp", worst_g / DBL_EPSILON, 8.0);
  CHECK_LE("root error: exact |dOmega|/(|Omega| cond) in ulp", worst_e / DBL_EPSILON, 8.0);
  CHECK_LE("root error: reference folds (the test needs the branch)", folds, 0);
}

/* The spherical-top path is the paper's A(t+h) = A(t) exp[phi W(omega)/omega] with the Cayley
 * angle phi = 2 atan(h omega/2) (section III.D; the paper's arcsin form), not the exact free
 * rotation by h omega: a free spherical top turns about its fixed axis at the rate phi/h, which
 * lags omega by (h omega)^2/12 relatively (phi = h omega - (h omega)^3/12 + ...).  Through the
 * integrator, 1000 steps at h omega = 0.1, 0.5 and 1 must equal the rotation by 1000 phi, and the
 * exact rotation by 1000 h omega must be the distance that lag predicts away. */
static int no_forces(void *ctx, const rl_system *sys, rl_forces *out)
{
  (void)ctx; (void)sys; (void)out;
  return RL_OK;
}

static void spherical_top_angle(void **state)
{
  (void)state;
  const double hw[3] = {0.1, 0.5, 1.0}, h = 0.01, J = 1.3, u[3] = {0.48, -0.6, 0.64};
  const int n = 1000;
  double worst = 0.0;
  for (int k = 0; k < 3; k++) {
    const double w = hw[k] / h, l[3] = {J * w * u[0], J * w * u[1], J * w * u[2]};
    rl_system *sys = rl_system_alloc(RL_UNITS_LJ);
    rl_species_desc d = {.name = "ball", .kind = RL_KIND_SPHERICAL, .mass = 1.0, .inertia = {J, J, J}};
    assert_int_equal(rl_system_add_species(sys, &d, 1, NULL), RL_OK);
    rl_system_set_removed_dof(sys, 0);
    assert_int_equal(rl_system_set_angmom(sys, 0, l), RL_OK);
    rl_integrator_params p;
    rl_integrator_params_default(&p);
    p.h = h;
    rl_integrator *in = rl_integrator_alloc(sys, &p, (rl_force_provider){no_forces, NULL});
    assert_int_equal(rl_integrator_init(in), RL_OK);
    for (int s = 0; s < n; s++) assert_int_equal(rl_integrator_step(in, NULL), RL_OK);
    const double phi = 2.0 * atan(0.5 * hw[k]);
    double A[9], Rc[9], Rx[9];
    rl_system_get_orientation(sys, 0, A);
    rodrigues(u, fmod(n * phi, 2.0 * M_PI), Rc);
    rodrigues(u, fmod(n * hw[k], 2.0 * M_PI), Rx);
    worst = fmax(worst, max_abs_diff(A, Rc, 9));
    /* the lag after n steps, n (h omega - phi), seen as the distance to the exact rotation:
     * |R(a) - R(b)| elementwise is at most 2 |sin((a - b)/2)|, reached for some element */
    const double lag = n * (hw[k] - phi), dist = max_abs_diff(A, Rx, 9);
    printf("info  spherical top, h omega = %.1f: phi = %.6f per step, h omega - phi = %.3e "
           "((h omega)^3/12 = %.3e, %.2f %% of h omega); after %d steps %.4f rad behind the exact "
           "rotation, max |A - A_exact| = %.4f\n", hw[k], phi, hw[k] - phi, pow(hw[k], 3) / 12.0,
           100.0 * (hw[k] - phi) / hw[k], n, lag, dist);
    assert_true(dist > 0.5 * fabs(sin(0.5 * lag)) && dist <= 2.0 * fabs(sin(0.5 * lag)) + 1e-12);
    rl_integrator_free(in);
    rl_system_free(sys);
  }
  CHECK_LE("spherical top, 1000 steps: |A - rotation by 1000 x 2 atan(h omega/2)|", worst, 1e-12);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(water_thermal),      cmocka_unit_test(extremes),
      cmocka_unit_test(cubic_root),         cmocka_unit_test(symmetric_and_linear),
      cmocka_unit_test(cayley_and_quaternions), cmocka_unit_test(quaternion_convention),
      cmocka_unit_test(cayley_overflow),    cmocka_unit_test(branch_from_zero),
      cmocka_unit_test(root_error_bound),
      cmocka_unit_test(spherical_top_angle),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
