/* The Python binding's native part: a deck's simulation (app/: deck -> scene -> relaxation ->
 * production integrator, as `rotleap run` builds it) behind a flat C interface for ctypes
 * (python/rotleap/_native.py declares every function below).  Plain types only: ints, longs,
 * doubles, double arrays the caller owns, and one callback.  Every call that can fail returns
 * an rl status (RL_OK = 0) with the message in rlpy_error(); the library never prints. */
#include "analysis.h"
#include "deck.h"
#include "outputs.h"
#include "runrec.h"
#include "scan.h"
#include "scene.h"
#include "thermo.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define RLPY_API __attribute__((visibility("default")))

/* A run stopped by SIGINT (Ctrl-C) between two steps: rlpy_run's status, for a KeyboardInterrupt. */
#define RLPY_INTERRUPTED (-2)
/* A Python reporter raised: the exception is Python's to re-raise. */
#define RLPY_REPORTER_RAISED (-3)

typedef int (*rlpy_callback)(int reporter);

typedef struct {
  rl_deck d;
  scene s;
  rl_integrator *in;
  rl_watch watch;          /* carried from one run call to the next                    */
  long step;               /* production steps done (from the start's step)            */
  long now;                /* the step of the state during a reporter's call            */
  const rl_run_report *cur;/* the report a Python reporter is reading                  */
  rlpy_callback cb;
  int cb_status;
  rl_run *drv;             /* the run driver of a run in progress (NULL between runs)   */
  running avg[6];          /* the checkpoint's averages, as rotleap run keeps them: the
                              conserved energy, potential, T, T_trans, T_rot, pressure  */
  char *physics;           /* the deck's settings that define the simulation (PHYS)     */
  struct {                 /* the streams the built-in reporters write (OUT_*: thermo,
                              trajectory, topology, analysis journal), which a checkpoint
                              marks as rotleap run marks its own (outputs.h)            */
    char *path;            /* NULL: none                                                */
    out_tracker t;
  } streams[OUT_NSTREAMS];
  analysis *an;            /* rotleap run's analysis, journaled to `journal` (or NULL)  */
  FILE *journal;
  char *text;              /* the last rlpy_thermo_header or rlpy_thermo_row (malloc'd) */
  char note[RL_DECK_PATH_MAX + 4096 + 256]; /* what the start did, as rotleap run notes it on stderr:
                              a checkpoint of other settings started a new run, a new run.seed
                              a new random stream ("" if nothing)                        */
} rlpy_sim;

typedef struct {
  rlpy_sim *sim;
  int index;
} rlpy_rep;

/* --------------------------------------------------------------------------- lifecycle */

RLPY_API const char *rlpy_error(void) { return rl_last_error(); }
RLPY_API const char *rlpy_version(void) { return ROTLEAP_VERSION; }

RLPY_API int rlpy_journal_close(rlpy_sim *p);

RLPY_API void rlpy_close(rlpy_sim *p)
{
  if (!p) return;
  rlpy_journal_close(p);
  for (int k = 0; k < OUT_NSTREAMS; k++) free(p->streams[k].path);
  rl_integrator_free(p->in);
  scene_free(&p->s);
  free(p->physics);
  free(p->text);
  free(p);
}

/* A checkpoint start, as rotleap run decides it (app/run.c, decide_continuation): the run of the
 * same settings continues with its run record (*cont = 1); one of other settings gives only its
 * state, completed to on-step, to a new run from step 0 (a note says so); a checkpoint written
 * during the relaxation is refused (rotleap run finishes that relaxation). */
static int start_record(rlpy_sim *p, run_record *rec, int *cont)
{
  const rl_deck *d = &p->d;
  *cont = 0;
  int st = runrec_decode(p->s.blob, p->s.blob_size, rl_system_count(p->s.sys), d->start, rec);
  if (st) return st;
  if (rec->relax_step >= 0)
    return rl_error(RL_EINVAL, "%s was written during the relaxation (run.equilibrate, at its step %ld): `rotleap run` "
                    "with system.start = %s finishes it; start the simulation from the checkpoint that run writes",
                    d->start, rec->relax_step, d->start);
  char diff[4096];
  if (runrec_other_simulation(rec, p->physics, d->thermostat, diff, sizeof diff)) {
    snprintf(p->note, sizeof p->note, "%s was written by a run with other settings (%s): a new run from its state "
             "(step 0; v and l completed to on-step with run.timestep = %g)", d->start, diff, d->timestep);
    st = scene_onstep(d, &p->s);
    p->s.restart = 0;
    return st;
  }
  *cont = 1;
  return RL_OK;
}

/* The run record of a checkpoint start into the production integrator (start_record's *cont):
 * the neighbour list, random states, accounts and barostat state, the averages and the watch, so
 * that the simulation goes on bit for bit as `rotleap run`'s continuation does. */
static int continue_record(rlpy_sim *p, const run_record *rec)
{
  const rl_deck *d = &p->d;
  const int st = runrec_restore(rec, &p->s, p->in, d->thermostat_seed, d->start, p->note, sizeof p->note);
  if (st) return st;
  const running *avg[6] = {&rec->E, &rec->U, &rec->T, &rec->Tt, &rec->Tr, &rec->P};
  for (int k = 0; k < 6; k++) p->avg[k] = *avg[k];
  if (rec->has_watch) p->watch = rec->watch;
  return RL_OK;
}

/* The deck at `path` with the overrides sets[nsets] ("section.key=value"): the scene, the
 * relaxation (run.equilibrate) and the production integrator, at the step the start gives (0,
 * or a checkpoint's).  NULL with the deck's problems, one a line, or the library's message. */
RLPY_API rlpy_sim *rlpy_open(const char *path, char **sets, int nsets)
{
  rlpy_sim *p = calloc(1, sizeof *p);
  if (!p) { rl_error(RL_ENOMEM, "out of memory"); return NULL; }
  char *msg = NULL;
  size_t len = 0;
  FILE *err = open_memstream(&msg, &len);
  if (!err) { free(p); rl_error(RL_ENOMEM, "out of memory"); return NULL; }
  const int problems = rl_deck_load(path, sets, nsets, &p->d, err);
  fclose(err);
  if (problems) {
    while (len > 0 && msg[len - 1] == '\n') msg[--len] = '\0';
    rl_error(RL_EINVAL, "%s", msg ? msg : "the deck has problems");
    free(msg);
    free(p);
    return NULL;
  }
  free(msg);
  rl_error_clear();
  rl_watch_init(&p->watch);
  if (!(p->physics = runrec_physics(&p->d))) {
    rl_error(RL_ENOMEM, "out of memory");
    rlpy_close(p);
    return NULL;
  }
  run_record rec;
  int cont = 0;
  int st = scene_build(&p->d, &p->s) ? RL_EINVAL : RL_OK;
  if (!st && p->s.restart) st = start_record(p, &rec, &cont);
  if (!st && !p->s.restart) st = scene_relax(&p->d, &p->s);
  if (!st) {
    rl_integrator_params ip;
    scene_integrator_params(&p->d, SCENE_RUN, &ip);
    p->in = rl_integrator_alloc(p->s.sys, &ip, rl_terms_provider(p->s.terms));
    st = !p->in ? RL_EINVAL : scene_add_barostat(&p->d, p->in); /* run.barostat, as rotleap run adds it */
    if (!st) st = cont ? continue_record(p, &rec) : rl_integrator_init(p->in);
  }
  if (st) {
    if (!rl_last_error()[0]) rl_error(st, "cannot build the simulation of %s", path);
    rlpy_close(p);
    return NULL;
  }
  p->step = p->s.restart ? p->s.step0 : 0;
  return p;
}

/* The note of the start (rlpy_sim.note): "" if nothing to say. */
RLPY_API const char *rlpy_note(const rlpy_sim *p) { return p->note; }

/* ------------------------------------------------------------------------------ queries */

RLPY_API int rlpy_count(const rlpy_sim *p) { return rl_system_count(p->s.sys); }
RLPY_API int rlpy_nrot(const rlpy_sim *p) { return rl_system_nrot(p->s.sys); }
RLPY_API long rlpy_step(const rlpy_sim *p) { return p->cur ? p->now : p->step; }
RLPY_API double rlpy_time(const rlpy_sim *p) { return rl_integrator_time(p->in); }
RLPY_API double rlpy_timestep(const rlpy_sim *p) { return p->d.timestep; }
RLPY_API long rlpy_deck_steps(const rlpy_sim *p) { return p->d.steps; }
RLPY_API long rlpy_energy_every(const rlpy_sim *p) { return p->d.energy_every; }
RLPY_API long rlpy_thermo_every(const rlpy_sim *p) { return p->d.thermo_every; }
RLPY_API long rlpy_trajectory_every(const rlpy_sim *p) { return p->d.trajectory_every; }
RLPY_API long rlpy_checkpoint_every(const rlpy_sim *p) { return p->d.checkpoint_every; }
/* 1 if `rotleap run` writes this deck's trajectory as a DCD of the sites (+ PDB), 0: extended XYZ. */
RLPY_API int rlpy_site_trajectory(const rlpy_sim *p) { return rl_deck_site_model(&p->s.mol); }
RLPY_API int rlpy_real_units(const rlpy_sim *p) { return p->d.units == RL_UNITS_REAL; }
RLPY_API const char *rlpy_model(const rlpy_sim *p) { return p->d.model->name; }
RLPY_API long rlpy_fallbacks(const rlpy_sim *p) { return rl_integrator_fallbacks(p->in); }
/* The kind of the bodies (rl_kind: all of one species). */
RLPY_API int rlpy_kind(const rlpy_sim *p) { return (int)rl_system_species_kind(p->s.sys, 0); }
RLPY_API int rlpy_nenergies(const rlpy_sim *p) { return rl_terms_nenergies(p->s.terms); }
RLPY_API const char *rlpy_energy_name(const rlpy_sim *p, int j) { return rl_terms_energy_name(p->s.terms, j); }
RLPY_API void rlpy_box(const rlpy_sim *p, double L[3]) { rl_system_box(p->s.sys, L); }

/* ----------------------------------------------------------------- values of a report */

/* The values of an on-step report, RLPY_NVALUES + nenergies of them: */
enum {
  V_STEP, V_TIME, V_LAST, V_TOTAL, V_POTENTIAL, V_KE_TRANS, V_KE_ROT, V_TEMPERATURE, V_T_TRANS, V_T_ROT,
  V_PRESSURE, V_CONSERVED, V_T_TRANS_MID, V_T_ROT_MID, V_MAX_H_OMEGA, V_FALLBACKS, V_VIRIAL,
  RLPY_NVALUES = V_VIRIAL + 9
};
RLPY_API int rlpy_nvalues(void) { return RLPY_NVALUES; }

static void values(const rlpy_sim *p, const rl_run_report *r, double *out)
{
  const rl_step_info *i = r->info;
  const double v[] = {(double)r->step, r->time, (double)r->last, i->total, i->potential, i->ke_trans, i->ke_rot,
                      i->temperature, i->t_trans, i->t_rot, scene_pressure_out(&p->d, r->pressure), i->conserved,
                      i->t_trans_mid, i->t_rot_mid, i->max_h_omega, (double)i->fallbacks};
  memcpy(out, v, sizeof v);
  memcpy(out + V_VIRIAL, r->forces->virial, sizeof(double[9]));
  for (int j = 0; j < rl_terms_nenergies(r->terms); j++) out[RLPY_NVALUES + j] = r->energies[j];
}

/* The report a Python reporter is called with: STEP (1: values into out) or STATE (0: step and
 * time into out[0], out[1]); RL_ESTATE outside a reporter. */
RLPY_API int rlpy_report(const rlpy_sim *p, double *out)
{
  if (!p->cur) return rl_error(RL_ESTATE, "no report: this is read in a reporter's call");
  if (p->cur->info) {
    values(p, p->cur, out);
    return 1;
  }
  out[0] = (double)p->cur->step;
  out[1] = p->cur->time;
  return 0;
}

/* Forces [n][3] and torques [nrot][3] of a STEP report (at its step). */
RLPY_API int rlpy_report_forces(const rlpy_sim *p, double *f, double *k)
{
  if (!p->cur || !p->cur->forces) return rl_error(RL_ESTATE, "no forces: they are read in a step reporter's call");
  memcpy(f, p->cur->forces->f, sizeof(double[3]) * (size_t)rl_system_count(p->s.sys));
  memcpy(k, p->cur->forces->k, sizeof(double[3]) * (size_t)rl_system_nrot(p->s.sys));
  return RL_OK;
}

/* The on-step values of the current state, as a step report (rl_integrator_observe: the forces
 * and what follows are unchanged). */
RLPY_API int rlpy_observe(rlpy_sim *p, double *out)
{
  rl_step_info info;
  int st = rl_integrator_observe(p->in, &info);
  if (st) return st;
  double comp[64];
  const int ne = rl_terms_nenergies(p->s.terms);
  for (int j = 0; j < ne && j < 64; j++) comp[j] = rl_terms_energy(p->s.terms, j);
  const rl_forces *F = rl_integrator_forces(p->in);
  rl_run_report r = {p->step, info.t, 1, &info, comp, rl_forces_pressure(p->s.sys, F, info.ke_trans), F,
                     p->s.sys, p->s.terms, {0.0, 0.0, 0.0}};
  rl_system_box(p->s.sys, r.box); /* the state observed is at the current box */
  values(p, &r, out);
  return RL_OK;
}

/* ------------------------------------------------------------------------- thermo rows */

/* The thermo file's header and rows, formatted by app/thermo.c as `rotleap run` writes them. */
static const char *keep_text(rlpy_sim *p, char *text, int ok)
{
  free(p->text);
  p->text = text;
  if (!ok || !text) {
    if (!text) rl_error(RL_ENOMEM, "out of memory");
    return NULL;
  }
  return text;
}

/* The header line (with its newline) of rotleap run's PREFIX.thermo.csv for this simulation: the
 * energy terms' columns, and those of its barostat and its species.  The string lives until the
 * next rlpy_thermo_* call or rlpy_close; NULL with a message. */
RLPY_API const char *rlpy_thermo_header(rlpy_sim *p) { return keep_text(p, thermo_header(&p->d, &p->s), 1); }

/* The row (with its newline) of rotleap run's PREFIX.thermo.csv for the report a step reporter is
 * called with, its calE from the simulation's running statistics of the conserved quantity over
 * every step with energies since its production began (those a checkpoint's run record keeps, as
 * rotleap run's).  As rlpy_thermo_header; NULL outside a step reporter's call. */
RLPY_API const char *rlpy_thermo_row(rlpy_sim *p)
{
  if (!p->cur || !p->cur->info) {
    rl_error(RL_ESTATE, "a thermo row is read in a step reporter's call");
    return NULL;
  }
  char *row = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&row, &len);
  if (!f) return keep_text(p, NULL, 0);
  const int st = thermo_row(f, "the thermo row", &p->d, &p->s, p->cur, &p->avg[0]);
  if (fclose(f) && !st) {
    free(row);
    return keep_text(p, NULL, 0);
  }
  return keep_text(p, row, !st);
}

/* ------------------------------------------------------------------------------ running */

static volatile sig_atomic_t got_sigint;
static void on_sigint(int sig) { (void)sig; got_sigint = 1; }

static int call_python(void *ctx, const rl_run_report *r)
{
  rlpy_rep *rep = ctx;
  rlpy_sim *p = rep->sim;
  p->cur = r;
  p->now = r->info && !r->last ? r->step + 1 : r->step; /* a step report comes after the step */
  const int st = p->cb(rep->index);
  p->cur = NULL;
  if (st) {
    p->cb_status = st;
    return rl_error(RL_EINVAL, "reporter %d raised an exception", rep->index);
  }
  return RL_OK;
}

/* The averages a checkpoint's run record carries, on the steps with energies, and the
 * analysis's record of the step when it has a journal (rotleap run's report_averages). */
static int report_averages(void *ctx, const rl_run_report *r)
{
  rlpy_sim *p = ctx;
  if (r->last) return RL_OK;
  const double x[6] = {r->info->conserved, r->info->potential, r->info->temperature, r->info->t_trans, r->info->t_rot,
                       scene_pressure_out(&p->d, r->pressure)};
  if (p->an) {
    const int st = analysis_step(p->an, r->info, x[5], r->forces, r->sys, r->box);
    if (st) return rl_error_wrap(st, "step %ld", r->step);
  }
  for (int k = 0; k < 6; k++) running_add(&p->avg[k], x[k]);
  return RL_OK;
}

/* The analysis's sample of the state (output.sample_every), as rotleap run's report_sample. */
static int report_sample(void *ctx, const rl_run_report *r)
{
  const int st = analysis_sample(((rlpy_sim *)ctx)->an, r->sys);
  return st ? rl_error_wrap(st, "step %ld", r->step) : RL_OK;
}

/* nsteps production steps with the reporters when[i] (RL_REPORT_STEP 0 / RL_REPORT_STATE 1)
 * every[i] steps, each calling cb(i); with `finish`, the row of the last state to the STEP
 * reporters (last = 1) as `rotleap run` writes it.  With catch_sigint (the caller's main
 * thread), SIGINT stops the run between two steps: RLPY_INTERRUPTED, *done steps taken.  A
 * reporter returning nonzero stops it: RLPY_REPORTER_RAISED. */
RLPY_API int rlpy_run(rlpy_sim *p, long nsteps, int nrep, const int *when, const long *every, rlpy_callback cb,
                      int finish, int catch_sigint, long *done)
{
  *done = 0;
  if (nsteps < 0) return rl_error(RL_EINVAL, "steps = %ld: a run takes 0 or more steps", nsteps);
  rl_run *drv = scene_run_driver(&p->d, &p->s, p->in);
  if (!drv) return RL_ENOMEM;
  *rl_run_watch(drv) = p->watch;
  rlpy_rep *reps = calloc((size_t)(nrep > 0 ? nrep : 1), sizeof *reps);
  int st = reps ? RL_OK : rl_error(RL_ENOMEM, "out of memory");
  p->cb = cb;
  p->cb_status = 0;
  const rl_reporter avg = {"averages", RL_REPORT_STEP, p->d.energy_every, report_averages, p};
  if (!st) st = rl_run_add_reporter(drv, &avg);
  const rl_reporter smp = {"samples", RL_REPORT_STATE, p->d.sample_every, report_sample, p};
  if (!st && p->an && p->d.sample_every > 0) st = rl_run_add_reporter(drv, &smp);
  for (int i = 0; !st && i < nrep; i++) {
    reps[i] = (rlpy_rep){p, i};
    char name[32];
    snprintf(name, sizeof name, "python reporter %d", i);
    const rl_reporter r = {name, when[i] ? RL_REPORT_STATE : RL_REPORT_STEP, every[i], call_python, &reps[i]};
    st = rl_run_add_reporter(drv, &r);
  }
  struct sigaction old, sa;
  if (!st && catch_sigint) {
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    got_sigint = 0;
    sigaction(SIGINT, &sa, &old);
  }
  if (!st) {
    p->drv = drv;
    st = rl_run_steps(drv, p->step, p->step + nsteps, catch_sigint ? &got_sigint : NULL, done);
    p->step += *done;
    p->watch = *rl_run_watch(drv);
    if (!st && finish && !(catch_sigint && got_sigint)) st = rl_run_finish(drv, p->step);
  }
  if (catch_sigint) sigaction(SIGINT, &old, NULL);
  if (p->cb_status) st = RLPY_REPORTER_RAISED;
  else if (!st && catch_sigint && got_sigint) st = RLPY_INTERRUPTED;
  free(reps);
  p->drv = NULL;
  rl_run_free(drv);
  return st;
}

/* ----------------------------------------------------------- the library's writers */

/* A checkpoint of the current state (in a state reporter's call: the state after its step) at
 * `path`, with the run record `rotleap run` writes: the averages, thermostat account and random
 * state, neighbour-list origin, watch, the deck's settings, and the marks of the streams given
 * to rlpy_stream (MARK_FINAL: they are written under their names), of stream k's first len[k]
 * bytes (len NULL or len[k] < 0: all it holds; the journal is synced first). */
RLPY_API int rlpy_checkpoint(rlpy_sim *p, const char *path, const long *len)
{
  if (p->cur && p->cur->info) return rl_error(RL_ESTATE, "a checkpoint is written from a state reporter or between runs");
  const long step = p->cur ? p->cur->step : p->step;
  const double time = p->cur ? p->cur->time : rl_integrator_time(p->in);
  run_record r;
  memset(&r, 0, sizeof r);
  r.version = 5;
  r.E = p->avg[0]; r.U = p->avg[1]; r.T = p->avg[2]; r.Tt = p->avg[3]; r.Tr = p->avg[4]; r.P = p->avg[5];
  r.done = step;
  r.thermostat = p->d.thermostat;
  r.seed = p->d.thermostat_seed;
  r.physics = p->physics;
  r.physics_len = strlen(p->physics);
  r.has_watch = 1;
  r.watch = p->drv ? *rl_run_watch(p->drv) : p->watch;
  r.relax_step = -1;
  int st = p->an && p->streams[OUT_SAMPLES].path ? analysis_journal_sync(p->an, NULL) : RL_OK;
  for (int k = 0; k < OUT_NSTREAMS && !st; k++)
    if (p->streams[k].path) st = outputs_mark_file(p->streams[k].path, &p->streams[k].t, len ? len[k] : -1, &r.marks[k]);
  return st ? st : runrec_write_checkpoint(path, p->s.sys, p->s.ff, p->in, &r, step, time);
}

/* Stream k (OUT_THERMO 0, OUT_TRAJ 1, OUT_TOPOLOGY 2, OUT_SAMPLES 3) is the file at `path`, written
 * from here on, with `skip` leading bytes outside its hash (a DCD's header); path NULL: none. */
RLPY_API int rlpy_stream(rlpy_sim *p, int k, const char *path, long skip)
{
  if (k < 0 || k >= OUT_NSTREAMS) return rl_error(RL_EINVAL, "stream %d: no such stream", k);
  char *copy = path ? strdup(path) : NULL;
  if (path && !copy) return rl_error(RL_ENOMEM, "out of memory");
  free(p->streams[k].path);
  p->streams[k].path = copy;
  p->streams[k].t = (out_tracker){skip, skip, OUTPUTS_HASH_INIT};
  return RL_OK;
}

/* rotleap run's analysis from here on, journaled to a new file at `path` (rotleap run's
 * PREFIX.samples, which its continuation replays), with a record of every step with energies and
 * a sample every output.sample_every steps. */
RLPY_API int rlpy_journal_open(rlpy_sim *p, const char *path)
{
  if (p->an) return rl_error(RL_EINVAL, "the simulation has an analysis journal already");
  int fd, st = rl_file_create(path, &fd);
  if (st) return st;
  if (!(p->journal = fdopen(fd, "w"))) {
    close(fd);
    return rl_error(RL_EINVAL, "cannot open %s: %s", path, strerror(errno));
  }
  if (!(p->an = analysis_alloc(&p->d, p->s.mols, p->s.sys))) st = RL_EINVAL;
  if (!st) st = analysis_set_tconf(p->an, p->s.terms, p->s.ff);
  if (!st) st = analysis_set_journal(p->an, p->journal, path);
  if (st) rlpy_journal_close(p);
  return st;
}

/* Ends the analysis and closes its journal (checked). */
RLPY_API int rlpy_journal_close(rlpy_sim *p)
{
  analysis_free(p->an);
  p->an = NULL;
  int st = RL_OK;
  if (p->journal && fclose(p->journal) != 0) st = rl_error(RL_EINVAL, "cannot write the analysis journal: %s", strerror(errno));
  p->journal = NULL;
  return st;
}

/* A trajectory written with io/'s writers as `rotleap run` writes PREFIX.dcd (dcd = 1: the
 * sites, first frame at the current step + every, with `topology` the PDB of the current state)
 * or PREFIX.xyz (dcd = 0: centres and axes or orientations).  NULL with a message. */
typedef struct {
  rl_dcd *dcd;
  FILE *xyz;
  char *path;
} rlpy_traj;

RLPY_API int rlpy_traj_close(rlpy_traj *t)
{
  if (!t) return RL_OK;
  int st = RL_OK;
  if (t->dcd) st = rl_dcd_close(t->dcd);
  if (t->xyz && fclose(t->xyz) && !st) st = rl_error(RL_EINVAL, "cannot write %s: %s", t->path, strerror(errno));
  free(t->path);
  free(t);
  return st;
}

RLPY_API rlpy_traj *rlpy_traj_open(rlpy_sim *p, const char *path, int dcd, long every, const char *topology)
{
  rlpy_traj *t = calloc(1, sizeof *t);
  if (!t || !(t->path = strdup(path))) {
    free(t);
    rl_error(RL_ENOMEM, "out of memory");
    return NULL;
  }
  int st = RL_OK;
  if (dcd) {
    if (topology) {
      const rl_molecule *mols[1] = {&p->s.mol};
      st = rl_pdb_write(topology, p->s.sys, mols);
    }
    if (!st && !(t->dcd = rl_dcd_create(path, p->s.sys, rlpy_step(p) + every, every, p->d.timestep, "rotleap"))) st = RL_EINVAL;
  } else if (!(t->xyz = fopen(path, "w"))) st = rl_error(RL_EINVAL, "cannot create %s: %s", path, strerror(errno));
  if (st) {
    rlpy_traj_close(t);
    return NULL;
  }
  return t;
}

/* The leading bytes of the trajectory file outside its mark's hash: a DCD's header, which every
 * frame rewrites (0 for XYZ); -1 with a message. */
RLPY_API long rlpy_traj_skip(const rlpy_traj *t)
{
  long header = 0, frame;
  if (t->dcd && rl_dcd_layout(t->path, &header, &frame)) return -1;
  return header;
}

/* The frame of the current state (in a state reporter's call: after its step). */
RLPY_API int rlpy_traj_frame(rlpy_sim *p, rlpy_traj *t)
{
  if (t->dcd) return rl_dcd_write_frame(t->dcd, p->s.sys);
  const long step = p->cur ? p->cur->step : p->step;
  const double time = p->cur ? p->cur->time : rl_integrator_time(p->in);
  int st = rl_xyz_write_frame(t->xyz, t->path, p->s.sys, time, step);
  if (!st && (ferror(t->xyz) || fflush(t->xyz))) st = rl_error(RL_EINVAL, "cannot write %s: %s", t->path, strerror(errno));
  return st;
}

/* -------------------------------------------------------------------------- the state */

/* Quantities: 0 centres [n][3], 1 velocities [n][3] (v(t - h/2), as the leapfrog and a checkpoint
 * hold them), 2 angular momenta [nrot][3] (lab frame, l(t - h/2)), 3 orientations [n][9] (A: lab
 * to body), 4 axes [n][3] (point dipoles, linear bodies), 5 forces [n][3], 6 torques [nrot][3]. */
enum { Q_POS, Q_VEL, Q_ANGMOM, Q_ORIENT, Q_AXIS, Q_FORCE, Q_TORQUE };

static int matrix_kind(rl_kind k) { return k != RL_KIND_POINT && k != RL_KIND_DIPOLE && k != RL_KIND_LINEAR; }
static int axis_kind(rl_kind k) { return k == RL_KIND_DIPOLE || k == RL_KIND_LINEAR; }

static int check_quantity(const rlpy_sim *p, int q)
{
  const rl_kind k = (rl_kind)rlpy_kind(p);
  if (q == Q_ORIENT && !matrix_kind(k))
    return rl_error(RL_EINVAL, "the bodies (%s) have no orientation matrix%s", rl_kind_name(k),
                    axis_kind(k) ? ": use axes" : "");
  if (q == Q_AXIS && !axis_kind(k))
    return rl_error(RL_EINVAL, "the bodies (%s) have no axis%s", rl_kind_name(k), matrix_kind(k) ? ": use orientations" : "");
  if (q < Q_POS || q > Q_TORQUE) return rl_error(RL_EINVAL, "quantity %d: no such quantity", q);
  return RL_OK;
}

RLPY_API int rlpy_get(const rlpy_sim *p, int q, double *out)
{
  int st = check_quantity(p, q);
  if (st) return st;
  const rl_system *s = p->s.sys;
  const int n = rl_system_count(s);
  const rl_forces *F = rl_integrator_forces(p->in);
  if (q == Q_FORCE) memcpy(out, F->f, sizeof(double[3]) * (size_t)n);
  if (q == Q_TORQUE) memcpy(out, F->k, sizeof(double[3]) * (size_t)rl_system_nrot(s));
  for (int i = 0; i < n && q < Q_FORCE; i++) {
    const int ri = rl_system_rot_index(s, i);
    if (q == Q_POS) rl_system_get_position(s, i, out + 3 * i);
    else if (q == Q_VEL) rl_system_get_velocity(s, i, out + 3 * i);
    else if (q == Q_ANGMOM && ri >= 0) rl_system_get_angmom(s, i, out + 3 * ri);
    else if (q == Q_ORIENT) rl_system_get_orientation(s, i, out + 9 * i);
    else if (q == Q_AXIS) rl_system_get_axis(s, i, out + 3 * i);
  }
  return RL_OK;
}

/* Sets one quantity (not forces or torques) of every body, then resumes the integrator at the
 * same step and time: forces at the new state, v and l taken as the half-step values they are
 * read as, the thermostat's account and random state kept.  A value the system refuses (an
 * orientation that is not orthonormal, an axis that is not unit) is an error naming the body,
 * and the quantity is left as it was. */
static int set_all(rl_system *s, int q, const double *in)
{
  int st = RL_OK;
  for (int i = 0; i < rl_system_count(s) && !st; i++) {
    const int ri = rl_system_rot_index(s, i);
    if (q == Q_POS) st = rl_system_set_position(s, i, in + 3 * i);
    else if (q == Q_VEL) st = rl_system_set_velocity(s, i, in + 3 * i);
    else if (q == Q_ANGMOM && ri >= 0) st = rl_system_set_angmom(s, i, in + 3 * ri);
    else if (q == Q_ORIENT) st = rl_system_set_orientation(s, i, in + 9 * i);
    else if (q == Q_AXIS) st = rl_system_set_axis(s, i, in + 3 * i);
    if (st) rl_error_wrap(st, "body %d", i);
  }
  return st;
}

/* The integrator resumed at the same step and time from the current state (forces recomputed,
 * v and l taken as the half-step values they are read as), the thermostat's account and random
 * state kept. */
static int resume_here(rlpy_sim *p)
{
  const size_t nrng = rl_integrator_rng_size(p->in);
  void *rng = nrng ? malloc(nrng) : NULL;
  if (nrng && !rng) return rl_error(RL_ENOMEM, "out of memory");
  if (rng) memcpy(rng, rl_integrator_rng_state(p->in), nrng);
  const double work = rl_integrator_thermostat_work(p->in);
  const int st = rl_integrator_resume(p->in, p->step, rl_integrator_time(p->in));
  if (rng) memcpy(rl_integrator_rng_state(p->in), rng, nrng);
  rl_integrator_set_thermostat_work(p->in, work);
  free(rng);
  return st;
}

RLPY_API int rlpy_set(rlpy_sim *p, int q, const double *in)
{
  int st = check_quantity(p, q);
  if (!st && q >= Q_FORCE) st = rl_error(RL_EINVAL, "forces and torques are computed, not set");
  if (st) return st;
  rl_system *s = p->s.sys;
  const size_t n = (size_t)rl_system_count(s) * (q == Q_ORIENT ? 9 : 3);
  double *old = malloc(sizeof(double) * (n ? n : 1));
  if (!old) return rl_error(RL_ENOMEM, "out of memory");
  rlpy_get(p, q, old);
  st = set_all(s, q, in);
  if (st) { /* the quantity as it was (values the system took before), the message kept */
    char msg[1024];
    snprintf(msg, sizeof msg, "%s", rl_last_error());
    set_all(s, q, old);
    free(old);
    return rl_error(st, "%s", msg);
  }
  free(old);
  return resume_here(p);
}

/* ------------------------------------------------------ a force term written in Python */

/* cb(f[n][3], k[nrot][3], virial[9], &energy, forces_only): adds its forces and lab torques (and
 * virial) to the arrays and sets its energy; nonzero if it raised. */
typedef int (*rlpy_force_cb)(double *f, double *k, double *virial, double *energy, int forces_only);

typedef struct { rlpy_force_cb cb; } rlpy_ext;

static void *ext_alloc(const rl_system *sys, const void *params)
{
  (void)sys;
  rlpy_ext *e = malloc(sizeof *e);
  if (e) *e = *(const rlpy_ext *)params;
  else rl_error(RL_ENOMEM, "out of memory");
  return e;
}

static int ext_compute(void *state, const rl_system *sys, rl_forces *out, double *energies)
{
  (void)sys;
  const rlpy_ext *e = state;
  double u = 0.0;
  if (e->cb(&out->f[0][0], out->k ? &out->k[0][0] : NULL, out->virial, &u, out->forces_only))
    return rl_error(RL_EINVAL, "the Python external force raised an exception");
  energies[0] = u;
  if (!out->forces_only) out->energy += u;
  return RL_OK;
}

static void ext_free(void *state) { free(state); }

static const rl_term_type rlpy_external_term = {
    "python", "a force term written in Python (rotleap.Simulation.add_external_force): one Python call per force "
    "computation", "", 1, {"external"}, ext_alloc, ext_compute, NULL, ext_free};

/* Adds the Python term cb to the simulation's sum (one per simulation) and resumes the step at
 * the current state with the forces recomputed (the thermostat's random state kept). */
RLPY_API int rlpy_add_external(rlpy_sim *p, rlpy_force_cb cb)
{
  if (rl_terms_find(p->s.terms, &rlpy_external_term)) return rl_error(RL_EINVAL, "the simulation has an external force already");
  const rlpy_ext e = {cb};
  int st = rl_terms_add(p->s.terms, &rlpy_external_term, &e, NULL);
  if (st) return st;
  return resume_here(p);
}

/* ------------------------------------------------------------------------------ scan */

/* `rotleap scan` with its arguments (those after "scan"): 0, 1 (a failure) or 2 (bad usage or
 * deck), its table on stdout and messages on stderr (flushed), its files under output.prefix. */
RLPY_API int rlpy_scan(int argc, char **argv)
{
  const int st = rl_app_scan(argc, argv);
  fflush(stdout);
  fflush(stderr);
  return st;
}

/* -------------------------------------------------------------------------- the catalogue */

RLPY_API int rlpy_catalog_count(void) { return rl_catalog_count(); }

/* Text fields of model i: 0 name, 1 description, 2 reference, 3 units ("real", "lj"), 4 family
 * (rl_kind_name); parameter k's name (10 + k) and unit (20 + k).  NULL out of range. */
RLPY_API const char *rlpy_catalog_text(int i, int field)
{
  const rl_model *m = i >= 0 && i < rl_catalog_count() ? rl_catalog_get(i) : NULL;
  if (!m) return NULL;
  switch (field) {
  case 0: return m->name;
  case 1: return m->description;
  case 2: return m->reference;
  case 3: return m->units == RL_UNITS_REAL ? "real" : "lj";
  case 4: return rl_kind_name(m->family);
  }
  if (field >= 10 && field < 10 + m->nparams) return m->param_names[field - 10];
  if (field >= 20 && field < 20 + m->nparams) return m->param_units[field - 20];
  return NULL;
}

/* Parameter count of model i and their defaults (defaults[RL_MODEL_MAX_PARAMS]). */
RLPY_API int rlpy_catalog_params(int i, double *defaults)
{
  const rl_model *m = rl_catalog_get(i);
  for (int k = 0; k < m->nparams; k++) defaults[k] = m->param_defaults[k];
  return m->nparams;
}

/* A molecule's mass, inertia[3], and per site (up to RL_MOLECULE_MAX_SITES) names[8 each],
 * body-frame positions [3], masses, sigma, epsilon, charge, dipole and quadrupole (along body
 * Z); the number of sites. */
static int molecule_out(const rl_molecule *m, double *mass, double *inertia, char *names, double *sites,
                        double *site_mass, double *sigma, double *epsilon, double *charge, double *dipole,
                        double *quadrupole)
{
  *mass = m->mass;
  memcpy(inertia, m->inertia, sizeof m->inertia);
  for (int s = 0; s < m->nsites; s++) {
    memcpy(names + 8 * s, m->site_names[s], 8);
    memcpy(sites + 3 * s, m->sites[s], sizeof m->sites[s]);
    site_mass[s] = m->site_mass[s];
    sigma[s] = m->sigma[s];
    epsilon[s] = m->epsilon[s];
    charge[s] = m->charge[s];
    dipole[s] = m->dipole[s];
    quadrupole[s] = m->quadrupole[s];
  }
  return m->nsites;
}

/* Model i built with its default parameters (molecule_out's arrays); -1 with a message. */
RLPY_API int rlpy_catalog_molecule(int i, double *mass, double *inertia, char *names, double *sites, double *site_mass,
                                   double *sigma, double *epsilon, double *charge, double *dipole, double *quadrupole)
{
  rl_molecule m;
  if (rl_model_build(rl_catalog_get(i), NULL, 0, &m)) return -1;
  return molecule_out(&m, mass, inertia, names, sites, site_mass, sigma, epsilon, charge, dipole, quadrupole);
}

/* The simulation's molecule (the deck's model with its parameters), as rlpy_catalog_molecule. */
RLPY_API int rlpy_molecule(const rlpy_sim *p, double *mass, double *inertia, char *names, double *sites,
                           double *site_mass, double *sigma, double *epsilon, double *charge, double *dipole,
                           double *quadrupole)
{
  return molecule_out(&p->s.mol, mass, inertia, names, sites, site_mass, sigma, epsilon, charge, dipole, quadrupole);
}

/* The deck's interactions: out[0] cutoff, 1 scheme (rl_cutoff_scheme), 2 LJ truncation
 * (rl_lj_truncation), 3 dispersion correction, 4 eps_rf, 5 coulomb (rl_deck_coulomb), 6 Ewald
 * tolerance, 7 alpha (0: derived), 8-10 PME grid (0: derived), 11 PME order, 12 eps' (inf:
 * tin foil), 13-15 Ewald kmax (0: derived), 16 dipole method (rl_dipole_method). */
RLPY_API void rlpy_interactions(const rlpy_sim *p, double *out)
{
  const rl_deck *d = &p->d;
  const rl_ewald_params *e = &d->ewald;
  const double v[] = {d->ff.cutoff, d->ff.scheme, d->ff.lj_truncation, d->ff.dispersion_correction, d->ff.eps_rf,
                      d->coulomb, e->tolerance, e->alpha, e->grid[0], e->grid[1], e->grid[2], e->order,
                      e->eps_surface, e->kmax[0], e->kmax[1], e->kmax[2], d->ff.dipole_method};
  memcpy(out, v, sizeof v);
}
