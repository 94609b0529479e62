/* The real-space part of the Ewald sum, the term "ewald-real" (ewald.h): the reference that the
 * pair kernels' Ewald rows will be checked against.  With point dipoles a separate plain-C row
 * (real_site_dip; ewald_dipole.h has the formulas) and a nine-component virial.
 *
 *   U_real = kc sum_{a<b} q_a q_b erfc(alpha r_ab) / r_ab   over charged site pairs of different
 *            bodies with r_ab < rc (minimum image; pairs within a body are excluded)
 *   f_a    = kc q_a q_b [erfc(alpha r) / r + (2 alpha / sqrt(pi)) exp(-alpha^2 r^2)] r_ab / r^2
 *
 * with erfc and exp(-x^2) from erfc.h (the vectorised form the kernels will use; <= 1e-15
 * relative).  Pairs are found through a cell list of the charged sites (cells at least rc wide;
 * with fewer than three cells along an edge every pair is tried), and every site sums its own
 * force over all its neighbours (a full list, each pair evaluated from both ends: twice the work
 * of a half list, and in exchange each site's force, half-energy and half-virial are sums over
 * its neighbours in cell order, so that the results are the same bits for any thread count).
 * The site virial is sum over pairs r_ab (x) f_ab; the molecular one follows in ew_finish. */
#include "ewald_impl.h"
#include "erfc.h"
#include "ewald_dipole.h"
#include "rotleap/error.h"
#include "../../core/threads.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  ew_base b; /* first */
  int nc[3], ncell;   /* cells per edge (all 1: every pair is tried)                            */
  int *cell_start;    /* [ncell + 1]                                                            */
  int *cellof;        /* [nq]                                                                   */
  int *order;         /* [nq] charged sites sorted by cell, in site order within a cell         */
  double *X, *Y, *Z;  /* [nq] wrapped positions, in cell order                                  */
  double *Qs;         /* [nq] charges, in cell order                                            */
  int *B;             /* [nq] bodies, in cell order                                             */
  double (*xw)[3];    /* [nq] wrapped positions, in site order                                  */
  double *esite;      /* [nq] half the energy of each site's pairs                              */
  double (*wsite)[6]; /* [nq] half its pairs' virial (xx yy zz xy xz yz)                        */
  /* with point dipoles (b.ndip > 0) */
  double *MX, *MY, *MZ; /* [nq] lab dipoles, in cell order                                       */
  double (*wsite9)[9];  /* [nq] half its pairs' virial, all nine (the dipoles make it asymmetric) */
} real_state;

static void real_free(void *state)
{
  real_state *s = state;
  if (!s) return;
  ew_base_free(&s->b);
  free(s->cell_start);
  free(s->cellof);
  free(s->order);
  free(s->X);
  free(s->Y);
  free(s->Z);
  free(s->Qs);
  free(s->B);
  free(s->xw);
  free(s->esite);
  free(s->wsite);
  free(s->MX);
  free(s->MY);
  free(s->MZ);
  free(s->wsite9);
  free(s);
}

/* Cells for the current cell and cutoff: at least rc wide, three or more per edge, or one. */
static int real_cells(real_state *s)
{
  int nc[3], brute = 0;
  for (int c = 0; c < 3; c++) {
    nc[c] = (int)(s->b.L[c] / s->b.info.cutoff);
    if (nc[c] < 3) brute = 1;
    if (nc[c] > 256) nc[c] = 256;
  }
  if (brute) nc[0] = nc[1] = nc[2] = 1;
  const int ncell = nc[0] * nc[1] * nc[2];
  if (ncell != s->ncell) {
    int *cs = realloc(s->cell_start, sizeof(int) * (size_t)(ncell + 1));
    if (!cs) return rl_error(RL_ENOMEM, "ewald-real: out of memory");
    s->cell_start = cs;
    s->ncell = ncell;
  }
  memcpy(s->nc, nc, sizeof nc);
  return RL_OK;
}

static int real_box(void *state, const rl_system *sys)
{
  real_state *s = state;
  const int st = ew_base_box(&s->b, sys);
  return st ? st : real_cells(s);
}

/* Per-CPU clones of the site rows (as forces/pair/ff_fast.c's): the vectorised erfc is 6 times
 * faster than the C library's erfc and exp in AVX-512 registers, and no faster in SSE2's two
 * lanes.  A clone sums its lanes in its own order: results differ between CPUs at round-off, not
 * between thread counts. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(ROTLEAP_NO_CLONES)
#define EW_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define EW_CLONES
#endif

/* Sum over the sites j0..j1 (cell order) of the pairs with charged site (xi, yi, zi), charge
 * kc q_i, body bi; adds its force, energy and virial (full pair values). */
static inline __attribute__((always_inline)) void real_row(const real_state *s, int j0, int j1, double xi, double yi, double zi, double kq, int bi,
                            double f[3], double *e, double w[6])
{
  const double L0 = s->b.L[0], L1 = s->b.L[1], L2 = s->b.L[2], h0 = 0.5 * L0, h1 = 0.5 * L1, h2 = 0.5 * L2;
  const double rc2 = s->b.info.cutoff * s->b.info.cutoff, a = s->b.info.alpha, c2a = 2.0 * a / sqrt(M_PI);
  const double *X = s->X, *Y = s->Y, *Z = s->Z, *Q = s->Qs;
  const int *B = s->B;
  double fx = 0, fy = 0, fz = 0, u = 0, wxx = 0, wyy = 0, wzz = 0, wxy = 0, wxz = 0, wyz = 0;
#pragma omp simd reduction(+ : fx, fy, fz, u, wxx, wyy, wzz, wxy, wxz, wyz)
  for (int j = j0; j < j1; j++) {
    double dx = xi - X[j], dy = yi - Y[j], dz = zi - Z[j];
    dx = dx > h0 ? dx - L0 : dx < -h0 ? dx + L0 : dx;
    dy = dy > h1 ? dy - L1 : dy < -h1 ? dy + L1 : dy;
    dz = dz > h2 ? dz - L2 : dz < -h2 ? dz + L2 : dz;
    const double r2 = dx * dx + dy * dy + dz * dz;
    const int in = r2 < rc2 && B[j] != bi;
    const double r = sqrt(in ? r2 : rc2), ir = 1.0 / r;
    double ex;
    const double ec = rl_erfc_exp(a * r, &ex);
    const double qq = in ? kq * Q[j] : 0.0;
    const double uij = qq * ec * ir, fr = (uij + qq * c2a * ex) * ir * ir;
    fx += fr * dx;
    fy += fr * dy;
    fz += fr * dz;
    u += uij;
    wxx += fr * dx * dx;
    wyy += fr * dy * dy;
    wzz += fr * dz * dz;
    wxy += fr * dx * dy;
    wxz += fr * dx * dz;
    wyz += fr * dy * dz;
  }
  f[0] += fx;
  f[1] += fy;
  f[2] += fz;
  *e += u;
  w[0] += wxx;
  w[1] += wyy;
  w[2] += wzz;
  w[3] += wxy;
  w[4] += wxz;
  w[5] += wyz;
}

/* Sorted site j against its neighbours; the results go to its site k. */
EW_CLONES static void real_site(real_state *s, int j)
{
  ew_base *b = &s->b;
  const int *nc = s->nc, k = s->order[j], cell = s->cellof[k];
  const int cx = cell % nc[0], cy = (cell / nc[0]) % nc[1], cz = cell / (nc[0] * nc[1]);
  double f[3] = {0, 0, 0}, e = 0, w[6] = {0, 0, 0, 0, 0, 0};
  const double kq = b->info.coulomb_constant * s->Qs[j];
  const int span = s->ncell == 1 ? 0 : 1;
  for (int oz = -span; oz <= span; oz++)
    for (int oy = -span; oy <= span; oy++)
      for (int ox = -span; ox <= span; ox++) {
        const int n = (((cz + oz + nc[2]) % nc[2]) * nc[1] + (cy + oy + nc[1]) % nc[1]) * nc[0] + (cx + ox + nc[0]) % nc[0];
        real_row(s, s->cell_start[n], s->cell_start[n + 1], s->X[j], s->Y[j], s->Z[j], kq, s->B[j], f, &e, w);
      }
  b->fq[k][0] += f[0];
  b->fq[k][1] += f[1];
  b->fq[k][2] += f[2];
  s->esite[k] = 0.5 * e;
  for (int c = 0; c < 6; c++) s->wsite[k][c] = 0.5 * w[c];
}

/* With point dipoles: sorted site j against its neighbours (ewald_dipole.h), results to site k.
 * Plain C: the dipolar rows are not vectorised. */
static void real_site_dip(real_state *s, int j)
{
  ew_base *b = &s->b;
  const int *nc = s->nc, k = s->order[j], cell = s->cellof[k];
  const int cx = cell % nc[0], cy = (cell / nc[0]) % nc[1], cz = cell / (nc[0] * nc[1]);
  const double L0 = b->L[0], L1 = b->L[1], L2 = b->L[2], h0 = 0.5 * L0, h1 = 0.5 * L1, h2 = 0.5 * L2;
  const double rc2 = b->info.cutoff * b->info.cutoff, a = b->info.alpha, kc = b->info.coulomb_constant;
  const double xi = s->X[j], yi = s->Y[j], zi = s->Z[j], qi = s->Qs[j], mi[3] = {s->MX[j], s->MY[j], s->MZ[j]};
  const int bi = s->B[j];
  double f[3] = {0, 0, 0}, E[3] = {0, 0, 0}, e = 0, w[9] = {0};
  const int span = s->ncell == 1 ? 0 : 1;
  for (int oz = -span; oz <= span; oz++)
    for (int oy = -span; oy <= span; oy++)
      for (int ox = -span; ox <= span; ox++) {
        const int n = (((cz + oz + nc[2]) % nc[2]) * nc[1] + (cy + oy + nc[1]) % nc[1]) * nc[0] + (cx + ox + nc[0]) % nc[0];
        for (int jj = s->cell_start[n]; jj < s->cell_start[n + 1]; jj++) {
          if (s->B[jj] == bi) continue;
          double r[3] = {xi - s->X[jj], yi - s->Y[jj], zi - s->Z[jj]};
          r[0] = r[0] > h0 ? r[0] - L0 : r[0] < -h0 ? r[0] + L0 : r[0];
          r[1] = r[1] > h1 ? r[1] - L1 : r[1] < -h1 ? r[1] + L1 : r[1];
          r[2] = r[2] > h2 ? r[2] - L2 : r[2] < -h2 ? r[2] + L2 : r[2];
          const double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
          if (!(r2 < rc2)) continue;
          const double rr = sqrt(r2), qj = s->Qs[jj], mj[3] = {s->MX[jj], s->MY[jj], s->MZ[jj]};
          double ex, B[4];
          const double ec = rl_erfc_exp(a * rr, &ex);
          ew_erfc_b4(a, rr, ec, ex, B);
          const double mir = mi[0] * r[0] + mi[1] * r[1] + mi[2] * r[2], mjr = mj[0] * r[0] + mj[1] * r[1] + mj[2] * r[2];
          const double mm = mi[0] * mj[0] + mi[1] * mj[1] + mi[2] * mj[2];
          const double G0 = qi * qj, G1 = qi * mjr - qj * mir + mm, G2 = -mir * mjr;
          e += G0 * B[0] + G1 * B[1] + G2 * B[2];
          const double fr = G0 * B[1] + G1 * B[2] + G2 * B[3];
          double fp[3];
          for (int c = 0; c < 3; c++) {
            fp[c] = fr * r[c] - B[1] * (qi * mj[c] - qj * mi[c]) + B[2] * (mjr * mi[c] + mir * mj[c]);
            f[c] += fp[c];
            E[c] += (qj * B[1] + B[2] * mjr) * r[c] - B[1] * mj[c];
          }
          for (int x = 0; x < 3; x++)
            for (int y = 0; y < 3; y++) w[3 * x + y] += r[x] * fp[y];
        }
      }
  for (int c = 0; c < 3; c++) {
    b->fq[k][c] += kc * f[c];
    b->eq[k][c] += kc * E[c];
  }
  s->esite[k] = 0.5 * kc * e;
  for (int c = 0; c < 9; c++) s->wsite9[k][c] = 0.5 * kc * w[c];
}

static int real_part(ew_base *b, double *energy, double W[9])
{
  real_state *s = (real_state *)b;
  const int T = b->threads, nq = b->nq, *nc = s->nc;
  (void)T; /* a build without OpenMP */
  /* wrap, bin and sort (counting sort: site order within a cell) */
  memset(s->cell_start, 0, sizeof(int) * (size_t)(s->ncell + 1));
  for (int k = 0; k < nq; k++) {
    int ci[3];
    for (int c = 0; c < 3; c++) {
      double x = b->xq[k][c] - b->L[c] * floor(b->xq[k][c] / b->L[c]);
      if (x >= b->L[c]) x -= b->L[c];
      if (x < 0.0) x = 0.0;
      ci[c] = (int)(x * nc[c] / b->L[c]);
      if (ci[c] >= nc[c]) ci[c] = nc[c] - 1;
      s->xw[k][c] = x;
    }
    s->cellof[k] = (ci[2] * nc[1] + ci[1]) * nc[0] + ci[0];
    s->cell_start[s->cellof[k] + 1]++;
  }
  for (int c = 0; c < s->ncell; c++) s->cell_start[c + 1] += s->cell_start[c];
  {
    int *fill = malloc(sizeof(int) * (size_t)s->ncell);
    if (!fill) return rl_error(RL_ENOMEM, "ewald-real: out of memory");
    memcpy(fill, s->cell_start, sizeof(int) * (size_t)s->ncell);
    for (int k = 0; k < nq; k++) s->order[fill[s->cellof[k]]++] = k;
    free(fill);
  }
  for (int j = 0; j < nq; j++) { /* sorted copies */
    const int k = s->order[j];
    s->X[j] = s->xw[k][0];
    s->Y[j] = s->xw[k][1];
    s->Z[j] = s->xw[k][2];
    s->Qs[j] = b->q[k];
    s->B[j] = b->qbody[k];
  }
  if (b->ndip) {
    for (int j = 0; j < nq; j++) {
      const int k = s->order[j];
      s->MX[j] = b->md[k][0];
      s->MY[j] = b->md[k][1];
      s->MZ[j] = b->md[k][2];
    }
#ifdef _OPENMP
#pragma omp parallel for num_threads(T) if (T > 1) schedule(dynamic, 64)
#endif
    for (int j = 0; j < nq; j++) real_site_dip(s, j);
    double E = 0;
    for (int k = 0; k < nq; k++) {
      E += s->esite[k];
      for (int c = 0; c < 9; c++) W[c] += s->wsite9[k][c];
    }
    *energy = E;
    return RL_OK;
  }
  /* every site against its neighbours (sorted order j, written back to site k) */
#ifdef _OPENMP
#pragma omp parallel for num_threads(T) if (T > 1) schedule(dynamic, 64)
#endif
  for (int j = 0; j < nq; j++) real_site(s, j);
  double E = 0, w[6] = {0, 0, 0, 0, 0, 0};
  for (int k = 0; k < nq; k++) {
    E += s->esite[k];
    for (int c = 0; c < 6; c++) w[c] += s->wsite[k][c];
  }
  *energy = E;
  ew_add_virial6(W, w);
  return RL_OK;
}

static void *real_alloc(const rl_system *sys, const void *params)
{
  real_state *s = ew_alloc(sizeof *s, sys, params, RL_EWALD_REAL);
  if (!s) return NULL;
  s->b.part = real_part;
  const size_t nq = (size_t)s->b.nq;
  s->cellof = malloc(sizeof(int) * nq);
  s->order = malloc(sizeof(int) * nq);
  s->X = malloc(sizeof(double) * nq);
  s->Y = malloc(sizeof(double) * nq);
  s->Z = malloc(sizeof(double) * nq);
  s->Qs = malloc(sizeof(double) * nq);
  s->B = malloc(sizeof(int) * nq);
  s->xw = malloc(sizeof(double[3]) * nq);
  s->esite = malloc(sizeof(double) * nq);
  s->wsite = malloc(sizeof(double[6]) * nq);
  if (s->b.ndip) {
    s->MX = malloc(sizeof(double) * nq);
    s->MY = malloc(sizeof(double) * nq);
    s->MZ = malloc(sizeof(double) * nq);
    s->wsite9 = malloc(sizeof(double[9]) * nq);
  }
  if (!s->cellof || !s->order || !s->X || !s->Y || !s->Z || !s->Qs || !s->B || !s->xw || !s->esite || !s->wsite || real_cells(s) ||
      (s->b.ndip && (!s->MX || !s->MY || !s->MZ || !s->wsite9))) {
    real_free(s);
    rl_error(RL_ENOMEM, "ewald-real: out of memory");
    return NULL;
  }
  return s;
}

static int real_compute(void *state, const rl_system *sys, rl_forces *out, double *energies)
{
  return ew_compute(state, sys, out, energies, 1);
}

const rl_term_type rl_term_ewald_real = {
    "ewald-real",
    "real-space part of the Ewald sum of point charges and dipoles: kc q q erfc(alpha r)/r (and the B_1, B_2 terms of "
    "dipoles) between sites of different bodies within the cutoff, minimum image (rotleap/ewald.h); the reference for "
    "the pair kernels' Ewald rows",
    "P. P. Ewald, Ann. Phys. 369, 253 (1921); J. Kolafa & J. W. Perram, Mol. Simul. 9, 351 (1992) (error estimate)",
    1,
    {"ewald_real"},
    real_alloc,
    real_compute,
    real_box,
    real_free};
