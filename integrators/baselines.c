/* The rotation kernels of the baseline integrators (issue 7), per body and pure: Fincham's
 * implicit quaternion leapfrog (eqs. 10-16 of the paper) and the NO_SQUISH free-rotor splitting
 * of Miller et al., J. Chem. Phys. 116, 8649 (2002), in quaternion + conjugate-momentum form.
 * The paper's hybrid scheme needs no kernel of its own (rl_omega_guarded, then rl_quat_rotate).
 * See include/rotleap/rotation.h for the contracts and docs/integrators.md for the methods. */
#include "rotleap/rotation.h"
#include "rotleap/error.h"

#include <math.h>

/* ------------------------------------------------------------ the generators of eq. 5 */

void rl_quat_generator(int k, const double q[4], double out[4])
{
  /* Q(Omega) = (Omega_X M_X + Omega_Y M_Y + Omega_Z M_Z)/2 read off eq. 5; each M_k is
   * antisymmetric with M_k^2 = -I, and {q, M_X q, M_Y q, M_Z q} is orthonormal for |q| = 1. */
  const double x = q[0], e = q[1], z = q[2], c = q[3];
  switch (k) {
  case 0: out[0] = -z; out[1] = c; out[2] = x; out[3] = -e; break;
  case 1: out[0] = -c; out[1] = -z; out[2] = e; out[3] = x; break;
  default: out[0] = e; out[1] = -x; out[2] = c; out[3] = -z; break;
  }
}

/* q' = Q(Omega) q (eq. 5) */
static void quat_deriv(const double Om[3], const double q[4], double d[4])
{
  const double X = Om[0], Y = Om[1], Z = Om[2];
  d[0] = 0.5 * (Z * q[1] - X * q[2] - Y * q[3]);
  d[1] = 0.5 * (-Z * q[0] - Y * q[2] + X * q[3]);
  d[2] = 0.5 * (X * q[0] + Y * q[1] + Z * q[3]);
  d[3] = 0.5 * (Y * q[0] - X * q[1] - Z * q[2]);
}

/* Omega = J^-1 A(q) l with A(q) of eq. 4 as it stands (no normalisation, as in the scheme) */
static void body_omega(const double J[3], const double q[4], const double l[3], double Om[3])
{
  double A[9];
  rl_quat_to_matrix(q, A);
  for (int a = 0; a < 3; a++) Om[a] = (A[3 * a] * l[0] + A[3 * a + 1] * l[1] + A[3 * a + 2] * l[2]) / J[a];
}

/* ------------------------------------------------------------------------------ Fincham */

/* A quaternion that should stay near the unit sphere and has grown past this norm is taken as
 * a diverging iteration (the fixed-point map of eq. 13 with eq. 14 has no bounded orbit then). */
#define FINCHAM_DIVERGED_NORM 4.0

int rl_fincham_quat(const double J[3], const double lt[3], const double lnext[3], double h,
                    double tol, int maxit, double q[4], rl_fincham_info *info)
{
  rl_fincham_info loc = {0, 0.0, 0.0, 0.0};
  double Om0[3], d0[4], a[4], qn[4];
  body_omega(J, q, lt, Om0);         /* Omega(t) = J^-1 A(t) l(t), eq. 11 */
  quat_deriv(Om0, q, d0);
  loc.h_omega = h * sqrt(Om0[0] * Om0[0] + Om0[1] * Om0[1] + Om0[2] * Om0[2]);
  for (int c = 0; c < 4; c++) {
    a[c] = q[c] + 0.5 * h * d0[c];   /* the known half of eq. 13 with eq. 14             */
    qn[c] = q[c] + h * d0[c];        /* q^(0) = q(t) + h Q(Omega(t)) q(t)                 */
  }
  int it, ok = 0;
  for (it = 1; it <= maxit; it++) {
    double Om1[3], d1[4], next[4], change = 0.0, n2 = 0.0;
    body_omega(J, qn, lnext, Om1);   /* Omega~(t+h) = J^-1 A(q(t+h)) l~(t+h), eq. 15      */
    quat_deriv(Om1, qn, d1);
    for (int c = 0; c < 4; c++) {
      next[c] = a[c] + 0.5 * h * d1[c];
      change = fmax(change, fabs(next[c] - qn[c]));
      n2 += next[c] * next[c];
      qn[c] = next[c];
    }
    loc.change = change;
    if (!isfinite(n2) || !isfinite(change) || n2 > FINCHAM_DIVERGED_NORM * FINCHAM_DIVERGED_NORM) {
      loc.iterations = it;
      if (info) *info = loc;
      return rl_error(RL_ENOCONV, "Fincham quaternion iteration (eqs. 13-16) diverged after %d "
                      "iterations (|q| = %.3g, h|Omega(t)| = %.3g): the step is too large for the "
                      "implicit scheme", it, sqrt(n2), loc.h_omega);
    }
    if (change <= tol) { ok = 1; break; }
  }
  if (!ok) {
    loc.iterations = maxit;
    if (info) *info = loc;
    return rl_error(RL_ENOCONV, "Fincham quaternion iteration (eqs. 13-16) did not converge to %g "
                    "in %d iterations (last change %.3g, h|Omega(t)| = %.3g)", tol, maxit,
                    loc.change, loc.h_omega);
  }
  loc.iterations = it;
  /* The trapezoidal update does not keep |q| = 1 (the paper's criticism): Fincham's codes
   * rescale q after each step, and so does this one; the defect removed is reported. */
  double n = sqrt(qn[0] * qn[0] + qn[1] * qn[1] + qn[2] * qn[2] + qn[3] * qn[3]);
  loc.norm_defect = fabs(n - 1.0);
  for (int c = 0; c < 4; c++) q[c] = qn[c] / n;
  if (info) *info = loc;
  return RL_OK;
}

/* ---------------------------------------------------------------------------- NO_SQUISH */

void rl_quat_conjugate_momentum(const double q[4], const double L[3], double p[4])
{
  /* p = dT/d(dq/dt) = 2 sum_k L_k M_k q (NO_SQUISH's p = 2 S(q) (0, L)^T in eq. 5's convention) */
  double m[4];
  p[0] = p[1] = p[2] = p[3] = 0.0;
  for (int k = 0; k < 3; k++) {
    rl_quat_generator(k, q, m);
    for (int c = 0; c < 4; c++) p[c] += 2.0 * L[k] * m[c];
  }
}

void rl_quat_body_angmom(const double q[4], const double p[4], double L[3])
{
  double m[4];
  for (int k = 0; k < 3; k++) {
    rl_quat_generator(k, q, m);
    L[k] = 0.5 * (m[0] * p[0] + m[1] * p[1] + m[2] * p[2] + m[3] * p[3]);
  }
}

/* The exact flow of H_k = L_k^2 / (2 J_k) over dt: L_k = (M_k q).p / 2 is constant, and
 * (q, p) rotate in the planes (q, M_k q), (p, M_k p) by zeta = dt L_k / (2 J_k). */
static void free_axis(int k, double Jk, double dt, double q[4], double p[4])
{
  double mq[4], mp[4];
  rl_quat_generator(k, q, mq);
  rl_quat_generator(k, p, mp);
  double Lk = 0.5 * (mq[0] * p[0] + mq[1] * p[1] + mq[2] * p[2] + mq[3] * p[3]);
  double zeta = 0.5 * dt * Lk / Jk, cz = cos(zeta), sz = sin(zeta);
  for (int c = 0; c < 4; c++) {
    q[c] = cz * q[c] + sz * mq[c];
    p[c] = cz * p[c] + sz * mp[c];
  }
}

void rl_nosquish_free(const double J[3], double h, double q[4], double p[4])
{
  /* Miller et al.'s symmetric sequence R_3(h/2) R_2(h/2) R_1(h) R_2(h/2) R_3(h/2), with body
   * axes 1, 2, 3 = X, Y, Z as the species gives them, one sub-step (their M = 1). */
  free_axis(2, J[2], 0.5 * h, q, p);
  free_axis(1, J[1], 0.5 * h, q, p);
  free_axis(0, J[0], h, q, p);
  free_axis(1, J[1], 0.5 * h, q, p);
  free_axis(2, J[2], 0.5 * h, q, p);
}
