/* Molecule types from sites: centre of mass, inertia tensor, principal axes (GSL), the body
 * frame, and classification into the cheapest exact family.  Contract in rotleap/molecule.h. */
#include "rotleap/molecule.h"
#include "rotleap/error.h"
#include "../core/system_impl.h"

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_math.h>
#include <math.h>
#include <string.h>

static int finite_n(const double *x, int n)
{
  for (int i = 0; i < n; i++)
    if (!isfinite(x[i])) return 0;
  return 1;
}

/* Eigen-decomposition of the symmetric 3x3 tensor T: ascending values, vectors as rows of V. */
static int principal_axes(const double T[9], double lam[3], double V[9])
{
  double t[9];
  memcpy(t, T, sizeof t);
  gsl_matrix_view m = gsl_matrix_view_array(t, 3, 3);
  gsl_vector *eval = gsl_vector_alloc(3);
  gsl_matrix *evec = gsl_matrix_alloc(3, 3);
  gsl_eigen_symmv_workspace *w = gsl_eigen_symmv_alloc(3);
  if (!eval || !evec || !w) {
    gsl_vector_free(eval); gsl_matrix_free(evec); gsl_eigen_symmv_free(w);
    return rl_error(RL_ENOMEM, "out of memory");
  }
  gsl_eigen_symmv(&m.matrix, eval, evec, w);
  gsl_eigen_symmv_sort(eval, evec, GSL_EIGEN_SORT_VAL_ASC);
  for (int k = 0; k < 3; k++) {
    lam[k] = gsl_vector_get(eval, k);
    for (int c = 0; c < 3; c++) V[3 * k + c] = gsl_matrix_get(evec, c, k);
  }
  gsl_eigen_symmv_free(w);
  gsl_matrix_free(evec);
  gsl_vector_free(eval);
  return RL_OK;
}

static double det3(const double V[9])
{
  return V[0] * (V[4] * V[8] - V[5] * V[7]) - V[1] * (V[3] * V[8] - V[5] * V[6]) +
         V[2] * (V[3] * V[7] - V[4] * V[6]);
}

static void cross(const double a[3], const double b[3], double c[3])
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

/* Rows x, y, z of V: make the frame right-handed by recomputing x = y cross z. */
static void right_handed(double V[9])
{
  if (det3(V) < 0.0) cross(V + 3, V + 6, V);
}

int rl_molecule_build(const rl_molecule_def *def, int force_general, rl_molecule *m)
{
  const char *nm = def && def->name ? def->name : "(unnamed)";
  if (!def || !m) return rl_error(RL_EINVAL, "rl_molecule_build: NULL argument");
  int n = def->nsites;
  if (n < 1 || n > RL_MOLECULE_MAX_SITES)
    return rl_error(RL_EINVAL, "molecule %s: %d sites (1 to %d allowed)", nm, n, RL_MOLECULE_MAX_SITES);
  if (!def->pos || !def->mass) return rl_error(RL_EINVAL, "molecule %s: site positions and masses are required", nm);
  memset(m, 0, sizeof *m);
  strncpy(m->name, nm, sizeof m->name - 1);
  m->nsites = n;
  double M = 0.0;
  for (int a = 0; a < n; a++) {
    const char *sn = def->site_names && def->site_names[a] ? def->site_names[a] : "X";
    strncpy(m->site_names[a], sn, sizeof m->site_names[a] - 1);
    if (!finite_n(def->pos + 3 * a, 3))
      return rl_error(RL_ENONFINITE, "molecule %s: site %d (%s): position is not finite", nm, a, sn);
    double ma = def->mass[a];
    if (!(ma >= 0.0) || !isfinite(ma))
      return rl_error(RL_EINVAL, "molecule %s: site %d (%s): mass %g must be >= 0 and finite", nm, a, sn, ma);
    m->site_mass[a] = ma;
    m->sigma[a] = def->sigma ? def->sigma[a] : 0.0;
    m->epsilon[a] = def->epsilon ? def->epsilon[a] : 0.0;
    m->charge[a] = def->charge ? def->charge[a] : 0.0;
    m->quadrupole[a] = def->quadrupole ? def->quadrupole[a] : 0.0;
    if (!isfinite(m->sigma[a]) || !isfinite(m->epsilon[a]) || !isfinite(m->charge[a]) ||
        !isfinite(m->quadrupole[a]) || (def->dipole && !finite_n(def->dipole + 3 * a, 3)))
      return rl_error(RL_ENONFINITE, "molecule %s: site %d (%s): a parameter is not finite", nm, a, sn);
    if (m->sigma[a] < 0.0 || m->epsilon[a] < 0.0)
      return rl_error(RL_EINVAL, "molecule %s: site %d (%s): sigma %g and epsilon %g must be >= 0",
                      nm, a, sn, m->sigma[a], m->epsilon[a]);
    if (m->quadrupole[a] != 0.0) m->has_quadrupole = 1;
    if (def->dipole && (def->dipole[3 * a] != 0.0 || def->dipole[3 * a + 1] != 0.0 || def->dipole[3 * a + 2] != 0.0))
      m->has_dipole = 1;
    M += ma;
  }
  if (!(M > 0.0)) return rl_error(RL_EINVAL, "molecule %s: total mass is zero", nm);
  m->mass = M;
  for (int c = 0; c < 3; c++) {
    double s = 0.0;
    for (int a = 0; a < n; a++) s += m->site_mass[a] * def->pos[3 * a + c];
    m->com[c] = s / M;
  }
  double T[9] = {0}, ext = 0.0;
  for (int a = 0; a < n; a++) {
    double d[3] = {def->pos[3 * a] - m->com[0], def->pos[3 * a + 1] - m->com[1], def->pos[3 * a + 2] - m->com[2]};
    double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], w = m->site_mass[a];
    ext = fmax(ext, sqrt(d2));
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) T[3 * i + j] += w * ((i == j ? d2 : 0.0) - d[i] * d[j]);
  }
  double lam[3], V[9];
  int st = principal_axes(T, lam, V);
  if (st) return st;
  const double rtol = def->inertia_rtol > 0.0 ? def->inertia_rtol : RL_INERTIA_RTOL;
  if (!(rtol <= 1e-4))
    return rl_error(RL_EINVAL, "molecule %s: inertia tolerance %g must be at most 1e-4", nm, def->inertia_rtol);
  double mx = lam[2], tol = rtol * mx;
  rl_kind kind;
  double dipvec[3] = {0, 0, 0};
  int dip_site = -1;
  for (int a = 0; a < n && def->dipole; a++)
    if (def->dipole[3 * a] != 0.0 || def->dipole[3 * a + 1] != 0.0 || def->dipole[3 * a + 2] != 0.0) {
      dip_site = a;
      memcpy(dipvec, def->dipole + 3 * a, sizeof dipvec);
      break;
    }

  if (!(mx > 0.0)) {
    /* all mass at one point */
    for (int a = 0; a < n; a++)
      if (fabs(def->pos[3 * a] - m->com[0]) + fabs(def->pos[3 * a + 1] - m->com[1]) +
              fabs(def->pos[3 * a + 2] - m->com[2]) > 0.0)
        return rl_error(RL_EINVAL, "molecule %s: site %d (%s) is off the centre but all mass sits at "
                        "one point: give the sites masses", nm, a, m->site_names[a]);
    if (!m->has_dipole && !m->has_quadrupole) {
      kind = RL_KIND_POINT;
      static const double I9[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
      memcpy(V, I9, sizeof I9);
    } else {
      const double *I = def->inertia;
      if (!m->has_dipole)
        return rl_error(RL_EINVAL, "molecule %s: a single-centre molecule needs a dipole to define "
                        "its axis", nm);
      if (!(I[0] > 0.0) || fabs(I[0] - I[1]) > RL_INERTIA_RTOL * I[0] ||
          fabs(I[0] - I[2]) > RL_INERTIA_RTOL * I[0])
        return rl_error(RL_EINVAL, "molecule %s: a point dipole needs a spherical inertia I, I, I "
                        "(got %g %g %g)", nm, I[0], I[1], I[2]);
      kind = RL_KIND_DIPOLE;
      double dn = sqrt(dipvec[0] * dipvec[0] + dipvec[1] * dipvec[1] + dipvec[2] * dipvec[2]);
      double z[3] = {dipvec[0] / dn, dipvec[1] / dn, dipvec[2] / dn};
      rl_frame_from_axis(z, V);
      lam[0] = lam[1] = lam[2] = I[0];
    }
  } else if (lam[0] <= tol) {
    kind = RL_KIND_LINEAR; /* axis = eigenvector of the zero moment */
    double z[3] = {V[0], V[1], V[2]};
    rl_frame_from_axis(z, V);
    double J = 0.5 * (lam[1] + lam[2]);
    lam[0] = lam[1] = J;
    lam[2] = 0.0;
  } else {
    int e01 = lam[1] - lam[0] <= tol, e12 = lam[2] - lam[1] <= tol;
    if (e01 && e12) {
      kind = RL_KIND_SPHERICAL;
      lam[0] = lam[1] = lam[2] = (lam[0] + lam[1] + lam[2]) / 3.0;
    } else if (e01 || e12) {
      kind = RL_KIND_SYMMETRIC;
      if (e12) { /* prolate: unique axis is the smallest moment -> put it on Z */
        double W[9] = {V[3], V[4], V[5], V[6], V[7], V[8], V[0], V[1], V[2]};
        double u = lam[0], e = 0.5 * (lam[1] + lam[2]);
        memcpy(V, W, sizeof W);
        lam[0] = lam[1] = e;
        lam[2] = u;
      } else {
        double e = 0.5 * (lam[0] + lam[1]);
        lam[0] = lam[1] = e;
      }
    } else {
      kind = RL_KIND_ASYMMETRIC;
    }
    right_handed(V);
  }

  /* body-frame sites; checks for axis kinds */
  for (int a = 0; a < n; a++) {
    double d[3] = {def->pos[3 * a] - m->com[0], def->pos[3 * a + 1] - m->com[1], def->pos[3 * a + 2] - m->com[2]};
    for (int r = 0; r < 3; r++) m->sites[a][r] = V[3 * r] * d[0] + V[3 * r + 1] * d[1] + V[3 * r + 2] * d[2];
    if (kind == RL_KIND_LINEAR || kind == RL_KIND_DIPOLE) {
      double off = hypot(m->sites[a][0], m->sites[a][1]);
      if (off > RL_AXIS_RTOL * ext)
        return rl_error(RL_EINVAL, "molecule %s: site %d (%s) is %.3g off the axis of a linear "
                        "molecule (more than %g of its size %.3g); all sites must lie on the axis",
                        nm, a, m->site_names[a], off, RL_AXIS_RTOL, ext);
      m->sites[a][0] = m->sites[a][1] = 0.0;
    }
    if (kind == RL_KIND_POINT) m->sites[a][0] = m->sites[a][1] = m->sites[a][2] = 0.0;
    if (def->dipole) {
      const double *mu = def->dipole + 3 * a;
      double body[3];
      for (int r = 0; r < 3; r++) body[r] = V[3 * r] * mu[0] + V[3 * r + 1] * mu[1] + V[3 * r + 2] * mu[2];
      double mn = sqrt(mu[0] * mu[0] + mu[1] * mu[1] + mu[2] * mu[2]);
      if (mn > 0.0 && hypot(body[0], body[1]) > 1e-9 * mn)
        return rl_error(RL_EINVAL, "molecule %s: site %d (%s): point dipoles must lie along the "
                        "molecular axis (body Z: the axis of a linear molecule or dipole, the unique "
                        "axis of a symmetric top, the largest-moment axis otherwise)", nm, a, m->site_names[a]);
      m->dipole[a] = body[2];
    }
    if (m->quadrupole[a] != 0.0 && kind != RL_KIND_LINEAR && kind != RL_KIND_DIPOLE)
      return rl_error(RL_EINVAL, "molecule %s: site %d (%s): point quadrupoles are supported along "
                      "the axis of linear molecules and point dipoles only", nm, a, m->site_names[a]);
  }
  (void)dip_site;
  if (kind == RL_KIND_SYMMETRIC || kind == RL_KIND_ASYMMETRIC) {
    /* a planar molecule has J_c = J_a + J_b exactly; the eigenvalues may break that by round-off,
     * which the system refuses as a violated triangle inequality: put the largest moment back on
     * the sum when it exceeds it by no more than the tolerance */
    const int c = lam[2] >= lam[0] && lam[2] >= lam[1] ? 2 : lam[1] >= lam[0] ? 1 : 0;
    const double sum = lam[(c + 1) % 3] + lam[(c + 2) % 3];
    if (lam[c] > sum && lam[c] - sum <= tol) lam[c] = sum;
  }
  memcpy(m->axes, V, sizeof m->axes);
  memcpy(m->inertia, lam, sizeof m->inertia);
  m->natural_kind = kind;
  m->kind = kind;
  if (force_general && kind != RL_KIND_POINT) {
    m->kind = RL_KIND_ASYMMETRIC;
    if (kind == RL_KIND_LINEAR || kind == RL_KIND_DIPOLE) m->inertia[2] = m->inertia[0];
  }
  return RL_OK;
}

void rl_molecule_species(const rl_molecule *m, rl_species_desc *d)
{
  memset(d, 0, sizeof *d);
  d->name = m->name;
  d->kind = m->kind;
  d->mass = m->mass;
  memcpy(d->inertia, m->inertia, sizeof d->inertia);
  d->nsites = m->nsites;
  d->sites = &m->sites[0][0];
}

