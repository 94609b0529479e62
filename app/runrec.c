/* The run record of a checkpoint (runrec.h). */
#include "runrec.h"

#include <math.h>
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
      if (r->thermostat < 0 || r->thermostat > 3) return bad_field(path, "thermostat", "is not one rotleap has");
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
    }
    /* an unknown tag: a section of a later rotleap, skipped */
    b.at += (size_t)len;
  }
  if (!seen_book) return bad_field(path, "BOOK", "section is missing");
  if (!seen_mark) return bad_field(path, "MARK", "section is missing");
  return RL_OK;
}
