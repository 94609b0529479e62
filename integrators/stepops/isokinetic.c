/* The paper's isokinetic thermostat (eqs. 17-18, section III.B), as published.  Before the kick
 * it takes beta = sqrt(T0/T(t)) of the on-step temperature (eqs. 9, 12) and hands it to the core,
 * whose kick is then eqs. 17-18: v(t+h/2) = (2 beta - 1) v(t) + h/2 f/m, likewise l, which makes
 * the on-step values beta v(t), beta l(t) and T(t) = T0.  The energy (1 - beta^2) K(t) it takes
 * out goes to its account.  The scheme's undamped period-2 mode is docs/integrators.md's "The
 * isokinetic scheme's period-2 mode". */
#include "thermostat.h"
#include "rotleap/error.h"

#include <math.h>

static int check(const void *par, const rl_system *sys, const rl_integrator_params *p)
{
  (void)sys; (void)p;
  return rl_thermostat_check_T0(&rl_stepop_isokinetic, par);
}

/* beta of eqs. 17-18 for the on-step temperature in c->info (1 at T = 0). */
static double beta_of(const rl_stepop *op, const rl_stepop_ctx *c)
{
  const double T = c->info->temperature;
  return T > 0.0 ? sqrt(((const rl_thermostat_params *)op->par)->T0 / T) : 1.0;
}

static int before_kick(rl_stepop *op, rl_stepop_ctx *c)
{
  rl_step_info *info = c->info;
  const double beta = beta_of(op, c);
  /* eqs. 17-18 carry (2 beta - 1) v forward: for beta < 1/2 that reverses the velocities, and
   * the scheme (meant to hold T near T0) no longer describes dynamics */
  if (beta < 0.5)
    return rl_error(RL_EINVAL, "isokinetic thermostat at step %ld (t = %g): on-step temperature %g "
                    "is more than 4 T0 = %g; eqs. 17-18 would reverse the velocities. Relax the "
                    "start first (Bussi with a short tau) or use a smaller time step", c->step,
                    c->t, info->temperature, 4.0 * ((const rl_thermostat_params *)op->par)->T0);
  info->beta = info->beta_rot = beta;
  c->kick_beta = beta;
  op->work += (1.0 - beta * beta) * (c->K[0] + c->K[1]);
  return RL_OK;
}

static void observe(const rl_stepop *op, rl_stepop_ctx *c)
{
  c->info->beta = c->info->beta_rot = beta_of(op, c);
}

static const rl_stepop_param params[] = {
    {"T0", "temperature", "target on-step temperature"},
    {NULL, NULL, NULL}};

const rl_stepop_type rl_stepop_isokinetic = {
    .name = "isokinetic",
    .label = "isokinetic thermostat",
    .reference = "I. P. Omelyan, Mol. Simul. 22, 213 (1999), eqs. 17-18 (section III.B); D. Fincham, Mol. Simul. 8, 165 (1992)",
    .params = params,
    .params_size = sizeof(rl_thermostat_params),
    .flags = RL_STEPOP_HOLDS_TEMPERATURE | RL_STEPOP_SCALES_KICK,
    .check = check,
    .hook = {[RL_STEP_BEFORE_KICK] = before_kick},
    .observe = observe,
};
