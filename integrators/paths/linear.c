/* Linear molecule: state r, v, rho, l; sites at r + Delta_a rho.  Section III.D: Omega_X =
 * theta_X, Omega_Y = theta_Y, Omega_Z = 0, i.e. rho(t+h) is rho(t) rotated about the part of
 * l(t+h/2)/J perpendicular to rho(t).  2 rotational degrees of freedom. */
#include "path.h"

static int rotate_linear(const rl_species *sp, rl_system *s, rl_rotation_work *w)
{
  return rl_rotate_axis_species(sp, s, w, 1);
}

const rl_family rl_family_linear = {RL_KIND_LINEAR, "linear",
                                    "rho rotated about (theta_X, theta_Y, 0) (III.D)", 2,
                                    rotate_linear, rl_ke_rot_axis};
