/* The system of rigid bodies: species table and contiguous state arrays. */
#include "system_impl.h"
#include "rotleap/error.h"
#include "rotleap/geometry.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

rl_system *rl_system_alloc(rl_units units)
{
  rl_system *s = calloc(1, sizeof *s);
  if (!s) { rl_error(RL_ENOMEM, "rl_system_alloc: out of memory"); return NULL; }
  s->units = units;
  s->kB = rl_units_kB(units);
  s->removed_dof = 3;
  return s;
}

void rl_system_free(rl_system *s)
{
  if (!s) return;
  for (int i = 0; i < s->nspecies; i++) free(s->sp[i].sites);
  free(s->sp);
  free(s->species_of);
  free(s->r);
  free(s->v);
  free(s->l);
  free(s->A);
  free(s->rho);
  free(s);
}

const char *rl_kind_name(rl_kind k)
{
  switch (k) {
  case RL_KIND_POINT: return "point";
  case RL_KIND_DIPOLE: return "dipole";
  case RL_KIND_LINEAR: return "linear";
  case RL_KIND_SPHERICAL: return "spherical";
  case RL_KIND_SYMMETRIC: return "symmetric";
  case RL_KIND_ASYMMETRIC: return "asymmetric";
  case RL_KIND_AUTO: return "auto";
  }
  return "?";
}

int rl_kind_rotational_dof(rl_kind k)
{
  if (k == RL_KIND_POINT) return 0;
  return rl_kind_is_axis(k) ? 2 : 3;
}

static int close_moments(double a, double b, double scale)
{
  return fabs(a - b) <= RL_INERTIA_RTOL * scale;
}

rl_kind rl_classify_inertia(const double J[3])
{
  double mx = fmax(J[0], fmax(J[1], J[2]));
  if (!(mx > 0.0)) return RL_KIND_POINT;
  int zero = 0;
  for (int i = 0; i < 3; i++) zero += J[i] <= RL_INERTIA_RTOL * mx;
  if (zero >= 1) return RL_KIND_LINEAR;
  int e01 = close_moments(J[0], J[1], mx), e12 = close_moments(J[1], J[2], mx),
      e02 = close_moments(J[0], J[2], mx);
  if (e01 && e12 && e02) return RL_KIND_SPHERICAL;
  if (e01 || e12 || e02) return RL_KIND_SYMMETRIC;
  return RL_KIND_ASYMMETRIC;
}

static int grow(void **p, size_t elem, int n)
{
  void *q = realloc(*p, elem * (size_t)(n > 0 ? n : 1));
  if (!q) return 0;
  *p = q;
  return 1;
}

static int finite3(const double a[3]) { return isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]); }

int rl_system_add_species(rl_system *s, const rl_species_desc *d, int count, int *species)
{
  const char *nm = d && d->name ? d->name : "(unnamed)";
  if (!s || !d) return rl_error(RL_EINVAL, "rl_system_add_species: NULL argument");
  if (count < 0) return rl_error(RL_EINVAL, "species %s: count %d is negative", nm, count);
  if (!(d->mass > 0.0) || !isfinite(d->mass))
    return rl_error(RL_EINVAL, "species %s: mass %g must be positive and finite", nm, d->mass);
  if (d->nsites < 0 || (d->nsites > 0 && !d->sites))
    return rl_error(RL_EINVAL, "species %s: nsites = %d but no site positions", nm, d->nsites);
  rl_kind kind = d->kind;
  const double *J = d->inertia;
  if (kind != RL_KIND_POINT) {
    for (int a = 0; a < 3; a++)
      if (!isfinite(J[a]) || J[a] < 0.0)
        return rl_error(RL_EINVAL, "species %s: principal moment J[%d] = %g must be finite and "
                        ">= 0", nm, a, J[a]);
  }
  if (kind == RL_KIND_AUTO) kind = rl_classify_inertia(J);
  double mx = fmax(J[0], fmax(J[1], J[2]));
  switch (kind) {
  case RL_KIND_POINT: break;
  case RL_KIND_DIPOLE:
    if (!(J[0] > 0.0) || !close_moments(J[0], J[1], mx) ||
        !(close_moments(J[2], J[0], mx) || J[2] == 0.0))
      return rl_error(RL_EINVAL, "species %s: a point dipole needs spherical inertia I, I, I "
                      "(or I, I, 0), got %g %g %g", nm, J[0], J[1], J[2]);
    break;
  case RL_KIND_LINEAR:
    if (!(J[0] > 0.0) || !close_moments(J[0], J[1], mx) || J[2] > RL_INERTIA_RTOL * mx)
      return rl_error(RL_EINVAL, "species %s: a linear molecule needs moments J, J, 0 with its "
                      "axis along body Z, got %g %g %g", nm, J[0], J[1], J[2]);
    break;
  default:
    for (int a = 0; a < 3; a++)
      if (!(J[a] > 0.0))
        return rl_error(RL_EINVAL, "species %s: %s body needs positive principal moments, "
                        "J[%d] = %g", nm, rl_kind_name(kind), a, J[a]);
    if (J[0] > J[1] + J[2] || J[1] > J[0] + J[2] || J[2] > J[0] + J[1])
      return rl_error(RL_EINVAL, "species %s: moments %g %g %g violate the triangle "
                      "inequality J_a <= J_b + J_c", nm, J[0], J[1], J[2]);
    if (kind == RL_KIND_SPHERICAL &&
        !(close_moments(J[0], J[1], mx) && close_moments(J[1], J[2], mx)))
      return rl_error(RL_EINVAL, "species %s: spherical top needs equal moments, got %g %g %g",
                      nm, J[0], J[1], J[2]);
    if (kind == RL_KIND_SYMMETRIC && !(close_moments(J[0], J[1], mx) ||
                                       close_moments(J[1], J[2], mx) ||
                                       close_moments(J[0], J[2], mx)))
      return rl_error(RL_EINVAL, "species %s: symmetric top needs two equal moments, got %g %g %g",
                      nm, J[0], J[1], J[2]);
    break;
  }
  for (int a = 0; a < d->nsites; a++) {
    const double *p = d->sites + 3 * a;
    if (!finite3(p)) return rl_error(RL_ENONFINITE, "species %s: site %d is not finite", nm, a);
    if (rl_kind_is_axis(kind) && (p[0] != 0.0 || p[1] != 0.0))
      return rl_error(RL_EINVAL, "species %s: %s species must have its sites on body Z; site %d "
                      "is at (%g, %g, %g)", nm, rl_kind_name(kind), a, p[0], p[1], p[2]);
    if (kind == RL_KIND_POINT && (p[0] != 0.0 || p[1] != 0.0 || p[2] != 0.0))
      return rl_error(RL_EINVAL, "species %s: a point species has its sites at the centre", nm);
  }

  if (s->nspecies == s->cap_species) {
    int cap = s->cap_species ? 2 * s->cap_species : 4;
    if (!grow((void **)&s->sp, sizeof *s->sp, cap)) return rl_error(RL_ENOMEM, "out of memory");
    s->cap_species = cap;
  }
  rl_species sp;
  memset(&sp, 0, sizeof sp);
  strncpy(sp.name, nm, sizeof sp.name - 1);
  sp.kind = kind;
  sp.mass = d->mass;
  memcpy(sp.J, J, sizeof sp.J);
  sp.perm[0] = 0; sp.perm[1] = 1; sp.perm[2] = 2;
  if (kind == RL_KIND_SYMMETRIC) { /* unique axis u becomes Z of the cyclic relabelling */
    int u = close_moments(J[0], J[1], mx) ? 2 : close_moments(J[1], J[2], mx) ? 0 : 1;
    sp.perm[0] = (u + 1) % 3; sp.perm[1] = (u + 2) % 3; sp.perm[2] = u;
  }
  sp.nsites = d->nsites;
  sp.first = s->n;
  sp.count = count;
  sp.site_off = s->nsites_total;
  sp.rot_off = kind == RL_KIND_POINT ? -1 : s->nrot;
  sp.mat_off = rl_kind_is_matrix(kind) ? s->nmat : -1;
  sp.axis_off = rl_kind_is_axis(kind) ? s->naxis : -1;
  if (d->nsites > 0) {
    sp.sites = malloc(sizeof(double) * 3 * (size_t)d->nsites);
    if (!sp.sites) return rl_error(RL_ENOMEM, "out of memory");
    memcpy(sp.sites, d->sites, sizeof(double) * 3 * (size_t)d->nsites);
  }

  int n = s->n + count;
  int nrot = s->nrot + (kind == RL_KIND_POINT ? 0 : count);
  int nmat = s->nmat + (rl_kind_is_matrix(kind) ? count : 0);
  int naxis = s->naxis + (rl_kind_is_axis(kind) ? count : 0);
  if (!grow((void **)&s->r, sizeof *s->r, n) || !grow((void **)&s->v, sizeof *s->v, n) ||
      !grow((void **)&s->species_of, sizeof *s->species_of, n) ||
      !grow((void **)&s->l, sizeof *s->l, nrot) || !grow((void **)&s->A, sizeof *s->A, nmat) ||
      !grow((void **)&s->rho, sizeof *s->rho, naxis)) {
    free(sp.sites);
    return rl_error(RL_ENOMEM, "rl_system_add_species: out of memory for %d bodies", n);
  }
  for (int i = s->n; i < n; i++) {
    s->species_of[i] = s->nspecies;
    memset(s->r[i], 0, sizeof s->r[i]);
    memset(s->v[i], 0, sizeof s->v[i]);
  }
  for (int i = s->nrot; i < nrot; i++) memset(s->l[i], 0, sizeof s->l[i]);
  for (int i = s->nmat; i < nmat; i++) {
    static const double I9[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(s->A[i], I9, sizeof I9);
  }
  for (int i = s->naxis; i < naxis; i++) { s->rho[i][0] = 0; s->rho[i][1] = 0; s->rho[i][2] = 1; }
  s->n = n; s->nrot = nrot; s->nmat = nmat; s->naxis = naxis;
  s->nsites_total += count * d->nsites;
  s->sp[s->nspecies] = sp;
  if (species) *species = s->nspecies;
  s->nspecies++;
  return RL_OK;
}

int rl_system_count(const rl_system *s) { return s->n; }
int rl_system_nspecies(const rl_system *s) { return s->nspecies; }
int rl_system_species_of(const rl_system *s, int i) { return s->species_of[i]; }
rl_kind rl_system_species_kind(const rl_system *s, int k) { return s->sp[k].kind; }
const char *rl_system_species_name(const rl_system *s, int k) { return s->sp[k].name; }
int rl_system_species_nsites(const rl_system *s, int k) { return s->sp[k].nsites; }
int rl_system_species_count(const rl_system *s, int k) { return s->sp[k].count; }
int rl_system_nsites(const rl_system *s) { return s->nsites_total; }
double rl_system_mass(const rl_system *s, int i) { return s->sp[s->species_of[i]].mass; }
void rl_system_inertia(const rl_system *s, int i, double J[3])
{
  memcpy(J, s->sp[s->species_of[i]].J, 3 * sizeof(double));
}
rl_units rl_system_units(const rl_system *s) { return s->units; }
double rl_system_kB(const rl_system *s) { return s->kB; }
void rl_system_set_removed_dof(rl_system *s, int removed) { s->removed_dof = removed; }
int rl_system_dof_translational(const rl_system *s) { return 3 * s->n - s->removed_dof; }
int rl_system_dof_rotational(const rl_system *s)
{
  int g = 0;
  for (int k = 0; k < s->nspecies; k++) g += s->sp[k].count * rl_kind_rotational_dof(s->sp[k].kind);
  return g;
}
int rl_system_dof(const rl_system *s)
{
  return rl_system_dof_translational(s) + rl_system_dof_rotational(s);
}

int rl_system_state_bytes(const rl_system *s, int k)
{
  const rl_species *sp = &s->sp[k];
  int b = (int)(sizeof s->r[0] + sizeof s->v[0]);
  if (sp->rot_off >= 0) b += (int)sizeof s->l[0];
  if (sp->mat_off >= 0) b += (int)sizeof s->A[0];
  if (sp->axis_off >= 0) b += (int)sizeof s->rho[0];
  return b;
}

int rl_system_rot_index(const rl_system *s, int i)
{
  const rl_species *sp = &s->sp[s->species_of[i]];
  return sp->rot_off < 0 ? -1 : sp->rot_off + (i - sp->first);
}
int rl_system_nrot(const rl_system *s) { return s->nrot; }
double (*rl_system_r(rl_system *s))[3] { return s->r; }
double (*rl_system_v(rl_system *s))[3] { return s->v; }

static int check_body(const rl_system *s, int i, const char *who)
{
  if (i < 0 || i >= s->n)
    return rl_error(RL_EINVAL, "%s: body %d out of range (system has %d)", who, i, s->n);
  return RL_OK;
}

int rl_system_set_position(rl_system *s, int i, const double r[3])
{
  int st = check_body(s, i, "rl_system_set_position");
  if (st) return st;
  if (!finite3(r)) return rl_error(RL_ENONFINITE, "rl_system_set_position: body %d: non-finite", i);
  memcpy(s->r[i], r, sizeof s->r[i]);
  return RL_OK;
}

int rl_system_set_velocity(rl_system *s, int i, const double v[3])
{
  int st = check_body(s, i, "rl_system_set_velocity");
  if (st) return st;
  if (!finite3(v)) return rl_error(RL_ENONFINITE, "rl_system_set_velocity: body %d: non-finite", i);
  memcpy(s->v[i], v, sizeof s->v[i]);
  return RL_OK;
}

int rl_system_set_angmom(rl_system *s, int i, const double l[3])
{
  int st = check_body(s, i, "rl_system_set_angmom");
  if (st) return st;
  if (!finite3(l)) return rl_error(RL_ENONFINITE, "rl_system_set_angmom: body %d: non-finite", i);
  int ri = rl_system_rot_index(s, i);
  if (ri < 0) return rl_error(RL_EINVAL, "rl_system_set_angmom: body %d is a point particle", i);
  memcpy(s->l[ri], l, sizeof s->l[ri]);
  return RL_OK;
}

int rl_check_rotation(const double A[9], const char *who, int body)
{
  for (int k = 0; k < 9; k++)
    if (!isfinite(A[k]))
      return rl_error(RL_ENONFINITE, "%s: body %d: orientation has a non-finite element", who, body);
  double e = rl_orthonormality_error(A);
  if (!(e <= 1e-10))
    return rl_error(RL_EORTHO, "%s: body %d: orientation matrix is not orthonormal "
                    "(max |A^T A - I| = %.3g > 1e-10)", who, body, e);
  double det = A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
               A[2] * (A[3] * A[7] - A[4] * A[6]);
  if (det < 0.0)
    return rl_error(RL_EORTHO, "%s: body %d: orientation matrix is a reflection (det = %g)", who,
                    body, det);
  return RL_OK;
}

static int check_unit(const double rho[3], const char *who, int i)
{
  if (!finite3(rho)) return rl_error(RL_ENONFINITE, "%s: body %d: axis is not finite", who, i);
  double n = sqrt(rho[0] * rho[0] + rho[1] * rho[1] + rho[2] * rho[2]);
  if (!(fabs(n - 1.0) <= 1e-10))
    return rl_error(RL_EORTHO, "%s: body %d: axis is not a unit vector (|rho| - 1 = %.3g)", who, i,
                    n - 1.0);
  return RL_OK;
}

void rl_frame_from_axis(const double rho[3], double A[9])
{
  double ax[3] = {fabs(rho[0]) < 0.9 ? 1.0 : 0.0, fabs(rho[0]) < 0.9 ? 0.0 : 1.0, 0.0};
  double d = ax[0] * rho[0] + ax[1] * rho[1];
  double x[3] = {ax[0] - d * rho[0], ax[1] - d * rho[1], -d * rho[2]};
  double nx = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
  for (int k = 0; k < 3; k++) x[k] /= nx;
  A[0] = x[0]; A[1] = x[1]; A[2] = x[2];
  A[3] = rho[1] * x[2] - rho[2] * x[1];
  A[4] = rho[2] * x[0] - rho[0] * x[2];
  A[5] = rho[0] * x[1] - rho[1] * x[0];
  A[6] = rho[0]; A[7] = rho[1]; A[8] = rho[2];
}

int rl_system_set_orientation(rl_system *s, int i, const double A[9])
{
  int st = check_body(s, i, "rl_system_set_orientation");
  if (st) return st;
  const rl_species *sp = &s->sp[s->species_of[i]];
  if (sp->kind == RL_KIND_POINT) return RL_OK; /* a point has no orientation: nothing to keep */
  if ((st = rl_check_rotation(A, "rl_system_set_orientation", i))) return st;
  if (sp->mat_off >= 0) memcpy(s->A[sp->mat_off + i - sp->first], A, 9 * sizeof(double));
  else memcpy(s->rho[sp->axis_off + i - sp->first], A + 6, 3 * sizeof(double));
  return RL_OK;
}

int rl_system_set_axis(rl_system *s, int i, const double rho[3])
{
  int st = check_body(s, i, "rl_system_set_axis");
  if (st) return st;
  const rl_species *sp = &s->sp[s->species_of[i]];
  if ((st = check_unit(rho, "rl_system_set_axis", i))) return st;
  if (sp->axis_off >= 0) { memcpy(s->rho[sp->axis_off + i - sp->first], rho, 3 * sizeof(double)); return RL_OK; }
  if (sp->kind == RL_KIND_POINT) return RL_OK;
  rl_frame_from_axis(rho, s->A[sp->mat_off + i - sp->first]); /* matrix kind: Z row is rho */
  return RL_OK;
}

void rl_system_get_position(const rl_system *s, int i, double r[3]) { memcpy(r, s->r[i], sizeof s->r[i]); }
void rl_system_get_velocity(const rl_system *s, int i, double v[3]) { memcpy(v, s->v[i], sizeof s->v[i]); }
void rl_system_get_angmom(const rl_system *s, int i, double l[3])
{
  int ri = rl_system_rot_index(s, i);
  if (ri < 0) { l[0] = l[1] = l[2] = 0.0; return; }
  memcpy(l, s->l[ri], sizeof s->l[ri]);
}

void rl_system_get_axis(const rl_system *s, int i, double rho[3])
{
  const rl_species *sp = &s->sp[s->species_of[i]];
  if (sp->axis_off >= 0) memcpy(rho, s->rho[sp->axis_off + i - sp->first], 3 * sizeof(double));
  else if (sp->mat_off >= 0) memcpy(rho, s->A[sp->mat_off + i - sp->first] + 6, 3 * sizeof(double));
  else { rho[0] = 0; rho[1] = 0; rho[2] = 1; }
}

void rl_system_get_orientation(const rl_system *s, int i, double A[9])
{
  const rl_species *sp = &s->sp[s->species_of[i]];
  if (sp->mat_off >= 0) { memcpy(A, s->A[sp->mat_off + i - sp->first], 9 * sizeof(double)); return; }
  static const double I9[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  if (sp->axis_off < 0) memcpy(A, I9, sizeof I9);
  else rl_frame_from_axis(s->rho[sp->axis_off + i - sp->first], A);
}

int rl_system_site_offset(const rl_system *s, int i)
{
  const rl_species *sp = &s->sp[s->species_of[i]];
  return sp->site_off + (i - sp->first) * sp->nsites;
}

void rl_system_site_positions_of(const rl_system *s, int i0, int i1, double (*out)[3])
{
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    const int b0 = i0 > sp->first ? i0 - sp->first : 0;
    const int b1 = i1 < sp->first + sp->count ? i1 - sp->first : sp->count;
    for (int b = b0; b < b1; b++) {
      int i = sp->first + b, o = sp->site_off + b * sp->nsites;
      const double *r = s->r[i];
      for (int a = 0; a < sp->nsites; a++) {
        const double *d = sp->sites + 3 * a;
        if (sp->mat_off >= 0) {
          const double *A = s->A[sp->mat_off + b]; /* r + A^T d */
          for (int c = 0; c < 3; c++) out[o + a][c] = r[c] + A[c] * d[0] + A[3 + c] * d[1] + A[6 + c] * d[2];
        } else if (sp->axis_off >= 0) {
          const double *rho = s->rho[sp->axis_off + b];
          for (int c = 0; c < 3; c++) out[o + a][c] = r[c] + d[2] * rho[c];
        } else {
          for (int c = 0; c < 3; c++) out[o + a][c] = r[c];
        }
      }
    }
  }
}

void rl_system_site_positions(const rl_system *s, double (*out)[3])
{
  rl_system_site_positions_of(s, 0, s->n, out);
}

int rl_system_set_cell(rl_system *s, const double h[9])
{
  int zero = 1;
  for (int k = 0; k < 9; k++) {
    if (!isfinite(h[k])) return rl_error(RL_ENONFINITE, "box: element %d of the cell matrix is %g, not finite", k, h[k]);
    zero &= h[k] == 0.0;
  }
  if (!zero) {
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++)
        if (a != b && h[3 * a + b] != 0.0)
          return rl_error(RL_EINVAL, "box: a triclinic cell (element %d%d = %g off the diagonal) is not supported; "
                          "give an orthorhombic box", a + 1, b + 1, h[3 * a + b]);
    for (int a = 0; a < 3; a++)
      if (!(h[4 * a] > 0.0))
        return rl_error(RL_EINVAL, "box: edge %c = %g must be positive (or every edge 0: no box)", "xyz"[a], h[4 * a]);
  }
  if (memcmp(s->cell, h, sizeof s->cell)) {
    memcpy(s->cell, h, sizeof s->cell);
    s->box_version++;
  }
  return RL_OK;
}

int rl_system_set_box(rl_system *s, const double L[3])
{
  const double h[9] = {L[0], 0, 0, 0, L[1], 0, 0, 0, L[2]};
  return rl_system_set_cell(s, h);
}

void rl_system_cell(const rl_system *s, double h[9]) { memcpy(h, s->cell, sizeof s->cell); }
void rl_system_box(const rl_system *s, double L[3])
{
  for (int a = 0; a < 3; a++) L[a] = s->cell[4 * a];
}
double rl_system_volume(const rl_system *s) { return s->cell[0] * s->cell[4] * s->cell[8]; }
int rl_system_periodic(const rl_system *s) { return s->cell[0] > 0.0; }
unsigned long rl_system_box_version(const rl_system *s) { return s->box_version; }

rl_system *rl_system_clone(const rl_system *s)
{
  rl_system *c = rl_system_alloc(s->units);
  if (!c) return NULL;
  c->removed_dof = s->removed_dof;
  memcpy(c->cell, s->cell, sizeof c->cell);
  c->box_version = s->box_version;
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    rl_species_desc d = {sp->name, sp->kind, sp->mass, {sp->J[0], sp->J[1], sp->J[2]}, sp->nsites, sp->sites};
    if (rl_system_add_species(c, &d, sp->count, NULL)) { rl_system_free(c); return NULL; }
  }
  memcpy(c->r, s->r, sizeof *s->r * (size_t)s->n);
  memcpy(c->v, s->v, sizeof *s->v * (size_t)s->n);
  if (s->nrot) memcpy(c->l, s->l, sizeof *s->l * (size_t)s->nrot);
  if (s->nmat) memcpy(c->A, s->A, sizeof *s->A * (size_t)s->nmat);
  if (s->naxis) memcpy(c->rho, s->rho, sizeof *s->rho * (size_t)s->naxis);
  return c;
}

static void random_rotation(gsl_rng *r, double A[9])
{
  double q[4], n = 0.0;
  for (int k = 0; k < 4; k++) { q[k] = gsl_ran_gaussian(r, 1.0); n += q[k] * q[k]; }
  n = sqrt(n);
  for (int k = 0; k < 4; k++) q[k] /= n;
  rl_quat_to_matrix(q, A);
}

int rl_system_lattice(rl_system *s, const double L[3], rl_lattice lat, int random, unsigned long seed)
{
  if (!(L[0] > 0 && L[1] > 0 && L[2] > 0) || !finite3(L))
    return rl_error(RL_EINVAL, "lattice: box %g %g %g must be positive and finite", L[0], L[1], L[2]);
  if (lat != RL_LATTICE_SC && lat != RL_LATTICE_FCC) return rl_error(RL_EINVAL, "lattice: unknown type %d", (int)lat);
  const int st = rl_system_set_box(s, L);
  if (st) return st;
  int per = lat == RL_LATTICE_FCC ? 4 : 1;
  /* cells per edge: smallest n with per n^3 >= N (cubic cells in a cubic box) */
  int nc = 1;
  while (per * nc * nc * nc < s->n) nc++;
  static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  if (!r) return rl_error(RL_ENOMEM, "out of memory");
  gsl_rng_set(r, seed);
  for (int i = 0; i < s->n; i++) {
    int cell = i / per, b = i % per, cx = cell % nc, cy = cell / nc % nc, cz = cell / (nc * nc);
    double x[3] = {(cx + basis[b][0] + 0.25) * L[0] / nc, (cy + basis[b][1] + 0.25) * L[1] / nc,
                   (cz + basis[b][2] + 0.25) * L[2] / nc};
    memcpy(s->r[i], x, sizeof x);
    double A[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    if (random) random_rotation(r, A);
    const rl_species *sp = &s->sp[s->species_of[i]];
    if (sp->mat_off >= 0) memcpy(s->A[sp->mat_off + i - sp->first], A, sizeof A);
    else if (sp->axis_off >= 0) memcpy(s->rho[sp->axis_off + i - sp->first], A + 6, 3 * sizeof(double));
  }
  gsl_rng_free(r);
  return RL_OK;
}

int rl_system_maxwell_boltzmann(rl_system *s, double T, unsigned long seed)
{
  if (!(T >= 0.0) || !isfinite(T)) return rl_error(RL_EINVAL, "Maxwell-Boltzmann: temperature %g must be >= 0", T);
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  if (!r) return rl_error(RL_ENOMEM, "out of memory");
  gsl_rng_set(r, seed);
  double kT = s->kB * T, P[3] = {0, 0, 0}, M = 0.0;
  for (int k = 0; k < s->nspecies; k++) {
    const rl_species *sp = &s->sp[k];
    for (int b = 0; b < sp->count; b++) {
      int i = sp->first + b;
      for (int c = 0; c < 3; c++) { s->v[i][c] = gsl_ran_gaussian(r, sqrt(kT / sp->mass)); P[c] += sp->mass * s->v[i][c]; }
      M += sp->mass;
      if (sp->rot_off < 0) continue;
      double *l = s->l[sp->rot_off + b];
      if (sp->axis_off >= 0) { /* l = sqrt(kT J) (g1 e1 + g2 e2), e1, e2 perpendicular to rho */
        double A[9];
        rl_system_get_orientation(s, i, A);
        double g1 = gsl_ran_gaussian(r, sqrt(kT * sp->J[0])), g2 = gsl_ran_gaussian(r, sqrt(kT * sp->J[0]));
        for (int c = 0; c < 3; c++) l[c] = g1 * A[c] + g2 * A[3 + c];
      } else { /* body components L_a ~ N(0, kT J_a), l = A^T L */
        const double *A = s->A[sp->mat_off + b];
        double Lb[3];
        for (int a = 0; a < 3; a++) Lb[a] = gsl_ran_gaussian(r, sqrt(kT * sp->J[a]));
        for (int c = 0; c < 3; c++) l[c] = A[c] * Lb[0] + A[3 + c] * Lb[1] + A[6 + c] * Lb[2];
      }
    }
  }
  for (int i = 0; i < s->n && M > 0.0; i++)
    for (int c = 0; c < 3; c++) s->v[i][c] -= P[c] / M;
  gsl_rng_free(r);
  return RL_OK;
}
