/* Linear molecule: state r, v, rho, l; sites at r + Delta_a rho.  Section III.D: Omega_X =
 * theta_X, Omega_Y = theta_Y, Omega_Z = 0, i.e. rho(t+h) is rho(t) rotated about the part of
 * l(t+h/2)/J perpendicular to rho(t).  2 rotational degrees of freedom. */
#include "../../core/threads.h"
#include "family.h"
#include "rotleap/rotation.h"

static int rotate_linear(const rl_species *sp, rl_system *s, rl_rotation_work *w)
{
  const double h = w->h, inv = 1.0 / sp->J[0];
  double (*l)[3] = s->l + sp->rot_off, (*rho)[3] = s->rho + sp->axis_off, hw = w->max_h_omega;
  /* each body on its own, so any thread count gives the same result (max is exact); a few
   * thousand bodies pay for the threads' start */
#ifdef _OPENMP
#pragma omp parallel for num_threads(w->threads) schedule(static) \
    if (w->threads > 1 && sp->count >= RL_THREAD_MIN_BODIES) reduction(max : hw)
#endif
  for (int b = 0; b < sp->count; b++) {
    double om[3] = {l[b][0] * inv, l[b][1] * inv, l[b][2] * inv};
    rl_project_out(om, rho[b]);
    rl_rotate_axis(rho[b], om, h);
    double x = h * rl_norm3(om);
    if (x > hw) hw = x;
  }
  w->max_h_omega = hw;
  return RL_OK;
}

const rl_family rl_family_linear = {RL_KIND_LINEAR, "linear",
                                    "rho rotated about (theta_X, theta_Y, 0) (III.D)", 2,
                                    rotate_linear, rl_ke_rot_axis};
