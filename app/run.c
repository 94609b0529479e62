/* rotleap run: deck -> scene -> relaxation -> production loop -> outputs.  The physics lives in
 * the library; this file owns the run's files (outputs.h), its checkpoints (runrec.h), signals
 * and messages. */
#include "run.h"
#include "analysis.h"
#include "outputs.h"
#include "quantity.h"
#include "runrec.h"
#include "scene.h"
#include "thermo.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static const char *pressure_unit(const rl_deck *d) { return d->units == RL_UNITS_REAL ? "bar" : "reduced"; }
static const char *energy_unit(const rl_deck *d) { return d->units == RL_UNITS_REAL ? "kJ/mol" : "reduced"; }

/* The energy components of the terms' last computation, into comp[rl_terms_nenergies]. */
static void energy_components(const rl_terms *t, double *comp)
{
  for (int j = 0; j < rl_terms_nenergies(t); j++) comp[j] = rl_terms_energy(t, j);
}

int rl_app_energy(const rl_deck *d, int json)
{
  scene s;
  /* from a checkpoint, whose v and l are half a step behind, the kinetic part of the pressure
   * uses them completed to on-step with run.timestep, as the run's own thermo row does */
  if (scene_build(d, &s) || scene_onstep(d, &s)) {
    fprintf(stderr, "rotleap energy: %s\n", rl_last_error());
    scene_free(&s);
    return 1;
  }
  int n = rl_system_count(s.sys), nr = rl_system_nrot(s.sys);
  rl_forces F = {calloc((size_t)n, sizeof(double[3])), calloc((size_t)(nr > 0 ? nr : 1), sizeof(double[3])), 0.0, {0}, 0};
  int st = F.f && F.k ? rl_terms_compute(s.terms, s.sys, &F) : RL_ENOMEM;
  if (st) {
    fprintf(stderr, "rotleap energy: %s\n", rl_last_error());
    free(F.f); free(F.k); scene_free(&s);
    return 1;
  }
  double comp[64];
  energy_components(s.terms, comp);
  const int ne = rl_terms_nenergies(s.terms);
  double ke = 0.0;
  for (int i = 0; i < n; i++) {
    double v[3];
    rl_system_get_velocity(s.sys, i, v);
    ke += 0.5 * s.mols[rl_system_species_of(s.sys, i)].mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  double P = scene_pressure_out(d, rl_forces_pressure(s.sys, &F, ke));
  /* a NaN is an error naming its term, as in a run, never a number printed with exit 0 */
  st = scene_check_finite(d, s.terms, comp, F.virial, P);
  for (int i = 0; !st && i < n; i++) {
    const int ri = rl_system_rot_index(s.sys, i);
    for (int c = 0; c < 3; c++)
      if (!isfinite(F.f[i][c]) || (ri >= 0 && !isfinite(F.k[ri][c]))) {
        st = rl_error(RL_ENONFINITE, "the force or torque on molecule %d is not finite", i);
        break;
      }
  }
  if (st) {
    fprintf(stderr, "rotleap energy: %s\n", rl_last_error());
    free(F.f); free(F.k); scene_free(&s);
    return 1;
  }
  const char *L = d->units == RL_UNITS_REAL ? "nm" : "reduced";
  if (json) {
    printf("{\"units\": {\"energy\": \"%s\", \"length\": \"%s\", \"force\": \"%s/%s\", \"torque\": \"%s\", "
           "\"pressure\": \"%s\"},\n \"energy\": {\"total\": %.17g", energy_unit(d), L, energy_unit(d), L,
           energy_unit(d), pressure_unit(d), F.energy);
    for (int j = 0; j < ne; j++) printf(", \"%s\": %.17g", rl_terms_energy_name(s.terms, j), comp[j]);
    printf("},\n \"terms\": [");
    for (int k = 0; k < rl_terms_count(s.terms); k++)
      printf("%s\"%s\"", k ? ", " : "", rl_terms_type(s.terms, k)->name);
    printf("],\n \"virial\": [");
    for (int k = 0; k < 9; k++) printf("%.17g%s", F.virial[k], k < 8 ? ", " : "");
    printf("],\n \"pressure\": %.17g,\n \"molecules\": [", P);
    for (int i = 0; i < n; i++) {
      int ri = rl_system_rot_index(s.sys, i);
      double z[3] = {0, 0, 0};
      const double *k = ri >= 0 ? F.k[ri] : z;
      printf("%s\n  {\"force\": [%.17g, %.17g, %.17g], \"torque\": [%.17g, %.17g, %.17g]}", i ? "," : "",
             F.f[i][0], F.f[i][1], F.f[i][2], k[0], k[1], k[2]);
    }
    printf("\n ]}\n");
  } else {
    printf("# energies in %s, forces in %s/%s, torques in %s, pressure in %s\n", energy_unit(d),
           energy_unit(d), L, energy_unit(d), pressure_unit(d));
    printf("term,value\ntotal,%.17g\n", F.energy);
    for (int j = 0; j < ne; j++) printf("%s,%.17g\n", rl_terms_energy_name(s.terms, j), comp[j]);
    printf("pressure,%.17g\n", P);
    printf("\nmolecule,fx,fy,fz,tx,ty,tz\n");
    for (int i = 0; i < n; i++) {
      int ri = rl_system_rot_index(s.sys, i);
      double z[3] = {0, 0, 0};
      const double *k = ri >= 0 ? F.k[ri] : z;
      printf("%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", i, F.f[i][0], F.f[i][1], F.f[i][2], k[0], k[1], k[2]);
    }
  }
  free(F.f); free(F.k); scene_free(&s);
  return 0;
}

static double now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* 1 if paths a and b name one existing file. */
static int same_file(const char *a, const char *b)
{
  struct stat sa, sb;
  return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

/* ------------------------------------------------------------------------------ signals */

/* SIGINT and SIGTERM, from the relaxation to the last output: the step in progress ends and the
 * run stops as if run.steps had been reached there (a checkpoint, the rows and the summary with
 * status = interrupted), exit status 128 + the signal.  The first signal restores the default
 * action of both, so that a second one, of either kind, stops at once.  A run killed by SIGKILL
 * leaves its files under their working names (outputs.h), which a continuation of its last
 * checkpoint takes up. */
static volatile sig_atomic_t got_signal;
static const int caught_sigs[2] = {SIGINT, SIGTERM};
static int sig_ignored[2]; /* a signal ignored at the start (a background job's SIGINT) stays so */

static void default_actions(void)
{
  for (int k = 0; k < 2; k++) {
    if (sig_ignored[k]) continue;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = SIG_DFL;
    sigemptyset(&sa.sa_mask);
    sigaction(caught_sigs[k], &sa, NULL);
  }
}

static void on_signal(int sig)
{
  got_signal = sig;
  default_actions(); /* sigaction is async-signal-safe */
}

static void catch_signals(int on)
{
  if (!on) { default_actions(); return; }
  for (int k = 0; k < 2; k++) {
    struct sigaction sa, old;
    sigaction(caught_sigs[k], NULL, &old);
    sig_ignored[k] = old.sa_handler == SIG_IGN;
    if (sig_ignored[k]) continue;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(caught_sigs[k], &sa, NULL);
  }
}

static const char *signal_text(int sig) { return sig == SIGINT ? "interrupted (SIGINT)" : "terminated (SIGTERM)"; }

/* ------------------------------------------------------------------------------ the run */

typedef struct {
  const rl_deck *d;
  scene s;
  outputs *out;
  char *chk_path, *chk_prev, *summary_path;
  char *physics;
  char *header;         /* the thermo file's header (thermo_header)                         */
  int site;             /* a DCD of the sites + PDB topology, else extended XYZ            */
  int same_prefix;      /* system.start is this prefix's checkpoint                        */
  int resumed;          /* the streams continue those of the checkpoint's run              */
  int moved_prev;       /* this run moved an earlier PREFIX.chk to PREFIX.chk.prev          */
  int streams;          /* the streams are open                                            */
  rl_integrator *in;
  rl_run *drv;          /* the library's run driver (run.h): the loop, its watch, the reporters */
  int progress;         /* a progress line on stderr                                        */
  double t0, last_progress; /* wall clock at the start, and at the last progress line       */
  analysis *an;
  FILE *thermo, *xyz, *journal; /* the analysis journal: PREFIX.samples (outputs.h)           */
  long journal_len;      /* its bytes at the checkpoint continued, to replay             */
  int journal_copied;    /* ... copied from the run of another prefix                    */
  rl_dcd *dcd;
  running E, U, T, Tt, Tr, P; /* E: the conserved quantity (the total energy in NVE)      */
  rl_watch watch;
  long first, done;
  int stopped;          /* the signal that ended the run                                    */
  long last_chk;        /* the step of the last checkpoint this run wrote or continues (-1)  */
  long relax_done;      /* relaxation steps done (for messages)                             */
  scene_relaxation *relax; /* a relaxation stopped by a signal, for its checkpoint          */
  char start_note[RL_DECK_PATH_MAX + 1024]; /* what is wrong with the start, if its energy says so (start_check) */
  int heats;             /* a term's energy jumps at the cutoff by orientation: an NVE run heats */
  char heats_term[64];   /* ... the first such term                                          */
} run_ctx;

/* A checkpoint at `step`, `time` of the integrator `in` (the production's, or the relaxation's
 * with relax_step >= 0).  marks: the streams' marks (NULL: taken now, if the streams are open).
 * Before the first checkpoint of a run that does not continue this prefix's own, an earlier
 * PREFIX.chk is kept as PREFIX.chk.prev until the run completes (its outputs stay complete). */
static int write_checkpoint(run_ctx *c, rl_integrator *in, long step, double time, long relax_step, double relax_time,
                            const out_mark *marks)
{
  const rl_deck *d = c->d;
  run_record r;
  memset(&r, 0, sizeof r);
  r.version = 5;
  r.E = c->E; r.U = c->U; r.T = c->T; r.Tt = c->Tt; r.Tr = c->Tr; r.P = c->P;
  r.done = relax_step >= 0 ? 0 : step;
  r.thermostat = relax_step >= 0 ? RL_THERMO_BUSSI : d->thermostat;
  r.seed = relax_step >= 0 ? d->seed + 2 : d->thermostat_seed;
  r.physics = c->physics;
  r.physics_len = strlen(c->physics);
  int st = RL_OK;
  if (marks) memcpy(r.marks, marks, sizeof r.marks);
  else if (c->streams) st = outputs_mark(c->out, r.marks);
  r.has_watch = 1;
  r.watch = c->watch;
  r.relax_step = relax_step;
  r.relax_time = relax_time;
  if (!st && !c->same_prefix && !c->moved_prev && access(c->chk_path, F_OK) == 0) {
    if (rename(c->chk_path, c->chk_prev) != 0)
      st = rl_error(RL_EINVAL, "cannot keep the earlier %s as %s: %s", c->chk_path, c->chk_prev, strerror(errno));
    else c->moved_prev = 1;
  }
  if (!st) st = runrec_write_checkpoint(c->chk_path, c->s.sys, c->s.ff, in, &r, relax_step >= 0 ? 0 : step, time);
  if (!st) c->last_chk = relax_step >= 0 ? 0 : step;
  return st;
}

/* The outputs a run under this prefix writes, for the check that none of them is the deck or
 * the start (scene_check_outputs). */
static int check_overwrites(const rl_deck *d, const outputs *o)
{
  static const char *const whole[] = {".chk", ".chk.prev", ".summary.txt", ".summary.txt.part", ".results.txt",
                                      ".results.txt.part", ".rdf.csv", ".rdf.csv.part", ".tcf.csv", ".tcf.csv.part",
                                      ".thermo.csv.prev", ".lock"};
  enum { NW = sizeof whole / sizeof whole[0] };
  char *names[NW + 2 * OUT_NSTREAMS];
  int n = 0, st = RL_OK;
  for (int k = 0; k < NW; k++) names[n++] = outputs_name(d->prefix, whole[k]);
  for (int k = 0; k < OUT_NSTREAMS; k++)
    if (outputs_path(o, k)) {
      names[n++] = outputs_name(outputs_path(o, k), "");
      names[n++] = outputs_name(outputs_part(o, k), "");
    }
  for (int k = 0; k < n && !st; k++)
    if (!names[k]) st = rl_error(RL_ENOMEM, "out of memory");
  if (!st) st = scene_check_outputs(d, (const char *const *)names, n);
  for (int k = 0; k < n; k++) free(names[k]);
  return st;
}

/* A run that writes new streams under this prefix would replace the working files of an
 * unfinished run there (killed, failed or stopped) that PREFIX.chk continues: refused, saying
 * how to continue it or let it go. */
static int check_unfinished(run_ctx *c)
{
  const rl_deck *d = c->d;
  if (access(c->chk_path, F_OK) != 0 || (d->start[0] && same_file(d->start, c->chk_path))) return RL_OK;
  rl_checkpoint_meta meta;
  memset(&meta, 0, sizeof meta);
  rl_system *sys = rl_checkpoint_load(c->chk_path, &meta);
  if (!sys) return RL_OK; /* not a checkpoint this run could continue: it is replaced */
  run_record r;
  int unfinished = 0;
  if (!runrec_decode(meta.blob, meta.blob_size, rl_system_count(sys), c->chk_path, &r))
    for (int k = 0; k < OUT_NSTREAMS; k++)
      if (r.marks[k].where == MARK_PART && outputs_part_matches(c->out, k, &r.marks[k])) unfinished = 1;
  const long step = meta.step;
  free((void *)meta.blob);
  rl_system_free(sys);
  if (!unfinished) return RL_OK;
  return rl_error(RL_EINVAL, "%s.*.part hold the outputs of an unfinished run (killed, stopped by an error or out of disk "
                  "space) up to its checkpoint %s at step %ld, which this run would replace: continue it with "
                  "system.start = %s, or let it go (rm %s.*.part %s) and run again, or give another output.prefix",
                  d->prefix, c->chk_path, step, c->chk_path, d->prefix, c->chk_path);
}

/* The analysis journal: continued (rec), copied from another prefix's run (other), or new. */
static int open_journal(run_ctx *c, const run_record *rec, const run_record *other)
{
  outputs *o = c->out;
  const out_mark *m = rec ? &rec->marks[OUT_SAMPLES] : other ? &other->marks[OUT_SAMPLES] : NULL;
  if (m && m->where != MARK_NONE) {
    int st;
    if (rec) st = outputs_resume(o, OUT_SAMPLES, m, outputs_path(o, OUT_SAMPLES), outputs_part(o, OUT_SAMPLES));
    else { /* the journal of the checkpoint's run, beside its checkpoint (PREFIX.chk: PREFIX.samples) */
      const size_t n = strlen(c->d->start);
      char *pre = n > 4 ? strndup(c->d->start, n - 4) : NULL;
      char *path = pre ? outputs_name(pre, ".samples") : NULL, *part = path ? outputs_name(path, ".part") : NULL;
      st = part ? outputs_resume(o, OUT_SAMPLES, m, path, part) : rl_error(RL_ENOMEM, "out of memory");
      free(pre);
      free(path);
      free(part);
      if (st) { /* a new journal instead */
        fprintf(stderr, "rotleap run: warning: the results cover the steps of this run only, from step %ld: %s\n",
                c->first, rl_last_error());
        st = RL_OK;
        m = NULL;
      }
      c->journal_copied = m != NULL;
    }
    if (st) return st;
    if (m) {
      c->journal_len = m->len;
      return (c->journal = outputs_append(o, OUT_SAMPLES)) ? RL_OK : RL_EINVAL;
    }
  }
  return (c->journal = outputs_create(o, OUT_SAMPLES)) ? RL_OK : RL_EINVAL;
}

/* The analysis takes its journal: a continuation replays the part its checkpoint covers first. */
static int attach_journal(run_ctx *c)
{
  const char *part = outputs_part(c->out, OUT_SAMPLES);
  int st = c->journal_len > 0 ? analysis_replay(c->an, part, c->journal_len) : RL_OK;
  if (st && c->journal_copied) { /* another prefix's journal this run cannot use: a new one */
    fprintf(stderr, "rotleap run: warning: the results cover the steps of this run only, from step %ld: %s\n", c->first,
            rl_last_error());
    analysis_free(c->an);
    c->an = analysis_alloc(c->d, c->s.mols, c->s.sys);
    if (!c->an || !(c->journal = outputs_create(c->out, OUT_SAMPLES))) return RL_EINVAL;
    st = RL_OK;
  }
  if (!st) st = analysis_set_tconf(c->an, c->s.terms, c->s.ff); /* output.tconf */
  return st ? st : analysis_set_journal(c->an, c->journal, part);
}

/* The streams of this run: new working files (a new run, or a continuation under another
 * prefix, whose rows and frames start at its first step), or those of the checkpoint's run
 * continued from its marks (rec: a continuation under this prefix).  The analysis journal
 * (PREFIX.samples) of a continuation under another prefix is copied from the journal of the
 * checkpoint's run (other), so that the results cover the whole run; if it cannot be, the
 * results cover this run's steps, and the run says so. */
static int open_streams(run_ctx *c, const run_record *rec, const run_record *other)
{
  const rl_deck *d = c->d;
  outputs *o = c->out;
  int st = RL_OK;
  if (rec && rec->marks[OUT_THERMO].where != MARK_NONE) {
    if (!(st = outputs_resume(o, OUT_THERMO, &rec->marks[OUT_THERMO], outputs_path(o, OUT_THERMO), outputs_part(o, OUT_THERMO))))
      if (!(c->thermo = outputs_append(o, OUT_THERMO))) st = RL_EINVAL;
  } else if (!(c->thermo = outputs_create(o, OUT_THERMO))) st = RL_EINVAL;
  else if (!c->header || fputs(c->header, c->thermo) < 0)
    st = rl_error(RL_EINVAL, "cannot write %s: %s", outputs_part(o, OUT_THERMO), strerror(errno));
  c->streams = 1;
  if (!st) st = open_journal(c, rec, other);
  if (st || d->trajectory_every <= 0) return st;
  const int resume = rec && rec->marks[OUT_TRAJ].where != MARK_NONE;
  if (c->site) { /* the DCD; its PDB topology is written by open_topology, at the production's start */
    long header, frame;
    if (resume) {
      if (!(st = outputs_resume(o, OUT_TRAJ, &rec->marks[OUT_TRAJ], outputs_path(o, OUT_TRAJ), outputs_part(o, OUT_TRAJ))) &&
          !(st = rl_dcd_layout(outputs_part(o, OUT_TRAJ), &header, &frame)) &&
          !(c->dcd = rl_dcd_append(outputs_part(o, OUT_TRAJ), c->s.sys, (rec->marks[OUT_TRAJ].len - header) / frame)))
        st = RL_EINVAL;
      if (!st && rec->marks[OUT_TOPOLOGY].where != MARK_NONE)
        st = outputs_resume(o, OUT_TOPOLOGY, &rec->marks[OUT_TOPOLOGY], outputs_path(o, OUT_TOPOLOGY),
                            outputs_part(o, OUT_TOPOLOGY));
    } else {
      c->dcd = rl_dcd_create(outputs_part(o, OUT_TRAJ), c->s.sys, c->first + d->trajectory_every, d->trajectory_every,
                             d->timestep, "rotleap");
      if (!c->dcd || rl_dcd_layout(outputs_part(o, OUT_TRAJ), &header, &frame)) st = RL_EINVAL;
      else outputs_started(o, OUT_TRAJ, header);
    }
  } else if (resume) {
    if (!(st = outputs_resume(o, OUT_TRAJ, &rec->marks[OUT_TRAJ], outputs_path(o, OUT_TRAJ), outputs_part(o, OUT_TRAJ))))
      if (!(c->xyz = outputs_append(o, OUT_TRAJ))) st = RL_EINVAL;
  } else if (!(c->xyz = outputs_create(o, OUT_TRAJ))) st = RL_EINVAL;
  return st;
}

/* The DCD's PDB topology: the production's starting state (after the relaxation), written once
 * by the run that starts the trajectory. */
static int open_topology(run_ctx *c)
{
  if (!c->site || c->d->trajectory_every <= 0 || outputs_started_p(c->out, OUT_TOPOLOGY)) return RL_OK;
  const rl_molecule *mols[1] = {&c->s.mol};
  const int st = rl_pdb_write(outputs_part(c->out, OUT_TOPOLOGY), c->s.sys, mols);
  if (!st) outputs_started(c->out, OUT_TOPOLOGY, 0);
  return st;
}

static int traj_frame(run_ctx *c, double time, long step)
{
  if (c->dcd) return rl_dcd_write_frame(c->dcd, c->s.sys);
  const char *path = outputs_part(c->out, OUT_TRAJ);
  int st = rl_xyz_write_frame(c->xyz, path, c->s.sys, time, step);
  if (!st && ferror(c->xyz)) st = rl_error(RL_EINVAL, "cannot write %s: %s", path, strerror(errno));
  return st;
}

/* What the interactions do at the cutoff, said before the run (the library never prints): setup
 * warnings (a cutoff shorter than the LJ well, no pair in range), and every term whose energy or
 * force jumps at the cutoff, with what that does to energy conservation.  A term whose energy
 * jumps by orientation (the dipolar reaction field, say) heats an NVE run at any time step: the
 * summary's drift warning then names it rather than the time step. */
static void report_setup(run_ctx *c)
{
  const rl_forcefield *ff = c->s.ff;
  rl_ff_warning w[8];
  const int nw = rl_forcefield_warnings(ff, w, 8);
  for (int k = 0; k < nw && k < 8; k++) fprintf(stderr, "rotleap run: warning: %s\n", w[k].text);
  char line[1024];
  if (scene_electrostatics(c->d, c->s.terms, line, sizeof line)) fprintf(stderr, "rotleap run: note: electrostatics: %s\n", line);
  const int ne = scene_ewald_warnings(c->s.terms, w, 8);
  for (int k = 0; k < ne && k < 8; k++) fprintf(stderr, "rotleap run: warning: %s\n", w[k].text);
  rl_ff_discontinuity dd[8];
  const int nd = rl_forcefield_discontinuities(ff, dd, 8);
  for (int k = 0; k < nd && k < 8; k++) {
    if (!dd[k].energy_jumps && !dd[k].force_jumps) continue;
    fprintf(stderr, "rotleap run: %s: %s\n", dd[k].heats ? "warning" : "note", dd[k].text);
    if (dd[k].heats && !c->heats) {
      c->heats = 1;
      snprintf(c->heats_term, sizeof c->heats_term, "%s", dd[k].term);
    }
  }
}

/* A start whose energy is far above a liquid's (U/N > 5 kT) has overlapping molecules, and a
 * failure in its first steps (a rotation that cannot be solved, an energy jump) is theirs, not
 * the time step's: the note names the molecule with the largest force and its nearest
 * neighbour, for the messages of such failures. */
static void start_check(run_ctx *c)
{
  const rl_deck *d = c->d;
  rl_system *sys = c->s.sys;
  const int n = rl_system_count(sys), nr = rl_system_nrot(sys);
  c->start_note[0] = '\0';
  rl_forces F = {calloc((size_t)(n > 0 ? n : 1), sizeof(double[3])), calloc((size_t)(nr > 0 ? nr : 1), sizeof(double[3])),
                 0.0, {0}, 0};
  const double kT = rl_units_kB(d->units) * (d->thermostat_temperature > 0 ? d->thermostat_temperature : d->temperature);
  int st = F.f && F.k ? rl_terms_compute(c->s.terms, sys, &F) : RL_ENOMEM;
  if (!st && n > 1 && kT > 0 && F.energy / (n * kT) > 5.0) {
    int worst = 0;
    double fmax = -1.0;
    for (int i = 0; i < n; i++) {
      const double f = sqrt(F.f[i][0] * F.f[i][0] + F.f[i][1] * F.f[i][1] + F.f[i][2] * F.f[i][2]);
      if (f > fmax) { fmax = f; worst = i; }
    }
    double ri[3], best = INFINITY, L[3];
    int near = -1;
    rl_system_box(sys, L);
    rl_system_get_position(sys, worst, ri);
    for (int j = 0; j < n; j++) {
      if (j == worst) continue;
      double rj[3], r2 = 0.0;
      rl_system_get_position(sys, j, rj);
      for (int k = 0; k < 3; k++) {
        double x = rj[k] - ri[k];
        x -= L[k] * nearbyint(x / L[k]);
        r2 += x * x;
      }
      if (r2 < best) { best = r2; near = j; }
    }
    snprintf(c->start_note, sizeof c->start_note, "the start's U/N is %.3g kT (a liquid's is negative): it has overlapping "
             "molecules; molecule %d (the one with the largest force, %.3g %s/%s) has its centre %.3g %s from molecule "
             "%d's%s%s: relax the start (run.equilibrate with a small run.equilibrate_timestep), lower the density, or mend "
             "the start", F.energy / (n * kT), worst, fmax, d->units == RL_UNITS_REAL ? "kJ/mol" : "epsilon",
             rl_dim_unit(Q_LENGTH, d->units), sqrt(best), rl_dim_unit(Q_LENGTH, d->units), near,
             d->start[0] ? " in " : "", d->start[0] ? d->start : "");
  }
  free(F.f);
  free(F.k);
}

/* The library's message for a failed step; for a non-finite potential energy, also the term
 * that is not finite; in the first steps of an overlapping start, what overlaps. */
static void step_error(const run_ctx *c, int st)
{
  const rl_deck *d = c->d;
  const scene *s = &c->s;
  char msg[1024], term[1024] = "";
  snprintf(msg, sizeof msg, "%s", rl_last_error());
  if (st == RL_ENONFINITE && s->terms) {
    double comp[64];
    energy_components(s->terms, comp);
    if (scene_check_finite(d, s->terms, comp, NULL, 0.0)) snprintf(term, sizeof term, ": %s", rl_last_error());
  }
  /* the start's note, unless the watch already blamed overlapping molecules */
  const int early = c->done < 20 && c->first == 0 && !strstr(msg, "overlapping molecules");
  rl_error(st, "%s%s%s%s", msg, term, early && c->start_note[0] ? "; " : "", early ? c->start_note : "");
  fprintf(stderr, "rotleap run: %s\n", rl_last_error());
}

/* The species line of the summary: family, rotation path, degrees of freedom and how far apart
 * the principal moments are (a molecule just outside the tolerance for calling two equal is
 * integrated by a slower path: visible here, and warned about). */
static int species_line(const run_ctx *c, int sp, char *buf, size_t cap)
{
  const rl_molecule *m = &c->s.mols[sp];
  const rl_system *sys = c->s.sys;
  const rl_kind kind = rl_system_species_kind(sys, sp);
  const int user = rl_deck_user_model(c->d->species[sp].model) != NULL;
  const double *J = m->inertia, Jmax = fmax(J[0], fmax(J[1], J[2]));
  const char *path = c->in ? rl_integrator_path(c->in, sp) : rl_kind_rotation_path(kind);
  int n = snprintf(buf, cap, "species = %s x %d: %s, %d+%d dof, rotation path: %s", m->name, c->d->species[sp].count, rl_kind_name(kind),
                   3, rl_kind_rotational_dof(kind), path ? path : "?");
  if (kind != RL_KIND_POINT && Jmax > 0 && n > 0 && (size_t)n < cap) {
    const double d01 = fabs(J[0] - J[1]) / Jmax, d12 = fabs(J[1] - J[2]) / Jmax, d02 = fabs(J[0] - J[2]) / Jmax;
    char scaled[96] = "";
    if (c->d->inertia_scale != 1.0)
      snprintf(scaled, sizeof scaled, " (the model's times system.inertia_scale = %g: heavier rotors)", c->d->inertia_scale);
    n += snprintf(buf + n, cap - (size_t)n, "; principal moments %.6g %.6g %.6g %s%s, relative differences %.3g (X-Y) %.3g "
                  "(Y-Z) %.3g (X-Z), equal below %g\n", J[0], J[1], J[2], c->d->units == RL_UNITS_REAL ? "amu nm^2" : "m sigma^2",
                  scaled, d01, d12, d02, RL_INERTIA_RTOL);
    const double dd[3] = {d01, d12, d02};
    for (int k = 0; k < 3 && n > 0 && (size_t)n < cap; k++)
      if (dd[k] > RL_INERTIA_RTOL && dd[k] <= RL_DECK_SYMMETRIZE_RTOL) {
        n += snprintf(buf + n, cap - (size_t)n, "warning = two principal moments of %s differ by %.3g relative, just above "
                      "the tolerance %g for calling them equal: it is integrated as %s, not by the faster path of a "
                      "more symmetric top; if the difference is rounding in its coordinates, %s%s%s\n",
                      m->name, dd[k], RL_INERTIA_RTOL, rl_kind_name(kind),
                      user ? "add symmetrize = yes to [molecule " : "symmetrise the model",
                      user ? m->name : "", user ? "] (moments within 1e-4 "
                      "relative are then made equal)" : "");
        break;
      }
  } else if (n > 0 && (size_t)n < cap) n += snprintf(buf + n, cap - (size_t)n, "\n");
  return n;
}

/* One species line per species (system.species: in its order). */
static int species_text(const run_ctx *c, char *buf, size_t cap)
{
  int n = 0;
  for (int sp = 0; sp < c->d->nspecies && n >= 0 && (size_t)n < cap; sp++) {
    const int k = species_line(c, sp, buf + n, cap - (size_t)n);
    if (k < 0) return k;
    n += k;
  }
  return n;
}

/* Whether the conserved energy drifts more than the time step alone explains, and why, in buf:
 * a drift above SCENE_DRIFT_WARN kT per molecule per time unit in a window, or a mean drift over
 * the windows above 0.01 and above three times its standard error.  A symplectic step on a
 * potential smooth at the cutoff conserves the energy with no trend; a drift comes from the
 * isokinetic scheme's undamped mode (scene_drift_mode), from a term whose energy jumps at the
 * cutoff by orientation (report_setup: it heats at any time step), or from a time step too large
 * for the dynamics.  0 if there is no such drift. */
static int drift_warning(const run_ctx *c, char *buf, size_t cap)
{
  const rl_deck *d = c->d;
  double sem;
  const double mean = rl_watch_drift(&c->watch, &sem);
  const char *tunit = d->units == RL_UNITS_REAL ? rl_dim_unit(Q_TIME, d->units) : "time unit";
  const int window = fabs(c->watch.max_rate) > SCENE_DRIFT_WARN;
  const int trend = isfinite(sem) && fabs(mean) > 0.01 && fabs(mean) > 3.0 * sem;
  if (!window && !trend) return 0;
  char size[160];
  if (trend) snprintf(size, sizeof size, "by %.3g +- %.2g kT per molecule per %s on average", mean, sem, tunit);
  else snprintf(size, sizeof size, "by up to %.3g kT per molecule per %s in a window of %g %s", c->watch.max_rate, tunit,
                SCENE_WINDOW, tunit);
  if (scene_drift_mode(d, c->watch.alt_at_max))
    snprintf(buf, cap, "the conserved energy drifts %s: the isokinetic thermostat's undamped step-to-step alternation of "
             "the kinetic energy (+-%.2g %% of run.temperature; a start out of equilibrium at run.temperature), not the "
             "time step; relax the start at run.temperature (run.equilibrate) or use run.ensemble = nvt-bussi", size,
             100.0 * c->watch.alt_at_max);
  else if (c->heats)
    snprintf(buf, cap, "the conserved energy drifts %s: the %s energy jumps at the cutoff by orientation, which heats a "
             "run at any time step (a smaller time step does not remove it; the warning before the run names the "
             "continuous alternative)", size, c->heats_term);
  else
    snprintf(buf, cap, "the conserved energy drifts %s: integration error is %s the system; the time step %g %s is too "
             "large for accurate dynamics (a smaller one will change the results)", size,
             (trend ? mean : c->watch.max_rate) > 0 ? "heating" : "cooling", d->timestep, rl_dim_unit(Q_TIME, d->units));
  return 1;
}

/* The summary: whole-run averages (they survive continuations), what ran, and the status. */
static int write_summary(run_ctx *c, const char *path, const char *status, const char *error, double wall, int io_bad)
{
  const rl_deck *d = c->d;
  const int n = d->count;
  const rl_forcefield *ff = c->s.ff;
  char au[160] = "n/a (no step with energies)", at[200] = "n/a", ap[160] = "n/a";
  if (c->U.n > 0) {
    snprintf(au, sizeof au, "%.8g +- sd %.3g %s", c->U.mean / n, running_sd(&c->U) / n, energy_unit(d));
    snprintf(at, sizeof at, "%.6g (translational %.6g, rotational %.6g)%s", c->T.mean, c->Tt.mean, c->Tr.mean,
             d->units == RL_UNITS_LJ ? "" : " K");
    snprintf(ap, sizeof ap, "%.6g +- sd %.3g %s", c->P.mean, running_sd(&c->P), pressure_unit(d));
  }
  char cE[64], cU[64], cEU[64], species[RL_DECK_MAX_SPECIES * 1024];
  /* relative fluctuations (0 with fewer than two steps; n/a where a mean is 0) */
  const double calE = c->E.n > 1 ? running_sd(&c->E) / fabs(c->E.mean) : 0.0,
               calU = c->U.n > 1 ? running_sd(&c->U) / fabs(c->U.mean) : 0.0;
  const char *tunit = d->units == RL_UNITS_REAL ? rl_dim_unit(Q_TIME, d->units) : "time unit";
  species_text(c, species, sizeof species);
  double sem;
  const double drift = rl_watch_drift(&c->watch, &sem);
  char drift_fit[200] = "n/a (fewer than two windows)";
  if (isfinite(sem)) snprintf(drift_fit, sizeof drift_fit, "%.3g +- %.2g kT per molecule per %s (mean over %ld windows)",
                              drift, sem, tunit, c->watch.nwin);
  rl_rot_method m = d->method;
  FILE *f = NULL;
  char *text = NULL;
  size_t len = 0;
  if (!(f = open_memstream(&text, &len))) return rl_error(RL_ENOMEM, "out of memory for the summary");
  fprintf(f, "# rotleap %s summary of %s\n", ROTLEAP_VERSION, d->path);
  fprintf(f, "status = %s\n", status);
  if (error) fprintf(f, "error = %s\n", error);
  if (c->stopped) fprintf(f, "stopped_by = %s\n", signal_text(c->stopped));
  if (c->relax_done >= 0 && c->relax_done < d->equilibrate_steps)
    fprintf(f, "relaxation = stopped at step %ld of %ld (system.start = %s continues it)\n", c->relax_done,
            d->equilibrate_steps, c->chk_path);
  char model[RL_DECK_MAX_SPECIES * 40] = "";
  for (int k = 0, o = 0; k < d->nspecies && o >= 0 && (size_t)o < sizeof model; k++)
    o += snprintf(model + o, sizeof model - (size_t)o, "%s%s", k ? " + " : "", d->species[k].model->name);
  fprintf(f, "steps = %ld of %ld (this invocation: %ld)\nmodel = %s\nmolecules = %d\n%sunits = %s\n", c->first + c->done,
          d->steps, c->done, model, n, species, d->units == RL_UNITS_LJ ? "lj" : "real");
  fprintf(f, "integrator = %s\ntimestep = %g %s\nenergy_every = %ld (the averages below are over these steps)\n",
          rl_rot_method_name(m), d->timestep, rl_dim_unit(Q_TIME, d->units), d->energy_every);
  fprintf(f, "neighbour_list = skin %.4g %s, %ld builds in this invocation\n", scene_skin(d, scene_lightest(d, c->s.mols)),
          rl_dim_unit(Q_LENGTH, d->units), ff ? rl_forcefield_rebuilds(ff) : 0L);
  char elec[1024];
  if (scene_electrostatics(d, c->s.terms, elec, sizeof elec)) fprintf(f, "electrostatics = %s\n", elec);
  fprintf(f, "pair_kernels = %s (%s rows, %d thread(s), %s precision)\nwall_seconds = %.3f\nfallbacks = %ld\n",
          ff ? rl_forcefield_kernel(ff) : "none", ff ? rl_forcefield_rows(ff) : "no", ff ? rl_forcefield_threads(ff) : 1,
          ff ? rl_forcefield_precision(ff) : "double", wall, c->in ? rl_integrator_fallbacks(c->in) : 0L);
  if (d->nspecies > 1) { /* a mixture: which kernel computes the pairs of each two species */
    fprintf(f, "pair_kernels_by_species =");
    for (int a = 0; a < d->nspecies; a++)
      for (int b = a; b < d->nspecies; b++)
        fprintf(f, "%s %s/%s: %s", a + b ? ";" : "", c->s.mols[a].name, c->s.mols[b].name,
                ff ? rl_forcefield_pair_kernel(ff, a, b) : "general");
    fprintf(f, " (general: the reference routine)\n");
  }
  fprintf(f, "U_per_molecule = %s\ntemperature = %s\npressure = %s\n", au, at, ap);
  fprintf(f, "calE = %s (relative fluctuation of the conserved quantity: the total energy%s)\ncalU = %s\n"
          "calE_over_calU = %s\n", rel_fluct_text(cE, sizeof cE, calE),
          d->thermostat == RL_THERMO_NONE ? ", conserved in NVE" : " plus the energy the thermostat took out",
          rel_fluct_text(cU, sizeof cU, calU), rel_fluct_text(cEU, sizeof cEU, calU > 0 ? calE / calU : c->U.n > 1 ? NAN : 0.0));
  fprintf(f, "rigidity_error = %.3g (max |A A^T - I| or ||rho| - 1| at the end)\n", scene_rigidity_error(c->s.sys));
  fprintf(f, "conserved_drift = %.3g kT per molecule per %s (largest over windows of %g %s; %s)\n", c->watch.max_rate, tunit,
          SCENE_WINDOW, tunit, c->watch.max_rate != 0.0 ? "above 0.5 warns, above 5 stops" : "the run was shorter than one window");
  fprintf(f, "conserved_drift_mean = %s\n", drift_fit);
  char dw[1024];
  if (drift_warning(c, dw, sizeof dw)) fprintf(f, "warning = %s\n", dw);
  if (io_bad) fprintf(f, "warning = some output files could not be written (the messages on stderr say which)\n");
  if (fclose(f) != 0) { free(text); return rl_error(RL_ENOMEM, "out of memory for the summary"); }
  rl_atomic_file af;
  int st = rl_atomic_open(&af, path);
  if (!st && fputs(text, af.fp) < 0) {
    st = rl_error(RL_EINVAL, "cannot write %s: %s", path, strerror(errno));
    rl_atomic_abort(&af);
  } else if (!st) st = rl_atomic_commit(&af);
  if (!st && !error) fputs(text, stdout);
  free(text);
  return st;
}

/* ---------------------------------------------------------- the run's reporters (run.h) */

/* The summary's running averages and the analysis, on the steps with energies (not the row of the
 * last state, which is no step of the run). */
static int report_averages(void *ctx, const rl_run_report *r)
{
  run_ctx *c = ctx;
  if (r->last) return RL_OK;
  const double pr = scene_pressure_out(c->d, r->pressure);
  const int st = analysis_step(c->an, r->info, pr, r->forces, r->sys, r->box);
  if (st) return rl_error_wrap(st, "step %ld", r->step);
  running_add(&c->E, r->info->conserved);
  running_add(&c->U, r->info->potential);
  running_add(&c->T, r->info->temperature);
  running_add(&c->Tt, r->info->t_trans);
  running_add(&c->Tr, r->info->t_rot);
  running_add(&c->P, pr);
  return RL_OK;
}

static int report_sample(void *ctx, const rl_run_report *r)
{
  const int st = analysis_sample(((run_ctx *)ctx)->an, r->sys);
  return st ? rl_error_wrap(st, "step %ld", r->step) : RL_OK;
}

static int traj_frame(run_ctx *c, double time, long step);
static int report_frame(void *ctx, const rl_run_report *r)
{
  const int st = traj_frame(ctx, r->time, r->step);
  return st ? rl_error_wrap(st, "step %ld", r->step) : RL_OK;
}

static int report_thermo(void *ctx, const rl_run_report *r)
{
  run_ctx *c = ctx;
  const int st = thermo_row(c->thermo, outputs_part(c->out, OUT_THERMO), c->d, &c->s, r, &c->E);
  return st && !r->last ? rl_error_wrap(st, "step %ld", r->step) : st;
}

static int write_checkpoint(run_ctx *c, rl_integrator *in, long step, double time, long relax_step, double relax_time,
                            const out_mark *marks);
/* A checkpoint every output.checkpoint_every steps (the last state's is written at the end). */
static int report_checkpoint(void *ctx, const rl_run_report *r)
{
  run_ctx *c = ctx;
  if (r->step >= c->d->steps) return RL_OK;
  c->watch = *rl_run_watch(c->drv);
  const int st = write_checkpoint(c, c->in, r->step, r->time, -1, 0.0, NULL);
  return st ? rl_error_wrap(st, "step %ld", r->step) : RL_OK;
}

static int report_progress(void *ctx, const rl_run_report *r)
{
  run_ctx *c = ctx;
  const rl_deck *d = c->d;
  if (now() - c->last_progress <= 0.5) return RL_OK;
  double el = now() - c->t0, frac = (double)r->step / d->steps;
  double nsday = d->units == RL_UNITS_REAL ? (r->step - c->first) * d->timestep * 1e-3 / el * 86400.0 : 0.0;
  fprintf(stderr, "\r%5.1f%%  step %ld/%ld  ETA %.0f s%s%.2f%s   ", 100.0 * frac, r->step, d->steps, el / frac - el,
          d->units == RL_UNITS_REAL ? "  " : "", nsday, d->units == RL_UNITS_REAL ? " ns/day" : "");
  c->last_progress = now();
  return RL_OK;
}

/* The continuation a checkpoint start asks for.  The run record must describe the simulation
 * this deck asks for (runrec_physics); if it does not, a run under another prefix starts a new
 * run from the checkpoint's state, and one under the checkpoint's own prefix is refused (its
 * averages and files would mix two simulations).  Sets *cont (continue the record) or turns
 * the start into a plain starting state. */
static int decide_continuation(run_ctx *c, run_record *rec, int *cont)
{
  const rl_deck *d = c->d;
  scene *s = &c->s;
  *cont = 0;
  if (!s->restart) return RL_OK;
  int st = runrec_decode(s->blob, s->blob_size, rl_system_count(s->sys), d->start, rec);
  if (st) return st;
  char diff[4096] = "", odiff[2048] = "";
  const int other = runrec_other_simulation(rec, c->physics, d->thermostat, diff, sizeof diff);
  const int outputs_other =
    rec->version >= 5 && runrec_physics_diff(rec->physics, rec->physics_len, c->physics, 1, odiff, sizeof odiff);
  if (other && c->same_prefix)
    return rl_error(RL_EINVAL, "%s was written by another simulation than this deck asks for (%s): a continuation under "
                    "the same output.prefix must keep these settings, or its averages and files would mix two "
                    "simulations; give another output.prefix to start a new run from this state", d->start, diff);
  if (other) {
    fprintf(stderr, "rotleap run: %s was written by a run with other settings (%s): starting a new run from its state "
                    "(step 0; v and l completed to on-step with run.timestep = %g)\n", d->start, diff, d->timestep);
    st = scene_onstep(d, s);
    s->restart = 0;
    return st;
  }
  /* the sampling of the files: a continuation appends to them, whose frames and samples are
   * evenly spaced; under another prefix its files are new */
  if (outputs_other && c->same_prefix)
    return rl_error(RL_EINVAL, "%s was written with other output settings (%s): a continuation under the same "
                    "output.prefix appends to its files and keeps their sampling; give another output.prefix for new "
                    "files", d->start, odiff);
  if (c->same_prefix && rec->version < 5)
    return rl_error(RL_EINVAL, "%s was written by an older rotleap (run record version %d), whose output files a "
                    "continuation cannot check: continue it under another output.prefix", d->start, rec->version);
  *cont = 1;
  return RL_OK;
}

/* The run record's bookkeeping into the production integrator (a continuation). */
static int restore_record(run_ctx *c, const run_record *rec)
{
  const rl_deck *d = c->d;
  scene *s = &c->s;
  char note[RL_DECK_PATH_MAX + 512];
  const int st = runrec_restore(rec, s, c->in, d->thermostat_seed, d->start, note, sizeof note);
  if (st) return st;
  if (note[0]) fprintf(stderr, "rotleap run: %s\n", note);
  c->E = rec->E; c->U = rec->U; c->T = rec->T; c->Tt = rec->Tt; c->Tr = rec->Tr; c->P = rec->P;
  if (rec->has_watch) c->watch = rec->watch;
  c->last_chk = s->step0;
  c->first = s->step0;
  if (c->first > d->steps)
    return rl_error(RL_EINVAL, "%s is at step %ld, past run.steps = %ld (the total a continuation runs to, counted from "
                    "the first run's step 0): ask for more steps", d->start, c->first, d->steps);
  return RL_OK;
}

/* The relaxation phase: from the start, or continued from a checkpoint written during it.  A
 * signal stops it at the step in progress: a checkpoint holds the relaxation's state (its
 * continuation finishes the relaxation and runs the production, bit for bit with a run that was
 * never stopped), and the summary says where it stopped.  Returns RL_OK with c->stopped set for
 * a stop. */
static int relax(run_ctx *c, const run_record *rec)
{
  const rl_deck *d = c->d;
  const long k0 = rec ? rec->relax_step : 0;
  if (d->equilibrate_steps <= 0 || k0 >= d->equilibrate_steps) return RL_OK;
  if (rec && runrec_restore_list(rec, &c->s)) return RL_EINVAL;
  scene_relaxation *r = scene_relax_begin(d, &c->s, k0, rec ? rec->relax_time : 0.0);
  if (!r) return RL_EINVAL;
  rl_integrator *in = scene_relax_integrator(r);
  if (rec) {
    if (rec->rng_size != rl_integrator_rng_size(in)) {
      scene_relax_end(r, 0);
      return rl_error(RL_EINVAL, "%s: the relaxation's random state has %zu bytes, expected %zu", d->start, rec->rng_size,
                      rl_integrator_rng_size(in));
    }
    memcpy(rl_integrator_rng_state(in), rec->rng, rec->rng_size);
    rl_integrator_set_thermostat_work(in, rec->thermo_work);
  }
  int st = scene_relax_run(d, &c->s, r, &got_signal);
  c->relax_done = scene_relax_step(r);
  if (!st && got_signal && c->relax_done < d->equilibrate_steps) { /* the run's end writes its checkpoint */
    c->stopped = got_signal;
    c->relax = r;
    fprintf(stderr, "rotleap run: %s during the relaxation, at its step %ld of %ld: writing the checkpoint and summary "
                    "(system.start = %s continues it)\n", signal_text(c->stopped), c->relax_done, d->equilibrate_steps,
            c->chk_path);
    return RL_OK;
  }
  const int fin = scene_relax_end(r, !st);
  return st ? st : fin;
}

int rl_app_run(const rl_deck *d)
{
  run_ctx c;
  memset(&c, 0, sizeof c);
  c.d = d;
  c.relax_done = -1;
  c.last_chk = -1;
  rl_watch_init(&c.watch);
  c.chk_path = outputs_name(d->prefix, ".chk");
  c.chk_prev = outputs_name(d->prefix, ".chk.prev");
  c.summary_path = outputs_name(d->prefix, ".summary.txt");
  c.physics = runrec_physics(d);
  { /* which trajectory: a DCD of the sites (+ PDB) or an extended XYZ of centres and axes */
    rl_molecule m;
    c.site = !rl_model_build(d->model, d->params, d->force_general, &m) && rl_deck_site_model(&m);
  }
  int st = !c.chk_path || !c.chk_prev || !c.summary_path || !c.physics ? rl_error(RL_ENOMEM, "out of memory") : RL_OK;
  if (!st && !(c.out = outputs_alloc(d->prefix, d->trajectory_every > 0 ? (c.site ? "dcd" : "xyz") : NULL, 1)))
    st = RL_ENOMEM;
  /* before anything is written: no output may overwrite the deck or the start, the directory
   * must be safe to write in, and no other run may be writing this prefix */
  if (!st) st = check_overwrites(d, c.out);
  if (!st) st = outputs_check_dir(d->prefix);
  if (!st) st = outputs_lock(c.out);
  if (st) {
    fprintf(stderr, "rotleap run: %s\n", rl_last_error());
    outputs_free(c.out);
    free(c.chk_path); free(c.chk_prev); free(c.summary_path); free(c.physics);
    return 1;
  }
  /* Signals are caught from here on (a stop before the first step writes nothing). */
  got_signal = 0;
  catch_signals(1);
  int progress = d->progress < 0 ? isatty(fileno(stderr)) : d->progress;
  const double t0 = now();
  c.same_prefix = d->start[0] && same_file(d->start, c.chk_path);
  run_record rec;
  memset(&rec, 0, sizeof rec);
  rec.relax_step = -1;
  int cont = 0;
  st = scene_build(d, &c.s);
  if (!st && !(c.header = thermo_header(d, &c.s))) st = rl_error(RL_ENOMEM, "out of memory");
  if (!st) st = decide_continuation(&c, &rec, &cont);
  const int relax_cont = cont && rec.relax_step >= 0; /* a checkpoint of a stopped relaxation */
  c.resumed = cont && c.same_prefix;
  c.first = cont && !relax_cont ? c.s.step0 : 0;
  if (!st && !c.resumed) st = check_unfinished(&c);
  /* the streams (their working files) are open from the relaxation on: a signal then ends the
   * run as it does the production, with its files, checkpoint and summary */
  if (!st) st = open_streams(&c, c.resumed ? &rec : NULL, cont && !c.resumed && !relax_cont ? &rec : NULL);
  if (st) fprintf(stderr, "rotleap run: %s\n", rl_last_error());
  /* the relaxation (a new run, or the rest of a stopped one) */
  if (!st) report_setup(&c);
  if (!st && !c.s.restart) start_check(&c);
  if (!st && (!c.s.restart || relax_cont)) {
    st = relax(&c, relax_cont ? &rec : NULL);
    if (st && c.relax_done < 20 && c.start_note[0]) rl_error_wrap(st, "%s", c.start_note);
    if (st) fprintf(stderr, "rotleap run: %s\n", rl_last_error());
  }
  if (!st && !c.stopped) {
    rl_integrator_params p;
    rl_integrator_params_default(&p);
    p.h = d->timestep;
    p.method = d->method;
    p.thermostat = d->thermostat;
    p.T0 = d->thermostat_temperature;
    p.tau = d->tau;
    p.tau_rot = d->tau_rot;
    p.seed = d->thermostat_seed;
    p.groups = d->thermostat_groups;
    p.force_general = d->force_general;
    p.threads = d->ff.threads; /* run.threads: the rotation solves too */
    p.energy_every = d->energy_every;
    c.in = rl_integrator_alloc(c.s.sys, &p, rl_terms_provider(c.s.terms));
    st = !c.in ? RL_EINVAL : scene_add_barostat(d, c.in);
    if (!st) st = cont && !relax_cont ? restore_record(&c, &rec) : rl_integrator_init(c.in);
    if (st) step_error(&c, st);
    else if ((st = open_topology(&c))) fprintf(stderr, "rotleap run: %s\n", rl_last_error());
  }
  if (!st && !c.stopped && (!(c.an = analysis_alloc(d, c.s.mols, c.s.sys)) || attach_journal(&c))) {
    fprintf(stderr, "rotleap run: %s\n", rl_last_error());
    st = RL_EINVAL;
  }
  if (!st && !c.stopped && !(c.drv = scene_run_driver(d, &c.s, c.in))) {
    fprintf(stderr, "rotleap run: %s\n", rl_last_error());
    st = RL_EINVAL;
  }
  if (c.drv) *rl_run_watch(c.drv) = c.watch; /* a continuation's, from its checkpoint */
  c.progress = progress;
  c.t0 = t0;
  /* the reporters, in the order a step calls them: averages and analysis of the step's values,
   * samples, frames, the thermo row, the checkpoint, the progress line */
  const rl_reporter reps[] = {
      {"averages", RL_REPORT_STEP, d->energy_every, report_averages, &c},
      {"samples", RL_REPORT_STATE, d->sample_every > 0 ? d->sample_every : 0, report_sample, &c},
      {"trajectory", RL_REPORT_STATE, d->trajectory_every > 0 ? d->trajectory_every : 0, report_frame, &c},
      {"thermo", RL_REPORT_STEP, d->thermo_every, report_thermo, &c},
      {"checkpoint", RL_REPORT_STATE, d->checkpoint_every > 0 ? d->checkpoint_every : 0, report_checkpoint, &c},
      {"progress", RL_REPORT_STATE, progress ? 1 : 0, report_progress, &c}};
  for (size_t q = 0; !st && c.drv && q < sizeof reps / sizeof reps[0]; q++)
    if (reps[q].every > 0 && (st = rl_run_add_reporter(c.drv, &reps[q]))) fprintf(stderr, "rotleap run: %s\n", rl_last_error());
  char failure[2048] = "";
  if (!st && !c.stopped) {
    st = rl_run_steps(c.drv, c.first, d->steps, &got_signal, &c.done);
    if (st) step_error(&c, st);
    else if (got_signal && c.first + c.done < d->steps) {
      c.stopped = got_signal;
      fprintf(stderr, "%srotleap run: %s at step %ld of %ld: writing the checkpoint, thermo rows and summary "
                      "(system.start = %s continues)\n", progress ? "\n" : "", signal_text(c.stopped),
              c.first + c.done, d->steps, c.chk_path);
    }
  }
  if (c.drv) c.watch = *rl_run_watch(c.drv);
  if (st) snprintf(failure, sizeof failure, "%s", rl_last_error());
  /* The end.  A run that completed (or was stopped by a signal) syncs its streams, renames them
   * to their names and writes its last checkpoint; one that failed leaves them under their
   * working names, with the checkpoint it last wrote, and an earlier run's files as they were.
   * The last checkpoint's marks are taken before the row of the last state: a continuation
   * drops that row and writes it again as the row of its first step, as a run that never
   * stopped there writes it. */
  int io_bad = 0;
  out_mark marks[OUT_NSTREAMS];
  if (c.dcd && rl_dcd_close(c.dcd) && !st) st = RL_EINVAL;
  c.dcd = NULL;
  if (!st && c.streams) st = outputs_mark(c.out, marks);
  if (!st && c.drv && c.streams) { /* the row of the last state, as LAMMPS prints its last step (also after 0 steps) */
    st = rl_run_finish(c.drv, c.first + c.done);
    if (st) fprintf(stderr, "rotleap run: %s\n", rl_last_error());
  }
  if (!st && c.streams) {
    out_mark synced[OUT_NSTREAMS]; /* the last row on disk before the renames */
    if (!(st = outputs_mark(c.out, synced)) && !(st = outputs_close(c.out)) && !(st = outputs_commit(c.out, marks))) {
      if (c.relax) { /* stopped during the relaxation: its state, for a continuation to finish it */
        rl_integrator *ri = scene_relax_integrator(c.relax);
        st = write_checkpoint(&c, ri, 0, 0.0, c.relax_done, rl_integrator_time(ri), marks);
      } else st = write_checkpoint(&c, c.in, c.first + c.done, rl_integrator_time(c.in), -1, 0.0, marks);
    }
  } else if (c.streams && outputs_close(c.out)) {
    fprintf(stderr, "rotleap run: %s\n", rl_last_error());
  }
  if (st && !failure[0]) {
    snprintf(failure, sizeof failure, "%s", rl_last_error());
    fprintf(stderr, "rotleap run: %s\n", failure);
  }
  if (progress) fputc('\n', stderr);
  /* results, RDF and TCF files: each is written (atomically) whatever happened to the others */
  char io_failure[1024] = "";
  rl_barostat_stats bstats;
  const rl_stepop *bop = scene_barostat(d, c.in);
  if (c.an && bop && !rl_barostat_stats_of(bop, &bstats)) analysis_set_barostat_stats(c.an, &bstats);
  if (c.an && c.first + c.done > 0 && analysis_write(c.an, d->prefix, st ? ".part" : NULL, d->sample_every * d->timestep)) {
    snprintf(io_failure, sizeof io_failure, "cannot write the results: %s", rl_last_error());
    fprintf(stderr, "rotleap run: %s\n", io_failure);
    io_bad = 1;
  }
  const double wall = now() - t0;
  /* a run that failed before its first step leaves nothing but its message: the working files
   * it created (headers only) go, those it continues stay as they were */
  if (st && c.done == 0 && c.streams) outputs_discard(c.out);
  const int started = !st || c.done > 0 || c.stopped;
  char *part_summary = outputs_name(c.summary_path, ".part");
  if (started) {
    const char *spath = st ? part_summary : c.summary_path;
    const char *status = st || io_bad ? "error" : c.stopped ? "interrupted" : "ok";
    if (spath && write_summary(&c, spath, status, st ? failure : io_bad ? io_failure : NULL, wall, io_bad)) {
      fprintf(stderr, "rotleap run: cannot write %s: %s\n", spath, rl_last_error());
      io_bad = 1;
    }
  }
  if (st && c.done > 0) {
    fprintf(stderr, "rotleap run: the rows and frames of this run up to the failure are in %s.*.part (%s says what "
                    "happened); the files of an earlier run under %s are as they were", d->prefix, part_summary, d->prefix);
    if (c.last_chk >= 0)
      fprintf(stderr, "; %s (step %ld) continues this run from its last checkpoint\n", c.chk_path, c.last_chk);
    else fputs("\n", stderr);
  }
  char dw[1024];
  if (!st && !io_bad && drift_warning(&c, dw, sizeof dw)) fprintf(stderr, "rotleap run: warning: %s\n", dw);
  if (!st && c.streams && c.moved_prev) unlink(c.chk_prev); /* the earlier run is replaced by a whole one */
  free(part_summary);
  analysis_free(c.an);
  rl_run_free(c.drv);
  scene_relax_end(c.relax, 0);
  rl_integrator_free(c.in);
  scene_free(&c.s);
  catch_signals(0);
  outputs_free(c.out);
  free(c.chk_path); free(c.chk_prev); free(c.summary_path); free(c.physics); free(c.header);
  if (c.stopped && !st && !io_bad) return 128 + c.stopped; /* the outputs are complete; the caller asked to stop */
  return st || io_bad ? 1 : 0;
}
