/* Pieces shared by the model families: on-step rotational kinetic energy by storage, and the
 * family look-up. */
#include "family.h"

double rl_ke_rot_matrix(const rl_species *sp, const rl_system *s, int b, const double lt[3])
{
  double th[3];
  rl_body_theta(s->A[sp->mat_off + b], sp->J, lt, th); /* Omega(t) = J^-1 A(t) l(t), eq. 11 */
  return 0.5 * (sp->J[0] * th[0] * th[0] + sp->J[1] * th[1] * th[1] + sp->J[2] * th[2] * th[2]);
}

double rl_ke_rot_axis(const rl_species *sp, const rl_system *s, int b, const double lt[3])
{
  /* two rotational degrees of freedom: only l perpendicular to rho carries energy */
  double lp[3] = {lt[0], lt[1], lt[2]};
  rl_project_out(lp, s->rho[sp->axis_off + b]);
  return 0.5 * (lp[0] * lp[0] + lp[1] * lp[1] + lp[2] * lp[2]) / sp->J[0];
}

const rl_family *rl_family_for(rl_kind kind, int force_general)
{
  if (force_general && rl_kind_is_matrix(kind)) return &rl_family_asymmetric;
  switch (kind) {
  case RL_KIND_POINT: return &rl_family_point;
  case RL_KIND_DIPOLE: return &rl_family_dipole;
  case RL_KIND_LINEAR: return &rl_family_linear;
  case RL_KIND_SPHERICAL: return &rl_family_spherical;
  case RL_KIND_SYMMETRIC: return &rl_family_symmetric;
  default: return &rl_family_asymmetric;
  }
}

const char *rl_kind_rotation_path(rl_kind kind)
{
  return kind == RL_KIND_AUTO ? "(classified)" : rl_family_for(kind, 0)->path;
}
