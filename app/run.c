/* The run driver: deck -> system, force field, integrator -> loop -> outputs.  Thin by design:
 * the physics lives in the library. */
#include "run.h"
#include "analysis.h"
#include "quantity.h"
#include "scene.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdint.h>
#include <sys/stat.h>
#include <stddef.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>


static const char *pressure_unit(const rl_deck *d) { return d->units == RL_UNITS_REAL ? "bar" : "reduced"; }
static const char *energy_unit(const rl_deck *d) { return d->units == RL_UNITS_REAL ? "kJ/mol" : "reduced"; }

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
  int st = F.f && F.k ? rl_forcefield_compute(s.ff, s.sys, &F) : RL_ENOMEM;
  if (st) {
    fprintf(stderr, "rotleap energy: %s\n", rl_last_error());
    free(F.f); free(F.k); scene_free(&s);
    return 1;
  }
  rl_ff_energies e;
  rl_forcefield_energies(s.ff, &e);
  double ke = 0.0;
  for (int i = 0; i < n; i++) {
    double v[3];
    rl_system_get_velocity(s.sys, i, v);
    ke += 0.5 * s.mol.mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  double P = scene_pressure_out(d, rl_forcefield_pressure(s.ff, &F, ke));
  /* a NaN is an error naming its term, as in a run, never a number printed with exit 0 */
  st = scene_check_finite(d, &e, F.virial, P);
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
           "\"pressure\": \"%s\"},\n \"energy\": {\"total\": %.17g, \"lj\": %.17g, \"coulomb\": %.17g, "
           "\"dipolar\": %.17g, \"quadrupolar\": %.17g, \"dispersion\": %.17g},\n \"virial\": [",
           energy_unit(d), L, energy_unit(d), L, energy_unit(d), pressure_unit(d), e.total, e.lj,
           e.coulomb, e.dipolar, e.quadrupolar, e.dispersion);
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
    printf("term,value\ntotal,%.17g\nlj,%.17g\ncoulomb,%.17g\ndipolar,%.17g\nquadrupolar,%.17g\n"
           "dispersion,%.17g\npressure,%.17g\n", e.total, e.lj, e.coulomb, e.dipolar, e.quadrupolar,
           e.dispersion, P);
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

/* Welford running mean and variance. */
typedef struct { long n; double mean, m2; } running;
static void run_add(running *r, double x)
{
  r->n++;
  double d = x - r->mean;
  r->mean += d / r->n;
  r->m2 += d * (x - r->mean);
}
static double run_sd(const running *r) { return r->n > 1 ? sqrt(r->m2 / (r->n - 1)) : 0.0; }

/* FNV-1a (64 bits) of a text: the fingerprint of a thermo row, by which a continuation recognises
 * the file of the run that wrote its checkpoint (run_blob's row_hash). */
static uint64_t fnv1a(const char *text)
{
  uint64_t h = 14695981039346656037ULL;
  for (; *text; text++) h = (h ^ (unsigned char)*text) * 1099511628211ULL;
  return h;
}

/* One row of PREFIX.thermo.csv (THERMO_HEADER's columns): the state at the start of step k.
 * Returns its fingerprint. */
static uint64_t thermo_row(FILE *f, long k, const rl_step_info *info, const rl_ff_energies *e, double pr,
                           const running *E)
{
  char row[1024];
  snprintf(row, sizeof row, "%ld,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.6g,%.6g,%.6g,%.10g,%.10g,%.4e,%.6g,%.6g\n",
           k, info->t, info->total, info->potential, e->lj, e->coulomb, e->dipolar, e->quadrupolar, e->dispersion,
           info->ke_trans, info->ke_rot, info->temperature, info->t_trans, info->t_rot, pr, info->conserved,
           E->n > 1 ? run_sd(E) / fabs(E->mean) : 0.0, info->t_trans_mid, info->t_rot_mid);
  fputs(row, f);
  return fnv1a(row);
}

/* Write `text` to path atomically (rl_atomic_*: temporary file, fsync, rename). */
static int write_atomic(const char *path, const char *text)
{
  rl_atomic_file af;
  if (rl_atomic_open(&af, path)) return -1;
  if (fputs(text, af.fp) < 0) { rl_atomic_abort(&af); return -1; }
  return rl_atomic_commit(&af) ? -1 : 0;
}

/* 1 if paths a and b name one existing file. */
static int same_file(const char *a, const char *b)
{
  struct stat sa, sb;
  return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

/* The newer of two files' modification times: 1 if a is at least as new as b (or b is missing). */
static int newer_or_only(const char *a, const char *b)
{
  struct stat sa, sb;
  if (stat(a, &sa)) return 0;
  if (stat(b, &sb)) return 1;
  return sa.st_mtim.tv_sec > sb.st_mtim.tv_sec ||
         (sa.st_mtim.tv_sec == sb.st_mtim.tv_sec && sa.st_mtim.tv_nsec >= sb.st_mtim.tv_nsec);
}

/* Trajectories: DCD + PDB topology for site models, extended XYZ for the rest.  A new
 * trajectory is written under a temporary name (path.part) and renamed over any earlier one
 * when the run ends with frames (or without error), so that a run which fails before its first
 * step leaves an earlier run's trajectory as it was.  A continuation of this prefix's run
 * (system.start = prefix.chk) appends in place, after the frames up to its checkpoint, to the
 * trajectory of the run whose thermo rows it keeps (TRAJ_APPEND: the complete one; TRAJ_PART: a
 * killed run's .part, if newer); a continuation that keeps no rows of that run writes a new one. */
enum { TRAJ_NEW, TRAJ_APPEND, TRAJ_PART };
typedef struct {
  long every;
  rl_dcd *dcd;
  FILE *xyz;
  int fresh; /* written under .part names, renamed by traj_close */
  char path[600], part[640], pdb[600], pdb_part[640];
} traj;


/* Keep the frames of an extended XYZ file up to step `last` (by their Step= key) and truncate
 * after them: a killed run's frames past its checkpoint go. */
static int xyz_keep_frames(const char *path, long last)
{
  FILE *fp = fopen(path, "r+");
  if (!fp) return rl_error(RL_EINVAL, "%s: cannot open for appending: %s", path, strerror(errno));
  char *line = NULL;
  size_t cap = 0;
  long at = 0, frame = 0;
  int st = RL_OK;
  for (;;) {
    const long start = ftell(fp);
    if (getline(&line, &cap, fp) <= 0) { at = start; break; } /* the end: every frame kept */
    char *end;
    const long natoms = strtol(line, &end, 10);
    const char *key = getline(&line, &cap, fp) > 0 ? strstr(line, " Step=") : NULL;
    if (end == line || natoms < 0 || !key) {
      st = rl_error(RL_EINVAL, "%s: frame %ld is not an extended XYZ frame written by rotleap (atom count, "
                    "then a comment line with Step=)", path, frame + 1);
      break;
    }
    if (strtol(key + 6, NULL, 10) > last) { at = start; break; }
    long k = 0;
    while (k < natoms && getline(&line, &cap, fp) > 0) k++;
    if (k < natoms) { at = start; break; } /* a frame cut short by a kill */
    frame++;
  }
  free(line);
  fclose(fp);
  if (!st && truncate(path, at))
    st = rl_error(RL_EINVAL, "%s: cannot truncate after frame %ld: %s", path, frame, strerror(errno));
  return st;
}

/* The frames of a DCD to keep for a continuation from step `first`: those up to that step.  The
 * interval between frames must be that of this run (DCD frames are evenly spaced). */
static int dcd_keep(const char *path, long every, long first, long *keep)
{
  long istart, nsavc;
  if (rl_dcd_info(path, &istart, &nsavc, NULL)) return 1;
  if (nsavc != every)
    return rl_error(RL_EINVAL, "%s has a frame every %ld steps, this run writes one every %ld "
                    "(output.trajectory_every): a continuation keeps the interval, or writes under another "
                    "output.prefix", path, nsavc, every);
  *keep = first < istart ? 0 : (first - istart) / every + 1;
  return 0;
}

static int traj_open(traj *t, const rl_deck *d, scene *s, long first, int mode)
{
  t->every = d->trajectory_every;
  const int site = rl_deck_site_model(&s->mol);
  snprintf(t->path, sizeof t->path, "%s.%s", d->prefix, site ? "dcd" : "xyz");
  snprintf(t->part, sizeof t->part, "%s.part", t->path);
  /* a continuation of this prefix appends; where there is no trajectory yet (the first run
   * wrote none), or the start is another prefix's checkpoint, a new one starts at this run's
   * first frame */
  if (site) {
    snprintf(t->pdb, sizeof t->pdb, "%s.pdb", d->prefix);
    snprintf(t->pdb_part, sizeof t->pdb_part, "%s.part", t->pdb);
  }
  /* a run of this prefix killed without a signal it could catch left its trajectory under the
   * .part name: a continuation of that run takes that one, if newer than the last complete one */
  if (mode == TRAJ_PART && access(t->part, F_OK) == 0 && newer_or_only(t->part, t->path)) {
    if (rename(t->part, t->path))
      return rl_error(RL_EINVAL, "cannot move %s to %s: %s", t->part, t->path, strerror(errno));
    if (site && access(t->pdb_part, F_OK) == 0 && rename(t->pdb_part, t->pdb))
      return rl_error(RL_EINVAL, "cannot move %s to %s: %s", t->pdb_part, t->pdb, strerror(errno));
  }
  t->fresh = mode == TRAJ_NEW || access(t->path, F_OK) != 0;
  const char *out = t->fresh ? t->part : t->path;
  if (site) {
    /* a new trajectory's PDB is its first state, under the .part name; a continuation keeps the
     * PDB of the run it continues (its topology and first state, as an uninterrupted run's), and
     * writes one only if there is none, after its DCD has been opened: a continuation that
     * fails leaves the PDB as it was */
    const rl_molecule *mols[1] = {&s->mol};
    if (t->fresh) {
      if (rl_pdb_write(t->pdb_part, s->sys, mols, d->box)) return 1;
      t->dcd = rl_dcd_create(out, s->sys, first + t->every, t->every, d->timestep, "rotleap");
      return t->dcd ? 0 : 1;
    }
    long keep = 0;
    if (dcd_keep(out, t->every, first, &keep) || !(t->dcd = rl_dcd_append(out, s->sys, keep))) return 1;
    return access(t->pdb, F_OK) == 0 ? 0 : rl_pdb_write(t->pdb, s->sys, mols, d->box);
  }
  if (!t->fresh && xyz_keep_frames(out, first)) return 1;
  t->xyz = fopen(out, t->fresh ? "w" : "a");
  if (!t->xyz) return rl_error(RL_EINVAL, "cannot write %s: %s", out, strerror(errno));
  return 0;
}

static int traj_frame(traj *t, scene *s, const rl_deck *d, double time, long step)
{
  if (t->dcd) return rl_dcd_write_frame(t->dcd, s->sys, d->box);
  int st = rl_xyz_write_frame(t->xyz, t->path, s->sys, d->box, time, step);
  if (!st && fflush(t->xyz)) st = rl_error(RL_EINVAL, "cannot write %s: %s", t->path, strerror(errno));
  return st;
}

/* Close; a new trajectory replaces the earlier one if `keep`, else it is removed.  Nonzero (with
 * the message set) if a file could not be completed or renamed. */
static int traj_close(traj *t, int keep)
{
  int st = 0;
  if (t->dcd && rl_dcd_close(t->dcd)) st = 1;
  if (t->xyz && fclose(t->xyz)) st = rl_error(RL_EINVAL, "cannot write %s: %s", t->path, strerror(errno));
  const int opened = t->dcd || t->xyz || (t->pdb[0] && access(t->pdb_part, F_OK) == 0);
  t->dcd = NULL;
  t->xyz = NULL;
  if (!t->fresh || !opened) return st;
  const char *parts[2] = {t->part, t->pdb_part}, *paths[2] = {t->path, t->pdb};
  for (int k = 0; k < 2; k++) {
    if (!parts[k][0] || access(parts[k], F_OK)) continue;
    if (!keep || st) { remove(parts[k]); continue; }
    if (rename(parts[k], paths[k])) st = rl_error(RL_EINVAL, "cannot rename %s to %s: %s", parts[k], paths[k], strerror(errno));
  }
  return st;
}

/* What a checkpoint carries besides the state: the run's own bookkeeping, so that a restart
 * continues bit for bit (thermostat account and random stream, the summary's accumulators), and
 * from version 3 the neighbour list's origin (rl_forcefield_list_origin: the centres at its last
 * build, which fix the list and the order of the pair sums; without them a restart rebuilds the
 * list from its own centres and continues to round-off only, once the box has a cell grid or the
 * pair loop has threads).  From version 4 it also names the last thermo row its run wrote before
 * the checkpoint's step (step and FNV-1a hash of the text), so that a continuation takes its
 * earlier rows from that run's file and no other.  Layout: run_blob, the random state (rng_size
 * bytes), then (version 3) a long count (0 or the number of bodies) and count x 3 doubles. */
#define RUN_BLOB_MAGIC "rotleap-run-4"
#define RUN_BLOB_MAGIC_V3 "rotleap-run-3" /* before the last thermo row */
#define RUN_BLOB_MAGIC_V2 "rotleap-run-2" /* before the list origin */
#define RUN_BLOB_MAGIC_V1 "rotleap-run-1" /* before the thermostat and the seed were recorded */
typedef struct {
  char magic[16];
  double thermo_work;
  running E, U, T, Tt, Tr, P;
  long done;
  unsigned long rng_size;
  /* version 2 */
  long thermostat;    /* rl_thermostat of the run that wrote it; -1: not recorded (version 1) */
  unsigned long seed; /* run.seed its random stream started from */
  /* version 4 */
  long row_step;      /* the last row of the run's thermo file before the checkpoint's step; -1:
                         the file has none; -2: not recorded (versions 1-3) */
  uint64_t row_hash;  /* fnv1a of that row's text */
} run_blob;
#define RUN_BLOB_V1_SIZE offsetof(run_blob, thermostat)
#define RUN_BLOB_V3_SIZE offsetof(run_blob, row_step)

/* The run record of a checkpoint into *b, the random state following it at blob + *hdr: 4, 3, 2
 * or 1 (its version), 0 if the checkpoint has none. */
static int read_blob(const scene *s, run_blob *b, size_t *hdr)
{
  static const struct { const char *magic; size_t size; int version; } known[] = {
      {RUN_BLOB_MAGIC, sizeof(run_blob), 4}, {RUN_BLOB_MAGIC_V3, RUN_BLOB_V3_SIZE, 3},
      {RUN_BLOB_MAGIC_V2, RUN_BLOB_V3_SIZE, 2}, {RUN_BLOB_MAGIC_V1, RUN_BLOB_V1_SIZE, 1}};
  memset(b, 0, sizeof *b);
  b->row_step = -2;
  for (size_t k = 0; k < sizeof known / sizeof known[0]; k++)
    if (s->blob_size >= known[k].size && !memcmp(s->blob, known[k].magic, strlen(known[k].magic) + 1)) {
      memcpy(b, s->blob, known[k].size);
      if (known[k].version == 1) b->thermostat = -1;
      *hdr = known[k].size;
      return known[k].version;
    }
  return 0;
}

static int write_checkpoint(const rl_deck *d, scene *s, rl_integrator *in, const run_blob *b0, const char *path)
{
  run_blob b = *b0;
  snprintf(b.magic, sizeof b.magic, "%s", RUN_BLOB_MAGIC);
  b.thermo_work = rl_integrator_thermostat_work(in);
  b.rng_size = (unsigned long)rl_integrator_rng_size(in);
  b.thermostat = d->thermostat;
  b.seed = d->thermostat_seed;
  const int n = rl_system_count(s->sys);
  const size_t list_bytes = sizeof(long) + sizeof(double[3]) * (size_t)n;
  size_t size = sizeof b + b.rng_size + list_bytes;
  unsigned char *buf = malloc(size);
  if (!buf) return rl_error(RL_ENOMEM, "out of memory");
  memcpy(buf, &b, sizeof b);
  if (b.rng_size) memcpy(buf + sizeof b, rl_integrator_rng_state(in), b.rng_size);
  { /* the list's origin, or a count of 0 (no list yet) */
    unsigned char *p = buf + sizeof b + b.rng_size;
    long count = n > 0 && rl_forcefield_list_origin(s->ff, (double(*)[3])(void *)(p + sizeof(long))) ? n : 0;
    memcpy(p, &count, sizeof count);
    if (!count) size = sizeof b + b.rng_size + sizeof(long);
  }
  rl_checkpoint_meta meta = {rl_integrator_time(in), rl_integrator_steps(in), {d->box[0], d->box[1], d->box[2]}, buf, size};
  int st = rl_checkpoint_write(path, s->sys, &meta);
  free(buf);
  return st;
}

/* SIGINT and SIGTERM during the production loop: the step in progress ends, and the run stops
 * as if run.steps had been reached there (checkpoint, thermo rows, summary with status =
 * interrupted), exit status 128 + the signal.  A second signal acts at once (the handler
 * restores the default action).  The handlers are installed before the thermo file is opened
 * and stay until the outputs are written; a signal after the last step changes nothing.  Before
 * that (building, relaxing) the default actions apply, and a run killed there has written
 * nothing.  A run killed by SIGKILL leaves its rows in PREFIX.thermo.csv.part, which a
 * continuation of its checkpoint reads. */
static volatile sig_atomic_t got_signal;

static void on_signal(int sig)
{
  got_signal = sig;
  signal(sig, SIG_DFL);
}

static void catch_signals(int on)
{
  static const int sigs[2] = {SIGINT, SIGTERM};
  static int ignored[2]; /* a signal ignored at the start (a background job's SIGINT) stays so */
  for (int k = 0; k < 2; k++) {
    struct sigaction sa, old;
    if (on) {
      sigaction(sigs[k], NULL, &old);
      ignored[k] = old.sa_handler == SIG_IGN;
    }
    if (ignored[k]) continue;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on ? on_signal : SIG_DFL;
    sigemptyset(&sa.sa_mask);
    sigaction(sigs[k], &sa, NULL);
  }
}

#define THERMO_HEADER                                                                          \
  "step,time,total,potential,lj,coulomb,dipolar,quadrupolar,dispersion,ke_trans,ke_rot,"        \
  "temperature,t_trans,t_rot,pressure,conserved,calE,t_trans_mid,t_rot_mid\n"

/* A complete thermo row: THERMO_HEADER's 19 columns and its newline (a run killed mid-write
 * leaves a torn last line in its .part file). */
static int thermo_row_complete(const char *line)
{
  int commas = 0;
  const char *c = line;
  for (; *c; c++) commas += *c == ',';
  return commas == 18 && c > line && c[-1] == '\n';
}

/* The complete rows before step `first` of the thermo file at path: their number in *nrows and
 * the last of them (its step and fnv1a, or -1 and 0 if none) in *last_step, *last_hash; with
 * copy_to, they are also copied there.  Returns 1 for a file with THERMO_HEADER's columns, 0 for
 * one with other columns, -1 if there is no file to read, -2 on a read or write error (reported). */
static int thermo_scan(const char *path, long first, long *nrows, long *last_step, uint64_t *last_hash, FILE *copy_to)
{
  *nrows = 0;
  *last_step = -1;
  *last_hash = 0;
  FILE *in = fopen(path, "r");
  if (!in) return -1;
  char *line = NULL;
  size_t cap = 0;
  int st = getline(&line, &cap, in) >= 0 && !strcmp(line, THERMO_HEADER);
  while (st == 1 && getline(&line, &cap, in) > 0) {
    char *end;
    const long step = strtol(line, &end, 10);
    if (end == line || !thermo_row_complete(line)) continue; /* a row torn by a kill */
    if (step >= first) break;
    (*nrows)++;
    *last_step = step;
    *last_hash = fnv1a(line);
    if (copy_to && fputs(line, copy_to) < 0) st = -2;
  }
  if (ferror(in)) st = -2;
  fclose(in);
  free(line);
  if (st == -2) fprintf(stderr, "rotleap run: cannot copy the earlier rows of %s: %s\n", path, strerror(errno));
  return st;
}

/* Which file holds the rows before step `first` of the run that wrote the checkpoint a
 * continuation of this prefix starts from (rec): a killed run's .part (a run killed without a
 * signal it could catch leaves its rows there), the .part.old an earlier run moved aside, or the
 * thermo file itself.  A file holds them if its last complete row before `first` is the one the
 * checkpoint names (version 4; none, if it names none), so that no other run's rows are ever
 * spliced in.  A checkpoint of version 3 or older names no row: a killed run's .part that has
 * rows is taken if it is newer than the thermo file, else the thermo file. */
enum { ROWS_NONE, ROWS_PART, ROWS_OLD, ROWS_FILE };
static int rows_source(const char *part, const char *oldpart, const char *thermo_path, long first,
                       const run_blob *rec)
{
  long nrows, step;
  uint64_t hash;
  if (rec->row_step < -1)
    return thermo_scan(part, first, &nrows, &step, &hash, NULL) == 1 && nrows > 0 && newer_or_only(part, thermo_path)
               ? ROWS_PART : ROWS_FILE;
  const char *file[3] = {part, oldpart, thermo_path};
  for (int k = 0; k < 3; k++)
    if (thermo_scan(file[k], first, &nrows, &step, &hash, NULL) == 1 && step == rec->row_step &&
        (step < 0 || hash == rec->row_hash))
      return k + 1; /* ROWS_PART, ROWS_OLD, ROWS_FILE */
  return ROWS_NONE;
}

/* The library's message for a failed step; for a non-finite potential energy, also the term
 * that is not finite. */
static void step_error(const rl_deck *d, const scene *s, int st)
{
  char msg[1024];
  snprintf(msg, sizeof msg, "%s", rl_last_error());
  rl_ff_energies e;
  if (st == RL_ENONFINITE && s->ff) {
    rl_forcefield_energies(s->ff, &e);
    if (scene_check_finite(d, &e, NULL, 0.0)) {
      fprintf(stderr, "rotleap run: %s: %s\n", msg, rl_last_error());
      return;
    }
  }
  fprintf(stderr, "rotleap run: %s\n", msg);
}

int rl_app_run(const rl_deck *d)
{
  scene s;
  char thermo_path[600], part[700], summary_path[600];
  snprintf(thermo_path, sizeof thermo_path, "%s.thermo.csv", d->prefix);
  snprintf(part, sizeof part, "%s.part", thermo_path);
  snprintf(summary_path, sizeof summary_path, "%s.summary.txt", d->prefix);
  char chk_path[600], oldpart[720];
  snprintf(chk_path, sizeof chk_path, "%s.chk", d->prefix);
  snprintf(oldpart, sizeof oldpart, "%s.old", part);
  { /* no output may overwrite the deck or the start (PREFIX.pdb = water.pdb, say), checked
     * before anything is written */
    static const char *const ext[] = {".thermo.csv", ".thermo.csv.part", ".thermo.csv.part.old", ".summary.txt",
                                      ".chk", ".results.txt", ".rdf.csv", ".tcf.csv", ".dcd", ".dcd.part",
                                      ".pdb", ".pdb.part", ".xyz", ".xyz.part"};
    enum { NOUT = sizeof ext / sizeof ext[0], NTRAJ = 6 }; /* the last NTRAJ: trajectory files */
    char out[NOUT][640];
    const char *outs[NOUT];
    rl_molecule m;
    const int site = !rl_model_build(d->model, d->params, d->force_general, &m) && rl_deck_site_model(&m);
    int n = 0;
    for (int k = 0; k < NOUT; k++) {
      const int traj = k >= NOUT - NTRAJ, xyz = k >= NOUT - 2;
      if (traj && (d->trajectory_every == 0 || xyz == site)) continue;
      snprintf(out[n], sizeof out[n], "%s%s", d->prefix, ext[k]);
      outs[n] = out[n];
      n++;
    }
    if (scene_check_outputs(d, outs, n)) {
      fprintf(stderr, "rotleap run: %s\n", rl_last_error());
      return 1;
    }
  }
  /* a continuation of this prefix's run (its rows are kept) */
  const int same_prefix = d->start[0] && same_file(d->start, chk_path);
  { /* an unwritable prefix is an error before the scene is built and relaxed; the thermo file
     * itself is opened only when the run is about to step (below) */
    char probe[740];
    snprintf(probe, sizeof probe, "%s.probe.%ld", part, (long)getpid());
    const int fd = open(probe, O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd < 0) {
      fprintf(stderr, "rotleap run: cannot write %s: %s (output.prefix = %s)\n", part, strerror(errno), d->prefix);
      return 1;
    }
    close(fd);
    unlink(probe);
  }
  if (scene_build(d, &s)) {
    fprintf(stderr, "rotleap run: %s\n", rl_last_error());
    scene_free(&s);
    return 1;
  }
  int progress = d->progress < 0 ? isatty(fileno(stderr)) : d->progress;
  rl_integrator_params p;
  rl_integrator *in = NULL;
  int st = RL_OK, n = d->count;
  if ((st = scene_relax(d, &s))) fprintf(stderr, "rotleap run: %s\n", rl_last_error());
  rl_integrator_params_default(&p);
  p.h = d->timestep;
  p.method = d->method;
  p.thermostat = d->thermostat;
  p.T0 = d->thermostat_temperature;
  p.tau = d->tau;
  p.seed = d->thermostat_seed;
  p.groups = d->thermostat_groups;
  p.force_general = d->force_general;
  p.threads = d->ff.threads; /* run.threads: the rotation solves too */
  p.energy_every = d->energy_every;
  if (!st) in = rl_integrator_alloc(s.sys, &p, rl_forcefield_provider(s.ff));
  run_blob rec;
  size_t hdr = 0;
  const int ver = s.restart ? read_blob(&s, &rec, &hdr) : 0;
  if (!st && in && ver) {
    /* a checkpoint of a run with another thermostat (an NVT equilibration before NVE production,
     * say) is a start, not a continuation: its half-step v, l are completed to on-step values
     * with run.timestep and the run, its step count and its averages start afresh.  A version 1
     * record says only whether the thermostat drew random numbers */
    if (ver >= 2 ? rec.thermostat != (long)d->thermostat : rec.rng_size != rl_integrator_rng_size(in)) {
      fprintf(stderr, "rotleap run: %s was written by a run with another thermostat: starting a new run from its "
                      "state (step 0; v and l completed to on-step with run.timestep = %g)\n", d->start, d->timestep);
      st = scene_onstep(d, &s);
      s.restart = 0;
    }
  }
  if (!st) {
    st = !in ? RL_EINVAL : s.restart ? RL_OK : rl_integrator_init(in);
    if (st) step_error(d, &s, st);
  }
  running E = {0}, U = {0}, T = {0}, Tt = {0}, Tr = {0}, P = {0};
  long first = 0;
  if (!st && s.restart) { /* continue: forces at t, no re-staggering, bookkeeping restored */
    if (!ver) {
      st = rl_error(RL_EINVAL, "%s was not written by rotleap run (no run record)", d->start);
    } else {
      const size_t rest = ver >= 3 ? s.blob_size - hdr - rec.rng_size : 0; /* the list's origin */
      long count = -1;
      if (ver >= 3 && s.blob_size >= hdr + rec.rng_size + sizeof count)
        memcpy(&count, (unsigned char *)s.blob + hdr + rec.rng_size, sizeof count);
      const int list_ok = ver < 3 || ((count == 0 || count == n) &&
                                      rest == sizeof count + sizeof(double[3]) * (size_t)(count > 0 ? count : 0));
      if (rec.rng_size != rl_integrator_rng_size(in) || s.blob_size < hdr + rec.rng_size ||
          (ver < 3 && s.blob_size != hdr + rec.rng_size))
        st = rl_error(RL_EINVAL, "%s was written with another thermostat (random state of %lu bytes, "
                      "this run needs %lu)", d->start, rec.rng_size, (unsigned long)rl_integrator_rng_size(in));
      else if (!list_ok)
        st = rl_error(RL_EINVAL, "%s: its neighbour-list record is damaged (%ld bodies in %zu bytes; the "
                      "system has %d)", d->start, count, rest, n);
      else {
        if (count == n) { /* the list the run had, so that the pair sums keep their order */
          double(*r0)[3] = malloc(sizeof *r0 * (size_t)n);
          if (!r0) st = rl_error(RL_ENOMEM, "out of memory");
          else {
            memcpy(r0, (unsigned char *)s.blob + hdr + rec.rng_size + sizeof count, sizeof *r0 * (size_t)n);
            st = rl_forcefield_set_list_origin(s.ff, (const double(*)[3])r0);
            free(r0);
          }
        }
        if (!st) st = rl_integrator_resume(in, s.step0, s.t0);
        /* a changed run.seed asks for a new random stream: the integrator was seeded with it */
        const int reseed = ver >= 2 && rec.rng_size && rec.seed != d->thermostat_seed;
        if (!st && reseed)
          fprintf(stderr, "rotleap run: run.seed = %lu differs from the seed %lu of the run that wrote %s: the "
                          "%s thermostat continues with a new random stream from seed %lu (not bit for bit "
                          "with a continuation that keeps seed %lu)\n", d->thermostat_seed, rec.seed, d->start,
                  rl_thermostat_name(d->thermostat), d->thermostat_seed, rec.seed);
        else if (!st && rec.rng_size) memcpy(rl_integrator_rng_state(in), (unsigned char *)s.blob + hdr, rec.rng_size);
        rl_integrator_set_thermostat_work(in, rec.thermo_work);
        E = rec.E; U = rec.U; T = rec.T; Tt = rec.Tt; Tr = rec.Tr; P = rec.P;
        first = s.step0;
        if (first > d->steps)
          st = rl_error(RL_EINVAL, "%s is at step %ld, past run.steps = %ld (the total a continuation runs "
                        "to, counted from the first run's step 0): ask for more steps", d->start, first, d->steps);
      }
    }
    if (st) fprintf(stderr, "rotleap run: %s\n", rl_last_error());
  }
  /* Signals are caught from here on: a run stopped before this point has written nothing. */
  got_signal = 0;
  catch_signals(1);
  /* The thermo file, opened now that the run is about to step.  A continuation of this prefix
   * starts it with the rows before its first step of the run that wrote its checkpoint
   * (rows_source), and appends to that run's trajectory.  A killed run's .part that is not read
   * is moved aside to .part.old, and back if this run fails before its first step. */
  FILE *thermo = NULL;
  int rows = ROWS_NONE, moved_part = 0, aside = 0, traj_mode = TRAJ_NEW;
  long row_step = -1, nrows = 0; /* the last row written before the step at hand, for checkpoints */
  uint64_t row_hash = 0;
  if (!st) {
    const int cont = s.restart && same_prefix;
    if (cont) rows = rows_source(part, oldpart, thermo_path, first, &rec);
    if (cont && rows == ROWS_NONE && access(thermo_path, F_OK) == 0) {
      fprintf(stderr, "rotleap run: warning: neither %s nor a killed run's %s holds the rows of the run that wrote %s "
                      "(its last row before step %ld): this run writes its own rows from step %ld and a new "
                      "trajectory; %s is kept as %s.prev\n", thermo_path, part, d->start, first, first, thermo_path,
              thermo_path);
      aside = 1;
    }
    traj_mode = !cont || rows == ROWS_NONE || rows == ROWS_OLD ? TRAJ_NEW : rows == ROWS_PART ? TRAJ_PART : TRAJ_APPEND;
    if (rows != ROWS_OLD && access(part, F_OK) == 0) {
      if (rename(part, oldpart))
        st = rl_error(RL_EINVAL, "cannot move %s aside to %s: %s", part, oldpart, strerror(errno));
      else moved_part = 1;
    }
    if (!st && !(thermo = fopen(part, "w"))) {
      st = rl_error(RL_EINVAL, "cannot write %s: %s (output.prefix = %s)", part, strerror(errno), d->prefix);
      if (moved_part) rename(oldpart, part);
    }
    if (st) fprintf(stderr, "rotleap run: %s\n", rl_last_error());
    else {
      fputs(THERMO_HEADER, thermo);
      const int got = rows == ROWS_NONE ? -1 : thermo_scan(rows == ROWS_FILE ? thermo_path : oldpart, first, &nrows,
                                                           &row_step, &row_hash, thermo);
      if (got == -2) st = RL_EINVAL;
      else if (got == 0) { /* the thermo file of an older rotleap (a version 3 checkpoint) */
        fprintf(stderr, "rotleap run: %s has other columns than this run writes; it is kept as %s.prev\n",
                thermo_path, thermo_path);
        aside = 1;
      }
    }
  }
  double t0 = now(), last_progress = 0.0;
  long done = 0, fallbacks = 0;
  int nrot = rl_system_nrot(s.sys);
  rl_forces fsnap_store = {calloc((size_t)n, sizeof(double[3])), calloc((size_t)(nrot > 0 ? nrot : 1), sizeof(double[3])), 0.0, {0}, 0};
  rl_forces *fsnap = &fsnap_store;
  traj tr = {0};
  if (!st && d->trajectory_every > 0 && traj_open(&tr, d, &s, first, traj_mode)) {
    fprintf(stderr, "rotleap run: %s\n", rl_last_error());
    st = RL_EINVAL;
  }
  scene_watch watch;
  scene_watch_init(&watch);
  analysis *an = NULL;
  if (!st && !(an = analysis_alloc(d, &s.mol, s.sys))) {
    fprintf(stderr, "rotleap run: %s\n", rl_last_error());
    st = RL_EINVAL;
  }
  int stopped = 0, wrote_chk = 0; /* the signal that ended the loop; a checkpoint was written */
  for (long k = first; !st && k < d->steps; k++) {
    if (got_signal) {
      stopped = got_signal;
      fprintf(stderr, "%srotleap run: %s at step %ld of %ld: writing the checkpoint, thermo rows and summary "
                      "(system.start = %s.chk continues)\n", progress ? "\n" : "",
              got_signal == SIGINT ? "interrupted (SIGINT)" : "terminated (SIGTERM)", k, d->steps, d->prefix);
      break;
    }
    /* the energies, virial and averages on the steps of output.energy_every (the integrator
     * computes forces only on the others; init and resume always compute all) */
    const int ev = k % d->energy_every == 0;
    rl_ff_energies e;
    rl_forcefield_energies(s.ff, &e); /* terms at the current time t */
    const rl_forces *F = rl_integrator_forces(in);
    double virial[9];
    if (ev) {
      memcpy(virial, F->virial, sizeof virial);
      memcpy(fsnap->f, F->f, sizeof(double[3]) * (size_t)n);
      if (nrot) memcpy(fsnap->k, F->k, sizeof(double[3]) * (size_t)nrot);
    }
    rl_step_info info;
    st = rl_integrator_step(in, &info);
    if (st) { /* the library's message names the step and the cause */
      step_error(d, &s, st);
      break;
    }
    if (ev && !info.has_energy) { /* cannot happen: the integrator has the same energy_every */
      fprintf(stderr, "rotleap run: internal error: no energies at step %ld\n", k);
      st = RL_ESTATE;
      break;
    }
    if ((st = scene_watch_step(d, &s, &watch, &info, k, d->energy_every, d->timestep, "run.timestep"))) {
      fprintf(stderr, "rotleap run: %s\n", rl_last_error());
      break;
    }
    double pr = 0.0;
    if (ev) {
      rl_forces Ft = {NULL, NULL, 0.0, {0}, 0};
      memcpy(Ft.virial, virial, sizeof virial);
      pr = scene_pressure_out(d, rl_forcefield_pressure(s.ff, &Ft, info.ke_trans));
      if ((st = scene_check_finite(d, &e, virial, pr))) {
        fprintf(stderr, "rotleap run: step %ld (t = %g): %s\n", k, info.t, rl_last_error());
        break;
      }
      analysis_step(an, &info, pr, fsnap, s.sys);
      run_add(&E, info.total);
      run_add(&U, info.potential);
      run_add(&T, info.temperature);
      run_add(&Tt, info.t_trans);
      run_add(&Tr, info.t_rot);
      run_add(&P, pr);
    }
    if (d->sample_every > 0 && (k + 1) % d->sample_every == 0 && analysis_sample(an, s.sys)) {
      fprintf(stderr, "rotleap run: step %ld: %s\n", k + 1, rl_last_error());
      st = RL_EINVAL;
    }
    done++;
    if (tr.every && (k + 1) % tr.every == 0 && traj_frame(&tr, &s, d, rl_integrator_time(in), k + 1)) {
      fprintf(stderr, "rotleap run: step %ld: %s\n", k + 1, rl_last_error());
      st = RL_EINVAL;
    }
    if (k % d->thermo_every == 0) {
      row_hash = thermo_row(thermo, k, &info, &e, pr, &E);
      row_step = k;
    }
    if (d->checkpoint_every > 0 && (k + 1) % d->checkpoint_every == 0 && k + 1 < d->steps) {
      fflush(thermo); /* every row before the checkpoint's step reaches the .part file before it */
      run_blob b = {"", 0, E, U, T, Tt, Tr, P, k + 1, 0, 0, 0, row_step, row_hash};
      if (write_checkpoint(d, &s, in, &b, chk_path)) {
        fprintf(stderr, "rotleap run: step %ld: %s\n", k + 1, rl_last_error());
        st = RL_EINVAL;
      } else wrote_chk = 1;
    }
    if (progress && now() - last_progress > 0.5) {
      double el = now() - t0, frac = (double)(k + 1) / d->steps;
      double nsday = d->units == RL_UNITS_REAL ? (k + 1) * d->timestep * 1e-3 / el * 86400.0 : 0.0;
      fprintf(stderr, "\r%5.1f%%  step %ld/%ld  ETA %.0f s%s%.2f%s   ", 100.0 * frac, k + 1, d->steps,
              el / frac - el, d->units == RL_UNITS_REAL ? "  " : "", nsday, d->units == RL_UNITS_REAL ? " ns/day" : "");
      last_progress = now();
    }
  }
  if (!st && in) { /* the row of the last state, as LAMMPS prints its last step (also after 0 steps) */
    rl_step_info info;
    rl_ff_energies e;
    st = rl_integrator_observe(in, &info);
    if (st) fprintf(stderr, "rotleap run: %s\n", rl_last_error());
    else {
      rl_forcefield_energies(s.ff, &e);
      rl_forces Ft = {NULL, NULL, 0.0, {0}, 0};
      memcpy(Ft.virial, rl_integrator_forces(in)->virial, sizeof Ft.virial);
      const double pr = scene_pressure_out(d, rl_forcefield_pressure(s.ff, &Ft, info.ke_trans));
      if ((st = scene_check_finite(d, &e, Ft.virial, pr)))
        fprintf(stderr, "rotleap run: step %ld (t = %g): %s\n", first + done, info.t, rl_last_error());
      else thermo_row(thermo, first + done, &info, &e, pr, &E);
    }
  }
  if (in) fallbacks = rl_integrator_fallbacks(in);
  /* a new trajectory replaces an earlier one only if this run has frames for it or ended well */
  const int traj_bad = traj_close(&tr, done > 0 || !st);
  if (traj_bad) fprintf(stderr, "rotleap run: %s\n", rl_last_error());
  /* results, RDF and TCF files: each is written (atomically) whatever happened to the others; a
   * failure is named on stderr and makes the exit status 1, like a failed thermo or trajectory */
  const int results_bad = an && done > 0 && analysis_write(an, d->prefix, NULL, d->sample_every * d->timestep);
  if (results_bad) fprintf(stderr, "rotleap run: cannot write the results: %s\n", rl_last_error());
  analysis_free(an);
  free(fsnap_store.f);
  free(fsnap_store.k);
  if (!st && in) { /* the final state, for a continuation */
    run_blob b = {"", 0, E, U, T, Tt, Tr, P, first + done, 0, 0, 0, row_step, row_hash};
    fflush(thermo);
    if (write_checkpoint(d, &s, in, &b, chk_path)) {
      fprintf(stderr, "rotleap run: %s\n", rl_last_error());
      st = RL_EINVAL;
    } else wrote_chk = 1;
  }
  if (progress) fputc('\n', stderr);
  double wall = now() - t0;
  /* the rows already written are kept whatever happened: close and rename; a run that failed
   * before its first step has none, and leaves the thermo file of an earlier run as it was */
  int io_ok = !thermo || fclose(thermo) == 0;
  if (!thermo) { /* nothing was written */
  } else if (st && done == 0) {
    remove(part);
    if (moved_part) rename(oldpart, part);
  } else {
    char prev[760];
    snprintf(prev, sizeof prev, "%s.prev", thermo_path);
    if (aside && access(thermo_path, F_OK) == 0 && rename(thermo_path, prev))
      fprintf(stderr, "rotleap run: cannot move %s aside to %s: %s\n", thermo_path, prev, strerror(errno));
    io_ok = io_ok && rename(part, thermo_path) == 0;
    /* a killed run's rows moved aside are superseded once this run has a checkpoint */
    if (io_ok && wrote_chk) remove(oldpart);
  }
  if (!io_ok) fprintf(stderr, "rotleap run: cannot write %s: %s\n", thermo_path, strerror(errno));
  /* the averages over this run's steps with energies (none: n/a, not zeros) */
  char au[160] = "n/a (no step with energies)", at[200] = "n/a", ap[160] = "n/a";
  if (U.n > 0) {
    snprintf(au, sizeof au, "%.8g +- sd %.3g %s", U.mean / n, run_sd(&U) / n, energy_unit(d));
    snprintf(at, sizeof at, "%.6g (translational %.6g, rotational %.6g)%s", T.mean, Tt.mean, Tr.mean,
             d->units == RL_UNITS_LJ ? "" : " K");
    snprintf(ap, sizeof ap, "%.6g +- sd %.3g %s", P.mean, run_sd(&P), pressure_unit(d));
  }
  char text[4096], cE[64], cU[64], cEU[64];
  /* relative fluctuations (0 with fewer than two steps; n/a where a mean is 0) */
  const double calE = E.n > 1 ? run_sd(&E) / fabs(E.mean) : 0.0, calU = U.n > 1 ? run_sd(&U) / fabs(U.mean) : 0.0;
  const char *tunit = d->units == RL_UNITS_REAL ? rl_dim_unit(Q_TIME, d->units) : "time unit";
  const int mode = scene_drift_mode(d, watch.alt_at_max); /* the isokinetic scheme's, not the step's */
  snprintf(text, sizeof text,
           "# rotleap %s summary of %s\n"
           "status = %s\nsteps = %ld of %ld (this invocation: %ld)\nmodel = %s\nmolecules = %d\nunits = %s\n"
           "timestep = %g %s\nenergy_every = %ld (the averages below are over these steps)\n"
           "neighbour_list = skin %.4g %s, %ld builds in this invocation\n"
           "pair_kernels = %s (%s rows, %d thread(s), %s precision)\nwall_seconds = %.3f\nfallbacks = %ld\n"
           "U_per_molecule = %s\n"
           "temperature = %s\n"
           "pressure = %s\n"
           "calE = %s\ncalU = %s\ncalE_over_calU = %s\n"
           "rigidity_error = %.3g (max |A A^T - I| or ||rho| - 1| at the end)\n"
           "conserved_drift = %.3g kT per molecule per %s (largest over windows of %g %s; %s)\n%s",
           ROTLEAP_VERSION, d->path, stopped ? "interrupted" : st ? "error" : "ok", first + done, d->steps, done, d->model->name, n,
           d->units == RL_UNITS_LJ ? "lj" : "real", d->timestep, rl_dim_unit(Q_TIME, d->units), d->energy_every,
           scene_skin(d, &s.mol), rl_dim_unit(Q_LENGTH, d->units), s.ff ? rl_forcefield_rebuilds(s.ff) : 0L,
           s.ff ? rl_forcefield_kernel(s.ff) : "none", s.ff ? rl_forcefield_rows(s.ff) : "no",
           s.ff ? rl_forcefield_threads(s.ff) : 1, s.ff ? rl_forcefield_precision(s.ff) : "double", wall, fallbacks,
           au, at, ap,
           rel_fluct_text(cE, sizeof cE, calE), rel_fluct_text(cU, sizeof cU, calU),
           rel_fluct_text(cEU, sizeof cEU, calU > 0 ? calE / calU : U.n > 1 ? NAN : 0.0),
           scene_rigidity_error(s.sys), watch.max_rate, tunit, SCENE_WINDOW, tunit,
           watch.max_rate != 0.0 ? "above 0.5 warns, above 5 stops" : "the run was shorter than one window",
           fabs(watch.max_rate) <= SCENE_DRIFT_WARN ? ""
           : mode ? "warning = the conserved energy drifts: the isokinetic thermostat's undamped step-to-step "
                    "alternation of the kinetic energy (a start out of equilibrium at run.temperature), not the time step; "
                    "relax the start at run.temperature (run.equilibrate) or use run.ensemble = nvt-bussi\n"
                  : "warning = the conserved energy drifts: integration error is heating or cooling the system; "
                    "a smaller time step will change the results\n");
  if (fabs(watch.max_rate) > SCENE_DRIFT_WARN && !st && mode)
    fprintf(stderr, "rotleap run: warning: the conserved energy drifted by %.3g kT per molecule per %s: the kinetic "
                    "energy alternates from step to step by +-%.2g %% of run.temperature, the isokinetic scheme's "
                    "undamped mode (a start out of equilibrium at run.temperature), not the time step: relax the start at "
                    "run.temperature (run.equilibrate) or use run.ensemble = nvt-bussi\n", watch.max_rate, tunit,
            100.0 * watch.alt_at_max);
  else if (fabs(watch.max_rate) > SCENE_DRIFT_WARN && !st)
    fprintf(stderr, "rotleap run: warning: the conserved energy drifted by %.3g kT per molecule per %s: the time "
                    "step %g is too large for accurate dynamics\n", watch.max_rate, tunit,
            d->timestep);
  /* a run that failed before its first step leaves the summary of an earlier run as it was,
   * like its thermo file and trajectory: it has nothing to report but the error, on stderr */
  if (!(st && done == 0) && write_atomic(summary_path, text)) {
    fprintf(stderr, "rotleap run: cannot write %s: %s\n", summary_path, strerror(errno));
    io_ok = 0;
  }
  if (traj_bad || results_bad) io_ok = 0;
  if (!st) fputs(text, stdout);
  rl_integrator_free(in);
  scene_free(&s);
  catch_signals(0);
  if (stopped) return 128 + stopped; /* the outputs are complete; the caller asked to stop */
  return st || !io_ok ? 1 : 0;
}
