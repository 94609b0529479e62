/* Extended XYZ (ASE/OVITO/QUIP convention) with the body Z axis as an orientation column. */
#include "io_internal.h"
#include "rotleap/error.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

int rl_xyz_write_frame(FILE *fp, const char *path, const rl_system *sys, double time, long step)
{
  double Lb[3] = {0, 0, 0};
  if (sys) rl_system_box(sys, Lb);
  const double *box = sys && rl_system_periodic(sys) ? Lb : NULL;
  if (!fp || !sys) return rl_error(RL_EINVAL, "rl_xyz_write_frame: NULL argument");
  if (!path) path = "(stream)";
  if (ferror(fp)) return rl_error(RL_EINVAL, "%s: not written: an earlier write to it failed", path);
  double s = rl_io_length_scale(sys);
  /* every call checked: the errno of the first failing one is the message */
  if (fprintf(fp, "%d\n", sys->n) < 0) goto fail;
  if (box && fprintf(fp, "Lattice=\"%.10f 0 0 0 %.10f 0 0 0 %.10f\" ", box[0] * s, box[1] * s, box[2] * s) < 0) goto fail;
  if (fprintf(fp, "Properties=species:S:1:pos:R:3:orientation:R:3:name:S:1 Time=%.17g Step=%ld Units=%s%s\n", time,
              step, sys->units == RL_UNITS_REAL ? "Angstrom" : "sigma", box ? " pbc=\"T T T\"" : "") < 0)
    goto fail;
  for (int i = 0; i < sys->n; i++) {
    int k = sys->species_of[i];
    double rho[3] = {0, 0, 0};
    if (sys->sp[k].kind != RL_KIND_POINT) rl_system_get_axis(sys, i, rho);
    const char *nm = sys->sp[k].name[0] ? sys->sp[k].name : "X";
    if (fprintf(fp, "X %.10f %.10f %.10f %.17g %.17g %.17g %s\n", sys->r[i][0] * s, sys->r[i][1] * s,
                sys->r[i][2] * s, rho[0], rho[1], rho[2], nm) < 0)
      goto fail;
  }
  if (fflush(fp) != 0) goto fail;
  return RL_OK;
fail:
  return rl_io_sys_error(errno, path, "cannot write");
}

int rl_xyz_write(const char *path, const rl_system *sys, double time, long step)
{
  if (!path) return rl_error(RL_EINVAL, "rl_xyz_write: NULL path");
  rl_atomic_file af;
  int st = rl_atomic_open(&af, path);
  if (st) return st;
  if ((st = rl_xyz_write_frame(af.fp, path, sys, time, step))) { rl_atomic_abort(&af); return st; }
  return rl_atomic_commit(&af);
}

/* ---------------------------------------------------------------------------- reading */

/* Find key=value in an extxyz comment line (value possibly "quoted"); *val: a malloc'd copy. */
static int find_key(const char *line, const char *key, char **val)
{
  size_t kl = strlen(key);
  const char *p = line;
  while (*p) {
    while (*p && isspace((unsigned char)*p)) p++;
    const char *k0 = p;
    while (*p && *p != '=' && !isspace((unsigned char)*p)) p++;
    size_t klen = (size_t)(p - k0);
    const char *v0 = NULL, *v1 = NULL;
    if (*p == '=') {
      p++;
      if (*p == '"') {
        v0 = ++p;
        while (*p && *p != '"') p++;
        v1 = p;
        if (*p) p++;
      } else {
        v0 = p;
        while (*p && !isspace((unsigned char)*p)) p++;
        v1 = p;
      }
    }
    if (klen == kl && strncasecmp(k0, key, kl) == 0 && v0) {
      *val = strndup(v0, (size_t)(v1 - v0));
      return *val ? 1 : -1;
    }
    if (klen == 0 && !v0 && *p) p++;
  }
  return 0;
}

/* Open path (a regular file) and read its first line, the number of bodies: at most one per 6
 * bytes of the file (a body's line holds at least three numbers). */
static int open_count(const char *path, FILE **fp, int *n, char **buf, size_t *cap)
{
  long long size;
  int st = rl_io_fopen_read(path, "", fp, &size), got = 0;
  if (st) return st;
  if ((st = rl_io_getline(*fp, path, 1, RL_IO_MAX_LINE, buf, cap, &got))) goto fail;
  char *end;
  errno = 0;
  long long v = got ? strtoll(*buf, &end, 10) : -1;
  if (!got || end == *buf || v < 0 || errno) {
    st = rl_error(RL_EINVAL, "%s:1: expected the number of particles", path);
    goto fail;
  }
  while (isspace((unsigned char)*end)) end++;
  if (*end) { st = rl_error(RL_EINVAL, "%s:1: expected the number of particles, found '%s'", path, *buf); goto fail; }
  if (v > size / 6 || v > INT_MAX) {
    st = rl_error(RL_EINVAL, "%s:1: %lld particles announced, but a file of %lld bytes holds at most %lld", path, v,
                  size, size / 6);
    goto fail;
  }
  *n = (int)v;
  return RL_OK;
fail:
  fclose(*fp);
  *fp = NULL;
  return st;
}

int rl_xyz_count(const char *path, int *n)
{
  if (!path || !n) return rl_error(RL_EINVAL, "rl_xyz_count: NULL argument");
  FILE *fp;
  char *buf = NULL;
  size_t cap = 0;
  int st = open_count(path, &fp, n, &buf, &cap);
  if (!st) fclose(fp);
  free(buf);
  return st;
}

/* Columns of a Properties= value (name:type:count triplets). */
typedef struct {
  int sp, name, pos, orient, n;
} xyz_cols;

static int parse_properties(const char *path, char *val, xyz_cols *c)
{
  c->sp = c->name = c->pos = c->orient = -1;
  long col = 0;
  char *save = NULL;
  for (char *nm = strtok_r(val, ":", &save); nm; nm = strtok_r(NULL, ":", &save)) {
    char *ty = strtok_r(NULL, ":", &save), *ct = strtok_r(NULL, ":", &save), *end = NULL;
    long k = ct ? strtol(ct, &end, 10) : 0;
    if (!ty || !ct || *end || k < 1)
      return rl_error(RL_EINVAL, "%s:2: malformed Properties= (name:type:count triplets)", path);
    /* a line of at most RL_IO_MAX_LINE characters holds at most half as many columns */
    if (k > RL_IO_MAX_LINE / 2 || col + k > RL_IO_MAX_LINE / 2)
      return rl_error(RL_EINVAL, "%s:2: Properties= announces %ld columns for '%.64s' after %ld others; a line of at "
                      "most %d characters holds at most %d", path, k, nm, col, RL_IO_MAX_LINE, RL_IO_MAX_LINE / 2);
    if (!strcmp(nm, "species") && k == 1) c->sp = (int)col;
    else if (!strcmp(nm, "name") && k == 1) c->name = (int)col;
    else if (!strcmp(nm, "pos") && k == 3) c->pos = (int)col;
    else if ((!strcmp(nm, "orientation") || !strcmp(nm, "dipoles") || !strcmp(nm, "axis") || !strcmp(nm, "rho")) && k == 3)
      c->orient = (int)col;
    col += k;
  }
  c->n = (int)col;
  if (c->pos < 0) return rl_error(RL_EINVAL, "%s:2: Properties= has no pos:R:3 column", path);
  return RL_OK;
}

/* The diagonal of a Lattice= value (9 numbers, orthorhombic) in system units (file units / s). */
static int parse_lattice(const char *path, const char *val, double s, double L[3])
{
  double h[9];
  const char *p = val;
  char *end;
  for (int k = 0; k < 9; k++) {
    h[k] = strtod(p, &end);
    if (end == p) return rl_error(RL_EINVAL, "%s:2: Lattice needs 9 numbers: \"%.200s\"", path, val);
    p = end;
  }
  for (int k = 0; k < 9; k++)
    if (k % 4 != 0 && h[k] != 0.0)
      return rl_error(RL_EINVAL, "%s:2: Lattice is not orthorhombic (off-diagonal %g); only orthorhombic boxes are supported",
                      path, h[k]);
  for (int c = 0; c < 3; c++) L[c] = h[4 * c] / s;
  return RL_OK;
}

int rl_xyz_box(const char *path, rl_units units, double box[3])
{
  if (!path || !box) return rl_error(RL_EINVAL, "rl_xyz_box: NULL argument");
  FILE *fp;
  char *buf = NULL, *val = NULL;
  size_t cap = 0;
  int n = 0, got, st = open_count(path, &fp, &n, &buf, &cap);
  if (st) { free(buf); return st; }
  box[0] = box[1] = box[2] = 0.0;
  if (!(st = rl_io_getline(fp, path, 2, RL_IO_MAX_LINE, &buf, &cap, &got)) && got) {
    int f = find_key(buf, "Lattice", &val);
    if (f < 0) st = rl_error(RL_ENOMEM, "%s:2: out of memory", path);
    else if (f > 0) st = parse_lattice(path, val, units == RL_UNITS_REAL ? 10.0 : 1.0, box);
  }
  free(val);
  free(buf);
  fclose(fp);
  return st;
}

int rl_xyz_read_state(const char *path, rl_system *sys, double box[3])
{
  if (!path || !sys) return rl_error(RL_EINVAL, "rl_xyz_read_state: NULL argument");
  FILE *fp;
  char *buf = NULL, *val = NULL, **tok = NULL;
  size_t cap = 0;
  int n = 0, got, st = open_count(path, &fp, &n, &buf, &cap);
  if (st) { free(buf); return st; }
  double s = rl_io_length_scale(sys), L[3] = {0, 0, 0};
  xyz_cols col = {0, -1, 1, 4, 4}; /* without Properties=: species x y z [ox oy oz] */
  if (n != sys->n) { st = rl_error(RL_EINVAL, "%s:1: %d particles, the system has %d", path, n, sys->n); goto done; }
  if ((st = rl_io_getline(fp, path, 2, RL_IO_MAX_LINE, &buf, &cap, &got))) goto done;
  if (!got) { st = rl_error(RL_EINVAL, "%s:2: missing comment line", path); goto done; }
  int f = find_key(buf, "Lattice", &val);
  if (f > 0 && (st = parse_lattice(path, val, s, L))) goto done;
  free(val);
  val = NULL;
  if (f >= 0) f = find_key(buf, "Properties", &val);
  if (f < 0) { st = rl_error(RL_ENOMEM, "%s:2: out of memory", path); goto done; }
  if (f > 0 && (st = parse_properties(path, val, &col))) goto done;
  tok = malloc(sizeof *tok * (size_t)(col.n + 8));
  if (!tok) { st = rl_error(RL_ENOMEM, "%s: out of memory", path); goto done; }
  const int label = col.name >= 0 ? col.name : col.sp; /* the species name */
  int need = col.pos + 3;
  if (col.orient >= 0 && col.orient + 3 > need) need = col.orient + 3;
  if (label >= 0 && label + 1 > need) need = label + 1;
  for (int i = 0; i < n && !st; i++) {
    int lineno = i + 3;
    if ((st = rl_io_getline(fp, path, lineno, RL_IO_MAX_LINE, &buf, &cap, &got))) break;
    if (!got) { st = rl_error(RL_EINVAL, "%s:%d: file ends after %d of %d particles", path, lineno, i, n); break; }
    int nt = 0;
    char *save = NULL;
    for (char *t = strtok_r(buf, " \t", &save); t && nt < col.n + 7; t = strtok_r(NULL, " \t", &save)) tok[nt++] = t;
    if (nt < need) { st = rl_error(RL_EINVAL, "%s:%d: %d columns, expected %d", path, lineno, nt, need); break; }
    int k = sys->species_of[i];
    const rl_species *sp = &sys->sp[k];
    if (label >= 0 && sp->name[0] && strcmp(tok[label], sp->name) != 0) {
      st = rl_error(RL_EINVAL, "%s:%d: species '%.64s', but body %d is a '%s'", path, lineno, tok[label], i + 1, sp->name);
      break;
    }
    double x[6];
    int has_or = col.orient >= 0 && (col.orient + 3 <= nt);
    for (int c = 0; c < (has_or ? 6 : 3); c++) {
      const int cc = c < 3 ? col.pos + c : col.orient + c - 3;
      const char *t = tok[cc];
      char *end;
      errno = 0;
      x[c] = strtod(t, &end);
      if (end == t || *end || errno || !isfinite(x[c])) {
        st = rl_error(RL_EINVAL, "%s:%d: column %d is not a number: '%.64s'", path, lineno, cc + 1, t);
        break;
      }
    }
    if (st) break;
    double r[3] = {x[0] / s, x[1] / s, x[2] / s};
    if ((st = rl_system_set_position(sys, i, r))) { st = rl_error_wrap(st, "%s:%d", path, lineno); break; }
    if (sp->kind == RL_KIND_POINT) continue;
    if (!has_or) {
      if (rl_kind_is_axis(sp->kind)) { st = rl_error(RL_EINVAL, "%s:%d: body %d ('%s', %s) needs an orientation column", path, lineno, i + 1, sp->name, rl_kind_name(sp->kind)); break; }
      continue;
    }
    double nr = sqrt(x[3] * x[3] + x[4] * x[4] + x[5] * x[5]);
    if (!(fabs(nr - 1.0) <= 1e-6)) {
      st = rl_error(RL_EINVAL, "%s:%d: orientation (%g, %g, %g) is not a unit vector (|o| = %.9g)", path, lineno, x[3], x[4], x[5], nr);
      break;
    }
    if (fabs(nr - 1.0) <= 1e-12) nr = 1.0; /* as written: keep the bits */
    double rho[3] = {x[3] / nr, x[4] / nr, x[5] / nr};
    if ((st = rl_system_set_axis(sys, i, rho))) { st = rl_error_wrap(st, "%s:%d", path, lineno); break; }
  }
  if (!st && box) for (int c = 0; c < 3; c++) box[c] = L[c];
done:
  free(tok);
  free(val);
  free(buf);
  fclose(fp);
  return st;
}
