/* Langevin dynamics in the middle of the drift: the O of BAOAB (Leimkuhler & Matthews, Appl.
 * Math. Res. Express 2013, 34; OpenMM's LangevinMiddleIntegrator), over the whole step h, between
 * the two half drifts and half rotations the core makes because this operator has a
 * RL_STEP_MID_DRIFT hook.  Every component of v and of the body-frame angular momentum relaxes as
 * an Ornstein-Uhlenbeck process with friction gamma = 1/tau, x <- c x + sqrt((1 - c^2) m kT) xi
 * with c = exp(-h gamma) (m the mass or the principal moment), which leaves the Maxwell-Boltzmann
 * law exactly invariant.  A matrix body's l is taken to its body frame by the half-rotated A; an
 * axis body (linear, dipole) has two equal moments and no spin about rho, so its noise is drawn
 * in 3-D and projected perpendicular to rho.  The noise moves the centre of mass
 * (RL_STEPOP_THERMAL_COM).  docs/integrators.md, "Langevin in the middle of the drift". */
#include "thermostat.h"
#include "rotleap/error.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>

static int check(const void *par, const rl_system *sys, const rl_integrator_params *p)
{
  (void)sys; (void)p;
  int st = rl_thermostat_check_T0(&rl_stepop_langevin, par);
  return st ? st : rl_thermostat_check_tau(&rl_stepop_langevin, par, "friction time");
}

/* The exact Ornstein-Uhlenbeck step over h of every component of v (friction time tau_t) and of
 * the body-frame angular momentum (tau_r, each principal axis), the bodies' frames those the
 * state holds.  on_step: v and l are first taken to the on-step v(t) = v(t-h/2) + h/2 f/m,
 * l(t) = l(t-h/2) + h/2 k and back by the same half kick after, so that the core's kick makes
 * B(h/2) O(h) B(h/2).  K[0], K[1]: translational and rotational kinetic energy before and after
 * the update; the energy taken out goes to the account.  Reports sqrt(K'/K) in beta, beta_rot,
 * and returns the kinetic energies before the update in Kin. */
static void ou_step(rl_stepop *op, rl_stepop_ctx *c, double tau_t, double tau_r, int on_step, double Kin[2])
{
  rl_system *s = c->sys;
  const rl_thermostat_params *tp = op->par;
  gsl_rng *r = op->state;
  const double h = c->p->h, hh = on_step ? 0.5 * h : 0.0;
  const double ct = exp(-h / tau_t), snt = sqrt(-expm1(-2.0 * h / tau_t));
  const double cr = exp(-h / tau_r), snr = sqrt(-expm1(-2.0 * h / tau_r));
  const double kT = s->kB * tp->T0;
  double K[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    const rl_family *fam = rl_family_for(sp->kind, c->p->force_general);
    const double sv = snt * sqrt(kT / sp->mass), w = hh / sp->mass;
    double sl[3];
    for (int a = 0; a < 3; a++) sl[a] = snr * sqrt(kT * sp->J[a]);
    for (int b = 0; b < sp->count; b++) {
      double *v = s->v[sp->first + b];
      const double *f = c->forces->f[sp->first + b];
      if (on_step)
        for (int a = 0; a < 3; a++) v[a] += w * f[a];
      K[0][0] += 0.5 * sp->mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      for (int a = 0; a < 3; a++) v[a] = ct * v[a] + sv * gsl_ran_gaussian_ziggurat(r, 1.0);
      K[0][1] += 0.5 * sp->mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      if (on_step)
        for (int a = 0; a < 3; a++) v[a] -= w * f[a];
      if (sp->rot_off < 0) continue;
      double *l = s->l[sp->rot_off + b];
      const double *kk = c->forces->k[sp->rot_off + b];
      if (on_step)
        for (int a = 0; a < 3; a++) l[a] += hh * kk[a];
      K[1][0] += fam->ke_rot(sp, s, b, l);
      if (sp->mat_off >= 0) {
        const double *A = s->A[sp->mat_off + b];
        double L[3];
        for (int a = 0; a < 3; a++)
          L[a] = cr * (A[3 * a] * l[0] + A[3 * a + 1] * l[1] + A[3 * a + 2] * l[2]) +
                 sl[a] * gsl_ran_gaussian_ziggurat(r, 1.0);
        for (int a = 0; a < 3; a++) l[a] = A[a] * L[0] + A[3 + a] * L[1] + A[6 + a] * L[2];
      } else {
        double xi[3];
        for (int a = 0; a < 3; a++) xi[a] = gsl_ran_gaussian_ziggurat(r, 1.0);
        rl_project_out(xi, s->rho[sp->axis_off + b]);
        for (int a = 0; a < 3; a++) l[a] = cr * l[a] + sl[0] * xi[a];
      }
      K[1][1] += fam->ke_rot(sp, s, b, l);
      if (on_step)
        for (int a = 0; a < 3; a++) l[a] -= hh * kk[a];
    }
  }
  op->work += (K[0][0] - K[0][1]) + (K[1][0] - K[1][1]);
  rl_step_info *info = c->info;
  info->beta = K[0][0] > 0.0 ? sqrt(K[0][1] / K[0][0]) : 1.0;
  info->beta_rot = K[1][0] > 0.0 ? sqrt(K[1][1] / K[1][0]) : 1.0;
  Kin[0] = K[0][0];
  Kin[1] = K[1][0];
}

/* Reports as t_trans_mid, t_rot_mid the temperatures of v, l at the middle of the drift, before
 * the update, whose law BAOAB makes exactly Maxwell's for a harmonic mode. */
static void report_mid(rl_stepop_ctx *c, const double K[2])
{
  c->info->t_trans_mid = c->dof_trans > 0 ? 2.0 * K[0] / (c->dof_trans * c->sys->kB) : 0.0;
  c->info->t_rot_mid = c->dof_rot > 0 ? 2.0 * K[1] / (c->dof_rot * c->sys->kB) : 0.0;
}

static int mid_drift(rl_stepop *op, rl_stepop_ctx *c)
{
  const double tau = ((const rl_thermostat_params *)op->par)->tau;
  double K[2];
  ou_step(op, c, tau, tau, 0, K);
  report_mid(c, K);
  return RL_OK;
}

static const rl_stepop_param params[] = {
    {"T0", "temperature", "target temperature"},
    {"tau", "time", "friction time 1/gamma (GROMACS's tau-t for sd, LAMMPS's damp)"},
    {"seed", "", "GSL mt19937 seed"},
    {NULL, NULL, NULL}};

const rl_stepop_type rl_stepop_langevin = {
    .name = "langevin",
    .label = "Langevin thermostat",
    .reference = "B. Leimkuhler and C. Matthews, Appl. Math. Res. Express 2013, 34 (BAOAB)",
    .params = params,
    .params_size = sizeof(rl_thermostat_params),
    .flags = RL_STEPOP_HOLDS_TEMPERATURE | RL_STEPOP_THERMAL_COM,
    .check = check,
    .alloc = rl_thermostat_rng_alloc,
    .free = rl_thermostat_rng_free,
    .hook = {[RL_STEP_MID_DRIFT] = mid_drift},
    .rng_state = rl_thermostat_rng_state,
};

/* ------------------------------------------------ Davidchack, Ouldridge & Tretyakov (DOT) */

static double dot_tau_rot(const rl_thermostat_params *tp) { return tp->tau_rot > 0.0 ? tp->tau_rot : tp->tau; }

static int dot_check(const rl_stepop_type *T, const void *par)
{
  const rl_thermostat_params *tp = par;
  int st = rl_thermostat_check_T0(T, tp);
  if (!st) st = rl_thermostat_check_tau(T, tp, "translational friction time");
  if (!st && (!(tp->tau_rot >= 0.0) || !isfinite(tp->tau_rot)))
    return rl_error(RL_EINVAL, "%s needs a positive rotational friction time tau_rot (0: tau), got %g", T->label, tp->tau_rot);
  return st;
}

static int dot_b_check(const void *par, const rl_system *sys, const rl_integrator_params *p)
{
  (void)sys; (void)p;
  return dot_check(&rl_stepop_langevin_dot, par);
}

static int dot_a_check(const void *par, const rl_system *sys, const rl_integrator_params *p)
{
  (void)sys; (void)p;
  return dot_check(&rl_stepop_langevin_dot_obabo, par);
}

static int dot_mid_drift(rl_stepop *op, rl_stepop_ctx *c)
{
  const rl_thermostat_params *tp = op->par;
  double K[2];
  ou_step(op, c, tp->tau, dot_tau_rot(tp), 0, K);
  report_mid(c, K);
  return RL_OK;
}

/* At RL_STEP_BEFORE_KICK: the O of O B A B O at the on-step values, between the two half kicks
 * the core's full kick then completes. */
static int dot_mid_kick(rl_stepop *op, rl_stepop_ctx *c)
{
  const rl_thermostat_params *tp = op->par;
  double K[2];
  ou_step(op, c, tp->tau, dot_tau_rot(tp), 1, K);
  return RL_OK;
}

static const rl_stepop_param dot_params[] = {
    {"T0", "temperature", "target temperature"},
    {"tau", "time", "translational friction time 1/gamma"},
    {"tau_rot", "time", "rotational friction time 1/gamma_r, the same on each principal axis (0: tau)"},
    {"seed", "", "GSL mt19937 seed"},
    {NULL, NULL, NULL}};

#define DOT_REFERENCE                                                                            \
  "R. L. Davidchack, T. E. Ouldridge and M. V. Tretyakov, J. Chem. Phys. 142, 144114 (2015) and " \
  "147, 224103 (2017); R. L. Davidchack, R. Handel and M. V. Tretyakov, J. Chem. Phys. 130, 234101 (2009)"

const rl_stepop_type rl_stepop_langevin_dot = {
    .name = "langevin-dot",
    .label = "Langevin-DOT thermostat",
    .reference = DOT_REFERENCE,
    .params = dot_params,
    .params_size = sizeof(rl_thermostat_params),
    .flags = RL_STEPOP_HOLDS_TEMPERATURE | RL_STEPOP_THERMAL_COM,
    .check = dot_b_check,
    .alloc = rl_thermostat_rng_alloc,
    .free = rl_thermostat_rng_free,
    .hook = {[RL_STEP_MID_DRIFT] = dot_mid_drift},
    .rng_state = rl_thermostat_rng_state,
};

const rl_stepop_type rl_stepop_langevin_dot_obabo = {
    .name = "langevin-dot-obabo",
    .label = "Langevin-DOT thermostat (O B A B O)",
    .reference = DOT_REFERENCE,
    .params = dot_params,
    .params_size = sizeof(rl_thermostat_params),
    .flags = RL_STEPOP_HOLDS_TEMPERATURE | RL_STEPOP_THERMAL_COM,
    .check = dot_a_check,
    .alloc = rl_thermostat_rng_alloc,
    .free = rl_thermostat_rng_free,
    .hook = {[RL_STEP_BEFORE_KICK] = dot_mid_kick},
    .rng_state = rl_thermostat_rng_state,
};
