/* The built-in step operators by name, the thermostat each rl_thermostat adds, and the pieces
 * the thermostats share (parameter checks, random stream). */
#include "thermostat.h"
#include "rotleap/error.h"

#include <gsl/gsl_rng.h>
#include <math.h>
#include <string.h>

const rl_stepop_type *rl_stepop_find(const char *name)
{
  static const rl_stepop_type *const all[] = {&rl_stepop_isokinetic, &rl_stepop_bussi, &rl_stepop_langevin,
                                                  &rl_stepop_langevin_dot, &rl_stepop_langevin_dot_obabo,
                                                  &rl_stepop_mc_barostat, &rl_stepop_crescale};
  for (size_t k = 0; name && k < sizeof all / sizeof *all; k++)
    if (!strcmp(all[k]->name, name)) return all[k];
  return NULL;
}

const rl_stepop_type *rl_stepop_for_thermostat(rl_thermostat t)
{
  switch (t) {
  case RL_THERMO_ISOKINETIC: return &rl_stepop_isokinetic;
  case RL_THERMO_BUSSI: return &rl_stepop_bussi;
  case RL_THERMO_LANGEVIN: return &rl_stepop_langevin;
  case RL_THERMO_LANGEVIN_DOT: return &rl_stepop_langevin_dot;
  case RL_THERMO_LANGEVIN_DOT_OBABO: return &rl_stepop_langevin_dot_obabo;
  default: return NULL;
  }
}

int rl_thermostat_check_T0(const rl_stepop_type *T, const rl_thermostat_params *tp)
{
  if (!(tp->T0 > 0.0) || !isfinite(tp->T0))
    return rl_error(RL_EINVAL, "%s needs a positive target temperature, got %g", T->label, tp->T0);
  return RL_OK;
}

int rl_thermostat_check_tau(const rl_stepop_type *T, const rl_thermostat_params *tp, const char *what)
{
  if (!(tp->tau > 0.0) || !isfinite(tp->tau))
    return rl_error(RL_EINVAL, "%s needs a positive %s tau, got %g", T->label, what, tp->tau);
  return RL_OK;
}

int rl_thermostat_rng_alloc(rl_stepop *op)
{
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  if (!r) return rl_error(RL_ENOMEM, "%s: out of memory", op->type->label);
  gsl_rng_set(r, ((const rl_thermostat_params *)op->par)->seed);
  op->state = r;
  return RL_OK;
}

void rl_thermostat_rng_free(rl_stepop *op) { gsl_rng_free(op->state); }

void *rl_thermostat_rng_state(rl_stepop *op, size_t *size)
{
  *size = gsl_rng_size(op->state);
  return gsl_rng_state(op->state);
}

size_t rl_stepop_save(const rl_stepop *op, void *buf) { return op && op->type->save ? op->type->save(op, buf) : 0; }

int rl_stepop_load(rl_stepop *op, const void *buf, size_t size)
{
  if (op && op->type->load) return op->type->load(op, buf, size);
  if (size) return rl_error(RL_EINVAL, "the %s keeps no state, but %zu bytes were given", op ? op->type->label : "(null)", size);
  return RL_OK;
}
