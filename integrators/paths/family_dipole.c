/* Point dipole (Stockmayer): state r, v, unit axis rho, lab l; spherical inertia I.
 * omega = l(t+h/2) / I and rho(t+h) = rho(t) rotated about omega by 2 atan(h omega/2), the
 * Cayley/exponential map of section III.D.  The discrete scheme conserves l(t+h/2).rho(t)
 * exactly (a rotation about l leaves l.rho unchanged, and the torque mu x E is perpendicular to
 * rho), so a spin that starts at zero stays zero: 2 rotational degrees of freedom. */
#include "../../core/threads.h"
#include "family.h"
#include "rotleap/rotation.h"

static int rotate_dipole(const rl_species *sp, rl_system *s, rl_rotation_work *w)
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
    rl_rotate_axis(rho[b], om, h);
    double x = h * rl_norm3(om);
    if (x > hw) hw = x;
  }
  w->max_h_omega = hw;
  return RL_OK;
}

const rl_family rl_family_dipole = {RL_KIND_DIPOLE, "dipole", "rho rotated about l/I (III.D)", 2,
                                    rotate_dipole, rl_ke_rot_axis};
