/* rotleap run's analysis, its files: PREFIX.results.txt (means with blocked errors, jackknifed
 * fluctuation quantities, the equilibrated part, the dielectric constant, the configurational
 * temperature, the barostat's lines), .rdf.csv and .tcf.csv, from the accumulators app/analysis.c
 * fills. */
#include "analysis_internal.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ------------------------------------------------------------------ results */

/* The units of the results and of the CSV columns, by unit system (lj: reduced units of
 * epsilon, sigma and the mass; tau = sigma sqrt(m / epsilon)). */
typedef struct {
  const char *E, *T, *P, *F2, *K2, *D, *time, *t_col, *r_col, *vacf_col, *wacf_col, *msd_col;
} units_text;

static units_text units_of(rl_units u)
{
  if (u == RL_UNITS_LJ)
    return (units_text){"epsilon", "epsilon/k_B", "epsilon/sigma^3", "(epsilon/sigma)^2", "epsilon^2", "sigma^2/tau",
                        "tau", "lag_time_tau", "r_sigma", "vacf_sigma2_per_tau2", "omega_acf_per_tau2", "msd_sigma2"};
  return (units_text){"kJ/mol", "K", "bar", "(kJ/mol/nm)^2", "(kJ/mol)^2", "nm^2/ps",
                      "ps", "lag_time_ps", "r_nm", "vacf_nm2_per_ps2", "omega_acf_per_ps2", "msd_nm2"};
}

/* "NAME = mean +- sem UNIT": the blocked mean of the samples from `from` on. */
static void line_mean(FILE *f, const char *name, const rl_trace *t, long from, const char *unit)
{
  const rl_moments m = rl_trace_moments(t, from);
  rl_block_result b;
  if (m.n == 0) fprintf(f, "%s = n/a (no step averaged)\n", name);
  else if (m.n < 4 || rl_trace_block_average(t, from, &b))
    fprintf(f, "%s = %.8g %s (no error bar: %ld samples)\n", name, m.mean, unit, m.n);
  else
    fprintf(f, "%s = %.8g +- %.2g %s%s\n", name, b.mean, b.sem, unit,
            b.converged ? "" : " (error bar a lower bound: no blocking plateau; run longer)");
}

const char *rel_fluct_text(char *buf, size_t n, double x)
{
  if (isfinite(x)) snprintf(buf, n, "%.6e", x);
  else snprintf(buf, n, "n/a (the mean is 0)");
  return buf;
}

/* ---- jackknife errors of fluctuation quantities */

/* An estimator of the moments m[k] of k = 0, 1, ... series (NaN where undefined). */
typedef double (*estimator)(const rl_moments *m, const void *ctx);

typedef struct {
  double value, err; /* over every sample from the start; jackknife error (NaN: none)        */
  long groups, len;  /* jackknife blocks and their length in samples                           */
  int plateau;       /* the blocking of every series found a plateau (else err is a lower bound) */
} jk_result;

/* value = f(moments of tr[k] from `from`), err = the jackknife standard error over blocks as
 * long as the longest Lee-Needs-Towler block of the series (their means' correlation time). */
static void jackknife(rl_trace *const *tr, int ntr, long from, estimator f, const void *ctx, jk_result *r)
{
  rl_moments all[4];
  for (int k = 0; k < ntr; k++) all[k] = rl_trace_moments(tr[k], from);
  r->value = f(all, ctx);
  r->err = NAN;
  r->groups = 0;
  r->len = rl_trace_block(tr[0]);
  r->plateau = 1;
  for (int k = 0; k < ntr; k++) {
    rl_block_result b;
    if (rl_trace_block_average(tr[k], from, &b)) return;
    r->plateau &= b.converged;
    if (1L << b.level > r->len) r->len = 1L << b.level;
  }
  const long m = rl_trace_groups(tr[0], from, r->len, NULL, 0);
  if (m < 2) return;
  rl_moments *g = malloc(sizeof *g * (size_t)(2 * ntr) * (size_t)m), *loo = g ? g + (size_t)ntr * (size_t)m : NULL;
  double *theta = malloc(sizeof *theta * (size_t)m);
  if (g && theta) {
    for (int k = 0; k < ntr; k++) {
      rl_trace_groups(tr[k], from, r->len, g + (size_t)k * (size_t)m, m);
      rl_moments_leave_one_out(g + (size_t)k * (size_t)m, m, loo + (size_t)k * (size_t)m);
    }
    for (long i = 0; i < m; i++) {
      rl_moments mi[4];
      for (int k = 0; k < ntr; k++) mi[k] = loo[(size_t)k * (size_t)m + (size_t)i];
      theta[i] = f(mi, ctx);
    }
    r->err = rl_jackknife_error(theta, m);
    r->groups = m;
  }
  free(g);
  free(theta);
}

/* " +- ERR" and the note of a jackknife result, its blocks in `what` (scale of them per sample). */
static void jk_text(const jk_result *r, long scale, const char *what, char *err, size_t n1, char *note, size_t n2)
{
  if (isnan(r->err)) {
    snprintf(err, n1, "%s", "");
    snprintf(note, n2, "no error bar: too few samples for 2 blocks");
    return;
  }
  snprintf(err, n1, " +- %.2g", r->err);
  snprintf(note, n2, "jackknife over %ld blocks of %ld %s%s", r->groups, r->len * scale, what,
           r->plateau ? "" : "; error bar a lower bound: no blocking plateau, run longer");
}

static double rel_fluct(const rl_moments *m, const void *ctx)
{
  (void)ctx;
  return m[0].n > 0 && m[0].mean != 0.0 ? sqrt(m[0].m2 / (double)m[0].n) / fabs(m[0].mean) : NAN;
}

static double rel_fluct_ratio(const rl_moments *m, const void *ctx)
{
  return rel_fluct(m, ctx) / rel_fluct(m + 1, ctx);
}

typedef struct {
  int nve, n, dof;
  double kB, T;
} cv_ctx;

/* C_V per molecule in k_B: from (K, U per molecule) moments */
static double heat_capacity(const rl_moments *m, const void *ctx)
{
  const cv_ctx *c = ctx;
  double cv;
  if (m[0].n < 2) return NAN;
  const double varK = m[0].m2 / (double)m[0].n, varU = m[1].m2 / (double)m[1].n * (double)c->n * (double)c->n;
  const int st = c->nve ? rl_heat_capacity_nve(m[0].mean, varK, c->dof, c->kB, &cv)
                        : rl_heat_capacity_isokinetic(varU, c->T, c->dof, c->kB, &cv);
  return st ? NAN : cv / (c->n * c->kB);
}

typedef struct {
  const rl_deck *d;
  double V, T;
} eps_ctx;

/* The dielectric constant from the moments of M's three components: <dM^2> = sum of their variances */
static double dielectric(const rl_moments *m, const void *ctx)
{
  const eps_ctx *c = ctx;
  double eps, dM2 = 0.0;
  for (int k = 0; k < 3; k++) dM2 += m[k].n > 0 ? m[k].m2 / (double)m[k].n : NAN;
  return rl_dielectric_constant(dM2, c->V, c->T, rl_deck_boundary_eps(c->d), c->d->units, c->d->ff.coulomb_constant, &eps)
             ? NAN : eps;
}

/* ---- the equilibrated part */

typedef struct {
  long i0, j0;     /* first step record and first sample averaged */
  double dt_rec;   /* time between step records                    */
} window;

static long step_of(const analysis *a, double t) { return llround(t / a->d->timestep); }

/* The first sample at a mark with at least i0 step records before it (samples if none). */
static long sample_start(const analysis *a, long i0)
{
  for (int k = 0; k < a->nmarks; k++)
    if (a->mark_c[k] >= i0) return k * a->mark_every;
  return a->samples;
}

/* Where the averages start (output.discard: auto, or a number of steps), and the lines that say so. */
static window equilibrate(const analysis *a, FILE *f)
{
  const rl_deck *d = a->d;
  const char *tu = units_of(d->units).time;
  window w = {0, 0, a->nstep > 1 ? (a->t_last - a->t_first) / (double)(a->nstep - 1) : d->timestep};
  if (a->nstep == 0) {
    fprintf(f, "averages_from = n/a (no step with energies)\n");
    return w;
  }
  const long per = lround(w.dt_rec / d->timestep); /* steps per record */
  if (d->discard < 0) {
    long len = 1;
    double g = NAN, neff = NAN;
    int limit = 0;
    if (rl_trace_equilibration(a->v[V_U], EQUIL_POINTS, 0.5, &w.i0, &len, &g, &neff, &limit)) w.i0 = 0;
    if (isnan(neff))
      fprintf(f, "equilibration = auto (output.discard): too few steps to detect, nothing discarded\n");
    else
      fprintf(f, "equilibration = auto (output.discard): the start in the first half of the run that maximises the "
                 "number of uncorrelated samples of U_per_molecule (Chodera, J. Chem. Theory Comput. 12, 1799 "
                 "(2016)), searched over its means of %ld steps: statistical inefficiency %.3g means, %.4g "
                 "uncorrelated means from there\n", len * per, g, neff);
    if (limit)
      fprintf(f, "equilibration_warning = the start found is at the end of the search (the first half of the run): the relaxation may "
                 "last longer; run longer (run.steps, run.equilibrate) or set output.discard\n");
    else if (neff < 10.0) /* every window drifts or the run is a few correlation times long */
      fprintf(f, "equilibration_warning = only %.3g uncorrelated samples of U_per_molecule: the run is too short for "
                 "its correlation time, or relaxing throughout; the averages and error bars are unreliable: run "
                 "longer\n", neff);
  } else {
    /* the first record at or after step `discard`, counted from the run's step 0 */
    const double x = ceil((((double)d->discard - 0.5) * d->timestep - a->t_first) / w.dt_rec);
    w.i0 = d->discard == 0 || x <= 0.0 ? 0 : x >= (double)a->nstep ? a->nstep : (long)x;
    w.i0 = rl_trace_align(a->v[V_U], w.i0);
    fprintf(f, "equilibration = output.discard = %ld steps\n", d->discard);
  }
  w.j0 = sample_start(a, w.i0);
  const long first = step_of(a, a->t_first);
  if (w.i0 >= a->nstep) {
    fprintf(f, "averages_from = n/a: the discarded steps cover the whole run (steps %ld to %ld); nothing is averaged\n",
            first, step_of(a, a->t_last));
    return w;
  }
  const double t0 = a->t_first + (double)w.i0 * w.dt_rec;
  fprintf(f, "averages_from = step %ld (t = %.6g %s): %ld steps discarded; %ld of %ld steps with energies and %ld of "
             "%ld sampled configurations averaged, in every result below, PREFIX.rdf.csv and PREFIX.tcf.csv\n",
          step_of(a, t0), t0, tu, step_of(a, t0) - first, a->nstep - w.i0, a->nstep, a->samples - w.j0, a->samples);
  return w;
}

/* The dielectric constant (from <dM^2> at volume V, temperature T) with its jackknife error over
 * blocks of the samples and, when the run is too short for it, a note.  V is the box's, or under
 * a barostat the mean volume of the step records from i0 (the volume line's).  M relaxes on the
 * collective dipole time, tens of ps for water, so a short run gives a value that can be far off
 * (the default TIP4P job, 10 ps) and must not stand as a bare number. */
static void dielectric_lines(FILE *f, const analysis *a, long i0, long j0, double T, const char *Tname,
                             double dt_sample)
{
  const rl_deck *d = a->d;
  const int real = d->units == RL_UNITS_REAL;
  const eps_ctx c = {d, a->baro ? rl_trace_moments(a->b[B_V], i0).mean : a->box[0] * a->box[1] * a->box[2], T};
  double dM2 = 0.0, eps;
  for (int k = 0; k < 3; k++) {
    const rl_moments m = rl_trace_moments(a->M[k], j0);
    dM2 += m.m2 / (double)m.n;
  }
  if (rl_dielectric_constant(dM2, c.V, T, rl_deck_boundary_eps(d), d->units, d->ff.coulomb_constant, &eps)) {
    fprintf(f, "dielectric_constant = n/a (%s)\n", rl_last_error());
    return;
  }
  jk_result r;
  jackknife((rl_trace *const *)a->M, 3, j0, dielectric, &c, &r);
  const long n = rl_trace_moments(a->M2, j0).n;
  char es[32], note[200];
  jk_text(&r, 1, "samples", es, sizeof es, note, sizeof note);
  /* the boundary the formula takes: the reaction field's eps_rf, or the Ewald sum's eps' (Neumann's
   * formula is the same with eps' for eps_rf) */
  char bnd[96];
  if (d->coulomb == RL_DECK_COULOMB_RF) snprintf(bnd, sizeof bnd, "reaction-field boundary eps_rf = %g", d->ff.eps_rf);
  else if (isinf(d->ewald.eps_surface)) snprintf(bnd, sizeof bnd, "Ewald sum in tin-foil (conducting) surroundings");
  else snprintf(bnd, sizeof bnd, "Ewald sum in surroundings eps' = %g", d->ewald.eps_surface);
  char vol[80] = "";
  if (a->baro) snprintf(vol, sizeof vol, ", at the mean volume %.8g %s", c.V, real ? "nm^3" : "sigma^3");
  fprintf(f, "dielectric_constant = %.4g%s (dipole fluctuations, %s, T = %g%s %s%s; %s)\n", eps, es, bnd, T,
          real ? " K" : "", Tname, vol, note);
  /* what the estimate needs: a plateau of the blocking of |M|^2 (more samples than a few
   * correlation times of M) and an error of at most 10 % of eps - 1, the part the fluctuation
   * measures */
  rl_block_result b;
  const int blocked = n >= 4 && !rl_trace_block_average(a->M2, j0, &b);
  const double rel = r.err / fabs(eps - 1.0), span = n * dt_sample;
  const char *tu = units_of(d->units).time;
  if (!blocked || isnan(r.err))
    fprintf(f, "dielectric_note = unreliable: %ld samples are too few for an error bar; run longer\n", n);
  else if (!b.converged)
    fprintf(f, "dielectric_note = unreliable: the run is shorter than the estimate needs: blocking <M^2> over its %ld "
               "samples (%.3g %s) found no plateau, so M has not decorrelated often enough and the error bar is a "
               "lower bound; run many times longer\n", n, span, tu);
  else if (!(rel <= 0.1))
    fprintf(f, "dielectric_note = unreliable: the run is shorter than the estimate needs: the error is %.0f %% of "
               "eps - 1; about %.2g %s of sampling (%.2g times this run's %.3g %s) would bring it to 10 %%\n",
            100.0 * rel, span * (rel / 0.1) * (rel / 0.1), tu, (rel / 0.1) * (rel / 0.1), span, tu);
  if (a->point_dipoles && d->ff.dipole_method == RL_DIPOLE_RF && d->coulomb == RL_DECK_COULOMB_RF) /* Ewald: no RF */
    fprintf(f, "dielectric_heating_note = the point dipoles interact by the dipolar reaction field (interactions.dipole "
               "= rf), whose energy jumps at the cutoff: it heats an NVE run, and a thermostat holds the temperature "
               "only by taking that heat out, so the run does not sample the canonical distribution the fluctuation "
               "formula assumes; read the dielectric constant as approximate (interactions.dipole = sf conserves "
               "energy but has no reaction-field boundary for the formula)\n");
}

/* The correlation functions of one run, as PREFIX.tcf.csv holds them (a NULL column is n/a). */
typedef struct {
  const analysis *a;
  long lag;
  double dt, *c[5];
  double *msd[RL_DECK_MAX_SPECIES]; /* a mixture: each species' MSD (NULL: n/a) */
} tcf_table;

static void write_tcf(FILE *fp, const void *ctx)
{
  const tcf_table *t = ctx;
  const units_text u = units_of(t->a->d->units);
  const char *vec = t->a->orient == ORIENT_AXIS ? "axis" : "dipole";
  fprintf(fp, "%s,%s_P1,%s_P2,%s,%s,%s", u.t_col, vec, vec, u.vacf_col, u.wacf_col, u.msd_col);
  for (int q = 0; q < t->a->nsp; q++) fprintf(fp, ",%s_%s", u.msd_col, t->a->sp_name[q]);
  fputc('\n', fp);
  for (long k = 0; k <= t->lag; k++) {
    fprintf(fp, "%.6g", k * t->dt);
    for (int q = 0; q < 5 + t->a->nsp; q++) {
      const double *c = q < 5 ? t->c[q] : t->msd[q - 5];
      if (c) fprintf(fp, ",%.6g", c[k]);
      else fputs(",n/a", fp);
    }
    fputc('\n', fp);
  }
}

/* The RDFs: r, then one g column per pair (r[nb], g[nrdf][nb]). */
typedef struct {
  const analysis *a;
  int nb;
  const double *r, *g;
} rdf_table;

static void write_rdf(FILE *fp, const void *ctx)
{
  const rdf_table *t = ctx;
  fprintf(fp, "%s", units_of(t->a->d->units).r_col);
  for (int q = 0; q < t->a->nrdf; q++) fprintf(fp, ",g_%s", t->a->rdf_name[q]);
  fprintf(fp, "\n");
  for (int b = 0; b < t->nb; b++) {
    fprintf(fp, "%.6g", t->r[b]);
    for (int q = 0; q < t->a->nrdf; q++) fprintf(fp, ",%.6g", t->g[(size_t)q * (size_t)t->nb + (size_t)b]);
    fprintf(fp, "\n");
  }
}
static void write_text(FILE *fp, const void *ctx) { fputs(ctx, fp); }

/* Append one failure to the "; "-separated list errs[n]. */
static void add_failure(char *errs, size_t n, const char *fmt, ...)
{
  const size_t used = strlen(errs);
  if (used + 2 >= n) return;
  if (used) strcat(errs, "; ");
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(errs + strlen(errs), n - strlen(errs), fmt, ap);
  va_end(ap);
}

/* Write `path` atomically (NAME.tmp.XXXXXX, renamed over NAME: on failure the earlier NAME is
 * left as it was).  On failure 1, with rl_atomic's message ("NAME: reason", naming the errno
 * reason) appended to errs[n]. */
static int write_file(const char *path, void (*fill)(FILE *, const void *), const void *ctx, char *errs, size_t n)
{
  rl_atomic_file af;
  if (!rl_atomic_open(&af, path)) {
    fill(af.fp, ctx);
    if (!rl_atomic_commit(&af)) return 0;
  }
  add_failure(errs, n, "%s", rl_last_error());
  return 1;
}


/* PREFIX EXT SUFFIX, allocated (NULL: out of memory). */
static char *file_name(const char *prefix, const char *ext, const char *suffix)
{
  const size_t n = strlen(prefix) + strlen(ext) + strlen(suffix) + 1;
  char *p = malloc(n);
  if (p) snprintf(p, n, "%s%s%s", prefix, ext, suffix);
  return p;
}

/* Self-diffusion from the MSD c[lag + 1] of the nf frames from j0, with a block error: the
 * standard error of D over D_BLOCKS consecutive parts of those frames, each fitted alike.  Of the
 * bodies b0 .. b0 + nb - 1 (all of them, or a species: then the line is self_diffusion_NAME). */
static void diffusion_line(FILE *f, const analysis *a, const double *msd, long j0, long nf, long lag, double dt,
                           const char *name, int b0, int nb)
{
  const units_text u = units_of(a->d->units);
  double D, Dfit;
  if (rl_diffusion_einstein(msd, lag + 1, dt, lag / 5, lag, &D, &Dfit)) return;
  const long part = nf / D_BLOCKS, plag = part / 2 < RL_TCF_MAX_LAG ? part / 2 : RL_TCF_MAX_LAG;
  double Db[D_BLOCKS], *c = plag >= 5 ? malloc(sizeof(double) * (size_t)(plag + 1)) : NULL;
  int ok = c != NULL;
  for (int b = 0; b < D_BLOCKS && ok; b++)
    ok = !rl_tcf_compute_bodies(a->pos, j0 + b * part, part, b0, nb, RL_TCF_MSD, plag, 1, c) &&
         !rl_diffusion_einstein(c, plag + 1, dt, plag / 5, plag, &Db[b], NULL);
  free(c);
  if (ok) {
    double mean = 0.0, s = 0.0;
    for (int b = 0; b < D_BLOCKS; b++) mean += Db[b] / D_BLOCKS;
    for (int b = 0; b < D_BLOCKS; b++) s += (Db[b] - mean) * (Db[b] - mean);
    fprintf(f, "self_diffusion%s%s = %.4g +- %.2g %s (Einstein, MSD lags %ld-%ld samples; error: standard error of D over "
               "%d consecutive parts of the samples, each fitted alike (lags %ld-%ld); the fit's own error, %.2g, is a "
               "lower bound: it ignores the correlation between lags)\n", name ? "_" : "", name ? name : "", D,
            sqrt(s / (D_BLOCKS * (D_BLOCKS - 1.0))), u.D, lag / 5, lag, D_BLOCKS, plag / 5, plag, Dfit);
  } else
    fprintf(f, "self_diffusion%s%s = %.4g +- %.2g %s (Einstein, MSD lags %ld-%ld samples; error: the fit's error of the "
               "slope, a lower bound: it ignores the correlation between lags; too few samples for a block error)\n",
            name ? "_" : "", name ? name : "", D, Dfit, u.D, lag / 5, lag);
}

/* A correlation function of the nf frames from j0 (rl_tcf_compute_range's arguments): over every
 * body, or in a mixture over the bodies of the species with mask[k] set (mask NULL: all of
 * them), the mean of the species' functions weighted by their counts. */
static int tcf_of(const analysis *a, const rl_vec_series *src, long j0, long nf, rl_tcf_kind kind, long lag,
                  const int *mask, double *c)
{
  if (!a->nsp || !mask) return rl_tcf_compute_range(src, j0, nf, kind, lag, 1, c);
  double *part = malloc(sizeof(double) * (size_t)(lag + 1));
  if (!part) return rl_error(RL_ENOMEM, "out of memory");
  long bodies = 0;
  int st = RL_OK;
  for (long k = 0; k <= lag; k++) c[k] = 0.0;
  for (int q = 0; q < a->nsp && !st; q++) {
    if (!mask[q]) continue;
    st = rl_tcf_compute_bodies(src, j0, nf, a->sp_first[q], a->sp_count[q], kind, lag, 1, part);
    for (long k = 0; k <= lag && !st; k++) c[k] += a->sp_count[q] * part[k];
    bodies += a->sp_count[q];
  }
  free(part);
  if (!st && !bodies) st = rl_error(RL_EINVAL, "no species of the mixture has it");
  for (long k = 0; k <= lag && !st; k++) c[k] /= (double)bodies;
  return st;
}

/* The correlation functions of the nf stored frames from j0, their file and the diffusion. */
static void correlation_lines(FILE *f, const analysis *a, long j0, const char *path, double dt_sample, char *errs,
                              size_t nerrs)
{
  const long stored = rl_vec_series_frames(a->pos), nf = stored - j0;
  if (a->samples - j0 >= 4 && nf < 4)
    fprintf(f, "correlation_functions = n/a (the %ld samples kept for them, memory bound %.0f MB: analysis.c, lie in the "
               "discarded part)\n", stored, RL_TCF_MEMORY / (1024.0 * 1024.0));
  if (nf < 4) return;
  const long lag = nf / 2 < RL_TCF_MAX_LAG ? nf / 2 : RL_TCF_MAX_LAG;
  if (a->samples > stored || nf / 2 > lag)
    fprintf(f, "correlation_functions = from the first %ld of %ld samples, lags up to %ld samples (memory bound %.0f MB, "
               "lag bound %d: app/analysis_internal.h)%s\n", stored, a->samples, lag, RL_TCF_MEMORY / (1024.0 * 1024.0),
            RL_TCF_MAX_LAG, j0 ? ", averaged over those after the discarded part" : "");
  fprintf(f, "orientation_vector = %s\n", a->orient_text);
  /* a column that cannot be computed is n/a in the file, with the reason here; never zeros */
  static const char *col[5] = {"P1", "P2", "vacf", "omega_acf", "msd"};
  double *c[5] = {NULL, NULL, NULL, NULL, NULL};
  rl_tcf_kind kinds[5] = {RL_TCF_P1, RL_TCF_P2, RL_TCF_DOT, RL_TCF_DOT, RL_TCF_MSD};
  rl_vec_series *src[5] = {a->axis, a->axis, a->vel, a->omega, a->pos};
  const int *mask[5] = {a->sp_orient, a->sp_orient, NULL, a->sp_rot, NULL}; /* a mixture: the bodies that have it */
  for (int k = a->orient == ORIENT_NONE ? 2 : 0; k < 5; k++) {
    if (!(c[k] = calloc((size_t)lag + 1, sizeof(double))))
      fprintf(f, "correlation_error = %s: out of memory\n", col[k]);
    else if (tcf_of(a, src[k], j0, nf, kinds[k], lag, mask[k], c[k])) {
      fprintf(f, "correlation_error = %s: %s\n", col[k], rl_last_error());
      free(c[k]);
      c[k] = NULL;
    }
  }
  if (c[4]) diffusion_line(f, a, c[4], j0, nf, lag, dt_sample, NULL, 0, a->n);
  tcf_table t = {a, lag, dt_sample, {c[0], c[1], c[2], c[3], c[4]}, {NULL}};
  for (int q = 0; q < a->nsp; q++) { /* a mixture: each species' MSD and self-diffusion */
    if (!(t.msd[q] = calloc((size_t)lag + 1, sizeof(double))))
      fprintf(f, "correlation_error = msd_%s: out of memory\n", a->sp_name[q]);
    else if (rl_tcf_compute_bodies(a->pos, j0, nf, a->sp_first[q], a->sp_count[q], RL_TCF_MSD, lag, 1, t.msd[q])) {
      fprintf(f, "correlation_error = msd_%s: %s\n", a->sp_name[q], rl_last_error());
      free(t.msd[q]);
      t.msd[q] = NULL;
    } else
      diffusion_line(f, a, t.msd[q], j0, nf, lag, dt_sample, a->sp_name[q], a->sp_first[q], a->sp_count[q]);
  }
  if (!path) add_failure(errs, nerrs, "tcf.csv: out of memory for its name");
  else if (write_file(path, write_tcf, &t, errs, nerrs)) fprintf(f, "# could not write %s\n", rl_last_error());
  for (int k = 0; k < 5; k++) free(c[k]);
  for (int q = 0; q < a->nsp; q++) free(t.msd[q]);
}

/* The RDFs of the samples from j0 and their file. */
static void rdf_lines(FILE *f, const analysis *a, long j0, const char *path, char *errs, size_t nerrs)
{
  if (a->nrdf == 0) return;
  if (rl_rdf_frames(a->rdf[0]) == 0) { /* nothing to normalise: no file, not garbage */
    fprintf(f, "rdf = n/a (no configuration was sampled: output.sample_every)\n");
    return;
  }
  if (j0 >= rl_rdf_frames(a->rdf[0])) {
    fprintf(f, "rdf = n/a (no sampled configuration after the discarded steps)\n");
    return;
  }
  const int nb = rl_rdf_nbins(a->rdf[0]);
  double *r = malloc(sizeof(double) * (size_t)nb), *g = malloc(sizeof(double) * (size_t)nb * (size_t)a->nrdf);
  int bad = !r || !g || !path;
  for (int q = 0; q < a->nrdf && !bad; q++)
    bad = rl_rdf_get_from(a->rdf[q], j0, r, g + (size_t)q * (size_t)nb, NULL) != RL_OK;
  rdf_table t = {a, nb, r, g};
  if (bad) {
    const char *why = !r || !g || !path ? "out of memory" : rl_last_error();
    add_failure(errs, nerrs, "%s: %s", path ? path : "rdf.csv", why);
    fprintf(f, "# could not write %s: %s\n", path ? path : "rdf.csv", why);
  } else if (write_file(path, write_rdf, &t, errs, nerrs))
    fprintf(f, "# could not write %s\n", rl_last_error());
  free(r);
  free(g);
}

/* k_B T_conf / k_B from the moments of (numerator, denominator) sums: a ratio of means */
static double tconf_ratio(const rl_moments *m, const void *ctx)
{
  const double kB = *(const double *)ctx;
  return m[0].n > 0 && m[1].mean > 0.0 ? m[0].mean / m[1].mean / kB : NAN;
}

/* The configurational temperatures of the samples from j0 (output.tconf). */
static void tconf_lines(FILE *f, const analysis *a, long j0)
{
  if (!a->tconf) return;
  const units_text u = units_of(a->d->units);
  static const char *name[3] = {"tconf_translational", "tconf_rotational", "tconf"};
  if (a->tconf_na[0]) {
    for (int k = 0; k < 3; k++) fprintf(f, "%s = n/a (%s)\n", name[k], a->tconf_na);
    return;
  }
  const long n = rl_trace_moments(a->tc[0], j0).n;
  if (n == 0) {
    for (int k = 0; k < 3; k++) fprintf(f, "%s = n/a (no sampled configuration averaged)\n", name[k]);
    return;
  }
  double kB = rl_units_kB(a->d->units);
  rl_trace *pairs[3][2] = {{a->tc[0], a->tc[1]}, {a->tc[2], a->tc[3]}, {a->tc[4], a->tc[5]}};
  for (int k = 0; k < 3; k++) {
    if (k == 1 && !(rl_trace_moments(a->tc[3], j0).mean > 0.0)) {
      fprintf(f, "%s = n/a (no rotating molecule, or no torque)\n", name[k]);
      continue;
    }
    jk_result r;
    char es[32], note[200];
    jackknife(pairs[k], 2, j0, tconf_ratio, &kB, &r);
    jk_text(&r, 1, "samples", es, sizeof es, note, sizeof note);
    fprintf(f, "%s = %.6g%s %s (<sum |%s|^2> / <sum %s>, %ld samples; %s)\n", name[k], r.value, es, u.T,
            k == 0 ? "F" : k == 1 ? "tau" : "F|^2 + |tau", k == 0 ? "lap_R U" : k == 1 ? "lap_phi U" : "lap_R U + lap_phi U",
            n, note);
  }
  if (a->tconf_note[0])
    fprintf(f, "tconf_note = biased: the forces jump at the cutoff (%s), which puts delta functions into the "
               "Laplacian that the configuration's sums leave out; use interactions.lj = shifted-force or switched, "
               "eps_rf = inf, dipole = sf for an exact estimate (docs/observables.md)\n", a->tconf_note);
}

/* calE, calU, their ratio and the heat capacity of the step records from i0. */
static void fluctuation_lines(FILE *f, const analysis *a, long i0, long per)
{
  const rl_deck *d = a->d;
  const int nve = d->thermostat == RL_THERMO_NONE, real = d->units == RL_UNITS_REAL;
  jk_result r;
  char v[64], es[32], note[200];
  rl_trace *eu[2] = {a->v[V_EC], a->v[V_U]};
  static const char *what[3] = {"calE", "calU", "calE_over_calU"};
  const char *of[3] = {nve ? "relative rms fluctuation of the total energy, the conserved quantity of NVE"
                           : "relative rms fluctuation of the conserved quantity: the total energy plus the energy the "
                             "thermostat took out (not of the total energy, which a thermostat does not conserve)",
                       "relative rms fluctuation of the potential energy", "the paper's accuracy ratio"};
  const long n = rl_trace_moments(a->v[V_U], i0).n;
  for (int k = 0; k < 3; k++) {
    if (n == 0) {
      fprintf(f, "%s = n/a (no step averaged)\n", what[k]);
      continue;
    }
    jackknife(eu + (k == 1), k == 2 ? 2 : 1, i0, k == 2 ? rel_fluct_ratio : rel_fluct, NULL, &r);
    jk_text(&r, per, "steps", es, sizeof es, note, sizeof note);
    if (isfinite(r.value)) fprintf(f, "%s = %s%s (%s; %s)\n", what[k], rel_fluct_text(v, sizeof v, r.value), es, of[k], note);
    else fprintf(f, "%s = %s [%s]\n", what[k], rel_fluct_text(v, sizeof v, r.value), of[k]);
  }
  /* The temperature of the fluctuation formulas: under a thermostat its target T0, the T of the
   * canonical (and isokinetic) distribution; the on-step T reads low at large steps (12 K for
   * water at 5 fs), which would bias C_V ~ 1/T^2 and y ~ 1/T.  In NVE the mean on-step T.
   * NVE: Lebowitz-Percus-Verlet from <dK^2>.  Any NVT: K and U are independent in the canonical
   * ensemble (and K is fixed in the isokinetic one), so the kinetic part is exactly f kB/2 and only
   * the configurational <dU^2>/(kB T0^2) is sampled: <dE^2>/(kB T^2) would add the noise of <dK^2>
   * and of cov(K, U), which converges slowly under Bussi, and the on-step K's step-size bias */
  const rl_moments mK = rl_trace_moments(a->v[V_K], i0), mU = rl_trace_moments(a->v[V_U], i0);
  if (mK.n == 0) {
    fprintf(f, "heat_capacity_per_molecule = n/a (no step averaged)\n");
    return;
  }
  const double kB = rl_units_kB(d->units), Tm = rl_trace_moments(a->v[V_T], i0).mean;
  const cv_ctx c = {nve, a->n, (int)llround(2.0 * mK.mean / (kB * Tm)), kB, nve ? Tm : d->thermostat_temperature};
  double cv;
  const double sdU = sqrt(mU.m2 / (double)mU.n) * a->n;
  const int st = nve ? rl_heat_capacity_nve(mK.mean, mK.m2 / (double)mK.n, c.dof, kB, &cv)
                     : rl_heat_capacity_isokinetic(sdU * sdU, c.T, c.dof, kB, &cv);
  if (st) {
    fprintf(f, "heat_capacity_per_molecule = n/a (%s)\n", rl_last_error());
    return;
  }
  rl_trace *ku[2] = {a->v[V_K], a->v[V_U]};
  jackknife(ku, 2, i0, heat_capacity, &c, &r);
  jk_text(&r, per, "steps", es, sizeof es, note, sizeof note);
  if (nve)
    fprintf(f, "heat_capacity_per_molecule = %.6g%s k_B (NVE, Lebowitz-Percus-Verlet formula; %s)\n", cv / (a->n * kB),
            es, note);
  else
    fprintf(f, "heat_capacity_per_molecule = %.6g%s k_B (%s formula) [f k_B/2 + <dU^2>/(k_B T0^2), f = %d, T0 = %g%s "
               "the thermostat's target; %s]\n", cv / (a->n * kB), es,
            d->thermostat == RL_THERMO_ISOKINETIC ? "isokinetic" : "canonical", c.dof, c.T, real ? " K" : "", note);
}

/* ---- under a barostat */

void analysis_set_barostat_stats(analysis *a, const rl_barostat_stats *s)
{
  if (!a || !s) return;
  a->stats = *s;
  a->have_stats = 1;
}

typedef struct {
  double kT, factor; /* k_B T0; kappa in the output's units per kappa in the system's */
} kappa_ctx;

/* kappa_T = <dV^2> / (k_B T0 <V>) from the moments of V */
static double kappa_t(const rl_moments *m, const void *ctx)
{
  const kappa_ctx *c = ctx;
  return m[0].n > 1 && m[0].mean > 0.0 ? c->factor * m[0].m2 / (double)m[0].n / (c->kT * m[0].mean) : NAN;
}

/* The least-squares slope of a trace's group means against their index from i0, with its
 * standard error from the scatter about the line (NaN with fewer than 3 groups); the groups are
 * about a twentieth of the samples (at least one stored block), long enough to be nearly
 * independent in a run many correlation times long.  *len: the group's samples. */
static double trace_slope(const rl_trace *t, long i0, double *err, long *len)
{
  const long n = rl_trace_count(t) - rl_trace_align(t, i0);
  *len = n / 20 > 1 ? n / 20 : 1;
  if (*len < rl_trace_block(t)) *len = rl_trace_block(t);
  *len = (*len + rl_trace_block(t) - 1) / rl_trace_block(t) * rl_trace_block(t);
  const long m = rl_trace_groups(t, i0, *len, NULL, 0);
  *err = NAN;
  if (m < 3) return NAN;
  rl_moments *g = malloc(sizeof *g * (size_t)m);
  if (!g) return NAN;
  rl_trace_groups(t, i0, *len, g, m);
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  for (long i = 0; i < m; i++) {
    sx += (double)i;
    sy += g[i].mean;
  }
  const double mx = sx / (double)m, my = sy / (double)m;
  for (long i = 0; i < m; i++) {
    sxx += ((double)i - mx) * ((double)i - mx);
    sxy += ((double)i - mx) * (g[i].mean - my);
  }
  const double b = sxy / sxx;
  double rss = 0.0;
  for (long i = 0; i < m; i++) {
    const double r = g[i].mean - my - b * ((double)i - mx);
    rss += r * r;
  }
  free(g);
  *err = sqrt(rss / (double)(m - 2) / sxx);
  return b;
}

/* Volume, density, box edges, enthalpy, kappa_T, the Monte Carlo acceptance and trial size or
 * the C-rescale effective energy's drift, over the step records from i0. */
static void barostat_lines(FILE *f, const analysis *a, long i0, long per, double dt_rec)
{
  const rl_deck *d = a->d;
  const int real = d->units == RL_UNITS_REAL;
  const units_text u = units_of(d->units);
  const char *vol = real ? "nm^3" : "sigma^3", *len = real ? "nm" : "sigma", *rho = real ? "g/cm^3" : "m/sigma^3";
  line_mean(f, "volume", a->b[B_V], i0, vol);
  line_mean(f, "density", a->b[B_RHO], i0, rho);
  line_mean(f, "box_Lx", a->b[B_LX], i0, len);
  line_mean(f, "box_Ly", a->b[B_LY], i0, len);
  line_mean(f, "box_Lz", a->b[B_LZ], i0, len);
  char hu[64];
  snprintf(hu, sizeof hu, "%s [H = U + K + P0 V per molecule, P0 = run.pressure]", u.E);
  line_mean(f, "enthalpy_per_molecule", a->b[B_H], i0, hu);
  const double kB = rl_units_kB(d->units);
  /* kappa: volume/energy in the system's units; 1/bar: times the bar in kJ/mol/nm^3 (1e5 N_A 1e-27 / 1e3) */
  const kappa_ctx kc = {kB * d->thermostat_temperature, real ? 0.0602214076 : 1.0};
  jk_result r;
  char es[32], note[200];
  if (rl_trace_moments(a->b[B_V], i0).n < 2) fprintf(f, "isothermal_compressibility = n/a (fewer than two steps averaged)\n");
  else {
    rl_trace *tv = a->b[B_V];
    jackknife(&tv, 1, i0, kappa_t, &kc, &r);
    jk_text(&r, per, "steps", es, sizeof es, note, sizeof note);
    fprintf(f, "isothermal_compressibility = %.6g%s %s [<dV^2>/(k_B T0 <V>), T0 = %g%s the thermostat's target; %s]\n",
            r.value, es, real ? "1/bar" : "sigma^3/epsilon", d->thermostat_temperature, real ? " K" : "", note);
  }
  if (d->barostat == 1 && a->have_stats) {
    const int aniso = d->baro_aniso == 1;
    for (int k = 0; k < (aniso ? 3 : 1); k++) {
      const long at = a->stats.attempted[k], ac = a->stats.accepted[k];
      char name[48];
      snprintf(name, sizeof name, aniso ? "mc_acceptance_L%c" : "mc_acceptance", "xyz"[k]);
      if (at > 0) fprintf(f, "%s = %.4f (%ld of %ld trials accepted in the whole run)\n", name, (double)ac / (double)at, ac, at);
      else fprintf(f, "%s = n/a (no trial)\n", name);
      snprintf(name, sizeof name, aniso ? "mc_trial_step_L%c" : "mc_trial_step", "xyz"[k]);
      fprintf(f, "%s = %.6g %s (the largest |dV| of a trial at the end, adapted to 25-75 %% acceptance)\n", name,
              a->stats.trial[k], vol);
    }
  }
  if (d->barostat == 2) {
    long glen;
    double err;
    const double b = trace_slope(a->v[V_EC], i0, &err, &glen); /* per group of glen records */
    const double scale = 1.0 / (a->n * kB * d->thermostat_temperature * (double)glen * dt_rec);
    const char *tunit = real ? u.time : "tau";
    if (isnan(b)) fprintf(f, "crescale_effective_energy_drift = n/a (too few steps averaged)\n");
    else
      fprintf(f, "crescale_effective_energy_drift = %.3g +- %.2g kT per molecule per %s [slope of the conserved column "
                 "(the effective energy: total + the thermostat's and barostat's work) over means of %ld steps]\n",
              b * scale, err * scale, tunit, glen * per);
  }
}

int analysis_write(analysis *a, const char *prefix, const char *suffix, double dt_sample)
{
  const rl_deck *d = a->d;
  const units_text u = units_of(d->units);
  if (!suffix) suffix = "";
  /* results.txt is composed in memory and written last, so that it can report the other files;
   * every file is attempted whatever happened to the others, and any failure is the return */
  char errs[1024] = "", *text = NULL;
  size_t text_len = 0;
  FILE *f = open_memstream(&text, &text_len);
  if (!f) return rl_error(RL_ENOMEM, "%s.results.txt%s: cannot compose the results: %s", prefix, suffix, strerror(errno));
  const long per = a->nstep > 1 ? lround((a->t_last - a->t_first) / (double)(a->nstep - 1) / d->timestep) : 1;
  /* nothing here may tell a continuation from the uninterrupted run: the files are the same */
  fprintf(f, "# rotleap results of steps %ld to %ld (t = %.6g to %.6g %s): %ld steps with energies, one in %ld, and %ld "
             "sampled configurations\n", step_of(a, a->t_first), step_of(a, a->t_last), a->t_first, a->t_last, u.time,
          a->nstep, per, a->samples);
  fprintf(f, "# errors: +- one standard error; of a mean: blocked (Flyvbjerg-Petersen, at the Lee-Needs-Towler level); of "
             "a fluctuation quantity (calE, calU, calE_over_calU, heat capacity, dielectric constant): jackknife over "
             "blocks at least that long\n");
  const window w = equilibrate(a, f);
  line_mean(f, "U_per_molecule", a->v[V_U], w.i0, u.E);
  line_mean(f, "temperature", a->v[V_T], w.i0, u.T);
  line_mean(f, "temperature_translational", a->v[V_TT], w.i0, u.T);
  line_mean(f, "temperature_rotational", a->v[V_TR], w.i0, u.T);
  for (int k = 0; k < a->nsp; k++) { /* a mixture: each species' (rl_species_kinetic: the dof shared) */
    char name[96];
    snprintf(name, sizeof name, "temperature_translational_%s", a->sp_name[k]);
    line_mean(f, name, a->vs[k][0], w.i0, u.T);
    snprintf(name, sizeof name, "temperature_rotational_%s", a->sp_name[k]);
    if (a->sp_rot[k]) line_mean(f, name, a->vs[k][1], w.i0, u.T);
    else fprintf(f, "%s = n/a (%s: point particles, no rotational degrees of freedom)\n", name, a->sp_name[k]);
  }
  line_mean(f, "pressure", a->v[V_P], w.i0, u.P);
  if (a->baro) barostat_lines(f, a, w.i0, per, w.dt_rec);
  line_mean(f, "mean_square_force", a->v[V_F2], w.i0, u.F2);
  line_mean(f, "mean_square_torque", a->v[V_K2], w.i0, u.K2);
  fluctuation_lines(f, a, w.i0, per);
  tconf_lines(f, a, w.j0);
  char *tcf_path = file_name(prefix, ".tcf.csv", suffix), *rdf_path = file_name(prefix, ".rdf.csv", suffix);
  correlation_lines(f, a, w.j0, tcf_path, dt_sample, errs, sizeof errs);
  if (a->dipolar && rl_trace_moments(a->M2, w.j0).n >= 2) {
    if (a->point_dipoles && d->ff.dipole_method == RL_DIPOLE_SF)
      fprintf(f, "dielectric_constant = n/a (dipole = sf has no reaction-field boundary for the "
                 "fluctuation formula; dipole = rf with eps_rf gives one)\n");
    else {
      const int nve = d->thermostat == RL_THERMO_NONE;
      const double T = nve ? rl_trace_moments(a->v[V_T], w.i0).mean : d->thermostat_temperature;
      dielectric_lines(f, a, w.i0, w.j0, T, nve ? "the mean temperature" : "the thermostat's target", dt_sample);
    }
  }
  rdf_lines(f, a, w.j0, rdf_path, errs, sizeof errs);
  free(tcf_path);
  free(rdf_path);
  /* the results file itself */
  const int composed = fclose(f) == 0 && text;
  char *path = file_name(prefix, ".results.txt", suffix);
  if (!composed || !path) add_failure(errs, sizeof errs, "%s.results.txt%s: out of memory composing it", prefix, suffix);
  else write_file(path, write_text, text, errs, sizeof errs);
  free(path);
  free(text);
  return errs[0] ? rl_error(RL_EINVAL, "%s", errs) : RL_OK;
}
