/* The shared leapfrog core: translation (eqs. 8-9), the revised angular-momentum rotation with
 * one path per body kind (integrators/paths/), and the step operators (thermostats, barostats;
 * include/rotleap/stepops.h, integrators/stepops/) called at the points of the step.
 *
 * A step from t to t+h, given forces and torques at t:
 *   1. on-step v(t) = v(t-h/2) + h/2 f/m, l(t) = l(t-h/2) + h/2 k        (eqs. 9, 12)
 *      -> kinetic energies and temperature at t                 [RL_STEP_BEFORE_KICK: kick beta]
 *   2. v(t+h/2) = (2 beta - 1) v(t) + h/2 f/m, same for l                  (eqs. 10, 17-18;
 *      beta = 1 is the plain kick)                                         [RL_STEP_AFTER_KICK]
 *   3. r(t+h) = r(t) + h v(t+h/2)                                          (eq. 8)
 *   4. rotation by kind, from l(t+h/2)                                     (eqs. 19-36, III.D),
 *      or by a baseline method for every matrix body (integrators/paths/baselines.c)
 *      3-4 in two halves of h/2 when an operator acts in the middle       [RL_STEP_MID_DRIFT]
 *                                                                          [RL_STEP_AFTER_DRIFT]
 *   5. forces at t+h from the provider.                                    [RL_STEP_END]
 * The core knows no particular operator: it calls their hooks in the order they were added. */
#include "rotleap/integrator.h"
#include "rotleap/error.h"
#include "rotleap/rotation.h"
#include "rotleap/stepops.h"
#include "rotleap/terms.h"
#include "../core/threads.h"
#include "paths/path.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The Cayley update is orthogonal in exact arithmetic; in floating point each product adds about
 * one ulp of non-orthogonality, which random-walks to ~1e-16 sqrt(steps) (2e-13 after 10^6
 * steps, measured).  Every RL_POLISH_INTERVAL steps one Newton-Schulz step A <- A (3I - A^T A)/2
 * (rho, q: x <- x (3 - |x|^2)/2) squares that error away.  It changes A by the accumulated
 * round-off only (~1e-14), unlike the renormalisation of non-orthogonal schemes, which corrects
 * O(h^3) truncation errors. */
#define RL_POLISH_INTERVAL 256

struct rl_integrator {
  rl_system *sys;
  rl_integrator_params p;
  rl_force_provider provider;
  rl_forces F;
  double (*q)[4]; /* [nmat] quaternions: RL_ROT_QUATERNION's state; the baselines' last q */
  double (*lprev)[3]; /* [nrot] l(t-h/2) before the kick, RL_ROT_FINCHAM only */
  int initialized;
  long steps, fallbacks, quat_iterations;
  double t;
  rl_stepop ops[RL_STEPOP_MAX]; /* the step operators, in the order they act at each point */
  int nops;
  int has[RL_STEP_NPOINTS]; /* some operator has a hook at this point */
  double work;        /* the conserved quantity's account while there is no operator (set by
                         rl_integrator_set_thermostat_work, e.g. from a checkpoint) */
  int threads;        /* of the rotation solves and the per-body loops: p.threads resolved */
  double *part;       /* [2 (ceil(n / RL_SUM_BLOCK) + 1)] the kinetic sums' block partials */
  rl_forces kept;     /* rl_stepop_forces_keep's copy of F (arrays allocated at the first keep) */
  int nspecies;       /* the system's species at alloc: entries of spk                     */
  rl_species_kinetic *spk; /* the last on-step report's per-species values (rl_step_info)   */
};

/* The per-body loops of a step run on in->threads threads (from RL_THREAD_MIN_BODIES bodies on,
 * which pay for the threads' start).  Their kinetic-energy sums are formed per block of
 * RL_SUM_BLOCK bodies and the blocks added in order, so the result does not depend on the thread
 * count. */
#define RL_SUM_BLOCK 1024
static int nblocks(int count) { return (count + RL_SUM_BLOCK - 1) / RL_SUM_BLOCK; }

const char *rl_rot_method_name(rl_rot_method m)
{
  switch (m) {
  case RL_ROT_CUBIC: return "rl";
  case RL_ROT_EXACT: return "rl-exact";
  case RL_ROT_QUATERNION: return "rl-quaternion";
  case RL_ROT_HYBRID: return "rl-hybrid";
  case RL_ROT_FINCHAM: return "fincham";
  case RL_ROT_NOSQUISH: return "no-squish";
  }
  return NULL;
}

void rl_integrator_params_default(rl_integrator_params *p)
{
  memset(p, 0, sizeof *p);
  p->h = 0.0;
  p->method = RL_ROT_CUBIC;
  p->guard_tol = RL_OMEGA_GUARD_TOL;
  p->quat_tol = 1e-12;
  p->quat_maxit = 100;
  p->force_general = 0;
  p->thermostat = RL_THERMO_NONE;
  p->T0 = 0.0;
  p->groups = RL_THERMO_GROUPS_TRANS_ROT;
}

const char *rl_thermo_groups_name(rl_thermo_groups g)
{
  switch (g) {
  case RL_THERMO_GROUPS_TRANS_ROT: return "trans-rot";
  case RL_THERMO_GROUPS_ALL: return "all";
  }
  return NULL;
}

const char *rl_thermostat_name(rl_thermostat t)
{
  switch (t) {
  case RL_THERMO_NONE: return "none";
  case RL_THERMO_ISOKINETIC: return "isokinetic";
  case RL_THERMO_BUSSI: return "Bussi";
  case RL_THERMO_LANGEVIN: return "Langevin";
  case RL_THERMO_LANGEVIN_DOT: return "Langevin-DOT";
  case RL_THERMO_LANGEVIN_DOT_OBABO: return "Langevin-DOT-OBABO";
  }
  return NULL;
}

const char *rl_step_point_name(rl_step_point pt)
{
  switch (pt) {
  case RL_STEP_BEFORE_KICK: return "before-kick";
  case RL_STEP_AFTER_KICK: return "after-kick";
  case RL_STEP_MID_DRIFT: return "mid-drift";
  case RL_STEP_AFTER_DRIFT: return "after-drift";
  case RL_STEP_END: return "end";
  default: return NULL;
  }
}

/* 1 if one of the operators has `flag`. */
static int any_flag(const rl_stepop *ops, int nops, unsigned flag)
{
  for (int k = 0; k < nops; k++)
    if (ops[k].type->flags & flag) return 1;
  return 0;
}

/* Translational degrees of freedom under the operators.  One that moves the centre of mass at
 * random (Langevin's noise, RL_STEPOP_THERMAL_COM) makes all 3N count; otherwise the operators
 * conserve (none) or scale (Bussi, isokinetic) the total momentum, which carries no thermal
 * energy, and the system's removed_dof (3 by default: the total momentum, held at zero by init and
 * resume) comes off. */
static int dof_trans(const rl_system *s, const rl_stepop *ops, int nops)
{
  return any_flag(ops, nops, RL_STEPOP_THERMAL_COM) ? 3 * s->n : rl_system_dof_translational(s);
}

/* The integrator's settings, the operators ops[0..nops) (their type and parameters) and the
 * system, in this order: parameters of the core, the operators' own checks, what the operators
 * ask of the core, the system. */
static int validate(const rl_system *s, const rl_integrator_params *p, const rl_stepop *ops, int nops)
{
  if (!(p->h > 0.0) || !isfinite(p->h))
    return rl_error(RL_EINVAL, "time step h = %g must be positive and finite", p->h);
  if (!rl_rot_method_name(p->method))
    return rl_error(RL_EINVAL, "unknown rotation method %d", (int)p->method);
  if ((p->method == RL_ROT_QUATERNION || p->method == RL_ROT_FINCHAM) &&
      (!(p->quat_tol > 0.0) || p->quat_maxit < 1))
    return rl_error(RL_EINVAL, "quaternion tolerance %g / max iterations %d must be positive",
                    p->quat_tol, p->quat_maxit);
  if (!rl_thermostat_name(p->thermostat))
    return rl_error(RL_EINVAL, "unknown thermostat %d", (int)p->thermostat);
  int st, scales = 0;
  for (int k = 0; k < nops; k++)
    if (ops[k].type->check && (st = ops[k].type->check(ops[k].par, s, p))) return st;
  for (int k = 0; k < nops; k++) {
    /* the baselines are kept as published, one rotation over h; the middle needs two of h/2 */
    if (ops[k].type->hook[RL_STEP_MID_DRIFT] && rl_rot_is_baseline(p->method))
      return rl_error(RL_EINVAL, "the %s splits the rotation into two half steps, which the baseline "
                      "%s does not provide; use rl, rl-exact or rl-quaternion", ops[k].type->label,
                      rl_rot_method_name(p->method));
    if ((ops[k].type->flags & RL_STEPOP_SCALES_KICK) && scales++)
      return rl_error(RL_EINVAL, "the %s scales the kick (eqs. 17-18), and so does an operator "
                      "before it: only one may", ops[k].type->label);
  }
  if (p->threads < 0)
    return rl_error(RL_EINVAL, "integrator threads = %d must be >= 0 (0: OMP_NUM_THREADS if set, "
                    "else 1)", p->threads);
  if (p->energy_every < 0)
    return rl_error(RL_EINVAL, "integrator energy_every = %ld must be >= 0 (0 or 1: every step)",
                    p->energy_every);
  if (s->n == 0) return rl_error(RL_EINVAL, "the system has no bodies");
  const int g = dof_trans(s, ops, nops) + rl_system_dof_rotational(s);
  if (any_flag(ops, nops, RL_STEPOP_HOLDS_TEMPERATURE) && g <= 0)
    return rl_error(RL_EINVAL, "the system has %d degrees of freedom: no temperature to hold", g);
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    /* the baselines are quaternion schemes for full orientations; an axis-only species has no
     * q to advance, and a re-derived axis scheme would not be the published baseline */
    if (rl_rot_is_baseline(p->method) && sp->axis_off >= 0)
      return rl_error(RL_EINVAL, "rotation method %s has no baseline for species '%s' (%s: only "
                      "its axis is stored); use rl, rl-exact or rl-quaternion for systems with "
                      "point dipoles or linear molecules", rl_rot_method_name(p->method),
                      sp->name, rl_kind_name(sp->kind));
    for (int b = 0; b < sp->count; b++) {
      if (sp->mat_off >= 0 && (st = rl_check_rotation(s->A[sp->mat_off + b], "integrator", sp->first + b)))
        return st;
      if (sp->axis_off >= 0) {
        const double *r = s->rho[sp->axis_off + b];
        double nr = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        if (!(fabs(nr - 1.0) <= 1e-10))
          return rl_error(RL_EORTHO, "integrator: body %d: axis is not a unit vector (|rho| - 1 = "
                          "%.3g)", sp->first + b, nr - 1.0);
      }
    }
  }
  return RL_OK;
}

/* Which points have hooks. */
static void note_hooks(rl_integrator *in)
{
  for (int pt = 0; pt < RL_STEP_NPOINTS; pt++) {
    in->has[pt] = 0;
    for (int k = 0; k < in->nops; k++)
      if (in->ops[k].type->hook[pt]) in->has[pt] = 1;
  }
}

/* Append an operator of type T with parameters par (validated): copy the parameters, alloc. */
static int op_create(rl_integrator *in, const rl_stepop_type *T, const void *par)
{
  rl_stepop *op = &in->ops[in->nops];
  *op = (rl_stepop){T, NULL, NULL, 0.0};
  if (T->params_size) {
    if (!(op->par = malloc(T->params_size))) return rl_error(RL_ENOMEM, "%s: out of memory", T->label);
    memcpy(op->par, par, T->params_size);
  }
  int st = T->alloc ? T->alloc(op) : RL_OK;
  if (st) {
    free(op->par);
    return st;
  }
  in->nops++;
  note_hooks(in);
  return RL_OK;
}

int rl_integrator_add_op(rl_integrator *in, const rl_stepop_type *T, const void *params)
{
  if (!in || !T) return rl_error(RL_EINVAL, "rl_integrator_add_op: NULL argument");
  if (in->initialized)
    return rl_error(RL_ESTATE, "rl_integrator_add_op: the %s must be added before rl_integrator_init "
                    "or resume (or after rl_integrator_finish)", T->label);
  if (in->nops == RL_STEPOP_MAX)
    return rl_error(RL_EINVAL, "rl_integrator_add_op: the integrator carries %d step operators, the "
                    "most it can", RL_STEPOP_MAX);
  if (T->params_size && !params) return rl_error(RL_EINVAL, "rl_integrator_add_op: the %s needs parameters", T->label);
  rl_stepop ops[RL_STEPOP_MAX];
  memcpy(ops, in->ops, sizeof(*ops) * (size_t)in->nops);
  ops[in->nops] = (rl_stepop){T, (void *)params, NULL, 0.0};
  int st = validate(in->sys, &in->p, ops, in->nops + 1);
  return st ? st : op_create(in, T, params);
}

int rl_integrator_nops(const rl_integrator *in) { return in->nops; }
rl_stepop *rl_integrator_op(rl_integrator *in, int k) { return k >= 0 && k < in->nops ? &in->ops[k] : NULL; }

rl_integrator *rl_integrator_alloc(rl_system *sys, const rl_integrator_params *p,
                                   rl_force_provider provider)
{
  if (!sys || !p) { rl_error(RL_EINVAL, "rl_integrator_alloc: NULL argument"); return NULL; }
  if (!provider.compute) { rl_error(RL_EINVAL, "rl_integrator_alloc: no force provider"); return NULL; }
  /* the thermostat of p, the first operator */
  const rl_stepop_type *T = rl_stepop_for_thermostat(p->thermostat);
  const rl_thermostat_params tp = {p->T0, p->tau, p->seed, p->groups, p->tau_rot};
  const rl_stepop first = {T, (void *)&tp, NULL, 0.0};
  if (validate(sys, p, &first, T ? 1 : 0)) return NULL;
  rl_integrator *in = calloc(1, sizeof *in);
  if (!in) { rl_error(RL_ENOMEM, "rl_integrator_alloc: out of memory"); return NULL; }
  in->sys = sys;
  in->p = *p;
  if (in->p.guard_tol <= 0.0) in->p.guard_tol = RL_OMEGA_GUARD_TOL;
  in->threads = rl_threads_resolve(p->threads);
  in->provider = provider;
  in->F.f = calloc((size_t)sys->n, sizeof *in->F.f);
  in->F.k = calloc((size_t)(sys->nrot > 0 ? sys->nrot : 1), sizeof *in->F.k);
  const int need_q = (p->method == RL_ROT_QUATERNION || rl_rot_is_baseline(p->method)) && sys->nmat > 0;
  const int need_lprev = p->method == RL_ROT_FINCHAM && sys->nrot > 0;
  if (need_q) in->q = calloc((size_t)sys->nmat, sizeof *in->q);
  if (need_lprev) in->lprev = calloc((size_t)sys->nrot, sizeof *in->lprev);
  in->part = malloc(sizeof *in->part * (size_t)(2 * (nblocks(sys->n) + 1)));
  in->nspecies = sys->nspecies;
  in->spk = calloc((size_t)(sys->nspecies > 0 ? sys->nspecies : 1), sizeof *in->spk);
  if (!in->F.f || !in->F.k || !in->part || !in->spk || (need_q && !in->q) || (need_lprev && !in->lprev)) {
    rl_integrator_free(in);
    rl_error(RL_ENOMEM, "rl_integrator_alloc: out of memory");
    return NULL;
  }
  if (T && op_create(in, T, &tp)) {
    rl_integrator_free(in);
    return NULL;
  }
  return in;
}

void rl_integrator_free(rl_integrator *in)
{
  if (!in) return;
  free(in->F.f);
  free(in->F.k);
  free(in->kept.f);
  free(in->kept.k);
  free(in->q);
  free(in->lprev);
  free(in->part);
  free(in->spk);
  for (int k = 0; k < in->nops; k++) {
    if (in->ops[k].type->free) in->ops[k].type->free(&in->ops[k]);
    free(in->ops[k].par);
  }
  free(in);
}

/* Forces and torques at the current time; energy and virial too if ev. */
static int compute_forces(rl_integrator *in, int ev)
{
  rl_system *s = in->sys;
  const int n = s->n, nr = s->nrot, par = in->threads > 1 && n >= RL_THREAD_MIN_BODIES;
  (void)par; /* a build without OpenMP */
#ifdef _OPENMP
#pragma omp parallel num_threads(in->threads) if (par)
#endif
  { /* each thread its share of the forces and torques */
    int i0, i1, k0, k1;
    rl_thread_range(n, &i0, &i1);
    rl_thread_range(nr, &k0, &k1);
    if (i1 > i0) memset(in->F.f + i0, 0, sizeof(*in->F.f) * (size_t)(i1 - i0));
    if (k1 > k0) memset(in->F.k + k0, 0, sizeof(*in->F.k) * (size_t)(k1 - k0));
  }
  in->F.energy = 0.0;
  memset(in->F.virial, 0, sizeof in->F.virial);
  in->F.forces_only = !ev;
  rl_error_clear();
  int st = in->provider.compute(in->provider.ctx, s, &in->F);
  if (st) return rl_error_wrap(RL_EFORCE, "force provider failed at step %ld (t = %g)", in->steps, in->t);
  if (ev && !isfinite(in->F.energy))
    return rl_error(RL_ENONFINITE, "non-finite potential energy at step %ld (t = %g)", in->steps, in->t);
  int bf = n, bk = nr; /* the first non-finite force and torque */
#ifdef _OPENMP
#pragma omp parallel num_threads(in->threads) if (par) reduction(min : bf, bk)
#endif
  {
    int i0, i1, k0, k1;
    rl_thread_range(n, &i0, &i1);
    rl_thread_range(nr, &k0, &k1);
    int i = i0, k = k0; /* (the reduction's private bf, bk start at INT_MAX) */
    while (i < i1 && isfinite(in->F.f[i][0] + in->F.f[i][1] + in->F.f[i][2])) i++;
    while (k < k1 && isfinite(in->F.k[k][0] + in->F.k[k][1] + in->F.k[k][2])) k++;
    if (i < i1) bf = i;
    if (k < k1) bk = k;
  }
  if (bf < n)
    return rl_error(RL_ENONFINITE, "non-finite force on body %d at step %ld (t = %g)", bf,
                    in->steps, in->t);
  if (bk < nr)
    return rl_error(RL_ENONFINITE, "non-finite torque (rotating body %d) at step %ld (t = %g)",
                    bk, in->steps, in->t);
  return RL_OK;
}

/* v <- sign (v + dt f/m), l <- sign (l + dt k) for every body, with the current forces: the
 * half-step stagger of init, the completion of finish and the reversal of reverse. */
static void kick(rl_integrator *in, double dt, double sign)
{
  rl_system *s = in->sys;
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    double w = dt / sp->mass;
    for (int b = 0; b < sp->count; b++) {
      int i = sp->first + b;
      for (int c = 0; c < 3; c++) s->v[i][c] = sign * (s->v[i][c] + w * in->F.f[i][c]);
      if (sp->rot_off >= 0)
        for (int c = 0; c < 3; c++)
          s->l[sp->rot_off + b][c] = sign * (s->l[sp->rot_off + b][c] + dt * in->F.k[sp->rot_off + b][c]);
    }
  }
}

/* The operators' accounts, for the conserved quantity: their sum, or the integrator's own while
 * there is no operator (summed from the first, so that one operator's account is returned as it
 * is). */
static double total_work(const rl_integrator *in)
{
  if (!in->nops) return in->work;
  double w = in->ops[0].work;
  for (int k = 1; k < in->nops; k++) w += in->ops[k].work;
  return w;
}

static void zero_work(rl_integrator *in)
{
  in->work = 0.0;
  for (int k = 0; k < in->nops; k++) in->ops[k].work = 0.0;
}

/* What the hooks of a step (or of observe) see: the step starting at the current time, whose
 * report info has the on-step values; beta = beta_rot = 1 and the conserved quantity with the
 * accounts as they are before the step. */
static void ctx_start(rl_integrator *in, rl_stepop_ctx *c, rl_step_info *info)
{
  *c = (rl_stepop_ctx){.in = in, .sys = in->sys, .p = &in->p, .step = in->steps, .t = in->t,
                       .forces = &in->F, .dof_trans = dof_trans(in->sys, in->ops, in->nops),
                       .dof_rot = rl_system_dof_rotational(in->sys), .K = {NAN, NAN},
                       .kick_beta = 1.0, .info = info};
  info->beta = info->beta_rot = 1.0;
  info->conserved = info->total + total_work(in);
}

/* The hooks of every operator at point pt, in the order the operators were added. */
static int run_hooks(rl_integrator *in, rl_step_point pt, rl_stepop_ctx *c)
{
  if (!in->has[pt]) return RL_OK;
  for (int k = 0; k < in->nops; k++) {
    const rl_stepop_hook f = in->ops[k].type->hook[pt];
    int st = f ? f(&in->ops[k], c) : RL_OK;
    if (st) return st;
  }
  return RL_OK;
}

int rl_stepop_forces(rl_stepop_ctx *c, int energy) { return compute_forces(c->in, energy); }

/* (F and kept: n and nrot rows; the copies are those of a computation) */
static void copy_forces(rl_forces *to, const rl_forces *from, int n, int nr)
{
  memcpy(to->f, from->f, sizeof *to->f * (size_t)n);
  if (nr) memcpy(to->k, from->k, sizeof *to->k * (size_t)nr);
  to->energy = from->energy;
  memcpy(to->virial, from->virial, sizeof to->virial);
  to->forces_only = from->forces_only;
}

int rl_stepop_forces_keep(rl_stepop_ctx *c)
{
  rl_integrator *in = c->in;
  const rl_system *s = in->sys;
  rl_terms *t = rl_terms_of_provider(in->provider);
  if (!t) return RL_OK; /* a provider whose report cannot be kept: put_back computes again */
  if (!in->kept.f) {
    in->kept.f = malloc(sizeof *in->kept.f * (size_t)(s->n > 0 ? s->n : 1));
    in->kept.k = malloc(sizeof *in->kept.k * (size_t)(s->nrot > 0 ? s->nrot : 1));
    if (!in->kept.f || !in->kept.k) {
      free(in->kept.f);
      free(in->kept.k);
      in->kept.f = NULL;
      in->kept.k = NULL;
      return rl_error(RL_ENOMEM, "out of memory for a copy of the forces");
    }
  }
  copy_forces(&in->kept, &in->F, s->n, s->nrot);
  rl_terms_keep(t);
  return RL_OK;
}

int rl_stepop_forces_put_back(rl_stepop_ctx *c, int energy)
{
  rl_integrator *in = c->in;
  rl_terms *t = rl_terms_of_provider(in->provider);
  if (!t || !in->kept.f) return compute_forces(in, energy);
  copy_forces(&in->F, &in->kept, in->sys->n, in->sys->nrot);
  rl_terms_put_back(t);
  return RL_OK;
}

void rl_stepop_kinetic(const rl_stepop_ctx *c, double K[2])
{
  const rl_system *s = c->sys;
  K[0] = K[1] = 0.0;
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    const rl_family *fam = rl_family_for(sp->kind, c->p->force_general);
    double kt = 0.0;
    for (int b = 0; b < sp->count; b++) {
      const double *v = s->v[sp->first + b];
      kt += v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
      if (sp->rot_off >= 0) K[1] += fam->ke_rot(sp, s, b, s->l[sp->rot_off + b]);
    }
    K[0] += 0.5 * sp->mass * kt;
  }
}

/* The centre of mass as the operators need it.  Under one that moves it at random (Langevin,
 * RL_STEPOP_THERMAL_COM) it is thermal, and nothing is done.  Otherwise, when the system's count takes the total momentum P out (removed_dof
 * >= 3), P must be zero, and a P above round-off (|P| > 1e-10 sum m|v|) is removed: a state that
 * comes from a Langevin run has |P| ~ sqrt(3 M kT).  One at round-off is left as it is, so that
 * restarts continue bit for bit.  Returns 1 if P was removed. */
static int zero_momentum(rl_integrator *in)
{
  rl_system *s = in->sys;
  if (any_flag(in->ops, in->nops, RL_STEPOP_THERMAL_COM) || s->removed_dof < 3) return 0;
  double P[3] = {0.0, 0.0, 0.0}, M = 0.0, mv = 0.0;
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    for (int i = sp->first; i < sp->first + sp->count; i++) {
      const double *v = s->v[i];
      for (int c = 0; c < 3; c++) P[c] += sp->mass * v[c];
      mv += sp->mass * sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      M += sp->mass;
    }
  }
  if (!(sqrt(P[0] * P[0] + P[1] * P[1] + P[2] * P[2]) > 1e-10 * mv)) return 0;
  for (int i = 0; i < s->n; i++)
    for (int c = 0; c < 3; c++) s->v[i][c] -= P[c] / M;
  return 1;
}

int rl_integrator_init(rl_integrator *in)
{
  rl_system *s = in->sys;
  int st = validate(s, &in->p, in->ops, in->nops);
  if (st) return st;
  /* dipoles and linear molecules carry no spin about their axis */
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    if (sp->axis_off >= 0)
      for (int b = 0; b < sp->count; b++) rl_project_out(s->l[sp->rot_off + b], s->rho[sp->axis_off + b]);
  }
  if (in->q)
    for (int k = 0; k < s->nspecies; k++) {
      const rl_species *sp = &s->sp[k];
      if (sp->mat_off < 0) continue;
      for (int b = 0; b < sp->count; b++)
        if ((st = rl_matrix_to_quat(s->A[sp->mat_off + b], in->q[sp->mat_off + b]))) return st;
    }
  zero_momentum(in);
  in->steps = 0;
  zero_work(in);
  in->fallbacks = 0;
  in->quat_iterations = 0;
  if ((st = compute_forces(in, 1))) return st;
  kick(in, -0.5 * in->p.h, 1.0); /* v(t - h/2) = v(t) - h/2 f/m */
  in->initialized = 1;
  return RL_OK;
}

static void polish_orientations(rl_integrator *in)
{
  rl_system *s = in->sys;
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    if (sp->mat_off < 0) continue;
    /* q is the state only where RL_ROT_QUATERNION actually moves it (the general path); the
     * fast paths and the baselines advance A, and their q must not overwrite it */
    const int qstate = in->p.method == RL_ROT_QUATERNION &&
                       rl_family_for(sp->kind, in->p.force_general) == &rl_family_asymmetric;
    for (int i = sp->mat_off; i < sp->mat_off + sp->count; i++) {
      if (qstate) {
        double *q = in->q[i], f = 0.5 * (3.0 - (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]));
        for (int c = 0; c < 4; c++) q[c] *= f;
        rl_quat_to_matrix(q, s->A[i]);
        continue;
      }
      double *A = s->A[i], M[9], B[9];
      for (int a = 0; a < 3; a++) /* M = (3I - A^T A)/2 */
        for (int b = 0; b < 3; b++)
          M[3 * a + b] = 0.5 * ((a == b ? 3.0 : 0.0) - (A[a] * A[b] + A[3 + a] * A[3 + b] + A[6 + a] * A[6 + b]));
      for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
          B[3 * a + b] = A[3 * a] * M[b] + A[3 * a + 1] * M[3 + b] + A[3 * a + 2] * M[6 + b];
      memcpy(A, B, sizeof B);
    }
  }
  for (int i = 0; i < s->naxis; i++) {
    double *r = s->rho[i], f = 0.5 * (3.0 - (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]));
    r[0] *= f; r[1] *= f; r[2] *= f;
  }
}

/* Step 4: every species rotated by w->h from its l. */
static int rotate_all(rl_integrator *in, rl_rotation_work *w)
{
  rl_system *s = in->sys;
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    int st = rl_family_for(sp->kind, in->p.force_general)->rotate(sp, s, w);
    if (st) return st;
  }
  return RL_OK;
}

/* r += hd v for every body. */
static void drift(rl_integrator *in, double hd)
{
  rl_system *s = in->sys;
  const int n = s->n;
#ifdef _OPENMP
#pragma omp parallel for num_threads(in->threads) schedule(static) \
    if (in->threads > 1 && n >= RL_THREAD_MIN_BODIES)
#endif
  for (int i = 0; i < n; i++)
    for (int c = 0; c < 3; c++) s->r[i][c] += hd * s->v[i][c];
}

static int all_finite(const double *x, int n)
{
  double z = 0.0;
  for (int c = 0; c < n; c++) z += 0.0 * x[c]; /* NaN iff some x[c] is NaN or Inf */
  return z == 0.0;
}

/* What of body i is not finite (position, orientation or axis), or NULL. */
static const char *nonfinite_part(const rl_system *s, int i)
{
  const rl_species *sp = &s->sp[s->species_of[i]];
  const int b = i - sp->first;
  if (!all_finite(s->r[i], 3)) return "position";
  if (sp->mat_off >= 0 && !all_finite(s->A[sp->mat_off + b], 9)) return "orientation";
  if (sp->axis_off >= 0 && !all_finite(s->rho[sp->axis_off + b], 3)) return "axis";
  return NULL;
}

/* After the drift and the rotation: RL_ENONFINITE naming the mid-step kinetic energy K (the
 * step's Kmid) or the first body whose new position or orientation is not finite, so that a step
 * never returns RL_OK with a NaN or Inf in the state (and no force provider sees one). */
static int check_state(const rl_integrator *in, const double K[2])
{
  const rl_system *s = in->sys;
  if (!isfinite(K[0]) || !isfinite(K[1]))
    return rl_error(RL_ENONFINITE, "non-finite mid-step kinetic energy at step %ld (t = %g): translational "
                    "%g, rotational %g", in->steps, in->t, K[0], K[1]);
  const int n = s->n;
  int bad = n;
#ifdef _OPENMP
#pragma omp parallel num_threads(in->threads) if (in->threads > 1 && n >= RL_THREAD_MIN_BODIES) \
    reduction(min : bad)
#endif
  {
    int i0, i1;
    rl_thread_range(n, &i0, &i1);
    for (int i = i0; i < i1; i++)
      if (nonfinite_part(s, i)) { bad = i; break; }
  }
  if (bad < n)
    return rl_error(RL_ENONFINITE, "non-finite %s of body %d after step %ld (t = %g)",
                    nonfinite_part(s, bad), bad, in->steps, in->t);
  return RL_OK;
}

/* The kick of one component x (v or l) by the force f over the step (eqs. 8, 10), as eqs. 17-18
 * under the isokinetic scheme (beta != 1, c2 = 2 beta - 1); w = h / 2 (times 1/m for v). */
static inline double plain_kick(double x, double w, double f) { return x + 2.0 * w * f; }
static inline double kicked(double beta, double c2, double x, double w, double f)
{
  return beta == 1.0 ? plain_kick(x, w, f) : c2 * (x + w * f) + w * f;
}

/* The on-step values at the current time t (eqs. 9, 12) from v(t-h/2), l(t-h/2) and the forces
 * at t: what a step reports for its starting time, before it changes anything. */
static void onstep_info(rl_integrator *in, rl_step_info *info)
{
  rl_system *s = in->sys;
  const double h = in->p.h, h2 = 0.5 * h;
  memset(info, 0, sizeof *info);
  info->t = in->t;
  info->has_energy = !in->F.forces_only;
  info->potential = info->has_energy ? in->F.energy : NAN;

  /* 1. on-step kinetic energies (eqs. 9, 12) */
  double ket = 0.0, ker = 0.0;
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    const rl_family *fam = rl_family_for(sp->kind, in->p.force_general);
    const double w = h2 / sp->mass;
    const int nb = nblocks(sp->count);
    double *pt = in->part, *pr = in->part + nb;
#ifdef _OPENMP
#pragma omp parallel for num_threads(in->threads) schedule(static) \
    if (in->threads > 1 && sp->count >= RL_THREAD_MIN_BODIES)
#endif
    for (int q = 0; q < nb; q++) {
      const int end = q < nb - 1 ? (q + 1) * RL_SUM_BLOCK : sp->count;
      double kt = 0.0, kr = 0.0;
      for (int b = q * RL_SUM_BLOCK; b < end; b++) {
        int i = sp->first + b;
        for (int c = 0; c < 3; c++) {
          double vt = s->v[i][c] + w * in->F.f[i][c];
          kt += vt * vt;
        }
        if (sp->rot_off >= 0) {
          const double *l = s->l[sp->rot_off + b], *kk = in->F.k[sp->rot_off + b];
          double lt[3] = {l[0] + h2 * kk[0], l[1] + h2 * kk[1], l[2] + h2 * kk[2]};
          kr += fam->ke_rot(sp, s, b, lt);
        }
      }
      pt[q] = kt;
      pr[q] = kr;
    }
    double kt = 0.0, kr = 0.0;
    for (int q = 0; q < nb; q++) {
      kt += pt[q];
      ker += pr[q];
      kr += pr[q];
    }
    ket += 0.5 * sp->mass * kt;
    if (k < in->nspecies) {
      in->spk[k].ke_trans = 0.5 * sp->mass * kt;
      in->spk[k].ke_rot = kr;
    }
  }
  int gt = dof_trans(s, in->ops, in->nops), gr = rl_system_dof_rotational(s), g = gt + gr;
  for (int k = 0; k < in->nspecies && k < s->nspecies; k++) { /* the dof shared as rl_species_kinetic says */
    const rl_species *sp = &s->sp[k];
    const double gtk = (double)gt * sp->count / s->n, grk = (double)sp->count * rl_kind_rotational_dof(sp->kind);
    in->spk[k].t_trans = gtk > 0.0 ? 2.0 * in->spk[k].ke_trans / (gtk * s->kB) : 0.0;
    in->spk[k].t_rot = grk > 0.0 ? 2.0 * in->spk[k].ke_rot / (grk * s->kB) : 0.0;
  }
  info->nspecies = in->nspecies < s->nspecies ? in->nspecies : s->nspecies;
  info->species = in->spk;
  info->ke_trans = ket;
  info->ke_rot = ker;
  info->total = ket + ker + info->potential;
  info->temperature = g > 0 ? 2.0 * (ket + ker) / (g * s->kB) : 0.0;
  info->t_trans = gt > 0 ? 2.0 * ket / (gt * s->kB) : 0.0;
  info->t_rot = gr > 0 ? 2.0 * ker / (gr * s->kB) : 0.0;
}

int rl_integrator_observe(rl_integrator *in, rl_step_info *out)
{
  if (!in || !in->initialized) return rl_error(RL_ESTATE, "rl_integrator_observe: call rl_integrator_init first");
  if (!out) return rl_error(RL_EINVAL, "rl_integrator_observe: no rl_step_info to fill");
  /* the same forces again, with the energy and virial (the kernels' forces do not depend on it) */
  if (in->F.forces_only) {
    int st = compute_forces(in, 1);
    if (st) return st;
  }
  rl_system *s = in->sys;
  const double h = in->p.h, h2 = 0.5 * h;
  rl_step_info info;
  onstep_info(in, &info);
  rl_stepop_ctx ctx;
  ctx_start(in, &ctx, &info);
  for (int k = 0; k < in->nops; k++)
    if (in->ops[k].type->observe) in->ops[k].type->observe(&in->ops[k], &ctx);
  /* the mid-step temperatures of the plain kick (eqs. 8, 10), before any thermostat acts: the
   * t_trans_mid, t_rot_mid a step reports */
  double Kmid[2] = {0.0, 0.0};
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    const rl_family *fam = rl_family_for(sp->kind, in->p.force_general);
    const double w = h2 / sp->mass;
    for (int b = 0; b < sp->count; b++) {
      const int i = sp->first + b;
      double v[3];
      for (int c = 0; c < 3; c++) v[c] = plain_kick(s->v[i][c], w, in->F.f[i][c]);
      Kmid[0] += 0.5 * sp->mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      if (sp->rot_off < 0) continue;
      const double *l = s->l[sp->rot_off + b], *kk = in->F.k[sp->rot_off + b];
      double lt[3];
      for (int c = 0; c < 3; c++) lt[c] = plain_kick(l[c], h2, kk[c]);
      Kmid[1] += fam->ke_rot(sp, s, b, lt);
    }
  }
  const int gt = ctx.dof_trans, gr = ctx.dof_rot;
  info.t_trans_mid = gt > 0 ? 2.0 * Kmid[0] / (gt * s->kB) : 0.0;
  info.t_rot_mid = gr > 0 ? 2.0 * Kmid[1] / (gr * s->kB) : 0.0;
  *out = info;
  return RL_OK;
}

int rl_integrator_step(rl_integrator *in, rl_step_info *out)
{
  if (!in || !in->initialized) return rl_error(RL_ESTATE, "rl_integrator_step: call rl_integrator_init first");
  rl_system *s = in->sys;
  const double h = in->p.h, h2 = 0.5 * h;
  rl_step_info info;
  onstep_info(in, &info);
  const double ket = info.ke_trans, ker = info.ke_rot;
  if (!isfinite(ket) || !isfinite(ker))
    return rl_error(RL_ENONFINITE, "non-finite on-step kinetic energy at step %ld (t = %g): translational "
                    "%g, rotational %g (velocities or angular momenta beyond the range of doubles)",
                    in->steps, in->t, ket, ker);
  rl_stepop_ctx ctx;
  ctx_start(in, &ctx, &info);
  const int gt = ctx.dof_trans, gr = ctx.dof_rot;
  ctx.K[0] = ket;
  ctx.K[1] = ker;
  int st = run_hooks(in, RL_STEP_BEFORE_KICK, &ctx);
  if (st) return st;
  const double beta = ctx.kick_beta;
  /* the drift rides in the kick's loop unless an operator acts between them */
  const int fused = !in->has[RL_STEP_AFTER_KICK] && !in->has[RL_STEP_MID_DRIFT];

  /* Fincham needs l(t-h/2) next to l'(t+h/2) for its on-step l'(t) */
  if (in->lprev) memcpy(in->lprev, s->l, sizeof(*s->l) * (size_t)s->nrot);

  /* 2-3. kick and drift; Kmid: kinetic energies of the plain kick's mid-step v(t+h/2) and
   * l(t+h/2), before any thermostat acts (rotational part with A(t), which the rotation below
   * replaces).  Under the isokinetic scheme the values carried forward are eqs. 17-18's; the
   * reported t_trans_mid, t_rot_mid are still those of the plain kick, as for Bussi (before its
   * rescaling); Langevin reports its own, of the middle of the drift. */
  const double c2 = 2.0 * beta - 1.0;
  double Kmid[2] = {0.0, 0.0};
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    const rl_family *fam = rl_family_for(sp->kind, in->p.force_general);
    const double w = h2 / sp->mass;
    const int nb = nblocks(sp->count);
    double *pt = in->part, *pr = in->part + nb;
#ifdef _OPENMP
#pragma omp parallel for num_threads(in->threads) schedule(static) \
    if (in->threads > 1 && sp->count >= RL_THREAD_MIN_BODIES)
#endif
    for (int q = 0; q < nb; q++) {
      const int end = q < nb - 1 ? (q + 1) * RL_SUM_BLOCK : sp->count;
      double kt = 0.0, kr = 0.0;
      for (int b = q * RL_SUM_BLOCK; b < end; b++) {
        int i = sp->first + b;
        double *v = s->v[i];
        const double *f = in->F.f[i];
        double x[3]; /* the plain kick, for Kmid; the same as v, l unless isokinetic */
        for (int c = 0; c < 3; c++) {
          x[c] = plain_kick(v[c], w, f[c]);
          v[c] = beta == 1.0 ? x[c] : kicked(beta, c2, v[c], w, f[c]); /* eq. 8, or 17 */
          if (fused) s->r[i][c] += h * v[c];
        }
        kt += 0.5 * sp->mass * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        if (sp->rot_off < 0) continue;
        double *l = s->l[sp->rot_off + b];
        const double *kk = in->F.k[sp->rot_off + b];
        for (int c = 0; c < 3; c++) {
          x[c] = plain_kick(l[c], h2, kk[c]);
          l[c] = beta == 1.0 ? x[c] : kicked(beta, c2, l[c], h2, kk[c]); /* eq. 10, or 18 */
        }
        kr += fam->ke_rot(sp, s, b, x);
      }
      pt[q] = kt;
      pr[q] = kr;
    }
    for (int q = 0; q < nb; q++) {
      Kmid[0] += pt[q];
      Kmid[1] += pr[q];
    }
  }
  info.t_trans_mid = gt > 0 ? 2.0 * Kmid[0] / (gt * s->kB) : 0.0;
  info.t_rot_mid = gr > 0 ? 2.0 * Kmid[1] / (gr * s->kB) : 0.0;
  ctx.K[0] = Kmid[0];
  ctx.K[1] = Kmid[1];
  if ((st = run_hooks(in, RL_STEP_AFTER_KICK, &ctx))) return st;
  ctx.K[0] = ctx.K[1] = NAN;
  /* 3-4. drift and rotation: over h, or two halves around the operators of the middle */
  const int split = in->has[RL_STEP_MID_DRIFT];
  const double hd = split ? h2 : h;
  rl_rotation_work rw = {hd, in->p.method, in->p.guard_tol, in->p.quat_tol, in->p.quat_maxit,
                         in->q, (const double (*)[3])in->F.k, (const double (*)[3])in->lprev,
                         in->steps, 0, 0, 0, 0.0, 0.0, in->threads};
  if (!fused) drift(in, hd);
  st = rotate_all(in, &rw);
  if (!st && split) {
    st = run_hooks(in, RL_STEP_MID_DRIFT, &ctx);
    if (!st) {
      drift(in, hd);
      st = rotate_all(in, &rw);
      rw.max_h_omega *= 2.0; /* reported as h |Omega| over the whole step */
    }
  }
  if (!st) st = check_state(in, Kmid);
  if (st) return st;
  info.fallbacks = rw.fallbacks;
  info.quat_iterations = rw.quat_iterations;
  info.quat_max_iterations = rw.quat_max_iterations;
  info.max_h_omega = rw.max_h_omega;
  info.quat_norm_defect = rw.quat_norm_defect;
  in->t += h;
  in->steps++;
  if (in->steps % RL_POLISH_INTERVAL == 0) polish_orientations(in);
  in->fallbacks += info.fallbacks;
  in->quat_iterations += info.quat_iterations;
  if ((st = run_hooks(in, RL_STEP_AFTER_DRIFT, &ctx))) return st;

  /* 5. forces at t + h, the energy and virial on the steps of energy_every */
  st = compute_forces(in, in->p.energy_every <= 1 || in->steps % in->p.energy_every == 0);
  if (!st) st = run_hooks(in, RL_STEP_END, &ctx);
  if (out) *out = info;
  return st;
}

int rl_integrator_reverse(rl_integrator *in)
{
  if (!in || !in->initialized) return rl_error(RL_ESTATE, "rl_integrator_reverse: not initialised");
  kick(in, in->p.h, -1.0); /* -(v(t-h/2) + h f/m) = -v(t+h/2) */
  return RL_OK;
}

int rl_integrator_resume(rl_integrator *in, long step, double t)
{
  int st = validate(in->sys, &in->p, in->ops, in->nops);
  if (st) return st;
  if (in->q) { /* quaternions are rebuilt from A: a quaternion restart is exact to round-off */
    rl_system *s = in->sys;
    for (int i = 0; i < s->nmat; i++)
      if ((st = rl_matrix_to_quat(s->A[i], in->q[i]))) return st;
  }
  zero_momentum(in);
  in->steps = step;
  in->t = t;
  in->fallbacks = 0;
  in->quat_iterations = 0;
  zero_work(in);
  if ((st = compute_forces(in, 1))) return st;
  in->initialized = 1;
  return RL_OK;
}

int rl_integrator_finish(rl_integrator *in)
{
  if (!in || !in->initialized) return rl_error(RL_ESTATE, "rl_integrator_finish: not initialised");
  kick(in, 0.5 * in->p.h, 1.0); /* v(t) = v(t-h/2) + h/2 f/m */
  in->initialized = 0;
  return RL_OK;
}

double rl_integrator_thermostat_work(const rl_integrator *in) { return total_work(in); }

void rl_integrator_set_thermostat_work(rl_integrator *in, double w)
{
  zero_work(in);
  if (in->nops) in->ops[0].work = w;
  else in->work = w;
}

/* The first operator with a random state (the thermostat's, when there is one), or NULL. */
static void *first_rng(rl_integrator *in, size_t *size)
{
  for (int k = 0; k < in->nops; k++) {
    void *r = in->ops[k].type->rng_state ? in->ops[k].type->rng_state(&in->ops[k], size) : NULL;
    if (r) return r;
  }
  *size = 0;
  return NULL;
}

size_t rl_integrator_rng_size(const rl_integrator *in)
{
  size_t n;
  first_rng((rl_integrator *)in, &n);
  return n;
}

void *rl_integrator_rng_state(rl_integrator *in)
{
  size_t n;
  return first_rng(in, &n);
}

int rl_integrator_dof(const rl_integrator *in, int *translational, int *rotational)
{
  const int gt = dof_trans(in->sys, in->ops, in->nops), gr = rl_system_dof_rotational(in->sys);
  if (translational) *translational = gt;
  if (rotational) *rotational = gr;
  return gt + gr;
}

const char *rl_integrator_path(const rl_integrator *in, int species)
{
  if (species < 0 || species >= in->sys->nspecies) return NULL;
  const rl_species *sp = &in->sys->sp[species];
  const int matrix = sp->kind == RL_KIND_SPHERICAL || sp->kind == RL_KIND_SYMMETRIC || sp->kind == RL_KIND_ASYMMETRIC ||
                     (in->p.force_general && sp->kind != RL_KIND_POINT);
  switch (matrix ? in->p.method : RL_ROT_CUBIC) {
  case RL_ROT_HYBRID: return "the paper's hybrid: Omega from eq. 28, quaternion Cayley update (rl-hybrid, a baseline)";
  case RL_ROT_FINCHAM: return "Fincham's implicit quaternion leapfrog (a baseline)";
  case RL_ROT_NOSQUISH: return "NO_SQUISH splitting (a baseline)";
  default: break;
  }
  const rl_family *f = rl_family_for(sp->kind, in->p.force_general);
  if (f != &rl_family_asymmetric) return f->path;
  const int forced = sp->kind != RL_KIND_ASYMMETRIC;
  switch (in->p.method) {
  case RL_ROT_EXACT:
    return forced ? "general path forced (system.force_general): eq. 28 solved by Newton (rl-exact)"
                  : "eq. 28 solved by Newton (rl-exact)";
  case RL_ROT_QUATERNION:
    return forced ? "general path forced (system.force_general): quaternions, eq. 23 iterated (rl-quaternion)"
                  : "quaternions, eq. 23 iterated (rl-quaternion)";
  default:
    return forced ? "general path forced (system.force_general): guarded quasi-analytic cubic (eqs. 28-36)" : f->path;
  }
}

long rl_integrator_fallbacks(const rl_integrator *in) { return in->fallbacks; }
long rl_integrator_quat_iterations(const rl_integrator *in) { return in->quat_iterations; }
long rl_integrator_steps(const rl_integrator *in) { return in->steps; }
double rl_integrator_time(const rl_integrator *in) { return in->t; }
const rl_forces *rl_integrator_forces(const rl_integrator *in) { return &in->F; }

void rl_integrator_mid_velocity(const rl_integrator *in, int i, double v[3])
{
  memcpy(v, in->sys->v[i], 3 * sizeof(double));
}

void rl_integrator_mid_angmom(const rl_integrator *in, int i, double l[3])
{
  rl_system_get_angmom(in->sys, i, l);
}

int rl_integrator_quaternion(const rl_integrator *in, int i, double q[4])
{
  const rl_system *s = in->sys;
  if (i < 0 || i >= s->n) return rl_error(RL_EINVAL, "rl_integrator_quaternion: body %d out of range", i);
  const rl_species *sp = &s->sp[s->species_of[i]];
  if (sp->mat_off < 0)
    return rl_error(RL_ESTATE, "body %d (%s) has no orientation quaternion: %s", i, rl_kind_name(sp->kind),
                    sp->axis_off >= 0 ? "only its axis is stored" : "it does not rotate");
  if (!in->q)
    return rl_error(RL_ESTATE, "body %d has no quaternion: rotation method %s does not use one", i,
                    rl_rot_method_name(in->p.method));
  const int b = i - sp->first;
  /* under RL_ROT_QUATERNION only the general path advances q; the spherical and symmetric fast
   * paths advance A, which is then the state, and their q is A's */
  if (in->p.method == RL_ROT_QUATERNION &&
      rl_family_for(sp->kind, in->p.force_general) != &rl_family_asymmetric)
    return rl_matrix_to_quat(s->A[sp->mat_off + b], q);
  memcpy(q, in->q[sp->mat_off + b], 4 * sizeof(double));
  return RL_OK;
}
