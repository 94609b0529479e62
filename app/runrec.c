/* The run record of a checkpoint (runrec.h). */
#include "runrec.h"
#include "quantity.h"

#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void running_add(running *r, double x)
{
  r->n++;
  double d = x - r->mean;
  r->mean += d / r->n;
  r->m2 += d * (x - r->mean);
}
double running_sd(const running *r) { return r->n > 1 ? sqrt(r->m2 / (r->n - 1)) : 0.0; }

#define MAGIC5 "rotleap-run-5"

/* ------------------------------------------------------------------------------ writing */

typedef struct { unsigned char *p; size_t n, cap; int bad; } wbuf;

static void put(wbuf *b, const void *x, size_t n)
{
  if (b->bad) return;
  if (b->n + n > b->cap) {
    size_t cap = b->cap ? b->cap : 1024;
    while (cap < b->n + n) cap *= 2;
    unsigned char *p = realloc(b->p, cap);
    if (!p) { b->bad = 1; return; }
    b->p = p;
    b->cap = cap;
  }
  memcpy(b->p + b->n, x, n);
  b->n += n;
}
static void put_u64(wbuf *b, uint64_t x)
{
  unsigned char c[8];
  for (int k = 0; k < 8; k++) c[k] = (unsigned char)(x >> (8 * k));
  put(b, c, 8);
}
static void put_i64(wbuf *b, int64_t x) { put_u64(b, (uint64_t)x); }
static void put_f64(wbuf *b, double x)
{
  uint64_t u;
  memcpy(&u, &x, 8);
  put_u64(b, u);
}
static void put_running(wbuf *b, const running *r)
{
  put_i64(b, r->n);
  put_f64(b, r->mean);
  put_f64(b, r->m2);
}
/* A section: its tag and a length patched in by end_section. */
static size_t begin_section(wbuf *b, const char tag[4])
{
  put(b, tag, 4);
  const size_t at = b->n;
  put_u64(b, 0);
  return at;
}
static void end_section(wbuf *b, size_t at)
{
  if (b->bad) return;
  const uint64_t len = b->n - at - 8;
  for (int k = 0; k < 8; k++) b->p[at + k] = (unsigned char)(len >> (8 * k));
}

static void put_watch(wbuf *b, const rl_watch *w)
{
  const double f[] = {w->prevE, w->T1, w->T2, w->alt_sum, w->alt_at_max, w->t0, w->c0, w->max_rate, w->U0,
                      w->rate_sum, w->rate_sum2, w->T_sum};
  const int64_t i[] = {w->alt_n, w->open, w->step0, w->nev, w->relax, w->nwin, w->T_n};
  for (size_t k = 0; k < sizeof f / sizeof f[0]; k++) put_f64(b, f[k]);
  for (size_t k = 0; k < sizeof i / sizeof i[0]; k++) put_i64(b, i[k]);
}

int runrec_encode(const run_record *r, unsigned char **out, size_t *size)
{
  wbuf b = {0};
  char magic[16] = MAGIC5;
  put(&b, magic, sizeof magic);
  size_t at = begin_section(&b, "BOOK");
  put_f64(&b, r->thermo_work);
  const running *acc[6] = {&r->E, &r->U, &r->T, &r->Tt, &r->Tr, &r->P};
  for (int k = 0; k < 6; k++) put_running(&b, acc[k]);
  put_i64(&b, r->done);
  put_i64(&b, r->thermostat);
  put_u64(&b, r->seed);
  end_section(&b, at);
  if (r->rng_size) {
    at = begin_section(&b, "RNG ");
    put(&b, r->rng, r->rng_size);
    end_section(&b, at);
  }
  if (r->list_count > 0) {
    at = begin_section(&b, "LIST");
    put_i64(&b, r->list_count);
    for (long i = 0; i < r->list_count; i++)
      for (int c = 0; c < 3; c++) put_f64(&b, r->list[i][c]);
    end_section(&b, at);
  }
  if (r->list_count > 0 && r->has_list_box) {
    at = begin_section(&b, "LBOX");
    for (int c = 0; c < 3; c++) put_f64(&b, r->list_box[c]);
    end_section(&b, at);
  }
  at = begin_section(&b, "PHYS");
  put(&b, r->physics ? r->physics : "", r->physics ? r->physics_len : 0);
  end_section(&b, at);
  at = begin_section(&b, "MARK");
  put_i64(&b, OUT_NSTREAMS);
  for (int k = 0; k < OUT_NSTREAMS; k++) {
    put_u64(&b, r->marks[k].where);
    put_i64(&b, r->marks[k].len);
    put_i64(&b, r->marks[k].skip);
    put_u64(&b, r->marks[k].hash);
  }
  end_section(&b, at);
  if (r->has_watch) {
    at = begin_section(&b, "WTCH");
    put_watch(&b, &r->watch);
    end_section(&b, at);
  }
  if (r->relax_step >= 0) {
    at = begin_section(&b, "RLAX");
    put_i64(&b, r->relax_step);
    put_f64(&b, r->relax_time);
    end_section(&b, at);
  }
  if (r->nops > 0) {
    at = begin_section(&b, "OPST");
    put_i64(&b, r->nops);
    for (int k = 0; k < r->nops; k++) {
      put_i64(&b, (int64_t)r->ops[k].name_len);
      put(&b, r->ops[k].name, r->ops[k].name_len);
      put_f64(&b, r->ops[k].work);
      put_i64(&b, (int64_t)r->ops[k].size);
      if (r->ops[k].size) put(&b, r->ops[k].bytes, r->ops[k].size);
    }
    end_section(&b, at);
  }
  if (b.bad) {
    free(b.p);
    return rl_error(RL_ENOMEM, "out of memory for the checkpoint's run record");
  }
  *out = b.p;
  *size = b.n;
  return RL_OK;
}

/* ------------------------------------------------------------------------------ reading */

typedef struct { const unsigned char *p; size_t n, at; int bad; } rbuf;

static uint64_t get_u64(rbuf *b)
{
  if (b->bad || b->n - b->at < 8) { b->bad = 1; return 0; }
  uint64_t x = 0;
  for (int k = 0; k < 8; k++) x |= (uint64_t)b->p[b->at + k] << (8 * k);
  b->at += 8;
  return x;
}
static int64_t get_i64(rbuf *b) { return (int64_t)get_u64(b); }
static double get_f64(rbuf *b)
{
  uint64_t u = get_u64(b);
  double x;
  memcpy(&x, &u, 8);
  return x;
}
static running get_running(rbuf *b)
{
  running r;
  r.n = (long)get_i64(b);
  r.mean = get_f64(b);
  r.m2 = get_f64(b);
  return r;
}

static int bad_field(const char *path, const char *field, const char *why)
{
  return rl_error(RL_EINVAL, "%s: the run record's %s %s: the checkpoint is damaged or was not written by rotleap run",
                  path, field, why);
}

static int check_running(const running *r, const char *path, const char *name)
{
  if (r->n < 0) return bad_field(path, name, "has a negative count");
  if (!isfinite(r->mean) || !isfinite(r->m2) || r->m2 < 0) return bad_field(path, name, "is not finite (or has a negative variance)");
  return RL_OK;
}

static int get_watch(rbuf *b, rl_watch *w)
{
  double *f[] = {&w->prevE, &w->T1, &w->T2, &w->alt_sum, &w->alt_at_max, &w->t0, &w->c0, &w->max_rate, &w->U0,
                 &w->rate_sum, &w->rate_sum2, &w->T_sum};
  for (size_t k = 0; k < sizeof f / sizeof f[0]; k++) *f[k] = get_f64(b);
  w->alt_n = (long)get_i64(b);
  w->open = (int)get_i64(b);
  w->step0 = (long)get_i64(b);
  w->nev = (long)get_i64(b);
  w->relax = (int)get_i64(b);
  w->nwin = (long)get_i64(b);
  w->T_n = (long)get_i64(b);
  /* prevE, T1, T2 are NaN before the first steps; the rest must be finite */
  const double *finite[] = {&w->alt_sum, &w->alt_at_max, &w->t0, &w->c0, &w->max_rate, &w->U0, &w->rate_sum, &w->rate_sum2, &w->T_sum};
  for (size_t k = 0; k < sizeof finite / sizeof finite[0]; k++)
    if (!isfinite(*finite[k])) return 1;
  return w->alt_n < 0 || w->nev < 0 || w->nwin < 0 || w->T_n < 0 || (w->open != 0 && w->open != 1) || (w->relax != 0 && w->relax != 1);
}

/* Versions 1-4: the struct older rotleap wrote (x86-64 layout), read field by field. */
static int decode_old(const unsigned char *p, size_t size, int version, const char *path, int nbodies, run_record *r)
{
  rbuf b = {p, size, 16, 0};
  r->thermo_work = get_f64(&b);
  running *acc[6] = {&r->E, &r->U, &r->T, &r->Tt, &r->Tr, &r->P};
  for (int k = 0; k < 6; k++) *acc[k] = get_running(&b);
  r->done = (long)get_i64(&b);
  r->rng_size = (size_t)get_u64(&b);
  r->thermostat = -1;
  if (version >= 2) {
    r->thermostat = (long)get_i64(&b);
    r->seed = (unsigned long)get_u64(&b);
  }
  if (version >= 4) { get_i64(&b); get_u64(&b); } /* the last thermo row: superseded by the marks */
  if (b.bad) return bad_field(path, "header", "is cut short");
  if (r->rng_size > size - b.at) return bad_field(path, "random state", "is longer than the record");
  r->rng = p + b.at;
  b.at += r->rng_size;
  if (version >= 3 && b.at < size) {
    const long count = (long)get_i64(&b);
    if (b.bad || (count != 0 && count != nbodies) || (size - b.at) != (size_t)count * 24)
      return bad_field(path, "neighbour-list origin", "does not match the system's bodies");
    r->list_count = count;
    r->list = count ? (const double(*)[3])(const void *)(p + b.at) : NULL;
  }
  return RL_OK;
}

int runrec_decode(const void *blob, size_t size, int nbodies, const char *path, run_record *r)
{
  memset(r, 0, sizeof *r);
  r->relax_step = -1;
  const unsigned char *p = blob;
  static const char *const old[4] = {"rotleap-run-1", "rotleap-run-2", "rotleap-run-3", "rotleap-run-4"};
  if (!p || size < 16) return bad_field(path, "magic", "is missing");
  for (int v = 0; v < 4; v++)
    if (!memcmp(p, old[v], strlen(old[v]) + 1)) {
      r->version = v + 1;
      int st = decode_old(p, size, v + 1, path, nbodies, r);
      if (!st) st = check_running(&r->E, path, "energy average");
      return st;
    }
  if (memcmp(p, MAGIC5, sizeof MAGIC5)) return bad_field(path, "magic", "is not one rotleap writes");
  r->version = 5;
  rbuf b = {p, size, 16, 0};
  int seen_book = 0, seen_mark = 0;
  while (b.at < size) {
    if (size - b.at < 12) return bad_field(path, "section header", "is cut short");
    char tag[5] = {0};
    memcpy(tag, p + b.at, 4);
    b.at += 4;
    const uint64_t len = get_u64(&b);
    if (len > size - b.at) return bad_field(path, tag, "section is longer than the record");
    rbuf s = {p + b.at, (size_t)len, 0, 0};
    if (!strcmp(tag, "BOOK")) {
      r->thermo_work = get_f64(&s);
      running *acc[6] = {&r->E, &r->U, &r->T, &r->Tt, &r->Tr, &r->P};
      static const char *const names[6] = {"energy average", "potential average", "temperature average",
                                           "translational temperature average", "rotational temperature average",
                                           "pressure average"};
      for (int k = 0; k < 6; k++) *acc[k] = get_running(&s);
      r->done = (long)get_i64(&s);
      r->thermostat = (long)get_i64(&s);
      r->seed = (unsigned long)get_u64(&s);
      if (s.bad || s.at != s.n) return bad_field(path, "BOOK", "section has the wrong size");
      if (!isfinite(r->thermo_work)) return bad_field(path, "thermostat account", "is not finite");
      for (int k = 0; k < 6; k++) {
        const int st = check_running(acc[k], path, names[k]);
        if (st) return st;
      }
      if (r->done < 0) return bad_field(path, "step count", "is negative");
      if (r->thermostat < 0 || r->thermostat > RL_THERMO_LANGEVIN_DOT_OBABO) return bad_field(path, "thermostat", "is not one rotleap has");
      seen_book = 1;
    } else if (!strcmp(tag, "RNG ")) {
      r->rng = s.p;
      r->rng_size = s.n;
    } else if (!strcmp(tag, "LIST")) {
      const long count = (long)get_i64(&s);
      if (s.bad || count != nbodies || s.n - s.at != (size_t)count * 24)
        return bad_field(path, "neighbour-list origin", "does not match the system's bodies");
      r->list_count = count;
      r->list = (const double(*)[3])(const void *)(s.p + s.at);
      for (long i = 0; i < count; i++)
        for (int c = 0; c < 3; c++) {
          double x;
          memcpy(&x, s.p + s.at + 8 * (3 * i + c), 8);
          if (!isfinite(x)) return bad_field(path, "neighbour-list origin", "is not finite");
        }
    } else if (!strcmp(tag, "LBOX")) {
      for (int c = 0; c < 3; c++) r->list_box[c] = get_f64(&s);
      if (s.bad || s.at != s.n || !(r->list_box[0] > 0.0 && r->list_box[1] > 0.0 && r->list_box[2] > 0.0) ||
          !isfinite(r->list_box[0] + r->list_box[1] + r->list_box[2]))
        return bad_field(path, "neighbour-list box", "is out of range");
      r->has_list_box = 1;
    } else if (!strcmp(tag, "PHYS")) {
      for (size_t i = 0; i < s.n; i++)
        if (!s.p[i]) return bad_field(path, "settings", "contain a NUL byte");
      r->physics = (const char *)s.p;
      r->physics_len = s.n;
    } else if (!strcmp(tag, "MARK")) {
      const int64_t n = get_i64(&s);
      if (n != OUT_NSTREAMS) return bad_field(path, "output marks", "have another number of streams");
      for (int k = 0; k < OUT_NSTREAMS; k++) {
        out_mark *m = &r->marks[k];
        m->where = (uint32_t)get_u64(&s);
        m->len = get_i64(&s);
        m->skip = get_i64(&s);
        m->hash = get_u64(&s);
        if (m->where > MARK_FINAL || m->len < 0 || m->skip < 0 || m->skip > m->len || (m->where == MARK_NONE && m->len))
          return bad_field(path, "output marks", "are out of range");
      }
      if (s.bad || s.at != s.n) return bad_field(path, "MARK", "section has the wrong size");
      seen_mark = 1;
    } else if (!strcmp(tag, "WTCH")) {
      if (get_watch(&s, &r->watch) || s.bad || s.at != s.n) return bad_field(path, "watch", "is out of range");
      r->has_watch = 1;
    } else if (!strcmp(tag, "RLAX")) {
      r->relax_step = (long)get_i64(&s);
      r->relax_time = get_f64(&s);
      if (s.bad || s.at != s.n || r->relax_step < 0 || !isfinite(r->relax_time))
        return bad_field(path, "relaxation step", "is out of range");
    } else if (!strcmp(tag, "OPST")) {
      const int64_t n = get_i64(&s);
      if (s.bad || n < 1 || n > RUNREC_MAX_OPS) return bad_field(path, "operator states", "have a count out of range");
      r->nops = (int)n;
      for (int k = 0; k < r->nops; k++) {
        const uint64_t nl = get_u64(&s);
        if (s.bad || nl == 0 || nl > 64 || nl > s.n - s.at) return bad_field(path, "operator states", "have a bad name");
        r->ops[k].name = (const char *)s.p + s.at;
        r->ops[k].name_len = (size_t)nl;
        s.at += (size_t)nl;
        r->ops[k].work = get_f64(&s);
        if (!isfinite(r->ops[k].work)) return bad_field(path, "operator states", "have an account that is not finite");
        const uint64_t size = get_u64(&s);
        if (s.bad || size > s.n - s.at) return bad_field(path, "operator states", "are cut short");
        r->ops[k].bytes = s.p + s.at;
        r->ops[k].size = (size_t)size;
        s.at += (size_t)size;
      }
      if (s.at != s.n) return bad_field(path, "OPST", "section has the wrong size");
    }
    /* an unknown tag: a section of a later rotleap, skipped */
    b.at += (size_t)len;
  }
  if (!seen_book) return bad_field(path, "BOOK", "section is missing");
  if (!seen_mark) return bad_field(path, "MARK", "section is missing");
  return RL_OK;
}

/* ------------------------------------------------------------- what a checkpoint holds */

/* The shortest decimal form of x that reads back as x. */
static const char *exact(char buf[40], double x)
{
  for (int p = 15; p <= 17; p++) {
    snprintf(buf, 40, "%.*g", p, x);
    if (strtod(buf, NULL) == x || isnan(x)) break;
  }
  return buf;
}

/* The settings that define the simulation a checkpoint continues, one "key = value" line each
 * (values in the system's units): a continuation whose deck gives other values runs another
 * simulation, and under the same output.prefix its averages and files would mix the two.  Not
 * here: what changes only the speed or the round-off (threads, kernel, precision, skin), the
 * bookkeeping (steps, thermo, checkpoints, progress) and run.seed (another seed continues with a
 * new random stream, and says so). */
char *runrec_physics(const rl_deck *d)
{
  size_t cap = 4096, n = 0;
  char *s = malloc(cap);
  if (!s) return NULL;
  s[0] = '\0';
#define ADD(...)                                                                                                   \
  do {                                                                                                             \
    int w_ = snprintf(s + n, cap - n, __VA_ARGS__);                                                                \
    if (w_ < 0) break;                                                                                             \
    if ((size_t)w_ >= cap - n) {                                                                                   \
      char *t_ = realloc(s, cap = 2 * cap + (size_t)w_);                                                           \
      if (!t_) { free(s); return NULL; }                                                                           \
      s = t_;                                                                                                      \
      snprintf(s + n, cap - n, __VA_ARGS__);                                                                       \
    }                                                                                                              \
    n += (size_t)w_;                                                                                               \
  } while (0)
  char r1[40], r2[40], r3[40], r4[40], r5[40], r6[40], r7[40];
  const char *L = rl_dim_unit(Q_LENGTH, d->units), *tu = rl_dim_unit(Q_TIME, d->units),
             *Tu = rl_dim_unit(Q_TEMPERATURE, d->units);
  static const char *const scheme[] = {"site", "molecule"}, *const lj[] = {"plain", "shifted", "shifted-force", "switched"},
                           *const dip[] = {"rf", "sf"};
  ADD("system.model = %s\n", d->model->name);
  for (int sp = 0; sp < d->nspecies; sp++) { /* the deck's molecules among the species */
    const rl_deck_molecule *um = rl_deck_user_model(d->species[sp].model);
    for (int a = 0; um && a < um->nsites; a++) { /* the deck's molecule: every site (a key each), in the system's units */
      char q[10][40];
      ADD("molecule.%s.site.%s = %s %s %s mass %s charge %s sigma %s epsilon %s dipole %s %s %s quadrupole %s\n", um->name,
          um->site_names[a], exact(q[0], um->pos[a][0]), exact(q[1], um->pos[a][1]), exact(q[2], um->pos[a][2]),
          exact(q[3], um->mass[a]), exact(q[4], um->charge[a]), exact(q[5], um->sigma[a]), exact(q[6], um->epsilon[a]),
          exact(q[7], um->dipole[a][0]), exact(q[8], um->dipole[a][1]), exact(q[9], um->dipole[a][2]), exact(r1, um->quadrupole[a]));
    }
    if (um)
      ADD("molecule.%s = %s%s, inertia %s %s %s, symmetrize %s\n", um->name, um->model.units == RL_UNITS_LJ ? "lj" : "real",
          um->model.geometric_mixing ? ", geometric mixing" : "", exact(r2, um->inertia[0]), exact(r3, um->inertia[1]),
          exact(r4, um->inertia[2]), um->symmetrize ? "yes" : "no");
  }
  for (int k = 0; k < d->model->nparams; k++)
    ADD("model.%s = %s %s\n", d->model->param_names[k], exact(r1, d->params[k]), d->model->param_units[k] ? d->model->param_units[k] : "");
  ADD("system.count = %d\n", d->count);
  if (d->nspecies > 1) {
    ADD("system.species =");
    for (int k = 0; k < d->nspecies; k++) ADD(" %s:%d", d->species[k].model->name, d->species[k].count);
    ADD("\n");
  }
  if (d->mixing != RL_DECK_MIXING_MODEL) ADD("interactions.mixing = %s\n", d->mixing == RL_DECK_MIXING_GEOMETRIC ? "geometric" : "lorentz-berthelot");
  for (int i = 0; i < d->npairs; i++)
    ADD("interactions.pairs = %s:%d %s:%d sigma %s epsilon %s\n", d->species[d->pairs[i].species[0]].model->name, d->pairs[i].site[0],
        d->species[d->pairs[i].species[1]].model->name, d->pairs[i].site[1], exact(r1, d->pairs[i].sigma), exact(r2, d->pairs[i].epsilon));
  ADD("system.force_general = %s\n", d->force_general ? "yes" : "no");
  if (d->inertia_scale != 1.0) ADD("system.inertia_scale = %s\n", exact(r1, d->inertia_scale));
  ADD("interactions.cutoff = %s %s\n", exact(r2, d->ff.cutoff), L);
  ADD("interactions.scheme = %s\n", scheme[d->ff.scheme]);
  ADD("interactions.lj = %s\n", lj[d->ff.lj_truncation]);
  if (d->ff.lj_truncation == RL_LJ_SWITCHED) ADD("interactions.switch = %s %s\n", exact(r3, d->ff.r_switch), L);
  ADD("interactions.dispersion_correction = %s\n", d->ff.dispersion_correction ? "yes" : "no");
  if (d->coulomb == RL_DECK_COULOMB_RF) ADD("interactions.eps_rf = %s\n", exact(r4, d->ff.eps_rf));
  else { /* the Ewald choice as given (derived values follow from it and the box) */
    const rl_ewald_params *e = &d->ewald;
    ADD("interactions.coulomb = %s\n", d->coulomb == RL_DECK_COULOMB_PME ? "pme" : "ewald");
    ADD("interactions.ewald_tolerance = %s\n", exact(r4, e->tolerance));
    if (e->alpha > 0) ADD("interactions.ewald_alpha = %s %s\n", exact(r3, e->alpha), rl_dim_unit(Q_INVLENGTH, d->units));
    if (d->coulomb == RL_DECK_COULOMB_PME) {
      if (e->grid[0] > 0) ADD("interactions.pme_grid = %d %d %d\n", e->grid[0], e->grid[1], e->grid[2]);
      ADD("interactions.pme_order = %d\n", e->order);
    } else {
      if (e->kmax[0] > 0) ADD("interactions.ewald_kmax = %d %d %d\n", e->kmax[0], e->kmax[1], e->kmax[2]);
      if (e->kmax_sq > 0) ADD("interactions.ewald_kmax2 = %s\n", exact(r3, e->kmax_sq));
    }
    ADD("interactions.ewald_boundary = %s\n", isinf(e->eps_surface) ? "tinfoil" : exact(r3, e->eps_surface));
  }
  ADD("interactions.dipole = %s\n", dip[d->ff.dipole_method]);
  ADD("run.timestep = %s %s\n", exact(r5, d->timestep), tu);
  ADD("run.integrator = %s\n", rl_rot_method_name(d->method));
    static const char *const ensemble[] = {"nve", "nvt-isokinetic", "nvt-bussi", "nvt-langevin", "nvt-langevin-dot", "nvt-langevin-dot-obabo"};
  ADD("run.ensemble = %s\n", ensemble[d->thermostat]);
  if (d->thermostat != RL_THERMO_NONE) ADD("run.temperature = %s %s\n", exact(r6, d->thermostat_temperature), Tu);
  if (d->thermostat >= RL_THERMO_BUSSI) ADD("run.tau = %s %s\n", exact(r7, d->tau), tu);
  if (d->thermostat >= RL_THERMO_LANGEVIN_DOT) ADD("run.tau_rot = %s %s\n", exact(r7, d->tau_rot), tu);
  if (d->thermostat == RL_THERMO_BUSSI) ADD("run.thermostat_groups = %s\n", rl_thermo_groups_name(d->thermostat_groups));
  if (d->barostat) {
    char b1[40], b2[40], b3[40];
    ADD("run.barostat = %s\nrun.pressure = %s %s\nrun.barostat_interval = %ld\nrun.barostat_coupling = %s\n",
        d->barostat == 1 ? "mc" : "c-rescale", exact(b1, scene_pressure_out(d, d->pressure)), d->units == RL_UNITS_REAL ? "bar" : "reduced",
        d->baro_interval, d->baro_aniso == 1 ? "anisotropic" : d->baro_aniso == 2 ? "semiisotropic" : "isotropic");
    if (d->barostat == 2)
      ADD("run.tau_p = %s %s\nrun.compressibility = %s (system units)\n", exact(b2, d->tau_p), tu, exact(b3, d->compressibility));
  }
  ADD("output.energy_every = %ld\n", d->energy_every);
  ADD("output.trajectory_every = %ld\n", d->trajectory_every);
  ADD("output.sample_every = %ld\n", d->sample_every);
  ADD("output.rdf = %s\n", d->rdf);
#undef ADD
  return s;
}

/* Every operator's account and own state into r's OPST list (buffers opst[] the caller frees),
 * when one of them keeps a state (a barostat): none otherwise, as before. */
static int save_ops(rl_integrator *in, run_record *r, void **opst)
{
  int any = 0;
  for (int k = 0; k < rl_integrator_nops(in); k++) any |= rl_stepop_save(rl_integrator_op(in, k), NULL) > 0;
  for (int k = 0; any && k < rl_integrator_nops(in) && r->nops < RUNREC_MAX_OPS; k++) {
    const rl_stepop *op = rl_integrator_op(in, k);
    const size_t size = rl_stepop_save(op, NULL);
    if (size && !(opst[r->nops] = malloc(size))) return rl_error(RL_ENOMEM, "out of memory");
    if (size) rl_stepop_save(op, opst[r->nops]);
    r->ops[r->nops].name = op->type->name;
    r->ops[r->nops].name_len = strlen(op->type->name);
    r->ops[r->nops].bytes = opst[r->nops];
    r->ops[r->nops].size = size;
    r->ops[r->nops].work = op->work;
    r->nops++;
  }
  return RL_OK;
}

/* The checkpoint of sys at `step`, `time` with the run record r (the caller fills the version,
 * averages, done, thermostat, seed, physics, marks, watch and relaxation fields), completed here
 * from the integrator (thermostat account and random state, the operators' states) and the
 * force field (the neighbour list's origin). */
int runrec_write_checkpoint(const char *path, const rl_system *sys, const rl_forcefield *ff, rl_integrator *in,
                            run_record *r, long step, double time)
{
  r->thermo_work = rl_integrator_thermostat_work(in);
  r->rng = rl_integrator_rng_state(in);
  r->rng_size = rl_integrator_rng_size(in);
  int st = RL_OK;
  const int n = rl_system_count(sys);
  double(*origin)[3] = n > 0 ? malloc(sizeof *origin * (size_t)n) : NULL;
  if (n > 0 && !origin) st = rl_error(RL_ENOMEM, "out of memory");
  if (!st && origin && rl_forcefield_list_origin(ff, origin)) {
    r->list_count = n;
    r->list = (const double(*)[3])origin;
    double L[3]; /* the box of the build, when a barostat has changed the system's since */
    rl_system_box(sys, L);
    r->has_list_box = rl_forcefield_list_box(ff, r->list_box) && memcmp(L, r->list_box, sizeof L) != 0;
  }
  void *opst[RUNREC_MAX_OPS] = {NULL};
  if (!st) st = save_ops(in, r, opst);
  unsigned char *blob = NULL;
  size_t size = 0;
  if (!st) st = runrec_encode(r, &blob, &size);
  for (int k = 0; k < RUNREC_MAX_OPS; k++) free(opst[k]);
  if (!st) {
    rl_checkpoint_meta meta = {time, step, {0, 0, 0}, blob, size}; /* the box: the system's */
    st = rl_checkpoint_write(path, sys, &meta);
  }
  free(blob);
  free(origin);
  r->list = NULL;
  r->list_count = 0;
  r->has_list_box = 0;
  return st;
}

/* ------------------------------------------------------------------------- continuing */

static int is_output_key(const char *line) { return !strncmp(line, "output.", 7); }

int runrec_physics_diff(const char *old, size_t len, const char *now_text, int outputs_only, char *msg, size_t cap)
{
  int count = 0;
  size_t used = 0;
  msg[0] = '\0';
  const char *end = old + len;
  /* a line of `old` is "key = value\n" */
  for (const char *line = old; line < end;) {
    const char *nl = memchr(line, '\n', (size_t)(end - line));
    if (!nl) nl = end;
    const char *eq = memchr(line, '=', (size_t)(nl - line));
    if (eq && eq > line && is_output_key(line) == outputs_only) {
      const size_t klen = (size_t)(eq - line); /* "key " */
      const char *mine = NULL;
      for (const char *p = now_text; *p;) {
        const char *pn = strchr(p, '\n');
        if (!pn) pn = p + strlen(p);
        if ((size_t)(pn - p) > klen && !strncmp(p, line, klen) && p[klen] == '=') { mine = p; break; }
        p = *pn ? pn + 1 : pn;
      }
      const char *mv = mine ? mine + klen + 2 : "(not used)";
      const size_t mvlen = mine ? strcspn(mv, "\n") : strlen(mv);
      const char *ov = eq + 2 <= nl ? eq + 2 : nl;
      if (mvlen != (size_t)(nl - ov) || strncmp(mv, ov, mvlen)) {
        count++;
        const int w = snprintf(msg + used, cap - used, "%s%.*s: %.*s -> %.*s", count > 1 ? "; " : "", (int)(klen - 1),
                               line, (int)(nl - ov), ov, (int)mvlen, mv);
        if (w > 0 && (size_t)w < cap - used) used += (size_t)w;
      }
    }
    line = nl < end ? nl + 1 : end;
  }
  /* settings the checkpoint's run did not have (a thermostat's temperature after NVE, say) */
  for (const char *p = now_text; *p;) {
    const char *pn = strchr(p, '\n');
    if (!pn) pn = p + strlen(p);
    const char *eq = memchr(p, '=', (size_t)(pn - p));
    if (eq && is_output_key(p) == outputs_only) {
      const size_t klen = (size_t)(eq - p);
      int found = 0;
      for (const char *line = old; line < end && !found;) {
        const char *nl = memchr(line, '\n', (size_t)(end - line));
        if (!nl) nl = end;
        found = (size_t)(nl - line) > klen && !strncmp(line, p, klen) && line[klen] == '=';
        line = nl < end ? nl + 1 : end;
      }
      if (!found) {
        count++;
        const int w = snprintf(msg + used, cap - used, "%s%.*s: (not used) -> %.*s", count > 1 ? "; " : "",
                               (int)(klen - 1), p, (int)(pn - eq - 2), eq + 2);
        if (w > 0 && (size_t)w < cap - used) used += (size_t)w;
      }
    }
    p = *pn ? pn + 1 : pn;
  }
  return count;
}

/* The accounts and states of a checkpoint's OPST back into in's operators of the same names: all
 * of them when the checkpoint has the section (one without the state of an operator that keeps
 * one is not this run's); nothing when neither has one. */
static int load_ops(rl_integrator *in, const run_record *rec, const char *path)
{
  for (int k = 0; k < rl_integrator_nops(in); k++) {
    rl_stepop *op = rl_integrator_op(in, k);
    const size_t want = rl_stepop_save(op, NULL);
    if (!want && !rec->nops) continue;
    int found = -1;
    for (int q = 0; q < rec->nops && found < 0; q++)
      if (rec->ops[q].name_len == strlen(op->type->name) && !memcmp(rec->ops[q].name, op->type->name, rec->ops[q].name_len)) found = q;
    if (found < 0) return rl_error(RL_EINVAL, "%s holds no state of the %s: it was written by a run without it", path, op->type->label);
    const int st = rl_stepop_load(op, rec->ops[found].bytes, rec->ops[found].size);
    if (st) return rl_error_wrap(st, "%s", path);
    op->work = rec->ops[found].work;
  }
  return RL_OK;
}

int runrec_restore_list(const run_record *rec, scene *s)
{
  const int n = rl_system_count(s->sys);
  if (rec->list_count != n || n <= 0) return RL_OK;
  double(*r0)[3] = malloc(sizeof *r0 * (size_t)n);
  if (!r0) return rl_error(RL_ENOMEM, "out of memory");
  memcpy(r0, rec->list, sizeof *r0 * (size_t)n);
  int st = rl_forcefield_set_list_origin(s->ff, (const double(*)[3])r0);
  if (!st && rec->has_list_box) st = rl_forcefield_set_list_box(s->ff, rec->list_box); /* kept through a barostat's moves */
  free(r0);
  return st;
}

int runrec_restore(const run_record *rec, scene *s, rl_integrator *in, unsigned long seed, const char *path,
                   char *note, size_t cap)
{
  note[0] = '\0';
  if (rec->rng_size != rl_integrator_rng_size(in))
    return rl_error(RL_EINVAL, "%s was written with another thermostat (random state of %zu bytes, this run needs %zu)",
                    path, rec->rng_size, rl_integrator_rng_size(in));
  int st = runrec_restore_list(rec, s);
  if (!st) st = rl_integrator_resume(in, s->step0, s->t0);
  if (st) return st;
  const int reseed = rec->version >= 2 && rec->rng_size && rec->seed != seed;
  if (reseed)
    snprintf(note, cap, "run.seed = %lu differs from the seed %lu of the run that wrote %s: the %s thermostat continues "
             "with a new random stream from seed %lu (not bit for bit with a continuation that keeps seed %lu)", seed,
             rec->seed, path, rl_thermostat_name((rl_thermostat)rec->thermostat), seed, rec->seed);
  else if (rec->rng_size) memcpy(rl_integrator_rng_state(in), rec->rng, rec->rng_size);
  rl_integrator_set_thermostat_work(in, rec->thermo_work);
  return load_ops(in, rec, path);
}

int runrec_other_simulation(const run_record *rec, const char *physics, rl_thermostat thermostat, char *diff, size_t cap)
{
  diff[0] = '\0';
  if (rec->version >= 5) return runrec_physics_diff(rec->physics, rec->physics_len, physics, 0, diff, cap) > 0;
  if (rec->version >= 2 ? rec->thermostat == (long)thermostat : (rec->rng_size > 0) == (thermostat >= RL_THERMO_BUSSI))
    return 0;
  snprintf(diff, cap, "run.ensemble: %s -> %s",
           rec->thermostat >= 0 ? rl_thermostat_name((rl_thermostat)rec->thermostat) : "?", rl_thermostat_name(thermostat));
  return 1;
}
