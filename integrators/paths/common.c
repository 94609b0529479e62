/* Pieces shared by the model families: on-step rotational kinetic energy by storage, the rotation
 * of the axis species (dipole, linear), and the family look-up. */
#include "../../core/threads.h"
#include "path.h"
#include "rotleap/rotation.h"

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

int rl_rotate_axis_species(const rl_species *sp, rl_system *s, rl_rotation_work *w, int perpendicular)
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
    if (perpendicular) rl_project_out(om, rho[b]);
    rl_rotate_axis(rho[b], om, h);
    double x = h * rl_norm3(om);
    if (x > hw) hw = x;
  }
  w->max_h_omega = hw;
  return RL_OK;
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
