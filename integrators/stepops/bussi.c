/* Canonical stochastic velocity rescaling (Bussi, Donadio & Parrinello, J. Chem. Phys. 126,
 * 014101 (2007)) after the kick: v(t+h/2) and l(t+h/2) are multiplied by alpha, alpha^2 drawn
 * for their kinetic energy K (rotational part from l(t+h/2) with A(t)), as leapfrog codes apply
 * it.  Scaling the propagated half-step values -- not the interpolated on-step ones through
 * eqs. 17-18, which would scale what is carried forward by 2 alpha - 1 and double the energy
 * fluctuation -- keeps the stationary law canonical.  With RL_THERMO_GROUPS_TRANS_ROT the
 * translational and rotational parts get one alpha each, drawn for their own K and dof (a group
 * with no dof or no kinetic energy is left alone); with RL_THERMO_GROUPS_ALL one alpha for the
 * sum (docs/integrators.md, "Bussi thermostat groups").  The energy taken out, sum (1 - alpha^2)
 * K, goes to the operator's account. */
#include "thermostat.h"
#include "rotleap/error.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>

static int check(const void *par, const rl_system *sys, const rl_integrator_params *p)
{
  (void)sys; (void)p;
  const rl_thermostat_params *tp = par;
  int st = rl_thermostat_check_T0(&rl_stepop_bussi, tp);
  if (st) return st;
  if (!rl_thermo_groups_name(tp->groups))
    return rl_error(RL_EINVAL, "unknown Bussi thermostat groups %d", (int)tp->groups);
  return rl_thermostat_check_tau(&rl_stepop_bussi, tp, "relaxation time");
}

/* Bussi et al. 2007, eq. (A7): the ratio K'/K of the new to the current kinetic energy for a
 * relaxation over dt/tau = x towards Kbar = g kT/2 with g degrees of freedom.  The sum of g - 1
 * squared normals is drawn as one chi-squared variate. */
static double bussi_ratio(gsl_rng *r, double K, double Kbar, int g, double x)
{
  double c = exp(-x), r1 = gsl_ran_gaussian(r, 1.0);
  double sum = g > 1 ? gsl_ran_chisq(r, g - 1.0) : 0.0;
  double f = Kbar / (g * K);
  double a2 = c + (1.0 - c) * (r1 * r1 + sum) * f + 2.0 * r1 * sqrt(c * (1.0 - c) * f);
  return a2 > 0.0 ? a2 : 0.0;
}

/* c->K: the kick's kinetic energies; the alphas are reported in beta (v) and beta_rot (l). */
static int after_kick(rl_stepop *op, rl_stepop_ctx *c)
{
  rl_system *s = c->sys;
  const rl_thermostat_params *tp = op->par;
  gsl_rng *r = op->state;
  const double *K = c->K;
  const int g[2] = {c->dof_trans, c->dof_rot};
  const double kT = s->kB * tp->T0, x = c->p->h / tp->tau;
  double a2[2] = {1.0, 1.0};
  if (tp->groups == RL_THERMO_GROUPS_ALL) {
    double Ks = K[0] + K[1];
    int gs = g[0] + g[1];
    if (Ks > 0.0 && gs > 0) a2[0] = a2[1] = bussi_ratio(r, Ks, 0.5 * gs * kT, gs, x);
  } else {
    for (int j = 0; j < 2; j++)
      if (K[j] > 0.0 && g[j] > 0) a2[j] = bussi_ratio(r, K[j], 0.5 * g[j] * kT, g[j], x);
  }
  const double a[2] = {sqrt(a2[0]), sqrt(a2[1])};
  for (int i = 0; i < s->n; i++)
    for (int k = 0; k < 3; k++) s->v[i][k] *= a[0];
  for (int i = 0; i < s->nrot; i++)
    for (int k = 0; k < 3; k++) s->l[i][k] *= a[1];
  op->work += (1.0 - a2[0]) * K[0] + (1.0 - a2[1]) * K[1];
  c->K[0] *= a2[0];
  c->K[1] *= a2[1];
  c->info->beta = a[0];
  c->info->beta_rot = a[1];
  return RL_OK;
}

static const rl_stepop_param params[] = {
    {"T0", "temperature", "target temperature"},
    {"tau", "time", "relaxation time of the kinetic energy (the velocities relax over 2 tau)"},
    {"seed", "", "GSL mt19937 seed"},
    {"groups", "", "trans-rot (one thermostat each) or all (one for both)"},
    {NULL, NULL, NULL}};

const rl_stepop_type rl_stepop_bussi = {
    .name = "bussi",
    .label = "Bussi thermostat",
    .reference = "G. Bussi, D. Donadio and M. Parrinello, J. Chem. Phys. 126, 014101 (2007)",
    .params = params,
    .params_size = sizeof(rl_thermostat_params),
    .flags = RL_STEPOP_HOLDS_TEMPERATURE,
    .check = check,
    .alloc = rl_thermostat_rng_alloc,
    .free = rl_thermostat_rng_free,
    .hook = {[RL_STEP_AFTER_KICK] = after_kick},
    .rng_state = rl_thermostat_rng_state,
};
