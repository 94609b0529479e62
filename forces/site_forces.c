/* Site forces to body forces and torques (forces.h): for providers that work site by site. */
#include "rotleap/forces.h"
#include "../core/system_impl.h"

#include <math.h>
#include <stddef.h>

void rl_system_add_site_forces_of(const rl_system *s, const double (*fs)[3], rl_forces *out,
                                  int i0, int i1)
{
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    const int b0 = i0 > sp->first ? i0 - sp->first : 0;
    const int b1 = i1 < sp->first + sp->count ? i1 - sp->first : sp->count;
    for (int b = b0; b < b1; b++) {
      int i = sp->first + b, o = sp->site_off + b * sp->nsites;
      double *f = out->f[i];
      double *t = sp->rot_off >= 0 ? out->k[sp->rot_off + b] : NULL;
      for (int a = 0; a < sp->nsites; a++) {
        const double *fa = fs[o + a], *d = sp->sites + 3 * a;
        f[0] += fa[0]; f[1] += fa[1]; f[2] += fa[2];
        if (!t) continue;
        double x[3]; /* r_a - r in the lab */
        if (sp->mat_off >= 0) {
          const double *A = s->A[sp->mat_off + b];
          for (int c = 0; c < 3; c++) x[c] = A[c] * d[0] + A[3 + c] * d[1] + A[6 + c] * d[2];
        } else {
          const double *rho = s->rho[sp->axis_off + b];
          for (int c = 0; c < 3; c++) x[c] = d[2] * rho[c];
        }
        t[0] += x[1] * fa[2] - x[2] * fa[1];
        t[1] += x[2] * fa[0] - x[0] * fa[2];
        t[2] += x[0] * fa[1] - x[1] * fa[0];
      }
    }
  }
}

void rl_system_add_site_forces(const rl_system *s, const double (*fs)[3], rl_forces *out)
{
  rl_system_add_site_forces_of(s, fs, out, 0, s->n);
}


double rl_forces_pressure(const rl_system *sys, const rl_forces *f, double ke_trans)
{
  double L[3];
  rl_system_box(sys, L);
  return rl_forces_pressure_in(L, f, ke_trans);
}

double rl_forces_pressure_in(const double L[3], const rl_forces *f, double ke_trans)
{
  const double V = L[0] * L[1] * L[2]; /* as rl_box_volume forms it */
  if (!(V > 0.0)) return NAN;
  return (2.0 * ke_trans + f->virial[0] + f->virial[4] + f->virial[8]) / (3.0 * V);
}
