/* Pieces shared by the built-in thermostats (integrators/stepops/): their parameter checks and
 * their random stream.  Internal header. */
#ifndef ROTLEAP_STEPOPS_THERMOSTAT_H
#define ROTLEAP_STEPOPS_THERMOSTAT_H

#include "rotleap/stepops.h"
#include "../paths/path.h"

/* RL_EINVAL unless T0 is positive and finite ("<label> needs a positive target temperature"). */
int rl_thermostat_check_T0(const rl_stepop_type *T, const rl_thermostat_params *tp);
/* RL_EINVAL unless tau is positive and finite; `what` names it ("relaxation time"). */
int rl_thermostat_check_tau(const rl_stepop_type *T, const rl_thermostat_params *tp, const char *what);
/* The random stream of the stochastic thermostats: a GSL mt19937 seeded with tp->seed in
 * op->state (alloc), freed (free), and its state for checkpoints (rng_state). */
int rl_thermostat_rng_alloc(rl_stepop *op);
void rl_thermostat_rng_free(rl_stepop *op);
void *rl_thermostat_rng_state(rl_stepop *op, size_t *size);

#endif
