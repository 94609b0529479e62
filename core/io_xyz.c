/* Extended XYZ (ASE/OVITO/QUIP convention) with the body Z axis as an orientation column. */
#include "io_internal.h"
#include "rotleap/error.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

int rl_xyz_write_frame(FILE *fp, const char *path, const rl_system *sys, const double box[3],
                       double time, long step)
{
  if (!fp || !sys) return rl_error(RL_EINVAL, "rl_xyz_write_frame: NULL argument");
  if (!path) path = "(stream)";
  double s = rl_io_length_scale(sys);
  fprintf(fp, "%d\n", sys->n);
  if (box)
    fprintf(fp, "Lattice=\"%.10f 0 0 0 %.10f 0 0 0 %.10f\" ", box[0] * s, box[1] * s, box[2] * s);
  fprintf(fp, "Properties=species:S:1:pos:R:3:orientation:R:3 Time=%.17g Step=%ld Units=%s", time, step,
          sys->units == RL_UNITS_REAL ? "Angstrom" : "sigma");
  if (box) fprintf(fp, " pbc=\"T T T\"");
  fputc('\n', fp);
  for (int i = 0; i < sys->n; i++) {
    int k = sys->species_of[i];
    double rho[3] = {0, 0, 0};
    if (sys->sp[k].kind != RL_KIND_POINT) rl_system_get_axis(sys, i, rho);
    const char *nm = sys->sp[k].name[0] ? sys->sp[k].name : "X";
    fprintf(fp, "%s %.10f %.10f %.10f %.17g %.17g %.17g\n", nm, sys->r[i][0] * s, sys->r[i][1] * s,
            sys->r[i][2] * s, rho[0], rho[1], rho[2]);
  }
  if (ferror(fp)) return rl_error(RL_EINVAL, "%s: write error", path);
  return RL_OK;
}

int rl_xyz_write(const char *path, const rl_system *sys, const double box[3], double time, long step)
{
  if (!path) return rl_error(RL_EINVAL, "rl_xyz_write: NULL path");
  rl_atomic_file af;
  int st = rl_atomic_open(&af, path);
  if (st) return st;
  if ((st = rl_xyz_write_frame(af.fp, path, sys, box, time, step))) { rl_atomic_abort(&af); return st; }
  return rl_atomic_commit(&af);
}

/* ---------------------------------------------------------------------------- reading */

/* Read one line (any length) into *buf; 0 at EOF. */
static int get_line(FILE *fp, char **buf, size_t *cap)
{
  size_t n = 0;
  int c;
  while ((c = fgetc(fp)) != EOF) {
    if (n + 2 > *cap) {
      size_t nc = *cap ? 2 * *cap : 256;
      char *b = realloc(*buf, nc);
      if (!b) return -1;
      *buf = b;
      *cap = nc;
    }
    if (c == '\n') break;
    (*buf)[n++] = (char)c;
  }
  if (c == EOF && n == 0) return 0;
  if (n && (*buf)[n - 1] == '\r') n--;
  (*buf)[n] = '\0';
  return 1;
}

/* Find key=value in an extxyz comment line (value possibly "quoted"); copies value. */
static int find_key(const char *line, const char *key, char *val, size_t valsz)
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
      size_t n = (size_t)(v1 - v0);
      if (n >= valsz) n = valsz - 1;
      memcpy(val, v0, n);
      val[n] = '\0';
      return 1;
    }
    if (klen == 0 && !v0 && *p) p++;
  }
  return 0;
}

int rl_xyz_count(const char *path, int *n)
{
  FILE *fp = fopen(path, "r");
  if (!fp) {
    int e = errno;
    return rl_error(RL_EINVAL, "%s: cannot open: %s", path, strerror(e));
  }
  char *buf = NULL;
  size_t cap = 0;
  int st = RL_OK, got = get_line(fp, &buf, &cap);
  fclose(fp);
  char *end;
  long v = got > 0 ? strtol(buf, &end, 10) : -1;
  if (got <= 0 || end == buf || v < 0 || v > 1000000000) st = rl_error(RL_EINVAL, "%s:1: expected the number of particles", path);
  else {
    while (isspace((unsigned char)*end)) end++;
    if (*end) st = rl_error(RL_EINVAL, "%s:1: expected the number of particles, found '%s'", path, buf);
    else *n = (int)v;
  }
  free(buf);
  return st;
}

int rl_xyz_read_state(const char *path, rl_system *sys, double box[3])
{
  if (!path || !sys) return rl_error(RL_EINVAL, "rl_xyz_read_state: NULL argument");
  int n, st = rl_xyz_count(path, &n);
  if (st) return st;
  if (n != sys->n) return rl_error(RL_EINVAL, "%s:1: %d particles, the system has %d", path, n, sys->n);
  FILE *fp = fopen(path, "r");
  if (!fp) return rl_error(RL_EINVAL, "%s: cannot reopen", path);
  char *buf = NULL;
  size_t cap = 0;
  double s = rl_io_length_scale(sys), L[3] = {0, 0, 0};
  int col_sp = 0, col_pos = 1, col_or = 4, ncols = 4; /* without Properties=: species x y z [o] */
  get_line(fp, &buf, &cap);
  if (get_line(fp, &buf, &cap) <= 0) { st = rl_error(RL_EINVAL, "%s:2: missing comment line", path); goto done; }
  char val[4096];
  if (find_key(buf, "Lattice", val, sizeof val)) {
    double h[9];
    char *p = val, *end;
    for (int k = 0; k < 9; k++) {
      h[k] = strtod(p, &end);
      if (end == p) { st = rl_error(RL_EINVAL, "%s:2: Lattice needs 9 numbers: \"%s\"", path, val); goto done; }
      p = end;
    }
    for (int k = 0; k < 9; k++)
      if (k % 4 != 0 && h[k] != 0.0) {
        st = rl_error(RL_EINVAL, "%s:2: Lattice is not orthorhombic (off-diagonal %g); only orthorhombic boxes are supported", path, h[k]);
        goto done;
      }
    for (int c = 0; c < 3; c++) L[c] = h[4 * c] / s;
  }
  if (find_key(buf, "Properties", val, sizeof val)) {
    col_sp = col_pos = col_or = -1;
    int col = 0;
    char *save = NULL;
    for (char *nm = strtok_r(val, ":", &save); nm; nm = strtok_r(NULL, ":", &save)) {
      char *ty = strtok_r(NULL, ":", &save), *ct = strtok_r(NULL, ":", &save);
      if (!ty || !ct || atoi(ct) < 1) { st = rl_error(RL_EINVAL, "%s:2: malformed Properties= (name:type:count triplets)", path); goto done; }
      int c = atoi(ct);
      if (!strcmp(nm, "species") && c == 1) col_sp = col;
      else if (!strcmp(nm, "pos") && c == 3) col_pos = col;
      else if ((!strcmp(nm, "orientation") || !strcmp(nm, "dipoles") || !strcmp(nm, "axis") || !strcmp(nm, "rho")) && c == 3) col_or = col;
      col += c;
    }
    ncols = col;
    if (col_pos < 0) { st = rl_error(RL_EINVAL, "%s:2: Properties= has no pos:R:3 column", path); goto done; }
  }
  char **tok = malloc(sizeof *tok * (size_t)(ncols + 8));
  if (!tok) { st = rl_error(RL_ENOMEM, "%s: out of memory", path); goto done; }
  for (int i = 0; i < n && !st; i++) {
    int lineno = i + 3;
    if (get_line(fp, &buf, &cap) <= 0) { st = rl_error(RL_EINVAL, "%s:%d: file ends after %d of %d particles", path, lineno, i, n); break; }
    int nt = 0;
    char *save = NULL;
    for (char *t = strtok_r(buf, " \t", &save); t && nt < ncols + 7; t = strtok_r(NULL, " \t", &save)) tok[nt++] = t;
    int need = col_pos + 3;
    if (col_or >= 0 && col_or + 3 > need) need = col_or + 3;
    if (col_sp >= 0 && col_sp + 1 > need) need = col_sp + 1;
    if (nt < need) { st = rl_error(RL_EINVAL, "%s:%d: %d columns, expected %d", path, lineno, nt, need); break; }
    int k = sys->species_of[i];
    const rl_species *sp = &sys->sp[k];
    if (col_sp >= 0 && sp->name[0] && strcmp(tok[col_sp], sp->name) != 0) {
      st = rl_error(RL_EINVAL, "%s:%d: species '%s', but body %d is a '%s'", path, lineno, tok[col_sp], i + 1, sp->name);
      break;
    }
    double x[6];
    int has_or = col_or >= 0 && (col_or + 3 <= nt);
    for (int c = 0; c < (has_or ? 6 : 3); c++) {
      const char *t = tok[c < 3 ? col_pos + c : col_or + c - 3];
      char *end;
      errno = 0;
      x[c] = strtod(t, &end);
      if (end == t || *end || errno || !isfinite(x[c])) {
        st = rl_error(RL_EINVAL, "%s:%d: column %d is not a number: '%s'", path, lineno, (c < 3 ? col_pos + c : col_or + c - 3) + 1, t);
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
  free(tok);
  if (!st && box) for (int c = 0; c < 3; c++) box[c] = L[c];
done:
  free(buf);
  fclose(fp);
  return st;
}
