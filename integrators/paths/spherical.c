/* Spherical top (J_XX = J_YY = J_ZZ = J): A(t+h) = A(t) exp[phi W(omega)/omega] with the lab
 * omega = l(t+h/2)/J and the Cayley angle phi = 2 atan(h omega/2) (section III.D, where the paper
 * writes it as arcsin[h omega/(1 + h^2 omega^2/4)]), computed as the Cayley matrix D(omega)
 * (rl_cayley); no solve.  This is eq. 28 with rho = 0, not the exact free rotation by h omega:
 * phi = h omega - (h omega)^3/12 + ..., so a free spherical top turns at phi/h instead of omega
 * (0.08 %, 2.0 % and 7.3 % slow at h omega = 0.1, 0.5 and 1; tests/integrators/test_rotation.c,
 * spherical_top_angle), with l and the rotational energy exact. */
#include "path.h"
#include "rotleap/rotation.h"

#include <string.h>

static int rotate_spherical(const rl_species *sp, rl_system *s, rl_rotation_work *w)
{
  if (rl_rot_is_baseline(w->method)) return rl_family_asymmetric.rotate(sp, s, w); /* no fast path */
  const double h = w->h, inv = 1.0 / sp->J[0];
  double (*l)[3] = s->l + sp->rot_off, (*A)[9] = s->A + sp->mat_off, hw = w->max_h_omega;
  for (int b = 0; b < sp->count; b++) {
    double om[3] = {l[b][0] * inv, l[b][1] * inv, l[b][2] * inv}, D[9], B[9];
    rl_cayley(om, h, D);
    const double *a = A[b];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++)
        B[3 * i + j] = a[3 * i] * D[j] + a[3 * i + 1] * D[3 + j] + a[3 * i + 2] * D[6 + j];
    memcpy(A[b], B, sizeof B);
    double x = h * rl_norm3(om);
    if (x > hw) hw = x;
  }
  w->max_h_omega = hw;
  return RL_OK;
}

const rl_family rl_family_spherical = {RL_KIND_SPHERICAL, "spherical",
                                       "A exp[phi W(omega)/omega], omega = l/J (III.D)", 3,
                                       rotate_spherical, rl_ke_rot_matrix};
