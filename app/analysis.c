/* rotleap run's analysis: a thin layer over include/rotleap/observables.h. */
#include "analysis.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_RDF RL_DECK_MAX_RDF

struct analysis {
  const rl_deck *d;
  const rl_molecule *mol;
  int n;
  rl_series *U, *T, *Tt, *Tr, *P, *E, *K, *F2, *K2, *M2; /* M2: |M|^2 per sample */
  int nrdf;
  rl_rdf *rdf[MAX_RDF];
  int rdf_site[MAX_RDF][2];
  char rdf_name[MAX_RDF][24];
  rl_vec_series *axis, *vel, *omega, *pos;
  double (*unwrapped)[3], (*buf)[3], (*dip)[3]; /* unwrapped: the centres of the last sample */
  rl_dipole_acc *M;
  rl_species_ff sff;
  int dipolar;       /* the molecules have a net dipole: M, its fluctuation, the dielectric constant */
  int orient;        /* the vector of P1/P2: ORIENT_DIPOLE, ORIENT_AXIS or ORIENT_NONE              */
  char orient_text[240]; /* results.txt's orientation_vector: which vector, or n/a and why          */
  int point_dipoles; /* sites with a point dipole: their boundary is dipole_method's */
  long tcf_cap;      /* samples kept for the correlation functions and the MSD (memory bound) */
  long samples;      /* samples taken                                                        */
};

/* The correlation functions and the MSD keep whole configurations (four vectors per body and
 * sample), and are computed directly over every time origin: memory grows with the run and
 * time with samples x lags.  A long run (10^7 steps of 216 TIP4P sampled every 10 would need
 * 20 GB) keeps the first RL_TCF_MEMORY bytes' worth of samples, and the lags go to
 * RL_TCF_MAX_LAG samples at most; results.txt says so when that happens.  The RDFs, the
 * dipole fluctuation and the block averages use every sample. */
#define RL_TCF_MEMORY (256.0 * 1024 * 1024)
#define RL_TCF_MAX_LAG 1000

enum { ORIENT_DIPOLE, ORIENT_AXIS, ORIENT_NONE };

/* Whether the molecule has a net dipole: |sum_a q_a s_a + sum_a p_a Z| (body frame, about the
 * centre of mass) above round-off of the scale of its charges and dipoles.  CO2 and CH4 have
 * charges and none; every rl_system_dipoles vector of theirs is zero. */
static int net_dipole(const rl_molecule *m)
{
  double mu[3] = {0.0, 0.0, 0.0}, scale = 0.0;
  for (int s = 0; s < m->nsites; s++) {
    const double *x = m->sites[s];
    for (int k = 0; k < 3; k++) mu[k] += m->charge[s] * x[k];
    mu[2] += m->dipole[s];
    scale += fabs(m->charge[s]) * sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) + fabs(m->dipole[s]);
  }
  return sqrt(mu[0] * mu[0] + mu[1] * mu[1] + mu[2] * mu[2]) > 1e-9 * scale;
}

/* The vector whose reorientation P1/P2 follow: the molecular dipole where there is one (water's
 * lies along its C2 axis, not body Z); without one, the molecular axis where the molecule has a
 * unique one (rho of linear molecules and point dipoles, body Z of a symmetric top); else none. */
static void choose_orientation(analysis *a, const char *model)
{
  const rl_kind k = a->mol->natural_kind;
  if (a->dipolar) {
    a->orient = ORIENT_DIPOLE;
    snprintf(a->orient_text, sizeof a->orient_text, "molecular dipole mu_i (tcf.csv columns dipole_P1, dipole_P2)");
  } else if (k == RL_KIND_LINEAR || k == RL_KIND_DIPOLE || k == RL_KIND_SYMMETRIC) {
    a->orient = ORIENT_AXIS;
    snprintf(a->orient_text, sizeof a->orient_text, "%s (model %s has no net dipole; tcf.csv columns axis_P1, "
             "axis_P2)", k == RL_KIND_SYMMETRIC ? "symmetry axis, body Z" : "molecular axis rho", model);
  } else {
    a->orient = ORIENT_NONE;
    if (k == RL_KIND_POINT)
      snprintf(a->orient_text, sizeof a->orient_text, "n/a (model %s: point molecules have no orientation; "
               "tcf.csv columns dipole_P1, dipole_P2 are n/a)", model);
    else
      snprintf(a->orient_text, sizeof a->orient_text, "n/a (model %s has no net dipole and, as a %s top, no "
               "unique molecular axis; tcf.csv columns dipole_P1, dipole_P2 are n/a)", model, rl_kind_name(k));
  }
}

analysis *analysis_alloc(const rl_deck *d, const rl_molecule *mol, const rl_system *sys)
{
  analysis *a = calloc(1, sizeof *a);
  if (!a) { rl_error(RL_ENOMEM, "out of memory for the analysis"); return NULL; }
  a->d = d;
  a->mol = mol;
  a->n = rl_system_count(sys);
  rl_series **ser[] = {&a->U, &a->T, &a->Tt, &a->Tr, &a->P, &a->E, &a->K, &a->F2, &a->K2, &a->M2};
  for (size_t k = 0; k < sizeof ser / sizeof ser[0]; k++) *ser[k] = rl_series_alloc();
  /* output.rdf: "O-O, H-H" */
  double rmax = 0.5 * fmin(d->box[0], fmin(d->box[1], d->box[2]));
  const int nrdf = rl_deck_rdf_pairs(d->rdf, mol, a->rdf_site, a->rdf_name);
  if (nrdf < 0) { analysis_free(a); return NULL; }
  for (; a->nrdf < nrdf; a->nrdf++) a->rdf[a->nrdf] = rl_rdf_alloc(rmax, 200);
  a->tcf_cap = (long)(RL_TCF_MEMORY / (4.0 * sizeof(double[3]) * (a->n > 0 ? a->n : 1)));
  if (a->tcf_cap < 8) a->tcf_cap = 8;
  a->axis = rl_vec_series_alloc(a->n);
  a->vel = rl_vec_series_alloc(a->n);
  a->omega = rl_vec_series_alloc(a->n);
  a->pos = rl_vec_series_alloc(a->n);
  a->unwrapped = calloc((size_t)a->n, sizeof *a->unwrapped);
  a->buf = calloc((size_t)a->n, sizeof *a->buf);
  a->dip = calloc((size_t)a->n, sizeof *a->dip);
  a->M = rl_dipole_acc_alloc();
  int ok = a->axis && a->vel && a->omega && a->pos && a->unwrapped && a->buf && a->dip && a->M;
  for (size_t k = 0; k < sizeof ser / sizeof ser[0]; k++) ok = ok && *ser[k];
  for (int k = 0; k < a->nrdf; k++) ok = ok && a->rdf[k];
  if (!ok) { /* the samplers would dereference NULL */
    analysis_free(a);
    rl_error(RL_ENOMEM, "out of memory for the analysis of %d molecules", rl_system_count(sys));
    return NULL;
  }
  a->sff = rl_molecule_ff(mol);
  for (int s = 0; s < mol->nsites; s++) a->point_dipoles |= mol->dipole[s] != 0.0;
  a->dipolar = net_dipole(mol);
  choose_orientation(a, d->model ? d->model->name : mol->name);
  return a;
}

void analysis_free(analysis *a)
{
  if (!a) return;
  rl_series *ser[] = {a->U, a->T, a->Tt, a->Tr, a->P, a->E, a->K, a->F2, a->K2, a->M2};
  for (size_t k = 0; k < sizeof ser / sizeof ser[0]; k++) rl_series_free(ser[k]);
  for (int k = 0; k < a->nrdf; k++) rl_rdf_free(a->rdf[k]);
  rl_vec_series_free(a->axis);
  rl_vec_series_free(a->vel);
  rl_vec_series_free(a->omega);
  rl_vec_series_free(a->pos);
  free(a->unwrapped); free(a->buf); free(a->dip);
  rl_dipole_acc_free(a->M);
  free(a);
}

int analysis_step(analysis *a, const rl_step_info *info, double pressure, const rl_forces *F, const rl_system *sys)
{
  rl_series_add(a->U, info->potential / a->n);
  rl_series_add(a->T, info->temperature);
  rl_series_add(a->Tt, info->t_trans);
  rl_series_add(a->Tr, info->t_rot);
  rl_series_add(a->P, pressure);
  rl_series_add(a->E, info->total);
  rl_series_add(a->K, info->ke_trans + info->ke_rot);
  double f2 = 0.0, k2 = 0.0;
  for (int i = 0; i < a->n; i++) {
    f2 += F->f[i][0] * F->f[i][0] + F->f[i][1] * F->f[i][1] + F->f[i][2] * F->f[i][2];
    int r = rl_system_rot_index(sys, i);
    if (r >= 0) k2 += F->k[r][0] * F->k[r][0] + F->k[r][1] * F->k[r][1] + F->k[r][2] * F->k[r][2];
  }
  rl_series_add(a->F2, f2 / a->n);
  rl_series_add(a->K2, k2 / a->n);
  return RL_OK;
}

int analysis_sample(analysis *a, const rl_system *sys)
{
  for (int k = 0; k < a->nrdf; k++)
    if (rl_rdf_add_sites(a->rdf[k], sys, a->d->box, 0, a->rdf_site[k][0], 0, a->rdf_site[k][1])) return 1;
  if (a->dipolar) {
    double M[3];
    if (rl_system_dipoles(sys, &a->sff, 1, a->dip, M) || rl_dipole_acc_add(a->M, M) ||
        rl_series_add(a->M2, M[0] * M[0] + M[1] * M[1] + M[2] * M[2]))
      return 1;
  }
  if (a->samples++ >= a->tcf_cap) return 0; /* the correlation functions have their samples */
  if (a->orient == ORIENT_DIPOLE) { if (rl_vec_series_add(a->axis, (const double (*)[3])a->dip)) return 1; }
  else if (a->orient == ORIENT_AXIS) {
    rl_system_axes(sys, a->buf);
    if (rl_vec_series_add(a->axis, (const double (*)[3])a->buf)) return 1;
  }
  rl_system_velocities(sys, a->buf);
  if (rl_vec_series_add(a->vel, (const double (*)[3])a->buf)) return 1;
  rl_system_angular_velocities(sys, a->buf);
  if (rl_vec_series_add(a->omega, (const double (*)[3])a->buf)) return 1;
  rl_system_positions(sys, a->buf);
  /* each centre is the image nearest its previous *unwrapped* position (rl_unwrap's contract):
   * nearest the previous raw position, a body would lose its image one sample after crossing */
  if (rl_vec_series_frames(a->pos) == 0) memcpy(a->unwrapped, a->buf, sizeof *a->buf * (size_t)a->n);
  else rl_unwrap(a->d->box, (const double (*)[3])a->unwrapped, (const double (*)[3])a->buf, a->n, a->unwrapped);
  return rl_vec_series_add(a->pos, (const double (*)[3])a->unwrapped);
}

static void line_block(FILE *f, const char *name, rl_series *s, const char *unit)
{
  rl_block_result b;
  if (rl_series_count(s) < 2 || rl_series_block_average(s, &b)) {
    fprintf(f, "%s = %.8g %s\n", name, rl_series_mean(s), unit);
    return;
  }
  fprintf(f, "%s = %.8g +- %.2g %s%s\n", name, b.mean, b.sem, unit, b.converged ? "" : " (error bar a lower bound: run longer)");
}

const char *rel_fluct_text(char *buf, size_t n, double x)
{
  if (isfinite(x)) snprintf(buf, n, "%.6e", x);
  else snprintf(buf, n, "n/a (the mean is 0)");
  return buf;
}

/* The dielectric constant eps (from <dM^2> at volume V, temperature T) with its error and, when the
 * run is too short for it, a note.  The error is the blocked standard error of <M^2>
 * (Flyvbjerg-Petersen, as for U and P) carried through Neumann's formula; it leaves out the
 * error of |<M>|^2, which is smaller.  M relaxes on the collective dipole time, tens of ps for
 * water, so a short run gives a value that can be far off (the default TIP4P job, 10 ps: 9.5 +- 11
 * with no plateau) and must not stand as a bare number. */
static void dielectric_lines(FILE *f, const analysis *a, double dM2, double V, double T, double eps, const char *Tname,
                             double dt_sample)
{
  const rl_deck *d = a->d;
  const int real = d->units == RL_UNITS_REAL;
  const long n = rl_series_count(a->M2);
  rl_block_result b;
  const int blocked = n >= 4 && !rl_series_block_average(a->M2, &b);
  double err = NAN, e2;
  const double h = 1e-6 * dM2; /* d eps / d<dM^2> by a one-sided difference */
  if (blocked && h > 0.0)
    err = rl_dielectric_constant(dM2 + h, V, T, d->ff.eps_rf, d->units, d->ff.coulomb_constant, &e2)
              ? INFINITY : fabs(e2 - eps) / h * b.sem;
  char es[32] = "n/a";
  if (!isnan(err)) snprintf(es, sizeof es, "%.2g", err);
  fprintf(f, "dielectric_constant = %.4g +- %s (dipole fluctuations, reaction-field boundary eps_rf = %g, T = %g%s "
             "%s; error from the blocked <M^2>)\n", eps, es, d->ff.eps_rf, T, real ? " K" : "", Tname);
  /* what the estimate needs: a plateau of the blocking (more samples than a few correlation
   * times of M) and an error of at most 10 % of eps - 1, the part the fluctuation measures */
  const double rel = err / fabs(eps - 1.0), span = n * dt_sample;
  const char *tu = real ? "ps" : "time units";
  if (!blocked)
    fprintf(f, "dielectric_note = unreliable: %ld samples are too few for an error bar; run longer\n", n);
  else if (!b.converged)
    fprintf(f, "dielectric_note = unreliable: the run is shorter than the estimate needs: blocking <M^2> over its %ld "
               "samples (%.3g %s) found no plateau, so M has not decorrelated often enough and the error bar is a "
               "lower bound; run many times longer\n", n, span, tu);
  else if (!(rel <= 0.1))
    fprintf(f, "dielectric_note = unreliable: the run is shorter than the estimate needs: the error is %.0f %% of "
               "eps - 1; about %.2g %s of sampling (%.2g times this run's %.3g %s) would bring it to 10 %%\n",
            100.0 * rel, span * (rel / 0.1) * (rel / 0.1), tu, (rel / 0.1) * (rel / 0.1), span, tu);
}

/* The correlation functions of one run, as PREFIX.tcf.csv holds them (a NULL column is n/a). */
typedef struct {
  const analysis *a;
  long lag;
  double dt, *c[5];
} tcf_table;

static void write_tcf(FILE *fp, const void *ctx)
{
  const tcf_table *t = ctx;
  const char *vec = t->a->orient == ORIENT_AXIS ? "axis" : "dipole";
  fprintf(fp, "lag_time,%s_P1,%s_P2,vacf,omega_acf,msd\n", vec, vec);
  for (long k = 0; k <= t->lag; k++) {
    fprintf(fp, "%.6g", k * t->dt);
    for (int q = 0; q < 5; q++)
      if (t->c[q]) fprintf(fp, ",%.6g", t->c[q][k]);
      else fputs(",n/a", fp);
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
  fprintf(fp, "r");
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

/* Write `path` atomically (NAME.tmp.<pid>, renamed over NAME: on failure the earlier NAME is
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

int analysis_write(analysis *a, const char *prefix, double dt_sample)
{
  const rl_deck *d = a->d;
  int real = d->units == RL_UNITS_REAL;
  const char *E = real ? "kJ/mol" : "";
  /* results.txt is composed in memory and written last, so that it can report the other files;
   * every file is attempted whatever happened to the others, and any failure is the return */
  char errs[1024] = "", path[700], *text = NULL;
  size_t text_len = 0;
  FILE *f = open_memstream(&text, &text_len);
  if (!f) return rl_error(RL_ENOMEM, "%s.results.txt: cannot compose the results: %s", prefix, strerror(errno));
  if (d->energy_every > 1)
    fprintf(f, "# rotleap results over %ld of this invocation's steps, one in %ld (output.energy_every; "
               "block-averaged standard errors, Flyvbjerg-Petersen)\n", rl_series_count(a->U), d->energy_every);
  else
    fprintf(f, "# rotleap results over this invocation's %ld steps (block-averaged standard errors, "
               "Flyvbjerg-Petersen)\n", rl_series_count(a->U));
  line_block(f, "U_per_molecule", a->U, E);
  line_block(f, "temperature", a->T, real ? "K" : "");
  line_block(f, "temperature_translational", a->Tt, real ? "K" : "");
  line_block(f, "temperature_rotational", a->Tr, real ? "K" : "");
  line_block(f, "pressure", a->P, real ? "bar" : "");
  line_block(f, "mean_square_force", a->F2, real ? "(kJ/mol/nm)^2" : "");
  line_block(f, "mean_square_torque", a->K2, real ? "(kJ/mol)^2" : "");
  char ce[64], cu[64];
  fprintf(f, "calE = %s\ncalU = %s\n", rel_fluct_text(ce, sizeof ce, rl_series_rel_fluct(a->E)),
          rel_fluct_text(cu, sizeof cu, rl_series_rel_fluct(a->U)));
  /* The temperature of the fluctuation formulas: under a thermostat its target T0, the T of the
   * canonical (and isokinetic) distribution; the on-step T reads low at large steps (12 K for
   * water at 5 fs), which would bias C_V ~ 1/T^2 and y ~ 1/T.  In NVE the mean on-step T. */
  const int nve = d->thermostat == RL_THERMO_NONE;
  const double kB = rl_units_kB(d->units), Tm = rl_series_mean(a->T), sdK = rl_series_sd(a->K),
               sdU = rl_series_sd(a->U) * a->n, T = nve ? Tm : d->thermostat_temperature;
  const int dof = (int)llround(2.0 * rl_series_mean(a->K) / (kB * Tm)); /* T = 2K/(g kB) defines g */
  /* NVE: Lebowitz-Percus-Verlet from <dK^2>.  Any NVT: K and U are independent in the canonical
   * ensemble (and K is fixed in the isokinetic one), so the kinetic part is exactly f kB/2 and only
   * the configurational <dU^2>/(kB T0^2) is sampled: <dE^2>/(kB T^2) would add the noise of <dK^2>
   * and of cov(K, U), which converges slowly under Bussi, and the on-step K's step-size bias */
  double cv = NAN;
  const int st = nve ? rl_heat_capacity_nve(rl_series_mean(a->K), sdK * sdK, dof, kB, &cv)
                     : rl_heat_capacity_isokinetic(sdU * sdU, T, dof, kB, &cv);
  if (st) fprintf(f, "heat_capacity_per_molecule = n/a (%s)\n", rl_last_error());
  else if (nve)
    fprintf(f, "heat_capacity_per_molecule = %.6g %s (NVE, Lebowitz-Percus-Verlet formula)\n", cv / (a->n * kB),
            real ? "k_B" : "");
  else
    fprintf(f, "heat_capacity_per_molecule = %.6g %s (%s formula) [f k_B/2 + <dU^2>/(k_B T0^2), f = %d, T0 = %g%s "
               "the thermostat's target]\n", cv / (a->n * kB), real ? "k_B" : "",
            d->thermostat == RL_THERMO_ISOKINETIC ? "isokinetic" : "canonical", dof, T, real ? " K" : "");
  long nf = rl_vec_series_frames(a->pos);
  if (nf >= 4) {
    long lag = nf / 2 < RL_TCF_MAX_LAG ? nf / 2 : RL_TCF_MAX_LAG;
    if (a->samples > nf || nf / 2 > lag)
      fprintf(f, "correlation_functions = from the first %ld of %ld samples, lags up to %ld samples "
                 "(memory bound %.0f MB, lag bound %d: analysis.c)\n", nf, a->samples, lag,
              RL_TCF_MEMORY / (1024.0 * 1024.0), RL_TCF_MAX_LAG);
    fprintf(f, "orientation_vector = %s\n", a->orient_text);
    /* a column that cannot be computed is n/a in the file, with the reason here; never zeros */
    static const char *col[5] = {"P1", "P2", "vacf", "omega_acf", "msd"};
    double *c[5] = {NULL, NULL, NULL, NULL, NULL};
    rl_tcf_kind kinds[5] = {RL_TCF_P1, RL_TCF_P2, RL_TCF_DOT, RL_TCF_DOT, RL_TCF_MSD};
    rl_vec_series *src[5] = {a->axis, a->axis, a->vel, a->omega, a->pos};
    for (int k = a->orient == ORIENT_NONE ? 2 : 0; k < 5; k++) {
      if (!(c[k] = calloc((size_t)lag + 1, sizeof(double))))
        fprintf(f, "correlation_error = %s: out of memory\n", col[k]);
      else if (rl_tcf_compute(src[k], kinds[k], lag, 1, c[k])) {
        fprintf(f, "correlation_error = %s: %s\n", col[k], rl_last_error());
        free(c[k]);
        c[k] = NULL;
      }
    }
    double D, Derr;
    if (c[4] && !rl_diffusion_einstein(c[4], lag + 1, dt_sample, lag / 5, lag, &D, &Derr))
      fprintf(f, "self_diffusion = %.4g +- %.2g %s (Einstein, MSD lags %ld-%ld samples)\n", D, Derr,
              real ? "nm^2/ps" : "", lag / 5, lag);
    tcf_table t = {a, lag, dt_sample, {c[0], c[1], c[2], c[3], c[4]}};
    snprintf(path, sizeof path, "%s.tcf.csv", prefix);
    if (write_file(path, write_tcf, &t, errs, sizeof errs)) fprintf(f, "# could not write %s\n", rl_last_error());
    for (int k = 0; k < 5; k++) free(c[k]);
  }
  if (a->dipolar && rl_dipole_acc_count(a->M) >= 2) {
    double mean[3], dM2 = rl_dipole_acc_fluct(a->M, mean), eps;
    double V = d->box[0] * d->box[1] * d->box[2];
    if (a->point_dipoles && d->ff.dipole_method == RL_DIPOLE_SF)
      fprintf(f, "dielectric_constant = n/a (dipole = sf has no reaction-field boundary for the "
                 "fluctuation formula; dipole = rf with eps_rf gives one)\n");
    else if (rl_dielectric_constant(dM2, V, T, d->ff.eps_rf, d->units, d->ff.coulomb_constant, &eps))
      fprintf(f, "dielectric_constant = n/a (%s)\n", rl_last_error());
    else
      dielectric_lines(f, a, dM2, V, T, eps, nve ? "the mean temperature" : "the thermostat's target", dt_sample);
  }
  if (a->nrdf > 0 && rl_rdf_frames(a->rdf[0]) == 0) /* nothing to normalise: no file, not garbage */
    fprintf(f, "rdf = n/a (no configuration was sampled: output.sample_every)\n");
  else if (a->nrdf > 0) {
    const int nb = rl_rdf_nbins(a->rdf[0]);
    double *r = malloc(sizeof(double) * (size_t)nb), *g = malloc(sizeof(double) * (size_t)nb * (size_t)a->nrdf);
    snprintf(path, sizeof path, "%s.rdf.csv", prefix);
    int bad = !r || !g;
    for (int q = 0; q < a->nrdf && !bad; q++) bad = rl_rdf_get(a->rdf[q], r, g + (size_t)q * (size_t)nb) != RL_OK;
    rdf_table t = {a, nb, r, g};
    if (bad) {
      add_failure(errs, sizeof errs, "%s: %s", path, !r || !g ? "out of memory" : rl_last_error());
      fprintf(f, "# could not write %s: %s\n", path, !r || !g ? "out of memory" : "the RDF could not be normalised");
    } else if (write_file(path, write_rdf, &t, errs, sizeof errs))
      fprintf(f, "# could not write %s\n", rl_last_error());
    free(r);
    free(g);
  }
  /* the results file itself */
  const int composed = fclose(f) == 0 && text;
  snprintf(path, sizeof path, "%s.results.txt", prefix);
  if (!composed) add_failure(errs, sizeof errs, "%s: out of memory composing it", path);
  else write_file(path, write_text, text, errs, sizeof errs);
  free(text);
  return errs[0] ? rl_error(RL_EINVAL, "%s", errs) : RL_OK;
}
