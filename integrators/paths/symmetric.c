/* Symmetric top (two equal moments): in the cyclic relabelling whose Z is the unique axis,
 * rho_Z = 0 so Omega_Z = theta_Z, and Omega_X, Omega_Y follow from eq. 29 with rho_Y = -rho_X
 * in closed form (section III.D).  No cubic. */
#include "path.h"
#include "rotleap/rotation.h"

static int rotate_symmetric(const rl_species *sp, rl_system *s, rl_rotation_work *w)
{
  if (rl_rot_is_baseline(w->method)) return rl_family_asymmetric.rotate(sp, s, w); /* no fast path */
  const double h = w->h;
  const int *p = sp->perm;
  const double Jp[3] = {sp->J[p[0]], sp->J[p[1]], sp->J[p[2]]};
  double (*l)[3] = s->l + sp->rot_off, (*A)[9] = s->A + sp->mat_off, hw = w->max_h_omega;
  for (int b = 0; b < sp->count; b++) {
    double th[3], tp[3], Op[3], Om[3];
    rl_body_theta(A[b], sp->J, l[b], th);
    for (int a = 0; a < 3; a++) tp[a] = th[p[a]];
    rl_omega_symmetric(Jp, tp, h, Op);
    for (int a = 0; a < 3; a++) Om[p[a]] = Op[a];
    rl_rotate_matrix(A[b], Om, h);
    double x = h * rl_norm3(Om);
    if (x > hw) hw = x;
  }
  w->max_h_omega = hw;
  return RL_OK;
}

const rl_family rl_family_symmetric = {RL_KIND_SYMMETRIC, "symmetric",
                                       "Omega_Z = theta_Z, eq. 29 closed form (III.D)", 3,
                                       rotate_symmetric, rl_ke_rot_matrix};
