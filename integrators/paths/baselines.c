/* The baseline rotation methods (issue 7) for one matrix body: the paper's hybrid scheme,
 * Fincham's implicit quaternion leapfrog and NO_SQUISH.  The state stays the rotation matrix:
 * q(t) is taken from A(t) (rl_matrix_to_quat, chi >= 0; every scheme here is unchanged by
 * q -> -q), the scheme advances q, and A(t+h) = A(q(t+h)) (eq. 4).  A step is therefore a
 * function of (A, l, k) alone and a restart from a checkpoint continues bit for bit.  The
 * quaternion a step produced is kept in w->q for rl_integrator_quaternion.
 *
 * NO_SQUISH in rotleap's leapfrog.  Miller et al. write one step as velocity Verlet:
 *   p <- p + h/2 * 2 S(q) (0, K)   (half kick by the body torque K = A k)
 *   free rotor over h               (the splitting of rl_nosquish_free)
 *   p <- p + h/2 * 2 S(q) (0, K)   (half kick with the new torque).
 * At fixed q the kick p += h S(q)(0, K) is L += h/2 K in the body frame, i.e. l += h/2 k in the
 * lab, and the free rotor conserves the lab l exactly.  So with l as the momentum variable the
 * step is: l += h/2 k(t); rotate; l += h/2 k(t+h).  Two consecutive steps join the closing half
 * kick of one and the opening half kick of the next into l(t+h/2) = l(t-h/2) + h k(t), which is
 * exactly rotleap's kick (step 2 of leapfrog.c); the drift of r and the free rotation commute
 * (disjoint variables).  The orientations at whole steps are therefore Miller's velocity-Verlet
 * orientations, the stored l(t+h/2) is their momentum after the first half kick, and the
 * on-step l(t) = l(t-h/2) + h/2 k(t) of eq. 12 is their on-step momentum: the same trajectory,
 * only staggered. */
#include "path.h"
#include "rotleap/error.h"
#include "rotleap/rotation.h"

#include <math.h>
#include <string.h>

int rl_rotate_baseline(const rl_species *sp, rl_system *s, int b, rl_rotation_work *w, double *hw)
{
  const double h = w->h;
  const int ir = sp->rot_off + b, im = sp->mat_off + b, body = sp->first + b;
  const double *l = s->l[ir];
  double *A = s->A[im], q[4];
  int st = rl_matrix_to_quat(A, q);
  if (st) return rl_error_wrap(st, "body %d at step %ld", body, w->step);
  /* Normalise: rl_matrix_to_quat of an A that is orthonormal only to round-off returns |q| - 1
   * of that size but not with the same factor, and A(q) squares |q| -- fed back every step,
   * that amplifies round-off exponentially (measured: |A^T A - I| 1e-16 -> 7e-4 in 250 steps for
   * the hybrid on the test cluster).  With |q| = 1 each step's A(q) is orthonormal to a few ulp
   * and nothing accumulates. */
  double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (int c = 0; c < 4; c++) q[c] /= n;
  switch (w->method) {
  case RL_ROT_HYBRID: {
    /* Omega(t+h/2) from the matrix form (eq. 28, guarded cubic), put into the quaternion
     * Cayley update (eq. 23) instead of eq. 24 */
    double th[3], Om[3];
    rl_omega_info oi;
    rl_body_theta(A, sp->J, l, th);
    st = rl_omega_guarded(sp->J, th, h, w->guard_tol, Om, &oi);
    if (st) return rl_error_wrap(st, "hybrid: body %d at step %ld", body, w->step);
    if (oi.path >= RL_OMEGA_PATH_NEWTON) w->fallbacks++;
    rl_quat_rotate(q, Om, h);
    *hw = h * rl_norm3(Om);
    break;
  }
  case RL_ROT_FINCHAM: {
    /* l'(t) = [l(t-h/2) + l'(t+h/2)]/2: eq. 12 in NVE, the thermostatted on-step l'(t) =
     * beta l(t) of eq. 18 under the isokinetic scheme; l~(t+h) = l'(t+h/2) + h/2 k(t), eq. 16 */
    const double *lp = w->l_prev[ir], *k = w->k[ir];
    double lt[3], ln[3];
    for (int c = 0; c < 3; c++) {
      lt[c] = 0.5 * (lp[c] + l[c]);
      ln[c] = l[c] + 0.5 * h * k[c];
    }
    rl_fincham_info fi;
    st = rl_fincham_quat(sp->J, lt, ln, h, w->quat_tol, w->quat_maxit, q, &fi);
    w->quat_iterations += fi.iterations;
    if (fi.iterations > w->quat_max_iterations) w->quat_max_iterations = fi.iterations;
    if (st) return rl_error_wrap(st, "Fincham: body %d at step %ld", body, w->step);
    if (fi.norm_defect > w->quat_norm_defect) w->quat_norm_defect = fi.norm_defect;
    *hw = fi.h_omega;
    break;
  }
  case RL_ROT_NOSQUISH: {
    /* principal L = A l, its conjugate momentum p, the free-rotor splitting; the lab l is an
     * exact invariant of every sub-rotation, so it is left as it is (recomputing it from p
     * would return it up to round-off) */
    double L[3], p[4], Om[3];
    for (int a = 0; a < 3; a++) {
      L[a] = A[3 * a] * l[0] + A[3 * a + 1] * l[1] + A[3 * a + 2] * l[2];
      Om[a] = L[a] / sp->J[a];
    }
    rl_quat_conjugate_momentum(q, L, p);
    rl_nosquish_free(sp->J, h, q, p);
    *hw = h * rl_norm3(Om);
    break;
  }
  default:
    return rl_error(RL_EINVAL, "rl_rotate_baseline: method %d is not a baseline", (int)w->method);
  }
  rl_quat_to_matrix(q, A);
  memcpy(w->q[im], q, sizeof q);
  return RL_OK;
}
