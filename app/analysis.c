/* rotleap run's analysis: a thin layer over include/rotleap/observables.h.
 *
 * Every input is a record: analysis_step and analysis_sample turn what they read (the step's
 * report, the configuration) into one, append it to the journal when there is one, and consume
 * it; analysis_replay consumes the records of a journal.  So the accumulators of a continuation
 * that replays the journal are those of the uninterrupted run, bit for bit.  The journal's
 * format is in docs/observables.md ("The analysis journal"). */
#include "analysis.h"
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
