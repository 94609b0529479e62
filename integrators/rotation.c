/* The rotation kernels of the revised angular-momentum leapfrog: the mid-step angular velocity
 * (eq. 28) by the guarded quasi-analytic cubic, by closed forms for symmetric tops, and by a
 * reference 3-D Newton iteration; the Cayley evolution (eqs. 23-24); quaternion helpers.
 * See include/rotleap/rotation.h for the contracts. */
#include "rotleap/rotation.h"
#include "rotleap/error.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

/* ---------------------------------------------------------------- eq. 28 and its residual */

static void rho_coeffs(const double J[3], double r[3])
{
  r[0] = (J[1] - J[2]) / (2.0 * J[0]);
  r[1] = (J[2] - J[0]) / (2.0 * J[1]);
  r[2] = (J[0] - J[1]) / (2.0 * J[2]);
}

static double norm3(const double a[3]) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/* rl_omega_residual with rho given */
static double residual_rho(const double r[3], const double theta[3], double h, const double Om[3])
{
  double res[3];
  res[0] = Om[0] - theta[0] - h * r[0] * Om[1] * Om[2];
  res[1] = Om[1] - theta[1] - h * r[1] * Om[2] * Om[0];
  res[2] = Om[2] - theta[2] - h * r[2] * Om[0] * Om[1];
  double n = norm3(Om), rn = norm3(res);
  if (n == 0.0) return rn == 0.0 ? 0.0 : INFINITY;
  return rn / n;
}

double rl_omega_residual(const double J[3], const double theta[3], double h, const double Om[3])
{
  double r[3];
  rho_coeffs(J, r);
  return residual_rho(r, theta, h, Om);
}

/* ----------------------------------------------------- the branch continuing from h = 0 */

/* g = Omega - theta - h P(Omega), the residual vector of eq. 28 with P = (rho_X Omega_Y Omega_Z,
 * rho_Y Omega_Z Omega_X, rho_Z Omega_X Omega_Y), and (if M) its Jacobian M = I - h dP/dOmega. */
static void eq28(const double r[3], const double th[3], double h, const double x[3], double g[3],
                 double M[9])
{
  g[0] = x[0] - th[0] - h * r[0] * x[1] * x[2];
  g[1] = x[1] - th[1] - h * r[1] * x[2] * x[0];
  g[2] = x[2] - th[2] - h * r[2] * x[0] * x[1];
  if (!M) return;
  M[0] = 1.0;               M[1] = -h * r[0] * x[2]; M[2] = -h * r[0] * x[1];
  M[3] = -h * r[1] * x[2];  M[4] = 1.0;              M[5] = -h * r[1] * x[0];
  M[6] = -h * r[2] * x[1];  M[7] = -h * r[2] * x[0]; M[8] = 1.0;
}

static double det3(const double M[9])
{
  return M[0] * (M[4] * M[8] - M[5] * M[7]) - M[1] * (M[3] * M[8] - M[5] * M[6]) +
         M[2] * (M[3] * M[7] - M[4] * M[6]);
}

static int solve3(const double M[9], const double b[3], double x[3])
{
  const double det = det3(M);
  if (!(fabs(det) > 0.0) || !isfinite(det)) return 0;
  double inv[9] = {M[4] * M[8] - M[5] * M[7], M[2] * M[7] - M[1] * M[8], M[1] * M[5] - M[2] * M[4],
                   M[5] * M[6] - M[3] * M[8], M[0] * M[8] - M[2] * M[6], M[2] * M[3] - M[0] * M[5],
                   M[3] * M[7] - M[4] * M[6], M[1] * M[6] - M[0] * M[7], M[0] * M[4] - M[1] * M[3]};
  for (int i = 0; i < 3; i++)
    x[i] = (inv[3 * i] * b[0] + inv[3 * i + 1] * b[1] + inv[3 * i + 2] * b[2]) / det;
  return 1;
}

static double dist3(const double a[3], const double b[3])
{
  double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  return norm3(d);
}

static double rho_max(const double r[3]) { return fmax(fmax(fabs(r[0]), fabs(r[1])), fabs(r[2])); }

/* Eq. 28 has up to five solutions; the scheme's is the one that continues from Omega = theta at
 * h = 0.  A certificate: with t = |theta|, m = max |rho| (<= 1/2 for physical moments) and
 * a = h m / sqrt(3), |P(Omega)| <= m |Omega|^2 / sqrt(3) and |dP/dOmega| <= sqrt(2) m |Omega|
 * (Frobenius).  So G(Omega) = theta + h P(Omega) maps the ball |Omega - theta| <= R into itself
 * when a (t + R)^2 <= R, i.e. R in [R-, R+] (which exist iff 4 a t <= 1), and contracts it when
 * sqrt(2) h m (t + R) < 1.  For such R eq. 28 has exactly one solution in the ball (Banach), and
 * since both conditions hold for every smaller h, the branch from theta stays in the ball: a
 * solution found in it is the branch.  Returns the largest such R (Inf if rho = 0), or -1 if
 * there is none, which happens from h m |theta| ~ 0.42 on (h|theta| ~ 0.84 for water). */
static double certified_radius(double m, const double th[3], double h)
{
  const double t = norm3(th), a = h * m / sqrt(3.0);
  if (!(a > 0.0)) return INFINITY; /* eq. 28 is Omega = theta */
  const double disc = 1.0 - 4.0 * a * t;
  if (!(disc >= 0.0)) return -1.0;
  const double q = 1.0 - 2.0 * a * t + sqrt(disc);
  const double rminus = 2.0 * a * t * t / q, rplus = q / (2.0 * a);
  const double R = fmin(rplus, (1.0 - 1e-12) * (1.0 / (sqrt(2.0) * h * m) - t));
  return R >= rminus ? R : -1.0;
}

/* Om in the certified ball.  The usual case first, without a root or a division: for
 * h m |theta| <= 0.4 the radius is at least 0.76 |theta| (both R+ and the contraction bound
 * decrease with h m |theta|, to 1.76 |theta| and 0.77 |theta| at 0.4). */
static int on_branch(double m, const double th[3], double h, const double Om[3])
{
  const double d[3] = {Om[0] - th[0], Om[1] - th[1], Om[2] - th[2]};
  const double t2 = th[0] * th[0] + th[1] * th[1] + th[2] * th[2], d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  if (h * h * m * m * t2 <= 0.16 && d2 <= 0.5 * t2) return 1;
  return sqrt(d2) <= certified_radius(m, th, h);
}

/* The branch itself, by continuation in h: from h0 with h0 m |theta| = 1/4, where the
 * fixed-point iteration of G contracts (by 0.43 at most) to the certified solution, to h in steps
 * of at most 0.05 in h m |theta|, with the tangent dOmega/dh = M^-1 P(Omega) as predictor and
 * Newton as corrector.  A step is accepted only if Newton converges within 8 iterations, lands
 * within a quarter of the step from the prediction, and keeps det M > 0: det M = 1 at h = 0 and
 * vanishes only where the branch folds, so on the branch it stays positive, and a root with
 * det M <= 0 belongs to another one.  Otherwise the step is halved.  Returns 0, or -1 if the step
 * falls below 1e-9 h (the branch folds, i.e. ends, before h) or after 20000 steps (h m |theta|
 * beyond ~1000: no usable step).  *iters counts Newton and fixed-point iterations. */
static int branch_continue(const double r[3], const double th[3], double h, double Om[3], int *iters)
{
  const double m = rho_max(r), t = norm3(th), h0 = fmin(h, 0.25 / (m * t)), dmax = 0.05 / (m * t);
  double x[3] = {th[0], th[1], th[2]}, g[3], M[9];
  for (int it = 0; it < 200; it++) { /* x <- theta + h0 P(x) = x - g */
    eq28(r, th, h0, x, g, NULL);
    for (int c = 0; c < 3; c++) x[c] -= g[c];
    (*iters)++;
    if (norm3(g) <= 1e-16 * (norm3(x) + t)) break;
  }
  double hk = h0, dh = dmax;
  for (int steps = 0; hk < h; steps++) {
    if (steps == 20000 || !isfinite(dmax)) return -1;
    const int last = dh >= h - hk;
    if (last) dh = h - hk;
    const double hn = last ? h : hk + dh;
    double P[3] = {r[0] * x[1] * x[2], r[1] * x[2] * x[0], r[2] * x[0] * x[1]}, tg[3], y[3], p[3];
    eq28(r, th, hk, x, g, M);
    if (!solve3(M, P, tg)) return -1;
    for (int c = 0; c < 3; c++) y[c] = p[c] = x[c] + (hn - hk) * tg[c];
    int ok = 0;
    for (int it = 0; it < 8 && !ok; it++) {
      double d[3];
      eq28(r, th, hn, y, g, M);
      if (!solve3(M, g, d)) break;
      for (int c = 0; c < 3; c++) y[c] -= d[c];
      (*iters)++;
      ok = norm3(d) <= 1e-15 * (norm3(y) + t);
    }
    if (ok) {
      eq28(r, th, hn, y, g, M);
      ok = det3(M) > 0.0 && dist3(y, p) <= 0.25 * (hn - hk) * norm3(tg) + 1e-12 * (norm3(y) + t);
    }
    if (!ok) {
      dh *= 0.5;
      if (dh < 1e-9 * h) return -1;
      continue;
    }
    memcpy(x, y, sizeof x);
    hk = hn;
    dh = fmin(2.0 * dh, dmax);
  }
  memcpy(Om, x, sizeof x);
  return 0;
}

/* Where the certificate does not hold (m = max |rho|), Om (a solution of eq. 28 found by a fast
 * path) is checked against the continued branch and replaced by it if it is another solution
 * (info->off_branch); with `failed` (the fast path found no solution) it is replaced in any case.
 * RL_ENOCONV if the branch cannot be followed to h. */
static int keep_branch(const double J[3], double m, const double th[3], double h, double Om[3],
                       rl_omega_info *info, int failed, const char *who)
{
  if (!failed && on_branch(m, th, h, Om)) return RL_OK;
  double r[3], Oc[3];
  rho_coeffs(J, r);
  info->path = RL_OMEGA_PATH_CONTINUATION;
  if (branch_continue(r, th, h, Oc, &info->iterations))
    return rl_error(RL_ENOCONV, "%s: the solution of eq. 28 that continues from h = 0 could not be "
                    "followed to h|theta| = %.3g (h = %g, theta = %g %g %g): it folds, or the step "
                    "is far too large", who, h * norm3(th), h, th[0], th[1], th[2]);
  if (failed || !(dist3(Oc, Om) <= 1e-9 * norm3(Oc))) {
    info->off_branch = !failed;
    memcpy(Om, Oc, sizeof Oc);
  }
  info->residual = rl_omega_residual(J, th, h, Om);
  return RL_OK;
}

/* ------------------------------------------------------- the reduced scalar equation (29) */

/* The solve works in a cyclic relabelling (X, Y, Z) of the body axes in which Z carries the
 * largest moment, so that nu^2 = -rho_X rho_Y >= 0 and 1 + h^2 nu^2 Omega_Z^2 never vanishes.
 * Cyclic relabelling leaves eq. 28 unchanged in form. */
typedef struct {
  double h, tx, ty, tz; /* h and theta in the solve frame      */
  double rx, ry, rz;    /* rho_X, rho_Y, rho_Z                  */
  double nu2;           /* -rho_X rho_Y                         */
} reduced;

/* Omega_X, Omega_Y as functions of Omega_Z = z (eq. 29). */
static inline void eq29(const reduced *s, double z, double *ox, double *oy)
{
  double d = 1.0 + s->h * s->h * s->nu2 * z * z;
  *ox = (s->tx + s->h * s->rx * s->ty * z) / d;
  *oy = (s->ty + s->h * s->ry * s->tx * z) / d;
}

/* F(z) = z - theta_Z - h rho_Z Omega_X(z) Omega_Y(z): the third of eqs. 28 after eq. 29.  Its
 * roots are exactly the solutions of eq. 28.  Returns F and F'(z), and Omega_X, Omega_Y of eq. 29
 * at z with their derivatives. */
static double reduced_eval(const reduced *s, double z, double *fp, double o[2], double d[2])
{
  const double h = s->h, a = h * h * s->nu2, id = 1.0 / (1.0 + a * z * z);
  o[0] = (s->tx + h * s->rx * s->ty * z) * id;
  o[1] = (s->ty + h * s->ry * s->tx * z) * id;
  d[0] = (h * s->rx * s->ty - 2.0 * a * z * o[0]) * id;
  d[1] = (h * s->ry * s->tx - 2.0 * a * z * o[1]) * id;
  *fp = 1.0 - h * s->rz * (d[0] * o[1] + o[0] * d[1]);
  return z - s->tz - h * s->rz * o[0] * o[1];
}

static double reduced_f(const reduced *s, double z, double *fp)
{
  double o[2], d[2], g;
  return reduced_eval(s, z, fp ? fp : &g, o, d);
}

/* One Newton step on F from z, with Omega_X, Omega_Y moved along eq. 29's tangent: the 3-D
 * Newton step of eq. 28 from (eq. 29 at z, z).  Its size is the error of z to first order
 * (residual over derivative, so whatever the conditioning), and the error after it is of the
 * order of its square.  If the step is at most tol |Omega| the corrected root is stored and 1
 * returned; else (or for a non-finite step) 0, with *ox, *oy those of eq. 29 at the old z. */
static int newton_step(const reduced *s, double *z, double *ox, double *oy, double tol)
{
  double o[2], d[2], fp;
  const double dz = -reduced_eval(s, *z, &fp, o, d) / fp;
  const double X = o[0] + d[0] * dz, Y = o[1] + d[1] * dz, Z = *z + dz;
  *ox = o[0];
  *oy = o[1];
  /* |step|^2 <= tol^2 |Omega|^2; false for NaN */
  if (!(dz * dz * (1.0 + d[0] * d[0] + d[1] * d[1]) <= tol * tol * (X * X + Y * Y + Z * Z))) return 0;
  *ox = X;
  *oy = Y;
  *z = Z;
  return 1;
}

/* Real root of a3 d^3 + a2 d^2 + a1 d + a0 = 0 that tends to 0 as h -> 0 (delta_1 of eq. 34).
 * Cardano's c - b/c is evaluated in its hyperbolic form 2 sqrt(b) sinh(asinh(p/b^1.5)/3), which
 * is the same number without the cancellation between c and b/c (both ~ 1/h) that costs
 * Cardano's literal form most of its digits at small h.  With three real roots (negative
 * discriminant) the one nearest 0 is taken.  Returns NaN if the cubic degenerates (a3 -> 0). */
double rl_cubic_small_root(double a0, double a1, double a2, double a3, int *three_real)
{
  if (three_real) *three_real = 0;
  if (!(a3 != 0.0)) return NAN;
  double sh = a2 / (3.0 * a3);
  double b = (3.0 * a1 * a3 - a2 * a2) / (9.0 * a3 * a3);
  double p = (9.0 * a1 * a2 * a3 - 27.0 * a0 * a3 * a3 - 2.0 * a2 * a2 * a2) / (54.0 * a3 * a3 * a3);
  double y;
  if (b > 0.0) {
    double sb = sqrt(b);
    y = 2.0 * sb * sinh(asinh(p / (b * sb)) / 3.0);
  } else if (b < 0.0) {
    double sb = sqrt(-b), arg = p / (sb * sb * sb);
    if (fabs(arg) <= 1.0) { /* three real roots: take the smallest |delta| */
      if (three_real) *three_real = 1;
      double phi = acos(arg) / 3.0, best = NAN;
      for (int k = 0; k < 3; k++) {
        double yk = 2.0 * sb * cos(phi - 2.0 * M_PI * k / 3.0);
        if (isnan(best) || fabs(yk - sh) < fabs(best - sh)) best = yk;
      }
      y = best;
    } else {
      y = copysign(2.0 * sb * cosh(acosh(fabs(arg)) / 3.0), p);
    }
  } else {
    y = cbrt(2.0 * p);
  }
  return y - sh;
}

/* Newton on F from z, at most `maxit` steps; returns 1 on convergence (step below round-off). */
static int newton_reduced(const reduced *s, double *z, int maxit, int *iters)
{
  double x = *z;
  for (int it = 0; it < maxit; it++) {
    double fp, f = reduced_f(s, x, &fp);
    (*iters)++;
    if (f == 0.0) { *z = x; return 1; }
    if (!(fp != 0.0) || !isfinite(fp)) return 0;
    double dx = -f / fp;
    if (!isfinite(dx)) return 0;
    x += dx;
    if (fabs(dx) <= 4.0 * DBL_EPSILON * (fabs(x) + fabs(s->tz) + DBL_MIN)) { *z = x; return 1; }
  }
  *z = x;
  return 0;
}

/* Safeguarded solve: find the sign change of F nearest to z0 on the side F(z0) points to (F(z)
 * ~ z for |z| -> inf, and F - z is bounded, so the search ends), then Newton-bisection in it. */
static double bracketed_reduced(const reduced *s, double z0, int *iters)
{
  double f0 = reduced_f(s, z0, NULL);
  if (f0 == 0.0) return z0;
  double dir = f0 > 0.0 ? -1.0 : 1.0;
  double scale = fabs(z0) + fabs(s->tx) + fabs(s->ty) + fabs(s->tz);
  double step = 1e-8 * (scale > 0.0 ? scale : 1.0);
  double a = z0, fa = f0, b = z0, fb = f0;
  for (int k = 0; k < 2100 && (fb > 0.0) == (f0 > 0.0); k++) {
    a = b;
    fa = fb;
    b = z0 + dir * step;
    fb = reduced_f(s, b, NULL);
    step *= 2.0;
    (*iters)++;
  }
  /* a, b bracket a root: fa and fb have opposite signs. */
  double x = 0.5 * (a + b);
  for (int it = 0; it < 200; it++) {
    double fp, f = reduced_f(s, x, &fp);
    (*iters)++;
    if (f == 0.0) return x;
    if ((f > 0.0) == (fa > 0.0)) { a = x; fa = f; } else { b = x; fb = f; }
    double xn = x - f / fp;
    int inside = isfinite(xn) && (xn - a) * (xn - b) < 0.0;
    if (!inside) xn = 0.5 * (a + b);
    if (fabs(xn - x) <= 2.0 * DBL_EPSILON * fabs(xn) || a == b) return xn;
    x = xn;
  }
  return x;
}

int rl_omega_guarded(const double J[3], const double theta[3], double h, double guard_tol,
                     double Omega[3], rl_omega_info *info)
{
  rl_omega_info loc = {RL_OMEGA_PATH_CUBIC, 0, 0.0, 0, 0};
  if (guard_tol <= 0.0) guard_tol = RL_OMEGA_GUARD_TOL;

  /* cyclic relabelling: the largest moment becomes Z */
  int kz = 2;
  if (J[0] > J[kz]) kz = 0;
  if (J[1] > J[kz]) kz = 1;
  int kx = (kz + 1) % 3, ky = (kz + 2) % 3;
  double Jp[3] = {J[kx], J[ky], J[kz]}, r[3];
  rho_coeffs(Jp, r);
  reduced s = {h, theta[kx], theta[ky], theta[kz], r[0], r[1], r[2], -r[0] * r[1]};
  double ro[3]; /* rho in the caller's axes (eq. 28 is cyclic: the same numbers) */
  ro[kx] = r[0]; ro[ky] = r[1]; ro[kz] = r[2];
  if (s.nu2 < 0.0) s.nu2 = 0.0; /* -0 or round-off when two largest moments coincide */

  double ox, oy, oz;
  if (s.nu2 == 0.0) {
    /* J_Z equals J_X or J_Y: eq. 28 is linear, solve it exactly. */
    loc.path = RL_OMEGA_PATH_LINEAR;
    if (s.rx == 0.0) { /* Omega_X = theta_X; Omega_Z (1 - h^2 rho_Z rho_Y theta_X^2) = ... */
      ox = s.tx;
      oz = (s.tz + h * s.rz * s.tx * s.ty) / (1.0 - h * h * s.rz * s.ry * s.tx * s.tx);
      oy = s.ty + h * s.ry * s.tx * oz;
    } else { /* rho_Y = 0: Omega_Y = theta_Y */
      oy = s.ty;
      oz = (s.tz + h * s.rz * s.tx * s.ty) / (1.0 - h * h * s.rz * s.rx * s.ty * s.ty);
      ox = s.tx + h * s.rx * s.ty * oz;
    }
  } else {
    /* eqs. 31-36 */
    double tx = s.tx, ty = s.ty, tz = s.tz, rx = s.rx, ry = s.ry, rz = s.rz, nu2 = s.nu2;
    double s0 = tz + h * rz * tx * ty; /* eq. 32 */
    double hn = h * h * nu2;
    double tp = 1.0 + hn * s0 * s0, tm = 1.0 - hn * s0 * s0;
    double g = ry * tx * tx + rx * ty * ty;
    double a0 = (s0 - tz) * tp * tp - h * rz * (tx * ty * tm + h * g * s0);
    double a1 = tp - h * h * (g * rz - nu2 * s0 * ((5.0 * s0 - 4.0 * tz) * tp + 2.0 * h * tx * ty * rz));
    double a2 = hn * (6.0 * s0 - 2.0 * tz + h * rz * tx * ty + hn * s0 * s0 * (10.0 * s0 - 6.0 * tz));
    double a3 = 2.0 * hn * (1.0 + hn * s0 * (5.0 * s0 - 2.0 * tz));
    double delta = rl_cubic_small_root(a0, a1, a2, a3, &loc.three_real);
    oz = s0 + delta;
    if (!isfinite(oz)) oz = s0; /* degenerate cubic: let the guard polish from s0 */
    /* the guard: one Newton step on the exact reduced equation from the cubic's root.  Its size
     * is the cubic's error to first order (residual over derivative, whatever the conditioning),
     * and the corrected root's error is of the order of its square: round-off when the step is
     * below guard_tol.  A larger step (or none) is a fallback. */
    if (!newton_step(&s, &oz, &ox, &oy, guard_tol)) loc.path = RL_OMEGA_PATH_NEWTON;
  }

  double Om[3];
  Om[kx] = ox; Om[ky] = oy; Om[kz] = oz;
  loc.residual = residual_rho(ro, theta, h, Om);
  if (loc.path == RL_OMEGA_PATH_NEWTON) {
    /* fallback: Newton on the exact reduced equation from the cubic's root to round-off (its
     * steps bound the error), keeping the branch continued from the cubic */
    double z = isfinite(oz) ? oz : s.tz;
    int ok = newton_reduced(&s, &z, 30, &loc.iterations);
    if (ok) {
      eq29(&s, z, &ox, &oy);
      Om[kx] = ox; Om[ky] = oy; Om[kz] = z;
      loc.residual = residual_rho(ro, theta, h, Om);
    }
    if (!ok || !(loc.residual <= 1e-12)) {
      loc.path = RL_OMEGA_PATH_BRACKET;
      z = bracketed_reduced(&s, isfinite(oz) ? oz : s.tz, &loc.iterations);
      eq29(&s, z, &ox, &oy);
      Om[kx] = ox; Om[ky] = oy; Om[kz] = z;
      loc.residual = residual_rho(ro, theta, h, Om);
    }
  }
  /* beyond the certified range, the root must be the branch from h = 0 (Cardano's three real
   * roots, or Newton, may have picked another) */
  int st = keep_branch(J, rho_max(r), theta, h, Om, &loc, !(loc.residual <= 1e-12), "rl_omega_guarded");
  /* beyond h|theta| ~ 1e100 the reduced equation overflows: keep the promise of a finite
   * Omega (theta itself) and let the residual below report the failure */
  if (!isfinite(Om[0] + Om[1] + Om[2])) {
    Om[0] = theta[0]; Om[1] = theta[1]; Om[2] = theta[2];
    loc.residual = residual_rho(ro, theta, h, Om);
  }
  Omega[0] = Om[0]; Omega[1] = Om[1]; Omega[2] = Om[2];
  if (info) *info = loc;
  if (st) return st;
  if (!(loc.residual <= 1e-12))
    return rl_error(RL_ENOCONV, "rl_omega_guarded: eq. 28 residual %.3g after fallback "
                    "(h = %g, theta = %g %g %g)", loc.residual, h, theta[0], theta[1], theta[2]);
  return RL_OK;
}

/* ------------------------------------------------------------------- reference 3-D Newton */

int rl_omega_exact(const double J[3], const double theta[3], double h, double Omega[3],
                   rl_omega_info *info)
{
  double r[3], x[3] = {theta[0], theta[1], theta[2]};
  rho_coeffs(J, r);
  int it;
  for (it = 1; it <= 100; it++) {
    double g[3], M[9], dx[3];
    eq28(r, theta, h, x, g, M);
    if (!solve3(M, g, dx)) break;
    /* damping: halve the step while it does not reduce |g| */
    double g0 = norm3(g), lam = 1.0, xn[3];
    for (int k = 0; k < 30; k++) {
      double gn[3];
      for (int i = 0; i < 3; i++) xn[i] = x[i] - lam * dx[i];
      eq28(r, theta, h, xn, gn, NULL);
      if (norm3(gn) <= g0 || lam < 1e-6) break;
      lam *= 0.5;
    }
    double change = lam * norm3(dx), size = norm3(xn);
    for (int i = 0; i < 3; i++) x[i] = xn[i];
    if (change <= 1e-15 * size || size == 0.0) break;
  }
  rl_omega_info loc = {RL_OMEGA_PATH_NEWTON, it, rl_omega_residual(J, theta, h, x), 0, 0};
  /* at large h Newton from theta may converge to another solution, or to none */
  const int failed = !(loc.residual <= 1e-13) && !(norm3(x) == 0.0);
  int st = keep_branch(J, rho_max(r), theta, h, x, &loc, failed, "rl_omega_exact");
  Omega[0] = x[0]; Omega[1] = x[1]; Omega[2] = x[2];
  if (info) *info = loc;
  if (!st && !(loc.residual <= 1e-13) && !(norm3(x) == 0.0))
    st = rl_error(RL_ENOCONV, "rl_omega_exact: Newton on eq. 28 did not converge "
                  "(residual %.3g after %d iterations)", loc.residual, loc.iterations);
  return st;
}

/* ---------------------------------------------------------------------- symmetric top */

void rl_omega_symmetric(const double J[3], const double theta[3], double h, double Omega[3])
{
  /* J_X = J_Y: rho_Z = 0, so Omega_Z = theta_Z; rho_Y = -rho_X, nu^2 = rho_X^2 (eq. 29). */
  double rx = (J[1] - J[2]) / (2.0 * J[0]);
  double ry = (J[2] - J[0]) / (2.0 * J[1]);
  double oz = theta[2];
  double d = 1.0 - h * h * rx * ry * oz * oz;
  Omega[0] = (theta[0] + h * rx * theta[1] * oz) / d;
  Omega[1] = (theta[1] + h * ry * theta[0] * oz) / d;
  Omega[2] = oz;
}

/* ---------------------------------------------------------------------- Cayley evolution */

/* The Cayley maps turn about u = w/|w| by phi = 2 atan(x), x = f h |w| (f = 1/2 for D and the
 * axis, 1/4 for the quaternion G).  Their usual form divides by 1 + x^2, which overflows for
 * h|w| beyond ~1e154 (x^2 = Inf, and then (1 - x^2)/(1 + x^2) = NaN).  For x^2 > 1 the callers
 * divide through by x^2 instead: cos phi = (y - 1)/(y + 1), sin phi = 2 (1/x)/(1 + y),
 * 1 - cos phi = 2/(1 + y) with y = 1/x^2, all finite (x = Inf gives the rotation by pi). */
static void cayley_large(const double w[3], double fh, double u[3], double *c, double *s, double *omc)
{
  double m = fmax(fmax(fabs(w[0]), fabs(w[1])), fabs(w[2]));
  for (int k = 0; k < 3; k++) u[k] = w[k] / m;
  double n = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (int k = 0; k < 3; k++) u[k] /= n;
  double ix = 1.0 / (fh * m * n), y = ix * ix, den = 1.0 + y;
  *c = (y - 1.0) / den;
  *s = 2.0 * ix / den;
  *omc = 2.0 / den;
}

void rl_cayley(const double w[3], double h, double D[9])
{
  double x2 = 0.25 * h * h * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  if (x2 > 1.0) { /* D = cos(phi) I + sin(phi) W(u) + (1 - cos(phi)) u u^T */
    double u[3], c, sn, b;
    cayley_large(w, 0.5 * h, u, &c, &sn, &b);
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) D[3 * i + j] = (i == j ? c : 0.0) + b * u[i] * u[j];
    D[1] += sn * u[2]; D[2] -= sn * u[1];
    D[3] -= sn * u[2]; D[5] += sn * u[0];
    D[6] += sn * u[1]; D[7] -= sn * u[0];
    return;
  }
  double inv = 1.0 / (1.0 + x2), c = (1.0 - x2) * inv, hs = h * inv, p = 0.5 * h * h * inv;
  /* W(w) of eq. 3: [[0, wz, -wy], [-wz, 0, wx], [wy, -wx, 0]] */
  D[0] = c + p * w[0] * w[0];
  D[1] = hs * w[2] + p * w[0] * w[1];
  D[2] = -hs * w[1] + p * w[0] * w[2];
  D[3] = -hs * w[2] + p * w[1] * w[0];
  D[4] = c + p * w[1] * w[1];
  D[5] = hs * w[0] + p * w[1] * w[2];
  D[6] = hs * w[1] + p * w[2] * w[0];
  D[7] = -hs * w[0] + p * w[2] * w[1];
  D[8] = c + p * w[2] * w[2];
}

void rl_rotate_matrix(double A[9], const double Omega[3], double h)
{
  double D[9], B[9];
  rl_cayley(Omega, h, D);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      B[3 * i + j] = D[3 * i] * A[j] + D[3 * i + 1] * A[3 + j] + D[3 * i + 2] * A[6 + j];
  for (int i = 0; i < 9; i++) A[i] = B[i];
}

void rl_rotate_axis(double rho[3], const double w[3], double h)
{
  /* d rho/dt = w x rho = W^T(w) rho; Cayley: rho' = [(1-x^2) rho + h w x rho + h^2/2 (w.rho) w]/(1+x^2) */
  double x2 = 0.25 * h * h * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  double c, hs, wr;
  const double *v = w; /* w, or its unit vector when x^2 > 1 (cayley_large) */
  double u[3];
  if (x2 > 1.0) {
    double b;
    cayley_large(w, 0.5 * h, u, &c, &hs, &b);
    wr = b * (u[0] * rho[0] + u[1] * rho[1] + u[2] * rho[2]);
    v = u;
  } else {
    double inv = 1.0 / (1.0 + x2);
    c = (1.0 - x2) * inv;
    hs = h * inv;
    wr = 0.5 * h * h * inv * (w[0] * rho[0] + w[1] * rho[1] + w[2] * rho[2]);
  }
  double cx = v[1] * rho[2] - v[2] * rho[1], cy = v[2] * rho[0] - v[0] * rho[2],
         cz = v[0] * rho[1] - v[1] * rho[0];
  double n0 = c * rho[0] + hs * cx + wr * v[0];
  double n1 = c * rho[1] + hs * cy + wr * v[1];
  double n2 = c * rho[2] + hs * cz + wr * v[2];
  rho[0] = n0; rho[1] = n1; rho[2] = n2;
}

/* --------------------------------------------------------------------------- quaternions */

void rl_quat_rotate(double q[4], const double Om[3], double h)
{
  /* eq. 23: q' = [I (1 - h^2 Omega^2/16) + h Q(Omega)] q / (1 + h^2 Omega^2/16), Q of eq. 5 */
  double x2 = h * h * (Om[0] * Om[0] + Om[1] * Om[1] + Om[2] * Om[2]) / 16.0;
  double c, g, X = Om[0], Y = Om[1], Z = Om[2];
  if (x2 > 1.0) { /* divided through by x^2 (cayley_large): g Omega = sin(phi) u */
    double u[3], b;
    cayley_large(Om, 0.25 * h, u, &c, &g, &b);
    X = u[0]; Y = u[1]; Z = u[2];
  } else {
    double inv = 1.0 / (1.0 + x2);
    c = (1.0 - x2) * inv;
    g = 0.5 * h * inv;
  }
  double n0 = c * q[0] + g * (Z * q[1] - X * q[2] - Y * q[3]);
  double n1 = c * q[1] + g * (-Z * q[0] - Y * q[2] + X * q[3]);
  double n2 = c * q[2] + g * (X * q[0] + Y * q[1] + Z * q[3]);
  double n3 = c * q[3] + g * (Y * q[0] - X * q[1] - Z * q[2]);
  q[0] = n0; q[1] = n1; q[2] = n2; q[3] = n3;
}

