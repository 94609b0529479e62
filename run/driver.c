/* The run driver (run.h): step, energies on their cadence, watch, reporters. */
#include "rotleap/run.h"
#include "rotleap/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_COMPONENTS 64

struct rl_run {
  rl_system *sys;
  rl_integrator *in;
  rl_terms *terms;
  rl_run_params p;
  rl_watch watch;
  rl_reporter *rep;
  int nrep, caprep;
  rl_forces snap;                  /* forces, torques, virial at t_k (steps with energies)       */
  double comp[MAX_COMPONENTS];     /* the terms' energy components at t_k                        */
};

rl_run *rl_run_alloc(rl_system *sys, rl_integrator *in, rl_terms *terms, const rl_run_params *p)
{
  if (!sys || !in || !terms || !p) { rl_error(RL_EINVAL, "rl_run_alloc: NULL argument"); return NULL; }
  if (rl_terms_nenergies(terms) > MAX_COMPONENTS) {
    rl_error(RL_EINVAL, "rl_run_alloc: more than %d energy components", MAX_COMPONENTS);
    return NULL;
  }
  rl_run *r = calloc(1, sizeof *r);
  const int n = rl_system_count(sys), nr = rl_system_nrot(sys);
  if (r) {
    r->snap.f = calloc((size_t)(n > 0 ? n : 1), sizeof(double[3]));
    r->snap.k = calloc((size_t)(nr > 0 ? nr : 1), sizeof(double[3]));
  }
  if (!r || !r->snap.f || !r->snap.k) {
    rl_run_free(r);
    rl_error(RL_ENOMEM, "out of memory for the run driver");
    return NULL;
  }
  r->sys = sys;
  r->in = in;
  r->terms = terms;
  r->p = *p;
  if (r->p.energy_every < 1) r->p.energy_every = 1;
  rl_watch_init(&r->watch);
  return r;
}

void rl_run_free(rl_run *r)
{
  if (!r) return;
  free(r->snap.f);
  free(r->snap.k);
  free(r->rep);
  free(r);
}

int rl_run_add_reporter(rl_run *r, const rl_reporter *rep)
{
  if (!r || !rep || !rep->report || rep->every < 1) return rl_error(RL_EINVAL, "rl_run_add_reporter: a reporter needs a function and every >= 1");
  if (rep->when == RL_REPORT_STEP && rep->every % r->p.energy_every)
    return rl_error(RL_EINVAL, "reporter '%s': every %ld steps is not a multiple of the energy cadence %ld",
                    rep->name ? rep->name : "?", rep->every, r->p.energy_every);
  if (r->nrep == r->caprep) {
    const int cap = r->caprep ? 2 * r->caprep : 8;
    rl_reporter *p = realloc(r->rep, sizeof *p * (size_t)cap);
    if (!p) return rl_error(RL_ENOMEM, "out of memory");
    r->rep = p;
    r->caprep = cap;
  }
  r->rep[r->nrep++] = *rep;
  return RL_OK;
}

rl_watch *rl_run_watch(rl_run *r) { return &r->watch; }

/* The library's check of a STEP report: every energy component, the total, the virial and the
 * pressure finite. */
static int default_check(void *ctx, const rl_run_report *rep)
{
  (void)ctx;
  double total = 0.0;
  for (int j = 0; j < rl_terms_nenergies(rep->terms); j++) {
    total += rep->energies[j];
    if (!isfinite(rep->energies[j]))
      return rl_error(RL_ENONFINITE, "the %s energy of the %s term is %g, not finite", rl_terms_energy_name(rep->terms, j),
                      rl_terms_type(rep->terms, rl_terms_energy_term(rep->terms, j))->name, rep->energies[j]);
  }
  if (!isfinite(total)) return rl_error(RL_ENONFINITE, "the total energy is %g, not finite", total);
  if (!isfinite(rep->pressure)) return rl_error(RL_ENONFINITE, "the pressure is %g, not finite (the virial)", rep->pressure);
  for (int k = 0; k < 9; k++)
    if (!isfinite(rep->forces->virial[k]))
      return rl_error(RL_ENONFINITE, "virial element %d%d is %g: not finite", k / 3 + 1, k % 3 + 1, rep->forces->virial[k]);
  return RL_OK;
}

static int check(rl_run *r, const rl_run_report *rep)
{
  const int st = r->p.check ? r->p.check(r->p.check_ctx, rep) : default_check(NULL, rep);
  return st ? rl_error_wrap(st, "step %ld (t = %g)", rep->step, rep->time) : RL_OK;
}

static int call(rl_reporter *rep, const rl_run_report *r)
{
  const int st = rep->report(rep->ctx, r);
  return st && !rl_last_error()[0] ? rl_error(st, "reporter '%s' failed", rep->name ? rep->name : "?") : st;
}

int rl_run_steps(rl_run *r, long first, long last, const volatile sig_atomic_t *stop, long *done)
{
  const int n = rl_system_count(r->sys), nr = rl_system_nrot(r->sys), ne = rl_terms_nenergies(r->terms);
  long steps = 0;
  int st = RL_OK;
  for (long k = first; k < last; k++) {
    if (stop && *stop) break;
    /* the values at t_k, before the step moves the state on: the energy components and, on the
     * steps with energies, forces, torques and virial (the integrator computes forces only on
     * the others; init and resume always compute all) */
    const int ev = k % r->p.energy_every == 0;
    for (int j = 0; j < ne; j++) r->comp[j] = rl_terms_energy(r->terms, j);
    const rl_forces *F = rl_integrator_forces(r->in);
    if (ev) {
      memcpy(r->snap.virial, F->virial, sizeof r->snap.virial);
      r->snap.energy = F->energy;
      memcpy(r->snap.f, F->f, sizeof(double[3]) * (size_t)n);
      if (nr) memcpy(r->snap.k, F->k, sizeof(double[3]) * (size_t)nr);
    }
    rl_step_info info;
    if ((st = rl_integrator_step(r->in, &info))) break; /* the library's message names the step and the cause */
    if (ev && !info.has_energy) { /* cannot happen: the integrator has the same energy cadence */
      st = rl_error(RL_ESTATE, "internal error: no energies at step %ld (the driver's energy cadence %ld is not the "
                    "integrator's)", k, r->p.energy_every);
      break;
    }
    if ((st = rl_watch_step(&r->watch, &r->p.watch, r->sys, &info, k, r->p.energy_every, r->p.h))) break;
    rl_run_report step = {k, info.t, 0, &info, r->comp, NAN, &r->snap, r->sys, r->terms};
    if (ev) {
      step.pressure = rl_forces_pressure(r->sys, &r->snap, info.ke_trans);
      if ((st = check(r, &step))) break;
    }
    const rl_run_report state = {k + 1, rl_integrator_time(r->in), 0, NULL, NULL, NAN, NULL, r->sys, r->terms};
    steps++;
    for (int q = 0; q < r->nrep && !st; q++) {
      rl_reporter *rep = &r->rep[q];
      if (rep->when == RL_REPORT_STEP && k % rep->every == 0) st = call(rep, &step);
      else if (rep->when == RL_REPORT_STATE && (k + 1) % rep->every == 0) st = call(rep, &state);
    }
    if (st) break;
  }
  if (done) *done = steps;
  return st;
}

int rl_run_finish(rl_run *r, long step)
{
  rl_step_info info;
  int st = rl_integrator_observe(r->in, &info);
  if (st) return st;
  const int ne = rl_terms_nenergies(r->terms);
  for (int j = 0; j < ne; j++) r->comp[j] = rl_terms_energy(r->terms, j);
  const rl_forces *F = rl_integrator_forces(r->in);
  rl_run_report rep = {step, info.t, 1, &info, r->comp, rl_forces_pressure(r->sys, F, info.ke_trans), F, r->sys, r->terms};
  if ((st = check(r, &rep))) return st;
  for (int q = 0; q < r->nrep && !st; q++)
    if (r->rep[q].when == RL_REPORT_STEP) st = call(&r->rep[q], &rep);
  return st;
}
