/* The pair force field (forces/pair/) as the force term "pair" (forcefield.h, terms.h): LJ with
 * its truncations and long-range correction, reaction-field Coulomb, point dipoles and linear
 * quadrupoles, site by site, with the specialised kernels. */
#include "rotleap/forcefield.h"
#include "rotleap/error.h"

#include "pair/forcefield_impl.h"

#include <math.h>
#include <stddef.h>

static void *pair_alloc(const rl_system *sys, const void *params)
{
  const rl_pair_params *pp = params;
  if (!pp) { rl_error(RL_EINVAL, "the pair term needs its parameters (rl_pair_params)"); return NULL; }
  rl_forcefield *ff = rl_forcefield_alloc(sys, &pp->p, pp->species, pp->nspecies); /* the system's cell */
  for (int s = 0; ff && pp->geometric_mixing && s < pp->nspecies; s++) { /* OPLS, EPM2: sigma_ab = sqrt(sigma_a sigma_b) */
    const rl_species_ff *f = &pp->species[s];
    for (int a = 0; a < f->nsites; a++)
      for (int b = a; b < f->nsites; b++)
        if (f->epsilon[a] > 0 && f->epsilon[b] > 0 &&
            rl_forcefield_set_lj_pair(ff, s, a, s, b, sqrt(f->sigma[a] * f->sigma[b]), sqrt(f->epsilon[a] * f->epsilon[b]))) {
          rl_forcefield_free(ff);
          return NULL;
        }
  }
  return ff;
}

static int pair_compute(void *state, const rl_system *sys, rl_forces *out, double *energies)
{
  const int st = rl_forcefield_compute(state, sys, out);
  if (st) return st;
  rl_ff_energies e;
  rl_forcefield_energies(state, &e);
  energies[0] = e.lj;
  energies[1] = e.coulomb;
  energies[2] = e.dipolar;
  energies[3] = e.quadrupolar;
  energies[4] = e.dispersion;
  return RL_OK;
}

static int pair_box_changed(void *state, const rl_system *sys) { return rl_ff_take_box(state, sys); }

static void pair_free(void *state) { rl_forcefield_free(state); }

const rl_term_type rl_term_pair = {
    "pair",
    "site-site pair interactions within a cutoff: Lennard-Jones (plain, shifted, shifted-force or switched, with "
    "the long-range dispersion correction), reaction-field Coulomb, point dipoles (reaction field or shifted "
    "force) and linear point quadrupoles; specialised kernels by site pattern (docs/interactions.md)",
    "OpenMM 7.7 NonbondedForce (CutoffPeriodic) for the reaction field; Barker & Watts, Mol. Phys. 26, 789 (1973); "
    "Allen & Germano, Mol. Phys. 104, 3225 (2006)",
    5,
    {"lj", "coulomb", "dipolar", "quadrupolar", "dispersion"},
    pair_alloc,
    pair_compute,
    pair_box_changed,
    pair_free};
