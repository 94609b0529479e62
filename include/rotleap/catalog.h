/* rotleap — the catalogue of named rigid models, each a const descriptor with its literature
 * reference, unit system and parameters (libxc-style).  Look-up by name. */
#ifndef ROTLEAP_CATALOG_H
#define ROTLEAP_CATALOG_H

#include "rotleap/molecule.h"
#include "rotleap/units.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RL_MODEL_MAX_PARAMS 4

typedef struct rl_model rl_model;
struct rl_model {
  const char *name;           /* look-up key, e.g. "tip4p"                                   */
  const char *description;
  const char *reference;      /* literature reference for the parameters                    */
  rl_units units;             /* real (nm, amu, kJ/mol, e) or lj (reduced)                   */
  rl_kind family;             /* the family it classifies to (checked by tests)              */
  int geometric_mixing;       /* 1: cross LJ pairs use sqrt(sigma_a sigma_b) (OPLS, EPM2);
                                 0: Lorentz-Berthelot                                         */
  int nparams;                /* adjustable parameters (reduced models)                       */
  const char *param_names[RL_MODEL_MAX_PARAMS];
  const char *param_units[RL_MODEL_MAX_PARAMS];
  double param_defaults[RL_MODEL_MAX_PARAMS];
  /* fills the site arrays of m from params (internal; use rl_model_build) */
  int (*define)(const rl_model *self, const double *params, int force_general, rl_molecule *m);
};

int rl_catalog_count(void);
const rl_model *rl_catalog_get(int i);
/* NULL (with a message listing the known names) if unknown. */
const rl_model *rl_catalog_find(const char *name);
/* Index of a parameter by name, -1 if the model has none of that name. */
int rl_model_param_index(const rl_model *model, const char *param);
/* Build the molecule type (params may be NULL for the defaults). */
int rl_model_build(const rl_model *model, const double *params, int force_general, rl_molecule *m);

#ifdef __cplusplus
}
#endif
#endif
