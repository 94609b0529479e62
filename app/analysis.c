/* rotleap run's analysis: a thin layer over include/rotleap/observables.h.
 *
 * Every input is a record: analysis_step and analysis_sample turn what they read (the step's
 * report, the configuration) into one, append it to the journal when there is one, and consume
 * it; analysis_replay consumes the records of a journal.  So the accumulators of a continuation
 * that replays the journal are those of the uninterrupted run, bit for bit.  The journal's
 * format is in docs/observables.md ("The analysis journal"). */
#include "analysis.h"

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

#define MAX_RDF RL_DECK_MAX_RDF
#define RDF_BINS 200

/* The values of a step record, after its time t; under a barostat the NB values of the box after them. */
enum { V_U, V_T, V_TT, V_TR, V_P, V_E, V_EC, V_K, V_F2, V_K2, NV };
enum { B_V, B_RHO, B_LX, B_LY, B_LZ, B_H, NB }; /* volume, density, edges, enthalpy per molecule */

struct analysis {
  const rl_deck *d;
  double box[3];     /* the system's box (a run at constant volume: the same all along); the deck's
                        under a barostat                                                        */
  const rl_molecule *mol;
  int n;
  rl_trace *v[NV];       /* the step series (V_U: U per molecule, V_E: total, V_EC: conserved)   */
  long nstep;            /* step records consumed                                                */
  double t_first, t_last; /* their first and last times                                          */
  rl_trace *M[3], *M2;   /* per sample: the total dipole's components and |M|^2 (dipolar)       */
  long *mark_c;          /* step records consumed before sample k S (k < nmarks): where the
                            samples of the equilibrated part start, on the RDFs' marks           */
  long mark_every;       /* S                                                                    */
  int nmarks;
  int nrdf;
  rl_rdf *rdf[MAX_RDF];
  int rdf_site[MAX_RDF][2], rdf_sp[MAX_RDF][2]; /* output.rdf: each pair's sites and species */
  char rdf_name[MAX_RDF][48];
  /* a mixture (d->nspecies > 1; else nsp = 0): each species' bodies (consecutive), rotational
   * dof per body and name, its temperatures per step (translational, rotational) and whether
   * its bodies carry the vector of P1/P2 (orient) */
  int nsp;
  int sp_first[RL_DECK_MAX_SPECIES], sp_count[RL_DECK_MAX_SPECIES], sp_rot[RL_DECK_MAX_SPECIES];
  int sp_orient[RL_DECK_MAX_SPECIES];
  const char *sp_name[RL_DECK_MAX_SPECIES];
  rl_trace *vs[RL_DECK_MAX_SPECIES][2];
  rl_vec_series *axis, *vel, *omega, *pos;
  double (*unwrapped)[3], (*buf)[3], (*dip)[3]; /* unwrapped: the centres of the last sample */
  rl_species_ff sff[RL_DECK_MAX_SPECIES]; /* each species', d->nspecies of them */
  int dipolar;       /* the molecules have a net dipole: M, its fluctuation, the dielectric constant */
  int orient;        /* the vector of P1/P2: ORIENT_DIPOLE, ORIENT_AXIS or ORIENT_NONE              */
  char orient_text[400]; /* results.txt's orientation_vector: which vector, or n/a and why          */
  int point_dipoles; /* sites with a point dipole: their boundary is dipole_method's */
  long tcf_cap;      /* samples kept for the correlation functions and the MSD (memory bound) */
  long samples;      /* samples taken                                                        */
  unsigned char *rec; /* one record (its largest size)                                        */
  uint32_t *hist;     /* [nrdf][RDF_BINS] one frame's pair counts                             */
  FILE *jfp;          /* the journal, or NULL                                                 */
  char *jpath;
  long jbytes;        /* bytes of the journal written or replayed                             */
  long seq;           /* records written or replayed                                          */
  int jbad;           /* a write failed: the journal is no longer a prefix of the run         */
  int replayed;
  /* output.tconf: the configurational temperature's sums of each sample (forcefield.h) */
  int tconf;
  rl_trace *tc[6];              /* per sample: sum |F|^2, sum lap_r, sum |tau|^2, sum lap_rot, and
                                   the totals sum |F|^2 + |tau|^2, sum lap_r + lap_rot                */
  const rl_forcefield *ff;      /* analysis_set_tconf: the force field the sums use                */
  char tconf_na[RL_FF_TEXT + 64]; /* why the sums cannot be taken (another term), or ""           */
  char tconf_note[3 * RL_FF_TEXT]; /* the force field's discontinuities (the estimator is biased) */
  /* run.barostat: the box's series (B_*), the mass of the density and the barostat's counts */
  int baro;
  rl_trace *b[NB];
  double mass;
  int have_stats;
  rl_barostat_stats stats;
};

/* The correlation functions and the MSD keep whole configurations (four vectors per body and
 * sample), and are computed directly over every time origin: memory grows with the run and
 * time with samples x lags.  A long run (10^7 steps of 216 TIP4P sampled every 10 would need
 * 20 GB) keeps the first RL_TCF_MEMORY bytes' worth of samples, and the lags go to
 * RL_TCF_MAX_LAG samples at most; results.txt says so when that happens.  The RDFs, the
 * dipole fluctuation and the block averages use every sample. */
#define RL_TCF_MEMORY (256.0 * 1024 * 1024)
#define RL_TCF_MAX_LAG 1000
/* Chodera's detection runs on at most this many block means of U (rl_trace_equilibration) */
#define EQUIL_POINTS 1000
/* The self-diffusion's block error: D of this many consecutive parts of the samples */
#define D_BLOCKS 5

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


/* ------------------------------------------------------------------ the journal's header */

#define JOURNAL_MAGIC "rotleapJ"
#define JOURNAL_VERSION 1u
#define JOURNAL_BOM 0x01020304u
#define TAG_STEP 0x50455453u   /* "STEP" in little-endian byte order */
#define TAG_SAMPLE 0x504d4153u /* "SAMP" */
#define RECORD_HEAD 16         /* tag (u32), payload bytes (u32), sequence number (i64) */

typedef struct {
  char magic[8];
  uint32_t version, bom, bytes;
  int32_t n, units, orient, dipolar, nrdf, nbins, site[MAX_RDF][2];
  double rmax, box[3], timestep;
  int64_t energy_every, sample_every, tcf_cap;
  char model[64];
  int32_t tconf; /* output.tconf; only in the header of a journal with it or with baro (so the others are as before) */
  int32_t baro;  /* run.barostat; only in the header of a journal with it or of a mixture */
  int32_t nsp;   /* a mixture's species; only in the header of a mixture's journal */
} jheader;

/* Copy k bytes between *x and buf + *off, in the direction `out` (1: x to buf). */
static void io(unsigned char *buf, size_t *off, void *x, size_t k, int out)
{
  if (out) memcpy(buf + *off, x, k);
  else memcpy(x, buf + *off, k);
  *off += k;
}

/* The header to or from buf (JOURNAL_HEADER_MAX bytes at most); returns its size. */
#define JOURNAL_HEADER_MAX 512
static size_t header_io(jheader *h, unsigned char *buf, int out)
{
  size_t o = 0;
  io(buf, &o, h->magic, sizeof h->magic, out);
  io(buf, &o, &h->version, 4, out);
  io(buf, &o, &h->bom, 4, out);
  io(buf, &o, &h->bytes, 4, out);
  int32_t *ints[] = {&h->n, &h->units, &h->orient, &h->dipolar, &h->nrdf, &h->nbins};
  for (size_t k = 0; k < sizeof ints / sizeof ints[0]; k++) io(buf, &o, ints[k], 4, out);
  io(buf, &o, h->site, sizeof h->site, out);
  io(buf, &o, &h->rmax, 8, out);
  io(buf, &o, h->box, sizeof h->box, out);
  io(buf, &o, &h->timestep, 8, out);
  io(buf, &o, &h->energy_every, 8, out);
  io(buf, &o, &h->sample_every, 8, out);
  io(buf, &o, &h->tcf_cap, 8, out);
  io(buf, &o, h->model, sizeof h->model, out);
  if (out ? h->tconf || h->baro || h->nsp : h->bytes > o) io(buf, &o, &h->tconf, 4, out);
  if (out ? h->baro || h->nsp : h->bytes > o) io(buf, &o, &h->baro, 4, out);
  if (out ? h->nsp : h->bytes > o) io(buf, &o, &h->nsp, 4, out);
  return o;
}

/* The header a journal of this analysis has. */
static void header_of(const analysis *a, jheader *h)
{
  memset(h, 0, sizeof *h);
  memcpy(h->magic, JOURNAL_MAGIC, 8);
  h->version = JOURNAL_VERSION;
  h->bom = JOURNAL_BOM;
  h->tconf = a->tconf;
  h->baro = a->baro;
  h->nsp = a->nsp;
  unsigned char scratch[JOURNAL_HEADER_MAX];
  h->bytes = (uint32_t)header_io(h, scratch, 1);
  h->n = a->n;
  h->units = (int32_t)a->d->units;
  h->orient = a->orient;
  h->dipolar = a->dipolar;
  h->nrdf = a->nrdf;
  h->nbins = RDF_BINS;
  for (int q = 0; q < a->nrdf; q++) {
    h->site[q][0] = a->rdf_site[q][0] | a->rdf_sp[q][0] << 16; /* one species: the site */
    h->site[q][1] = a->rdf_site[q][1] | a->rdf_sp[q][1] << 16;
  }
  h->rmax = a->nrdf ? rl_rdf_rmax(a->rdf[0]) : 0.0;
  memcpy(h->box, a->box, sizeof h->box);
  h->timestep = a->d->timestep;
  h->energy_every = a->d->energy_every;
  h->sample_every = a->d->sample_every;
  h->tcf_cap = a->tcf_cap;
  snprintf(h->model, sizeof h->model, "%s", a->d->model ? a->d->model->name : a->mol->name);
}

/* RL_OK if a journal's header `got` is the one this analysis writes, else the first difference. */
static int header_check(const jheader *got, const jheader *want, const char *path)
{
  if (memcmp(got->magic, want->magic, 8))
    return rl_error(RL_EINVAL, "%s is not a rotleap analysis journal (no '%s' at its start)", path, JOURNAL_MAGIC);
  if (got->bom != want->bom)
    return rl_error(RL_EINVAL, "%s was written on a machine of another byte order", path);
  if (got->version == want->version && got->tconf != want->tconf)
    return rl_error(RL_EINVAL, "%s was written with output.tconf = %s, this run has %s", path, got->tconf ? "yes" : "no",
                    want->tconf ? "yes" : "no");
  if (got->version == want->version && got->baro != want->baro)
    return rl_error(RL_EINVAL, "%s was written with run.barostat %d, this run has %d", path, got->baro, want->baro);
  if (got->version == want->version && got->nsp != want->nsp)
    return rl_error(RL_EINVAL, "%s was written for %d species (system.species), this run has %d", path,
                    got->nsp > 1 ? got->nsp : 1, want->nsp > 1 ? want->nsp : 1);
  if (got->version != want->version || got->bytes != want->bytes)
    return rl_error(RL_EINVAL, "%s is an analysis journal of version %u (%u header bytes); this rotleap reads "
                    "version %u (%u bytes)", path, got->version, got->bytes, want->version, want->bytes);
#define SAME(f, what, fmt) \
  if (got->f != want->f) \
    return rl_error(RL_EINVAL, "%s was written for " what " " fmt ", this run has " fmt, path, got->f, want->f)
  SAME(n, "a system of", "%d molecules");
  SAME(units, "units", "%d");
  SAME(energy_every, "output.energy_every =", "%" PRId64);
  SAME(sample_every, "output.sample_every =", "%" PRId64);
  SAME(timestep, "run.timestep =", "%.17g");
  SAME(nrdf, "output.rdf with", "%d pairs");
  SAME(orient, "orientation vector", "%d");
  SAME(dipolar, "dipolar =", "%d");
  SAME(nbins, "RDFs of", "%d bins");
  SAME(rmax, "RDFs up to", "%.17g");
  SAME(tcf_cap, "a correlation-function bound of", "%" PRId64 " samples");
#undef SAME
  if (strncmp(got->model, want->model, sizeof got->model))
    return rl_error(RL_EINVAL, "%s was written for model %.64s, this run has %.64s", path, got->model, want->model);
  if (memcmp(got->box, want->box, sizeof got->box))
    return rl_error(RL_EINVAL, "%s was written for a box of %.17g x %.17g x %.17g, this run has %.17g x %.17g x %.17g",
                    path, got->box[0], got->box[1], got->box[2], want->box[0], want->box[1], want->box[2]);
  if (memcmp(got->site, want->site, sizeof got->site))
    return rl_error(RL_EINVAL, "%s was written for other output.rdf site pairs", path);
  return RL_OK;
}

/* ------------------------------------------------------------------ alloc, free */

analysis *analysis_alloc(const rl_deck *d, const rl_molecule *mols, const rl_system *sys)
{
  const rl_molecule *mol = &mols[0];
  analysis *a = calloc(1, sizeof *a);
  if (!a) { rl_error(RL_ENOMEM, "out of memory for the analysis"); return NULL; }
  a->d = d;
  a->mol = mol;
  a->n = rl_system_count(sys);
  int ok = 1;
  for (int k = 0; k < NV; k++) ok = (a->v[k] = rl_trace_alloc(0)) && ok;
  for (int k = 0; k < 3; k++) ok = (a->M[k] = rl_trace_alloc(0)) && ok;
  a->tconf = d->tconf && d->sample_every > 0;
  for (int k = 0; k < 6 && a->tconf; k++) ok = (a->tc[k] = rl_trace_alloc(0)) && ok;
  a->baro = d->barostat;
  for (int k = 0; k < NB && a->baro; k++) ok = (a->b[k] = rl_trace_alloc(0)) && ok;
  for (int i = 0; i < a->n && a->baro; i++) a->mass += rl_system_mass(sys, i);
  if (d->units == RL_UNITS_REAL) a->mass /= 602.214076; /* u/nm^3 -> g/cm^3, as the thermo file's density */
  ok = (a->M2 = rl_trace_alloc(0)) && ok;
  /* output.rdf: "O-O, H-H" */
  /* under a barostat, the deck's box (the first run's start; a continuation's box differs) in the
   * journal's header; each sample carries its own box, which the RDFs' normalisation and the
   * unwrapping use; the dielectric constant takes the mean volume (dielectric_lines) */
  if (d->barostat) memcpy(a->box, d->box, sizeof a->box);
  else rl_system_box(sys, a->box);
  double rmax = 0.5 * fmin(a->box[0], fmin(a->box[1], a->box[2]));
  if (d->barostat) rmax = fmin(rmax, d->ff.cutoff); /* the box may shrink to twice the cutoff, not below */
  rl_deck_rdf_pair pairs[MAX_RDF];
  const int nrdf = rl_deck_rdf_species_pairs(d->rdf, mols, d->nspecies, pairs);
  if (nrdf < 0) { analysis_free(a); return NULL; }
  for (; a->nrdf < nrdf; a->nrdf++) {
    const rl_deck_rdf_pair *p = &pairs[a->nrdf];
    for (int k = 0; k < 2; k++) {
      a->rdf_site[a->nrdf][k] = p->site[k];
      a->rdf_sp[a->nrdf][k] = p->species[k];
    }
    memcpy(a->rdf_name[a->nrdf], p->name, sizeof p->name);
    a->rdf[a->nrdf] = rl_rdf_alloc(rmax, RDF_BINS);
  }
  if (d->nspecies > 1) { /* a mixture: the species' temperatures, MSD and diffusion */
    a->nsp = d->nspecies;
    for (int k = 0, first = 0; k < a->nsp; k++) {
      a->sp_first[k] = first;
      first += a->sp_count[k] = rl_system_species_count(sys, k);
      a->sp_rot[k] = rl_kind_rotational_dof(rl_system_species_kind(sys, k));
      a->sp_name[k] = mols[k].name;
      for (int q = 0; q < 2; q++) ok = (a->vs[k][q] = rl_trace_alloc(0)) && ok;
    }
  }
  a->tcf_cap = (long)(RL_TCF_MEMORY / (4.0 * sizeof(double[3]) * (a->n > 0 ? a->n : 1)));
  if (a->tcf_cap < 8) a->tcf_cap = 8;
  a->axis = rl_vec_series_alloc(a->n);
  a->vel = rl_vec_series_alloc(a->n);
  a->omega = rl_vec_series_alloc(a->n);
  a->pos = rl_vec_series_alloc(a->n);
  a->unwrapped = calloc((size_t)a->n, sizeof *a->unwrapped);
  a->buf = calloc((size_t)a->n, sizeof *a->buf);
  a->dip = calloc((size_t)a->n, sizeof *a->dip);
  a->mark_c = calloc(RL_RDF_MARKS, sizeof *a->mark_c);
  a->mark_every = 1;
  /* the largest record: a sample that still feeds the correlation functions */
  a->rec = malloc((size_t)a->nrdf * (16 + 4 * RDF_BINS) + 24 + 4 * sizeof(double[3]) * (size_t)a->n +
                  8 * (1 + NV + NB + 2 * (size_t)a->nsp) + sizeof(double[4]) + sizeof(double[3]));
  a->hist = malloc(sizeof *a->hist * RDF_BINS);
  ok = ok && a->axis && a->vel && a->omega && a->pos && a->unwrapped && a->buf && a->dip && a->mark_c && a->rec &&
       a->hist;
  for (int k = 0; k < a->nrdf; k++) ok = ok && a->rdf[k];
  if (!ok) { /* the samplers would dereference NULL */
    analysis_free(a);
    rl_error(RL_ENOMEM, "out of memory for the analysis of %d molecules", rl_system_count(sys));
    return NULL;
  }
  for (int k = 0; k < d->nspecies; k++) {
    a->sff[k] = rl_molecule_ff(&mols[k]);
    for (int s = 0; s < mols[k].nsites; s++) a->point_dipoles |= mols[k].dipole[s] != 0.0;
    a->dipolar |= net_dipole(&mols[k]);
  }
  choose_orientation(a, d->model ? d->model->name : mol->name);
  if (a->nsp) { /* a mixture: P1/P2 over the species whose bodies carry the vector */
    char which[160] = "";
    for (int k = 0, at = 0; k < a->nsp; k++) {
      const rl_kind kk = mols[k].natural_kind;
      a->sp_orient[k] = a->dipolar ? net_dipole(&mols[k])
                                   : kk == RL_KIND_LINEAR || kk == RL_KIND_DIPOLE || kk == RL_KIND_SYMMETRIC;
      if (a->sp_orient[k] && at < (int)sizeof which)
        at += snprintf(which + at, sizeof which - (size_t)at, "%s%s", at ? ", " : "", mols[k].name);
    }
    if (!a->dipolar) a->orient = which[0] ? ORIENT_AXIS : ORIENT_NONE;
    if (a->orient == ORIENT_NONE)
      snprintf(a->orient_text, sizeof a->orient_text, "n/a (no species of the mixture has a net dipole or a unique "
               "molecular axis; tcf.csv columns dipole_P1, dipole_P2 are n/a)");
    else
      snprintf(a->orient_text, sizeof a->orient_text, "%s of the molecules of %s (the species that have one; tcf.csv "
               "columns %s_P1, %s_P2)", a->dipolar ? "molecular dipole mu_i" : "molecular axis (rho, or body Z of a "
               "symmetric top)", which, a->dipolar ? "dipole" : "axis", a->dipolar ? "dipole" : "axis");
  }
  return a;
}

void analysis_free(analysis *a)
{
  if (!a) return;
  for (int k = 0; k < NV; k++) rl_trace_free(a->v[k]);
  for (int k = 0; k < 3; k++) rl_trace_free(a->M[k]);
  for (int k = 0; k < 6; k++) rl_trace_free(a->tc[k]);
  for (int k = 0; k < NB; k++) rl_trace_free(a->b[k]);
  for (int k = 0; k < a->nsp; k++)
    for (int q = 0; q < 2; q++) rl_trace_free(a->vs[k][q]);
  rl_trace_free(a->M2);
  for (int k = 0; k < a->nrdf; k++) rl_rdf_free(a->rdf[k]);
  rl_vec_series_free(a->axis);
  rl_vec_series_free(a->vel);
  rl_vec_series_free(a->omega);
  rl_vec_series_free(a->pos);
  free(a->unwrapped); free(a->buf); free(a->dip); free(a->mark_c); free(a->rec); free(a->hist); free(a->jpath);
  free(a);
}

int analysis_set_tconf(analysis *a, const rl_terms *terms, const rl_forcefield *ff)
{
  if (!a || !a->tconf) return RL_OK;
  a->ff = NULL;
  a->tconf_na[0] = a->tconf_note[0] = '\0';
  for (int k = 0; terms && k < rl_terms_count(terms); k++)
    if (strcmp(rl_terms_type(terms, k)->name, "pair")) {
      snprintf(a->tconf_na, sizeof a->tconf_na, "the force term '%s' has no Laplacian in rl_config_temperature (only "
               "the pair term has)", rl_terms_type(terms, k)->name);
      return RL_OK;
    }
  if (!ff) {
    snprintf(a->tconf_na, sizeof a->tconf_na, "no pair force field");
    return RL_OK;
  }
  a->ff = ff;
  rl_ff_discontinuity dis[8];
  const int nd = rl_forcefield_discontinuities(ff, dis, 8);
  for (int t = 0; t < nd && t < 8; t++) {
    if (!dis[t].force_jumps && !dis[t].energy_jumps) continue;
    const size_t used = strlen(a->tconf_note);
    snprintf(a->tconf_note + used, sizeof a->tconf_note - used, "%s%s (%s jumps)", used ? ", " : "", dis[t].term,
             dis[t].energy_jumps ? "energy" : "force");
  }
  return RL_OK;
}

/* ------------------------------------------------------------------ records */

/* Bytes of the next sample record's payload (it feeds the correlation functions or not). */
static size_t sample_bytes(const analysis *a)
{
  size_t len = (size_t)a->nrdf * (16 + 4 * RDF_BINS) + (a->dipolar ? 24 : 0) + (a->tconf ? sizeof(double[4]) : 0) +
               (a->baro ? sizeof(double[3]) : 0);
  if (a->samples < a->tcf_cap) len += (size_t)(3 + (a->orient != ORIENT_NONE)) * sizeof(double[3]) * (size_t)a->n;
  return len;
}

/* Bytes of a step record's payload: t, the NV values, under a barostat the NB of the box, and in
 * a mixture each species' translational and rotational temperature. */
static size_t step_bytes(const analysis *a) { return 8 * (size_t)(1 + NV + (a->baro ? NB : 0) + 2 * a->nsp); }

static int consume_step(analysis *a, const unsigned char *p)
{
  double x[1 + NV + NB + 2 * RL_DECK_MAX_SPECIES];
  const int nx = (int)(step_bytes(a) / 8), nb = a->baro ? NB : 0;
  memcpy(x, p, step_bytes(a));
  for (int k = 0; k < nx; k++)
    if (!isfinite(x[k])) return rl_error(RL_ENONFINITE, "analysis: a step record with a non-finite value (%d)", k);
  if (a->nstep == 0) a->t_first = x[0];
  a->t_last = x[0];
  for (int k = 0; k < nx - 1; k++) {
    rl_trace *t = k < NV ? a->v[k] : k < NV + nb ? a->b[k - NV] : a->vs[(k - NV - nb) / 2][(k - NV - nb) % 2];
    int st = rl_trace_add(t, x[1 + k]);
    if (st) return st;
  }
  a->nstep++;
  return RL_OK;
}

/* Before sample j = k S, the step records consumed so far (RL_RDF_MARKS marks, as rl_rdf's). */
static void mark_sample(analysis *a)
{
  if (a->samples % a->mark_every) return;
  if (a->nmarks == RL_RDF_MARKS) {
    for (int k = 0; k < RL_RDF_MARKS / 2; k++) a->mark_c[k] = a->mark_c[2 * k];
    a->nmarks = RL_RDF_MARKS / 2;
    a->mark_every *= 2;
    if (a->samples % a->mark_every) return;
  }
  a->mark_c[a->nmarks++] = a->nstep;
}

/* Copy n x 3 doubles from p into a->buf; returns p after them. */
static const unsigned char *get_vectors(analysis *a, const unsigned char *p)
{
  memcpy(a->buf, p, sizeof(double[3]) * (size_t)a->n);
  return p + sizeof(double[3]) * (size_t)a->n;
}

static int consume_sample(analysis *a, const unsigned char *p)
{
  int st = RL_OK;
  mark_sample(a);
  double box[3]; /* the sample's: under a barostat its own, first in the record */
  memcpy(box, a->box, sizeof box);
  if (a->baro) {
    memcpy(box, p, sizeof box);
    p += sizeof box;
  }
  if (a->tconf) { /* the configurational temperature's sums come first */
    double x[4];
    memcpy(x, p, sizeof x);
    p += sizeof x;
    for (int k = 0; k < 4 && !st; k++) st = rl_trace_add(a->tc[k], x[k]);
    if (!st) st = rl_trace_add(a->tc[4], x[0] + x[2]);
    if (!st) st = rl_trace_add(a->tc[5], x[1] + x[3]);
  }
  for (int q = 0; q < a->nrdf && !st; q++) {
    double pairs;
    int32_t na;
    memcpy(&pairs, p, 8);
    memcpy(&na, p + 8, 4);
    memcpy(a->hist, p + 16, 4 * RDF_BINS);
    p += 16 + 4 * RDF_BINS;
    st = rl_rdf_add_counts(a->rdf[q], box, a->hist, pairs, na);
  }
  if (a->dipolar && !st) {
    double M[3];
    memcpy(M, p, sizeof M);
    p += sizeof M;
    for (int k = 0; k < 3 && !st; k++) st = rl_trace_add(a->M[k], M[k]);
    if (!st) st = rl_trace_add(a->M2, M[0] * M[0] + M[1] * M[1] + M[2] * M[2]);
  }
  if (st || a->samples++ >= a->tcf_cap) return st; /* the correlation functions have their samples */
  if (a->orient != ORIENT_NONE) {
    p = get_vectors(a, p);
    if ((st = rl_vec_series_add(a->axis, (const double(*)[3])a->buf))) return st;
  }
  rl_vec_series *vs[2] = {a->vel, a->omega};
  for (int k = 0; k < 2; k++) {
    p = get_vectors(a, p);
    if ((st = rl_vec_series_add(vs[k], (const double(*)[3])a->buf))) return st;
  }
  get_vectors(a, p);
  /* each centre is the image nearest its previous *unwrapped* position (rl_unwrap's contract):
   * nearest the previous raw position, a body would lose its image one sample after crossing */
  if (rl_vec_series_frames(a->pos) == 0) memcpy(a->unwrapped, a->buf, sizeof *a->buf * (size_t)a->n);
  else rl_unwrap(box, (const double(*)[3])a->unwrapped, (const double(*)[3])a->buf, a->n, a->unwrapped);
  return rl_vec_series_add(a->pos, (const double(*)[3])a->unwrapped);
}

/* RL_OK unless a write of the journal failed (then nothing more is taken: the journal would no
 * longer hold what the analysis consumed). */
static int journal_ok(const analysis *a)
{
  return a->jbad ? rl_error(RL_EINVAL, "%s: an earlier write of the analysis journal failed", a->jpath) : RL_OK;
}

/* Journal a record (when there is a journal), then consume it. */
static int feed(analysis *a, uint32_t tag, size_t len)
{
  if (a->jfp) {
    unsigned char head[RECORD_HEAD];
    const uint32_t bytes = (uint32_t)len;
    const int64_t seq = a->seq;
    memcpy(head, &tag, 4);
    memcpy(head + 4, &bytes, 4);
    memcpy(head + 8, &seq, 8);
    errno = 0;
    if (fwrite(head, 1, sizeof head, a->jfp) != sizeof head || fwrite(a->rec, 1, len, a->jfp) != len) {
      a->jbad = 1;
      return rl_error(RL_EINVAL, "%s: cannot write the analysis journal: %s", a->jpath,
                      errno ? strerror(errno) : "write error");
    }
    a->jbytes += (long)(sizeof head + len);
  }
  a->seq++;
  return tag == TAG_STEP ? consume_step(a, a->rec) : consume_sample(a, a->rec);
}

int analysis_step(analysis *a, const rl_step_info *info, double pressure, const rl_forces *F, const rl_system *sys,
                  const double *box)
{
  int st = journal_ok(a);
  if (st) return st;
  double f2 = 0.0, k2 = 0.0;
  for (int i = 0; i < a->n; i++) {
    f2 += F->f[i][0] * F->f[i][0] + F->f[i][1] * F->f[i][1] + F->f[i][2] * F->f[i][2];
    int r = rl_system_rot_index(sys, i);
    if (r >= 0) k2 += F->k[r][0] * F->k[r][0] + F->k[r][1] * F->k[r][1] + F->k[r][2] * F->k[r][2];
  }
  double x[1 + NV + NB + 2 * RL_DECK_MAX_SPECIES];
  x[0] = info->t;
  x[1 + V_U] = info->potential / a->n;
  x[1 + V_T] = info->temperature;
  x[1 + V_TT] = info->t_trans;
  x[1 + V_TR] = info->t_rot;
  x[1 + V_P] = pressure;
  x[1 + V_E] = info->total;
  x[1 + V_EC] = info->conserved;
  x[1 + V_K] = info->ke_trans + info->ke_rot;
  x[1 + V_F2] = f2 / a->n;
  x[1 + V_K2] = k2 / a->n;
  if (a->baro) { /* the box at t, and H = U + K + P0 V per molecule with the barostat's target P0 */
    double L[3];
    if (box) memcpy(L, box, sizeof L);
    else rl_system_box(sys, L);
    const double V = L[0] * L[1] * L[2];
    x[1 + NV + B_V] = V;
    x[1 + NV + B_RHO] = a->mass / V;
    for (int k = 0; k < 3; k++) x[1 + NV + B_LX + k] = L[k];
    x[1 + NV + B_H] = (info->total + a->d->pressure * V) / a->n;
  }
  if (a->nsp && (!info->species || info->nspecies < a->nsp))
    return rl_error(RL_EINVAL, "analysis_step: the step report has no kinetic energies per species (%d of %d)",
                    info->species ? info->nspecies : 0, a->nsp);
  for (int k = 0, o = 1 + NV + (a->baro ? NB : 0); k < a->nsp; k++) {
    x[o + 2 * k] = info->species[k].t_trans;
    x[o + 2 * k + 1] = info->species[k].t_rot;
  }
  const size_t len = step_bytes(a);
  for (size_t k = 0; k < len / 8; k++) /* a record is whole or not at all */
    if (!isfinite(x[k])) return rl_error(RL_ENONFINITE, "analysis_step: a non-finite value at t = %g (%zu)", info->t, k);
  memcpy(a->rec, x, len);
  return feed(a, TAG_STEP, len);
}

/* Append n x 3 doubles at p; returns p after them. */
static unsigned char *put_vectors(unsigned char *p, const double (*v)[3], int n)
{
  memcpy(p, v, sizeof(double[3]) * (size_t)n);
  return p + sizeof(double[3]) * (size_t)n;
}

int analysis_sample(analysis *a, const rl_system *sys)
{
  int st = journal_ok(a);
  if (st) return st;
  unsigned char *p = a->rec;
  if (a->baro) {
    double box[3];
    rl_system_box(sys, box);
    memcpy(p, box, sizeof box);
    p += sizeof box;
  }
  if (a->tconf) {
    rl_tconf_sums t = {0.0, 0.0, 0.0, 0.0};
    if (!a->ff && !a->tconf_na[0])
      return rl_error(RL_ESTATE, "analysis_sample: output.tconf needs the force field (analysis_set_tconf)");
    if (a->ff && (st = rl_config_temperature(a->ff, sys, &t))) return st;
    const double x[4] = {t.f2, t.lap_r, t.k2, t.lap_rot}; /* zeros where n/a: the lines say why */
    memcpy(p, x, sizeof x);
    p += sizeof x;
  }
  for (int q = 0; q < a->nrdf; q++) {
    double pairs;
    int na;
    if ((st = rl_rdf_count_sites(a->rdf[q], sys, a->rdf_sp[q][0], a->rdf_site[q][0], a->rdf_sp[q][1],
                                 a->rdf_site[q][1], a->hist, &pairs, &na)))
      return st;
    const int32_t na32 = na, pad = 0;
    memcpy(p, &pairs, 8);
    memcpy(p + 8, &na32, 4);
    memcpy(p + 12, &pad, 4);
    memcpy(p + 16, a->hist, 4 * RDF_BINS);
    p += 16 + 4 * RDF_BINS;
  }
  if (a->dipolar) {
    double M[3];
    if ((st = rl_system_dipoles(sys, a->sff, a->d->nspecies, a->dip, M))) return st;
    memcpy(p, M, sizeof M);
    p += sizeof M;
  }
  if (a->samples < a->tcf_cap) {
    if (a->orient == ORIENT_DIPOLE) p = put_vectors(p, (const double(*)[3])a->dip, a->n);
    else if (a->orient == ORIENT_AXIS) {
      rl_system_axes(sys, a->buf);
      p = put_vectors(p, (const double(*)[3])a->buf, a->n);
    }
    rl_system_velocities(sys, a->buf);
    p = put_vectors(p, (const double(*)[3])a->buf, a->n);
    rl_system_angular_velocities(sys, a->buf);
    p = put_vectors(p, (const double(*)[3])a->buf, a->n);
    rl_system_positions(sys, a->buf);
    p = put_vectors(p, (const double(*)[3])a->buf, a->n);
  }
  return feed(a, TAG_SAMPLE, (size_t)(p - a->rec));
}

/* ------------------------------------------------------------------ journal and replay */

int analysis_set_journal(analysis *a, FILE *fp, const char *path)
{
  if (!a || !fp || !path) return rl_error(RL_EINVAL, "analysis_set_journal: NULL argument");
  if (a->jfp) return rl_error(RL_ESTATE, "%s: the analysis already has a journal (%s)", path, a->jpath);
  if (a->seq > 0 && !a->replayed)
    return rl_error(RL_ESTATE, "%s: the journal must be set before the analysis's first step or sample (it has "
                    "consumed %ld records)", path, a->seq);
  errno = 0;
  const long pos = ftell(fp);
  if (pos < 0) return rl_error(RL_EINVAL, "%s: cannot tell the journal's position: %s", path, strerror(errno));
  if (!(a->jpath = strdup(path))) return rl_error(RL_ENOMEM, "out of memory");
  if (a->replayed) { /* appending to the journal just replayed, cut to what was replayed */
    if (pos != a->jbytes) {
      free(a->jpath);
      a->jpath = NULL;
      return rl_error(RL_EINVAL, "%s: the journal is positioned at byte %ld but the analysis replayed its first %ld "
                      "bytes: cut it to %ld bytes and append from there", path, pos, a->jbytes, a->jbytes);
    }
  } else {
    if (pos != 0) {
      free(a->jpath);
      a->jpath = NULL;
      return rl_error(RL_EINVAL, "%s: a new journal must start empty (it is at byte %ld)", path, pos);
    }
    jheader h;
    unsigned char buf[JOURNAL_HEADER_MAX];
    header_of(a, &h);
    const size_t len = header_io(&h, buf, 1);
    errno = 0;
    if (fwrite(buf, 1, len, fp) != len) {
      free(a->jpath);
      a->jpath = NULL;
      return rl_error(RL_EINVAL, "%s: cannot write the analysis journal: %s", path, errno ? strerror(errno) : "write error");
    }
    a->jbytes = (long)len;
  }
  a->jfp = fp;
  return RL_OK;
}

int analysis_journal_sync(analysis *a, long *nbytes)
{
  if (!a || !a->jfp) return rl_error(RL_ESTATE, "analysis_journal_sync: the analysis has no journal");
  int st = journal_ok(a);
  if (st) return st;
  errno = 0;
  if (fflush(a->jfp) || fsync(fileno(a->jfp))) {
    a->jbad = 1;
    return rl_error(RL_EINVAL, "%s: cannot write the analysis journal: %s", a->jpath,
                    errno ? strerror(errno) : "write error");
  }
  if (nbytes) *nbytes = a->jbytes;
  return RL_OK;
}

/* Read k bytes at the journal's current position: RL_OK, or a message naming what was cut. */
static int read_exact(FILE *f, void *buf, size_t k, const char *path, long at)
{
  errno = 0;
  if (fread(buf, 1, k, f) == k) return RL_OK;
  return rl_error(RL_EINVAL, "%s: cannot read %zu bytes at byte %ld: %s", path, k, at,
                  ferror(f) && errno ? strerror(errno) : "the file ends there");
}

int analysis_replay(analysis *a, const char *path, long nbytes)
{
  if (!a || !path) return rl_error(RL_EINVAL, "analysis_replay: NULL argument");
  if (a->seq > 0 || a->jfp || a->replayed)
    return rl_error(RL_ESTATE, "%s: a journal is replayed into a fresh analysis, before its journal is set", path);
  FILE *f = fopen(path, "rb");
  if (!f) return rl_error(RL_EINVAL, "cannot open the analysis journal %s: %s", path, strerror(errno));
  struct stat sb;
  int st = RL_OK;
  jheader want, got;
  memset(&got, 0, sizeof got);
  header_of(a, &want);
  unsigned char hbuf[JOURNAL_HEADER_MAX];
  char magic[8] = "";
  if (fstat(fileno(f), &sb) || !S_ISREG(sb.st_mode))
    st = rl_error(RL_EINVAL, "%s: not a regular file", path);
  else if (fread(magic, 1, 8, f) != 8 || memcmp(magic, JOURNAL_MAGIC, 8))
    st = rl_error(RL_EINVAL, "%s is not a rotleap analysis journal (no '%s' at its start)", path, JOURNAL_MAGIC);
  else if (rewind(f), (st = read_exact(f, hbuf, want.bytes, path, 0)))
    ;
  else if (header_io(&got, hbuf, 0), (st = header_check(&got, &want, path)))
    ;
  else if ((long)sb.st_size < nbytes)
    st = rl_error(RL_EINVAL, "%s holds %ld bytes, fewer than the %ld the checkpoint counts: it was cut short or "
                  "replaced", path, (long)sb.st_size, nbytes);
  else if (nbytes < (long)want.bytes)
    st = rl_error(RL_EINVAL, "%s: the checkpoint counts %ld bytes of it, fewer than its %u-byte header", path, nbytes,
                  want.bytes);
  long at = (long)want.bytes;
  while (!st && at < nbytes) {
    unsigned char head[RECORD_HEAD];
    uint32_t tag, len;
    int64_t seq;
    if (nbytes - at < RECORD_HEAD) {
      st = rl_error(RL_EINVAL, "%s: byte %ld, where the checkpoint's part of it ends, is not at a record boundary "
                    "(a record starts at byte %ld)", path, nbytes, at);
      break;
    }
    if ((st = read_exact(f, head, sizeof head, path, at))) break;
    memcpy(&tag, head, 4);
    memcpy(&len, head + 4, 4);
    memcpy(&seq, head + 8, 8);
    const size_t want_len = tag == TAG_STEP ? step_bytes(a) : tag == TAG_SAMPLE ? sample_bytes(a) : 0;
    if (!want_len || len != want_len || seq != a->seq) {
      st = rl_error(RL_EINVAL, "%s: the record at byte %ld is damaged or of another run (tag %08x, %u bytes, number "
                    "%" PRId64 "; expected record number %ld%s)", path, at, tag, len, seq, a->seq,
                    tag == TAG_SAMPLE ? " of the sample size this run writes" : "");
      break;
    }
    if (nbytes - at - RECORD_HEAD < (long)len) {
      st = rl_error(RL_EINVAL, "%s: byte %ld, where the checkpoint's part of it ends, is not at a record boundary "
                    "(the record at byte %ld ends at byte %ld)", path, nbytes, at, at + RECORD_HEAD + (long)len);
      break;
    }
    if ((st = read_exact(f, a->rec, len, path, at + RECORD_HEAD))) break;
    a->seq++;
    st = tag == TAG_STEP ? consume_step(a, a->rec) : consume_sample(a, a->rec);
    if (st) st = rl_error_wrap(st, "%s: the record at byte %ld cannot be replayed", path, at);
    at += RECORD_HEAD + (long)len;
  }
  fclose(f);
  if (!st) {
    a->replayed = 1;
    a->jbytes = nbytes;
  }
  return st;
}

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
               "lag bound %d: analysis.c)%s\n", stored, a->samples, lag, RL_TCF_MEMORY / (1024.0 * 1024.0),
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
