/* Batches of a row's neighbours for the portable rows (and the box constants, images, pruning
 * radius and sums every row shares). */
#ifndef ROTLEAP_PAIR_BATCH_H
#define ROTLEAP_PAIR_BATCH_H

#include "kernel.h"

#include <math.h>
#include <string.h>

#define RL_FAST_B 64    /* neighbours per batch                                     */

/* A batch of up to RL_FAST_B neighbours of body i, structure of arrays.  Neighbours whose
 * centres are farther than the pruning radius (rc, plus twice the species' extent for a site
 * cutoff) are dropped when the batch is filled: the list's skin and extent padding hold about
 * twice as many pairs as interact. */
typedef struct {
  int n, np;                               /* neighbours kept; padded length               */
  int idx[RL_FAST_B + RL_FAST_W];         /* + slack: tip4p_fill512's full-vector stores,   */
                                           /* take_candidate's images of a last neighbour   */
  /* 64-byte aligned rows (each a multiple of 64 bytes): otherwise GCC peels scalar
   * iterations to align the vector stores, and those ran a third of the time */
  _Alignas(64) double w[RL_FAST_B];        /* 1 for a neighbour, 0 for padding              */
  double R[3][RL_FAST_B + RL_FAST_W];      /* centre_i - centre_j, minimum image (+ slack)  */
  double x[RL_FAST_MAXS][3][RL_FAST_B];    /* j's sites: lab (P_SITE), else site - centre   */
  double f[RL_FAST_MAXS][3][RL_FAST_B];    /* forces on j's sites                            */
  double g[RL_FAST_MAXS][3][RL_FAST_B];    /* tip4p: forces on i's sites from each j         */
  double r2min[RL_FAST_B];                 /* tip4p: closest site pair of each j, squared    */
  double m[3][RL_FAST_B];                  /* stockmayer: j's dipole                          */
  double t[3][RL_FAST_B];                  /* stockmayer: torques on j                       */
} batch;

/* In a box with an edge shorter than twice the pruning radius rp (P_SHIFT), the images of a
 * neighbour other than the centres' minimum image (X, Y, Z) can be closer than rp too.  Only
 * X -+ L can (rp < L), and only where |X| > L - rp: far_axes gives those components as bits
 * (for 256 TIP4P at rc = 0.9 nm about a third of the candidates have one). */
RL_INLINE int far_axes(const box_consts *B, double rp, double X, double Y, double Z)
{
  return (fabs(X) > B->L[0] - rp) | (fabs(Y) > B->L[1] - rp) << 1 |
         (fabs(Z) > B->L[2] - rp) << 2;
}

/* The images of neighbour j given by the combinations of the far components, each written to
 * the batch's idx and R from slot n on and kept if inside rp; returns the new n.  Out of line,
 * so that the fills stay small enough for GCC to inline them in the rows. */
static __attribute__((noinline, unused)) int other_images(const box_consts *B, double rp2, int far, int j,
                                                  double X, double Y, double Z, batch *b, int n)
{
  const double x[2] = {X, X > 0.0 ? X - B->L[0] : X + B->L[0]};
  const double y[2] = {Y, Y > 0.0 ? Y - B->L[1] : Y + B->L[1]};
  const double z[2] = {Z, Z > 0.0 ? Z - B->L[2] : Z + B->L[2]};
  for (int m = 1; m < 8; m++) {
    if (m & ~far) continue;
    const double u = x[m & 1], v = y[(m >> 1) & 1], w = z[m >> 2];
    b->idx[n] = j;
    b->R[0][n] = u; b->R[1][n] = v; b->R[2][n] = w;
    n += u * u + v * v + w * w < rp2;
  }
  return n;
}

/* Candidate j at centre separation (X, Y, Z) from i: its minimum image goes to slot n and is
 * kept if inside rp (img: its other images within rp too, other_images); returns the new n.
 * Branch-free: every candidate is written to slot n, which only a kept one keeps (a branch on
 * the distance was mispredicted for a good fraction of the candidates). */
RL_INLINE int take_candidate(const box_consts *B, double rp, double rp2, int img, int j, double X,
                             double Y, double Z, batch *b, int n)
{
  X -= B->L[0] * RL_RND(X * B->iL[0]);
  Y -= B->L[1] * RL_RND(Y * B->iL[1]);
  Z -= B->L[2] * RL_RND(Z * B->iL[2]);
  b->idx[n] = j;
  b->R[0][n] = X; b->R[1][n] = Y; b->R[2][n] = Z;
  n += X * X + Y * Y + Z * Z < rp2;
  if (img) {
    const int far = far_axes(B, rp, X, Y, Z);
    if (far) n = other_images(B, rp2, far, j, X, Y, Z, b, n);
  }
  return n;
}

/* Whether a box needs other_images for pruning radius rp (squared: rp2): an edge < 2 rp. */
RL_INLINE int needs_images(const int MODE, const box_consts *B, double rp2)
{
  if (MODE != P_SHIFT) return 0;
  for (int c = 0; c < 3; c++)
    if (B->L[c] * B->L[c] < 4.0 * rp2) return 1;
  return 0;
}

/* Fill b with the next neighbours of row nbr[*pos .. len) within the pruning radius
 * (squared: rp2); advance *pos.  Slot s holds site K->perm[s] of each body (DIP: the
 * dipoles too).  ZERO: clear the forces (for kernels that add to them). */
RL_INLINE void batch_fill(const int MODE, const int DIP, const int ZERO, const kview *V,
                          const box_consts *B, int i, const int *nbr, int len, int *pos,
                          const fast_species *K, double rp2, int img, batch *b)
{
  const double cx = V->c[i][0], cy = V->c[i][1], cz = V->c[i][2];
  const int ns = K->ns;
  const double mu = K->mu;
  const double rp = img ? sqrt(rp2) : 0.0;
  int n = 0, p = *pos;
  for (; p < len && n < RL_FAST_B; p++) {
    const int j = nbr[p];
    const int n0 = n;
    n = take_candidate(B, rp, rp2, img, j, cx - V->c[j][0], cy - V->c[j][1], cz - V->c[j][2],
                       b, n);
    if (n > RL_FAST_B) { /* j's images do not all fit: the next batch takes j */
      n = n0;
      break;
    }
    const int oj = V->soff[j];
    const int hi = n > n0 + 1 ? n : n0 + 1; /* the slots of j's kept images (slot n0 always) */
    for (int k = n0; k < hi; k++) {
      b->w[k] = 1.0;
      for (int s = 0; s < ns; s++)
        for (int c = 0; c < 3; c++)
          b->x[s][c][k] = MODE == P_SITE ? V->site[oj + K->perm[s]][c] : V->dsite[oj + K->perm[s]][c];
      if (DIP)
        for (int c = 0; c < 3; c++) b->m[c][k] = mu * V->ax[j][c];
    }
  }
  *pos = p;
  const int np = (n + RL_FAST_W - 1) / RL_FAST_W * RL_FAST_W;
  for (int k = n; k < np; k++) { /* padding: a copy of the first neighbour, weight 0 */
    b->idx[k] = b->idx[0];
    b->w[k] = 0.0;
    for (int c = 0; c < 3; c++) b->R[c][k] = b->R[c][0];
    for (int s = 0; s < ns; s++)
      for (int c = 0; c < 3; c++) b->x[s][c][k] = b->x[s][c][0];
    if (DIP)
      for (int c = 0; c < 3; c++) b->m[c][k] = b->m[c][0];
  }
  if (ZERO) /* the term loops add to f; the fused kernels store every f (and t) */
    for (int s = 0; s < ns; s++)
      for (int c = 0; c < 3; c++) memset(b->f[s][c], 0, sizeof(double) * (size_t)np);
  b->n = n;
  b->np = np;
}

/* Add the batch's forces (and torques) on the neighbours. */
RL_INLINE void batch_scatter(const int DIP, const kview *V, const batch *b,
                             const fast_species *K, double (*fs)[3], double (*tq)[3])
{
  for (int k = 0; k < b->n; k++) {
    const int j = b->idx[k], oj = V->soff[j];
    for (int s = 0; s < K->ns; s++)
      for (int c = 0; c < 3; c++) fs[oj + K->perm[s]][c] += b->f[s][c][k];
    if (DIP)
      for (int c = 0; c < 3; c++) tq[j][c] += b->t[c][k];
  }
}

/* r = (site of i at a[]) - (site s of neighbour k), by MODE. */
RL_INLINE void sep(const int MODE, const box_consts *B, double ax, double ay, double az,
                   const batch *b, int s, int k, double *dx, double *dy, double *dz)
{
  double x, y, z;
  if (MODE == P_SITE) {
    x = ax - b->x[s][0][k]; y = ay - b->x[s][1][k]; z = az - b->x[s][2][k];
    x -= B->L[0] * RL_RND(x * B->iL[0]);
    y -= B->L[1] * RL_RND(y * B->iL[1]);
    z -= B->L[2] * RL_RND(z * B->iL[2]);
  } else {
    x = b->R[0][k] + ax - b->x[s][0][k];
    y = b->R[1][k] + ay - b->x[s][1][k];
    z = b->R[2][k] + az - b->x[s][2][k];
  }
  *dx = x; *dy = y; *dz = z;
}

/* The cutoff factor of a site pair (1 inside, 0 outside or padding): the cutoff as a factor,
 * not a select, because GCC 12 turns `s += c ? u : 0` into a conditional update of the
 * reduction, which AVX2 cannot if-convert. */
RL_INLINE double inside(const int MODE, const box_consts *B, const batch *b, int k, double r2)
{
  return MODE == P_MOL ? b->w[k] : b->w[k] * (r2 < B->rc2 ? 1.0 : 0.0);
}

/* The site position of i that sep() expects: lab (P_SITE) or relative to the centre. */
RL_INLINE const double *site_of_i(const int MODE, const kview *V, int s)
{
  return MODE == P_SITE ? V->site[s] : V->dsite[s];
}

/* Add a row's sums to the thread's accumulators (site virial, symmetric). */
static inline void acc_add(rl_ksums *acc, double elj, double ecoul, const double w[6], double bad)
{
  acc->lj += elj;
  acc->coul += ecoul;
  acc->vir[0] += w[0]; acc->vir[1] += w[1]; acc->vir[2] += w[2];
  acc->vir[3] += w[1]; acc->vir[4] += w[3]; acc->vir[5] += w[4];
  acc->vir[6] += w[2]; acc->vir[7] += w[4]; acc->vir[8] += w[5];
  acc->bad |= bad != 0.0;
}

/* The pruning radius of a species' rows, squared. */
RL_INLINE double prune2(const int MODE, const box_consts *B, const fast_species *K)
{
  const double rp = MODE == P_MOL ? B->rc : B->rc + 2.0 * K->extent;
  return rp * rp;
}

#endif
