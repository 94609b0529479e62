/* PDB: topology/structure writer and a reader of starting states that recovers each rigid
 * molecule's centre and orientation by a least-squares fit of its body-frame sites. */
#include "io_internal.h"
#include "rotleap/error.h"

#include <ctype.h>
#include <errno.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ---------------------------------------------------------------------------- writing */

static void element_of(const rl_system *sys, const rl_molecule *const *mols, int k, int a,
                       const char *name, char el[3])
{
  el[0] = '\0';
  if (sys->units != RL_UNITS_REAL) return;
  const rl_molecule *m = mols ? mols[k] : NULL;
  if (m && a < m->nsites && m->site_mass[a] == 0.0) return; /* virtual site: no element */
  int n = 0;
  while (n < 2 && isalpha((unsigned char)name[n])) n++;
  if (n == 0) return;
  /* one-letter elements of the catalogue first (H1 -> H, not a two-letter guess) */
  el[0] = name[0];
  el[1] = '\0';
  if (n == 2 && islower((unsigned char)name[1])) { el[1] = name[1]; el[2] = '\0'; }
}

int rl_pdb_write(const char *path, const rl_system *sys, const rl_molecule *const *mols)
{
  double Lb[3] = {0, 0, 0};
  if (sys) rl_system_box(sys, Lb);
  const double *box = sys && rl_system_periodic(sys) ? Lb : NULL;
  if (!path || !sys) return rl_error(RL_EINVAL, "rl_pdb_write: NULL argument");
  double s = rl_io_length_scale(sys);
  double(*x)[3] = rl_io_atom_positions(sys);
  if (!x) return rl_error_wrap(RL_ENOMEM, "%s", path);
  int na = rl_io_natoms(sys);
  for (int a = 0; a < na; a++)
    for (int c = 0; c < 3; c++)
      if (!(fabs(x[a][c] * s) < 9999.9995)) {
        double bad = x[a][c] * s;
        free(x);
        return rl_error(RL_EINVAL, "%s: atom %d coordinate %g does not fit PDB's %%8.3f field", path,
                        a + 1, bad);
      }
  rl_atomic_file af;
  int st = rl_atomic_open(&af, path);
  if (st) { free(x); return st; }
  FILE *fp = af.fp;
  /* every call checked: the first failure (its errno, kept by the atomic file) is the message */
  if (fprintf(fp, "REMARK   1 rotleap %s; lengths in %s\n", "structure",
              sys->units == RL_UNITS_REAL ? "Angstrom" : "reduced units (sigma)") < 0 ||
      (box && fprintf(fp, "CRYST1%9.3f%9.3f%9.3f%7.2f%7.2f%7.2f P 1           1\n", box[0] * s, box[1] * s,
                      box[2] * s, 90.0, 90.0, 90.0) < 0))
    goto fail;
  int o = 0;
  for (int k = 0; k < sys->nspecies; k++) {
    const rl_species *sp = &sys->sp[k];
    char res[4];
    rl_io_res_name(sys, k, res);
    int ns = sp->nsites > 0 ? sp->nsites : 1;
    for (int b = 0; b < sp->count; b++) {
      int i = sp->first + b;
      for (int a = 0; a < ns; a++, o++) {
        char nm[8], el[3], field[12];
        rl_io_site_name(sys, mols, k, a, nm);
        element_of(sys, mols, k, a, nm, el);
        if (strlen(nm) < 4) snprintf(field, sizeof field, " %-3.3s", nm);
        else snprintf(field, sizeof field, "%-4.4s", nm);
        if (fprintf(fp, "ATOM  %5d %-4s %-3s A%4d    %8.3f%8.3f%8.3f%6.2f%6.2f          %2s\n",
                    (o + 1) % 100000, field, res, (i + 1) % 10000, x[o][0] * s, x[o][1] * s, x[o][2] * s,
                    1.0, 0.0, el) < 0)
          goto fail;
      }
    }
  }
  if (fputs("TER\nEND\n", fp) < 0) goto fail;
  free(x);
  return rl_atomic_commit(&af);
fail:
  free(x);
  return rl_atomic_fail(&af);
}

/* ---------------------------------------------------------------------------- reading */

typedef struct {
  double x[3];
  char name[5];
  int line;
} pdb_atom;

typedef struct {
  int first, count, line, seq;
  char name[5];
} pdb_res;

typedef struct {
  pdb_atom *atoms;
  pdb_res *res;
  int natoms, nres, cap_atoms, cap_res;
  double box[3];
  int has_box;
  int coarse; /* every coordinate's third decimal is 0: the file holds 0.01 file units (GROMACS's,
                 from .gro's 0.001 nm) */
} pdb_data;

static void pdb_data_free(pdb_data *p)
{
  free(p->atoms);
  free(p->res);
}

/* Copy columns [c0, c1] (1-based, inclusive) of line, trimmed. */
static void field(const char *line, size_t len, int c0, int c1, char *out, size_t outsz)
{
  size_t n = 0;
  for (int c = c0; c <= c1 && (size_t)c <= len && n + 1 < outsz; c++) out[n++] = line[c - 1];
  out[n] = '\0';
  while (n > 0 && isspace((unsigned char)out[n - 1])) out[--n] = '\0';
  size_t s = 0;
  while (out[s] && isspace((unsigned char)out[s])) s++;
  if (s) memmove(out, out + s, n - s + 1);
}

static int number(const char *path, int lineno, const char *line, size_t len, int c0, int c1,
                  const char *what, double *v)
{
  char buf[32], *end;
  field(line, len, c0, c1, buf, sizeof buf);
  errno = 0;
  *v = strtod(buf, &end);
  if (!buf[0] || *end || errno || !isfinite(*v))
    return rl_error(RL_EINVAL, "%s:%d: %s in columns %d-%d is not a number: '%s'", path, lineno,
                    what, c0, c1, buf);
  return RL_OK;
}

/* PDB records are 80 columns; longer lines (some writers pad them) are accepted up to this. */
#define PDB_MAX_LINE 1024

static int parse_pdb(const char *path, pdb_data *p)
{
  memset(p, 0, sizeof *p);
  p->coarse = 1;
  FILE *fp;
  long long size;
  int st = rl_io_fopen_read(path, "", &fp, &size);
  if (st) return st;
  char *line = NULL;
  size_t cap = 0;
  int lineno = 0, new_res = 1, got;
  char prev_key[24] = "";
  while (!(st = rl_io_getline(fp, path, lineno + 1, PDB_MAX_LINE, &line, &cap, &got)) && got) {
    lineno++;
    size_t len = strlen(line);
    if (strncmp(line, "ENDMDL", 6) == 0 || strncmp(line, "END", 3) == 0) break; /* first model */
    if (strncmp(line, "TER", 3) == 0) { new_res = 1; continue; }
    if (strncmp(line, "CRYST1", 6) == 0) {
      double ang[3];
      for (int c = 0; c < 3 && !st; c++) st = number(path, lineno, line, len, 7 + 9 * c, 15 + 9 * c, "CRYST1 cell length", &p->box[c]);
      for (int c = 0; c < 3 && !st; c++) st = number(path, lineno, line, len, 34 + 7 * c, 40 + 7 * c, "CRYST1 cell angle", &ang[c]);
      if (st) break;
      for (int c = 0; c < 3; c++)
        if (fabs(ang[c] - 90.0) > 0.01) {
          st = rl_error(RL_EINVAL, "%s:%d: CRYST1 angles %.2f %.2f %.2f: only orthorhombic boxes (90 degrees) are supported",
                        path, lineno, ang[0], ang[1], ang[2]);
          break;
        }
      if (st) break;
      p->has_box = 1;
      continue;
    }
    if (strncmp(line, "ATOM  ", 6) != 0 && strncmp(line, "HETATM", 6) != 0) continue;
    if (len < 54) {
      st = rl_error(RL_EINVAL, "%s:%d: ATOM record has %d columns, coordinates need 54", path, lineno, (int)len);
      break;
    }
    if (p->natoms == p->cap_atoms) {
      int cap = p->cap_atoms ? 2 * p->cap_atoms : 1024;
      pdb_atom *n = realloc(p->atoms, sizeof *n * (size_t)cap);
      if (!n) { st = rl_error(RL_ENOMEM, "%s:%d: out of memory", path, lineno); break; }
      p->atoms = n;
      p->cap_atoms = cap;
    }
    pdb_atom *at = &p->atoms[p->natoms];
    static const char *axis[3] = {"x", "y", "z"};
    for (int c = 0; c < 3 && !st; c++) st = number(path, lineno, line, len, 31 + 8 * c, 38 + 8 * c, axis[c], &at->x[c]);
    if (st) break;
    for (int c = 0; c < 3; c++) p->coarse &= line[37 + 8 * c] == '0';
    field(line, len, 13, 16, at->name, sizeof at->name);
    at->line = lineno;
    char key[24], resname[5], seq[8];
    field(line, len, 18, 21, resname, sizeof resname); /* 18-20; 21 too for CHARMM's TIP3 */
    field(line, len, 23, 26, seq, sizeof seq);
    snprintf(key, sizeof key, "%c|%s|%s", len >= 22 ? line[21] : ' ', seq, resname);
    if (new_res || strcmp(key, prev_key) != 0) {
      if (p->nres == p->cap_res) {
        int cap = p->cap_res ? 2 * p->cap_res : 256;
        pdb_res *n = realloc(p->res, sizeof *n * (size_t)cap);
        if (!n) { st = rl_error(RL_ENOMEM, "%s:%d: out of memory", path, lineno); break; }
        p->res = n;
        p->cap_res = cap;
      }
      pdb_res *r = &p->res[p->nres++];
      r->first = p->natoms;
      r->count = 0;
      r->line = lineno;
      r->seq = atoi(seq);
      snprintf(r->name, sizeof r->name, "%s", resname);
      strcpy(prev_key, key);
      new_res = 0;
    }
    p->res[p->nres - 1].count++;
    p->natoms++;
  }
  free(line);
  fclose(fp);
  if (st) pdb_data_free(p);
  return st;
}

int rl_pdb_count(const char *path, rl_units units, int *nres, double box[3])
{
  pdb_data p;
  int st = parse_pdb(path, &p);
  if (st) return st;
  if (nres) *nres = p.nres;
  if (box)
    for (int c = 0; c < 3; c++) box[c] = p.has_box ? p.box[c] / (units == RL_UNITS_REAL ? 10.0 : 1.0) : 0.0;
  pdb_data_free(&p);
  return RL_OK;
}

/* Least-squares rotation R (row-major) with y_a ~ R z_a for centred point sets (Horn 1987,
 * J. Opt. Soc. Am. A 4, 629: the unit quaternion is the top eigenvector of a 4x4 matrix). */
static int fit_rotation(int n, const double (*z)[3], const double (*y)[3], double R[9])
{
  double S[3][3] = {{0}};
  for (int a = 0; a < n; a++)
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) S[i][j] += z[a][i] * y[a][j];
  double N[16] = {
      S[0][0] + S[1][1] + S[2][2], S[1][2] - S[2][1], S[2][0] - S[0][2], S[0][1] - S[1][0],
      S[1][2] - S[2][1], S[0][0] - S[1][1] - S[2][2], S[0][1] + S[1][0], S[2][0] + S[0][2],
      S[2][0] - S[0][2], S[0][1] + S[1][0], -S[0][0] + S[1][1] - S[2][2], S[1][2] + S[2][1],
      S[0][1] - S[1][0], S[2][0] + S[0][2], S[1][2] + S[2][1], -S[0][0] - S[1][1] + S[2][2]};
  gsl_matrix_view Nv = gsl_matrix_view_array(N, 4, 4);
  gsl_vector *eval = gsl_vector_alloc(4);
  gsl_matrix *evec = gsl_matrix_alloc(4, 4);
  gsl_eigen_symmv_workspace *w = gsl_eigen_symmv_alloc(4);
  if (!eval || !evec || !w) {
    gsl_vector_free(eval); gsl_matrix_free(evec); gsl_eigen_symmv_free(w);
    return RL_ENOMEM;
  }
  gsl_eigen_symmv(&Nv.matrix, eval, evec, w);
  gsl_eigen_symmv_sort(eval, evec, GSL_EIGEN_SORT_VAL_DESC);
  double q[4], nq = 0.0;
  for (int k = 0; k < 4; k++) { q[k] = gsl_matrix_get(evec, (size_t)k, 0); nq += q[k] * q[k]; }
  gsl_vector_free(eval); gsl_matrix_free(evec); gsl_eigen_symmv_free(w);
  nq = sqrt(nq);
  double qw = q[0] / nq, qx = q[1] / nq, qy = q[2] / nq, qz = q[3] / nq;
  R[0] = qw * qw + qx * qx - qy * qy - qz * qz;
  R[1] = 2.0 * (qx * qy - qw * qz);
  R[2] = 2.0 * (qx * qz + qw * qy);
  R[3] = 2.0 * (qx * qy + qw * qz);
  R[4] = qw * qw - qx * qx + qy * qy - qz * qz;
  R[5] = 2.0 * (qy * qz - qw * qx);
  R[6] = 2.0 * (qx * qz - qw * qy);
  R[7] = 2.0 * (qy * qz + qw * qx);
  R[8] = qw * qw - qx * qx - qy * qy + qz * qz;
  return RL_OK;
}

/* ------------------------------------------------------------ residue names and atom names */

/* The species a default residue-name alias stands for: water (a species whose molecule has
 * sites O, H1, H2 and at most one more, massless), Na+ or Cl- (a species named na..., cl...
 * with one site, or whose one site is Na, Cl). */
enum { ALIAS_WATER, ALIAS_NA, ALIAS_CL };
static const struct { const char *name; int what; } res_alias[] = {
    {"HOH", ALIAS_WATER}, {"WAT", ALIAS_WATER}, {"SOL", ALIAS_WATER}, {"H2O", ALIAS_WATER},
    {"TIP3", ALIAS_WATER}, {"TIP4", ALIAS_WATER}, {"T3P", ALIAS_WATER}, {"T4P", ALIAS_WATER},
    {"T4E", ALIAS_WATER}, {"SPC", ALIAS_WATER}, {"NA", ALIAS_NA}, {"NA+", ALIAS_NA},
    {"SOD", ALIAS_NA}, {"CL", ALIAS_CL}, {"CL-", ALIAS_CL}, {"CLA", ALIAS_CL}};

static int site_named(const rl_molecule *m, const char *name)
{
  for (int a = 0; a < m->nsites; a++)
    if (!strcasecmp(m->site_names[a], name)) return a;
  return -1;
}

static int species_is(const rl_system *sys, const rl_molecule *const *mols, int k, int what)
{
  const rl_molecule *m = mols ? mols[k] : NULL;
  const char *nm = sys->sp[k].name;
  if (what == ALIAS_WATER) {
    if (!m || m->nsites < 3 || m->nsites > 4 || site_named(m, "O") < 0 || site_named(m, "H1") < 0 ||
        site_named(m, "H2") < 0)
      return 0;
    int virt = 0; /* the site besides O, H1, H2 (if any) massless; they have masses */
    for (int a = 0; a < m->nsites; a++) virt += m->site_mass[a] == 0.0;
    return virt == m->nsites - 3;
  }
  const char *el = what == ALIAS_NA ? "na" : "cl";
  if (m && m->nsites == 1 && !strcasecmp(m->site_names[0], el)) return 1;
  return (!m || m->nsites == 1) && !strncasecmp(nm, el, 2) && !isalpha((unsigned char)nm[2]);
}

/* The species of residue name res: the map's, else the species whose own name or the residue
 * name rotleap writes for it (rl_io_res_name) it is, else a default alias that fits one
 * species only.  -1: none, -2: more than one. */
static int residue_species(const rl_system *sys, const rl_molecule *const *mols, const rl_pdb_residue *map,
                           int nmap, const char *res)
{
  for (int j = 0; j < nmap; j++)
    if (!strcasecmp(map[j].name, res)) return map[j].species;
  int found = -1;
  for (int k = 0; k < sys->nspecies; k++) {
    char own[4];
    rl_io_res_name(sys, k, own);
    if (!strcasecmp(sys->sp[k].name, res) || !strcasecmp(own, res)) {
      if (found >= 0) return -2;
      found = k;
    }
  }
  if (found >= 0) return found;
  for (size_t j = 0; j < sizeof res_alias / sizeof res_alias[0]; j++) {
    if (strcasecmp(res_alias[j].name, res)) continue;
    for (int k = 0; k < sys->nspecies; k++)
      if (species_is(sys, mols, k, res_alias[j].what)) {
        if (found >= 0) return -2;
        found = k;
      }
    return found;
  }
  return -1;
}

/* Whether atom name nm (any case) names site a of species k: the site's name, rotleap's name
 * for it (MW for TIP4P's M), GROMACS's (the element letter + W: OW HW1 HW2 MW), CHARMM's OH2 for
 * O, and for the one massless site of a molecule the names codes give virtual sites (M, MW, EP
 * for OpenMM's extra particles, EPW for AMBER's, OM, LP).  A one-site species takes any name:
 * the residue name identified it. */
static int atom_is_site(const rl_system *sys, const rl_molecule *const *mols, int k, int a, int nvirt,
                        const char *nm)
{
  const rl_molecule *m = mols ? mols[k] : NULL;
  char want[8];
  rl_io_site_name(sys, mols, k, a, want);
  if (!strcasecmp(nm, want)) return 1;
  if (!m || a >= m->nsites) return 0;
  if (m->nsites == 1) return 1;
  const char *orig = m->site_names[a];
  char w[12];
  snprintf(w, sizeof w, "%c%c%s", orig[0], 'W', orig[0] ? orig + 1 : "");
  if (!strcasecmp(nm, orig) || (orig[0] && isalpha((unsigned char)orig[0]) && !strcasecmp(nm, w)) ||
      (!strcasecmp(orig, "O") && !strcasecmp(nm, "OH2")))
    return 1;
  if (m->site_mass[a] == 0.0 && nvirt == 1) {
    static const char *const virt[] = {"M", "MW", "EP", "EPW", "EP1", "OM", "LP"};
    for (size_t j = 0; j < sizeof virt / sizeof virt[0]; j++)
      if (!strcasecmp(nm, virt[j])) return 1;
  }
  return 0;
}

/* Which atom of residue r is site a (site[a]; -1: a massless site the file leaves out), by
 * position first, then by name; an error names the atom that fits no site. */
static int match_atoms(const char *path, const rl_system *sys, const rl_molecule *const *mols, int k,
                       const pdb_data *p, const pdb_res *r, int i, int *site)
{
  const rl_species *sp = &sys->sp[k];
  const rl_molecule *m = mols ? mols[k] : NULL;
  const int ns = sp->nsites > 0 ? sp->nsites : 1;
  int nvirt = 0;
  if (m && m->nsites == ns)
    for (int a = 0; a < ns; a++) nvirt += m->site_mass[a] == 0.0;
  const int missing = r->count == ns - nvirt && nvirt > 0 && ns - nvirt >= (rl_kind_is_axis(sp->kind) ? 2 : 3);
  if (r->count != ns && !missing) {
    char alt[64] = "";
    if (nvirt > 0 && ns - nvirt >= (rl_kind_is_axis(sp->kind) ? 2 : 3))
      snprintf(alt, sizeof alt, " (or %d without its massless sites)", ns - nvirt);
    return rl_error(RL_EINVAL, "%s:%d: residue %s %d (molecule %d) has %d atoms, species '%s' has %d sites%s", path,
                    r->line, r->name, r->seq, i + 1, r->count, sp->name, ns, alt);
  }
  const pdb_atom *at = &p->atoms[r->first];
  if (!m) {
    for (int a = 0; a < ns; a++) site[a] = a;
    return RL_OK;
  }
  int used[RL_MOLECULE_MAX_SITES] = {0};
  for (int a = 0; a < ns; a++) {
    site[a] = -1;
    if (a < r->count && !used[a] && atom_is_site(sys, mols, k, a, nvirt, at[a].name)) site[a] = a;
    for (int b = 0; b < r->count && site[a] < 0; b++)
      if (!used[b] && atom_is_site(sys, mols, k, a, nvirt, at[b].name)) site[a] = b;
    if (site[a] >= 0) used[site[a]] = 1;
    else if (!(missing && m->site_mass[a] == 0.0)) {
      char want[8];
      rl_io_site_name(sys, mols, k, a, want);
      int b = a < r->count && !used[a] ? a : 0; /* the atom in its place, or the first left over */
      while (b < r->count && used[b]) b++;
      if (b == r->count) b = r->count - 1;
      return rl_error(RL_EINVAL, "%s:%d: residue %s %d atom '%s' is not site %d '%s' of species '%s'%s", path,
                      at[b].line, r->name, r->seq, at[b].name, a + 1, want, sp->name,
                      a < r->count && b == a ? "" : " (and no other atom of the residue is)");
    }
  }
  return RL_OK;
}

int rl_pdb_read_state(const char *path, rl_system *sys, const rl_molecule *const *mols, double tol,
                      double *rms_max, double box[3])
{
  return rl_pdb_read_state_residues(path, sys, mols, NULL, 0, tol, rms_max, box);
}

int rl_pdb_read_state_residues(const char *path, rl_system *sys, const rl_molecule *const *mols,
                               const rl_pdb_residue *map, int nmap, double tol, double *rms_max, double box[3])
{
  if (!path || !sys || (nmap > 0 && !map) || nmap < 0)
    return rl_error(RL_EINVAL, "rl_pdb_read_state: NULL argument");
  for (int j = 0; j < nmap; j++)
    if (map[j].species < 0 || map[j].species >= sys->nspecies)
      return rl_error(RL_EINVAL, "rl_pdb_read_state: residue %.8s: species %d out of range", map[j].name, map[j].species);
  pdb_data p;
  int st = parse_pdb(path, &p);
  if (st) return st;
  double s = rl_io_length_scale(sys);
  const char *lu = sys->units == RL_UNITS_REAL ? "A" : "sigma";
  const int coarse = tol <= 0.0 && p.coarse && p.natoms > 0;
  if (tol <= 0.0) tol = (coarse ? 0.1 : 0.01) / s; /* 10x the resolution of the file's coordinates */
  /* body[ri]: the body residue ri sets; by residue name with several species or a map, else in order */
  int *body = NULL;
  int by_name = nmap > 0;
  if (!by_name && sys->nspecies > 1) { /* a mixture rl_pdb_write wrote (names as it writes them, in order) reads in order */
    by_name = p.nres != sys->n;
    for (int ri = 0; ri < p.nres && !by_name; ri++) {
      char own[4];
      rl_io_res_name(sys, sys->species_of[ri], own);
      by_name = strcasecmp(own, p.res[ri].name) != 0;
    }
  }
  if (!by_name && p.nres != sys->n) {
    st = rl_error(RL_EINVAL, "%s: %d residues (molecules), the system has %d", path, p.nres, sys->n);
    goto done;
  }
  if (by_name) {
    int seen[64] = {0}, first_line[64] = {0};
    if (sys->nspecies > 64) { st = rl_error(RL_EINVAL, "%s: more than 64 species", path); goto done; }
    if (!(body = malloc(sizeof *body * (size_t)(p.nres > 0 ? p.nres : 1)))) {
      st = rl_error(RL_ENOMEM, "%s: out of memory", path);
      goto done;
    }
    int k = -1;
    for (int ri = 0; ri < p.nres; ri++) {
      const pdb_res *r = &p.res[ri];
      if (ri == 0 || strcmp(r->name, p.res[ri - 1].name)) k = residue_species(sys, mols, map, nmap, r->name);
      if (k < 0) {
        char have[64 * 8] = "";
        for (int q = 0; q < sys->nspecies && strlen(have) < sizeof have - 80; q++)
          snprintf(have + strlen(have), sizeof have - strlen(have), "%s%s", q ? ", " : "", sys->sp[q].name);
        st = rl_error(RL_EINVAL, "%s:%d: residue %s %d: %s species of the system (%s) has the residue name '%s'; "
                      "map it to one (a deck's system.residues = %s:SPECIES)", path, r->line, r->name, r->seq,
                      k == -2 ? "more than one" : "no", have, r->name, r->name[0] ? r->name : "RES");
        goto done;
      }
      if (!seen[k]) first_line[k] = r->line;
      if (seen[k] == sys->sp[k].count) {
        st = rl_error(RL_EINVAL, "%s:%d: residue %s %d is molecule %d of species '%s' (residues from line %d), the "
                      "system has %d", path, r->line, r->name, r->seq, seen[k] + 1, sys->sp[k].name, first_line[k],
                      sys->sp[k].count);
        goto done;
      }
      body[ri] = sys->sp[k].first + seen[k]++;
    }
    for (int q = 0; q < sys->nspecies; q++)
      if (seen[q] != sys->sp[q].count) {
        st = rl_error(RL_EINVAL, "%s: %d residues of species '%s', the system has %d", path, seen[q], sys->sp[q].name,
                      sys->sp[q].count);
        goto done;
      }
  }
  double L[3];
  for (int c = 0; c < 3; c++) L[c] = p.has_box ? p.box[c] / s : 0.0;
  double worst = 0.0;
  for (int ri = 0; ri < p.nres && !st; ri++) {
    const int i = body ? body[ri] : ri;
    int k = sys->species_of[i];
    const rl_species *sp = &sys->sp[k];
    const pdb_res *r = &p.res[ri];
    int ns = sp->nsites > 0 ? sp->nsites : 1;
    if (ns > RL_MOLECULE_MAX_SITES) { st = rl_error(RL_EINVAL, "%s: species '%s' has too many sites", path, sp->name); break; }
    int site[RL_MOLECULE_MAX_SITES];
    if ((st = match_atoms(path, sys, mols, k, &p, r, i, site))) break;
    const pdb_atom *at = &p.atoms[r->first];
    /* the sites the file holds (a massless one may be left out: the fit places it) */
    int np = 0, idx[RL_MOLECULE_MAX_SITES];
    for (int a = 0; a < ns; a++)
      if (site[a] >= 0) idx[np++] = a;
    const double *ref = at[site[idx[0]]].x;
    double y[RL_MOLECULE_MAX_SITES][3], z[RL_MOLECULE_MAX_SITES][3], yc[3] = {0, 0, 0}, zc[3] = {0, 0, 0};
    for (int q = 0; q < np; q++)
      for (int c = 0; c < 3; c++) {
        const int a = idx[q];
        double v = at[site[a]].x[c] / s;
        if (q > 0 && L[c] > 0.0) v -= L[c] * round((v - ref[c] / s) / L[c]); /* make whole */
        y[q][c] = v;
        z[q][c] = sp->nsites > 0 ? sp->sites[3 * a + c] : 0.0;
        yc[c] += v / np;
        zc[c] += z[q][c] / np;
      }
    double A[9];
    rl_system_get_orientation(sys, i, A);
    double R[9] = {A[0], A[3], A[6], A[1], A[4], A[7], A[2], A[5], A[8]}; /* keep: A^T */
    if (ns >= 2 && sp->kind != RL_KIND_POINT) {
      for (int a = 0; a < np; a++)
        for (int c = 0; c < 3; c++) { y[a][c] -= yc[c]; z[a][c] -= zc[c]; }
      if ((st = fit_rotation(np, (const double(*)[3])z, (const double(*)[3])y, R))) {
        st = rl_error(st, "%s:%d: residue %s %d: out of memory in the fit", path, r->line, r->name, r->seq);
        break;
      }
      for (int a = 0; a < np; a++)
        for (int c = 0; c < 3; c++) { y[a][c] += yc[c]; z[a][c] += zc[c]; }
    }
    /* centre: r = ybar - R zbar; RMS of y_a - (r + R z_a) */
    double rc[3], ss = 0.0;
    for (int c = 0; c < 3; c++) rc[c] = yc[c] - (R[3 * c] * zc[0] + R[3 * c + 1] * zc[1] + R[3 * c + 2] * zc[2]);
    for (int a = 0; a < np; a++)
      for (int c = 0; c < 3; c++) {
        double d = y[a][c] - rc[c] - (R[3 * c] * z[a][0] + R[3 * c + 1] * z[a][1] + R[3 * c + 2] * z[a][2]);
        ss += d * d;
      }
    double rms = sqrt(ss / np);
    if (!(rms <= tol)) {
      st = rl_error(RL_EINVAL, "%s:%d: residue %s %d (molecule %d): its geometry does not match species "
                    "'%s': RMS fit error %.4g %s > tolerance %.4g %s%s",
                    path, r->line, r->name, r->seq, i + 1, sp->name, rms * s, lu, tol * s, lu,
                    coarse ? " (10x the resolution of the file's coordinates, whose third decimals are all 0)" : "");
      break;
    }
    if (rms > worst) worst = rms;
    if ((st = rl_system_set_position(sys, i, rc))) { st = rl_error_wrap(st, "%s:%d", path, r->line); break; }
    if (ns >= 2 && sp->kind != RL_KIND_POINT) {
      double At[9] = {R[0], R[3], R[6], R[1], R[4], R[7], R[2], R[5], R[8]};
      if (rl_kind_is_axis(sp->kind)) {
        double n = sqrt(At[6] * At[6] + At[7] * At[7] + At[8] * At[8]);
        double rho[3] = {At[6] / n, At[7] / n, At[8] / n};
        st = rl_system_set_axis(sys, i, rho);
      } else {
        st = rl_system_set_orientation(sys, i, At);
      }
      if (st) { st = rl_error_wrap(st, "%s:%d", path, r->line); break; }
    }
  }
  if (!st) {
    if (rms_max) *rms_max = worst;
    if (box) for (int c = 0; c < 3; c++) box[c] = L[c];
  }
done:
  free(body);
  pdb_data_free(&p);
  return st;
}
