/* Checkpoints: versioned, CRC-32-checked, little-endian binary, written atomically.
 *
 *   offset  size  field
 *   0       8     magic "RLCHKPT\0"
 *   8       4     format version (u32)                 -- this fixed 24-byte header and the
 *   12      4     reserved, 0                             CRC trailer never change between
 *   16      8     payload length P (u64)                  versions
 *   24      P     payload (below)
 *   24+P    4     CRC-32 (zlib polynomial) of bytes [0, 24+P)
 *
 * Payload, version 1: u32 units, i32 removed_dof, f64 time, i64 step, f64 box[3], u32 nspecies,
 * per species {u32 name length, name bytes, i32 kind, f64 mass, f64 J[3], i32 nsites,
 * f64 sites[nsites][3], i32 count}, u32 n, nrot, nmat, naxis, f64 r[n][3], v[n][3], l[nrot][3],
 * A[nmat][9], rho[naxis][3], u64 blob size, blob bytes. */
#include "io_internal.h"
#include "rotleap/error.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <stdint.h>
#include <unistd.h>

static const unsigned char MAGIC[8] = {'R', 'L', 'C', 'H', 'K', 'P', 'T', 0};
#define HDR 24

typedef struct {
  unsigned char *p;
  size_t n, cap;
  int oom;
} wbuf;

static void put(wbuf *b, const void *d, size_t n)
{
  if (b->oom) return;
  if (b->n + n > b->cap) {
    size_t c = b->cap ? b->cap : 4096;
    while (c < b->n + n) c *= 2;
    unsigned char *q = realloc(b->p, c);
    if (!q) { b->oom = 1; return; }
    b->p = q;
    b->cap = c;
  }
  if (n) memcpy(b->p + b->n, d, n);
  b->n += n;
}
static void put_u32(wbuf *b, uint32_t v) { unsigned char t[4]; rl_le32(t, v); put(b, t, 4); }
static void put_u64(wbuf *b, uint64_t v) { unsigned char t[8]; rl_le64(t, v); put(b, t, 8); }
static void put_f64s(wbuf *b, const double *x, size_t n)
{
  for (size_t i = 0; i < n; i++) {
    uint64_t u;
    memcpy(&u, &x[i], 8);
    put_u64(b, u);
  }
}

int rl_checkpoint_write(const char *path, const rl_system *sys, const rl_checkpoint_meta *meta)
{
  if (!path || !sys || !meta) return rl_error(RL_EINVAL, "rl_checkpoint_write: NULL argument");
  if (meta->blob_size && !meta->blob) return rl_error(RL_EINVAL, "%s: blob_size %zu with a NULL blob", path, meta->blob_size);
  wbuf b = {0};
  put(&b, MAGIC, 8);
  put_u32(&b, RL_CHECKPOINT_VERSION);
  put_u32(&b, 0);
  put_u64(&b, 0); /* payload length, filled below */
  put_u32(&b, (uint32_t)sys->units);
  put_u32(&b, (uint32_t)sys->removed_dof);
  put_f64s(&b, &meta->time, 1);
  put_u64(&b, (uint64_t)(int64_t)meta->step);
  double box[3];
  rl_system_box(sys, box); /* the system's box (meta->box is what a read found) */
  put_f64s(&b, box, 3);
  put_u32(&b, (uint32_t)sys->nspecies);
  for (int k = 0; k < sys->nspecies; k++) {
    const rl_species *sp = &sys->sp[k];
    size_t nl = strlen(sp->name);
    put_u32(&b, (uint32_t)nl);
    put(&b, sp->name, nl);
    put_u32(&b, (uint32_t)sp->kind);
    put_f64s(&b, &sp->mass, 1);
    put_f64s(&b, sp->J, 3);
    put_u32(&b, (uint32_t)sp->nsites);
    put_f64s(&b, sp->sites, 3 * (size_t)sp->nsites);
    put_u32(&b, (uint32_t)sp->count);
  }
  put_u32(&b, (uint32_t)sys->n);
  put_u32(&b, (uint32_t)sys->nrot);
  put_u32(&b, (uint32_t)sys->nmat);
  put_u32(&b, (uint32_t)sys->naxis);
  put_f64s(&b, &sys->r[0][0], 3 * (size_t)sys->n);
  put_f64s(&b, &sys->v[0][0], 3 * (size_t)sys->n);
  if (sys->nrot) put_f64s(&b, &sys->l[0][0], 3 * (size_t)sys->nrot);
  if (sys->nmat) put_f64s(&b, &sys->A[0][0], 9 * (size_t)sys->nmat);
  if (sys->naxis) put_f64s(&b, &sys->rho[0][0], 3 * (size_t)sys->naxis);
  put_u64(&b, (uint64_t)meta->blob_size);
  put(&b, meta->blob, meta->blob_size);
  if (b.oom) { free(b.p); return rl_error(RL_ENOMEM, "%s: out of memory building the checkpoint", path); }
  rl_le64(b.p + 16, (uint64_t)(b.n - HDR));
  put_u32(&b, rl_crc32(0, b.p, b.n));
  if (b.oom) { free(b.p); return rl_error(RL_ENOMEM, "%s: out of memory building the checkpoint", path); }

  rl_atomic_file af;
  int st = rl_atomic_open(&af, path);
  if (st) { free(b.p); return st; }
  const int short_write = fwrite(b.p, 1, b.n, af.fp) != b.n;
  free(b.p);
  return short_write ? rl_atomic_fail(&af) : rl_atomic_commit(&af);
}

/* ---------------------------------------------------------------------------- reading */

typedef struct {
  const unsigned char *p;
  size_t n, at;
  const char *path;
  int bad;
} rbuf;

static const unsigned char *take(rbuf *b, size_t n, const char *what)
{
  if (b->bad) return NULL;
  if (n > b->n - b->at) {
    b->bad = rl_error(RL_EINVAL, "%s: checkpoint payload ends inside %s (offset %zu)", b->path, what, b->at);
    return NULL;
  }
  const unsigned char *q = b->p + b->at;
  b->at += n;
  return q;
}
static uint32_t get_u32(rbuf *b, const char *what) { const unsigned char *q = take(b, 4, what); return q ? rl_get32(q) : 0; }
static uint64_t get_u64(rbuf *b, const char *what) { const unsigned char *q = take(b, 8, what); return q ? rl_get64(q) : 0; }
static void get_f64s(rbuf *b, double *x, size_t n, const char *what)
{
  if (n > (b->n - b->at) / 8 + 1) { take(b, b->n + 1, what); return; }
  for (size_t i = 0; i < n; i++) {
    uint64_t u = get_u64(b, what);
    memcpy(&x[i], &u, 8);
  }
}

typedef struct {
  char name[64];
  int kind, nsites, count;
  double mass, J[3];
  double *sites;
} ck_species;

typedef struct {
  unsigned char *file;
  int units, removed_dof, nspecies, n, nrot, nmat, naxis;
  double time, box[3];
  long step;
  ck_species *sp;
  double *r, *v, *l, *A, *rho;
  size_t blob_size;
  const unsigned char *blob;
} ck_data;

static void ck_free(ck_data *c)
{
  if (c->sp)
    for (int k = 0; k < c->nspecies; k++) free(c->sp[k].sites);
  free(c->sp);
  free(c->r); free(c->v); free(c->l); free(c->A); free(c->rho);
  free(c->file);
  memset(c, 0, sizeof *c);
}

/* Every field read is checked as the deck checks its keys: a checkpoint with a valid CRC may still
 * have been crafted, or written by a run that went wrong.  Bodies are counted from 1. */
static int ck_validate(const char *path, const ck_data *c)
{
#define BAD(...) rl_error(RL_EINVAL, __VA_ARGS__)
  if (c->units != RL_UNITS_REAL && c->units != RL_UNITS_LJ)
    return BAD("%s: checkpoint field 'units' is %d: 0 (real) or 1 (lj) expected", path, c->units);
  if (c->removed_dof < 0 || c->removed_dof > 3)
    return BAD("%s: checkpoint field 'removed_dof' is %d: 0 to 3 expected", path, c->removed_dof);
  if (!isfinite(c->time)) return BAD("%s: checkpoint field 'time' is %g: not finite", path, c->time);
  if (c->step < 0) return BAD("%s: checkpoint field 'step' is %ld: negative", path, c->step);
  const int no_box = c->box[0] == 0.0 && c->box[1] == 0.0 && c->box[2] == 0.0; /* a system without a box */
  for (int d = 0; d < 3 && !no_box; d++)
    if (!(isfinite(c->box[d]) && c->box[d] > 0.0))
      return BAD("%s: checkpoint field 'box' edge %d is %g: must be finite and > 0", path, d + 1, c->box[d]);
  long long n = 0, nrot = 0, nmat = 0, naxis = 0;
  for (int k = 0; k < c->nspecies; k++) {
    const ck_species *s = &c->sp[k];
#define BADSP(fmt, ...) BAD("%s: species %d ('%s'): checkpoint field " fmt, path, k + 1, s->name, __VA_ARGS__)
    if (s->kind < RL_KIND_POINT || s->kind > RL_KIND_ASYMMETRIC)
      return BADSP("'kind' is %d: not a known kind (0 to 5)", s->kind);
    const rl_kind kind = (rl_kind)s->kind;
    if (!(isfinite(s->mass) && s->mass > 0.0)) return BADSP("'mass' is %g: must be finite and > 0", s->mass);
    for (int a = 0; a < 3; a++) {
      const int needed = rl_kind_is_matrix(kind) || (rl_kind_is_axis(kind) && a < 2);
      if (!isfinite(s->J[a]) || s->J[a] < 0.0 || (needed && !(s->J[a] > 0.0)))
        return BADSP("'J[%d]' is %g: must be finite and %s", a, s->J[a], needed ? "> 0 for this kind" : ">= 0");
    }
    for (int q = 0; q < 3 * s->nsites; q++)
      if (!isfinite(s->sites[q])) return BADSP("'sites': site %d is not finite", q / 3 + 1);
    if (s->count < 0) return BADSP("'count' is %d: negative", s->count);
#undef BADSP
    n += s->count;
    nrot += kind != RL_KIND_POINT ? s->count : 0;
    nmat += rl_kind_is_matrix(kind) ? s->count : 0;
    naxis += rl_kind_is_axis(kind) ? s->count : 0;
  }
  if (n != c->n || nrot != c->nrot || nmat != c->nmat || naxis != c->naxis)
    return BAD("%s: checkpoint fields 'n', 'nrot', 'nmat', 'naxis' (%d, %d, %d, %d) do not match its species table "
               "(%lld, %lld, %lld, %lld)", path, c->n, c->nrot, c->nmat, c->naxis, n, nrot, nmat, naxis);
  char who[512];
  snprintf(who, sizeof who, "%.400s: checkpoint field 'A'", path);
  int i = 0, ir = 0, im = 0, ia = 0;
  for (int k = 0; k < c->nspecies; k++) {
    const rl_kind kind = (rl_kind)c->sp[k].kind;
    for (int b = 0; b < c->sp[k].count; b++, i++) {
      const double *r = c->r + 3 * i, *v = c->v + 3 * i;
      if (!(isfinite(r[0]) && isfinite(r[1]) && isfinite(r[2])))
        return BAD("%s: checkpoint field 'r' of body %d is not finite (%g %g %g)", path, i + 1, r[0], r[1], r[2]);
      if (!(isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2])))
        return BAD("%s: checkpoint field 'v' of body %d is not finite (%g %g %g)", path, i + 1, v[0], v[1], v[2]);
      if (kind != RL_KIND_POINT) {
        const double *l = c->l + 3 * ir++;
        if (!(isfinite(l[0]) && isfinite(l[1]) && isfinite(l[2])))
          return BAD("%s: checkpoint field 'l' of body %d is not finite (%g %g %g)", path, i + 1, l[0], l[1], l[2]);
      }
      if (rl_kind_is_matrix(kind) && rl_check_rotation(c->A + 9 * im++, who, i + 1)) return RL_EINVAL;
      if (rl_kind_is_axis(kind)) {
        const double *u = c->rho + 3 * ia++, nu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        if (!(fabs(nu - 1.0) <= 1e-10))
          return BAD("%s: checkpoint field 'rho' of body %d is not a unit vector (%g %g %g, |rho| - 1 = %.3g)", path,
                     i + 1, u[0], u[1], u[2], nu - 1.0);
      }
    }
  }
#undef BAD
  return RL_OK;
}

static int ck_parse(const char *path, ck_data *c)
{
  memset(c, 0, sizeof *c);
  int fd;
  long long fsize;
  int st = rl_io_open_read(path, " checkpoint", &fd, &fsize);
  if (st) return st;
  if (fsize < 0 || (unsigned long long)fsize > SIZE_MAX - 1) {
    close(fd);
    return rl_error(RL_EINVAL, "%s: checkpoint of %lld bytes is too large", path, fsize);
  }
  size_t size = (size_t)fsize;
  c->file = malloc(size ? size : 1);
  if (!c->file) { close(fd); return rl_error(RL_ENOMEM, "%s: out of memory for %zu bytes", path, size); }
  int e = rl_io_read_at(fd, c->file, size, 0);
  close(fd);
  if (e) {
    ck_free(c);
    return e > 0 ? rl_io_sys_error(e, path, "cannot read the checkpoint")
                 : rl_error(RL_EINVAL, "%s: the checkpoint shrank while it was read", path);
  }
  const unsigned char *f = c->file;
  if (size < 8 || memcmp(f, MAGIC, 8) != 0) {
    ck_free(c);
    return rl_error(RL_EINVAL, "%s: not a rotleap checkpoint (bad magic number)", path);
  }
  if (size < HDR + 4) {
    ck_free(c);
    return rl_error(RL_EINVAL, "%s: checkpoint truncated: %zu bytes, the header alone needs %d", path, size, HDR + 4);
  }
  uint32_t version = rl_get32(f + 8);
  if (version != RL_CHECKPOINT_VERSION) {
    ck_free(c);
    return rl_error(RL_EINVAL, "%s: checkpoint format version %u; this build of rotleap reads version %d",
                    path, version, RL_CHECKPOINT_VERSION);
  }
  uint64_t plen = rl_get64(f + 16);
  if (plen > size || size < HDR + plen + 4) {
    ck_free(c);
    return rl_error(RL_EINVAL, "%s: checkpoint truncated: %zu bytes, its header announces %llu", path, size,
                    (unsigned long long)(HDR + plen + 4));
  }
  if (size != HDR + plen + 4) {
    ck_free(c);
    return rl_error(RL_EINVAL, "%s: checkpoint has %llu bytes after its end (%zu bytes, header announces %llu)",
                    path, (unsigned long long)(size - HDR - plen - 4), size, (unsigned long long)(HDR + plen + 4));
  }
  uint32_t crc = rl_crc32(0, f, HDR + plen), stored = rl_get32(f + HDR + plen);
  if (crc != stored) {
    ck_free(c);
    return rl_error(RL_EINVAL, "%s: checkpoint checksum mismatch (CRC-32 stored %08x, computed %08x): "
                    "the file is corrupted", path, stored, crc);
  }
  rbuf b = {f + HDR, plen, 0, path, 0};
  c->units = (int)get_u32(&b, "units");
  c->removed_dof = (int)get_u32(&b, "removed_dof");
  get_f64s(&b, &c->time, 1, "time");
  c->step = (long)(int64_t)get_u64(&b, "step");
  get_f64s(&b, c->box, 3, "box");
  /* every count is bounded by the bytes left before anything is allocated for it: a species
   * entry takes at least 48 bytes (name length, kind, mass, J, nsites, count), a site 24 */
  uint32_t ns = get_u32(&b, "species count");
  if (!b.bad && ns > (b.n - b.at) / 48)
    b.bad = rl_error(RL_EINVAL, "%s: checkpoint species count %u does not fit in the %zu bytes left", path, ns, b.n - b.at);
  if (!b.bad) {
    c->sp = calloc(ns ? ns : 1, sizeof *c->sp);
    if (!c->sp) b.bad = rl_error(RL_ENOMEM, "%s: out of memory", path);
    else c->nspecies = (int)ns;
  }
  for (int k = 0; k < c->nspecies && !b.bad; k++) {
    ck_species *s = &c->sp[k];
    uint32_t nl = get_u32(&b, "species name");
    if (!b.bad && nl >= sizeof s->name)
      b.bad = rl_error(RL_EINVAL, "%s: species %d: checkpoint field 'name' is %u bytes long (at most %zu)", path,
                       k + 1, nl, sizeof s->name - 1);
    const unsigned char *nm = take(&b, nl, "species name");
    if (nm) snprintf(s->name, sizeof s->name, "%.*s", (int)nl, (const char *)nm);
    s->kind = (int)get_u32(&b, "species kind");
    get_f64s(&b, &s->mass, 1, "species mass");
    get_f64s(&b, s->J, 3, "species moments");
    uint32_t nsites = get_u32(&b, "species sites");
    if (!b.bad && nsites > (b.n - b.at) / 24)
      b.bad = rl_error(RL_EINVAL, "%s: species %d: checkpoint site count %u does not fit in the %zu bytes left", path,
                       k + 1, nsites, b.n - b.at);
    if (b.bad) break;
    s->nsites = (int)nsites;
    s->sites = malloc(sizeof(double) * 3 * (nsites ? nsites : 1));
    if (!s->sites) { b.bad = rl_error(RL_ENOMEM, "%s: out of memory", path); break; }
    get_f64s(&b, s->sites, 3 * (size_t)nsites, "species sites");
    s->count = (int)get_u32(&b, "species count");
  }
  c->n = (int)get_u32(&b, "body count");
  c->nrot = (int)get_u32(&b, "rotating body count");
  c->nmat = (int)get_u32(&b, "matrix body count");
  c->naxis = (int)get_u32(&b, "axis body count");
  if (!b.bad && (c->n < 0 || c->nrot < 0 || c->nmat < 0 || c->naxis < 0 ||
                 (size_t)c->n * 48 + (size_t)c->nrot * 24 + (size_t)c->nmat * 72 + (size_t)c->naxis * 24 > plen))
    b.bad = rl_error(RL_EINVAL, "%s: state counts exceed the payload", path);
  if (!b.bad) {
    c->r = malloc(sizeof(double) * 3 * (size_t)(c->n + 1));
    c->v = malloc(sizeof(double) * 3 * (size_t)(c->n + 1));
    c->l = malloc(sizeof(double) * 3 * (size_t)(c->nrot + 1));
    c->A = malloc(sizeof(double) * 9 * (size_t)(c->nmat + 1));
    c->rho = malloc(sizeof(double) * 3 * (size_t)(c->naxis + 1));
    if (!c->r || !c->v || !c->l || !c->A || !c->rho) b.bad = rl_error(RL_ENOMEM, "%s: out of memory", path);
  }
  if (!b.bad) {
    get_f64s(&b, c->r, 3 * (size_t)c->n, "r");
    get_f64s(&b, c->v, 3 * (size_t)c->n, "v");
    get_f64s(&b, c->l, 3 * (size_t)c->nrot, "l");
    get_f64s(&b, c->A, 9 * (size_t)c->nmat, "A");
    get_f64s(&b, c->rho, 3 * (size_t)c->naxis, "rho");
  }
  uint64_t bs = get_u64(&b, "blob size");
  c->blob = take(&b, (size_t)bs, "blob");
  c->blob_size = (size_t)bs;
  if (!b.bad && b.at != b.n) b.bad = rl_error(RL_EINVAL, "%s: %zu unexpected bytes after the blob", path, b.n - b.at);
  if (!b.bad) b.bad = ck_validate(path, c);
  if (b.bad) { st = b.bad; ck_free(c); return st; }
  return RL_OK;
}

static int differs(double a, double b) { return !(fabs(a - b) <= 1e-12 * fmax(fabs(a), fabs(b))); }

static int ck_match(const char *path, const ck_data *c, const rl_system *sys)
{
  static const char *un[2] = {"real", "lj"};
  if (c->units != (int)sys->units)
    return rl_error(RL_EINVAL, "%s: checkpoint units '%s', the system's '%s'", path,
                    c->units == 0 || c->units == 1 ? un[c->units] : "?", un[sys->units]);
  if (c->nspecies != sys->nspecies)
    return rl_error(RL_EINVAL, "%s: checkpoint has %d species, the system %d", path, c->nspecies, sys->nspecies);
  for (int k = 0; k < c->nspecies; k++) {
    const ck_species *a = &c->sp[k];
    const rl_species *s = &sys->sp[k];
#define MISMATCH(fmt, ...) \
  rl_error(RL_EINVAL, "%s: species %d ('%s'): " fmt, path, k + 1, s->name, __VA_ARGS__)
    if (strcmp(a->name, s->name) != 0) return MISMATCH("name '%s' in the checkpoint, '%s' in the system", a->name, s->name);
    if (a->kind != (int)s->kind)
      return MISMATCH("kind %s in the checkpoint, %s in the system", rl_kind_name((rl_kind)a->kind), rl_kind_name(s->kind));
    if (a->count != s->count) return MISMATCH("%d molecules in the checkpoint, %d in the system", a->count, s->count);
    if (differs(a->mass, s->mass)) return MISMATCH("mass %.17g in the checkpoint, %.17g in the system", a->mass, s->mass);
    for (int d = 0; d < 3; d++)
      if (differs(a->J[d], s->J[d]))
        return MISMATCH("moment J[%d] %.17g in the checkpoint, %.17g in the system", d, a->J[d], s->J[d]);
    if (a->nsites != s->nsites) return MISMATCH("%d sites in the checkpoint, %d in the system", a->nsites, s->nsites);
    double scale = 0.0;
    for (int q = 0; q < 3 * s->nsites; q++) scale = fmax(scale, fabs(s->sites[q]));
    for (int q = 0; q < 3 * s->nsites; q++)
      if (!(fabs(a->sites[q] - s->sites[q]) <= 1e-12 * scale))
        return MISMATCH("site %d coordinate %d is %.17g in the checkpoint, %.17g in the system", q / 3 + 1,
                        q % 3, a->sites[q], s->sites[q]);
#undef MISMATCH
  }
  if (c->n != sys->n || c->nrot != sys->nrot || c->nmat != sys->nmat || c->naxis != sys->naxis)
    return rl_error(RL_EINVAL, "%s: state array sizes differ from the system's", path);
  return RL_OK;
}

static int ck_restore(const char *path, ck_data *c, rl_system *sys, rl_checkpoint_meta *meta)
{
  void *blob = NULL;
  if (meta && c->blob_size) {
    blob = malloc(c->blob_size);
    if (!blob) return rl_error(RL_ENOMEM, "%s: out of memory for a %zu-byte blob", path, c->blob_size);
    memcpy(blob, c->blob, c->blob_size);
  }
  memcpy(sys->r, c->r, sizeof(double) * 3 * (size_t)c->n);
  memcpy(sys->v, c->v, sizeof(double) * 3 * (size_t)c->n);
  if (c->nrot) memcpy(sys->l, c->l, sizeof(double) * 3 * (size_t)c->nrot);
  if (c->nmat) memcpy(sys->A, c->A, sizeof(double) * 9 * (size_t)c->nmat);
  if (c->naxis) memcpy(sys->rho, c->rho, sizeof(double) * 3 * (size_t)c->naxis);
  sys->removed_dof = c->removed_dof;
  rl_system_set_box(sys, c->box); /* checked by ck_parse: finite and positive, or all zero */
  if (meta) {
    meta->time = c->time;
    meta->step = c->step;
    memcpy(meta->box, c->box, sizeof meta->box);
    meta->blob = blob;
    meta->blob_size = c->blob_size;
  }
  return RL_OK;
}

int rl_checkpoint_read(const char *path, rl_system *sys, rl_checkpoint_meta *meta)
{
  if (!path || !sys) return rl_error(RL_EINVAL, "rl_checkpoint_read: NULL argument");
  ck_data c;
  int st = ck_parse(path, &c);
  if (st) return st;
  if (!(st = ck_match(path, &c, sys))) st = ck_restore(path, &c, sys, meta);
  ck_free(&c);
  return st;
}

rl_system *rl_checkpoint_load(const char *path, rl_checkpoint_meta *meta)
{
  if (!path) { rl_error(RL_EINVAL, "rl_checkpoint_load: NULL path"); return NULL; }
  ck_data c;
  if (ck_parse(path, &c)) return NULL;
  rl_system *sys = rl_system_alloc((rl_units)c.units); /* units validated by ck_parse */
  if (!sys) goto fail;
  for (int k = 0; k < c.nspecies; k++) {
    const ck_species *s = &c.sp[k];
    rl_species_desc d = {s->name, (rl_kind)s->kind, s->mass, {s->J[0], s->J[1], s->J[2]}, s->nsites, s->sites};
    if (rl_system_add_species(sys, &d, s->count, NULL)) {
      rl_error_wrap(RL_EINVAL, "%s: species %d ('%s')", path, k + 1, s->name);
      goto fail;
    }
  }
  if (ck_match(path, &c, sys) || ck_restore(path, &c, sys, meta)) goto fail;
  ck_free(&c);
  return sys;
fail:
  rl_system_free(sys);
  ck_free(&c);
  return NULL;
}
