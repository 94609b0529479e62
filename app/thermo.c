/* The thermo file's header and rows (thermo.h). */
#include "thermo.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The columns: step, time, total, potential, the energy components of every force term (terms.h:
 * lj, coulomb, dipolar, quadrupolar, dispersion for the pair term), kinetic energies,
 * temperatures, pressure, the conserved quantity, calE and the mid-step temperatures; under a
 * barostat also the volume, the density (g/cm3; reduced: mass per volume), the box edges and the
 * pressure tensor (thermo_row); in a mixture then each species' translational and, if it
 * rotates, rotational temperature (rl_species_kinetic). */
static int mixture_species(const rl_deck *d) { return d->nspecies > 1 ? d->nspecies : 0; }

char *thermo_header(const rl_deck *d, const scene *s)
{
  char *h = NULL;
  size_t n = 0;
  FILE *f = open_memstream(&h, &n);
  if (!f) return NULL;
  fputs("step,time,total,potential", f);
  for (int j = 0; j < rl_terms_nenergies(s->terms); j++) fprintf(f, ",%s", rl_terms_energy_name(s->terms, j));
  fputs(",ke_trans,ke_rot,temperature,t_trans,t_rot,pressure,conserved,calE,t_trans_mid,t_rot_mid", f);
  fputs(d->barostat ? ",volume,density,Lx,Ly,Lz,Pxx,Pyy,Pzz,Pxy,Pxz,Pyz" : "", f);
  for (int k = 0; k < mixture_species(d); k++) {
    fprintf(f, ",t_trans_%s", s->mols[k].name);
    if (rl_kind_rotational_dof(rl_system_species_kind(s->sys, k))) fprintf(f, ",t_rot_%s", s->mols[k].name);
  }
  fputc('\n', f);
  if (fclose(f)) { free(h); return NULL; }
  return h;
}

/* The state at the start of step k with its energy components comp (the terms' at that time);
 * calE is the running relative fluctuation of the conserved quantity (E).  Under a barostat
 * (box) the pressure tensor P_ab = (2 K_trans/3 delta_ab + W_ab)/V of the molecular virial W
 * (row-major): its kinetic part is the isotropic one of the scalar pressure (the on-step
 * velocities' tensor is not kept), so its trace/3 is the pressure column and its anisotropy the
 * virial's; scaled by pscale (to bar). */
static int row(FILE *f, const char *path, long k, const rl_step_info *info, const rl_terms *t, const double *comp,
               double pr, const running *E, const double *box, double mass, const double *W, double pscale,
               const rl_system *sys, int nsp)
{
  int bad = fprintf(f, "%ld,%.10g,%.10g,%.10g", k, info->t, info->total, info->potential) < 0;
  for (int j = 0; j < rl_terms_nenergies(t) && !bad; j++) bad = fprintf(f, ",%.10g", comp[j]) < 0;
  if (!bad)
    bad = fprintf(f, ",%.10g,%.10g,%.6g,%.6g,%.6g,%.10g,%.10g,%.4e,%.6g,%.6g", info->ke_trans, info->ke_rot,
                  info->temperature, info->t_trans, info->t_rot, pr, info->conserved,
                  E->n > 1 ? running_sd(E) / fabs(E->mean) : 0.0, info->t_trans_mid, info->t_rot_mid) < 0;
  if (!bad && box) {
    const double V = box[0] * box[1] * box[2];
    bad = fprintf(f, ",%.10g,%.10g,%.10g,%.10g,%.10g", V, mass / V, box[0], box[1], box[2]) < 0;
    const double kin = 2.0 * info->ke_trans / 3.0;
    static const int ab[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
    for (int q = 0; q < 6 && !bad; q++)
      bad = fprintf(f, ",%.10g", pscale * ((q < 3 ? kin : 0.0) + (W ? W[3 * ab[q][0] + ab[q][1]] : NAN)) / V) < 0;
  }
  for (int q = 0; q < nsp && !bad; q++) {
    const rl_species_kinetic *sk = q < info->nspecies && info->species ? &info->species[q] : NULL;
    bad = fprintf(f, ",%.6g", sk ? sk->t_trans : NAN) < 0;
    if (!bad && rl_kind_rotational_dof(rl_system_species_kind(sys, q))) bad = fprintf(f, ",%.6g", sk ? sk->t_rot : NAN) < 0;
  }
  if (!bad) bad = fputc('\n', f) == EOF;
  if (bad) return rl_error(RL_EINVAL, "cannot write %s: %s", path, strerror(errno));
  return RL_OK;
}

int thermo_row(FILE *f, const char *path, const rl_deck *d, const scene *s, const rl_run_report *r, const running *E)
{
  if (!r->info) return rl_error(RL_ESTATE, "a thermo row is written from a step report");
  return row(f, path, r->step, r->info, r->terms, r->energies, scene_pressure_out(d, r->pressure), E,
             d->barostat ? r->box : NULL, scene_density_mass(d, s->sys), r->forces ? r->forces->virial : NULL,
             scene_pressure_out(d, 1.0), s->sys, mixture_species(d));
}
