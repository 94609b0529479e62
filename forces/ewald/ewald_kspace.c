/* Classical Ewald: the reciprocal sum over k vectors, the term "ewald" (ewald.h), the exact
 * reference for the mesh.
 *
 *   U_recip = sum_{k in half space} A(k) |S(k)|^2,  A(k) = (4 pi kc / V) exp(-k^2/4 alpha^2) / k^2
 *   f_a     = 2 q_a sum_k A(k) k Im[exp(i k.r_a) S(k)*]
 *   W_site  = sum_k A(k) |S(k)|^2 (delta - 2 (1 + k^2/4 alpha^2) k k^T / k^2)
 * over k = 2 pi (n_x/Lx, n_y/Ly, n_z/Lz), n in the half space (n_x > 0, or n_x = 0 and n_y > 0,
 * or n_x = n_y = 0 and n_z > 0), |n_c| <= kmax_c and, with kmax_sq > 0, n^2 <= kmax_sq: the
 * sum of OpenMM 7.7's reference Ewald (ReferenceLJCoulombIxn::calculateEwaldIxn, whose kmaxx
 * is rotleap's kmax + 1), with the spherical limit of the NIST SPC/E reference sums and LAMMPS.
 *
 * exp(i k.r) = exp(i n_x t_x) exp(i n_y t_y) exp(i n_z t_z), t_c = 2 pi x_c / L_c, from per-site
 * tables of exp(i n t_c), n = 0..kmax_c, built by repeated multiplication as OpenMM does.  The
 * vectors are kept as columns (n_x, n_y) of consecutive n_z.  Threads: the structure factors
 * column by column (each S(k) a sum over the sites in order), then the forces site by site
 * (each a sum over the vectors in order), the energy and virial per column added in order: the
 * same bits for any thread count. */
#include "ewald_impl.h"
#include "rotleap/error.h"
#include "../../core/threads.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  ew_base b; /* first */
  int ncol, nk;
  int *col_nx, *col_ny, *col_start; /* [ncol], [ncol + 1]                                       */
  int *knz;                         /* [nk] n_z of each vector, columns in order                */
  double *A, *vf;                   /* [nk] A(k), 2 (1 + k^2/4 alpha^2) / k^2                   */
  double (*k)[3];                   /* [nk]                                                     */
  double *Sr, *Si;                  /* [nk] structure factor                                    */
  double *tab;                      /* [nq][2 (kx+1) + 2 (ky+1) + 2 (kz+1)] cos, sin tables     */
  int tstride, toff[3];
  double *colsum;                   /* [ncol][7] energy and virial per column                   */
} ewald_state;

static void ewald_free(void *state)
{
  ewald_state *s = state;
  if (!s) return;
  ew_base_free(&s->b);
  free(s->col_nx);
  free(s->col_ny);
  free(s->col_start);
  free(s->knz);
  free(s->A);
  free(s->vf);
  free(s->k);
  free(s->Sr);
  free(s->Si);
  free(s->tab);
  free(s->colsum);
  free(s);
}

/* The vectors' prefactors for the current cell. */
static void ewald_prefactors(ewald_state *s)
{
  const double *L = s->b.L, a = s->b.info.alpha, V = L[0] * L[1] * L[2];
  const double coef = 4.0 * M_PI * s->b.info.coulomb_constant / V, factor = -1.0 / (4.0 * a * a);
  for (int c = 0; c < s->ncol; c++)
    for (int j = s->col_start[c]; j < s->col_start[c + 1]; j++) {
      const double kx = s->col_nx[c] * (2 * M_PI / L[0]), ky = s->col_ny[c] * (2 * M_PI / L[1]), kz = s->knz[j] * (2 * M_PI / L[2]);
      const double k2 = kx * kx + ky * ky + kz * kz;
      s->k[j][0] = kx;
      s->k[j][1] = ky;
      s->k[j][2] = kz;
      s->A[j] = coef * exp(k2 * factor) / k2;
      s->vf[j] = 2.0 * (1.0 - k2 * factor) / k2;
    }
}

static int ewald_box(void *state, const rl_system *sys)
{
  ewald_state *s = state;
  const int st = ew_base_box(&s->b, sys);
  if (st) return st;
  ewald_prefactors(s);
  return RL_OK;
}

/* exp(i n t) for site k, axis c, n >= 0 (conjugated for n < 0) */
static inline void eint(const ewald_state *s, int k, int c, int n, double *re, double *im)
{
  const double *t = s->tab + (size_t)k * s->tstride + s->toff[c];
  const int m = n < 0 ? -n : n;
  *re = t[2 * m];
  *im = n < 0 ? -t[2 * m + 1] : t[2 * m + 1];
}

/* The tables exp(i n t_c), n = 0..kmax_c, of every site. */
static void ewald_tables(ewald_state *s)
{
  ew_base *b = &s->b;
  const int T = b->threads, nq = b->nq;
  (void)T; /* a build without OpenMP */
  const int *km = b->info.kmax;
#ifdef _OPENMP
#pragma omp parallel num_threads(T) if (T > 1)
#endif
  {
    int k0, k1;
    rl_thread_range(nq, &k0, &k1);
    for (int k = k0; k < k1; k++)
      for (int c = 0; c < 3; c++) {
        double *t = s->tab + (size_t)k * s->tstride + s->toff[c];
        const double th = b->xq[k][c] * (2 * M_PI / b->L[c]);
        t[0] = 1.0;
        t[1] = 0.0;
        if (km[c] < 1) continue;
        t[2] = cos(th);
        t[3] = sin(th);
        for (int n = 2; n <= km[c]; n++) {
          t[2 * n] = t[2 * n - 2] * t[2] - t[2 * n - 1] * t[3];
          t[2 * n + 1] = t[2 * n - 2] * t[3] + t[2 * n - 1] * t[2];
        }
      }
  }
}

/* exp(i (n_x t_x + n_y t_y)) of site k for column c */
static inline void col_phase(const ewald_state *s, int k, int c, double *er, double *ei)
{
  double xr, xi, yr, yi;
  eint(s, k, 0, s->col_nx[c], &xr, &xi);
  eint(s, k, 1, s->col_ny[c], &yr, &yi);
  *er = xr * yr - xi * yi;
  *ei = xr * yi + xi * yr;
}

/* exp(i k.r) of site k for vector j, from its column's phase (er, ei) */
static inline void vec_phase(const ewald_state *s, int k, int j, double er, double ei, double *pr, double *pi)
{
  double zr, zi;
  eint(s, k, 2, s->knz[j], &zr, &zi);
  *pr = er * zr - ei * zi;
  *pi = er * zi + ei * zr;
}

/* Energy and site virial of the columns [their structure factors made], added in column order:
 * sum_k A |S|^2 (delta - 2 (1 + k^2/4 alpha^2) k k^T / k^2). */
static void ewald_column_sums(ewald_state *s, int c)
{
  const int j0 = s->col_start[c], j1 = s->col_start[c + 1];
  double e = 0, w[6] = {0, 0, 0, 0, 0, 0};
  for (int j = j0; j < j1; j++) {
    const double ek = s->A[j] * (s->Sr[j] * s->Sr[j] + s->Si[j] * s->Si[j]), v = s->vf[j], *kv = s->k[j];
    e += ek;
    w[0] += ek * (1.0 - v * kv[0] * kv[0]);
    w[1] += ek * (1.0 - v * kv[1] * kv[1]);
    w[2] += ek * (1.0 - v * kv[2] * kv[2]);
    w[3] -= ek * v * kv[0] * kv[1];
    w[4] -= ek * v * kv[0] * kv[2];
    w[5] -= ek * v * kv[1] * kv[2];
  }
  double *cs = s->colsum + (size_t)c * 7;
  cs[0] = e;
  for (int j = 0; j < 6; j++) cs[1 + j] = w[j];
}

static void ewald_total(const ewald_state *s, double *energy, double W[9])
{
  double E = 0, w[6] = {0, 0, 0, 0, 0, 0};
  for (int c = 0; c < s->ncol; c++) {
    E += s->colsum[(size_t)c * 7];
    for (int j = 0; j < 6; j++) w[j] += s->colsum[(size_t)c * 7 + 1 + j];
  }
  *energy = E;
  ew_add_virial6(W, w);
}

/* With point dipoles: S(k) = sum_a (q_a + i mu_a.k) exp(i k.r_a), and per site
 *   f_a = 2 sum_k A k Im[S* (q_a + i mu_a.k) e^{i k.r_a}],  E_a = 2 sum_k A k Im[S* e^{i k.r_a}];
 * the site virial (dipoles held fixed under the strain, so that mu.k changes with k) is that of
 * the charges with this S plus -sum_a mu_a (x) E_a (storage W[3r + c] = -dU/d strain_cr). */
static int ewald_part_dip(ewald_state *s, double *energy, double W[9])
{
  ew_base *b = &s->b;
  const int T = b->threads, nq = b->nq;
  (void)T; /* a build without OpenMP */
#ifdef _OPENMP
#pragma omp parallel for num_threads(T) if (T > 1) schedule(dynamic, 4)
#endif
  for (int c = 0; c < s->ncol; c++) {
    const int j0 = s->col_start[c], j1 = s->col_start[c + 1];
    const double kx = s->k[j0][0], ky = s->k[j0][1];
    double *Sr = s->Sr + j0, *Si = s->Si + j0;
    memset(Sr, 0, sizeof(double) * (size_t)(j1 - j0));
    memset(Si, 0, sizeof(double) * (size_t)(j1 - j0));
    for (int k = 0; k < nq; k++) {
      double er, ei, pr, pi;
      col_phase(s, k, c, &er, &ei);
      const double q = b->q[k], *m = b->md[k], mxy = m[0] * kx + m[1] * ky;
      for (int j = j0; j < j1; j++) {
        vec_phase(s, k, j, er, ei, &pr, &pi);
        const double mk = mxy + m[2] * s->k[j][2];
        Sr[j - j0] += q * pr - mk * pi;
        Si[j - j0] += q * pi + mk * pr;
      }
    }
    ewald_column_sums(s, c);
  }
  ewald_total(s, energy, W);
#ifdef _OPENMP
#pragma omp parallel num_threads(T) if (T > 1)
#endif
  {
    int k0, k1;
    rl_thread_range(nq, &k0, &k1);
    for (int k = k0; k < k1; k++) {
      double f[3] = {0, 0, 0}, E[3] = {0, 0, 0};
      const double q = b->q[k], *m = b->md[k];
      for (int c = 0; c < s->ncol; c++) {
        double er, ei, pr, pi;
        col_phase(s, k, c, &er, &ei);
        for (int j = s->col_start[c]; j < s->col_start[c + 1]; j++) {
          vec_phase(s, k, j, er, ei, &pr, &pi);
          const double *kv = s->k[j];
          const double cr = pr * s->Sr[j] + pi * s->Si[j], ci = pi * s->Sr[j] - pr * s->Si[j];
          const double mk = m[0] * kv[0] + m[1] * kv[1] + m[2] * kv[2];
          const double g = s->A[j] * (q * ci + mk * cr), h = s->A[j] * ci;
          for (int d = 0; d < 3; d++) {
            f[d] += g * kv[d];
            E[d] += h * kv[d];
          }
        }
      }
      for (int d = 0; d < 3; d++) {
        b->fq[k][d] += 2.0 * f[d];
        b->eq[k][d] += 2.0 * E[d];
      }
    }
  }
  ew_dipole_virial(b, W);
  return RL_OK;
}

static int ewald_part(ew_base *b, double *energy, double W[9])
{
  ewald_state *s = (ewald_state *)b;
  const int T = b->threads, nq = b->nq;
  (void)T; /* a build without OpenMP */
  ewald_tables(s);
  if (b->ndip) return ewald_part_dip(s, energy, W);
  /* structure factors, column by column */
#ifdef _OPENMP
#pragma omp parallel for num_threads(T) if (T > 1) schedule(dynamic, 4)
#endif
  for (int c = 0; c < s->ncol; c++) {
    const int j0 = s->col_start[c], j1 = s->col_start[c + 1];
    double *Sr = s->Sr + j0, *Si = s->Si + j0;
    memset(Sr, 0, sizeof(double) * (size_t)(j1 - j0));
    memset(Si, 0, sizeof(double) * (size_t)(j1 - j0));
    for (int k = 0; k < nq; k++) {
      double er, ei, pr, pi;
      col_phase(s, k, c, &er, &ei);
      er *= b->q[k];
      ei *= b->q[k];
      for (int j = j0; j < j1; j++) {
        vec_phase(s, k, j, er, ei, &pr, &pi);
        Sr[j - j0] += pr;
        Si[j - j0] += pi;
      }
    }
    ewald_column_sums(s, c);
  }
  ewald_total(s, energy, W);
  /* forces, site by site */
#ifdef _OPENMP
#pragma omp parallel num_threads(T) if (T > 1)
#endif
  {
    int k0, k1;
    rl_thread_range(nq, &k0, &k1);
    for (int k = k0; k < k1; k++) {
      double f[3] = {0, 0, 0};
      for (int c = 0; c < s->ncol; c++) {
        double er, ei, pr, pi;
        col_phase(s, k, c, &er, &ei);
        for (int j = s->col_start[c]; j < s->col_start[c + 1]; j++) {
          vec_phase(s, k, j, er, ei, &pr, &pi);
          const double g = s->A[j] * (pi * s->Sr[j] - pr * s->Si[j]);
          f[0] += g * s->k[j][0];
          f[1] += g * s->k[j][1];
          f[2] += g * s->k[j][2];
        }
      }
      const double q2 = 2.0 * b->q[k];
      b->fq[k][0] += q2 * f[0];
      b->fq[k][1] += q2 * f[1];
      b->fq[k][2] += q2 * f[2];
    }
  }
  return RL_OK;
}

static void *ewald_alloc(const rl_system *sys, const void *params)
{
  ewald_state *s = ew_alloc(sizeof *s, sys, params, RL_EWALD_SUM);
  if (!s) return NULL;
  s->b.part = ewald_part;
  const int *km = s->b.info.kmax;
  const double ksq = s->b.info.kmax_sq;
  /* the vectors of the half space, by columns (n_x, n_y) */
  const long maxcol = (long)(km[0] + 1) * (2 * km[1] + 1), maxk = s->b.info.nkvec;
  s->col_nx = malloc(sizeof(int) * (size_t)maxcol);
  s->col_ny = malloc(sizeof(int) * (size_t)maxcol);
  s->col_start = malloc(sizeof(int) * (size_t)(maxcol + 1));
  s->knz = malloc(sizeof(int) * (size_t)maxk);
  s->A = malloc(sizeof(double) * (size_t)maxk);
  s->vf = malloc(sizeof(double) * (size_t)maxk);
  s->k = malloc(sizeof(double[3]) * (size_t)maxk);
  s->Sr = malloc(sizeof(double) * (size_t)maxk);
  s->Si = malloc(sizeof(double) * (size_t)maxk);
  s->colsum = malloc(sizeof(double) * 7 * (size_t)maxcol);
  s->toff[0] = 0;
  s->toff[1] = 2 * (km[0] + 1);
  s->toff[2] = s->toff[1] + 2 * (km[1] + 1);
  s->tstride = s->toff[2] + 2 * (km[2] + 1);
  s->tab = malloc(sizeof(double) * (size_t)s->tstride * (size_t)s->b.nq);
  if (!s->col_nx || !s->col_ny || !s->col_start || !s->knz || !s->A || !s->vf || !s->k || !s->Sr || !s->Si || !s->colsum || !s->tab) {
    ewald_free(s);
    rl_error(RL_ENOMEM, "ewald: out of memory (%ld k vectors)", maxk);
    return NULL;
  }
  int nk = 0, nc = 0;
  for (int x = 0; x <= km[0]; x++)
    for (int y = x ? -km[1] : 0; y <= km[1]; y++) {
      const int start = nk;
      for (int z = (x || y) ? -km[2] : 1; z <= km[2]; z++) {
        if (ksq > 0 && (double)x * x + (double)y * y + (double)z * z > ksq) continue;
        s->knz[nk++] = z;
      }
      if (nk == start) continue;
      s->col_nx[nc] = x;
      s->col_ny[nc] = y;
      s->col_start[nc] = start;
      nc++;
    }
  s->col_start[nc] = nk;
  s->ncol = nc;
  s->nk = nk;
  ewald_prefactors(s);
  return s;
}

static int ewald_compute(void *state, const rl_system *sys, rl_forces *out, double *energies)
{
  return ew_compute(state, sys, out, energies, 5);
}

const rl_term_type rl_term_ewald = {
    "ewald",
    "reciprocal-space Ewald sum of point charges and dipoles over k vectors (kmax per axis and a spherical limit), with the self "
    "term, the intramolecular exclusion correction, a neutralising background and the surface term (rotleap/ewald.h)",
    "P. P. Ewald, Ann. Phys. 369, 253 (1921); M. P. Allen & D. J. Tildesley, Computer Simulation of Liquids, 2nd ed., "
    "section 6.2 (2017); S. W. de Leeuw, J. W. Perram & E. R. Smith, Proc. R. Soc. Lond. A 373, 27 (1980)",
    5,
    {"ewald_recip", "ewald_self", "ewald_intra", "ewald_background", "ewald_surface"},
    ewald_alloc,
    ewald_compute,
    ewald_box,
    ewald_free};
