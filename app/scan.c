/* rotleap scan: the speed-accuracy trade of a deck's scene over time steps and integrators.
 *
 * One shared start (the deck's start after its relaxation phase) is cloned for every run; each
 * run gets a fresh force field and integrator, the deck's ensemble, and either the same number of
 * steps (the paper's Fig. 1 convention) or the same simulated time.  Per run: calE and calU
 * (relative fluctuations of the conserved and potential energies), their ratio, the drift of the
 * conserved energy (least squares, per molecule), the worst orthonormality error at the end,
 * guarded-solve fallbacks, iterations, an RDF distance from the reference run (the first
 * integrator at the smallest step), T_trans, T_rot and their ratio, wall time per step and
 * ns/day.  Outputs (each written atomically after every run, so a scan stopped part-way keeps
 * what it has done): PREFIX.scan.csv, PREFIX.scan_calE.csv (calE against run length), PREFIX.scan.txt (the
 * table), and PNG plots by scripts/plot_scan.py. */
#include "scan.h"
#include "analysis.h"
#include "outputs.h"
#include "quantity.h"
#include "scene.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define SCAN_MAX 64 /* time steps and integrators each */
/* Steps of one run at most: a scan compares many runs, and 1e9 steps is already days for 64
 * molecules; it keeps every count of the run (calE curve points) in an int. */
#define SCAN_MAX_STEPS 1000000000L

typedef struct {
  int integ;          /* index into rl_deck_integrators */
  double h;
  long steps;         /* planned            */
  long done;          /* steps completed    */
  int ok;
  int analysis_bad;   /* its .results/.rdf/.tcf files could not be written */
  char error[512];
  double calE, calU, drift, ortho, t_trans, t_rot, rdf_dist, wall_per_step, ns_day, iterations;
  double max_h_omega;
  double tconf_trans, tconf_rot; /* output.tconf: configurational temperatures (NaN: not taken) */
  double V, V_err, rho, rho_err; /* run.barostat: the blocked means of the volume and density (NaN: none) */
  int V_plateau;                 /* their blocking found a plateau (else the errors are lower bounds) */
  long fallbacks;
  rl_rdf *rdf;
  double (*curve)[3]; /* step, time, running calE */
  int ncurve;
} scan_run;

typedef struct {
  double h[SCAN_MAX];
  int nh;
  int integ[SCAN_MAX];
  int ninteg;
  long steps;         /* 0: the deck's run.steps            */
  double time;        /* > 0: equal simulated time instead  */
  double tolerance;   /* calE / calU                        */
  int plot;
  int analysis;       /* per-run results, RDFs, TCFs          */
  const char *prefix;
  char electrostatics[1024]; /* the Ewald terms' choice (scene_electrostatics), "" for the reaction field */
} scan_opts;

static double now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* "1,2,4,6" with an optional unit (the next argument, or the suffix of the last value, which then
 * applies to every bare value: "1,2,4fs" is 1, 2 and 4 fs) -> h[], sorted. */
static int parse_timesteps(const char *list, const char *unit, rl_units u, scan_opts *o, char *err, size_t errlen)
{
  char buf[1024], last_unit[64] = "";
  snprintf(buf, sizeof buf, "%s", list);
  const char *tail = strrchr(list, ',') ? strrchr(list, ',') + 1 : list;
  while (*tail && (strchr("0123456789.+-eE ", *tail))) tail++;
  if (*tail && !unit) snprintf(last_unit, sizeof last_unit, "%s", tail);
  o->nh = 0;
  for (char *save, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    if (o->nh == SCAN_MAX) { snprintf(err, errlen, "--timesteps: more than %d values", SCAN_MAX); return -1; }
    char q[256], e[256];
    int bare = 1;
    for (const char *c = tok; *c; c++) bare &= strchr("0123456789.+-eE ", *c) != NULL;
    const char *uu = unit ? unit : bare && last_unit[0] ? last_unit : NULL;
    snprintf(q, sizeof q, "%s%s%s", tok, uu ? " " : "", uu ? uu : "");
    double h;
    if (rl_parse_quantity(q, Q_TIME, u, 0, &h, e, sizeof e)) { snprintf(err, errlen, "--timesteps: %s", e); return -1; }
    if (!(h > 0)) { snprintf(err, errlen, "--timesteps: '%s' is not a positive time step", q); return -1; }
    o->h[o->nh++] = h;
  }
  if (!o->nh) { snprintf(err, errlen, "--timesteps: no values"); return -1; }
  qsort(o->h, (size_t)o->nh, sizeof o->h[0], cmp_double);
  return 0;
}

static int parse_integrators(const char *list, scan_opts *o, char *err, size_t errlen)
{
  char buf[1024];
  snprintf(buf, sizeof buf, "%s", list);
  o->ninteg = 0;
  for (char *save, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
    int k = rl_deck_integrator_lookup(tok);
    if (k < 0) {
      int n = snprintf(err, errlen, "--integrators: unknown integrator '%s' (known:", tok);
      for (int i = 0; i < rl_deck_nintegrators && n > 0 && (size_t)n < errlen; i++)
        n += snprintf(err + n, errlen - (size_t)n, " %s", rl_deck_integrators[i].name);
      if (n > 0 && (size_t)n < errlen) snprintf(err + n, errlen - (size_t)n, ")");
      return -1;
    }
    if (o->ninteg == SCAN_MAX) { snprintf(err, errlen, "--integrators: more than %d", SCAN_MAX); return -1; }
    o->integ[o->ninteg++] = k;
  }
  if (!o->ninteg) { snprintf(err, errlen, "--integrators: none given"); return -1; }
  return 0;
}

/* The first pair of output.rdf ("O-O, H-H" -> O, O), or site 0 - site 0. */
static int rdf_pair(const rl_deck *d, const rl_molecule *m, int site[2], char *name, size_t len)
{
  int pairs[RL_DECK_MAX_RDF][2];
  char names[RL_DECK_MAX_RDF][24];
  const int n = rl_deck_rdf_pairs(d->rdf, m, pairs, names);
  if (n < 0) return RL_EINVAL;
  site[0] = n ? pairs[0][0] : 0;
  site[1] = n ? pairs[0][1] : 0;
  if (n) snprintf(name, len, "%s", names[0]);
  else snprintf(name, len, "%s-%s", m->site_names[0], m->site_names[0]);
  return 0;
}

/* The steps of a run at time step h: --steps, or --time / h, or run.steps (unchecked). */
static double run_steps_exact(const rl_deck *d, const scan_opts *o, double h)
{
  return o->time > 0 ? o->time / h : (double)(o->steps > 0 ? o->steps : d->steps);
}
static long run_steps(const rl_deck *d, const scan_opts *o, double h)
{
  const double x = run_steps_exact(d, o, h);
  return x < 2.0 ? 2 : x > (double)SCAN_MAX_STEPS ? SCAN_MAX_STEPS : lround(x);
}

/* What one scan run accumulates from the run driver's reports. */
typedef struct {
  scan_run *r;
  const rl_deck *d;
  long thermo;              /* a point of the calE curve every this many steps               */
  rl_series *E, *U;
  analysis *an;
  rl_system *sys;
  const int *site;
  long sample;
  int cap;                  /* of r->curve                                                   */
  long done;
  double st_sum, stt, sE, stE, sTt, sTr, its;
  double report_wall;       /* time spent in these reporters (not the step's cost)          */
  const rl_forcefield *tconf; /* output.tconf: the pair term whose sums each sample takes     */
  rl_tconf_sums tc;         /* their sums over the samples                                   */
  rl_series *V, *rho;       /* run.barostat: the volume and density of every step (else NULL) */
  double mass;              /* of the density                                                 */
} scan_acc;

/* Every step: the series of calE and calU, the sums of the drift fit and the temperatures, the
 * iterations, the calE curve every `thermo` steps and at the last, the analysis. */
static int scan_step(void *ctx, const rl_run_report *rep)
{
  scan_acc *a = ctx;
  if (rep->last) return RL_OK;
  const double t0 = now();
  const rl_step_info *info = rep->info;
  scan_run *r = a->r;
  const long k = rep->step;
  int st = RL_OK;
  rl_series_add(a->E, info->conserved);
  rl_series_add(a->U, info->potential);
  a->st_sum += info->t; a->stt += info->t * info->t; a->sE += info->conserved; a->stE += info->t * info->conserved;
  a->sTt += info->t_trans; a->sTr += info->t_rot;
  a->its += info->quat_iterations;
  r->max_h_omega = fmax(r->max_h_omega, info->max_h_omega);
  a->done++;
  if (k % a->thermo == 0 || k + 1 == r->steps) {
    if (r->ncurve == a->cap) {
      void *grown = a->cap < INT_MAX / 2 ? realloc(r->curve, sizeof *r->curve * (size_t)a->cap * 2) : NULL;
      if (!grown) return rl_error(RL_ENOMEM, "step %ld: out of memory for the calE curve (%d points)", k, a->cap);
      r->curve = grown;
      a->cap *= 2;
    }
    double *c = r->curve[r->ncurve++];
    c[0] = (double)k; c[1] = info->t; c[2] = a->done > 1 ? rl_series_rel_fluct(a->E) : 0.0;
  }
  if (a->an) st = analysis_step(a->an, info, scene_pressure_out(a->d, rep->pressure), rep->forces, rep->sys, rep->box);
  if (!st && a->V) {
    const double V = rep->box[0] * rep->box[1] * rep->box[2];
    if (!(st = rl_series_add(a->V, V))) st = rl_series_add(a->rho, a->mass / V);
  }
  a->report_wall += now() - t0;
  return st;
}

/* output.tconf: the pair term of the scene's terms (NULL, and the columns n/a, where another term
 * has no Laplacian in rl_config_temperature, or without output.tconf). */
static const rl_forcefield *scan_tconf_ff(const rl_deck *d, rl_terms *t)
{
  if (!d->tconf || !t || rl_terms_count(t) != 1) return NULL;
  return rl_terms_find(t, &rl_term_pair);
}

/* One sample's sums added to sum. */
static int scan_tconf_add(const rl_forcefield *ff, const rl_system *sys, rl_tconf_sums *sum)
{
  rl_tconf_sums t;
  const int st = rl_config_temperature(ff, sys, &t);
  sum->f2 += t.f2;
  sum->lap_r += t.lap_r;
  sum->k2 += t.k2;
  sum->lap_rot += t.lap_rot;
  return st;
}

/* Every sampling interval: the RDF of the first output.rdf pair, the analysis's sample and, with
 * output.tconf, the configurational temperature's sums. */
static int scan_sample(void *ctx, const rl_run_report *rep)
{
  scan_acc *a = ctx;
  const double t0 = now();
  int st = rl_rdf_add_sites(a->r->rdf, rep->sys, 0, a->site[0], 0, a->site[1]);
  if (!st && a->an) st = analysis_sample(a->an, rep->sys);
  if (!st && a->tconf) st = scan_tconf_add(a->tconf, rep->sys, &a->tc);
  a->report_wall += now() - t0;
  return st;
}

/* One run from a clone of `start`.  Fills r (ok = 0 with the error on failure). */
static void one_run(const rl_deck *d, const scene *base, const rl_system *start, const scan_opts *o,
                    const int site[2], scan_run *r)
{
  const int n = d->count;
  const long thermo = d->thermo_every > 0 ? d->thermo_every : 100;
  r->steps = run_steps(d, o, r->h); /* 2 .. SCAN_MAX_STEPS: checked before the scan */
  long sample = 0;
  if (d->sample_every > 0) { /* the deck's sampling interval in time; beyond the run: none */
    const double x = d->sample_every * d->timestep / r->h;
    sample = x > (double)r->steps ? r->steps + 1 : lround(x);
    if (sample < 1) sample = 1;
  }
  double Lmin = fmin(d->box[0], fmin(d->box[1], d->box[2]));
  rl_system *sys = rl_system_clone(start);
  rl_terms *ff = sys ? scene_terms(d, &base->mol, sys) : NULL;
  rl_series *E = rl_series_alloc(), *U = rl_series_alloc();
  rl_series *sV = d->barostat ? rl_series_alloc() : NULL, *srho = d->barostat ? rl_series_alloc() : NULL;
  /* under a barostat the box may shrink to twice the cutoff (the barostat's bound): the RDF to the cutoff */
  r->rdf = sample ? rl_rdf_alloc(d->barostat ? fmin(0.5 * Lmin, d->ff.cutoff) : 0.5 * Lmin, 200) : NULL;
  int cap = (int)(r->steps / thermo + 2 < 4096 ? r->steps / thermo + 2 : 4096); /* grows with the run */
  r->curve = malloc(sizeof *r->curve * (size_t)cap);
  rl_integrator *in = NULL;
  /* the analysis sees this run's step, energies every step and its sampling interval (its step
   * numbers and times are this run's, not the deck's run.timestep's) */
  rl_deck dr = *d;
  dr.timestep = r->h;
  dr.energy_every = 1;
  dr.sample_every = sample;
  analysis *an = o->analysis && sys ? analysis_alloc(&dr, base->mols, sys) : NULL;
  if (an) analysis_set_tconf(an, ff, scan_tconf_ff(d, ff));
  int st = !sys || !ff || (o->analysis && !an) ? RL_EINVAL : RL_OK; /* these say why */
  if (!st && (!E || !U || !r->curve || (sample && !r->rdf) || (d->barostat && (!sV || !srho))))
    st = rl_error(RL_ENOMEM, "out of memory for the run's accumulators (%d molecules)", n);
  rl_run *drv = NULL;
  if (!st) {
    rl_integrator_params p;
    scene_integrator_params(d, SCENE_RUN, &p); /* the deck's, at this run's step and integrator */
    p.h = r->h;
    p.method = rl_deck_integrators[r->integ].method;
    p.energy_every = 1;
    in = rl_integrator_alloc(sys, &p, rl_terms_provider(ff));
    st = in ? scene_add_barostat(d, in) : RL_EINVAL; /* the deck's, its interval in this run's steps */
    if (!st) st = rl_integrator_init(in);
    rl_run_params rp = {.energy_every = 1, .h = r->h};
    scene_watch_params(d, 0, &rp.watch);
    rp.watch.names.timestep = "the time step";
    if (!st && !(drv = rl_run_alloc(sys, in, ff, &rp))) st = RL_ENOMEM;
  }
  scan_acc acc = {r, d, thermo, E, U, an, sys, site, sample, cap, 0, 0, 0, 0, 0, 0, 0, 0, 0.0,
                  sample ? scan_tconf_ff(d, ff) : NULL, {0.0, 0.0, 0.0, 0.0}, sV, srho,
                  sys ? scene_density_mass(d, sys) : 0.0};
  r->max_h_omega = 0.0;
  r->tconf_trans = r->tconf_rot = NAN;
  const rl_reporter reps[2] = {{"scan", RL_REPORT_STEP, 1, scan_step, &acc},
                               {"scan samples", RL_REPORT_STATE, sample > 0 ? sample : 1, scan_sample, &acc}};
  for (int q = 0; !st && q < (sample > 0 ? 2 : 1); q++) st = rl_run_add_reporter(drv, &reps[q]);
  double wall = 0.0;
  long done = 0;
  if (!st) { /* the cost per step: the driver's time less its reporters' */
    const double t0 = now();
    st = rl_run_steps(drv, 0, r->steps, NULL, &done);
    wall = now() - t0 - acc.report_wall;
  }
  rl_run_free(drv);
  double st_sum = acc.st_sum, stt = acc.stt, sE = acc.sE, stE = acc.stE, sTt = acc.sTt, sTr = acc.sTr, its = acc.its;
  r->ok = !st;
  r->done = done;
  if (st) snprintf(r->error, sizeof r->error, "%s", rl_last_error());
  if (an && done > 0) { /* PREFIX.<integrator>.h<h> .results.txt, .rdf.csv, .tcf.csv */
    char tail[96];
    snprintf(tail, sizeof tail, ".%s.h%g", rl_deck_integrators[r->integ].name, r->h * (d->units == RL_UNITS_REAL ? 1e3 : 1.0));
    char *pre = outputs_name(o->prefix, tail);
    if (!pre || analysis_write(an, pre, NULL, (sample ? sample : 1) * r->h)) {
      fprintf(stderr, "rotleap scan: writing %s%s.*: %s\n", o->prefix, tail, pre ? rl_last_error() : "out of memory");
      r->analysis_bad = 1;
    }
    free(pre);
  }
  analysis_free(an);
  if (done > 1) {
    r->calE = rl_series_rel_fluct(E);
    r->calU = rl_series_rel_fluct(U);
    double var_t = stt / done - (st_sum / done) * (st_sum / done);
    double slope = var_t > 0 ? (stE / done - (st_sum / done) * (sE / done)) / var_t : 0.0;
    r->drift = slope / n * (d->units == RL_UNITS_REAL ? 1e3 : 1.0); /* per molecule per ns (real) */
    r->t_trans = sTt / done;
    r->t_rot = sTr / done;
    const double kB = rl_units_kB(d->units);
    r->tconf_trans = acc.tconf && acc.tc.lap_r > 0.0 ? acc.tc.f2 / acc.tc.lap_r / kB : NAN;
    r->tconf_rot = acc.tconf && acc.tc.lap_rot > 0.0 ? acc.tc.k2 / acc.tc.lap_rot / kB : NAN;
    r->wall_per_step = wall / done;
    r->ns_day = d->units == RL_UNITS_REAL ? r->h * 1e-3 * 86400.0 / r->wall_per_step : 0.0;
  }
  r->V = r->V_err = r->rho = r->rho_err = NAN;
  rl_block_result bv, br;
  if (sV && !rl_series_block_average(sV, &bv) && !rl_series_block_average(srho, &br)) {
    r->V = bv.mean;
    r->V_err = bv.sem;
    r->rho = br.mean;
    r->rho_err = br.sem;
    r->V_plateau = bv.converged && br.converged;
  }
  rl_series_free(sV);
  rl_series_free(srho);
  r->ortho = sys ? scene_rigidity_error(sys) : NAN;
  r->fallbacks = in ? rl_integrator_fallbacks(in) : 0;
  int nmat = 0;
  for (int i = 0; sys && i < n; i++) {
    rl_kind kk = rl_system_species_kind(sys, rl_system_species_of(sys, i));
    nmat += kk == RL_KIND_SPHERICAL || kk == RL_KIND_SYMMETRIC || kk == RL_KIND_ASYMMETRIC;
  }
  r->iterations = done && nmat ? its / ((double)done * nmat) : 0.0;
  rl_integrator_free(in);
  rl_series_free(E);
  rl_series_free(U);
  rl_terms_free(ff);
  rl_system_free(sys);
}

/* The RDF distance as text: "n/a" where either run sampled no configuration (as the summary
 * says for averages over no step), never "nan". */
static const char *rdf_text(char *buf, size_t len, const char *fmt, double x)
{
  if (isnan(x)) snprintf(buf, len, "n/a");
  else snprintf(buf, len, fmt, x);
  return buf;
}

static void print_table(FILE *f, const rl_deck *d, const scan_opts *o, const scan_run *runs, int nruns,
                        const char *rdfname)
{
  const char *tu = rl_dim_unit(Q_TIME, d->units);
  int real = d->units == RL_UNITS_REAL;
  double hs = real ? 1e3 : 1.0; /* print steps in fs */
  fprintf(f, "# rotleap scan of %s: %s, %d molecules, %s%s%s; shared start, %s\n", d->path, d->model->name, d->count,
          d->thermostat == RL_THERMO_NONE ? "NVE" : d->barostat ? "NPT (" : "NVT (",
          d->thermostat == RL_THERMO_NONE ? "" : rl_thermostat_name(d->thermostat),
          d->thermostat == RL_THERMO_NONE ? "" : ")",
          o->time > 0 ? "equal simulated time" : "equal number of steps");
  if (d->barostat)
    fprintf(f, "# barostat: %s at %g %s, every %ld steps of each run; rho, V: blocked means over every step of the run "
               "(from the shared start: no equilibration discarded) +- their standard error%s\n",
            d->barostat == 1 ? "Monte Carlo" : "C-rescale", scene_pressure_out(d, d->pressure), real ? "bar" : "(reduced)",
            d->baro_interval, real ? "; rho in g/cm^3, V in nm^3" : "");
  if (o->electrostatics[0]) fprintf(f, "# electrostatics: %s\n", o->electrostatics);
  fprintf(f, "# calE, calU: relative rms fluctuations of the conserved and potential energy; drift: of the conserved "
             "energy, %s per molecule per %s; ortho: max |A A^T - I| or ||rho|-1| at the end; rdf: int |g - g_ref| dr "
             "/ r_max for %s against the first run; iter: quaternion/implicit iterations per body and step\n",
          real ? "kJ/mol" : "reduced", real ? "ns" : "time unit", rdfname);
  if (d->tconf)
    fprintf(f, "# Tc_trans, Tc_rot: configurational temperatures <sum |F|^2> / <sum lap_R U> and <sum |tau|^2> / <sum "
               "lap_phi U> over the samples (output.tconf; docs/observables.md)\n");
  fprintf(f, "%-14s %7s %7s %10s %10s %8s %10s %8s %6s %8s %8s %6s ", "integrator", real ? "h(fs)" : "h", "steps", "calE",
          "calU", "E/U", "drift", "ortho", "fallb", "T_trans", "T_rot", "Tr/Tt");
  if (d->tconf) fprintf(f, "%8s %8s ", "Tc_trans", "Tc_rot");
  if (d->barostat) fprintf(f, "%10s %9s %10s %9s ", "rho", "+-", "V", "+-");
  fprintf(f, "%8s %6s %9s %9s  %s\n", "rdf", "iter", "ms/step", real ? "ns/day" : "", "status");
  for (int k = 0; k < nruns; k++) {
    const scan_run *r = &runs[k];
    char rdf[32];
    fprintf(f, "%-14s %7.3g %7ld %10.3e %10.3e %7.2f%% %10.3e %8.1e %6ld %8.2f %8.2f %6.3f ",
            rl_deck_integrators[r->integ].name, r->h * hs, r->done, r->calE, r->calU,
            r->calU > 0 ? 100.0 * r->calE / r->calU : 0.0, r->drift, r->ortho, r->fallbacks, r->t_trans, r->t_rot,
            r->t_trans > 0 ? r->t_rot / r->t_trans : 0.0);
    if (d->tconf) {
      char tt[32], tr[32];
      fprintf(f, "%8s %8s ", rdf_text(tt, sizeof tt, "%.2f", r->tconf_trans), rdf_text(tr, sizeof tr, "%.2f", r->tconf_rot));
    }
    if (d->barostat) {
      char x[4][32];
      fprintf(f, "%10s %9s %10s %9s ", rdf_text(x[0], sizeof x[0], "%.5g", r->rho), rdf_text(x[1], sizeof x[1], "%.2g", r->rho_err),
              rdf_text(x[2], sizeof x[2], "%.6g", r->V), rdf_text(x[3], sizeof x[3], "%.2g", r->V_err));
    }
    fprintf(f, "%8s %6.2f %9.3f %9.3g  %s\n", rdf_text(rdf, sizeof rdf, "%.4f", r->rdf_dist), r->iterations,
            1e3 * r->wall_per_step, r->ns_day, r->ok ? "ok" : r->error);
  }
  fprintf(f, "# largest time step with calE/calU <= %.3g%% (and no error):\n", 100.0 * o->tolerance);
  for (int i = 0; i < o->ninteg; i++) {
    const scan_run *best = NULL;
    for (int k = 0; k < nruns; k++)
      if (runs[k].integ == o->integ[i] && runs[k].ok && runs[k].calU > 0 &&
          runs[k].calE <= o->tolerance * runs[k].calU)
        best = &runs[k];
    if (best)
      fprintf(f, "#   %-14s %g %s (%.3g ns/day)\n", rl_deck_integrators[o->integ[i]].name, best->h * hs,
              real ? "fs" : tu, best->ns_day);
    else
      fprintf(f, "#   %-14s none of the steps scanned\n", rl_deck_integrators[o->integ[i]].name);
  }
}

/* A CSV field: the text quoted, inner quotes doubled. */
static void csv_text(FILE *f, const char *s)
{
  fputc('"', f);
  for (; *s; s++) {
    if (*s == '"') fputc('"', f);
    fputc(*s == '\n' ? ' ' : *s, f);
  }
  fputc('"', f);
}

static int write_table_csv(const rl_deck *d, const scan_opts *o, const scan_run *runs, int nruns, const char *rdfname,
                           const char *path);
static int write_curve_csv(const rl_deck *d, const scan_run *runs, int nruns, const char *path);

static int write_outputs(const rl_deck *d, const scan_opts *o, const char *prefix, const scan_run *runs,
                         int nruns, const char *rdfname)
{
  rl_atomic_file af;
  char *path[3] = {outputs_name(prefix, ".scan.csv"), outputs_name(prefix, ".scan_calE.csv"), outputs_name(prefix, ".scan.txt")};
  int st = !path[0] || !path[1] || !path[2] ? rl_error(RL_ENOMEM, "out of memory") : RL_OK;
  if (!st) st = write_table_csv(d, o, runs, nruns, rdfname, path[0]);
  if (!st) st = write_curve_csv(d, runs, nruns, path[1]);
  if (!st && !(st = rl_atomic_open(&af, path[2]))) {
    print_table(af.fp, d, o, runs, nruns, rdfname);
    st = rl_atomic_commit(&af);
  }
  for (int k = 0; k < 3; k++) free(path[k]);
  return st ? 1 : 0;
}

static int write_table_csv(const rl_deck *d, const scan_opts *o, const scan_run *runs, int nruns, const char *rdfname,
                           const char *path)
{
  rl_atomic_file af;
  const int real = d->units == RL_UNITS_REAL;
  if (rl_atomic_open(&af, path)) return 1;
  fprintf(af.fp, "integrator,h_%s,steps,steps_done,calE,calU,calE_over_calU,drift_per_molecule_per_%s,ortho_error,fallbacks,"
                 "iterations_per_body_step,max_h_omega,t_trans,t_rot,t_rot_over_t_trans,tconf_trans,tconf_rot,rdf_distance_%s,"
                 "wall_s_per_step,ns_per_day,%smeets_tolerance,status\n",
          real ? "fs" : "reduced", real ? "ns" : "time", rdfname,
          !d->barostat ? "" : real ? "density_g_cm3,density_err,volume_nm3,volume_err,volume_plateau,"
                                   : "density,density_err,volume,volume_err,volume_plateau,");
  for (int k = 0; k < nruns; k++) {
    const scan_run *r = &runs[k];
    int meets = r->ok && r->calU > 0 && r->calE <= o->tolerance * r->calU;
    char rdf[32], tt[32], tr[32];
    fprintf(af.fp, "%s,%.10g,%ld,%ld,%.6e,%.6e,%.6e,%.6e,%.3e,%ld,%.4g,%.4g,%.6g,%.6g,%.6g,%s,%s,%s,%.6e,%.6g,%s",
            rl_deck_integrators[r->integ].name, r->h * (real ? 1e3 : 1.0), r->steps, r->done, r->calE, r->calU,
            r->calU > 0 ? r->calE / r->calU : 0.0, r->drift, r->ortho, r->fallbacks, r->iterations, r->max_h_omega,
            r->t_trans, r->t_rot, r->t_trans > 0 ? r->t_rot / r->t_trans : 0.0,
            rdf_text(tt, sizeof tt, "%.6g", r->tconf_trans), rdf_text(tr, sizeof tr, "%.6g", r->tconf_rot),
            rdf_text(rdf, sizeof rdf, "%.6e", r->rdf_dist), r->wall_per_step, r->ns_day, "");
    if (d->barostat) {
      char x[4][32];
      fprintf(af.fp, "%s,%s,%s,%s,%s,", rdf_text(x[0], sizeof x[0], "%.8g", r->rho), rdf_text(x[1], sizeof x[1], "%.3g", r->rho_err),
              rdf_text(x[2], sizeof x[2], "%.8g", r->V), rdf_text(x[3], sizeof x[3], "%.3g", r->V_err),
              isnan(r->V) ? "n/a" : r->V_plateau ? "yes" : "no");
    }
    fprintf(af.fp, "%s,", meets ? "yes" : "no");
    csv_text(af.fp, r->ok ? "ok" : r->error);
    fputc('\n', af.fp);
  }
  return rl_atomic_commit(&af);
}

static int write_curve_csv(const rl_deck *d, const scan_run *runs, int nruns, const char *path)
{
  rl_atomic_file af;
  const int real = d->units == RL_UNITS_REAL;
  if (rl_atomic_open(&af, path)) return 1;
  fprintf(af.fp, "integrator,h_%s,step,time_%s,calE\n", real ? "fs" : "reduced", real ? "ps" : "reduced");
  for (int k = 0; k < nruns; k++)
    for (int j = 0; j < runs[k].ncurve; j++)
      fprintf(af.fp, "%s,%.10g,%.0f,%.10g,%.6e\n", rl_deck_integrators[runs[k].integ].name,
              runs[k].h * (real ? 1e3 : 1.0), runs[k].curve[j][0], runs[k].curve[j][1], runs[k].curve[j][2]);
  return rl_atomic_commit(&af);
}

/* PNG plots by scripts/plot_scan.py (matplotlib), next to the CSVs. */
static int plot(const char *prefix)
{
  const char *script = getenv("ROTLEAP_PLOT_SCAN");
  char def[1024];
  if (!script) {
    snprintf(def, sizeof def, "%s/scripts/plot_scan.py", ROTLEAP_SOURCE_DIR);
    script = def;
  }
  if (access(script, R_OK)) {
    fprintf(stderr, "rotleap scan: plots not made: %s not found (set ROTLEAP_PLOT_SCAN)\n", script);
    return 1;
  }
  const char *py = access("/usr/bin/python3", X_OK) ? "python3" : "/usr/bin/python3";
  if (strchr(prefix, '\'') || strchr(script, '\'')) {
    fprintf(stderr, "rotleap scan: plots not made: a quote in the path\n");
    return 1;
  }
  const size_t n = strlen(py) + strlen(script) + strlen(prefix) + 16;
  char *cmd = malloc(n);
  if (!cmd) return 1;
  snprintf(cmd, n, "'%s' '%s' '%s'", py, script, prefix);
  int rc = system(cmd);
  free(cmd);
  if (rc) {
    fprintf(stderr, "rotleap scan: plots not made (%s exited with %d; it needs python3-matplotlib); the CSV files are "
                    "complete\n", script, rc);
    return 1;
  }
  return 0;
}

static void usage(FILE *f)
{
  fprintf(f,
          "usage: rotleap scan DECK [--timesteps LIST [UNIT]] [--integrators LIST] [--steps N | --time T]\n"
          "                        [--tolerance X] [--analysis] [--no-plot] [--set section.key=value ...]\n"
          "\n"
          "Runs the deck's scene from one shared start (the deck's start after its run.equilibrate relaxation;\n"
          "give system.start = an equilibrated checkpoint for a careful scan: its half-step velocities are\n"
          "completed to on-step ones with run.timestep, the step of the run that wrote it) for every time step and\n"
          "integrator, in the deck's ensemble, and reports per run: calE, calU and their ratio, the drift of\n"
          "the conserved energy per molecule and ns, the orthonormality error, guarded-solve fallbacks,\n"
          "iterations, the RDF distance (first output.rdf pair, else site 0 - site 0) from the first\n"
          "integrator's smallest step, T_trans, T_rot and their ratio, wall time per step and ns/day.  It\n"
          "marks, per integrator, the largest step with calE/calU <= the tolerance.\n"
          "\n"
          "  --timesteps LIST   e.g. \"1,2,4,6 fs\" (default: run.timestep)\n"
          "  --integrators LIST e.g. rl,rl-quaternion (default: run.integrator); known:");
  for (int i = 0; i < rl_deck_nintegrators; i++) fprintf(f, " %s", rl_deck_integrators[i].name);
  fprintf(f,
          "\n  --steps N          steps per run (default run.steps): the same number for every step size\n"
          "  --time T           instead, the same simulated time per run, e.g. \"10 ps\"; a run has 2 to\n"
          "                     1e9 steps (refused otherwise, before anything runs)\n"
          "  --tolerance X      calE/calU tolerance, \"5%%\" or 0.05 (default 5%%)\n"
          "  --no-plot          skip PREFIX.scan_calE.png and PREFIX.scan_pareto.png\n"
          "  --analysis         also write each run's analysis, as rotleap run does (output.rdf,\n"
          "                     sample_every): PREFIX.<integrator>.h<h>.results.txt, .rdf.csv, .tcf.csv\n"
          "\n"
          "Writes PREFIX.scan.csv, PREFIX.scan_calE.csv (calE against run length), PREFIX.scan.txt and the\n"
          "plots, PREFIX = output.prefix; each file is replaced atomically after every run.\n");
}

int rl_app_scan(int argc, char **argv)
{
  const char *path = NULL, *ts = NULL, *ts_unit = NULL, *integ = NULL, *steps = NULL, *time = NULL, *tol = NULL;
  char **sets = calloc((size_t)argc + 1, sizeof *sets);
  int nsets = 0, plot_it = 1, analysis_it = 0;
  if (!sets) return 1;
  for (int i = 0; i < argc; i++) {
    const char *a = argv[i];
    const char **slot = !strcmp(a, "--timesteps") ? &ts : !strcmp(a, "--integrators") ? &integ
                      : !strcmp(a, "--steps") ? &steps : !strcmp(a, "--time") ? &time
                      : !strcmp(a, "--tolerance") ? &tol : NULL;
    if (!strcmp(a, "--help") || !strcmp(a, "-h")) { usage(stdout); free(sets); return 0; }
    if (slot || !strcmp(a, "--set")) {
      if (i + 1 >= argc) { fprintf(stderr, "rotleap scan: %s needs a value\n", a); free(sets); return 2; }
      if (slot) *slot = argv[++i];
      else sets[nsets++] = argv[++i];
      /* "--timesteps 1,2,4 fs": a unit as the next word */
      if (slot == &ts && i + 1 < argc && argv[i + 1][0] != '-') {
        double x;
        char e[128], q[64];
        snprintf(q, sizeof q, "1 %s", argv[i + 1]);
        if (!rl_parse_quantity(q, Q_TIME, RL_UNITS_REAL, 0, &x, e, sizeof e)) ts_unit = argv[++i];
      }
    } else if (!strcmp(a, "--no-plot")) plot_it = 0;
    else if (!strcmp(a, "--analysis")) analysis_it = 1;
    else if (a[0] == '-') { fprintf(stderr, "rotleap scan: unknown option '%s' (rotleap scan --help)\n", a); free(sets); return 2; }
    else if (path) { fprintf(stderr, "rotleap scan: more than one deck ('%s', '%s')\n", path, a); free(sets); return 2; }
    else path = a;
  }
  if (!path) { fprintf(stderr, "rotleap scan: no deck given (rotleap scan --help)\n"); free(sets); return 2; }
  rl_deck d;
  int problems = rl_deck_load(path, sets, nsets, &d, stderr);
  free(sets);
  if (problems) {
    fprintf(stderr, "rotleap scan: %d problem%s in %s; nothing was run\n", problems, problems > 1 ? "s" : "", path);
    return 2;
  }
  if (d.nspecies > 1) { /* the scan's shared start and analysis are built for one molecule */
    fprintf(stderr, "rotleap scan: %s: a mixture (system.species) cannot be scanned yet: scan one species, or time "
                    "the mixture with rotleap run at each step\n", path);
    return 2;
  }
  scan_opts o;
  memset(&o, 0, sizeof o);
  o.tolerance = 0.05;
  o.plot = plot_it;
  o.analysis = analysis_it;
  o.prefix = d.prefix;
  char err[512] = "";
  int bad = 0;
  if (ts) bad |= parse_timesteps(ts, ts_unit, d.units, &o, err, sizeof err) != 0;
  else { o.h[0] = d.timestep; o.nh = 1; }
  double w = rl_deck_thermal_omega(&d);
  const char *tkey;
  const double T = rl_deck_max_temperature(&d, &tkey);
  for (int j = 0; !bad && j < o.nh; j++)
    if (o.h[j] * w > 1.0) {
      snprintf(err, sizeof err, "--timesteps: %g %s is too large for %s at %g %s%s: h times the thermal "
               "angular velocity is %.3g > 1, no step can follow the rotation", o.h[j], rl_dim_unit(Q_TIME, d.units),
               d.model->name, T, rl_dim_unit(Q_TEMPERATURE, d.units), tkey, o.h[j] * w);
      bad = 1;
    }
  if (!bad && integ) bad |= parse_integrators(integ, &o, err, sizeof err) != 0;
  else if (!bad) {
    for (int i = 0; i < rl_deck_nintegrators; i++)
      if (rl_deck_integrators[i].method == d.method) o.integ[0] = i;
    o.ninteg = 1;
  }
  if (!bad && steps) {
    char *end;
    errno = 0;
    o.steps = strtol(steps, &end, 10);
    if (errno || *end || o.steps < 2) { snprintf(err, sizeof err, "--steps: '%s' is not a whole number >= 2", steps); bad = 1; }
  }
  if (!bad && time && (rl_parse_quantity(time, Q_TIME, d.units, 0, &o.time, err, sizeof err) || !(o.time > 0))) {
    if (!err[0]) snprintf(err, sizeof err, "--time: '%s' must be positive", time);
    bad = 1;
  }
  if (!bad && steps && time) { snprintf(err, sizeof err, "give --steps or --time, not both"); bad = 1; }
  /* every run between 2 and SCAN_MAX_STEPS steps (the time steps are sorted) */
  if (!bad && o.nh > 0) {
    const char *what = time ? "--time" : steps ? "--steps" : "run.steps";
    const double most = run_steps_exact(&d, &o, o.h[0]), least = run_steps_exact(&d, &o, o.h[o.nh - 1]);
    const double hs = d.units == RL_UNITS_REAL ? 1e3 : 1.0;
    const char *hu = d.units == RL_UNITS_REAL ? " fs" : "";
    char given[64];
    snprintf(given, sizeof given, "%.40s", time ? time : steps ? steps : "");
    if (!time && !steps) snprintf(given, sizeof given, "= %ld", d.steps);
    if (!(most <= (double)SCAN_MAX_STEPS)) {
      snprintf(err, sizeof err, "%s %s is %.3g steps at h = %g%s: a scan run takes at most %ld (give %s)",
               what, given, most, o.h[0] * hs, hu, SCAN_MAX_STEPS,
               time ? "a shorter --time" : steps ? "fewer --steps" : "--steps or --time");
      bad = 1;
    } else if (time && !(lround(least) >= 2)) {
      snprintf(err, sizeof err, "--time %s is %.3g steps at h = %g%s: a run needs at least 2", given, least,
               o.h[o.nh - 1] * hs, hu);
      bad = 1;
    }
  }
  if (!bad && tol) {
    char *end;
    o.tolerance = strtod(tol, &end);
    if (*end == '%' && !end[1]) { o.tolerance /= 100.0; end++; }
    if (*end || !(o.tolerance > 0)) { snprintf(err, sizeof err, "--tolerance: '%s' is not a positive fraction or percentage", tol); bad = 1; }
  }
  if (bad) { fprintf(stderr, "rotleap scan: %s\n", err); return 2; }
  /* none of the scan's files may overwrite the deck or the start; the directory must be safe to
   * write in, and no other run may be writing this prefix (PREFIX.lock, as rotleap run) */
  static const char *const ext[] = {".scan.csv", ".scan_calE.csv", ".scan.txt", ".scan_calE.png", ".scan_pareto.png"};
  char *outs[5];
  int st = RL_OK;
  for (int k = 0; k < 5; k++)
    if (!(outs[k] = outputs_name(d.prefix, ext[k]))) st = rl_error(RL_ENOMEM, "out of memory");
  if (!st) st = scene_check_outputs(&d, (const char *const *)outs, 5);
  for (int k = 0; k < 5; k++) free(outs[k]);
  outputs *lock = st ? NULL : outputs_alloc(d.prefix, NULL, 0);
  if (!st && !lock) st = RL_ENOMEM;
  if (!st) st = outputs_check_dir(d.prefix);
  if (!st) st = outputs_lock(lock);
  if (st) {
    fprintf(stderr, "rotleap scan: %s\n", rl_last_error());
    outputs_free(lock);
    return 1;
  }

  scene s;
  if (scene_build(&d, &s) || scene_relax(&d, &s) || scene_onstep(&d, &s)) {
    fprintf(stderr, "rotleap scan: %s\n", rl_last_error());
    scene_free(&s);
    outputs_free(lock);
    return 1;
  }
  scene_electrostatics(&d, s.terms, o.electrostatics, sizeof o.electrostatics);
  int site[2];
  char rdfname[64];
  if (rdf_pair(&d, &s.mol, site, rdfname, sizeof rdfname)) {
    fprintf(stderr, "rotleap scan: %s\n", rl_last_error());
    scene_free(&s);
    outputs_free(lock);
    return 1;
  }
  int nruns = o.nh * o.ninteg;
  scan_run *runs = calloc((size_t)nruns, sizeof *runs);
  if (!runs) { scene_free(&s); outputs_free(lock); return 1; }
  int progress = d.progress < 0 ? isatty(fileno(stderr)) : d.progress, io_bad = 0;
  const double hs = d.units == RL_UNITS_REAL ? 1e3 : 1.0;
  for (int i = 0, k = 0; i < o.ninteg && !io_bad; i++)
    for (int j = 0; j < o.nh && !io_bad; j++, k++) {
      scan_run *r = &runs[k];
      r->integ = o.integ[i];
      r->h = o.h[j];
      if (progress)
        fprintf(stderr, "rotleap scan: run %d/%d: %s at h = %g%s ...\n", k + 1, nruns, rl_deck_integrators[r->integ].name,
                r->h * hs, d.units == RL_UNITS_REAL ? " fs" : "");
      one_run(&d, &s, s.sys, &o, site, r);
      if (!r->ok) fprintf(stderr, "rotleap scan: %s at h = %g%s: %s\n", rl_deck_integrators[r->integ].name, r->h * hs,
                d.units == RL_UNITS_REAL ? " fs" : "", r->error);
      /* RDF distance from the reference run (runs[0]: first integrator, smallest step) */
      for (int q = 0; q <= k; q++) {
        double dist = NAN;
        if (runs[0].rdf && runs[q].rdf && rl_rdf_frames(runs[0].rdf) > 0 && rl_rdf_frames(runs[q].rdf) > 0 &&
            !rl_rdf_distance(runs[q].rdf, runs[0].rdf, &dist))
          dist /= rl_rdf_rmax(runs[0].rdf);
        runs[q].rdf_dist = dist;
      }
      if (write_outputs(&d, &o, d.prefix, runs, k + 1, rdfname)) {
        fprintf(stderr, "rotleap scan: %s\n", rl_last_error());
        io_bad = 1;
      }
    }
  if (!io_bad) {
    print_table(stdout, &d, &o, runs, nruns, rdfname);
    printf("# outputs: %s.scan.csv, %s.scan_calE.csv, %s.scan.txt%s\n", d.prefix, d.prefix, d.prefix,
           o.plot ? ", .scan_calE.png, .scan_pareto.png" : "");
    if (o.plot) plot(d.prefix);
  }
  /* runs that blew up are results of the scan (reported in the table), not failures of it;
     a file that could not be written is (as for rotleap run) */
  int analysis_bad = 0;
  for (int k = 0; k < nruns; k++) {
    analysis_bad |= runs[k].analysis_bad;
    rl_rdf_free(runs[k].rdf);
    free(runs[k].curve);
  }
  free(runs);
  scene_free(&s);
  outputs_free(lock);
  if (analysis_bad) fprintf(stderr, "rotleap scan: some per-run analysis files were not written (above)\n");
  return io_bad || analysis_bad ? 1 : 0;
}
