/* rotleap — force terms: the interactions of a scene as a sum of typed terms.
 *
 * A term type is a const descriptor (libxc / GSL style): its name, what it computes and its
 * literature reference, the names of the energy components it reports, and the functions that
 * make its state from its own parameter block, add its forces, torques, energy and molecular
 * virial to the shared accumulators, follow a change of the system's cell, and free it.  Types
 * are looked up by name, as the model catalogue is.  rl_terms is the scene's provider: it sums
 * its terms into one rl_forces (forces.h), in the order they were added, and keeps the energy of
 * every component of the last computation (the thermo file's columns, `rotleap energy --json`).
 * A term is added without touching the integrator or any other term (docs/extending.md).
 *
 * Before each computation the provider compares the system's box version (system.h) with the
 * one it last saw and, if the cell changed, calls every term's box_changed first: the one
 * mechanism by which pair lists, image lists, kernel tables and meshes follow a barostat. */
#ifndef ROTLEAP_TERMS_H
#define ROTLEAP_TERMS_H

#include "rotleap/forces.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RL_TERM_MAX_ENERGIES 8

typedef struct {
  const char *name;           /* look-up key, e.g. "pair"                                         */
  const char *description;
  const char *reference;      /* literature reference of the method                               */
  int nenergies;              /* energy components it reports (their sum is its energy)           */
  const char *energy_names[RL_TERM_MAX_ENERGIES];
  /* State for sys from the type's parameter block (documented with the type); NULL with a message. */
  void *(*alloc)(const rl_system *sys, const void *params);
  /* Add the term's forces and torques (and, unless out->forces_only, its energy and virial) for
   * the current configuration to out; energies[nenergies] receive its components (NaN with
   * forces_only).  RL_OK or a status with a message. */
  int (*compute)(void *state, const rl_system *sys, rl_forces *out, double *energies);
  /* The system's cell changed: update what depends on it (RL_EINVAL if the term cannot follow,
   * e.g. a cutoff beyond half the new box).  NULL: the term does not depend on the cell. */
  int (*box_changed)(void *state, const rl_system *sys);
  void (*free)(void *state);
} rl_term_type;

/* The term types rotleap has, by name (NULL with a message listing them if unknown). */
const rl_term_type *rl_term_type_find(const char *name);
int rl_term_type_count(void);
const rl_term_type *rl_term_type_get(int i);

typedef struct rl_terms rl_terms;

/* An empty sum for sys (NULL on out of memory). */
rl_terms *rl_terms_alloc(const rl_system *sys);
void rl_terms_free(rl_terms *t); /* frees every term's state; accepts NULL */
/* Add a term of `type` made from its parameter block; its index in *index (may be NULL). */
int rl_terms_add(rl_terms *t, const rl_term_type *type, const void *params, int *index);
int rl_terms_count(const rl_terms *t);
const rl_term_type *rl_terms_type(const rl_terms *t, int k);
void *rl_terms_state(rl_terms *t, int k);
/* The state of the first term of `type`, or NULL. */
void *rl_terms_find(rl_terms *t, const rl_term_type *type);

/* The sum of the terms into out (whose arrays the caller zeroed: the provider contract). */
int rl_terms_compute(rl_terms *t, const rl_system *sys, rl_forces *out);
rl_force_provider rl_terms_provider(rl_terms *t);
/* The sum behind a provider made by rl_terms_provider (NULL for any other provider). */
rl_terms *rl_terms_of_provider(rl_force_provider p);
/* Keep the energy components of the last computation, and put them back (what the sum reports
 * besides rl_forces): a caller that puts the configuration back after a computation (a rejected
 * Monte Carlo move) puts back the computation with it instead of repeating it
 * (rl_stepop_forces_keep). */
void rl_terms_keep(rl_terms *t);
void rl_terms_put_back(rl_terms *t);

/* The energy components of every term, in order: their number, names and values at the last
 * computation (NaN where it was forces only); the sum of the values is the potential energy. */
int rl_terms_nenergies(const rl_terms *t);
const char *rl_terms_energy_name(const rl_terms *t, int j);
double rl_terms_energy(const rl_terms *t, int j);
/* The term that reports component j (its index). */
int rl_terms_energy_term(const rl_terms *t, int j);

#ifdef __cplusplus
}
#endif
#endif
