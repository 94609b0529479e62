/* The barostats as step operators (stepops.h): a Monte Carlo barostat at the end of the step
 * (OpenMM's MonteCarloBarostat and MonteCarloAnisotropicBarostat) and stochastic cell rescaling
 * after the drift (Bernetti & Bussi, J. Chem. Phys. 153, 114107 (2020); GROMACS's C-rescale).
 * Both scale the centres of mass only: the molecules stay rigid and keep their orientations.
 * The cell changes through rl_system_set_box, which the force terms follow (terms.h). */
#include "thermostat.h"
#include "rotleap/error.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  gsl_rng *rng;
  double trial[3];              /* Monte Carlo: the trial size of dV, per edge (isotropic: [0])   */
  long attempted[3], accepted[3]; /* since the last adaptation                                   */
  long total_attempted[3], total_accepted[3];
  int pending;                  /* C-rescale: a move of this step waits for the virial after it
                                   (1 isotropic, 2 semi-isotropic)                                  */
  double trW0, lnmu;            /* its virial trace before and ln mu                              */
  double W0[3], lnmu3[3];       /* semi-isotropic: the virial's diagonal before, ln mu per edge    */
  int n;                        /* bodies of the saved centres                                    */
  double (*r)[3];               /* Monte Carlo: the centres before a trial                        */
} baro_state;

static int check(const void *par, const rl_system *sys, const rl_integrator_params *p, const rl_stepop_type *T)
{
  const rl_barostat_params *b = par;
  (void)p;
  if (!rl_system_periodic(sys)) return rl_error(RL_EINVAL, "the %s needs a periodic box", T->label);
  if (!isfinite(b->P0)) return rl_error(RL_EINVAL, "the %s needs a finite pressure, got %g", T->label, b->P0);
  if (!(b->T0 > 0.0) || !isfinite(b->T0))
    return rl_error(RL_EINVAL, "the %s needs a positive temperature, got %g", T->label, b->T0);
  if (b->interval < 1) return rl_error(RL_EINVAL, "the %s needs an interval >= 1 step, got %ld", T->label, b->interval);
  if (!(b->min_edge >= 0.0) || !isfinite(b->min_edge))
    return rl_error(RL_EINVAL, "the %s's smallest box edge %g must be >= 0", T->label, b->min_edge);
  if (b->coupling != RL_BARO_ISOTROPIC && b->coupling != RL_BARO_ANISOTROPIC && b->coupling != RL_BARO_SEMIISOTROPIC)
    return rl_error(RL_EINVAL, "the %s: unknown coupling %d", T->label, (int)b->coupling);
  return RL_OK;
}

static int mc_check(const void *par, const rl_system *sys, const rl_integrator_params *p)
{
  const rl_barostat_params *b = par;
  int st = check(par, sys, p, &rl_stepop_mc_barostat);
  if (!st && b->coupling == RL_BARO_SEMIISOTROPIC)
    st = rl_error(RL_EINVAL, "the %s is isotropic or anisotropic (semi-isotropic coupling: C-rescale)",
                  rl_stepop_mc_barostat.label);
  if (!st && (!(b->trial >= 0.0) || !(b->trial < 1.0)))
    st = rl_error(RL_EINVAL, "the %s's first trial size %g must lie in [0, 1) (a fraction of V; 0: 0.01)",
                  rl_stepop_mc_barostat.label, b->trial);
  return st;
}

static int cr_check(const void *par, const rl_system *sys, const rl_integrator_params *p)
{
  const rl_barostat_params *b = par;
  const rl_stepop_type *T = &rl_stepop_crescale;
  int st = check(par, sys, p, T);
  if (st) return st;
  if (!(b->tau_p > 0.0) || !isfinite(b->tau_p))
    return rl_error(RL_EINVAL, "the %s needs a positive coupling time tau_p, got %g", T->label, b->tau_p);
  if (!(b->compressibility > 0.0) || !isfinite(b->compressibility))
    return rl_error(RL_EINVAL, "the %s needs a positive compressibility, got %g", T->label, b->compressibility);
  if (b->coupling == RL_BARO_ANISOTROPIC)
    return rl_error(RL_EINVAL, "the %s is isotropic or semi-isotropic (anisotropic coupling: the Monte Carlo barostat)",
                    T->label);
  const long ev = p->energy_every > 1 ? p->energy_every : 1;
  if (b->interval % ev)
    return rl_error(RL_EINVAL, "the %s acts every %ld steps, not a multiple of the energy cadence %ld: it needs "
                    "the virial on its steps", T->label, b->interval, ev);
  return RL_OK;
}

static int baro_alloc(rl_stepop *op)
{
  baro_state *b = calloc(1, sizeof *b);
  if (b) b->rng = gsl_rng_alloc(gsl_rng_mt19937);
  if (!b || !b->rng) {
    free(b);
    return rl_error(RL_ENOMEM, "%s: out of memory", op->type->label);
  }
  gsl_rng_set(b->rng, ((const rl_barostat_params *)op->par)->seed);
  op->state = b;
  return RL_OK;
}

static void baro_free(rl_stepop *op)
{
  baro_state *b = op->state;
  if (!b) return;
  gsl_rng_free(b->rng);
  free(b->r);
  free(b);
}

/* ---------------------------------------------------------------- checkpoint state */

#define SAVE_MAGIC 0x726c6261726f3031ull /* "rlbaro01" */
enum { SAVE_DOUBLES = 3, SAVE_LONGS = 12 };

static size_t baro_save(const rl_stepop *op, void *buf)
{
  const baro_state *b = op->state;
  const size_t nr = gsl_rng_size(b->rng);
  const size_t size = 8 + 8 * SAVE_DOUBLES + 8 * SAVE_LONGS + nr;
  if (!buf) return size;
  unsigned char *p = buf;
  const uint64_t magic = SAVE_MAGIC;
  memcpy(p, &magic, 8);
  memcpy(p + 8, b->trial, 8 * SAVE_DOUBLES);
  int64_t l[SAVE_LONGS];
  for (int k = 0; k < 3; k++) {
    l[k] = b->attempted[k];
    l[3 + k] = b->accepted[k];
    l[6 + k] = b->total_attempted[k];
    l[9 + k] = b->total_accepted[k];
  }
  memcpy(p + 8 + 8 * SAVE_DOUBLES, l, sizeof l);
  memcpy(p + 8 + 8 * SAVE_DOUBLES + 8 * SAVE_LONGS, gsl_rng_state(b->rng), nr);
  return size;
}

static int baro_load(rl_stepop *op, const void *buf, size_t size)
{
  baro_state *b = op->state;
  const unsigned char *p = buf;
  uint64_t magic;
  if (size != baro_save(op, NULL) || (memcpy(&magic, p, 8), magic != SAVE_MAGIC))
    return rl_error(RL_EINVAL, "the %s's saved state has %zu bytes, not the %zu it writes", op->type->label, size,
                    baro_save(op, NULL));
  double trial[3];
  int64_t l[SAVE_LONGS];
  memcpy(trial, p + 8, sizeof trial);
  memcpy(l, p + 8 + 8 * SAVE_DOUBLES, sizeof l);
  for (int k = 0; k < 3; k++)
    if (!(trial[k] >= 0.0) || !isfinite(trial[k]))
      return rl_error(RL_EINVAL, "the %s's saved trial size %g is out of range", op->type->label, trial[k]);
  for (int k = 0; k < SAVE_LONGS; k++)
    if (l[k] < 0) return rl_error(RL_EINVAL, "the %s's saved counts are negative", op->type->label);
  memcpy(b->trial, trial, sizeof trial);
  for (int k = 0; k < 3; k++) {
    b->attempted[k] = (long)l[k];
    b->accepted[k] = (long)l[3 + k];
    b->total_attempted[k] = (long)l[6 + k];
    b->total_accepted[k] = (long)l[9 + k];
  }
  memcpy(gsl_rng_state(b->rng), p + 8 + 8 * SAVE_DOUBLES + 8 * SAVE_LONGS, gsl_rng_size(b->rng));
  return RL_OK;
}

int rl_barostat_stats_of(const rl_stepop *op, rl_barostat_stats *out)
{
  if (!op || !out || (op->type != &rl_stepop_mc_barostat && op->type != &rl_stepop_crescale))
    return rl_error(RL_EINVAL, "rl_barostat_stats_of: not a barostat");
  const baro_state *b = op->state;
  for (int k = 0; k < 3; k++) {
    out->attempted[k] = b->total_attempted[k];
    out->accepted[k] = b->total_accepted[k];
    out->trial[k] = b->trial[k];
  }
  return RL_OK;
}

/* The new edges L' checked against the smallest the run allows: RL_EINVAL naming the step. */
static int check_edges(const rl_stepop *op, const rl_stepop_ctx *c, const double L[3], const double Ln[3])
{
  const rl_barostat_params *bp = op->par;
  for (int k = 0; k < 3; k++)
    if (!(Ln[k] >= bp->min_edge) || !isfinite(Ln[k]))
      return rl_error(RL_EINVAL, "the %s would shrink the box edge L%c from %g to %g at step %ld, below %g "
                      "(twice the cutoff: the pair term cannot follow): the system is collapsing (a pressure too "
                      "high for this state, or too few molecules for the cutoff)", op->type->label, "xyz"[k],
                      L[k], Ln[k], c->step + 1, bp->min_edge);
  return RL_OK;
}

/* ------------------------------------------------------------------------ Monte Carlo */

/* The acceptance exponent w / kT of a move V -> Vn that changes the potential by dU. */
static double mc_exponent(double dU, double P0, double V, double Vn, int n, double kT)
{
  return (dU + P0 * (Vn - V) - n * kT * log(Vn / V)) / kT;
}

/* The trial to the box Ln (centres scaled by f) from L, whose energy is U: accepted, or the
 * centres, box and computation (forces, energies, virial: rl_stepop_forces_keep) put back as
 * they were, without computing them again (for a provider that cannot keep its report: computed
 * again, with the energy if ev).  The pair list stays through the trial and its return when its
 * skin allows (pairlist.h); else the trial builds it, and that list serves the old box too. */
static int mc_trial(rl_stepop *op, rl_stepop_ctx *c, const double L[3], const double Ln[3], const double f[3],
                    double U, int ev, int axis)
{
  const rl_barostat_params *bp = op->par;
  baro_state *b = op->state;
  rl_system *s = c->sys;
  const int n = s->n;
  int st;
  memcpy(b->r, s->r, sizeof *b->r * (size_t)n);
  if ((st = rl_stepop_forces_keep(c))) return st;
  for (int i = 0; i < n; i++)
    for (int k = 0; k < 3; k++) s->r[i][k] *= f[k];
  if ((st = rl_system_set_box(s, Ln)) || (st = rl_stepop_forces(c, 1))) return st;
  const double kT = s->kB * bp->T0, dU = c->forces->energy - U;
  const double w = mc_exponent(dU, bp->P0, L[0] * L[1] * L[2], Ln[0] * Ln[1] * Ln[2], n, kT);
  if (w > 0.0 && gsl_rng_uniform(b->rng) > exp(-w)) { /* rejected */
    memcpy(s->r, b->r, sizeof *b->r * (size_t)n);
    return (st = rl_system_set_box(s, L)) ? st : rl_stepop_forces_put_back(c, ev);
  }
  b->accepted[axis]++;
  b->total_accepted[axis]++;
  op->work -= dU;
  return RL_OK;
}

static int mc_end(rl_stepop *op, rl_stepop_ctx *c)
{
  const rl_barostat_params *bp = op->par;
  baro_state *b = op->state;
  rl_system *s = c->sys;
  if ((c->step + 1) % bp->interval) return RL_OK;
  const int n = s->n;
  if (b->n != n) {
    free(b->r);
    b->r = malloc(sizeof *b->r * (size_t)(n > 0 ? n : 1));
    if (!b->r) { b->n = 0; return rl_error(RL_ENOMEM, "%s: out of memory", op->type->label); }
    b->n = n;
  }
  int st;
  const int ev = !c->forces->forces_only; /* the step's own cadence, restored on a rejection */
  if (!ev && (st = rl_stepop_forces(c, 1))) return st;
  const double U = c->forces->energy;
  double L[3], Ln[3];
  rl_system_box(s, L);
  const double V = L[0] * L[1] * L[2];
  const int aniso = bp->coupling == RL_BARO_ANISOTROPIC;
  const int axis = aniso ? (int)fmin(2.0, floor(3.0 * gsl_rng_uniform(b->rng))) : 0;
  if (!(b->trial[axis] > 0.0)) b->trial[axis] = (bp->trial > 0.0 ? bp->trial : 0.01) * V;
  const double dV = b->trial[axis] * 2.0 * (gsl_rng_uniform(b->rng) - 0.5), Vn = V + dV;
  double f[3] = {1.0, 1.0, 1.0};
  if (aniso) f[axis] = Vn / V;
  else f[0] = f[1] = f[2] = cbrt(Vn / V);
  for (int k = 0; k < 3; k++) Ln[k] = L[k] * f[k];
  b->attempted[axis]++;
  b->total_attempted[axis]++;
  if (Vn > 0.0) { /* a move to V' <= 0 is rejected (the law has no weight there) */
    if ((st = check_edges(op, c, L, Ln)) || (st = mc_trial(op, c, L, Ln, f, U, ev, axis))) return st;
  } else if (!ev && (st = rl_stepop_forces(c, 0))) return st;
  if (b->attempted[axis] >= 10) { /* OpenMM's adaptation of the trial size */
    if (b->accepted[axis] < 0.25 * b->attempted[axis]) b->trial[axis] /= 1.1;
    else if (b->accepted[axis] > 0.75 * b->attempted[axis]) b->trial[axis] = fmin(b->trial[axis] * 1.1, 0.3 * V);
    if (b->accepted[axis] < 0.25 * b->attempted[axis] || b->accepted[axis] > 0.75 * b->attempted[axis])
      b->attempted[axis] = b->accepted[axis] = 0;
  }
  return RL_OK;
}

/* -------------------------------------------------------------- stochastic cell rescaling */

/* Scale the centres by mu[k] and v(t+h/2) by 1/mu[k] per edge: the translational kinetic energy
 * before (*K0) and after (*K1). */
static void cr_scale(rl_system *s, const double mu[3], double *K0, double *K1)
{
  *K0 = *K1 = 0.0;
  for (int q = 0; q < s->nspecies; q++) {
    const rl_species *sp = &s->sp[q];
    double k0 = 0.0, k1 = 0.0;
    for (int i = sp->first; i < sp->first + sp->count; i++) {
      double *r = s->r[i], *v = s->v[i];
      k0 += v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
      for (int k = 0; k < 3; k++) {
        r[k] *= mu[k];
        v[k] /= mu[k];
      }
      k1 += v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    }
    *K0 += 0.5 * sp->mass * k0;
    *K1 += 0.5 * sp->mass * k1;
  }
}

/* Semi-isotropic: a = ln(Lx Ly) and z = ln Lz, each with its own noise,
 *   da = -(2x/3)(P0 - P_xy) + sqrt(2 kT (2x/3)/V) xi_1,  dz = -(x/3)(P0 - P_zz) + sqrt(2 kT (x/3)/V) xi_2,
 * P_xy = (2K/3 + (W_xx + W_yy)/2)/V, P_zz = (2K/3 + W_zz)/V, x = kappa dt / tau_p: ln V = a + z then
 * moves with the isotropic drift x (P - P0) and noise 2 kT x / V, so its law is the isotropic
 * one; mu_x = mu_y = exp(da/2), mu_z = exp(dz). */
static int cr_semi(rl_stepop *op, rl_stepop_ctx *c, const double L[3], double V, double kT, double x)
{
  const rl_barostat_params *bp = op->par;
  baro_state *b = op->state;
  rl_system *s = c->sys;
  const double *W = c->forces->virial, kin = 2.0 * c->info->ke_trans / 3.0;
  const double Pxy = (kin + 0.5 * (W[0] + W[4])) / V, Pzz = (kin + W[8]) / V;
  const double xa = 2.0 * x / 3.0, xz = x / 3.0;
  const double da = -xa * (bp->P0 - Pxy) + sqrt(2.0 * kT * xa / V) * gsl_ran_gaussian(b->rng, 1.0);
  const double dz = -xz * (bp->P0 - Pzz) + sqrt(2.0 * kT * xz / V) * gsl_ran_gaussian(b->rng, 1.0);
  const double mu[3] = {exp(0.5 * da), exp(0.5 * da), exp(dz)};
  double Ln[3], K0, K1;
  for (int k = 0; k < 3; k++) Ln[k] = L[k] * mu[k];
  int st = check_edges(op, c, L, Ln);
  if (st) return st;
  cr_scale(s, mu, &K0, &K1);
  if ((st = rl_system_set_box(s, Ln))) return st;
  double dU = 0.0; /* to first order; completed to the trapezoid in cr_end */
  for (int k = 0; k < 3; k++) {
    b->W0[k] = W[4 * k];
    b->lnmu3[k] = log(mu[k]);
    dU -= W[4 * k] * b->lnmu3[k];
  }
  op->work -= (K1 - K0) + dU;
  b->pending = 2;
  b->total_attempted[0]++;
  b->total_accepted[0]++;
  return RL_OK;
}

static int cr_after_drift(rl_stepop *op, rl_stepop_ctx *c)
{
  const rl_barostat_params *bp = op->par;
  baro_state *b = op->state;
  rl_system *s = c->sys;
  if (c->step % bp->interval) return RL_OK;
  const rl_forces *F = c->forces; /* at t: with the virial (interval is a multiple of energy_every) */
  if (F->forces_only)
    return rl_error(RL_ESTATE, "the %s has no virial at step %ld (the energy cadence)", op->type->label, c->step);
  double L[3], Ln[3];
  rl_system_box(s, L);
  const double V = L[0] * L[1] * L[2], kT = s->kB * bp->T0, trW = F->virial[0] + F->virial[4] + F->virial[8];
  const double P = (2.0 * c->info->ke_trans + trW) / (3.0 * V);
  const double x = bp->compressibility * bp->interval * c->p->h / bp->tau_p;
  if (bp->coupling == RL_BARO_SEMIISOTROPIC) return cr_semi(op, c, L, V, kT, x);
  const double deps = -x * (bp->P0 - P) + sqrt(2.0 * kT * x / V) * gsl_ran_gaussian(b->rng, 1.0);
  const double mu = exp(deps / 3.0);
  for (int k = 0; k < 3; k++) Ln[k] = L[k] * mu;
  int st = check_edges(op, c, L, Ln);
  if (st) return st;
  double K0, K1; /* the translational kinetic energy of v(t+h/2), before and after */
  cr_scale(s, (const double[3]){mu, mu, mu}, &K0, &K1);
  if ((st = rl_system_set_box(s, Ln))) return st;
  /* the energy the move changes: dK exactly, dU = -tr W ln mu to first order here, completed to
   * the trapezoid -(tr W + tr W') ln mu / 2 at the end of the step (cr_end), with W' the virial
   * in the new box: second order in ln mu, which the noise makes O(h^1/2) per move */
  op->work -= (K1 - K0) - trW * log(mu);
  b->pending = 1;
  b->trW0 = trW;
  b->lnmu = log(mu);
  b->total_attempted[0]++;
  b->total_accepted[0]++;
  return RL_OK;
}

static int cr_end(rl_stepop *op, rl_stepop_ctx *c)
{
  baro_state *b = op->state;
  if (!b->pending) return RL_OK;
  const int semi = b->pending == 2;
  b->pending = 0;
  int st;
  if (c->forces->forces_only && (st = rl_stepop_forces(c, 1))) return st;
  const double *W = c->forces->virial;
  if (semi)
    for (int k = 0; k < 3; k++) op->work += 0.5 * (W[4 * k] - b->W0[k]) * b->lnmu3[k];
  else op->work += 0.5 * (W[0] + W[4] + W[8] - b->trW0) * b->lnmu;
  return RL_OK;
}

/* ------------------------------------------------------------------------ descriptors */

static const rl_stepop_param params[] = {
    {"P0", "pressure", "target pressure"},
    {"T0", "temperature", "temperature of the ensemble (the thermostat's)"},
    {"interval", "steps", "steps between moves"},
    {"tau_p", "time", "C-rescale: coupling time"},
    {"compressibility", "1/pressure", "C-rescale: isothermal compressibility"},
    {"trial", "", "Monte Carlo: first trial size, a fraction of V (0: 0.01)"},
    {"coupling", "", "isotropic, anisotropic (Monte Carlo only) or semi-isotropic (C-rescale only)"},
    {"min_edge", "length", "smallest box edge a move may make (0: no check)"},
    {"seed", "", "GSL mt19937 seed"},
    {NULL, NULL, NULL}};

const rl_stepop_type rl_stepop_mc_barostat = {
    .name = "mc-barostat",
    .label = "Monte Carlo barostat",
    .reference = "OpenMM MonteCarloBarostat; J. Aqvist et al., Chem. Phys. Lett. 384, 288 (2004); K.-H. Chow and "
                 "D. M. Ferguson, Comput. Phys. Commun. 91, 283 (1995)",
    .params = params,
    .params_size = sizeof(rl_barostat_params),
    .check = mc_check,
    .alloc = baro_alloc,
    .free = baro_free,
    .hook = {[RL_STEP_END] = mc_end},
    .save = baro_save,
    .load = baro_load,
};

const rl_stepop_type rl_stepop_crescale = {
    .name = "c-rescale",
    .label = "stochastic cell rescaling barostat",
    .reference = "M. Bernetti and G. Bussi, J. Chem. Phys. 153, 114107 (2020)",
    .params = params,
    .params_size = sizeof(rl_barostat_params),
    .check = cr_check,
    .alloc = baro_alloc,
    .free = baro_free,
    .hook = {[RL_STEP_AFTER_DRIFT] = cr_after_drift, [RL_STEP_END] = cr_end},
    .save = baro_save,
    .load = baro_load,
};
