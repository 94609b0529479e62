/* Specialised pair kernels and the threaded pair loop (issue 8).
 *
 * At alloc (rl_ff_fast_setup) each species gets a kernel from its site pattern:
 *   sites      LJ and charges only, <= RL_FAST_MAXS sites: a fixed list of (site a, site b,
 *              LJ | charge | both) terms made once, so the inner loop never tests which terms
 *              apply.  One LJ site without charge + three charges without LJ is "tip4p"
 *              (1 LJ + 9 charge terms); anything else is "charge-lj" (all terms).
 *   stockmayer one site at the centre with LJ and a dipole, no charge: LJ + dipole-dipole.
 * Pairs of two bodies of one such species go through its kernel; every other pair (another
 * species, quadrupoles, charge-dipole, LJ overrides that break a pattern) through the reference
 * routine rl_ff_body_pair.
 *
 * Layout: at each list build the bodies are ranked in cell order (x fastest); the kernels read
 * copies of centres, axes and sites in that order, refreshed every step, so a row's neighbours
 * lie in a few contiguous runs of memory and consecutive rows share them (`ffbench scaling`
 * shows the cost per molecule against N).  The molecule-pair Verlet list is in CSR
 * form (row m: the ranks above m within rlist), split at build time into kernel rows and
 * reference rows.  A kernel walks a row in batches of RL_FAST_B neighbours: it keeps those
 * within the centres' interaction range (the list holds about twice as many), copies their
 * sites into structure-of-arrays buffers padded to 8 lanes, runs branch-free `omp simd` loops
 * (the cutoff as a 0/1 factor), then scatters the forces.  Where the CPU has AVX-512 (and
 * ROTLEAP_NO_AVX512 is unset) the TIP4P rows with the centres' image keep only the
 * neighbours' indices and centre separations in their batches (tip4p_fill512) and form all
 * terms in registers from transposes of 128-byte records (tip4p_row512), and the dipole rows
 * keep no batch at all: they pack each eight neighbours within the cutoff into registers and
 * form their terms there (dipole_row512).  Where the CPU has AVX2 but not AVX-512 (and
 * ROTLEAP_NO_AVX2 is unset) both do the same four lanes wide (tip4p_row256, dipole_row256).
 * The portable TIP4P rows run their 10 terms in one loop; "charge-lj" one loop per term.  Each term is the reference formula; 1/sqrt is rl_rsqrt
 * (a few ulp, no divider; vrsqrt14pd and two Newton steps in the AVX-512 rows), a * b + c may
 * be one FMA, and separations and sums are formed in another order, so results agree with the
 * reference to round-off.
 *
 * Threads: rows are split into contiguous ranges of nearly equal cost, one per thread; each
 * thread adds into its own site-force and torque buffers; the buffers and the per-thread energy
 * and virial sums are added in thread order.  Fixed thread count: reproducible bit for bit.
 *
 * Virial: kernels add r (x) f with r the site separation; afterwards W = sum r (x) f -
 * sum_sites d_a (x) F_a (d_a = site - centre, F_a = total site force), which equals the
 * reference sum of R (x) f with R = r - d_a + d_b.  The TIP4P kernel with the centres' image
 * adds R (x) F per pair directly, and the compute step adds back its share of the correction
 * (see tip4p_row). */
#include "../../core/threads.h"
#include "forcefield_impl.h"
#include "rsqrt.h"
#include "rotleap/error.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#define RL_FAST_B 64    /* neighbours per batch                                     */
#define RL_FAST_MAXS 8  /* sites per molecule in the site kernels                   */
#define RL_FAST_MAXT (RL_FAST_MAXS * RL_FAST_MAXS)

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(ROTLEAP_NO_CLONES)
#define RL_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define RL_CLONES
#endif
#define RL_INLINE static inline __attribute__((always_inline))

/* The dipole and TIP4P rows in AVX-512 registers (dipole_row512, tip4p_row512), picked at
 * setup when the CPU has AVX-512F and ROTLEAP_NO_AVX512 is not set in the environment. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(ROTLEAP_NO_CLONES)
#define RL_X512 1
#include <immintrin.h>
#define RL_T512 __attribute__((target("avx512f")))
#else
#define RL_X512 0
#define RL_T512
#endif

/* nearbyint(x) for |x| < 2^51 in the default rounding mode, written so it vectorises:
 * x + 1.5 2^52 has unit spacing, so the sum rounds x to the nearest integer (ties to even). */
#define RL_RND(x) (((x) + 6755399441055744.0) - 6755399441055744.0)

enum { K_NONE = 0, K_SITES = 1, K_DIPOLE = 2, K_TIP4P = 3 };
enum { T_LJ = 0, T_COUL = 1, T_BOTH = 2 };

typedef struct {
  int a, b, what;
  double qq;                     /* kc q_a q_b                                          */
  double c6, c12, eshift, fshift; /* LJ (rl_lj_coef)                                    */
} fast_term;

/* What the kernels read: the bodies in the list's (spatial) order, see rl_ff_fast. */
typedef struct {
  double (*c)[3];                /* [n] centres                                          */
  double (*ax)[3];               /* [n] body Z axes                                      */
  double (*site)[3];             /* [nsites] lab sites                                   */
  double (*dsite)[3];            /* [nsites] site - centre                               */
  int *soff;                     /* [n] first site                                       */
  int *sp;                       /* [n] species                                          */
  double (*pk)[8];               /* [n] dipole ranks, AVX-512 path: centre, 0, mu axis, 0 */
  double (*pk4)[16];             /* [n] TIP4P ranks, AVX-512 path: centre, then site       */
                                 /* perm[s] - centre at 3 + 3 s, 0                      */
  float (*pk4f)[16];             /* [n] TIP4P ranks, mixed precision: site perm[s] -     */
                                 /* centre at 3 s, 0                                    */
  /* The image list of a small box (AVX2 TIP4P rows, see build_images): row m's images are
   * xnbr[xstart[m] .. xstart[m + 1]), the neighbour's rank, and its separation from m is
   * centre_m - centre_j + (xs[0][q], xs[1][q], xs[2][q]).  NULL where not in use. */
  const int *xstart, *xnbr;
  const double *xs[3];
} kview;

typedef struct fast_species fast_species;
typedef void (*row_fn)(const rl_forcefield *ff, const kview *V, const fast_species *K, int i,
                       const int *nbr, int len, double (*fs)[3], double (*tq)[3],
                       double (*ft)[8], double (*ft4)[16], rl_acc *acc);

struct fast_species {
  int kind, ns, nterms;
  fast_term t[RL_FAST_MAXT];     /* tip4p: t[0] the LJ term, t[1 + 3 p + q] charge p, q  */
  int perm[RL_FAST_MAXS];        /* batch slot s holds site perm[s] (tip4p: LJ site first) */
  double extent;                 /* max |site - centre|                                  */
  double mu;                     /* stockmayer: dipole moment                          */
  row_fn row[3];                 /* by separation mode (P_SITE, P_SHIFT, P_MOL)         */
  row_fn row_fo[3];              /* the same for a forces-only compute (acc->forces_only):
                                    rows without the energy and virial sums where there is
                                    such a variant (the AVX-512 TIP4P and dipole rows)   */
};

typedef struct {
  int *f, *g;                    /* kernel / reference neighbours of this chunk's rows  */
  long fcap, gcap, fn, gn;
} chunk_rows;

struct rl_ff_fast {
  int nthreads;
  fast_species *sk;              /* [nspecies]                                          */
  const char *name;
  char namebuf[96];
  rl_nlist *chk;                 /* positions at the last build (rebuild test only)     */
  int *fstart, *gstart;          /* [n + 1] CSR row starts                              */
  int *fnbr, *gnbr;              /* [npairs]                                            */
  long fcap, gcap;
  int *tlo;                      /* [nthreads + 1] row ranges                           */
  int *thi;                      /* [nthreads] thread t's rows write the kernel buffers   */
                                 /* (pfs, ptq, pft, pft4) of ranks [tlo[t], thi[t])    */
  int *rmax;                     /* [n] highest rank of row m and its kernel neighbours   */
  int nchunk;                    /* the list build's rows in chunks, threads take them  */
  chunk_rows *tr;                /* [nchunk] in turn (dynamic: the first ranks have more */
                                 /* candidates of higher rank)                          */
  int **cand;                    /* [nthreads][n + 16] one row's candidates within rlist */
  int *cell_of, *cell_start, *cell_body; /* cell list workspace                          */
  int ncell_cap;
  double *bx;                    /* [3 n] centres by rank, x then y then z: the build's scan */
  double (*fsbuf)[3];            /* [(nthreads - 1) nsites]                             */
  double (*tqbuf)[3];            /* [(nthreads - 1) n]                                  */
  rl_acc *acc;                   /* [nthreads]                                          */
  int *status;                   /* [nthreads]                                          */
  int *mode;                     /* [nspecies] separation mode of this compute          */
  /* Spatial order: at each build the bodies are ranked by cell (x fastest), and the kernels
   * work on copies in that order (V, refreshed every step), so a row's neighbours sit in a
   * few contiguous runs of memory and consecutive rows share them.  Kernel rows and their
   * neighbours are ranks; reference rows are ranks with body neighbours. */
  int *ord;                      /* [n] body of each rank                                */
  kview V;
  double (*pfs)[3];              /* [nthreads nsites] kernel site forces, rank order    */
  double (*ptq)[3];              /* [nthreads n] kernel torques, rank order             */
  int vec;                       /* the dipole and TIP4P rows: VEC_PORTABLE, or the      */
                                 /* register rows on VEC_512 (AVX-512) or VEC_256 (AVX2) */
  int tmix;                      /* the TIP4P rows in mixed precision (AVX2, pk4f)        */
  int ndip;                      /* bodies of K_DIPOLE species                           */
  double (*pft)[8];              /* vec:  [nthreads n] force 0..2, torque 4..6 on dipole  */
                                 /* ranks from the batches (rows add their own to pfs) */
  int ntip4p;                    /* bodies of K_TIP4P species                            */
  double (*pft4)[16];            /* vec:  [nthreads n] forces on TIP4P ranks' sites from */
                                 /* the batches, as in pk4                              */
  int *xstart, *xnbr;            /* the image list (kview), [n + 1] and [xcap + 4]       */
  struct far_image *xfar;        /* [n + 4] build_images' workspace                       */
  double *xsh;                   /* [3 (xcap + 4)] its shifts, x then y then z           */
  long xcap;
};

#ifndef _OPENMP
static int omp_get_thread_num(void) { return 0; }
#endif

/* ------------------------------------------------------------------------ LJ and RF */

/* The LJ coefficients of one term, copied by value into the loop: a load through a pointer
 * inside an `omp simd` loop becomes a masked load after if-conversion, which AVX2 lacks and
 * which stopped GCC 12 from vectorising the whole loop. */
typedef struct {
  double c6, c12, eshift, fshift;
} lj_consts;

RL_INLINE lj_consts lj_of(const fast_term *T)
{
  lj_consts c = {T->c6, T->c12, T->eshift, T->fshift};
  return c;
}

/* rl_lj_pair, branch-free, given ir2 = 1 / r2 (a kernel that has 1 / r from rl_rsqrt passes
 * its square, and saves a divide) */
RL_INLINE double lj_eval_ir2(const int trunc, const lj_consts C, double rc, double rsw, double r2,
                             double ir2, double *fr)
{
  double ir6 = ir2 * ir2 * ir2;
  double u = (C.c12 * ir6 - C.c6) * ir6;
  double f = (12.0 * C.c12 * ir6 - 6.0 * C.c6) * ir6 * ir2;
  if (trunc == RL_LJ_SHIFTED) {
    u -= C.eshift;
  } else if (trunc == RL_LJ_SHIFTED_FORCE) {
    double r = sqrt(r2);
    u -= C.eshift + (r - rc) * C.fshift;
    f += C.fshift / r;
  } else if (trunc == RL_LJ_SWITCHED) {
    double r = sqrt(r2);
    double w = rc - rsw, x = (r - rsw) / w;
    double S = 1.0 + x * x * x * (-10.0 + x * (15.0 - 6.0 * x));
    double dS = x * x * (-30.0 + x * (60.0 - 30.0 * x)) / w;
    double fsw = f * S - u * dS / r, usw = u * S;
    int sw = r > rsw, out = r >= rc;
    f = sw ? fsw : f;
    u = sw ? usw : u;
    f = out ? 0.0 : f;
    u = out ? 0.0 : u;
  }
  *fr = f;
  return u;
}

RL_INLINE double lj_eval(const int trunc, const lj_consts C, double rc, double rsw, double r2,
                         double *fr)
{
  return lj_eval_ir2(trunc, C, rc, rsw, r2, 1.0 / r2, fr);
}

/* ------------------------------------------------------------------------ batches */

/* How a kernel forms site separations r = (site a of i) - (site b of j):
 *   P_SITE   site cutoff, each site pair's own minimum image (boxes with an edge <= rp);
 *   P_SHIFT  site cutoff, r = R + d_a - d_b with R an image of the centres' separation, three
 *            fewer roundings per term than P_SITE.  A site pair inside the cutoff has centres
 *            closer than the pruning radius rp = rc + 2 extent.  When every edge L >= 2 rp the
 *            centres' minimum image is the only image that close; in smaller boxes (edges
 *            rp < L < 2 rp, e.g. 256 TIP4P at rc = 0.9 nm) the fills also emit the images
 *            X -+ L of the components with |X| > L - rp (other_images), each a lane of its own.
 *            Every site pair is then counted once: L >= 2 rc puts at most one of its images
 *            inside the cutoff.  Edges L <= rp (2 extent >= rc: molecules as long as the cutoff)
 *            take P_SITE;
 *   P_MOL    molecule cutoff: r = R + d_a - d_b, and the pair interacts iff |R| < rc. */
enum { P_SITE = 0, P_SHIFT = 1, P_MOL = 2 };

/* Batches are padded to a multiple of the widest vector (8 doubles, AVX-512), so the vector
 * loops never run a scalar remainder; padding lanes carry weight 0. */
#define RL_FAST_W 8

typedef struct {
  double L[3], iL[3], rc, rc2, rsw, md2, krf, crf;
} box_consts;

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

static box_consts consts_of(const rl_forcefield *ff)
{
  const double rc = ff->p.cutoff, md = ff->min_distance;
  box_consts B = {{ff->box.L[0], ff->box.L[1], ff->box.L[2]},
                  {ff->box.invL[0], ff->box.invL[1], ff->box.invL[2]},
                  rc, rc * rc, ff->p.r_switch, md * md, ff->rf.krf, ff->rf.crf};
  return B;
}

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
static __attribute__((noinline)) int other_images(const box_consts *B, double rp2, int far, int j,
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

/* ------------------------------------------------------------------------ site kernels */

typedef struct {
  double fx, fy, fz, elj, ecoul, bad, w[6];
} term_sums;

/* One term (site a of body i, site b of every neighbour in the batch) over the batch.
 * WHAT: T_LJ, T_COUL or T_BOTH.  Branch-free: the cutoff and the padding are factors. */
RL_INLINE void term_loop(const int MODE, const int TRUNC, const int WHAT, const box_consts *B,
                         const fast_term *T, const double *pa, batch *b, term_sums *s)
{
  const double rc = B->rc, rsw = B->rsw, md2 = B->md2, krf = B->krf, crf = B->crf;
  const double ax = pa[0], ay = pa[1], az = pa[2], qq = T->qq;
  const lj_consts C = lj_of(T);
  const int sb = T->b, np = b->np;
  double fax = 0.0, fay = 0.0, faz = 0.0, elj = 0.0, ecoul = 0.0, bad = 0.0;
  double w0 = 0.0, w1 = 0.0, w2 = 0.0, w3 = 0.0, w4 = 0.0, w5 = 0.0;
  double *fbx = b->f[sb][0], *fby = b->f[sb][1], *fbz = b->f[sb][2];
#pragma omp simd reduction(+ : fax, fay, faz, elj, ecoul, bad, w0, w1, w2, w3, w4, w5)
  for (int k = 0; k < np; k++) {
    double dx, dy, dz;
    sep(MODE, B, ax, ay, az, b, sb, k, &dx, &dy, &dz);
    double r2 = dx * dx + dy * dy + dz * dz;
    const double in = inside(MODE, B, b, k, r2);
    bad += in * (r2 < md2 ? 1.0 : 0.0);
    double fx = 0.0, fy = 0.0, fz = 0.0;
    if (WHAT != T_COUL) {
      double fr, u = lj_eval(TRUNC, C, rc, rsw, r2, &fr);
      fr *= in;
      elj += in * u;
      fx += fr * dx; fy += fr * dy; fz += fr * dz;
    }
    if (WHAT != T_LJ) { /* rl_coulomb_rf_pair */
      double ir = rl_rsqrt(r2);
      double fr = qq * (ir * ir * ir - 2.0 * krf);
      double u = qq * (ir + krf * r2 - crf);
      fr *= in;
      ecoul += in * u;
      fx += fr * dx; fy += fr * dy; fz += fr * dz;
    }
    fax += fx; fay += fy; faz += fz;
    fbx[k] -= fx; fby[k] -= fy; fbz[k] -= fz;
    w0 += dx * fx; w1 += dx * fy; w2 += dx * fz;
    w3 += dy * fy; w4 += dy * fz; w5 += dz * fz;
  }
  s->fx = fax; s->fy = fay; s->fz = faz; s->elj = elj; s->ecoul = ecoul; s->bad = bad;
  s->w[0] = w0; s->w[1] = w1; s->w[2] = w2; s->w[3] = w3; s->w[4] = w4; s->w[5] = w5;
}

/* Add a row's sums to the thread's accumulators (site virial, symmetric). */
static inline void acc_add(rl_acc *acc, double elj, double ecoul, const double w[6], double bad)
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

/* One row of a site-kernel species ("charge-lj"): rank i against the ranks nbr[0..len) (same
 * species), one loop per term. */
RL_INLINE void sites_row(const int MODE, const int TRUNC, const rl_forcefield *ff, const kview *V,
                         const fast_species *K, int i, const int *nbr, int len,
                         double (*fs)[3], rl_acc *acc)
{
  const int ns = K->ns, oi = V->soff[i];
  const box_consts B = consts_of(ff);
  const double rp2 = prune2(MODE, &B, K);
  const int img = needs_images(MODE, &B, rp2);
  batch b;
  double fi[RL_FAST_MAXS][3];
  memset(fi, 0, sizeof fi);
  double elj = 0.0, ecoul = 0.0, w[6] = {0}, bad = 0.0;
  for (int pos = 0; pos < len;) {
    batch_fill(MODE, 0, 1, V, &B, i, nbr, len, &pos, K, rp2, img, &b); /* K->perm: identity */
    if (b.n == 0) continue;
    for (int t = 0; t < K->nterms; t++) {
      const fast_term *T = &K->t[t];
      const double *pa = site_of_i(MODE, V, oi + T->a);
      term_sums s = {0};
      if (T->what == T_LJ) term_loop(MODE, TRUNC, T_LJ, &B, T, pa, &b, &s);
      else if (T->what == T_COUL) term_loop(MODE, TRUNC, T_COUL, &B, T, pa, &b, &s);
      else term_loop(MODE, TRUNC, T_BOTH, &B, T, pa, &b, &s);
      fi[T->a][0] += s.fx; fi[T->a][1] += s.fy; fi[T->a][2] += s.fz;
      elj += s.elj; ecoul += s.ecoul; bad += s.bad;
      for (int c = 0; c < 6; c++) w[c] += s.w[c];
    }
    batch_scatter(0, V, &b, K, fs, NULL);
  }
  for (int a = 0; a < ns; a++)
    for (int c = 0; c < 3; c++) fs[oi + a][c] += fi[a][c];
  acc_add(acc, elj, ecoul, w, bad);
}

/* ------------------------------------------------------------------------ TIP4P kernel */

/* What a TIP4P register row (tip4p_row512, tip4p_row256) needs of row i: the box, the pruning
 * radius, the LJ and charge-pair constants, i's sites relative to its centre (from its record:
 * it alone is fresh, the site buffers are not), and the overlap limit (as tip4p_row's). */
typedef struct {
  box_consts B;
  double rp2, lim, a[4][3], qq[3][3];
  int img;
  lj_consts C;
} tip_row;

RL_INLINE void tip_row_of(const int MODE, const rl_forcefield *ff, const kview *V,
                          const fast_species *K, int i, tip_row *T)
{
  T->B = consts_of(ff);
  T->rp2 = prune2(MODE, &T->B, K);
  T->img = needs_images(MODE, &T->B, T->rp2);
  T->C = lj_of(&K->t[0]);
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) T->a[s][c] = V->pk4[i][3 + 3 * s + c];
  for (int p = 0; p < 3; p++)
    for (int q = 0; q < 3; q++) T->qq[p][q] = K->t[1 + 3 * p + q].qq;
  T->lim = MODE == P_MOL || T->B.md2 < T->B.rc2 ? T->B.md2 : T->B.rc2;
}


/* lj_eval_ir2 on a vector type VT (lj8, lj4), given ir2 = 1 / r^2 and, for the truncations,
 * rr = |r| and ir = 1 / |r|; V1 broadcasts, SEL(rr, a, b) is b beyond r_switch, 0 beyond the
 * cutoff, else a. */
#define RL_LJ_VEC(VT, V1, SEL)                                                                 \
  const VT ir6 = ir2 * ir2 * ir2;                                                              \
  VT ul = (V1(C.c12) * ir6 - V1(C.c6)) * ir6;                                                  \
  VT frl = (V1(12.0 * C.c12) * ir6 - V1(6.0 * C.c6)) * ir6 * ir2;                              \
  if (TRUNC == RL_LJ_SHIFTED) {                                                                \
    ul = ul - V1(C.eshift);                                                                    \
  } else if (TRUNC == RL_LJ_SHIFTED_FORCE) {                                                   \
    ul = ul - (V1(C.eshift) + (rr - V1(B->rc)) * V1(C.fshift));                                \
    frl = frl + V1(C.fshift) * ir;                                                             \
  } else if (TRUNC == RL_LJ_SWITCHED) {                                                        \
    const double w = B->rc - B->rsw;                                                           \
    const VT x = (rr - V1(B->rsw)) * V1(1.0 / w);                                              \
    const VT Sw = V1(1.0) + x * x * x * (V1(-10.0) + x * (V1(15.0) - V1(6.0) * x));           \
    const VT dS = x * x * (V1(-30.0) + x * (V1(60.0) - V1(30.0) * x)) * V1(1.0 / w);          \
    const VT fsw = frl * Sw - ul * dS * ir, usw = ul * Sw;                                     \
    frl = SEL(rr, frl, fsw);                                                                   \
    ul = SEL(rr, ul, usw);                                                                     \
  }                                                                                            \
  *u = ul;                                                                                     \
  *fr = frl

#if RL_X512
/* The TIP4P rows on AVX-512: each TIP4P rank's centre and sites relative to it sit in a
 * 128-byte record (V->pk4), two 512-bit rows.  The fill tests eight candidates at a time
 * against the pruning radius (their centres transposed from the records, sep8) and packs the
 * kept ones' indices and separations onto the batch (a scalar pass over the candidates was a
 * fifth of the TIP4P time, issue 8).  tip4p_pairs512 then loads the kept ones' records eight at
 * a time, transposes each half (8 x 8) into their sites, forms the terms, and transposes the
 * site forces back into records, added with two 512-bit adds per neighbour into the thread's
 * buffer (ft4). */

/* in[r][c] -> out[c][r], eight rows of eight doubles: 24 shuffles */
RL_T512 static inline void tr8x8(const __m512d in[8], __m512d out[8])
{
  const __m512i even = _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0);
  const __m512i odd = _mm512_set_epi64(15, 14, 7, 6, 11, 10, 3, 2);
  __m512d u[4], v[4];
  for (int h = 0; h < 2; h++) { /* rows 0-3, then 4-7 */
    const __m512d *r = in + 4 * h;
    const __m512d t0 = _mm512_unpacklo_pd(r[0], r[1]), t1 = _mm512_unpackhi_pd(r[0], r[1]);
    const __m512d t2 = _mm512_unpacklo_pd(r[2], r[3]), t3 = _mm512_unpackhi_pd(r[2], r[3]);
    __m512d *w = h ? v : u; /* columns 0|4, 2|6, 1|5, 3|7 of four rows */
    w[0] = _mm512_permutex2var_pd(t0, even, t2);
    w[1] = _mm512_permutex2var_pd(t0, odd, t2);
    w[2] = _mm512_permutex2var_pd(t1, even, t3);
    w[3] = _mm512_permutex2var_pd(t1, odd, t3);
  }
  out[0] = _mm512_shuffle_f64x2(u[0], v[0], 0x44);
  out[4] = _mm512_shuffle_f64x2(u[0], v[0], 0xEE);
  out[2] = _mm512_shuffle_f64x2(u[1], v[1], 0x44);
  out[6] = _mm512_shuffle_f64x2(u[1], v[1], 0xEE);
  out[1] = _mm512_shuffle_f64x2(u[2], v[2], 0x44);
  out[5] = _mm512_shuffle_f64x2(u[2], v[2], 0xEE);
  out[3] = _mm512_shuffle_f64x2(u[3], v[3], 0x44);
  out[7] = _mm512_shuffle_f64x2(u[3], v[3], 0xEE);
}

/* 1 / sqrt(x) on 8 lanes: vrsqrt14pd (relative error < 2^-14) and two Newton steps
 * (error ~ 1.5 e^2 each: 6e-9, then 5e-17), within a few ulp like rl_rsqrt */
RL_T512 static inline __m512d rsqrt8(__m512d x)
{
  const __m512d half = _mm512_set1_pd(0.5), h = _mm512_mul_pd(half, x);
  __m512d y = _mm512_rsqrt14_pd(x);
  y = _mm512_fmadd_pd(y, _mm512_fnmadd_pd(_mm512_mul_pd(h, y), y, half), y);
  y = _mm512_fmadd_pd(y, _mm512_fnmadd_pd(_mm512_mul_pd(h, y), y, half), y);
  return y;
}

/* lj_eval_ir2 on 8 lanes (RL_LJ_VEC; the dipole rows pass rsqrt8's rr and ir, the TIP4P rows
 * a divide's) */
#define RL_SEL8(rr, a, b)                                                                      \
  _mm512_maskz_mov_pd(_mm512_cmp_pd_mask(rr, _mm512_set1_pd(B->rc), _CMP_LT_OQ),              \
                      _mm512_mask_blend_pd(_mm512_cmp_pd_mask(rr, _mm512_set1_pd(B->rsw),     \
                                                              _CMP_GT_OQ), a, b))
RL_T512 RL_INLINE void lj8(const int TRUNC, const lj_consts C, const box_consts *B, __m512d ir2,
                           __m512d rr, __m512d ir, __m512d *u, __m512d *fr)
{
  RL_LJ_VEC(__m512d, _mm512_set1_pd, RL_SEL8);
}
#undef RL_SEL8

/* The box and the centre of row i, broadcast, for sep8. */
typedef struct {
  __m512d c[3], L[3], iL[3], big;
  __m512i even, odd; /* lanes (0 1 8 9 4 5 12 13) and (2 3 10 11 6 7 14 15) of two vectors */
} sep8_consts;

RL_T512 static inline sep8_consts sep8_of(const box_consts *B, const double *ci)
{
  sep8_consts S;
  for (int c = 0; c < 3; c++) {
    S.c[c] = _mm512_set1_pd(ci[c]);
    S.L[c] = _mm512_set1_pd(B->L[c]);
    S.iL[c] = _mm512_set1_pd(B->iL[c]);
  }
  S.big = _mm512_set1_pd(6755399441055744.0);
  S.even = _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0);
  S.odd = _mm512_set_epi64(15, 14, 7, 6, 11, 10, 3, 2);
  return S;
}

/* The minimum-image separations R[c] = centre_i - centre of record q[l] in lane l, for eight
 * records whose first three doubles are the centre (32-byte aligned): their first 256 bits
 * are paired into four vectors (record l | record l + 4) and transposed.  The image as
 * take_candidate's RL_RND: X -= L nearbyint(X / L). */
RL_T512 static inline void sep8(const sep8_consts *S, const double *const q[8], __m512d R[3])
{
  __m512d c[4];
  for (int l = 0; l < 4; l++)
    c[l] = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_load_pd(q[l])),
                              _mm256_load_pd(q[l + 4]), 1);
  const __m512d cl01 = _mm512_unpacklo_pd(c[0], c[1]), ch01 = _mm512_unpackhi_pd(c[0], c[1]);
  const __m512d cl23 = _mm512_unpacklo_pd(c[2], c[3]), ch23 = _mm512_unpackhi_pd(c[2], c[3]);
  R[0] = _mm512_permutex2var_pd(cl01, S->even, cl23);
  R[1] = _mm512_permutex2var_pd(ch01, S->even, ch23);
  R[2] = _mm512_permutex2var_pd(cl01, S->odd, cl23);
  for (int d = 0; d < 3; d++) {
    const __m512d X = _mm512_sub_pd(S->c[d], R[d]);
    const __m512d k = _mm512_sub_pd(_mm512_fmadd_pd(X, S->iL[d], S->big), S->big);
    R[d] = _mm512_fnmadd_pd(S->L[d], k, X);
  }
}

/* Append the lanes of keep (in lane order) of the candidates' indices id and separations
 * (X, Y, Z) to the batch from slot n; returns the new n.  Each store is a full vector: the
 * batch's idx and R rows have RL_FAST_W slots of slack past RL_FAST_B for it. */
RL_T512 static inline int fill_append512(batch *b, int n, __mmask8 keep, __m512i id, __m512d X,
                                         __m512d Y, __m512d Z)
{
  _mm256_storeu_si256((__m256i *)(b->idx + n),
                      _mm512_castsi512_si256(_mm512_maskz_compress_epi32(keep, id)));
  _mm512_storeu_pd(b->R[0] + n, _mm512_maskz_compress_pd(keep, X));
  _mm512_storeu_pd(b->R[1] + n, _mm512_maskz_compress_pd(keep, Y));
  _mm512_storeu_pd(b->R[2] + n, _mm512_maskz_compress_pd(keep, Z));
  return n + __builtin_popcount(keep);
}

/* batch_fill for the TIP4P rows with the centres' image (P_SHIFT, P_MOL), eight candidates at
 * a time: their centres are read from the first 256 bits of their records and transposed
 * (sep8), the minimum image and the pruning test run in one vector each, and the kept ones are
 * packed (vcompresspd) onto the batch in list order.  The batch gets the same neighbours in the
 * same lanes as from batch_fill, and ends where batch_fill's does (when full, or before a
 * neighbour whose images would not all fit), so the pair sums do not depend on which
 * candidates beyond rp the list holds, that is on when it was built: restarts stay bit for
 * bit (tests/cli/restart_tests.sh).  In a box that needs the other images (img), eight
 * candidates of which one has another image within rp go one by one through take_candidate,
 * which puts a neighbour's images right after it; for 256 TIP4P at rc = 0.9 nm that is about
 * one group in eight. */
RL_T512 static inline void tip4p_fill512(const kview *V, const box_consts *B, int i,
                                         const int *nbr, int len, int *pos, double rp2, int img,
                                         batch *b)
{
  const sep8_consts S = sep8_of(B, V->pk4[i]); /* the record starts with the centre */
  const __m512d Lx = S.L[0], Ly = S.L[1], Lz = S.L[2], vrp2 = _mm512_set1_pd(rp2);
  const double rp = img ? sqrt(rp2) : 0.0;
  const __m512d nx = _mm512_set1_pd(B->L[0] - rp), ny = _mm512_set1_pd(B->L[1] - rp),
                nz = _mm512_set1_pd(B->L[2] - rp), zero = _mm512_setzero_pd();
  int n = 0, p = *pos, full = 0;
  while (p < len && n < RL_FAST_B && !full) {
    const int cnt = len - p < RL_FAST_W ? len - p : RL_FAST_W;
    const __mmask8 live = (__mmask8)((1u << cnt) - 1u);
    const double *q[8];
    for (int l = 0; l < 8; l++) q[l] = V->pk4[nbr[p + (l < cnt ? l : 0)]]; /* tail: the first */
    __m512d R[3];
    sep8(&S, q, R);
    const __m512d X = R[0], Y = R[1], Z = R[2];
    const __m512d r2 = _mm512_fmadd_pd(Z, Z, _mm512_fmadd_pd(Y, Y, _mm512_mul_pd(X, X)));
    __mmask8 keep = _mm512_mask_cmp_pd_mask(live, r2, vrp2, _CMP_LT_OQ);
    if (img) { /* does any of the eight have another image within rp (other_images)? */
      const __mmask8 fx = _mm512_mask_cmp_pd_mask(live, _mm512_abs_pd(X), nx, _CMP_GT_OQ);
      const __mmask8 fy = _mm512_mask_cmp_pd_mask(live, _mm512_abs_pd(Y), ny, _CMP_GT_OQ);
      const __mmask8 fz = _mm512_mask_cmp_pd_mask(live, _mm512_abs_pd(Z), nz, _CMP_GT_OQ);
      const __m512d xs[2] = {X, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(X, zero, _CMP_GT_OQ),
                                                     _mm512_add_pd(X, Lx), _mm512_sub_pd(X, Lx))};
      const __m512d ys[2] = {Y, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(Y, zero, _CMP_GT_OQ),
                                                     _mm512_add_pd(Y, Ly), _mm512_sub_pd(Y, Ly))};
      const __m512d zs[2] = {Z, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(Z, zero, _CMP_GT_OQ),
                                                     _mm512_add_pd(Z, Lz), _mm512_sub_pd(Z, Lz))};
      /* the images that shift two or three components (a corner's) only if a lane has one */
      const int nm = (fx & fy) | (fx & fz) | (fy & fz) ? 7 : 3;
      static const int order[7] = {1, 2, 4, 3, 5, 6, 7};
      __mmask8 more = 0, km[8] = {keep, 0, 0, 0, 0, 0, 0, 0}; /* km[m]: image m kept */
      for (int t = 0; t < nm; t++) {
        const int m = order[t];
        const __mmask8 far = (m & 1 ? fx : live) & (m & 2 ? fy : live) & (m & 4 ? fz : live);
        const __m512d u = xs[m & 1], v = ys[(m >> 1) & 1], w = zs[m >> 2];
        const __m512d s2 = _mm512_fmadd_pd(w, w, _mm512_fmadd_pd(v, v, _mm512_mul_pd(u, u)));
        km[m] = _mm512_mask_cmp_pd_mask(far, s2, vrp2, _CMP_LT_OQ);
        more |= km[m];
      }
      if (more) {
        /* a neighbour's images follow it, as in take_candidate: each of the eight in list
         * order, its minimum image (m = 0) then its other images m = 1 .. 7 (other_images'
         * order), from the vectors' lanes (before 2026-11-22 the eight went one by one through
         * take_candidate; other_images alone was 4 % of a 256-TIP4P step in perf) */
        _Alignas(64) double u[2][8], v[2][8], w[2][8];
        _mm512_store_pd(u[0], X); _mm512_store_pd(u[1], xs[1]);
        _mm512_store_pd(v[0], Y); _mm512_store_pd(v[1], ys[1]);
        _mm512_store_pd(w[0], Z); _mm512_store_pd(w[1], zs[1]);
        unsigned kept[8] = {0}; /* lane l: bit m if image m is kept */
        for (int m = 0; m < 8; m++)
          for (int l = 0; l < 8; l++) kept[l] |= ((km[m] >> l) & 1u) << m;
        for (int l = 0; l < cnt && n < RL_FAST_B; l++, p++) {
          if (n + __builtin_popcount(kept[l]) > RL_FAST_B) { /* the next batch takes it */
            full = 1;
            break;
          }
          for (unsigned bits = kept[l]; bits; bits &= bits - 1) {
            const int m = __builtin_ctz(bits);
            b->idx[n] = nbr[p];
            b->R[0][n] = u[m & 1][l];
            b->R[1][n] = v[(m >> 1) & 1][l];
            b->R[2][n] = w[m >> 2][l];
            n++;
          }
        }
        continue;
      }
    }
    /* the kept ones in list order, as many as fit: a batch ends where batch_fill's does */
    const __m512i id = _mm512_maskz_loadu_epi32((__mmask16)live, nbr + p);
    const int room = RL_FAST_B - n;
    if (__builtin_popcount(keep) > room) {
      while (__builtin_popcount(keep) > room) keep &= (__mmask8)~(1u << (31 - __builtin_clz(keep)));
      p += 32 - __builtin_clz(keep); /* past the last one taken */
    } else {
      p += cnt;
    }
    n = fill_append512(b, n, keep, id, X, Y, Z);
  }
  *pos = p;
  const int np = (n + RL_FAST_W - 1) / RL_FAST_W * RL_FAST_W;
  for (int k = n; k < np; k++) { /* padding: a copy of the first neighbour, masked out */
    b->idx[k] = b->idx[0];
    for (int c = 0; c < 3; c++) b->R[c][k] = b->R[c][0];
  }
  b->n = n;
  b->np = np;
}

/* The sums of a TIP4P row on AVX-512 over all its neighbours, lane by lane (tip4p_pairs512). */
typedef struct {
  __m512d fi[4][3]; /* forces on i's sites, by slot (LJ site, then charges) */
  __m512d w[9];     /* EV: R (x) F, F the pair's force on i */
  __m512d elj, ecoul;
  __m512d r2min;    /* the closest site pair of each lane's neighbours */
} tip_sums;

/* The 1 LJ + 9 Coulomb terms of a TIP4P batch (P_SHIFT or P_MOL), eight neighbours per
 * vector, in registers: each eight neighbours' records are loaded and transposed into their
 * sites, the terms formed (lj8 with a divide for 1 / r^2; the Coulomb terms as
 * rl_coulomb_rf_pair with 1/sqrt from vrsqrt14pd and two Newton steps, relative error
 * 2^-14 -> 6e-9 -> 5e-17, where the portable rows' rl_rsqrt takes four steps from a bit trick),
 * the forces on i's sites added to the row's running sums S, and the forces on the
 * neighbours' sites transposed back into records and added to the thread's buffer (ft4).
 * Until 2026-11-22 the batch went through memory between an `omp simd` LJ loop, a Coulomb
 * loop, a reduction per site component and a scatter loop, which took half of a 256-TIP4P
 * row's time (perf).  Neighbour k of a batch takes lane k mod 8 as before, and the batches end
 * where batch_fill's do, so the sums do not depend on when the list was built.  The cutoff
 * (P_SHIFT) and the padding are masks. */
RL_T512 RL_INLINE void tip4p_pairs512(const int MODE, const int EV, const int TRUNC,
                                      const lj_consts C, const box_consts *B,
                                      const double a[4][3], const double qq[3][3],
                                      const kview *V, const batch *b, double (*ft4)[16],
                                      tip_sums *S)
{
#define V1(x) _mm512_set1_pd(x)
  const __m512d zero = _mm512_setzero_pd(), half = V1(0.5), rc2 = V1(B->rc2);
  const __m512d krf = V1(B->krf), krf2 = V1(2.0 * B->krf), crf = V1(B->crf);
  for (int k = 0; k < b->n; k += RL_FAST_W) {
    const int cnt = b->n - k < RL_FAST_W ? b->n - k : RL_FAST_W;
    const __mmask8 live = (__mmask8)((1u << cnt) - 1u);
    const __m512d R[3] = {_mm512_load_pd(b->R[0] + k), _mm512_load_pd(b->R[1] + k),
                          _mm512_load_pd(b->R[2] + k)};
    __m512d lo[8], hi[8], A[8], H[8];
    for (int l = 0; l < 8; l++) {
      const double *q = V->pk4[b->idx[k + l]];
      lo[l] = _mm512_load_pd(q);
      hi[l] = _mm512_load_pd(q + 8);
    }
    tr8x8(lo, A); /* A[3 + 3 s + c]: site s, component c of the eight (s = 0, 1; c < 2) */
    tr8x8(hi, H); /* H[3 + 3 s + c - 8]: the rest */
    __m512d xj[4][3], gj[4][3];
    for (int s = 0; s < 4; s++)
      for (int c = 0; c < 3; c++) {
        const int e = 3 + 3 * s + c;
        xj[s][c] = e < 8 ? A[e] : H[e - 8];
      }
    { /* LJ between the LJ sites (slot 0): lj_eval */
      __m512d d[3];
      for (int c = 0; c < 3; c++) d[c] = R[c] + V1(a[0][c]) - xj[0][c];
      const __m512d r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      const __mmask8 in = MODE == P_MOL ? live : _mm512_mask_cmp_pd_mask(live, r2, rc2, _CMP_LT_OQ);
      S->r2min = _mm512_mask_min_pd(S->r2min, live, S->r2min, r2);
      const __m512d ir2 = V1(1.0) / r2;
      __m512d rr = zero, ir = zero;
      if (TRUNC == RL_LJ_SHIFTED_FORCE || TRUNC == RL_LJ_SWITCHED) {
        rr = _mm512_sqrt_pd(r2);
        ir = V1(1.0) / rr;
      }
      __m512d u, fr;
      lj8(TRUNC, C, B, ir2, rr, ir, &u, &fr);
      fr = _mm512_maskz_mov_pd(in, fr);
      if (EV) S->elj = _mm512_mask_add_pd(S->elj, in, S->elj, u);
      for (int c = 0; c < 3; c++) {
        const __m512d f = fr * d[c];
        S->fi[0][c] = S->fi[0][c] + f;
        gj[0][c] = zero - f;
      }
    }
    for (int q = 0; q < 3; q++)
      for (int c = 0; c < 3; c++) gj[1 + q][c] = zero;
    for (int p = 0; p < 3; p++) { /* charge p of i against charge q of j: rl_coulomb_rf_pair */
      __m512d ra[3];
      for (int c = 0; c < 3; c++) ra[c] = R[c] + V1(a[1 + p][c]);
      for (int q = 0; q < 3; q++) {
        __m512d d[3];
        for (int c = 0; c < 3; c++) d[c] = ra[c] - xj[1 + q][c];
        const __m512d r2 =
            _mm512_fmadd_pd(d[2], d[2], _mm512_fmadd_pd(d[1], d[1], _mm512_mul_pd(d[0], d[0])));
        const __mmask8 in =
            MODE == P_MOL ? live : _mm512_mask_cmp_pd_mask(live, r2, rc2, _CMP_LT_OQ);
        S->r2min = _mm512_mask_min_pd(S->r2min, live, S->r2min, r2);
        const __m512d h = half * r2;
        __m512d ir = _mm512_rsqrt14_pd(r2);
        ir = _mm512_fmadd_pd(ir, _mm512_fnmadd_pd(h, ir * ir, half), ir);
        ir = _mm512_fmadd_pd(ir, _mm512_fnmadd_pd(h, ir * ir, half), ir);
        const __m512d qv = V1(qq[p][q]);
        const __m512d fr = _mm512_maskz_mul_pd(in, qv, ir * ir * ir - krf2);
        if (EV) /* qq (1/r + krf r^2 - crf) */
          S->ecoul = _mm512_mask3_fmadd_pd(qv, _mm512_fmadd_pd(krf, r2, ir) - crf, S->ecoul, in);
        for (int c = 0; c < 3; c++) {
          const __m512d f = fr * d[c];
          S->fi[1 + p][c] = S->fi[1 + p][c] + f;
          gj[1 + q][c] = gj[1 + q][c] - f;
        }
      }
    }
    if (EV) /* R (x) F, F = -(sum of the forces on j's sites) the pair's force on i */
      for (int c = 0; c < 3; c++) {
        const __m512d F = zero - ((gj[0][c] + gj[1][c]) + (gj[2][c] + gj[3][c]));
        for (int r = 0; r < 3; r++) S->w[3 * r + c] = S->w[3 * r + c] + R[r] * F;
      }
    /* the forces on the neighbours' sites, as records (centre 0, sites, 0), added in order */
    const __m512d ea[8] = {zero, zero, zero, gj[0][0], gj[0][1], gj[0][2], gj[1][0], gj[1][1]};
    const __m512d eh[8] = {gj[1][2], gj[2][0], gj[2][1], gj[2][2],
                           gj[3][0], gj[3][1], gj[3][2], zero};
    tr8x8(ea, lo);
    tr8x8(eh, hi);
    for (int l = 0; l < cnt; l++) {
      double *o = ft4[b->idx[k + l]];
      _mm512_store_pd(o, _mm512_add_pd(_mm512_load_pd(o), lo[l]));
      _mm512_store_pd(o + 8, _mm512_add_pd(_mm512_load_pd(o + 8), hi[l]));
    }
  }
#undef V1
}

/* tip4p_row on AVX-512 (P_SHIFT, P_MOL): the batches from tip4p_fill512, their terms in
 * registers (tip4p_pairs512), i's site forces and (EV) the energies and R (x) F summed lane by
 * lane over the row and reduced at its end. */
RL_T512 RL_INLINE void tip4p_row512(const int EV, const int MODE, const int TRUNC,
                                    const rl_forcefield *ff, const kview *V, const fast_species *K,
                                    int i, const int *nbr, int len, double (*fs)[3],
                                    double (*ft4)[16], rl_acc *acc)
{
  tip_row T;
  tip_row_of(MODE, ff, V, K, i, &T);
  const __m512d z = _mm512_setzero_pd();
  tip_sums S;
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) S.fi[s][c] = z;
  for (int c = 0; c < 9; c++) S.w[c] = z;
  S.elj = S.ecoul = z;
  S.r2min = _mm512_set1_pd(HUGE_VAL);
  batch b;
  for (int pos = 0; pos < len;) {
    tip4p_fill512(V, &T.B, i, nbr, len, &pos, T.rp2, T.img, &b);
    if (b.n) tip4p_pairs512(MODE, EV, TRUNC, T.C, &T.B, T.a, T.qq, V, &b, ft4, &S);
  }
  const int oi = V->soff[i];
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) fs[oi + K->perm[s]][c] += _mm512_reduce_add_pd(S.fi[s][c]);
  if (EV) {
    acc->lj += _mm512_reduce_add_pd(S.elj);
    acc->coul += _mm512_reduce_add_pd(S.ecoul);
    for (int c = 0; c < 9; c++) acc->vir[c] += _mm512_reduce_add_pd(S.w[c]);
  }
  /* overlap: a site pair inside the cutoff closer than the minimum distance, as tip4p_row */
  acc->bad |= _mm512_cmp_pd_mask(S.r2min, _mm512_set1_pd(T.lim), _CMP_LT_OQ) != 0;
}
#endif


/* One LJ site without charge and three charges without LJ (TIP4P and its reparametrisations):
 * the batch's sites are gathered in the order LJ site, charge sites (K->perm), and the 1 LJ
 * + 9 Coulomb terms run in one loop, so each neighbour's sites are loaded once and its forces
 * stored once.  Each term is the reference formula (1/sqrt by rl_rsqrt).  On AVX-512
 * tip4p_row512 forms the same terms in registers instead.
 *
 * Virial: with the centres' image (P_SHIFT, P_MOL) every term's separation is r = R + d_a -
 * d_b, so the pair's share of the molecular virial is R (x) F with F the pair's total force:
 * 9 multiply-adds per pair instead of 6 per term.  rl_ff_fast_compute adds back sum d (x) F
 * over these kernels' site forces, which the final site-to-molecule correction subtracts
 * from every site force.  With site images (P_SITE) each term keeps r (x) f. */
RL_INLINE void tip4p_row(const int MODE, const int TRUNC, const rl_forcefield *ff,
                         const kview *V, const fast_species *K, int i, const int *nbr, int len,
                         double (*fs)[3], rl_acc *acc)
{
  const int oi = V->soff[i];
  const box_consts B = consts_of(ff);
  const double rp2 = prune2(MODE, &B, K);
  const int img = needs_images(MODE, &B, rp2);
  const double rc = B.rc, rsw = B.rsw, md2 = B.md2, krf = B.krf, crf = B.crf;
  const lj_consts C = lj_of(&K->t[0]);
  double a[4][3], qq[3][3];
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) a[s][c] = site_of_i(MODE, V, oi + K->perm[s])[c];
  for (int p = 0; p < 3; p++)
    for (int q = 0; q < 3; q++) qq[p][q] = K->t[1 + 3 * p + q].qq;
  batch b;
  double fi[4][3] = {{0}};
  double elj = 0.0, ecoul = 0.0, bad = 0.0;
  double w0 = 0.0, w1 = 0.0, w2 = 0.0, w3 = 0.0, w4 = 0.0, w5 = 0.0;
  double v0 = 0.0, v1 = 0.0, v2 = 0.0, v3 = 0.0, v4 = 0.0, v5 = 0.0, v6 = 0.0, v7 = 0.0, v8 = 0.0;
  const int SITEVIR = MODE == P_SITE;
  for (int pos = 0; pos < len;) {
    batch_fill(MODE, 0, 0, V, &B, i, nbr, len, &pos, K, rp2, img, &b);
    if (b.n == 0) continue;
    const int np = b.np;
#pragma omp simd reduction(+ : elj, ecoul, w0, w1, w2, w3, w4, w5)
    for (int k = 0; k < np; k++) {
      double gi[4][3] = {{0}}, gj[4][3] = {{0}};
      double r2min;
      { /* LJ between the LJ sites */
        double dx, dy, dz;
        sep(MODE, &B, a[0][0], a[0][1], a[0][2], &b, 0, k, &dx, &dy, &dz);
        double r2 = dx * dx + dy * dy + dz * dz;
        const double in = inside(MODE, &B, &b, k, r2);
        r2min = r2;
        double fr, u = lj_eval(TRUNC, C, rc, rsw, r2, &fr);
        fr *= in;
        elj += in * u;
        const double fx = fr * dx, fy = fr * dy, fz = fr * dz;
        gi[0][0] += fx; gi[0][1] += fy; gi[0][2] += fz;
        gj[0][0] -= fx; gj[0][1] -= fy; gj[0][2] -= fz;
        if (SITEVIR) {
          w0 += dx * fx; w1 += dx * fy; w2 += dx * fz;
          w3 += dy * fy; w4 += dy * fz; w5 += dz * fz;
        }
      }
      /* the term loops must be unrolled before the k loop can be vectorised */
#pragma GCC unroll 3
      for (int p = 0; p < 3; p++)
#pragma GCC unroll 3
        for (int q = 0; q < 3; q++) { /* rl_coulomb_rf_pair */
          double dx, dy, dz;
          sep(MODE, &B, a[1 + p][0], a[1 + p][1], a[1 + p][2], &b, 1 + q, k, &dx, &dy, &dz);
          double r2 = dx * dx + dy * dy + dz * dz;
          const double in = inside(MODE, &B, &b, k, r2);
          r2min = r2 < r2min ? r2 : r2min;
          /* (qq in) x: the reference's qq x times a 0/1 factor, bit for bit, one multiply less */
          const double qin = qq[p][q] * in, ir = rl_rsqrt(r2);
          const double fr = qin * (ir * ir * ir - 2.0 * krf);
          ecoul += qin * (ir + krf * r2 - crf);
          const double fx = fr * dx, fy = fr * dy, fz = fr * dz;
          gi[1 + p][0] += fx; gi[1 + p][1] += fy; gi[1 + p][2] += fz;
          gj[1 + q][0] -= fx; gj[1 + q][1] -= fy; gj[1 + q][2] -= fz;
          if (SITEVIR) {
            w0 += dx * fx; w1 += dx * fy; w2 += dx * fz;
            w3 += dy * fy; w4 += dy * fz; w5 += dz * fz;
          }
        }
#pragma GCC unroll 4
      for (int s = 0; s < 4; s++)
#pragma GCC unroll 3
        for (int c = 0; c < 3; c++) {
          b.f[s][c][k] = gj[s][c];
          b.g[s][c][k] = gi[s][c];
        }
      b.r2min[k] = r2min;
    }
    { /* overlap: a site pair inside the cutoff closer than the minimum distance, i.e. (the
       * cutoff being a 0/1 factor) r2min < min(md2, rc2), or < md2 for a molecule cutoff; one
       * min per term in the loop above instead of a compare, select and add */
      const double lim = MODE == P_MOL || md2 < B.rc2 ? md2 : B.rc2;
#pragma omp simd reduction(+ : bad)
      for (int k = 0; k < np; k++) bad += b.w[k] * (b.r2min[k] < lim ? 1.0 : 0.0);
    }
    for (int s = 0; s < 4; s++)
      for (int c = 0; c < 3; c++) {
        double sum = 0.0;
#pragma omp simd reduction(+ : sum)
        for (int k = 0; k < np; k++) sum += b.g[s][c][k];
        fi[s][c] += sum;
      }
    if (!SITEVIR) { /* R (x) F, F the pair's force on i; a loop of its own, because its 9
                           * sums in the term loop spilled registers there */
#pragma omp simd reduction(+ : v0, v1, v2, v3, v4, v5, v6, v7, v8)
      for (int k = 0; k < np; k++) {
        const double Fx = (b.g[0][0][k] + b.g[1][0][k]) + (b.g[2][0][k] + b.g[3][0][k]);
        const double Fy = (b.g[0][1][k] + b.g[1][1][k]) + (b.g[2][1][k] + b.g[3][1][k]);
        const double Fz = (b.g[0][2][k] + b.g[1][2][k]) + (b.g[2][2][k] + b.g[3][2][k]);
        const double Rx = b.R[0][k], Ry = b.R[1][k], Rz = b.R[2][k];
        v0 += Rx * Fx; v1 += Rx * Fy; v2 += Rx * Fz;
        v3 += Ry * Fx; v4 += Ry * Fy; v5 += Ry * Fz;
        v6 += Rz * Fx; v7 += Rz * Fy; v8 += Rz * Fz;
      }
    }
    batch_scatter(0, V, &b, K, fs, NULL);
  }
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) fs[oi + K->perm[s]][c] += fi[s][c];
  const double w[6] = {w0, w1, w2, w3, w4, w5};
  acc_add(acc, elj, ecoul, w, bad); /* w = 0 unless SITEVIR, v = 0 if SITEVIR */
  acc->vir[0] += v0; acc->vir[1] += v1; acc->vir[2] += v2;
  acc->vir[3] += v3; acc->vir[4] += v4; acc->vir[5] += v5;
  acc->vir[6] += v6; acc->vir[7] += v7; acc->vir[8] += v8;
}

/* ------------------------------------------------------------------- Stockmayer kernel */

#if RL_X512
/* The dipole rows on AVX-512 without batch arrays (issue 8): eight list entries at a time are
 * loaded from their 64-byte records (V->pk: centre, 0, mu axis, 0) and transposed with
 * shuffles; those within the cutoff are packed with vcompresspd and appended, in list order,
 * to a pending vector of up to 7 neighbours (a lane rotation and a blend).  Each time eight
 * are pending, their pair terms are formed in registers; the forces and torques on the eight
 * neighbours are transposed back into records and added to the thread's packed buffer (ft).
 * Neighbour k of the row (counting only those within the cutoff) takes lane k mod 8, so the
 * lanes, and the rounding of the row's sums, do not depend on which candidates beyond the
 * cutoff the list holds (a run restarted from a checkpoint rebuilds the list at another step
 * and continues bit for bit). */

/* The row's running sums: force and torque on i, virial, energies, overlaps. */
typedef struct {
  __m512d fx, fy, fz, tx, ty, tz, w0, w1, w2, w3, w4, w5, w6, w7, w8, elj, edip;
  __mmask8 bad;
} dip_sums;

/* The pair terms of i with the eight neighbours in lanes (X, Y, Z: centre_i - centre_j,
 * m: mu_j), of which the first nv are real (the others hold copies of lane 0 and add nothing):
 * lj_eval_ir2 and rl_dipole_dipole_rf / _sf as in dipole_row, on vectors. */
RL_T512 RL_INLINE void dip_pairs8(const int DSF, const int EV, const int TRUNC, const lj_consts C,
                                      const box_consts *B, double kc, double krf,
                                      const __m512d mi[3], __m512d X, __m512d Y, __m512d Z,
                                      __m512d mjx, __m512d mjy, __m512d mjz, const int *idx,
                                      int nv, double (*ft)[8], dip_sums *S)
{
#define V1(a) _mm512_set1_pd(a)
  const __mmask8 live = (__mmask8)((1u << nv) - 1u);
  const __m512d r2 = X * X + Y * Y + Z * Z;
  S->bad |= _mm512_mask_cmp_pd_mask(live, r2, V1(B->md2), _CMP_LT_OQ);
  const __m512d ir = rsqrt8(r2), ir2 = ir * ir, ir3 = ir * ir2, ir5 = ir3 * ir2;
  const __m512d rr = r2 * ir; /* |r|, for the truncations and the shifted-force dipoles */
  __m512d ul, frl;
  lj8(TRUNC, C, B, ir2, rr, ir, &ul, &frl);
  /* rl_dipole_dipole_rf / _sf (dd_plain in dipole.c), regrouped: with K = kc (RF) or kc b(x)
   * (SF), m3 = -3 / r^5, Bj = K m3 pj and Bi = K m3 pi, the force on i is s R - Bj mu_i - Bi mu_j,
   * and the fields are g_i = A mu_j + Bj R, g_j = A mu_i + Bi R with A = K (1 / r^3 - 2 krf)
   * (RF) or K / r^3 (SF): about 20 fewer multiplies and adds per 8 pairs than dipole_row */
  const __m512d pij = mi[0] * mjx + mi[1] * mjy + mi[2] * mjz;
  const __m512d pi = mi[0] * X + mi[1] * Y + mi[2] * Z;
  const __m512d pj = mjx * X + mjy * Y + mjz * Z;
  const __m512d m3 = V1(-3.0) * ir5, e15 = V1(-5.0) * m3 * pi * pj * ir2;
  __m512d Kd, A, s;
  if (DSF) { /* rl_dipole_dipole_sf: b(x) = 1 - 4 x^3 + 3 x^4, x = r / rc */
    const __m512d x = rr * V1(1.0 / B->rc);
    const __m512d bb = V1(1.0) + x * x * x * (V1(-4.0) + V1(3.0) * x);
    const __m512d db = x * x * (V1(-12.0) + V1(12.0) * x) * V1(1.0 / B->rc);
    const __m512d g0 = pij * ir3 + m3 * pi * pj;
    Kd = V1(kc) * bb;
    A = Kd * ir3;
    s = frl - Kd * (m3 * pij + e15) - V1(kc) * g0 * db * ir;
  } else { /* rl_dipole_dipole_rf */
    Kd = V1(kc);
    A = Kd * (ir3 - V1(2.0 * krf));
    s = frl - Kd * (m3 * pij + e15);
  }
  const __m512d Bj = Kd * m3 * pj, Bi = Kd * m3 * pi;
  __m512d fx = s * X - Bj * mi[0] - Bi * mjx;
  __m512d fy = s * Y - Bj * mi[1] - Bi * mjy;
  __m512d fz = s * Z - Bj * mi[2] - Bi * mjz;
  const __m512d gix = A * mjx + Bj * X, giy = A * mjy + Bj * Y, giz = A * mjz + Bj * Z;
  const __m512d gjx = A * mi[0] + Bi * X, gjy = A * mi[1] + Bi * Y, gjz = A * mi[2] + Bi * Z;
  const __m512d ud = pij * A + Bi * pj;
  /* the padding lanes add nothing */
  fx = _mm512_maskz_mov_pd(live, fx); fy = _mm512_maskz_mov_pd(live, fy);
  fz = _mm512_maskz_mov_pd(live, fz);
  /* force on i, and (EV) the energies and the virial R (x) F */
  S->fx += fx; S->fy += fy; S->fz += fz;
  if (EV) {
    S->elj = _mm512_mask_add_pd(S->elj, live, S->elj, ul);
    S->edip = _mm512_mask_add_pd(S->edip, live, S->edip, ud);
    S->w0 += X * fx; S->w1 += X * fy; S->w2 += X * fz;
    S->w3 += Y * fx; S->w4 += Y * fy; S->w5 += Y * fz;
    S->w6 += Z * fx; S->w7 += Z * fy; S->w8 += Z * fz;
  }
  /* torques -mu x g on i and on j */
  S->tx = _mm512_mask_sub_pd(S->tx, live, S->tx, mi[1] * giz - mi[2] * giy);
  S->ty = _mm512_mask_sub_pd(S->ty, live, S->ty, mi[2] * gix - mi[0] * giz);
  S->tz = _mm512_mask_sub_pd(S->tz, live, S->tz, mi[0] * giy - mi[1] * gix);
  const __m512d zero = _mm512_setzero_pd();
  const __m512d in[8] = {zero - fx, zero - fy, zero - fz, zero,
                         mjz * gjy - mjy * gjz, mjx * gjz - mjz * gjx, mjy * gjx - mjx * gjy,
                         zero};
  __m512d r[8]; /* neighbour l: (f 0 | t 0) */
  tr8x8(in, r);
  for (int l = 0; l < nv; l++) {
    double *o = ft[idx[l]];
    _mm512_store_pd(o, _mm512_add_pd(_mm512_load_pd(o), r[l]));
  }
#undef V1
}

RL_T512 RL_INLINE void dipole_row512(const int DSF, const int EV, const int TRUNC,
                                         const rl_forcefield *ff, const kview *V,
                                         const fast_species *K, int i, const int *nbr, int len,
                                         double (*fs)[3], double (*tq)[3], double (*ft)[8],
                                         rl_acc *acc)
{
  const box_consts B = consts_of(ff);
  const lj_consts C = lj_of(&K->t[0]);
  const double kc = ff->kc, krf = ff->rf.krf;
  const double *pi = V->pk[i]; /* i's record: centre, 0, mu axis, 0 */
  const __m512d mi[3] = {_mm512_set1_pd(pi[4]), _mm512_set1_pd(pi[5]), _mm512_set1_pd(pi[6])};
  const sep8_consts S8 = sep8_of(&B, pi);
  const __m512d rc2 = _mm512_set1_pd(B.rc2);
  const __m512i even = S8.even, odd = S8.odd;
  const __m512i iota = _mm512_set_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0);
  const __m512d z0 = _mm512_setzero_pd();
  dip_sums S = {z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, 0};
  /* the pending neighbours, lanes 0 .. pn - 1 */
  __m512d pX = _mm512_setzero_pd(), pY = pX, pZ = pX, pmx = pX, pmy = pX, pmz = pX;
  __m512i pid = _mm512_setzero_si512();
  int pn = 0;
  _Alignas(64) int idx[16];
  for (int p = 0; p < len; p += RL_FAST_W) {
    const int cnt = len - p < RL_FAST_W ? len - p : RL_FAST_W;
    const double *q[8];
    if (cnt == RL_FAST_W)
      for (int l = 0; l < 8; l++) q[l] = V->pk[nbr[p + l]];
    else
      for (int l = 0; l < 8; l++) q[l] = V->pk[nbr[p + (l < cnt ? l : 0)]]; /* the first again */
    __m512d R[3], d[4]; /* d: halves (record q[l] | record q[l + 4]) of the dipole */
    sep8(&S8, q, R);
    for (int l = 0; l < 4; l++)
      d[l] = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_load_pd(q[l] + 4)),
                                _mm256_load_pd(q[l + 4] + 4), 1);
    const __m512d X = R[0], Y = R[1], Z = R[2];
    const __m512d r2 = _mm512_fmadd_pd(Z, Z, _mm512_fmadd_pd(Y, Y, _mm512_mul_pd(X, X)));
    const __mmask8 keep = _mm512_cmp_pd_mask(r2, rc2, _CMP_LT_OQ) & (__mmask8)((1u << cnt) - 1u);
    if (!keep) continue;
    const int kc8 = __builtin_popcount(keep);
    const __m512d dl01 = _mm512_unpacklo_pd(d[0], d[1]), dh01 = _mm512_unpackhi_pd(d[0], d[1]);
    const __m512d dl23 = _mm512_unpacklo_pd(d[2], d[3]), dh23 = _mm512_unpackhi_pd(d[2], d[3]);
    /* the kept ones packed, then rotated up by pn lanes: lanes pn .. 7 continue the pending
     * ones, lanes 0 .. pn + kc8 - 9 are the overflow */
    const __m512i rot = _mm512_and_si512(_mm512_sub_epi32(iota, _mm512_set1_epi32(pn)),
                                         _mm512_set1_epi32(7));
    const __m512i rot64 = _mm512_cvtepi32_epi64(_mm512_castsi512_si256(rot));
#define RL_ROT(V) _mm512_permutexvar_pd(rot64, _mm512_maskz_compress_pd(keep, V))
    const __m512d nX = RL_ROT(X), nY = RL_ROT(Y), nZ = RL_ROT(Z);
    const __m512d nmx = RL_ROT(_mm512_permutex2var_pd(dl01, even, dl23));
    const __m512d nmy = RL_ROT(_mm512_permutex2var_pd(dh01, even, dh23));
    const __m512d nmz = RL_ROT(_mm512_permutex2var_pd(dl01, odd, dl23));
#undef RL_ROT
    const __m512i id = _mm512_maskz_loadu_epi32((__mmask16)((1u << cnt) - 1u), nbr + p);
    const __m512i nid = _mm512_permutexvar_epi32(rot, _mm512_maskz_compress_epi32(keep, id));
    const __mmask8 old = (__mmask8)((1u << pn) - 1u);
    const __m512d aX = _mm512_mask_blend_pd(old, nX, pX), aY = _mm512_mask_blend_pd(old, nY, pY),
                  aZ = _mm512_mask_blend_pd(old, nZ, pZ);
    const __m512d amx = _mm512_mask_blend_pd(old, nmx, pmx),
                  amy = _mm512_mask_blend_pd(old, nmy, pmy),
                  amz = _mm512_mask_blend_pd(old, nmz, pmz);
    const __m512i aid = _mm512_mask_blend_epi32((__mmask16)old, nid, pid);
    if (pn + kc8 < RL_FAST_W) { /* still pending */
      pX = aX; pY = aY; pZ = aZ; pmx = amx; pmy = amy; pmz = amz; pid = aid;
      pn += kc8;
      continue;
    }
    _mm512_store_si512(idx, aid);
    dip_pairs8(DSF, EV, TRUNC, C, &B, kc, krf, mi, aX, aY, aZ, amx, amy, amz, idx, RL_FAST_W, ft, &S);
    pX = nX; pY = nY; pZ = nZ; pmx = nmx; pmy = nmy; pmz = nmz; pid = nid;
    pn += kc8 - RL_FAST_W;
  }
  if (pn) { /* the last ones; the other lanes repeat lane 0 */
    const __mmask8 old = (__mmask8)((1u << pn) - 1u);
    const __m512i z = _mm512_setzero_si512();
#define RL_PAD(V) _mm512_mask_blend_pd(old, _mm512_permutexvar_pd(z, V), V)
    _mm512_store_si512(idx, pid);
    dip_pairs8(DSF, EV, TRUNC, C, &B, kc, krf, mi, RL_PAD(pX), RL_PAD(pY), RL_PAD(pZ), RL_PAD(pmx),
               RL_PAD(pmy), RL_PAD(pmz), idx, pn, ft, &S);
#undef RL_PAD
  }
  /* the force and torque on i go to its record too, so the dipole ranks need no site buffers */
  (void)fs;
  (void)tq;
  ft[i][0] += _mm512_reduce_add_pd(S.fx);
  ft[i][1] += _mm512_reduce_add_pd(S.fy);
  ft[i][2] += _mm512_reduce_add_pd(S.fz);
  ft[i][4] += _mm512_reduce_add_pd(S.tx);
  ft[i][5] += _mm512_reduce_add_pd(S.ty);
  ft[i][6] += _mm512_reduce_add_pd(S.tz);
  acc->lj += _mm512_reduce_add_pd(S.elj);
  acc->dip += _mm512_reduce_add_pd(S.edip);
  const __m512d w[9] = {S.w0, S.w1, S.w2, S.w3, S.w4, S.w5, S.w6, S.w7, S.w8};
  for (int c = 0; c < 9; c++) acc->vir[c] += _mm512_reduce_add_pd(w[c]);
  acc->bad |= S.bad != 0;
}
#endif

#if RL_X512
/* The TIP4P and dipole rows on AVX2 (issue 8; 4 doubles per vector, 16 registers), for CPUs
 * without AVX-512 (AMD Zen 2/3, older Intel): the design of the AVX-512 rows above, four
 * neighbours to a vector.  A fill (fill256) tests four candidates at a time against the
 * pruning radius, their centres transposed from the records (V->pk4 or V->pk, which start
 * with the centre), and appends the kept ones' indices and separations to the batch, in list
 * order, with branch-free scalar stores (AVX2 has no compress).  The batches end where
 * batch_fill's do, and neighbour k of a batch takes lane k mod 4, so the sums do not depend
 * on when the list was built.  The pair loops load each four neighbours' records, transpose
 * them (4 x 4) into sites or dipoles, form the terms in registers, and transpose the forces
 * on the neighbours back into records added to the thread's buffer (ft4, ft).  1 / sqrt is
 * rsqrt4: vrsqrtps on the value rounded to single precision, then two Newton steps (relative
 * error below 2e-14). */

#define RL_T256 __attribute__((target("avx2,fma")))
/* The TIP4P rows on AVX2 are scheduled before register allocation, with an eye on register
 * pressure (GCC's -fschedule-insns -fsched-pressure, off by default on x86): with 16 vector
 * registers the row's 12 site-force sums, its neighbours' 12 site coordinates and 12 site
 * forces do not fit, and GCC's default order spilled about a fifth of its instructions to the
 * stack.  ffbench kernel tip4p 256 1, A/B on an AMD EPYC (Zen 3) guest: 0.76 -> 0.63 ms; the
 * dipole rows, with fewer live values, gained nothing. */
#define RL_SCHED __attribute__((optimize("schedule-insns", "sched-pressure")))

/* in[r][c] -> out[c][r], four rows of four doubles */
RL_T256 static inline void tr4x4(const __m256d in[4], __m256d out[4])
{
  const __m256d t0 = _mm256_unpacklo_pd(in[0], in[1]), t1 = _mm256_unpackhi_pd(in[0], in[1]);
  const __m256d t2 = _mm256_unpacklo_pd(in[2], in[3]), t3 = _mm256_unpackhi_pd(in[2], in[3]);
  out[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
  out[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
  out[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
  out[3] = _mm256_permute2f128_pd(t1, t3, 0x31);
}

/* 1 / sqrt(x) on 4 lanes for 2^-126 < x < 2^127 (single-precision range): vrsqrtps (relative
 * error < 1.5 2^-12 = 3.7e-4) and two Newton steps (error ~ 1.5 e^2 each: 2e-7, then 6e-14;
 * measured: at most 1.5e-14, 46 bits, over x in [e^-20, e^20]).  That is the accuracy GROMACS
 * aims at in its double-precision SIMD math (GMX_SIMD_ACCURACY_BITS_DOUBLE = 44, two steps from
 * an 11-bit start on AVX2), far below what changes a trajectory's statistics; a third step
 * (full double precision, as rl_rsqrt and rsqrt8) cost 10 % of a TIP4P row. */
RL_T256 static inline __m256d rsqrt4(__m256d x)
{
  const __m256d half = _mm256_set1_pd(0.5), h = _mm256_mul_pd(half, x);
  __m256d y = _mm256_cvtps_pd(_mm_rsqrt_ps(_mm256_cvtpd_ps(x)));
#pragma GCC unroll 2
  for (int k = 0; k < 2; k++)
    y = _mm256_fmadd_pd(y, _mm256_fnmadd_pd(_mm256_mul_pd(h, y), y, half), y);
  return y;
}

RL_T256 static inline double hsum4(__m256d v)
{
  const __m128d s = _mm_add_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
  return _mm_cvtsd_f64(_mm_add_sd(s, _mm_unpackhi_pd(s, s)));
}

/* lj_eval_ir2 on 4 lanes (RL_LJ_VEC) */
#define RL_SEL4(rr, a, b)                                                                      \
  _mm256_and_pd(_mm256_cmp_pd(rr, _mm256_set1_pd(B->rc), _CMP_LT_OQ),                         \
                _mm256_blendv_pd(a, b, _mm256_cmp_pd(rr, _mm256_set1_pd(B->rsw), _CMP_GT_OQ)))
RL_T256 RL_INLINE void lj4(const int TRUNC, const lj_consts C, const box_consts *B, __m256d ir2,
                           __m256d rr, __m256d ir, __m256d *u, __m256d *fr)
{
  RL_LJ_VEC(__m256d, _mm256_set1_pd, RL_SEL4);
}
#undef RL_SEL4

/* The lanes below cnt (1..4) as a mask vector. */
RL_T256 static inline __m256d live4(int cnt)
{
  const __m256d iota = _mm256_set_pd(3.0, 2.0, 1.0, 0.0);
  return _mm256_cmp_pd(iota, _mm256_set1_pd((double)cnt), _CMP_LT_OQ);
}

/* For each 4-bit mask of kept lanes, the permutation that packs them to the front in lane
 * order: d, as eight 32-bit indices (pairs, for doubles); i, as four (for ints). */
typedef struct {
  _Alignas(32) int d[8];
  _Alignas(16) int i[4];
} pack4;
static const pack4 pack4_lut[16] = {
#define RL_P1(k) 2 * (k), 2 * (k) + 1
#define RL_PACK(a, b, c, e) {{RL_P1(a), RL_P1(b), RL_P1(c), RL_P1(e)}, {a, b, c, e}}
    RL_PACK(0, 0, 0, 0), RL_PACK(0, 0, 0, 0), RL_PACK(1, 0, 0, 0), RL_PACK(0, 1, 0, 0),
    RL_PACK(2, 0, 0, 0), RL_PACK(0, 2, 0, 0), RL_PACK(1, 2, 0, 0), RL_PACK(0, 1, 2, 0),
    RL_PACK(3, 0, 0, 0), RL_PACK(0, 3, 0, 0), RL_PACK(1, 3, 0, 0), RL_PACK(0, 1, 3, 0),
    RL_PACK(2, 3, 0, 0), RL_PACK(0, 2, 3, 0), RL_PACK(1, 2, 3, 0), RL_PACK(0, 1, 2, 3),
#undef RL_PACK
#undef RL_P1
};

/* Append the candidates nbr[p .. p + cnt) whose lanes are set in `keep`, with separations R
 * (lane l: candidate p + l), to the batch from slot *n, in lane order: packed by pack4_lut while
 * the batch has room for all four, else one by one while it has room.  Returns how many
 * candidates it took (all cnt, or fewer when the batch filled). */
RL_T256 RL_INLINE int append4(batch *b, int *n, const int *nbr, int p, int cnt, unsigned keep,
                              const __m256d R[3])
{
  if (cnt == 4 && *n + 4 <= RL_FAST_B) {
    const __m256i pd = _mm256_load_si256((const __m256i *)pack4_lut[keep].d);
    const __m128i pi = _mm_load_si128((const __m128i *)pack4_lut[keep].i);
    for (int d = 0; d < 3; d++)
      _mm256_storeu_pd(b->R[d] + *n, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(R[d]), pd)));
    const __m128 id = _mm_castsi128_ps(_mm_loadu_si128((const __m128i *)(nbr + p)));
    _mm_storeu_si128((__m128i *)(b->idx + *n), _mm_castps_si128(_mm_permutevar_ps(id, pi)));
    *n += __builtin_popcount(keep);
    return 4;
  }
  _Alignas(32) double x[3][4]; /* [component][lane] */
  for (int d = 0; d < 3; d++) _mm256_store_pd(x[d], R[d]);
  int l;
  for (l = 0; l < cnt && *n < RL_FAST_B; l++) { /* slot n is kept only if lane l is */
    b->idx[*n] = nbr[p + l];
    b->R[0][*n] = x[0][l]; b->R[1][*n] = x[1][l]; b->R[2][*n] = x[2][l];
    *n += (keep >> l) & 1u;
  }
  return l;
}

/* Close a batch of n neighbours: pad it to a multiple of RL_FAST_W with the first neighbour's
 * record at twice the pruning radius, so that every site pair lies beyond the cutoff
 * (|r| >= 2 rp - 2 extent > rc) and none is the closest pair. */
RL_INLINE void pad_batch(batch *b, int n, double rp2)
{
  const int np = (n + RL_FAST_W - 1) / RL_FAST_W * RL_FAST_W;
  const double pad = 2.0 * sqrt(rp2);
  for (int k = n; k < np; k++) {
    b->idx[k] = b->idx[0];
    b->R[0][k] = pad;
    b->R[1][k] = b->R[2][k] = 0.0;
  }
  b->n = n;
  b->np = np;
}

/* batch_fill's neighbours (indices and centre separations only) for rows whose records
 * rec + stride j (stride 8 or 16 doubles, 32-byte aligned) start with the centre, four
 * candidates at a time: the minimum image as take_candidate's RL_RND, the pruning test in one
 * vector, the kept ones appended in list order (packed by pack4_lut while the batch has room
 * for all four: ffbench kernel stockmayer 8000 1, A/B on an AMD EPYC guest, -6 %; TIP4P, where
 * the pairs dominate, unchanged).  In a box that needs the other images (img), the images of
 * the four candidates within rp are tested in vectors too, and only four of which one keeps
 * another image are appended one by one, each neighbour's images right after it, as
 * take_candidate does.  A batch ends where batch_fill's does: when full, or before a neighbour
 * whose images would not all fit. */
RL_T256 RL_INLINE void fill256(const double *rec, int stride, const box_consts *B,
                                   const double *ci, const int *nbr, int len, int *pos,
                                   double rp2, int img, batch *b)
{
  const __m256d c[3] = {_mm256_set1_pd(ci[0]), _mm256_set1_pd(ci[1]), _mm256_set1_pd(ci[2])};
  const __m256d L[3] = {_mm256_set1_pd(B->L[0]), _mm256_set1_pd(B->L[1]),
                        _mm256_set1_pd(B->L[2])};
  const __m256d iL[3] = {_mm256_set1_pd(B->iL[0]), _mm256_set1_pd(B->iL[1]),
                         _mm256_set1_pd(B->iL[2])};
  const __m256d big = _mm256_set1_pd(6755399441055744.0), vrp2 = _mm256_set1_pd(rp2);
  const double rp = img ? sqrt(rp2) : 0.0;
  const __m256d sign = _mm256_set1_pd(-0.0);
  const __m256d near[3] = {_mm256_set1_pd(B->L[0] - rp), _mm256_set1_pd(B->L[1] - rp),
                           _mm256_set1_pd(B->L[2] - rp)};
  int n = 0, p = *pos;
  while (p < len && n < RL_FAST_B) {
    const int cnt = len - p < 4 ? len - p : 4;
    const unsigned live = (1u << cnt) - 1u;
    __m256d q[4], t[4];
    for (int l = 0; l < 4; l++) q[l] = _mm256_load_pd(rec + (size_t)stride * nbr[p + (l < cnt ? l : 0)]);
    tr4x4(q, t);
    __m256d R[3];
    for (int d = 0; d < 3; d++) {
      const __m256d X = _mm256_sub_pd(c[d], t[d]);
      const __m256d k = _mm256_sub_pd(_mm256_fmadd_pd(X, iL[d], big), big);
      R[d] = _mm256_fnmadd_pd(L[d], k, X);
    }
    const __m256d r2 = _mm256_fmadd_pd(R[2], R[2], _mm256_fmadd_pd(R[1], R[1], _mm256_mul_pd(R[0], R[0])));
    const unsigned keep = (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(r2, vrp2, _CMP_LT_OQ)) & live;
    if (img) { /* the other images within rp (other_images), as in tip4p_fill512 */
      unsigned fc[3];
      for (int d = 0; d < 3; d++)
        fc[d] = (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(_mm256_andnot_pd(sign, R[d]), near[d], _CMP_GT_OQ)) & live;
      __m256d X1[3]; /* R shifted by one box edge towards zero (only where some lane is far) */
      unsigned kept[4] = {0, 0, 0, 0}, extra = 0; /* lane l: bit m if image m is kept */
      if (fc[0] | fc[1] | fc[2]) {
        for (int d = 0; d < 3; d++) {
          const __m256d pos = _mm256_cmp_pd(R[d], _mm256_setzero_pd(), _CMP_GT_OQ);
          X1[d] = _mm256_blendv_pd(_mm256_add_pd(R[d], L[d]), _mm256_sub_pd(R[d], L[d]), pos);
        }
        for (int m = 1; m < 8; m++) { /* image m: component d shifted if bit d of m is set */
          const unsigned far = (m & 1 ? fc[0] : live) & (m & 2 ? fc[1] : live) & (m & 4 ? fc[2] : live);
          if (!far) continue;
          const __m256d u = m & 1 ? X1[0] : R[0], v = m & 2 ? X1[1] : R[1], w = m & 4 ? X1[2] : R[2];
          const __m256d q2 = _mm256_fmadd_pd(w, w, _mm256_fmadd_pd(v, v, _mm256_mul_pd(u, u)));
          unsigned km = (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(q2, vrp2, _CMP_LT_OQ)) & far;
          extra |= km;
          for (; km; km &= km - 1) kept[__builtin_ctz(km)] |= 1u << m;
        }
      }
      if (extra) { /* some lane keeps another image besides (or instead of) the minimum one */
        for (int l = 0; l < 4; l++) kept[l] |= (keep >> l) & 1u;
        _Alignas(32) double x[2][3][4]; /* [shifted][component][lane] */
        for (int d = 0; d < 3; d++) {
          _mm256_store_pd(x[0][d], R[d]);
          _mm256_store_pd(x[1][d], X1[d]);
        }
        int l, full = 0;
        for (l = 0; l < cnt && n < RL_FAST_B; l++) {
          if (n + __builtin_popcount(kept[l]) > RL_FAST_B) { /* the next batch takes it */
            full = 1;
            break;
          }
          for (unsigned bits = kept[l]; bits; bits &= bits - 1) {
            const int m = __builtin_ctz(bits);
            b->idx[n] = nbr[p + l];
            b->R[0][n] = x[m & 1][0][l];
            b->R[1][n] = x[(m >> 1) & 1][1][l];
            b->R[2][n] = x[m >> 2][2][l];
            n++;
          }
        }
        p += l;
        if (full) break;
        continue;
      }
    }
    p += append4(b, &n, nbr, p, cnt, keep, R);
  }
  *pos = p;
  pad_batch(b, n, rp2);
}

/* fill256 for a row of the image list (kview.xstart, build_images): entry q is neighbour
 * nbr[q] at c_i - c_j + s_q, so there is no minimum image to take and no other image to look
 * for; the kept entries are appended in list order (append4, as fill256). */
RL_T256 RL_INLINE void fill256x(const double *rec, int stride, const double *ci, const int *nbr,
                                const double *const sh[3], int len, int *pos, double rp2, batch *b)
{
  const __m256d c[3] = {_mm256_set1_pd(ci[0]), _mm256_set1_pd(ci[1]), _mm256_set1_pd(ci[2])};
  const __m256d vrp2 = _mm256_set1_pd(rp2);
  int n = 0, p = *pos;
  while (p < len && n < RL_FAST_B) {
    const int cnt = len - p < 4 ? len - p : 4;
    const unsigned live = (1u << cnt) - 1u;
    __m256d q[4], t[4], R[3];
    for (int l = 0; l < 4; l++) q[l] = _mm256_load_pd(rec + (size_t)stride * nbr[p + (l < cnt ? l : 0)]);
    tr4x4(q, t);
    for (int d = 0; d < 3; d++) /* the shifts have 4 slots of slack past the last row */
      R[d] = _mm256_add_pd(_mm256_sub_pd(c[d], t[d]), _mm256_loadu_pd(sh[d] + p));
    const __m256d r2 = _mm256_fmadd_pd(R[2], R[2], _mm256_fmadd_pd(R[1], R[1], _mm256_mul_pd(R[0], R[0])));
    const unsigned keep = (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(r2, vrp2, _CMP_LT_OQ)) & live;
    p += append4(b, &n, nbr, p, cnt, keep, R);
  }
  *pos = p;
  pad_batch(b, n, rp2);
}

/* The sums of a TIP4P row on AVX2, lane by lane, as tip_sums. */
typedef struct {
  __m256d fi[4][3], w[9], elj, ecoul, r2min;
} tip_sums4;

/* tip4p_pairs512 on four lanes. */
RL_T256 RL_INLINE void tip4p_pairs256(const int MODE, const int EV, const int TRUNC,
                                      const lj_consts C, const box_consts *B,
                                      const double a[4][3], const double qq[3][3],
                                      const kview *V, const batch *b, double (*ft4)[16],
                                      tip_sums4 *S)
{
#define V1(x) _mm256_set1_pd(x)
  const __m256d zero = _mm256_setzero_pd(), rc2 = V1(B->rc2);
  const __m256d krf = V1(B->krf), krf2 = V1(2.0 * B->krf), crf = V1(B->crf);
  for (int k = 0; k < b->n; k += 4) {
    const int cnt = b->n - k < 4 ? b->n - k : 4;
    const __m256d live = live4(cnt); /* P_MOL: the padding (P_SHIFT: beyond the cutoff) */
    const __m256d R[3] = {_mm256_load_pd(b->R[0] + k), _mm256_load_pd(b->R[1] + k),
                          _mm256_load_pd(b->R[2] + k)};
    __m256d Q[4][4]; /* Q[u][e]: element 4 u + e of the four records */
#pragma GCC unroll 4
    for (int u = 0; u < 4; u++) {
      __m256d r[4];
#pragma GCC unroll 4
      for (int l = 0; l < 4; l++) r[l] = _mm256_load_pd(V->pk4[b->idx[k + l]] + 4 * u);
      tr4x4(r, Q[u]);
    }
    __m256d xj[4][3], gj[4][3];
#pragma GCC unroll 4
    for (int s = 0; s < 4; s++)
#pragma GCC unroll 3
      for (int c = 0; c < 3; c++) {
        const int e = 3 + 3 * s + c;
        xj[s][c] = Q[e / 4][e % 4];
      }
    { /* LJ between the LJ sites (slot 0): lj_eval */
      __m256d d[3];
#pragma GCC unroll 3
      for (int c = 0; c < 3; c++) d[c] = R[c] + V1(a[0][c]) - xj[0][c];
      const __m256d r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      const __m256d in = MODE == P_MOL ? live : _mm256_cmp_pd(r2, rc2, _CMP_LT_OQ);
      S->r2min = _mm256_min_pd(S->r2min, r2);
      const __m256d ir2 = V1(1.0) / r2;
      __m256d rr = zero, ir = zero;
      if (TRUNC == RL_LJ_SHIFTED_FORCE || TRUNC == RL_LJ_SWITCHED) {
        rr = _mm256_sqrt_pd(r2);
        ir = V1(1.0) / rr;
      }
      __m256d u, fr;
      lj4(TRUNC, C, B, ir2, rr, ir, &u, &fr);
      fr = _mm256_and_pd(in, fr);
      if (EV) S->elj = S->elj + _mm256_and_pd(in, u);
#pragma GCC unroll 3
      for (int c = 0; c < 3; c++) {
        S->fi[0][c] = _mm256_fmadd_pd(fr, d[c], S->fi[0][c]);
        gj[0][c] = _mm256_fnmadd_pd(fr, d[c], zero);
      }
    }
#pragma GCC unroll 3
    for (int q = 0; q < 3; q++)
#pragma GCC unroll 3
      for (int c = 0; c < 3; c++) gj[1 + q][c] = zero;
#pragma GCC unroll 3
    for (int p = 0; p < 3; p++) { /* charge p of i against charge q of j: rl_coulomb_rf_pair */
      __m256d ra[3];
#pragma GCC unroll 3
      for (int c = 0; c < 3; c++) ra[c] = R[c] + V1(a[1 + p][c]);
#pragma GCC unroll 3
      for (int q = 0; q < 3; q++) {
        __m256d d[3];
#pragma GCC unroll 3
        for (int c = 0; c < 3; c++) d[c] = ra[c] - xj[1 + q][c];
        const __m256d r2 =
            _mm256_fmadd_pd(d[2], d[2], _mm256_fmadd_pd(d[1], d[1], _mm256_mul_pd(d[0], d[0])));
        const __m256d in = MODE == P_MOL ? live : _mm256_cmp_pd(r2, rc2, _CMP_LT_OQ);
        S->r2min = _mm256_min_pd(S->r2min, r2);
        const __m256d ir = rsqrt4(r2);
        const __m256d qv = _mm256_and_pd(in, V1(qq[p][q]));
        const __m256d fr = qv * (ir * ir * ir - krf2);
        if (EV) /* qq (1/r + krf r^2 - crf) */
          S->ecoul = _mm256_fmadd_pd(qv, _mm256_fmadd_pd(krf, r2, ir) - crf, S->ecoul);
#pragma GCC unroll 3
        for (int c = 0; c < 3; c++) {
          S->fi[1 + p][c] = _mm256_fmadd_pd(fr, d[c], S->fi[1 + p][c]);
          gj[1 + q][c] = _mm256_fnmadd_pd(fr, d[c], gj[1 + q][c]);
        }
      }
    }
    if (EV) /* R (x) F, F = -(sum of the forces on j's sites) the pair's force on i */
#pragma GCC unroll 3
      for (int c = 0; c < 3; c++) {
        const __m256d F = zero - ((gj[0][c] + gj[1][c]) + (gj[2][c] + gj[3][c]));
#pragma GCC unroll 3
        for (int r = 0; r < 3; r++) S->w[3 * r + c] = S->w[3 * r + c] + R[r] * F;
      }
    /* the forces on the neighbours' sites, as records (centre 0, sites, 0), added in order */
    const __m256d e[4][4] = {{zero, zero, zero, gj[0][0]},
                             {gj[0][1], gj[0][2], gj[1][0], gj[1][1]},
                             {gj[1][2], gj[2][0], gj[2][1], gj[2][2]},
                             {gj[3][0], gj[3][1], gj[3][2], zero}};
    __m256d o[4][4]; /* o[u][l]: quarter u of neighbour l's record */
#pragma GCC unroll 4
    for (int u = 0; u < 4; u++) tr4x4(e[u], o[u]);
    for (int l = 0; l < cnt; l++) {
      double *r = ft4[b->idx[k + l]];
#pragma GCC unroll 4
      for (int u = 0; u < 4; u++)
        _mm256_store_pd(r + 4 * u, _mm256_add_pd(_mm256_load_pd(r + 4 * u), o[u][l]));
    }
  }
#undef V1
}


/* ---------------------------------------------------------------- mixed precision (AVX2) */

/* in[r][c] -> out[c][r], eight rows of eight floats: 24 shuffles */
RL_T256 static inline void tr8x8f(const __m256 in[8], __m256 out[8])
{
  __m256 t[8], u[8];
  for (int h = 0; h < 2; h++) {
    const __m256 *r = in + 4 * h;
    __m256 *v = t + 4 * h, *w = u + 4 * h;
    v[0] = _mm256_unpacklo_ps(r[0], r[1]); v[1] = _mm256_unpackhi_ps(r[0], r[1]);
    v[2] = _mm256_unpacklo_ps(r[2], r[3]); v[3] = _mm256_unpackhi_ps(r[2], r[3]);
    w[0] = _mm256_shuffle_ps(v[0], v[2], _MM_SHUFFLE(1, 0, 1, 0)); /* columns 0 | 4 */
    w[1] = _mm256_shuffle_ps(v[0], v[2], _MM_SHUFFLE(3, 2, 3, 2)); /* 1 | 5 */
    w[2] = _mm256_shuffle_ps(v[1], v[3], _MM_SHUFFLE(1, 0, 1, 0)); /* 2 | 6 */
    w[3] = _mm256_shuffle_ps(v[1], v[3], _MM_SHUFFLE(3, 2, 3, 2)); /* 3 | 7 */
  }
  for (int c = 0; c < 4; c++) {
    out[c] = _mm256_permute2f128_ps(u[c], u[4 + c], 0x20);
    out[4 + c] = _mm256_permute2f128_ps(u[c], u[4 + c], 0x31);
  }
}

/* in[r][c] -> out[c][r], eight rows of four floats */
RL_T256 static inline void tr8x4f(const __m128 in[8], __m256 out[4])
{
  __m256 v[4];
  for (int l = 0; l < 4; l++) v[l] = _mm256_insertf128_ps(_mm256_castps128_ps256(in[l]), in[4 + l], 1);
  const __m256 t0 = _mm256_unpacklo_ps(v[0], v[1]), t1 = _mm256_unpackhi_ps(v[0], v[1]);
  const __m256 t2 = _mm256_unpacklo_ps(v[2], v[3]), t3 = _mm256_unpackhi_ps(v[2], v[3]);
  out[0] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
  out[1] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
  out[2] = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
  out[3] = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2));
}

/* 1 / sqrt(x), single precision: vrsqrtps (relative error < 3.7e-4) and one Newton step */
RL_T256 static inline __m256 rsqrt8f(__m256 x)
{
  const __m256 y = _mm256_rsqrt_ps(x), h = _mm256_mul_ps(_mm256_set1_ps(0.5f), x);
  return _mm256_mul_ps(y, _mm256_fnmadd_ps(_mm256_mul_ps(h, y), y, _mm256_set1_ps(1.5f)));
}

/* eight doubles at p as floats */
RL_T256 static inline __m256 load8d(const double *p)
{
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm256_cvtpd_ps(_mm256_load_pd(p))),
                              _mm256_cvtpd_ps(_mm256_load_pd(p + 4)), 1);
}

/* s += the eight floats of v, as four doubles */
RL_T256 static inline __m256d acc8f(__m256d s, __m256 v)
{
  return _mm256_add_pd(s, _mm256_add_pd(_mm256_cvtps_pd(_mm256_castps256_ps128(v)),
                                        _mm256_cvtps_pd(_mm256_extractf128_ps(v, 1))));
}

#define RL_SEL8F(rr, a, b)                                                                     \
  _mm256_and_ps(_mm256_cmp_ps(rr, _mm256_set1_ps((float)B->rc), _CMP_LT_OQ),                  \
                _mm256_blendv_ps(a, b, _mm256_cmp_ps(rr, _mm256_set1_ps((float)B->rsw), _CMP_GT_OQ)))
#define RL_V1F(x) _mm256_set1_ps((float)(x))
RL_T256 RL_INLINE void lj8f(const int TRUNC, const lj_consts C, const box_consts *B, __m256 ir2,
                            __m256 rr, __m256 ir, __m256 *u, __m256 *fr)
{
  RL_LJ_VEC(__m256, RL_V1F, RL_SEL8F);
}
#undef RL_SEL8F

/* tip4p_pairs256 in single precision, eight lanes: the neighbours' sites from their float
 * records (V->pk4f), the centres' separations rounded to float, the terms in float; the forces
 * on the neighbours' sites go back to their double records, the forces on i's sites, the
 * energies and the virial are summed in double per batch. */
RL_T256 RL_INLINE void tip4p_pairs8f(const int MODE, const int EV, const int TRUNC,
                                     const lj_consts C, const box_consts *B,
                                     const double a[4][3], const double qq[3][3],
                                     const kview *V, const batch *b, double (*ft4)[16],
                                     tip_sums4 *S)
{
#define V1 RL_V1F
  const __m256 zero = _mm256_setzero_ps(), rc2 = V1(B->rc2);
  const __m256 krf = V1(B->krf), krf2 = V1(2.0 * B->krf), crf = V1(B->crf);
  const __m256 iota = _mm256_set_ps(7.f, 6.f, 5.f, 4.f, 3.f, 2.f, 1.f, 0.f);
  __m256 fi[4][3], r2min = V1(HUGE_VALF);
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) fi[s][c] = zero;
  for (int k = 0; k < b->n; k += 8) {
    const int cnt = b->n - k < 8 ? b->n - k : 8;
    const __m256 live = _mm256_cmp_ps(iota, V1(cnt), _CMP_LT_OQ);
    const __m256 R[3] = {load8d(b->R[0] + k), load8d(b->R[1] + k), load8d(b->R[2] + k)};
    __m256 xj[12];
    {
      __m256 lo[8];
      __m128 hi[8];
#pragma GCC unroll 8
      for (int l = 0; l < 8; l++) {
        const float *q = V->pk4f[b->idx[k + l]];
        lo[l] = _mm256_load_ps(q);
        hi[l] = _mm_load_ps(q + 8);
      }
      tr8x8f(lo, xj);
      tr8x4f(hi, xj + 8);
    }
    __m256 gj[4][3];
    { /* LJ between the LJ sites (slot 0) */
      __m256 d[3];
#pragma GCC unroll 3
      for (int c = 0; c < 3; c++) d[c] = R[c] + V1(a[0][c]) - xj[c];
      const __m256 r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      const __m256 in = MODE == P_MOL ? live : _mm256_cmp_ps(r2, rc2, _CMP_LT_OQ);
      r2min = _mm256_min_ps(r2min, r2);
      const __m256 ir2 = V1(1.0) / r2;
      __m256 rr = zero, ir = zero;
      if (TRUNC == RL_LJ_SHIFTED_FORCE || TRUNC == RL_LJ_SWITCHED) {
        ir = rsqrt8f(r2);
        rr = r2 * ir;
      }
      __m256 u, fr;
      lj8f(TRUNC, C, B, ir2, rr, ir, &u, &fr);
      fr = _mm256_and_ps(in, fr);
      if (EV) S->elj = acc8f(S->elj, _mm256_and_ps(in, u));
#pragma GCC unroll 3
      for (int c = 0; c < 3; c++) {
        fi[0][c] = _mm256_fmadd_ps(fr, d[c], fi[0][c]);
        gj[0][c] = _mm256_fnmadd_ps(fr, d[c], zero);
      }
    }
#pragma GCC unroll 3
    for (int q = 0; q < 3; q++)
#pragma GCC unroll 3
      for (int c = 0; c < 3; c++) gj[1 + q][c] = zero;
    __m256 ec = zero;
#pragma GCC unroll 3
    for (int p = 0; p < 3; p++) {
      __m256 ra[3];
#pragma GCC unroll 3
      for (int c = 0; c < 3; c++) ra[c] = R[c] + V1(a[1 + p][c]);
#pragma GCC unroll 3
      for (int q = 0; q < 3; q++) {
        __m256 d[3];
#pragma GCC unroll 3
        for (int c = 0; c < 3; c++) d[c] = ra[c] - xj[3 * (1 + q) + c];
        const __m256 r2 =
            _mm256_fmadd_ps(d[2], d[2], _mm256_fmadd_ps(d[1], d[1], _mm256_mul_ps(d[0], d[0])));
        const __m256 in = MODE == P_MOL ? live : _mm256_cmp_ps(r2, rc2, _CMP_LT_OQ);
        r2min = _mm256_min_ps(r2min, r2);
        const __m256 ir = rsqrt8f(r2);
        const __m256 qv = _mm256_and_ps(in, V1(qq[p][q]));
        const __m256 fr = qv * (ir * ir * ir - krf2);
        if (EV) ec = _mm256_fmadd_ps(qv, _mm256_fmadd_ps(krf, r2, ir) - crf, ec);
#pragma GCC unroll 3
        for (int c = 0; c < 3; c++) {
          fi[1 + p][c] = _mm256_fmadd_ps(fr, d[c], fi[1 + p][c]);
          gj[1 + q][c] = _mm256_fnmadd_ps(fr, d[c], gj[1 + q][c]);
        }
      }
    }
    if (EV) {
      S->ecoul = acc8f(S->ecoul, ec);
      /* R (x) F in double: R from the batch, F the pair's force on i */
#pragma GCC unroll 3
      for (int c = 0; c < 3; c++) {
        const __m256 F = zero - ((gj[0][c] + gj[1][c]) + (gj[2][c] + gj[3][c]));
        const __m256d F0 = _mm256_cvtps_pd(_mm256_castps256_ps128(F));
        const __m256d F1 = _mm256_cvtps_pd(_mm256_extractf128_ps(F, 1));
#pragma GCC unroll 3
        for (int r = 0; r < 3; r++)
          S->w[3 * r + c] = S->w[3 * r + c] + _mm256_load_pd(b->R[r] + k) * F0 +
                            _mm256_load_pd(b->R[r] + k + 4) * F1;
      }
    }
    /* the forces on the neighbours' sites, as records (centre 0, sites, 0), added in order */
    const __m256 e[16] = {zero,     zero,     zero,     gj[0][0], gj[0][1], gj[0][2],
                          gj[1][0], gj[1][1], gj[1][2], gj[2][0], gj[2][1], gj[2][2],
                          gj[3][0], gj[3][1], gj[3][2], zero};
    __m256 o[2][8]; /* o[h][l]: half h of neighbour l's record */
    tr8x8f(e, o[0]);
    tr8x8f(e + 8, o[1]);
    for (int l = 0; l < cnt; l++) {
      double *r = ft4[b->idx[k + l]];
#pragma GCC unroll 2
      for (int h = 0; h < 2; h++) {
        const __m256d u0 = _mm256_cvtps_pd(_mm256_castps256_ps128(o[h][l]));
        const __m256d u1 = _mm256_cvtps_pd(_mm256_extractf128_ps(o[h][l], 1));
        _mm256_store_pd(r + 8 * h, _mm256_add_pd(_mm256_load_pd(r + 8 * h), u0));
        _mm256_store_pd(r + 8 * h + 4, _mm256_add_pd(_mm256_load_pd(r + 8 * h + 4), u1));
      }
    }
  }
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) S->fi[s][c] = acc8f(S->fi[s][c], fi[s][c]);
  S->r2min = _mm256_min_pd(S->r2min, _mm256_cvtps_pd(_mm_min_ps(_mm256_castps256_ps128(r2min),
                                                                _mm256_extractf128_ps(r2min, 1))));
#undef V1
}
#undef RL_V1F

/* tip4p_row512 on AVX2; MIXED: the pairs in single precision (tip4p_pairs8f).  In a box that
 * needs the other images, the row's neighbours come from the image list (build_images), so the
 * fill needs no minimum image and no search for images (fill256x). */
RL_T256 RL_INLINE void tip4p_row256(const int MIXED, const int EV, const int MODE, const int TRUNC,
                                    const rl_forcefield *ff, const kview *V, const fast_species *K,
                                    int i, const int *nbr, int len, double (*fs)[3],
                                    double (*ft4)[16], rl_acc *acc)
{
  tip_row T;
  tip_row_of(MODE, ff, V, K, i, &T);
  const __m256d z = _mm256_setzero_pd();
  tip_sums4 S;
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) S.fi[s][c] = z;
  for (int c = 0; c < 9; c++) S.w[c] = z;
  S.elj = S.ecoul = z;
  S.r2min = _mm256_set1_pd(HUGE_VAL);
  batch b;
  const double *sh[3] = {NULL, NULL, NULL};
  const int xl = MODE == P_SHIFT && T.img && V->xstart; /* the image list (build_images) */
  if (xl) {
    const int q0 = V->xstart[i];
    nbr = V->xnbr + q0;
    len = V->xstart[i + 1] - q0;
    for (int c = 0; c < 3; c++) sh[c] = V->xs[c] + q0;
  }
  for (int pos = 0; pos < len;) {
    if (xl) fill256x(V->pk4[0], 16, V->pk4[i], nbr, sh, len, &pos, T.rp2, &b);
    else fill256(V->pk4[0], 16, &T.B, V->pk4[i], nbr, len, &pos, T.rp2, T.img, &b);
    if (b.n && MIXED) tip4p_pairs8f(MODE, EV, TRUNC, T.C, &T.B, T.a, T.qq, V, &b, ft4, &S);
    else if (b.n) tip4p_pairs256(MODE, EV, TRUNC, T.C, &T.B, T.a, T.qq, V, &b, ft4, &S);
  }
  const int oi = V->soff[i];
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) fs[oi + K->perm[s]][c] += hsum4(S.fi[s][c]);
  if (EV) {
    acc->lj += hsum4(S.elj);
    acc->coul += hsum4(S.ecoul);
    for (int c = 0; c < 9; c++) acc->vir[c] += hsum4(S.w[c]);
  }
  /* overlap: a site pair inside the cutoff closer than the minimum distance, as tip4p_row */
  acc->bad |= _mm256_movemask_pd(_mm256_cmp_pd(S.r2min, _mm256_set1_pd(T.lim), _CMP_LT_OQ)) != 0;
}

/* dipole_row512 on AVX2: the neighbours within the cutoff from fill256 (records V->pk:
 * centre, 0, mu axis, 0), four at a time; the terms as dip_pairs8. */
RL_T256 RL_INLINE void dipole_row256(const int DSF, const int EV, const int TRUNC,
                                     const rl_forcefield *ff, const kview *V,
                                     const fast_species *K, int i, const int *nbr, int len,
                                     double (*ft)[8], rl_acc *acc)
{
#define V1(a) _mm256_set1_pd(a)
  const box_consts B = consts_of(ff);
  const lj_consts C = lj_of(&K->t[0]);
  const double kc = ff->kc, krf = ff->rf.krf;
  const double *pr = V->pk[i];
  const __m256d mi[3] = {V1(pr[4]), V1(pr[5]), V1(pr[6])};
  const __m256d zero = _mm256_setzero_pd(), md2 = V1(B.md2);
  __m256d Sf[3] = {zero, zero, zero}, St[3] = {zero, zero, zero}, Sw[9], elj = zero, edip = zero;
  for (int c = 0; c < 9; c++) Sw[c] = zero;
  int bad = 0;
  batch b;
  for (int pos = 0; pos < len;) {
    fill256(V->pk[0], 8, &B, pr, nbr, len, &pos, B.rc2, 0, &b);
    for (int k = 0; k < b.n; k += 4) {
      const int cnt = b.n - k < 4 ? b.n - k : 4;
      const __m256d live = live4(cnt);
      const __m256d X = _mm256_load_pd(b.R[0] + k), Y = _mm256_load_pd(b.R[1] + k),
                    Z = _mm256_load_pd(b.R[2] + k);
      __m256d q[4], m[4];
      for (int l = 0; l < 4; l++) q[l] = _mm256_load_pd(V->pk[b.idx[k + l]] + 4);
      tr4x4(q, m);
      const __m256d mjx = m[0], mjy = m[1], mjz = m[2];
      const __m256d r2 = X * X + Y * Y + Z * Z;
      bad |= _mm256_movemask_pd(_mm256_and_pd(live, _mm256_cmp_pd(r2, md2, _CMP_LT_OQ)));
      const __m256d ir = rsqrt4(r2), ir2 = ir * ir, ir3 = ir * ir2, ir5 = ir3 * ir2;
      const __m256d rr = r2 * ir;
      __m256d ul, frl;
      lj4(TRUNC, C, &B, ir2, rr, ir, &ul, &frl);
      /* dip_pairs8's regrouping of rl_dipole_dipole_rf / _sf */
      const __m256d pij = mi[0] * mjx + mi[1] * mjy + mi[2] * mjz;
      const __m256d pi = mi[0] * X + mi[1] * Y + mi[2] * Z;
      const __m256d pj = mjx * X + mjy * Y + mjz * Z;
      const __m256d m3 = V1(-3.0) * ir5, e15 = V1(-5.0) * m3 * pi * pj * ir2;
      __m256d Kd, A, s;
      if (DSF) {
        const __m256d x = rr * V1(1.0 / B.rc);
        const __m256d bb = V1(1.0) + x * x * x * (V1(-4.0) + V1(3.0) * x);
        const __m256d db = x * x * (V1(-12.0) + V1(12.0) * x) * V1(1.0 / B.rc);
        const __m256d g0 = pij * ir3 + m3 * pi * pj;
        Kd = V1(kc) * bb;
        A = Kd * ir3;
        s = frl - Kd * (m3 * pij + e15) - V1(kc) * g0 * db * ir;
      } else {
        Kd = V1(kc);
        A = Kd * (ir3 - V1(2.0 * krf));
        s = frl - Kd * (m3 * pij + e15);
      }
      const __m256d Bj = Kd * m3 * pj, Bi = Kd * m3 * pi;
      const __m256d fx = _mm256_and_pd(live, s * X - Bj * mi[0] - Bi * mjx);
      const __m256d fy = _mm256_and_pd(live, s * Y - Bj * mi[1] - Bi * mjy);
      const __m256d fz = _mm256_and_pd(live, s * Z - Bj * mi[2] - Bi * mjz);
      const __m256d gix = A * mjx + Bj * X, giy = A * mjy + Bj * Y, giz = A * mjz + Bj * Z;
      const __m256d gjx = A * mi[0] + Bi * X, gjy = A * mi[1] + Bi * Y, gjz = A * mi[2] + Bi * Z;
      Sf[0] = Sf[0] + fx; Sf[1] = Sf[1] + fy; Sf[2] = Sf[2] + fz;
      if (EV) {
        elj = elj + _mm256_and_pd(live, ul);
        edip = edip + _mm256_and_pd(live, pij * A + Bi * pj);
        const __m256d Rv[3] = {X, Y, Z}, Fv[3] = {fx, fy, fz};
        for (int r = 0; r < 3; r++)
          for (int c = 0; c < 3; c++) Sw[3 * r + c] = Sw[3 * r + c] + Rv[r] * Fv[c];
      }
      St[0] = St[0] - _mm256_and_pd(live, mi[1] * giz - mi[2] * giy);
      St[1] = St[1] - _mm256_and_pd(live, mi[2] * gix - mi[0] * giz);
      St[2] = St[2] - _mm256_and_pd(live, mi[0] * giy - mi[1] * gix);
      const __m256d e0[4] = {zero - fx, zero - fy, zero - fz, zero};
      const __m256d e1[4] = {mjz * gjy - mjy * gjz, mjx * gjz - mjz * gjx, mjy * gjx - mjx * gjy, zero};
      __m256d o0[4], o1[4];
      tr4x4(e0, o0);
      tr4x4(e1, o1);
      for (int l = 0; l < cnt; l++) {
        double *o = ft[b.idx[k + l]];
        _mm256_store_pd(o, _mm256_add_pd(_mm256_load_pd(o), o0[l]));
        _mm256_store_pd(o + 4, _mm256_add_pd(_mm256_load_pd(o + 4), o1[l]));
      }
    }
  }
  /* the force and torque on i go to its record, as in dipole_row512 */
  for (int c = 0; c < 3; c++) {
    ft[i][c] += hsum4(Sf[c]);
    ft[i][4 + c] += hsum4(St[c]);
  }
  if (EV) {
    acc->lj += hsum4(elj);
    acc->dip += hsum4(edip);
    for (int c = 0; c < 9; c++) acc->vir[c] += hsum4(Sw[c]);
  }
  acc->bad |= bad != 0;
#undef V1
}
#endif

/* LJ + point dipoles, one site at the centre, so r = R, the centres' minimum image, for both
 * cutoff schemes.  DSF: 0 reaction field (rl_dipole_dipole_rf), 1 shifted force (_sf).  The
 * portable rows (AVX2, baseline, ROTLEAP_NO_AVX512); dipole_row512 is the same on AVX-512. */
RL_INLINE void dipole_row(const int DSF, const int TRUNC, const rl_forcefield *ff,
                          const kview *V, const fast_species *K, int i, const int *nbr, int len,
                          double (*fs)[3], double (*tq)[3], rl_acc *acc)
{
  const int oi = V->soff[i];
  const box_consts B = consts_of(ff);
  const double rc = B.rc, rc2 = B.rc2, rsw = B.rsw, md2 = B.md2;
  const double kc = ff->kc, krf = ff->rf.krf, mu = K->mu;
  const lj_consts C = lj_of(&K->t[0]);
  const double mix = mu * V->ax[i][0], miy = mu * V->ax[i][1], miz = mu * V->ax[i][2];
  batch b;
  double fix = 0.0, fiy = 0.0, fiz = 0.0, tix = 0.0, tiy = 0.0, tiz = 0.0;
  double elj = 0.0, edip = 0.0;
  double w0 = 0, w1 = 0, w2 = 0, w3 = 0, w4 = 0, w5 = 0, w6 = 0, w7 = 0, w8 = 0;
  double bad = 0.0;
  for (int pos = 0; pos < len;) {
    batch_fill(P_MOL, 1, 0, V, &B, i, nbr, len, &pos, K, rc2, 0, &b);
    if (b.n == 0) continue;
    const int np = b.np;
    /* the pair terms; each lane's force on j, torque on j and torque on i go to the batch
     * (b.f, b.t, b.g), and the sums over the lanes are formed in the loop below: with all 17
     * sums in this loop GCC kept them in memory, loaded and stored every iteration */
#pragma omp simd reduction(+ : elj, edip, bad)
    for (int k = 0; k < np; k++) {
      const double rx = b.R[0][k], ry = b.R[1][k], rz = b.R[2][k];
      double r2 = rx * rx + ry * ry + rz * rz;
      const double in = b.w[k] * (r2 < rc2 ? 1.0 : 0.0);
      bad += in * (r2 < md2 ? 1.0 : 0.0);
      /* dd_plain (dipole.c) */
      const double mjx = b.m[0][k], mjy = b.m[1][k], mjz = b.m[2][k];
      double ir = rl_rsqrt(r2), ir2 = ir * ir, ir3 = ir * ir2, ir5 = ir3 * ir2;
      double frl, ul = lj_eval_ir2(TRUNC, C, rc, rsw, r2, ir2, &frl);
      double pij = mix * mjx + miy * mjy + miz * mjz;
      double pi = mix * rx + miy * ry + miz * rz;
      double pj = mjx * rx + mjy * ry + mjz * rz;
      double e15 = 15.0 * pi * pj * ir5 * ir2;
      double drx = -3.0 * ir5 * (pij * rx + mix * pj + mjx * pi) + e15 * rx;
      double dry = -3.0 * ir5 * (pij * ry + miy * pj + mjy * pi) + e15 * ry;
      double drz = -3.0 * ir5 * (pij * rz + miz * pj + mjz * pi) + e15 * rz;
      double gix = mjx * ir3 - 3.0 * ir5 * pj * rx, giy = mjy * ir3 - 3.0 * ir5 * pj * ry,
             giz = mjz * ir3 - 3.0 * ir5 * pj * rz;
      double gjx = mix * ir3 - 3.0 * ir5 * pi * rx, gjy = miy * ir3 - 3.0 * ir5 * pi * ry,
             gjz = miz * ir3 - 3.0 * ir5 * pi * rz;
      double rr = sqrt(r2), g0 = pij * ir3 - 3.0 * pi * pj * ir5, ud, fpx, fpy, fpz;
      if (DSF) { /* rl_dipole_dipole_sf */
        double x = rr / rc;
        double bb = 1.0 + x * x * x * (-4.0 + 3.0 * x);
        double db = x * x * (-12.0 + 12.0 * x) / rc;
        fpx = -kc * (bb * drx + g0 * db * rx / rr);
        fpy = -kc * (bb * dry + g0 * db * ry / rr);
        fpz = -kc * (bb * drz + g0 * db * rz / rr);
        gix *= kc * bb; giy *= kc * bb; giz *= kc * bb;
        gjx *= kc * bb; gjy *= kc * bb; gjz *= kc * bb;
        ud = kc * bb * g0;
      } else { /* rl_dipole_dipole_rf */
        fpx = -kc * drx; fpy = -kc * dry; fpz = -kc * drz;
        gix = kc * (gix - 2.0 * krf * mjx); giy = kc * (giy - 2.0 * krf * mjy);
        giz = kc * (giz - 2.0 * krf * mjz);
        gjx = kc * (gjx - 2.0 * krf * mix); gjy = kc * (gjy - 2.0 * krf * miy);
        gjz = kc * (gjz - 2.0 * krf * miz);
        ud = kc * (g0 - 2.0 * krf * pij);
      }
      double fx = frl * rx, fy = frl * ry, fz = frl * rz; /* site_pair: LJ, then the dipoles */
      fx += fpx; fy += fpy; fz += fpz;
      fx *= in; fy *= in; fz *= in;
      gix *= in; giy *= in; giz *= in;
      gjx *= in; gjy *= in; gjz *= in;
      elj += in * ul;
      edip += in * ud;
      b.f[0][0][k] = -fx; b.f[0][1][k] = -fy; b.f[0][2][k] = -fz;
      b.g[0][0][k] = -(miy * giz - miz * giy); /* torque -mu x g on i */
      b.g[0][1][k] = -(miz * gix - mix * giz);
      b.g[0][2][k] = -(mix * giy - miy * gix);
      b.t[0][k] = -(mjy * gjz - mjz * gjy);
      b.t[1][k] = -(mjz * gjx - mjx * gjz);
      b.t[2][k] = -(mjx * gjy - mjy * gjx);
    }
    /* the row's sums: force and torque on i, virial R (x) F with F = -b.f the force on i */
#pragma omp simd reduction(+ : fix, fiy, fiz, tix, tiy, tiz, w0, w1, w2, w3, w4, w5, w6, w7, w8)
    for (int k = 0; k < np; k++) {
      const double Fx = b.f[0][0][k], Fy = b.f[0][1][k], Fz = b.f[0][2][k];
      const double rx = b.R[0][k], ry = b.R[1][k], rz = b.R[2][k];
      fix -= Fx; fiy -= Fy; fiz -= Fz;
      tix += b.g[0][0][k]; tiy += b.g[0][1][k]; tiz += b.g[0][2][k];
      w0 -= rx * Fx; w1 -= rx * Fy; w2 -= rx * Fz;
      w3 -= ry * Fx; w4 -= ry * Fy; w5 -= ry * Fz;
      w6 -= rz * Fx; w7 -= rz * Fy; w8 -= rz * Fz;
    }
    batch_scatter(1, V, &b, K, fs, tq);
  }
  fs[oi][0] += fix; fs[oi][1] += fiy; fs[oi][2] += fiz;
  tq[i][0] += tix; tq[i][1] += tiy; tq[i][2] += tiz;
  acc->lj += elj;
  acc->dip += edip;
  acc->vir[0] += w0; acc->vir[1] += w1; acc->vir[2] += w2;
  acc->vir[3] += w3; acc->vir[4] += w4; acc->vir[5] += w5;
  acc->vir[6] += w6; acc->vir[7] += w7; acc->vir[8] += w8;
  acc->bad |= bad != 0.0;
}

/* Instances: one function per (mode, truncation) and (dipole method, truncation), each
 * compiled for AVX-512, AVX2 and baseline x86-64 and picked at load time; the dipole and
 * TIP4P rows in AVX-512 registers (dipx_*, tip4px_*; forces only: dipo_*, tip4po_*), picked
 * at setup. */
#define ROW_FN_T(ATTR, NAME, BODY)                                                             \
  ATTR static void NAME(const rl_forcefield *ff, const kview *V, const fast_species *K, int i,  \
                        const int *nbr, int len, double (*fs)[3], double (*tq)[3],             \
                        double (*ft)[8], double (*ft4)[16], rl_acc *acc)                       \
  {                                                                                            \
    (void)tq;                                                                                  \
    (void)ft;                                                                                  \
    (void)ft4;                                                                                 \
    BODY;                                                                                      \
  }
#define ROW_FN(NAME, BODY) ROW_FN_T(RL_CLONES, NAME, BODY)
#define SITES4(M, P)                                                                           \
  ROW_FN(sites_##M##0, sites_row(P, RL_LJ_PLAIN, ff, V, K, i, nbr, len, fs, acc))                 \
  ROW_FN(sites_##M##1, sites_row(P, RL_LJ_SHIFTED, ff, V, K, i, nbr, len, fs, acc))               \
  ROW_FN(sites_##M##2, sites_row(P, RL_LJ_SHIFTED_FORCE, ff, V, K, i, nbr, len, fs, acc))         \
  ROW_FN(sites_##M##3, sites_row(P, RL_LJ_SWITCHED, ff, V, K, i, nbr, len, fs, acc))              \
  ROW_FN(tip4p_##M##0, tip4p_row(P, RL_LJ_PLAIN, ff, V, K, i, nbr, len, fs, acc))                 \
  ROW_FN(tip4p_##M##1, tip4p_row(P, RL_LJ_SHIFTED, ff, V, K, i, nbr, len, fs, acc))               \
  ROW_FN(tip4p_##M##2, tip4p_row(P, RL_LJ_SHIFTED_FORCE, ff, V, K, i, nbr, len, fs, acc))         \
  ROW_FN(tip4p_##M##3, tip4p_row(P, RL_LJ_SWITCHED, ff, V, K, i, nbr, len, fs, acc))
SITES4(s, P_SITE)
SITES4(h, P_SHIFT)
SITES4(m, P_MOL)
ROW_FN(dip_r0, dipole_row(0, RL_LJ_PLAIN, ff, V, K, i, nbr, len, fs, tq, acc))
ROW_FN(dip_r1, dipole_row(0, RL_LJ_SHIFTED, ff, V, K, i, nbr, len, fs, tq, acc))
ROW_FN(dip_r2, dipole_row(0, RL_LJ_SHIFTED_FORCE, ff, V, K, i, nbr, len, fs, tq, acc))
ROW_FN(dip_r3, dipole_row(0, RL_LJ_SWITCHED, ff, V, K, i, nbr, len, fs, tq, acc))
ROW_FN(dip_f0, dipole_row(1, RL_LJ_PLAIN, ff, V, K, i, nbr, len, fs, tq, acc))
ROW_FN(dip_f1, dipole_row(1, RL_LJ_SHIFTED, ff, V, K, i, nbr, len, fs, tq, acc))
ROW_FN(dip_f2, dipole_row(1, RL_LJ_SHIFTED_FORCE, ff, V, K, i, nbr, len, fs, tq, acc))
ROW_FN(dip_f3, dipole_row(1, RL_LJ_SWITCHED, ff, V, K, i, nbr, len, fs, tq, acc))
#if RL_X512
/* The instances of one register-row kind (DIP512, TIP512, DIP256, TIP256) for every dipole
 * method or separation mode and every truncation. */
#define DIP_EV(INST, R, F, EV)                                                                 \
  INST(R##0, 0, EV, RL_LJ_PLAIN)                                                               \
  INST(R##1, 0, EV, RL_LJ_SHIFTED)                                                             \
  INST(R##2, 0, EV, RL_LJ_SHIFTED_FORCE)                                                       \
  INST(R##3, 0, EV, RL_LJ_SWITCHED)                                                            \
  INST(F##0, 1, EV, RL_LJ_PLAIN)                                                               \
  INST(F##1, 1, EV, RL_LJ_SHIFTED)                                                             \
  INST(F##2, 1, EV, RL_LJ_SHIFTED_FORCE)                                                       \
  INST(F##3, 1, EV, RL_LJ_SWITCHED)
#define TIP_EV(INST, H, M, EV)                                                                 \
  INST(H##0, EV, P_SHIFT, RL_LJ_PLAIN)                                                         \
  INST(H##1, EV, P_SHIFT, RL_LJ_SHIFTED)                                                       \
  INST(H##2, EV, P_SHIFT, RL_LJ_SHIFTED_FORCE)                                                 \
  INST(H##3, EV, P_SHIFT, RL_LJ_SWITCHED)                                                      \
  INST(M##0, EV, P_MOL, RL_LJ_PLAIN)                                                           \
  INST(M##1, EV, P_MOL, RL_LJ_SHIFTED)                                                         \
  INST(M##2, EV, P_MOL, RL_LJ_SHIFTED_FORCE)                                                   \
  INST(M##3, EV, P_MOL, RL_LJ_SWITCHED)
/* EV = 0: the forces-only rows (no energy and virial sums), dipo_* and tip4po_* */
#define DIP512(NAME, DSF, EV, TRUNC)                                                           \
  ROW_FN_T(RL_T512, NAME, dipole_row512(DSF, EV, TRUNC, ff, V, K, i, nbr, len, fs, tq, ft, acc))
DIP_EV(DIP512, dipx_r, dipx_f, 1)
DIP_EV(DIP512, dipo_r, dipo_f, 0)
/* flatten: the fill (with other_images' branch) is too large for GCC to inline on its own */
#define TIP512(NAME, EV, MODE, TRUNC)                                                          \
  ROW_FN_T(RL_T512 __attribute__((flatten)), NAME,                                             \
           tip4p_row512(EV, MODE, TRUNC, ff, V, K, i, nbr, len, fs, ft4, acc))
TIP_EV(TIP512, tip4px_h, tip4px_m, 1)
TIP_EV(TIP512, tip4po_h, tip4po_m, 0)
/* the same rows on AVX2: dipy_* and tip4py_* (forces only: dipz_*, tip4pz_*) */
#define DIP256(NAME, DSF, EV, TRUNC)                                                           \
  ROW_FN_T(RL_T256, NAME, (void)fs; dipole_row256(DSF, EV, TRUNC, ff, V, K, i, nbr, len, ft, acc))
DIP_EV(DIP256, dipy_r, dipy_f, 1)
DIP_EV(DIP256, dipz_r, dipz_f, 0)
#define TIP256(NAME, EV, MODE, TRUNC)                                                          \
  ROW_FN_T(RL_T256 RL_SCHED __attribute__((flatten)), NAME,                                    \
           tip4p_row256(0, EV, MODE, TRUNC, ff, V, K, i, nbr, len, fs, ft4, acc))
TIP_EV(TIP256, tip4py_h, tip4py_m, 1)
TIP_EV(TIP256, tip4pz_h, tip4pz_m, 0)
/* mixed precision on AVX2: tip4pf_* (forces only: tip4pg_*) */
#define TIP256F(NAME, EV, MODE, TRUNC)                                                         \
  ROW_FN_T(RL_T256 RL_SCHED __attribute__((flatten)), NAME,                                    \
           tip4p_row256(1, EV, MODE, TRUNC, ff, V, K, i, nbr, len, fs, ft4, acc))
TIP_EV(TIP256F, tip4pf_h, tip4pf_m, 1)
TIP_EV(TIP256F, tip4pg_h, tip4pg_m, 0)
#endif

/* [mode][truncation] */
static const row_fn sites_fns[3][4] = {{sites_s0, sites_s1, sites_s2, sites_s3},
                                       {sites_h0, sites_h1, sites_h2, sites_h3},
                                       {sites_m0, sites_m1, sites_m2, sites_m3}};
/* [variant][mode][truncation]: variant VEC_PORTABLE, then for AVX-512 and AVX2 the register
 * rows and the same without the energy and virial sums (forces only), then (TIP4P) the AVX2
 * rows in mixed precision, with and without those sums; site images (P_SITE) only portable.
 * Without target attributes (not GCC on x86-64) every variant is portable. */
enum { VEC_PORTABLE = 0, VEC_512 = 1, VEC_256 = 2 };
#define VAR_EV(vec) ((vec) == VEC_512 ? 1 : (vec) == VEC_256 ? 3 : 0)
#define VAR_FO(vec) ((vec) == VEC_512 ? 2 : (vec) == VEC_256 ? 4 : 0)
#if RL_X512
#define TIP_VAR(H, M)                                                                          \
  {{tip4p_s0, tip4p_s1, tip4p_s2, tip4p_s3},                                                   \
   {H##0, H##1, H##2, H##3},                                                                   \
   {M##0, M##1, M##2, M##3}}
#define DIP_VAR(R, F) {{R##0, R##1, R##2, R##3}, {F##0, F##1, F##2, F##3}}
#else
#define TIP_VAR(H, M) TIP_VAR0
#define DIP_VAR(R, F) DIP_VAR0
#endif
#define TIP_VAR0                                                                               \
  {{tip4p_s0, tip4p_s1, tip4p_s2, tip4p_s3},                                                   \
   {tip4p_h0, tip4p_h1, tip4p_h2, tip4p_h3},                                                   \
   {tip4p_m0, tip4p_m1, tip4p_m2, tip4p_m3}}
#define DIP_VAR0 {{dip_r0, dip_r1, dip_r2, dip_r3}, {dip_f0, dip_f1, dip_f2, dip_f3}}
static const row_fn tip4p_fns[7][3][4] = {TIP_VAR0, TIP_VAR(tip4px_h, tip4px_m),
                                          TIP_VAR(tip4po_h, tip4po_m), TIP_VAR(tip4py_h, tip4py_m),
                                          TIP_VAR(tip4pz_h, tip4pz_m), TIP_VAR(tip4pf_h, tip4pf_m),
                                          TIP_VAR(tip4pg_h, tip4pg_m)};
/* [variant, as tip4p_fns][dipole method][truncation] */
static const row_fn dipole_fns[5][2][4] = {DIP_VAR0, DIP_VAR(dipx_r, dipx_f),
                                           DIP_VAR(dipo_r, dipo_f), DIP_VAR(dipy_r, dipy_f),
                                           DIP_VAR(dipz_r, dipz_f)};

/* ------------------------------------------------------------------------ setup */

static void term_set(const rl_forcefield *ff, int ta, int tb, fast_term *T)
{
  const rl_lj_coef *c = &ff->lj[ta * ff->ntypes + tb];
  T->c6 = c->c6;
  T->c12 = c->c12;
  T->eshift = c->eshift;
  T->fshift = c->fshift;
  T->qq = ff->kc * ff->q[ta] * ff->q[tb];
}

/* The kernel of species k from its sites and the current LJ table. */
static void classify(const rl_forcefield *ff, int k, int vec, int tmix, fast_species *K)
{
  memset(K, 0, sizeof *K);
  int ns = ff->sp_nsites[k], o = ff->type_off[k];
  if (ns < 1 || ns > RL_FAST_MAXS || ff->sp_count[k] < 2) return;
  int ndip = 0, nq = 0, nquad = 0;
  for (int a = 0; a < ns; a++) {
    ndip += ff->mu[o + a] != 0.0;
    nquad += ff->Q[o + a] != 0.0;
    nq += ff->q[o + a] != 0.0;
  }
  if (nquad) return;
  K->ns = ns;
  K->extent = ff->sp_extent[k];
  for (int a = 0; a < ns; a++) K->perm[a] = a;
  if (ndip) { /* stockmayer: one site at the centre, LJ + dipole, no charge */
    if (ns != 1 || nq || ff->sp_extent[k] != 0.0) { K->ns = 0; return; }
    K->kind = K_DIPOLE;
    K->mu = ff->mu[o];
    K->nterms = 1;
    term_set(ff, o, o, &K->t[0]);
    for (int m = 0; m < 3; m++) {
      const int dsf = ff->p.dipole_method == RL_DIPOLE_SF, tr = ff->p.lj_truncation;
      K->row[m] = dipole_fns[VAR_EV(vec)][dsf][tr];
      K->row_fo[m] = dipole_fns[VAR_FO(vec)][dsf][tr];
    }
    return;
  }
  K->kind = K_SITES;
  int nlj = 0, ncoul = 0, nboth = 0, ljsite = -1;
  for (int a = 0; a < ns; a++)
    for (int b = 0; b < ns; b++) {
      int lj = ff->lj[(o + a) * ff->ntypes + o + b].epsilon != 0.0;
      int qq = ff->q[o + a] != 0.0 && ff->q[o + b] != 0.0;
      if (!lj && !qq) continue;
      fast_term *T = &K->t[K->nterms++];
      T->a = a;
      T->b = b;
      T->what = lj && qq ? T_BOTH : lj ? T_LJ : T_COUL;
      nlj += T->what == T_LJ;
      ncoul += T->what == T_COUL;
      nboth += T->what == T_BOTH;
      if (T->what == T_LJ && a == b) ljsite = a;
      term_set(ff, o + a, o + b, T);
    }
  for (int m = 0; m < 3; m++) K->row[m] = K->row_fo[m] = sites_fns[m][ff->p.lj_truncation];
  /* TIP4P pattern: one LJ site (with itself only, no charge), three charges without LJ */
  if (ns == 4 && nlj == 1 && ljsite >= 0 && ncoul == 9 && nboth == 0) {
    K->kind = K_TIP4P;
    int s = 1;
    K->perm[0] = ljsite;
    for (int a = 0; a < 4; a++)
      if (a != ljsite) K->perm[s++] = a;
    term_set(ff, o + ljsite, o + ljsite, &K->t[0]);
    K->t[0].a = K->t[0].b = 0;
    K->t[0].what = T_LJ;
    for (int p = 0; p < 3; p++)
      for (int q = 0; q < 3; q++) {
        fast_term *T = &K->t[1 + 3 * p + q];
        term_set(ff, o + K->perm[1 + p], o + K->perm[1 + q], T);
        T->a = 1 + p;
        T->b = 1 + q;
        T->what = T_COUL;
      }
    for (int m = 0; m < 3; m++) {
      K->row[m] = tip4p_fns[tmix ? 5 : VAR_EV(vec)][m][ff->p.lj_truncation];
      K->row_fo[m] = tip4p_fns[tmix ? 6 : VAR_FO(vec)][m][ff->p.lj_truncation];
    }
  }
}

static const char *species_name(const fast_species *K)
{
  return K->kind == K_DIPOLE ? "stockmayer" : K->kind == K_TIP4P ? "tip4p"
                                            : K->kind == K_SITES ? "charge-lj" : NULL;
}

void rl_ff_fast_free(rl_ff_fast *f)
{
  if (!f) return;
  free(f->sk);
  rl_nlist_free(f->chk);
  free(f->fstart); free(f->gstart); free(f->fnbr); free(f->gnbr);
  free(f->tlo); free(f->thi); free(f->rmax);
  if (f->tr)
    for (int c = 0; c < f->nchunk; c++) { free(f->tr[c].f); free(f->tr[c].g); }
  free(f->tr);
  if (f->cand)
    for (int t = 0; t < f->nthreads; t++) free(f->cand[t]);
  free(f->cand);
  free(f->cell_of); free(f->cell_start); free(f->cell_body); free(f->bx);
  free(f->fsbuf); free(f->tqbuf);
  free(f->acc);
  free(f->status);
  free(f->mode);
  free(f->ord);
  free(f->V.c); free(f->V.ax); free(f->V.site); free(f->V.dsite); free(f->V.soff); free(f->V.sp);
  free(f->pfs); free(f->ptq);
  free(f->V.pk); free(f->pft); free(f->V.pk4); free(f->pft4); free(f->V.pk4f);
  free(f->xstart); free(f->xnbr); free(f->xsh); free(f->xfar);
  free(f);
}

/* Zeroed, 64-byte aligned (bytes: a multiple of 64). */
static void *alloc_records(size_t bytes)
{
  void *p = aligned_alloc(64, bytes);
  if (p) memset(p, 0, bytes);
  return p;
}

int rl_ff_fast_setup(rl_forcefield *ff)
{
  long builds = ff->fast ? rl_ff_fast_builds(ff->fast) : 0;
  rl_ff_fast_free(ff->fast);
  ff->fast = NULL;
  if (ff->p.kernel == RL_KERNEL_GENERAL || !ff->p.neighbor_list) return RL_OK;
  rl_ff_fast *f = calloc(1, sizeof *f);
  if (!f) return rl_error(RL_ENOMEM, "forcefield: out of memory");
  const int T = rl_threads_resolve(ff->p.threads);
  f->nthreads = T;
  int n = ff->n;
  f->sk = calloc((size_t)ff->nspecies, sizeof *f->sk);
  f->chk = rl_nlist_alloc(ff->skin);
  f->fstart = calloc((size_t)n + 1, sizeof(int));
  f->gstart = calloc((size_t)n + 1, sizeof(int));
  f->tlo = calloc((size_t)T + 1, sizeof(int));
  f->thi = calloc((size_t)T, sizeof(int));
  f->rmax = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  f->nchunk = T > 1 ? 16 * T : 1;
  f->tr = calloc((size_t)f->nchunk, sizeof *f->tr);
  f->cand = calloc((size_t)T, sizeof *f->cand);
  f->acc = calloc((size_t)T, sizeof *f->acc);
  f->status = calloc((size_t)T, sizeof *f->status);
  f->mode = calloc((size_t)(ff->nspecies > 0 ? ff->nspecies : 1), sizeof *f->mode);
  f->cell_of = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  f->cell_body = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  const size_t n1 = (size_t)(n > 0 ? n : 1), s1 = (size_t)(ff->nsites > 0 ? ff->nsites : 1);
  f->ord = malloc(sizeof(int) * n1);
  f->V.soff = malloc(sizeof(int) * n1);
  f->V.sp = malloc(sizeof(int) * n1);
  f->V.c = malloc(sizeof *f->V.c * n1);
  f->V.ax = malloc(sizeof *f->V.ax * n1);
  f->V.site = malloc(sizeof *f->V.site * s1);
  f->V.dsite = malloc(sizeof *f->V.dsite * s1);
  f->pfs = calloc(s1 * (size_t)T, sizeof *f->pfs); /* zero between computes (see the sums) */
  f->ptq = calloc(n1 * (size_t)T, sizeof *f->ptq);
  f->bx = malloc(sizeof *f->bx * 3 * n1);
  if (T > 1) {
    f->fsbuf = malloc(sizeof *f->fsbuf * (size_t)(T - 1) * (size_t)(ff->nsites > 0 ? ff->nsites : 1));
    f->tqbuf = malloc(sizeof *f->tqbuf * (size_t)(T - 1) * (size_t)(n > 0 ? n : 1));
  }
  if (!f->sk || !f->chk || !f->fstart || !f->gstart || !f->tlo || !f->thi || !f->rmax ||
      !f->tr || !f->cand || !f->acc || !f->status || !f->mode || !f->ord || !f->V.soff ||
      !f->V.sp || !f->V.c || !f->V.ax || !f->V.site || !f->V.dsite || !f->pfs || !f->ptq ||
      !f->cell_of || !f->cell_body || !f->bx ||
      (T > 1 && (!f->fsbuf || !f->tqbuf))) {
    rl_ff_fast_free(f);
    return rl_error(RL_ENOMEM, "forcefield: out of memory for the kernels' workspace");
  }
  for (int t = 0; t < T; t++)
    if (!(f->cand[t] = malloc(sizeof(int) * (n1 + 16)))) { /* scan512 stores 16 at a time */
      rl_ff_fast_free(f);
      return rl_error(RL_ENOMEM, "forcefield: out of memory for the kernels' workspace");
    }
  f->chk->builds = builds;
  /* name: the kernels in use, then "+general" if any pair takes the reference routine */
  int general = 0, used = 0;
  char *p = f->namebuf;
  size_t left = sizeof f->namebuf;
  int nonempty = 0;
  for (int k = 0; k < ff->nspecies; k++) nonempty += ff->sp_count[k] > 0 && ff->sp_nsites[k] > 0;
#if RL_X512
  const int avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                   !getenv("ROTLEAP_NO_AVX2");
  if (__builtin_cpu_supports("avx512f") && !getenv("ROTLEAP_NO_AVX512")) f->vec = VEC_512;
  else if (avx2) f->vec = VEC_256;
  f->tmix = ff->p.precision == RL_PRECISION_MIXED && avx2; /* the AVX2 rows, on AVX-512 too */
#endif
  for (int k = 0; k < ff->nspecies; k++) {
    classify(ff, k, f->vec, f->tmix, &f->sk[k]);
    if (f->sk[k].kind == K_DIPOLE) f->ndip += ff->sp_count[k];
    if (f->sk[k].kind == K_TIP4P) f->ntip4p += ff->sp_count[k];
    if (ff->sp_count[k] == 0 || ff->sp_nsites[k] == 0) continue;
    const char *nm = species_name(&f->sk[k]);
    if (!nm) { general = 1; continue; }
    if (!strstr(f->namebuf, nm)) {
      int w = snprintf(p, left, "%s%s", used ? "+" : "", nm);
      if (w > 0 && (size_t)w < left) { p += w; left -= (size_t)w; }
      used = 1;
    }
  }
  if (nonempty > 1) general = 1; /* pairs of different species */
  if (f->vec) { /* the register rows' records: 64 bytes (dipoles), 128 (TIP4P) */
    const size_t T1 = (size_t)T;
    if (f->ndip) {
      f->V.pk = alloc_records(sizeof *f->V.pk * n1);
      f->pft = alloc_records(sizeof *f->pft * n1 * T1);
    }
    if (f->ntip4p) {
      if (f->tmix && !(f->V.pk4f = alloc_records(sizeof *f->V.pk4f * n1))) {
        rl_ff_fast_free(f);
        return rl_error(RL_ENOMEM, "forcefield: out of memory for the kernels' workspace");
      }
      f->V.pk4 = alloc_records(sizeof *f->V.pk4 * n1);
      f->pft4 = alloc_records(sizeof *f->pft4 * n1 * T1);
    }
    if ((f->ndip && (!f->V.pk || !f->pft)) || (f->ntip4p && (!f->V.pk4 || !f->pft4))) {
      rl_ff_fast_free(f);
      return rl_error(RL_ENOMEM, "forcefield: out of memory for the kernels' workspace");
    }
  }
  if (general) snprintf(p, left, "%s", used ? "+general" : "general");
  f->name = f->namebuf;
  ff->fast = f;
  return RL_OK;
}

const char *rl_ff_fast_name(const rl_ff_fast *f) { return f->name; }
const char *rl_ff_fast_rows(const rl_ff_fast *f)
{
  if (rl_ff_fast_mixed(f)) return f->vec == VEC_512 ? "avx512+avx2-mixed" : "avx2-mixed";
  return f->vec == VEC_512 ? "avx512" : f->vec == VEC_256 ? "avx2" : "portable";
}
int rl_ff_fast_mixed(const rl_ff_fast *f) { return f->tmix && f->ntip4p > 0; }
void rl_ff_fast_invalidate(rl_ff_fast *f)
{
  if (f) rl_nlist_invalidate(f->chk);
}
int rl_ff_fast_threads(const rl_ff_fast *f) { return f->nthreads; }
long rl_ff_fast_builds(const rl_ff_fast *f) { return f ? f->chk->builds : 0; }

const double (*rl_ff_fast_origin(const rl_ff_fast *f, int n))[3]
{
  return f && f->chk->n == n && f->chk->r0 ? (const double(*)[3])f->chk->r0 : NULL;
}

/* ------------------------------------------------------------------------ the list */

static int push(int **a, long *cap, long *len, int v)
{
  if (*len == *cap) {
    long nc = *cap ? 2 * *cap : 4096;
    int *p = realloc(*a, sizeof *p * (size_t)nc);
    if (!p) return 1;
    *a = p;
    *cap = nc;
  }
  (*a)[(*len)++] = v;
  return 0;
}

#if RL_X512
/* The list build's candidates on AVX-512: of the ranks in the runs [lo[r], hi[r]), those whose
 * centre (X, Y, Z by rank) lies within rlist of ri, in rank order, eight at a time, packed
 * with vpcompressd (the scalar loop was 11 % of a 64,000-dipole step in perf, issue 8).  The
 * separation, its image and r^2 take the scalar loop's operations in its order, each rounded
 * once (the _round_ forms are not fused into FMAs under -ffp-contract=fast), so both keep the
 * same pairs to the last bit.  Stores 16 indices at a time: cand needs 16 slots of slack. */
RL_T512 static int scan512(const double *X, const double *Y, const double *Z, const double ri[3],
                           const rl_box *box, double rl2, const int *lo, const int *hi, int nr,
                           int *cand)
{
#define RL_CUR _MM_FROUND_CUR_DIRECTION
  const __m512d c[3] = {_mm512_set1_pd(ri[0]), _mm512_set1_pd(ri[1]), _mm512_set1_pd(ri[2])};
  const __m512d L[3] = {_mm512_set1_pd(box->L[0]), _mm512_set1_pd(box->L[1]),
                        _mm512_set1_pd(box->L[2])};
  const __m512d iL[3] = {_mm512_set1_pd(box->invL[0]), _mm512_set1_pd(box->invL[1]),
                         _mm512_set1_pd(box->invL[2])};
  const __m512d big = _mm512_set1_pd(6755399441055744.0), R2 = _mm512_set1_pd(rl2);
  const __m512i iota = _mm512_set_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0);
  const double *P[3] = {X, Y, Z};
  int nin = 0;
  for (int r = 0; r < nr; r++)
    for (int m = lo[r]; m < hi[r]; m += 8) {
      const int left = hi[r] - m;
      const __mmask8 live = left >= 8 ? (__mmask8)0xFF : (__mmask8)((1u << left) - 1u);
      __m512d d2 = _mm512_setzero_pd();
      for (int k = 0; k < 3; k++) { /* d -= L RL_RND(d / L); d2 = (dx^2 + dy^2) + dz^2 */
        __m512d d = _mm512_sub_round_pd(c[k], _mm512_maskz_loadu_pd(live, P[k] + m), RL_CUR);
        __m512d q = _mm512_add_round_pd(_mm512_mul_round_pd(d, iL[k], RL_CUR), big, RL_CUR);
        q = _mm512_sub_round_pd(q, big, RL_CUR);
        d = _mm512_sub_round_pd(d, _mm512_mul_round_pd(L[k], q, RL_CUR), RL_CUR);
        const __m512d dd = _mm512_mul_round_pd(d, d, RL_CUR);
        d2 = k ? _mm512_add_round_pd(d2, dd, RL_CUR) : dd;
      }
      const __mmask8 keep = _mm512_mask_cmp_pd_mask(live, d2, R2, _CMP_LT_OQ);
      const __m512i id = _mm512_add_epi32(_mm512_set1_epi32(m), iota);
      _mm512_storeu_si512(cand + nin, _mm512_maskz_compress_epi32((__mmask16)keep, id));
      nin += __builtin_popcount(keep);
    }
#undef RL_CUR
  return nin;
}
#endif

/* The cost of row m (species k) in units of about one pair term: kernel terms per listed
 * pair, 16 per reference pair, and for the row itself (its setup, the last partial vector, the
 * lane sums) 60 for a dipole row and 110 for a site row: the later ranks list fewer neighbours
 * of higher rank, and without that term the thread with the later rows took 8 % longer (8,000
 * dipoles).  For the TIP4P rows on AVX2 a fit of cycles per row against its length gave about
 * 500 + 55 fl cycles, so a row costs as much as 9 of its pairs (12 units each); the all-pairs
 * list of a small box (256 TIP4P) has rows of 0 to 200 pairs, and thread 1 took twice as many.
 * The other site rows take the same 110 unmeasured (about 10 CO2 pairs, 37 charge-LJ pairs). */
static double row_cost(const rl_ff_fast *f, int k, int m)
{
  const fast_species *K = &f->sk[k];
  const int fl = f->fstart[m + 1] - f->fstart[m], gl = f->gstart[m + 1] - f->gstart[m];
  return K->kind == K_DIPOLE ? 4.0 * fl + (fl > 0 ? 60.0 : 0.0) + 16.0 * gl
                             : (double)fl * (K->nterms + 2) + (fl > 0 ? 110.0 : 0.0) + 16.0 * gl;
}

/* Whether the AVX2 TIP4P rows take the image list: some TIP4P species separates its sites by
 * shifting the centres' separation (P_SHIFT) in a box that needs other images (needs_images),
 * the modes rl_ff_fast_compute gives it. */
static int images_wanted(const rl_forcefield *ff)
{
  const rl_ff_fast *f = ff->fast;
  if ((f->vec != VEC_256 && !f->tmix) || ff->p.scheme == RL_CUTOFF_MOLECULE) return 0;
  const box_consts B = consts_of(ff);
  for (int k = 0; k < ff->nspecies; k++) {
    const fast_species *K = &f->sk[k];
    if (K->kind != K_TIP4P || ff->sp_count[k] == 0) continue;
    const double rp = ff->p.cutoff + 2.0 * K->extent;
    int shift = 1;
    for (int c = 0; c < 3; c++) shift &= ff->box.L[c] > rp && ff->box.L[c] >= 2.0 * ff->p.cutoff;
    if (shift && needs_images(P_SHIFT, &B, prune2(P_SHIFT, &B, K))) return 1;
  }
  return 0;
}

/* The image list of a small box, for the TIP4P rows on AVX2 (issue 8).  In a box with an edge
 * shorter than twice the pruning radius a neighbour can be in range through more than one
 * image of its centre, and fill256 looks for those images every step (for 256 TIP4P at
 * rc = 0.9 nm a third of the candidates have a far component), with branches and scalar
 * appends that took a good part of the row (`ffbench time tip4p 256 1 1000 --h 0.006`: the
 * step 0.83-0.87 of the time before, medians of alternating runs, builds included).  Here,
 * once per build, each image of a listed neighbour within rlist (at the build's centres)
 * becomes an entry of its own with its shift s, a multiple of the edges, so that the fill forms
 * c_i - c_j + s, tests it and packs it (fill256x).  That is exact between builds: the centres
 * are continuous (never wrapped), and as each moves less than half the skin, every image within
 * the pruning radius at a step was within rlist at the build.  Each site pair inside the cutoff
 * is still met once (L >= 2 rc).  A row lists its neighbours' minimum images in list order,
 * four at a time, then the other images of those that have any.  Kernel rows of other kinds
 * get empty rows.  Returns 0, or 1 when out of memory. */
#if RL_X512
/* One neighbour whose minimum image has another image within rlist (build_images): its shifts and
 * squared separations per component (0: the minimum image's, 1: the other's), and as bits the
 * components whose switch alone stays inside rlist. */
typedef struct far_image {
  int j, one;
  double s[2][3], x2[2][3];
} far_image;

/* Room in the image list for `more` entries past q (and the 4 slots of slack): grow it, keeping
 * the q entries written.  Returns 0, or 1 when out of memory. */
static int images_room(rl_ff_fast *f, long q, long more)
{
  if (q + more <= f->xcap) return 0;
  const long cap = 2 * (q + more), stride = f->xcap + 4;
  int *xn = realloc(f->xnbr, sizeof(int) * (size_t)(cap + 4));
  if (!xn) return 1;
  f->xnbr = xn;
  double *xs = malloc(sizeof(double) * 3 * (size_t)(cap + 4));
  if (!xs) return 1;
  if (f->xsh)
    for (int c = 0; c < 3; c++) memcpy(xs + c * (cap + 4), f->xsh + c * stride, sizeof(double) * (size_t)q);
  free(f->xsh);
  f->xsh = xs;
  f->xcap = cap;
  return 0;
}

RL_T256 static int build_images(rl_forcefield *ff)
{
  rl_ff_fast *f = ff->fast;
  const int n = ff->n;
  const rl_box *box = &ff->box;
  const double rl = ff->rlist, rl2 = rl * rl;
  const double *bx = f->bx, *by = bx + n, *bz = by + n;
  if (!f->xstart && !(f->xstart = malloc(sizeof(int) * ((size_t)n + 1)))) return 1;
  if (!f->xfar && !(f->xfar = malloc(sizeof *f->xfar * ((size_t)n + 4)))) return 1;
  /* room for every listed neighbour's minimum image and a quarter more (grown per row below
   * when short), with a margin so that the next builds' lists fit as well */
  if (images_room(f, 0, f->fstart[n] + f->fstart[n] / 4 + 8)) return 1;
  const __m256d L[3] = {_mm256_set1_pd(box->L[0]), _mm256_set1_pd(box->L[1]), _mm256_set1_pd(box->L[2])};
  const __m256d iL[3] = {_mm256_set1_pd(box->invL[0]), _mm256_set1_pd(box->invL[1]),
                         _mm256_set1_pd(box->invL[2])};
  const __m256d big = _mm256_set1_pd(6755399441055744.0), vrl2 = _mm256_set1_pd(rl2);
  const __m256d zero = _mm256_setzero_pd();
  const double *P[3] = {bx, by, bz};
  const int *fnbr = f->fnbr;
  far_image *xfar = f->xfar;
  long stride = f->xcap + 4, q = 0;
  int *xn = f->xnbr;
  double *xs = f->xsh;
  for (int m = 0; m < n; m++) {
    f->xstart[m] = (int)q;
    if (f->sk[f->V.sp[m]].kind != K_TIP4P) continue;
    const int lo = f->fstart[m], hi = f->fstart[m + 1];
    int nfar = 0;
    if (images_room(f, q, hi - lo)) return 1; /* the row's minimum images (4 at a time) */
    stride = f->xcap + 4;
    xn = f->xnbr;
    xs = f->xsh;
    /* the minimum images, four neighbours at a time (RL_RND as in the build's scan) */
    for (int p = lo; p < hi; p += 4) {
      const int cnt = hi - p < 4 ? hi - p : 4;
      _Alignas(16) int id[4];
      __m128i vi;
      if (cnt == 4) { /* one load: four int stores read back as one vector would not forward */
        vi = _mm_loadu_si128((const __m128i *)(fnbr + p));
        _mm_store_si128((__m128i *)id, vi);
      } else {
        for (int l = 0; l < 4; l++) id[l] = fnbr[p + (l < cnt ? l : 0)];
        vi = _mm_load_si128((const __m128i *)id);
      }
      __m256d s0[3], s1[3], q0[3], q1[3];
      for (int c = 0; c < 3; c++) {
        const double *Pc = P[c];
        const __m256d d = _mm256_sub_pd(_mm256_set1_pd(Pc[m]),
                                        _mm256_set_pd(Pc[id[3]], Pc[id[2]], Pc[id[1]], Pc[id[0]]));
        const __m256d k = _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(d, iL[c]), big), big);
        s0[c] = _mm256_sub_pd(zero, _mm256_mul_pd(L[c], k));
        const __m256d x0 = _mm256_add_pd(d, s0[c]);
        const __m256d t = _mm256_blendv_pd(L[c], _mm256_sub_pd(zero, L[c]), _mm256_cmp_pd(x0, zero, _CMP_GT_OQ));
        const __m256d x1 = _mm256_add_pd(x0, t);
        s1[c] = _mm256_add_pd(s0[c], t);
        q0[c] = _mm256_mul_pd(x0, x0);
        q1[c] = _mm256_mul_pd(x1, x1);
      }
      _mm_storeu_si128((__m128i *)(xn + q), vi);
      for (int c = 0; c < 3; c++) _mm256_storeu_pd(xs + c * stride + q, s0[c]);
      q += cnt;
      /* an image is inside rlist only if each of its components alone, switched, is (the other
       * image is the farther one): bit c of `one` for lane l; about one neighbour in ten has one
       * for 256 TIP4P at 0.9 nm */
      const __m256d sum = _mm256_add_pd(_mm256_add_pd(q0[0], q0[1]), q0[2]);
      unsigned one[3], any = 0;
      for (int c = 0; c < 3; c++) {
        const __m256d sw = _mm256_add_pd(_mm256_sub_pd(sum, q0[c]), q1[c]);
        one[c] = (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(sw, vrl2, _CMP_LT_OQ)) & ((1u << cnt) - 1u);
        any |= one[c];
      }
      if (!any) continue;
      _Alignas(32) double v[4][3][4]; /* s0, s1, q0, q1 by [component][lane] */
      for (int c = 0; c < 3; c++) {
        _mm256_store_pd(v[0][c], s0[c]);
        _mm256_store_pd(v[1][c], s1[c]);
        _mm256_store_pd(v[2][c], q0[c]);
        _mm256_store_pd(v[3][c], q1[c]);
      }
      for (; any; any &= any - 1) {
        const int l = __builtin_ctz(any);
        far_image *F = &xfar[nfar++];
        F->j = id[l];
        F->one = (int)((one[0] >> l & 1u) | (one[1] >> l & 1u) << 1 | (one[2] >> l & 1u) << 2);
        for (int c = 0; c < 3; c++) {
          F->s[0][c] = v[0][c][l];
          F->s[1][c] = v[1][c][l];
          F->x2[0][c] = v[2][c][l];
          F->x2[1][c] = v[3][c][l];
        }
      }
    }
    /* then the other images of the neighbours that have them: image im takes the other image
     * of component c where bit c is set */
    for (int e = 0; e < nfar; e++) {
      const far_image *F = &xfar[e];
      if (images_room(f, q, 7)) return 1; /* its other images */
      stride = f->xcap + 4;
      xn = f->xnbr;
      xs = f->xsh;
      for (int im = 1; im < 8; im++) {
        const int a = im & 1, g = (im >> 1) & 1, h = im >> 2;
        if ((im & F->one) != im || !(F->x2[a][0] + F->x2[g][1] + F->x2[h][2] < rl2)) continue;
        xn[q] = F->j;
        xs[q] = F->s[a][0];
        xs[stride + q] = F->s[g][1];
        xs[2 * stride + q] = F->s[h][2];
        q++;
      }
    }
  }
  f->xstart[n] = (int)q;
  for (int c = 0; c < 3; c++) /* fill256x's last vector reads up to 3 slots past the last row */
    for (long r = q; r < q + 4; r++) xs[c * stride + r] = 0.0;
  f->V.xstart = f->xstart;
  f->V.xnbr = f->xnbr;
  for (int c = 0; c < 3; c++) f->V.xs[c] = f->xsh + c * stride;
  return 0;
}
#else
static int build_images(rl_forcefield *ff) /* images_wanted is 0 without the AVX2 rows */
{
  (void)ff;
  return 1;
}
#endif

static int build(rl_forcefield *ff)
{
  rl_ff_fast *f = ff->fast;
  const int n = ff->n, T = f->nthreads;
  const rl_box *box = &ff->box;
  const double rl = ff->rlist, rl2 = rl * rl;
  /* Cells of edge >= rlist / 2, searched +-2 cells (the 5^3 stencil spans 15.6 rlist^3 of
   * candidates, against 27 rlist^3 for cells >= rlist searched +-1), when every edge holds at
   * least 5; else all pairs, through the same branch-free scan (a branch per pair made the
   * builds 5 % of a 256-TIP4P step at 6 fs, rebuilt every 6 steps).  With cells >= rlist a
   * box of a few list radii had 3 per edge and every body was a candidate of every other:
   * builds took ~3 steps' time for 2,048 TIP4P. */
  enum { reach = 2 }; /* a constant: sizes the runs arrays below */
  int nc[3];
  for (int c = 0; c < 3; c++) nc[c] = (int)fmin(256.0, floor(box->L[c] / (0.5 * rl)));
  const int cells = nc[0] >= 2 * reach + 1 && nc[1] >= 2 * reach + 1 && nc[2] >= 2 * reach + 1;
  const int ncell = cells ? nc[0] * nc[1] * nc[2] : 1;
  if (cells) {
    if (ncell + 1 > f->ncell_cap) {
      int *cs = realloc(f->cell_start, sizeof *cs * (size_t)(ncell + 1));
      if (!cs) return rl_error(RL_ENOMEM, "neighbour list: out of memory for %d cells", ncell);
      f->cell_start = cs;
      f->ncell_cap = ncell + 1;
    }
    memset(f->cell_start, 0, sizeof(int) * (size_t)(ncell + 1));
    for (int i = 0; i < n; i++) {
      f->cell_of[i] = rl_box_cell_index(box, ff->centre[i], nc);
      f->cell_start[f->cell_of[i] + 1]++;
    }
    for (int c = 0; c < ncell; c++) f->cell_start[c + 1] += f->cell_start[c];
    for (int i = 0; i < n; i++) f->cell_body[f->cell_start[f->cell_of[i]]++] = i; /* ascending */
    for (int c = ncell; c > 0; c--) f->cell_start[c] = f->cell_start[c - 1];
    f->cell_start[0] = 0;
  }
  /* the spatial order (cell_body lists the bodies cell by cell), and each rank's species,
   * first site in the kernels' copies and centre */
  for (int m = 0; m < n; m++) f->ord[m] = cells ? f->cell_body[m] : m;
  for (int m = 0, o = 0; m < n; m++) {
    const int i = f->ord[m];
    f->V.soff[m] = o;
    f->V.sp[m] = ff->body_species[i];
    o += ff->sp_nsites[f->V.sp[m]];
    for (int c = 0; c < 3; c++) /* the scan reads these */
      f->bx[(size_t)c * (size_t)n + (size_t)m] = ff->centre[i][c];
  }
  /* one species with a kernel and sites (a neat liquid): every candidate is a kernel pair */
  int live_species = 0, neat = 1;
  for (int k = 0; k < ff->nspecies; k++)
    if (ff->sp_count[k] > 0) {
      live_species++;
      neat &= f->sk[k].kind != K_NONE && ff->sp_nsites[k] > 0;
    }
  neat &= live_species == 1;
  const double *bx = f->bx, *by = bx + n, *bz = bx + 2 * (size_t)n;
  /* rows: chunk c holds ranks m in [n c / C, n (c+1) / C); body i = ord[m] lists the j of
   * higher rank, kernel pairs by rank, reference pairs by body; lengths go to f/gstart[m+1].
   * A chunk's rows do not depend on the thread that takes it. */
  int fail = 0;
  const int C = f->nchunk;
#pragma omp parallel num_threads(T) reduction(| : fail)
  {
    int *cand = f->cand[omp_get_thread_num()];
#pragma omp for schedule(dynamic, 1)
    for (int ch = 0; ch < C; ch++) {
      chunk_rows *tr = &f->tr[ch];
      tr->fn = tr->gn = 0;
      int m0 = (int)((long)n * ch / C), m1 = (int)((long)n * (ch + 1) / C);
      for (int mi = m0; mi < m1 && !fail; mi++) {
        const int i = f->ord[mi];
        int ki = ff->body_species[i];
        int fast_i = f->sk[ki].kind != K_NONE;
        long f0 = tr->fn, g0 = tr->gn;
        const double ri[3] = {bx[mi], by[mi], bz[mi]};
        if (ff->sp_nsites[ki] > 0) {
          /* the runs of ranks to scan: the cell stencil's, or (all pairs) the ranks above mi */
          int lo[(2 * reach + 1) * (2 * reach + 1) * (2 * reach + 1)], hi[sizeof lo / sizeof *lo];
          int nr = 0, nin = 0;
          if (!cells) {
            lo[0] = mi + 1;
            hi[0] = n;
            nr = hi[0] > lo[0];
          } else {
            int id = f->cell_of[i];
            int cx = id % nc[0], cy = (id / nc[0]) % nc[1], cz = id / (nc[0] * nc[1]);
            int wx[2 * reach + 1], wy[2 * reach + 1], wz[2 * reach + 1]; /* wrapped, no `%` */
            for (int d = -reach; d <= reach; d++) {
              const int x = cx + d, y = cy + d, z = cz + d;
              wx[d + reach] = x < 0 ? x + nc[0] : x >= nc[0] ? x - nc[0] : x;
              wy[d + reach] = y < 0 ? y + nc[1] : y >= nc[1] ? y - nc[1] : y;
              wz[d + reach] = z < 0 ? z + nc[2] : z >= nc[2] ? z - nc[2] : z;
            }
            /* the candidates of higher rank within rlist, branch-free (about a quarter of the
             * stencil's bodies are inside, a branch was mispredicted often); runs of cells
             * along x are contiguous in rank unless the stencil wraps */
            const int runs = cx - reach >= 0 && cx + reach < nc[0] ? 1 : 2 * reach + 1;
            for (int dz = 0; dz <= 2 * reach; dz++)
              for (int dy = 0; dy <= 2 * reach; dy++)
                for (int r = 0; r < runs; r++) {
                  const int row = (wz[dz] * nc[1] + wy[dy]) * nc[0];
                  const int c0 = row + (runs == 1 ? wx[0] : wx[r]);
                  const int c1 = row + (runs == 1 ? wx[2 * reach] : wx[r]);
                  lo[nr] = f->cell_start[c0] > mi + 1 ? f->cell_start[c0] : mi + 1;
                  hi[nr] = f->cell_start[c1 + 1];
                  nr += hi[nr] > lo[nr];
                }
          }
#if RL_X512
          if (f->vec == VEC_512)
            nin = scan512(bx, by, bz, ri, box, rl2, lo, hi, nr, cand);
          else
#endif
            for (int r = 0; r < nr; r++)
              for (int m = lo[r]; m < hi[r]; m++) {
                double d[3] = {ri[0] - bx[m], ri[1] - by[m], ri[2] - bz[m]};
                for (int c = 0; c < 3; c++) d[c] -= box->L[c] * RL_RND(d[c] * box->invL[c]);
                cand[nin] = m;
                nin += d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < rl2;
              }
          if (neat) { /* all kernel pairs: one copy */
            if (tr->fn + nin > tr->fcap) {
              long nc2 = tr->fcap ? 2 * tr->fcap : 4096;
              while (nc2 < tr->fn + nin) nc2 *= 2;
              int *p = realloc(tr->f, sizeof *p * (size_t)nc2);
              if (!p) { fail = 1; break; }
              tr->f = p;
              tr->fcap = nc2;
            }
            if (nin) /* tr->f is still NULL while no row has had a pair (a dilute gas) */
              memcpy(tr->f + tr->fn, cand, sizeof(int) * (size_t)nin);
            tr->fn += nin;
            nin = 0;
          }
          for (int q = 0; q < nin && !fail; q++) {
            const int m = cand[q], kj = f->V.sp[m];
            if (ff->sp_nsites[kj] == 0) continue;
            if (fast_i && kj == ki)
              fail |= push(&tr->f, &tr->fcap, &tr->fn, m);
            else
              fail |= push(&tr->g, &tr->gcap, &tr->gn, f->ord[m]);
          }
        }
        f->fstart[mi + 1] = (int)(tr->fn - f0);
        f->gstart[mi + 1] = (int)(tr->gn - g0);
        int top = mi;
        for (long q = f0; q < tr->fn; q++) top = tr->f[q] > top ? tr->f[q] : top;
        f->rmax[mi] = top;
      }
    }
  }
  if (fail) return rl_error(RL_ENOMEM, "neighbour list: out of memory");
  f->fstart[0] = f->gstart[0] = 0;
  for (int i = 0; i < n; i++) {
    f->fstart[i + 1] += f->fstart[i];
    f->gstart[i + 1] += f->gstart[i];
  }
  long nf = f->fstart[n], ng = f->gstart[n];
  if (nf > f->fcap) {
    int *p = realloc(f->fnbr, sizeof *p * (size_t)nf);
    if (!p) return rl_error(RL_ENOMEM, "neighbour list: out of memory for %ld pairs", nf);
    f->fnbr = p;
    f->fcap = nf;
  }
  if (ng > f->gcap) {
    int *p = realloc(f->gnbr, sizeof *p * (size_t)ng);
    if (!p) return rl_error(RL_ENOMEM, "neighbour list: out of memory for %ld pairs", ng);
    f->gnbr = p;
    f->gcap = ng;
  }
  for (int c = 0; c < C; c++) {
    int i0 = (int)((long)n * c / C);
    if (f->tr[c].fn) memcpy(f->fnbr + f->fstart[i0], f->tr[c].f, sizeof(int) * (size_t)f->tr[c].fn);
    if (f->tr[c].gn) memcpy(f->gnbr + f->gstart[i0], f->tr[c].g, sizeof(int) * (size_t)f->tr[c].gn);
  }
  /* compute ranges: equal shares of cost (row_cost) */
  double total = 0.0;
  for (int i = 0; i < n; i++) total += row_cost(f, ff->body_species[f->ord[i]], i);
  double run = 0.0;
  int t = 1;
  f->tlo[0] = 0;
  for (int i = 0; i < n && t < T; i++) {
    run += row_cost(f, ff->body_species[f->ord[i]], i);
    while (t < T && run >= total * t / T) f->tlo[t++] = i + 1;
  }
  while (t <= T) f->tlo[t++] = n;
  /* the ranks each thread's rows write: its own, and their neighbours (of higher rank), so that
   * it zeroes and the sums read only those (at 64,000 dipoles on two threads each thread's
   * buffer was 4 MB, of which the other half stayed zero) */
  for (int u = 0; u < T; u++) {
    int hi = f->tlo[u + 1];
    for (int m = f->tlo[u]; m < f->tlo[u + 1]; m++) hi = f->rmax[m] + 1 > hi ? f->rmax[m] + 1 : hi;
    f->thi[u] = hi;
  }
  /* positions at this build, for the rebuild test */
  rl_nlist *chk = f->chk;
  if (chk->n != n || !chk->r0) {
    double(*r0)[3] = realloc(chk->r0, sizeof *r0 * (size_t)(n > 0 ? n : 1));
    if (!r0) return rl_error(RL_ENOMEM, "neighbour list: out of memory for %d bodies", n);
    chk->r0 = r0;
  }
  if (n > 0) memcpy(chk->r0, ff->centre, sizeof *chk->r0 * (size_t)n);
  f->V.xstart = NULL; /* until build_images succeeds */
  if (images_wanted(ff) && build_images(ff))
    return rl_error(RL_ENOMEM, "neighbour list: out of memory for the images of a small box");
  chk->n = n;
  chk->rlist = rl;
  chk->npairs = nf + ng;
  chk->builds++;
  return RL_OK;
}

/* ------------------------------------------------------------------------ compute */

int rl_ff_fast_compute(rl_forcefield *ff, rl_acc *out)
{
  rl_ff_fast *f = ff->fast;
  const int n = ff->n, ns = ff->nsites, T = f->nthreads;
  /* the fast minimum image needs |d / L| < 2^51 */
  int far = 0;
#ifdef _OPENMP
#pragma omp parallel for num_threads(T) schedule(static) if (T > 1 && n >= RL_THREAD_MIN_BODIES) \
    reduction(| : far)
#endif
  for (int i = 0; i < n; i++)
    for (int c = 0; c < 3; c++) far |= fabs(ff->centre[i][c]) * ff->box.invL[c] > 1e12;
  if (far) return 1;
  if (ff->origin) { /* a restart: first the list the run had, built from its centres */
    double(*cur)[3] = ff->centre;
    ff->centre = ff->origin;
    int st = build(ff);
    ff->centre = cur;
    free(ff->origin);
    ff->origin = NULL;
    if (st) return st;
  }
  if (rl_nlist_needs_rebuild(f->chk, &ff->box, n, (const double(*)[3])ff->centre, NULL, T) ||
      f->chk->rlist != ff->rlist) {
    int st = build(ff);
    if (st) return st;
  }
  /* each species' separation mode (see P_SHIFT): the molecular shift where the box allows */
  int *mode = f->mode;
  for (int k = 0; k < ff->nspecies; k++) {
    const double rp = ff->p.cutoff + 2.0 * f->sk[k].extent, two_rc = 2.0 * ff->p.cutoff;
    int shift = 1;
    for (int c = 0; c < 3; c++) shift &= ff->box.L[c] > rp && ff->box.L[c] >= two_rc;
    mode[k] = ff->p.scheme == RL_CUTOFF_MOLECULE ? P_MOL : shift ? P_SHIFT : P_SITE;
  }
  kview *V = &f->V;
  const int *ord = f->ord;
  /* every body a dipole rank on the AVX-512 rows (a Stockmayer fluid): the kernels read and
   * write only the 64-byte records, so the copies and the sums below take a short path */
  const int dip_only = f->pft && f->ndip == n;
  /* no pairs for the reference routine: the threads' site-force buffers stay empty */
  const int general = f->gstart[n] > 0;
#pragma omp parallel num_threads(T)
  {
    int t = omp_get_thread_num();
    /* the kernels' copies in rank order */
    if (dip_only) {
#pragma omp for schedule(static)
      for (int m = 0; m < n; m++) {
        const int i = ord[m];
        const double mu = f->sk[ff->body_species[i]].mu;
        for (int c = 0; c < 3; c++) {
          V->pk[m][c] = ff->centre[i][c];
          V->pk[m][4 + c] = mu * ff->axis[i][c];
        }
      }
    } else
#pragma omp for schedule(static)
    for (int m = 0; m < n; m++) {
      const int i = ord[m], k = ff->body_species[i], ns_i = ff->sp_nsites[k];
      const int oi = ff->body_site_off[i], om = V->soff[m];
      const fast_species *K = &f->sk[k];
      if (V->pk4 && K->kind == K_TIP4P && mode[k] != P_SITE) {
        /* the AVX-512 TIP4P rows read only the records (and the list only kernel pairs, so no
         * other species' row reads this rank) */
        for (int c = 0; c < 3; c++) {
          V->pk4[m][c] = ff->centre[i][c];
          for (int s = 0; s < 4; s++) V->pk4[m][3 + 3 * s + c] = ff->dsite[oi + K->perm[s]][c];
        }
        if (V->pk4f)
          for (int c = 0; c < 12; c++) V->pk4f[m][c] = (float)V->pk4[m][3 + c];
        continue;
      }
      for (int c = 0; c < 3; c++) {
        V->c[m][c] = ff->centre[i][c];
        V->ax[m][c] = ff->axis[i][c];
      }
      if (V->pk && K->kind == K_DIPOLE) { /* the AVX-512 dipole rows read no sites */
        for (int c = 0; c < 3; c++) {
          V->pk[m][c] = ff->centre[i][c];
          V->pk[m][4 + c] = K->mu * ff->axis[i][c];
        }
        continue;
      }
      for (int a = 0; a < ns_i; a++)
        for (int c = 0; c < 3; c++) {
          V->site[om + a][c] = ff->site[oi + a][c];
          V->dsite[om + a][c] = ff->dsite[oi + a][c];
        }
    } /* implicit barrier */
    double(*fs)[3] = t == 0 ? ff->fs : f->fsbuf + (size_t)(t - 1) * (size_t)ns;
    double(*tq)[3] = t == 0 ? ff->tq : f->tqbuf + (size_t)(t - 1) * (size_t)n;
    double(*pfs)[3] = f->pfs + (size_t)t * (size_t)ns;
    double(*ptq)[3] = f->ptq + (size_t)t * (size_t)n;
    if (t > 0 && general) {
      memset(fs, 0, sizeof *fs * (size_t)ns);
      memset(tq, 0, sizeof *tq * (size_t)n);
    }
    /* the kernel buffers (pfs, ptq, pft, pft4) are zero here: allocated so, and the sums below
     * zero what they read; the thread's rows write ranks [tlo[t], thi[t]) only */
    double(*pft)[8] = f->pft ? f->pft + (size_t)t * (size_t)n : NULL;
    double(*pft4)[16] = f->pft4 ? f->pft4 + (size_t)t * (size_t)n : NULL;
    rl_acc *a = &f->acc[t];
    memset(a, 0, sizeof *a);
    a->fs = fs;
    a->tq = tq;
    a->site_virial = 1;
    a->quiet = 1;
    a->forces_only = out->forces_only;
    int st = RL_OK;
    for (int m = f->tlo[t]; m < f->tlo[t + 1] && !st && !a->bad; m++) {
      const int i = ord[m], k = ff->body_species[i];
      const fast_species *K = &f->sk[k];
      int fl = f->fstart[m + 1] - f->fstart[m];
      if (fl > 0)
        (a->forces_only ? K->row_fo : K->row)[mode[k]](ff, V, K, m, f->fnbr + f->fstart[m], fl,
                                                       pfs, ptq, pft, pft4, a);
      for (int q = f->gstart[m]; q < f->gstart[m + 1] && !st; q++)
        st = rl_ff_body_pair(ff, i, f->gnbr[q], a);
    }
    f->status[t] = st;
#ifdef _OPENMP /* -fopenmp-simd accepts the other directives without OpenMP, not this one */
#pragma omp barrier
#endif
    if (T > 1 && general) { /* add the other threads' buffers, in thread order */
#pragma omp for schedule(static)
      for (int s = 0; s < ns; s++)
        for (int u = 1; u < T; u++) {
          const double *b = f->fsbuf[(size_t)(u - 1) * (size_t)ns + (size_t)s];
          ff->fs[s][0] += b[0]; ff->fs[s][1] += b[1]; ff->fs[s][2] += b[2];
        }
#pragma omp for schedule(static)
      for (int i = 0; i < n; i++)
        for (int u = 1; u < T; u++) {
          const double *b = f->tqbuf[(size_t)(u - 1) * (size_t)n + (size_t)i];
          ff->tq[i][0] += b[0]; ff->tq[i][1] += b[1]; ff->tq[i][2] += b[2];
        }
    }
    /* the kernels' forces and torques back to body order, threads in order, each record zeroed
     * once read (for the next compute: one pass over the buffers instead of a memset and a
     * read, 2 % of a 64,000-dipole step); for the kernels that add the molecular virial
     * (tip4p_row), + sum d (x) F over their site forces, which the correction below subtracts
     * again */
    double cv[9] = {0};
    if (dip_only) {
#pragma omp for schedule(static)
      for (int m = 0; m < n; m++) {
        const int i = ord[m], oi = ff->body_site_off[i];
        for (int u = 0; u < T; u++) {
          if (m < f->tlo[u] || m >= f->thi[u]) continue; /* not written by thread u */
          double *q = f->pft[(size_t)u * (size_t)n + (size_t)m];
          for (int c = 0; c < 3; c++) {
            ff->fs[oi][c] += q[c];
            ff->tq[i][c] += q[4 + c];
          }
          for (int c = 0; c < 8; c++) q[c] = 0.0;
        }
      }
    } else
#pragma omp for schedule(static)
    for (int m = 0; m < n; m++) {
      const int i = ord[m], k = ff->body_species[i], ns_i = ff->sp_nsites[k];
      const int oi = ff->body_site_off[i], om = V->soff[m];
      const int mv = f->sk[k].kind == K_TIP4P && mode[k] != P_SITE; /* 4 sites */
      const int cvir = mv && !out->forces_only; /* their rows summed R (x) F */
      double F[4][3];                           /* cvir: kernel site forces */
      if (cvir) /* a loop, not an initialiser: GCC made that a `rep stos`, 2.5 % of a dipole step */
        for (int a = 0; a < 4; a++) F[a][0] = F[a][1] = F[a][2] = 0.0;
      for (int u = 0; u < T; u++) {
        if (m < f->tlo[u] || m >= f->thi[u]) continue; /* not written by thread u */
        double(*pf)[3] = f->pfs + (size_t)u * (size_t)ns + (size_t)om;
        double *pt = f->ptq[(size_t)u * (size_t)n + (size_t)m];
        for (int a = 0; a < ns_i; a++)
          for (int c = 0; c < 3; c++) {
            ff->fs[oi + a][c] += pf[a][c];
            if (cvir) F[a][c] += pf[a][c];
            pf[a][c] = 0.0;
          }
        for (int c = 0; c < 3; c++) {
          ff->tq[i][c] += pt[c];
          pt[c] = 0.0;
        }
        if (f->pft) { /* every rank's record is zeroed, whatever its kind and mode */
          double *q = f->pft[(size_t)u * (size_t)n + (size_t)m];
          if (f->sk[k].kind == K_DIPOLE) /* ns_i = 1 */
            for (int c = 0; c < 3; c++) {
              ff->fs[oi][c] += q[c];
              ff->tq[i][c] += q[4 + c];
            }
          for (int c = 0; c < 8; c++) q[c] = 0.0;
        }
        if (f->pft4) { /* record slot s: site perm[s] */
          double *q = f->pft4[(size_t)u * (size_t)n + (size_t)m];
          if (mv)
            for (int s = 0; s < 4; s++)
              for (int c = 0; c < 3; c++) {
                const int a = f->sk[k].perm[s];
                ff->fs[oi + a][c] += q[3 + 3 * s + c];
                if (cvir) F[a][c] += q[3 + 3 * s + c];
              }
          for (int c = 0; c < 16; c++) q[c] = 0.0;
        }
      }
      if (cvir)
        for (int a = 0; a < 4; a++)
          for (int x = 0; x < 3; x++)
            for (int y = 0; y < 3; y++) cv[3 * x + y] += ff->dsite[oi + a][x] * F[a][y];
    }
    for (int c = 0; c < 9; c++) f->acc[t].vir[c] += cv[c]; /* this thread's: read in order below */
  }
  int bad = 0;
  for (int t = 0; t < T; t++) {
    if (f->status[t] || f->acc[t].bad) bad = 1;
    out->lj += f->acc[t].lj;
    out->coul += f->acc[t].coul;
    out->dip += f->acc[t].dip;
    out->quad += f->acc[t].quad;
    for (int c = 0; c < 9; c++) out->vir[c] += f->acc[t].vir[c];
  }
  if (bad) return 1; /* the reference loop reruns and reports the overlap */
  if (dip_only || out->forces_only) return RL_OK; /* point dipoles: every d is zero */
  for (int s = 0; s < ns; s++) /* molecular virial: minus sum_sites d (x) F */
    for (int x = 0; x < 3; x++)
      for (int y = 0; y < 3; y++) out->vir[3 * x + y] -= ff->dsite[s][x] * ff->fs[s][y];
  return RL_OK;
}
