/* Point dipole (Stockmayer): state r, v, unit axis rho, lab l; spherical inertia I.
 * omega = l(t+h/2) / I and rho(t+h) = rho(t) rotated about omega by 2 atan(h omega/2), the
 * Cayley/exponential map of section III.D.  The discrete scheme conserves l(t+h/2).rho(t)
 * exactly (a rotation about l leaves l.rho unchanged, and the torque mu x E is perpendicular to
 * rho), so a spin that starts at zero stays zero: 2 rotational degrees of freedom. */
#include "path.h"

static int rotate_dipole(const rl_species *sp, rl_system *s, rl_rotation_work *w)
{
  return rl_rotate_axis_species(sp, s, w, 0);
}

const rl_family rl_family_dipole = {RL_KIND_DIPOLE, "dipole", "rho rotated about l/I (III.D)", 2,
                                    rotate_dipole, rl_ke_rot_axis};
