/* Asymmetric body, the general path: theta = J^-1 A(t) l(t+h/2); Omega(t+h/2) from eq. 28 by
 * the guarded quasi-analytic cubic (default), the exact 3-D Newton solve, or the quaternion
 * variant (eq. 23 iterated with eqs. 19-20 in quaternion space); A(t+h) = D(Omega) A(t).
 * Under a baseline method (hybrid, Fincham, NO_SQUISH) every matrix body comes here and is
 * moved by integrators/paths/baselines.c. */
#include "path.h"
#include "rotleap/error.h"
#include "rotleap/rotation.h"

#include <math.h>
#include <string.h>

static int rotate_quaternion(const rl_species *sp, int b, const double l[3], double A[9],
                             rl_rotation_work *w, double *hw)
{
  double *q = w->q[sp->mat_off + b], qn[4] = {q[0], q[1], q[2], q[3]}, Om[3] = {0, 0, 0};
  const double h = w->h;
  int it;
  for (it = 1; it <= w->quat_maxit; it++) {
    double qm[4], Am[9], qt[4] = {q[0], q[1], q[2], q[3]};
    for (int c = 0; c < 4; c++) qm[c] = 0.5 * (q[c] + qn[c]);
    rl_quat_to_matrix(qm, Am); /* A(t+h/2) = A[q(t+h/2)], eqs. 4, 20 */
    rl_body_theta(Am, sp->J, l, Om); /* eq. 19 */
    rl_quat_rotate(qt, Om, h);       /* eq. 23 */
    double d = 0.0;
    for (int c = 0; c < 4; c++) { d = fmax(d, fabs(qt[c] - qn[c])); qn[c] = qt[c]; }
    if (d <= w->quat_tol) break;
  }
  if (it > w->quat_maxit)
    return rl_error(RL_ENOCONV, "quaternion iteration (eq. 23) did not converge to %g in %d "
                    "iterations for body %d at step %ld (h|Omega| = %.3g)", w->quat_tol,
                    w->quat_maxit, sp->first + b, w->step, h * rl_norm3(Om));
  memcpy(q, qn, sizeof qn);
  rl_quat_to_matrix(q, A);
  *hw = h * rl_norm3(Om);
  w->quat_iterations += it;
  if (it > w->quat_max_iterations) w->quat_max_iterations = it;
  return RL_OK;
}

/* The default paths (cubic, exact) for one body: Omega(t+h/2) from theta = J^-1 A l, then
 * A <- D(Omega) A.  On an error A is left as it was. */
static int solve_rotate(const rl_species *sp, double A[9], const double l[3],
                        const rl_rotation_work *w, int *fallback, double *hw)
{
  double th[3], Om[3];
  rl_omega_info oi;
  rl_body_theta(A, sp->J, l, th);
  int st = w->method == RL_ROT_EXACT ? rl_omega_exact(sp->J, th, w->h, Om, &oi)
                                     : rl_omega_guarded(sp->J, th, w->h, w->guard_tol, Om, &oi);
  if (st) return st;
  *fallback = w->method == RL_ROT_CUBIC && oi.path >= RL_OMEGA_PATH_NEWTON;
  rl_rotate_matrix(A, Om, w->h);
  *hw = w->h * rl_norm3(Om);
  return RL_OK;
}

static int rotate_asymmetric(const rl_species *sp, rl_system *s, rl_rotation_work *w)
{
  double (*l)[3] = s->l + sp->rot_off, (*A)[9] = s->A + sp->mat_off;
  if (rl_rot_is_baseline(w->method) || w->method == RL_ROT_QUATERNION) {
    for (int b = 0; b < sp->count; b++) {
      double hw = 0.0;
      int st = rl_rot_is_baseline(w->method) ? rl_rotate_baseline(sp, s, b, w, &hw)
                                             : rotate_quaternion(sp, b, l[b], A[b], w, &hw);
      if (st) return st;
      if (hw > w->max_h_omega) w->max_h_omega = hw;
    }
    return RL_OK;
  }
  /* Bodies are independent, and what they report back (a count, a maximum) does not depend on
   * their order, so the result is the same for any thread count.  A failed solve leaves its
   * body as it was: the first one is solved again on this thread for the error message (the
   * message buffer is per thread). */
  long fallbacks = 0;
  double mx = w->max_h_omega;
  int first = sp->count;
#ifdef _OPENMP
#pragma omp parallel for num_threads(w->threads) schedule(static) if (w->threads > 1) \
    reduction(+ : fallbacks) reduction(max : mx) reduction(min : first)
#endif
  for (int b = 0; b < sp->count; b++) {
    int fb = 0;
    double hw = 0.0;
    if (solve_rotate(sp, A[b], l[b], w, &fb, &hw)) {
      if (b < first) first = b;
      continue;
    }
    fallbacks += fb;
    if (hw > mx) mx = hw;
  }
  w->fallbacks += fallbacks;
  w->max_h_omega = mx;
  if (first < sp->count) {
    int fb;
    double hw;
    int st = solve_rotate(sp, A[first], l[first], w, &fb, &hw);
    return rl_error_wrap(st ? st : RL_ENOCONV, "body %d at step %ld", sp->first + first, w->step);
  }
  return RL_OK;
}

const rl_family rl_family_asymmetric = {RL_KIND_ASYMMETRIC, "asymmetric",
                                        "guarded quasi-analytic cubic (eqs. 28-36)", 3,
                                        rotate_asymmetric, rl_ke_rot_matrix};
