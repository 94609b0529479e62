/* The interactions of a scene as a sum of typed terms (terms.h). */
#include "rotleap/terms.h"
#include "rotleap/error.h"
#include "rotleap/forcefield.h"
#include "rotleap/ewald.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The term types, by name.  A new term type is one more entry (docs/extending.md). */
static const rl_term_type *const types[] = {&rl_term_pair, &rl_term_ewald_real, &rl_term_ewald, &rl_term_pme};
enum { NTYPES = sizeof types / sizeof types[0] };

int rl_term_type_count(void) { return NTYPES; }
const rl_term_type *rl_term_type_get(int i) { return i >= 0 && i < NTYPES ? types[i] : NULL; }

const rl_term_type *rl_term_type_find(const char *name)
{
  for (int i = 0; i < NTYPES; i++)
    if (name && !strcmp(types[i]->name, name)) return types[i];
  char known[256] = "";
  for (int i = 0; i < NTYPES; i++) {
    strncat(known, i ? ", " : "", sizeof known - strlen(known) - 1);
    strncat(known, types[i]->name, sizeof known - strlen(known) - 1);
  }
  rl_error(RL_EINVAL, "unknown force term '%s' (known: %s)", name ? name : "(null)", known);
  return NULL;
}

#define MAX_ENERGIES 64

typedef struct {
  const rl_term_type *type;
  void *state;
  int first; /* its first energy component in the sum's list */
} term;

struct rl_terms {
  const rl_system *sys;
  term *t;
  int n, cap;
  int nenergies;
  double energies[MAX_ENERGIES]; /* the components of the last computation, all terms in order */
  double kept[MAX_ENERGIES];     /* the provider's keep (put back by put_back)                  */
  unsigned long box_version;     /* the system's box version the terms last followed           */
};

rl_terms *rl_terms_alloc(const rl_system *sys)
{
  if (!sys) { rl_error(RL_EINVAL, "rl_terms_alloc: NULL system"); return NULL; }
  rl_terms *t = calloc(1, sizeof *t);
  if (!t) { rl_error(RL_ENOMEM, "out of memory"); return NULL; }
  t->sys = sys;
  t->box_version = rl_system_box_version(sys);
  for (int j = 0; j < MAX_ENERGIES; j++) t->energies[j] = NAN;
  return t;
}

void rl_terms_free(rl_terms *t)
{
  if (!t) return;
  for (int k = 0; k < t->n; k++)
    if (t->t[k].type->free) t->t[k].type->free(t->t[k].state);
  free(t->t);
  free(t);
}

int rl_terms_add(rl_terms *t, const rl_term_type *type, const void *params, int *index)
{
  if (!t || !type || !type->alloc || !type->compute) return rl_error(RL_EINVAL, "rl_terms_add: NULL argument or incomplete type");
  if (type->nenergies < 1 || type->nenergies > RL_TERM_MAX_ENERGIES || t->nenergies + type->nenergies > MAX_ENERGIES)
    return rl_error(RL_EINVAL, "rl_terms_add: term '%s' has %d energy components (1 to %d, and at most %d in a sum)",
                    type->name, type->nenergies, RL_TERM_MAX_ENERGIES, MAX_ENERGIES);
  if (t->n == t->cap) {
    const int cap = t->cap ? 2 * t->cap : 4;
    term *p = realloc(t->t, sizeof *p * (size_t)cap);
    if (!p) return rl_error(RL_ENOMEM, "out of memory");
    t->t = p;
    t->cap = cap;
  }
  void *state = type->alloc(t->sys, params);
  if (!state) return rl_error_wrap(RL_EINVAL, "force term '%s'", type->name);
  t->t[t->n] = (term){type, state, t->nenergies};
  t->nenergies += type->nenergies;
  if (index) *index = t->n;
  t->n++;
  return RL_OK;
}

int rl_terms_count(const rl_terms *t) { return t ? t->n : 0; }
const rl_term_type *rl_terms_type(const rl_terms *t, int k) { return t && k >= 0 && k < t->n ? t->t[k].type : NULL; }
void *rl_terms_state(rl_terms *t, int k) { return t && k >= 0 && k < t->n ? t->t[k].state : NULL; }

void *rl_terms_find(rl_terms *t, const rl_term_type *type)
{
  for (int k = 0; t && k < t->n; k++)
    if (t->t[k].type == type) return t->t[k].state;
  return NULL;
}

int rl_terms_compute(rl_terms *t, const rl_system *sys, rl_forces *out)
{
  /* the one mechanism by which the terms follow the cell: its version, checked here */
  const unsigned long v = rl_system_box_version(sys);
  if (v != t->box_version) {
    for (int k = 0; k < t->n; k++)
      if (t->t[k].type->box_changed) {
        const int st = t->t[k].type->box_changed(t->t[k].state, sys);
        if (st) return rl_error_wrap(st, "force term '%s' cannot follow the new box", t->t[k].type->name);
      }
    t->box_version = v;
  }
  for (int k = 0; k < t->n; k++) {
    const int st = t->t[k].type->compute(t->t[k].state, sys, out, t->energies + t->t[k].first);
    if (st) return st;
  }
  return RL_OK;
}

static int terms_provider_fn(void *ctx, const rl_system *sys, rl_forces *out) { return rl_terms_compute(ctx, sys, out); }
rl_force_provider rl_terms_provider(rl_terms *t) { return (rl_force_provider){terms_provider_fn, t}; }
rl_terms *rl_terms_of_provider(rl_force_provider p) { return p.compute == terms_provider_fn ? p.ctx : NULL; }

/* The energy components are all the sum reports besides the forces; the terms' own states (pair
 * lists, meshes) follow the configuration they are given. */
void rl_terms_keep(rl_terms *t) { memcpy(t->kept, t->energies, sizeof t->kept); }
void rl_terms_put_back(rl_terms *t) { memcpy(t->energies, t->kept, sizeof t->energies); }

int rl_terms_nenergies(const rl_terms *t) { return t ? t->nenergies : 0; }
double rl_terms_energy(const rl_terms *t, int j) { return t && j >= 0 && j < t->nenergies ? t->energies[j] : NAN; }

int rl_terms_energy_term(const rl_terms *t, int j)
{
  for (int k = 0; t && k < t->n; k++)
    if (j >= t->t[k].first && j < t->t[k].first + t->t[k].type->nenergies) return k;
  return -1;
}

const char *rl_terms_energy_name(const rl_terms *t, int j)
{
  const int k = rl_terms_energy_term(t, j);
  return k < 0 ? NULL : t->t[k].type->energy_names[j - t->t[k].first];
}
