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
 * Layout: a molecule-pair Verlet list in CSR form (row i: the j > i within rlist), split at
 * build time into kernel rows and reference rows.  A kernel walks a row in batches of RL_FAST_B
 * neighbours: it copies their sites into structure-of-arrays buffers, then runs one
 * branch-free loop per term over the batch (`omp simd`, masks as selects), then scatters the
 * forces.  Each term is the reference arithmetic (same formulas, same operation order per site
 * pair); the sums run in another order, so results agree to round-off.
 *
 * Threads: rows are split into contiguous ranges of nearly equal cost, one per thread; each
 * thread adds into its own site-force and torque buffers; the buffers and the per-thread energy
 * and virial sums are added in thread order.  Fixed thread count: reproducible bit for bit.
 *
 * Virial: kernels add r (x) f with r the site separation; afterwards W = sum r (x) f -
 * sum_sites d_a (x) F_a (d_a = site - centre, F_a = total site force), which equals the
 * reference sum of R (x) f with R = r - d_a + d_b. */
#include "forcefield_impl.h"
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

/* nearbyint(x) for |x| < 2^51 in the default rounding mode, written so it vectorises:
 * x + 1.5 2^52 has unit spacing, so the sum rounds x to the nearest integer (ties to even). */
#define RL_RND(x) (((x) + 6755399441055744.0) - 6755399441055744.0)

enum { K_NONE = 0, K_SITES = 1, K_DIPOLE = 2 };
enum { T_LJ = 0, T_COUL = 1, T_BOTH = 2 };

typedef struct {
  int a, b, what;
  double qq;                     /* kc q_a q_b                                          */
  double c6, c12, eshift, fshift; /* LJ (rl_lj_coef)                                    */
} fast_term;

typedef struct fast_species fast_species;
typedef void (*row_fn)(const rl_forcefield *ff, const fast_species *K, int i, const int *nbr,
                       int len, double (*fs)[3], double (*tq)[3], rl_acc *acc);

struct fast_species {
  int kind, ns, nterms;
  fast_term t[RL_FAST_MAXT];
  double mu;                     /* stockmayer: dipole moment                          */
  row_fn row;
};

typedef struct {
  int *f, *g;                    /* kernel / reference neighbours of this thread's rows */
  long fcap, gcap, fn, gn;
} thread_rows;

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
  thread_rows *tr;               /* [nthreads]                                          */
  int *cell_of, *cell_start, *cell_body; /* cell list workspace                          */
  int ncell_cap;
  double (*fsbuf)[3];            /* [(nthreads - 1) nsites]                             */
  double (*tqbuf)[3];            /* [(nthreads - 1) n]                                  */
  rl_acc *acc;                   /* [nthreads]                                          */
  int *status;                   /* [nthreads]                                          */
};

#ifndef _OPENMP
static int omp_get_max_threads(void) { return 1; }
static int omp_get_thread_num(void) { return 0; }
#endif

/* ------------------------------------------------------------------------ LJ and RF */

RL_INLINE double lj_eval(const int trunc, const fast_term *T, double rc, double rsw, double r2,
                         double *fr)
{ /* rl_lj_pair, branch-free */
  double ir2 = 1.0 / r2, ir6 = ir2 * ir2 * ir2;
  double u = (T->c12 * ir6 - T->c6) * ir6;
  double f = (12.0 * T->c12 * ir6 - 6.0 * T->c6) * ir6 * ir2;
  if (trunc == RL_LJ_SHIFTED) {
    u -= T->eshift;
  } else if (trunc == RL_LJ_SHIFTED_FORCE) {
    double r = sqrt(r2);
    u -= T->eshift + (r - rc) * T->fshift;
    f += T->fshift / r;
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

/* ------------------------------------------------------------------------ site kernels */

typedef struct {
  double L[3], iL[3], rc, rc2, rsw, md2, krf, crf;
} box_consts;

typedef struct {
  double fx, fy, fz, elj, ecoul, bad, w[6];
} term_sums;

/* One term (site a of body i, site b of every neighbour in the batch) over the batch.
 * WHAT: T_LJ, T_COUL or T_BOTH.  Branch-free: the cutoff and the other masks are selects. */
RL_INLINE void term_loop(const int SCHEME, const int TRUNC, const int WHAT, const box_consts *B,
                         const fast_term *T, const double *pa, double (*xb)[RL_FAST_B],
                         double (*fb)[RL_FAST_B], double (*Rb)[RL_FAST_B], const double *inb,
                         int nb, term_sums *s)
{
  const double Lx = B->L[0], Ly = B->L[1], Lz = B->L[2];
  const double iLx = B->iL[0], iLy = B->iL[1], iLz = B->iL[2];
  const double rc = B->rc, rc2 = B->rc2, rsw = B->rsw, md2 = B->md2, krf = B->krf, crf = B->crf;
  const double ax = pa[0], ay = pa[1], az = pa[2], qq = T->qq;
  double fax = 0.0, fay = 0.0, faz = 0.0, elj = 0.0, ecoul = 0.0, bad = 0.0;
  double w0 = 0.0, w1 = 0.0, w2 = 0.0, w3 = 0.0, w4 = 0.0, w5 = 0.0;
  double *fbx = fb[0], *fby = fb[1], *fbz = fb[2];
  const double *bx = xb[0], *by = xb[1], *bz = xb[2];
#pragma omp simd reduction(+ : fax, fay, faz, elj, ecoul, bad, w0, w1, w2, w3, w4, w5)
  for (int k = 0; k < nb; k++) {
    double dx, dy, dz;
    if (SCHEME == RL_CUTOFF_SITE) {
      dx = ax - bx[k]; dy = ay - by[k]; dz = az - bz[k];
      dx -= Lx * RL_RND(dx * iLx);
      dy -= Ly * RL_RND(dy * iLy);
      dz -= Lz * RL_RND(dz * iLz);
    } else { /* r = R + d_a - d_b */
      dx = Rb[0][k] + ax - bx[k]; dy = Rb[1][k] + ay - by[k]; dz = Rb[2][k] + az - bz[k];
    }
    double r2 = dx * dx + dy * dy + dz * dz;
    const int in = SCHEME == RL_CUTOFF_SITE ? r2 < rc2 : inb[k] != 0.0;
    bad += in && r2 < md2 ? 1.0 : 0.0;
    double fx = 0.0, fy = 0.0, fz = 0.0;
    if (WHAT != T_COUL) {
      double fr, u = lj_eval(TRUNC, T, rc, rsw, r2, &fr);
      fr = in ? fr : 0.0;
      elj += in ? u : 0.0;
      fx += fr * dx; fy += fr * dy; fz += fr * dz;
    }
    if (WHAT != T_LJ) { /* rl_coulomb_rf_pair */
      double ir = 1.0 / sqrt(r2);
      double fr = qq * (ir * ir * ir - 2.0 * krf);
      double u = qq * (ir + krf * r2 - crf);
      fr = in ? fr : 0.0;
      ecoul += in ? u : 0.0;
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

/* One row of a site-kernel species: body i against nbr[0..len) (same species).
 * SCHEME: RL_CUTOFF_SITE or RL_CUTOFF_MOLECULE; TRUNC: the LJ truncation. */
RL_INLINE void sites_row(const int SCHEME, const int TRUNC, const rl_forcefield *ff,
                         const fast_species *K, int i, const int *nbr, int len,
                         double (*fs)[3], rl_acc *acc)
{
  const int ns = K->ns;
  const int oi = ff->body_site_off[i];
  const double Lx = ff->box.L[0], Ly = ff->box.L[1], Lz = ff->box.L[2];
  const double iLx = ff->box.invL[0], iLy = ff->box.invL[1], iLz = ff->box.invL[2];
  const double rc = ff->p.cutoff, rc2 = rc * rc, rsw = ff->p.r_switch;
  const double md2 = ff->min_distance * ff->min_distance;
  const double krf = ff->rf.krf, crf = ff->rf.crf;
  double xs[RL_FAST_MAXS][3][RL_FAST_B], fj[RL_FAST_MAXS][3][RL_FAST_B];
  double Rb[3][RL_FAST_B], inb[RL_FAST_B];
  double fi[RL_FAST_MAXS][3];
  memset(fi, 0, sizeof fi);
  double elj = 0.0, ecoul = 0.0, w0 = 0.0, w1 = 0.0, w2 = 0.0, w3 = 0.0, w4 = 0.0, w5 = 0.0;
  double bad = 0.0;
  const box_consts bx = {{Lx, Ly, Lz}, {iLx, iLy, iLz}, rc, rc2, rsw, md2, krf, crf};
  for (int base = 0; base < len; base += RL_FAST_B) {
    int nb = len - base < RL_FAST_B ? len - base : RL_FAST_B;
    for (int k = 0; k < nb; k++) { /* gather */
      int j = nbr[base + k], oj = ff->body_site_off[j];
      for (int b = 0; b < ns; b++)
        for (int c = 0; c < 3; c++) {
          xs[b][c][k] = SCHEME == RL_CUTOFF_SITE ? ff->site[oj + b][c] : ff->dsite[oj + b][c];
          fj[b][c][k] = 0.0;
        }
      if (SCHEME == RL_CUTOFF_MOLECULE)
        for (int c = 0; c < 3; c++) Rb[c][k] = ff->centre[i][c] - ff->centre[j][c];
    }
    if (SCHEME == RL_CUTOFF_MOLECULE) {
#pragma omp simd
      for (int k = 0; k < nb; k++) {
        double X = Rb[0][k], Y = Rb[1][k], Z = Rb[2][k];
        X -= Lx * RL_RND(X * iLx);
        Y -= Ly * RL_RND(Y * iLy);
        Z -= Lz * RL_RND(Z * iLz);
        Rb[0][k] = X; Rb[1][k] = Y; Rb[2][k] = Z;
        inb[k] = X * X + Y * Y + Z * Z < rc2 ? 1.0 : 0.0;
      }
    }
    for (int t = 0; t < K->nterms; t++) {
      const fast_term *T = &K->t[t];
      const double *pa = SCHEME == RL_CUTOFF_SITE ? ff->site[oi + T->a] : ff->dsite[oi + T->a];
      term_sums s = {0};
      if (T->what == T_LJ) term_loop(SCHEME, TRUNC, T_LJ, &bx, T, pa, xs[T->b], fj[T->b], Rb, inb, nb, &s);
      else if (T->what == T_COUL) term_loop(SCHEME, TRUNC, T_COUL, &bx, T, pa, xs[T->b], fj[T->b], Rb, inb, nb, &s);
      else term_loop(SCHEME, TRUNC, T_BOTH, &bx, T, pa, xs[T->b], fj[T->b], Rb, inb, nb, &s);
      fi[T->a][0] += s.fx; fi[T->a][1] += s.fy; fi[T->a][2] += s.fz;
      elj += s.elj; ecoul += s.ecoul; bad += s.bad;
      w0 += s.w[0]; w1 += s.w[1]; w2 += s.w[2]; w3 += s.w[3]; w4 += s.w[4]; w5 += s.w[5];
    }
    for (int k = 0; k < nb; k++) { /* scatter */
      int oj = ff->body_site_off[nbr[base + k]];
      for (int b = 0; b < ns; b++)
        for (int c = 0; c < 3; c++) fs[oj + b][c] += fj[b][c][k];
    }
  }
  for (int a = 0; a < ns; a++)
    for (int c = 0; c < 3; c++) fs[oi + a][c] += fi[a][c];
  acc->lj += elj;
  acc->coul += ecoul;
  acc->vir[0] += w0; acc->vir[1] += w1; acc->vir[2] += w2;
  acc->vir[3] += w1; acc->vir[4] += w3; acc->vir[5] += w4;
  acc->vir[6] += w2; acc->vir[7] += w4; acc->vir[8] += w5;
  acc->bad |= bad != 0.0;
}

/* ------------------------------------------------------------------- Stockmayer kernel */

/* LJ + point dipoles, one site at the centre (r = the centres' minimum image for both cutoff
 * schemes).  DSF: 0 reaction field (rl_dipole_dipole_rf), 1 shifted force (_sf). */
RL_INLINE void dipole_row(const int DSF, const int TRUNC, const rl_forcefield *ff,
                          const fast_species *K, int i, const int *nbr, int len,
                          double (*fs)[3], double (*tq)[3], rl_acc *acc)
{
  const int oi = ff->body_site_off[i];
  const double Lx = ff->box.L[0], Ly = ff->box.L[1], Lz = ff->box.L[2];
  const double iLx = ff->box.invL[0], iLy = ff->box.invL[1], iLz = ff->box.invL[2];
  const double rc = ff->p.cutoff, rc2 = rc * rc, rsw = ff->p.r_switch;
  const double md2 = ff->min_distance * ff->min_distance;
  const double kc = ff->kc, krf = ff->rf.krf, mu = K->mu;
  const fast_term *T = &K->t[0];
  const double cx = ff->site[oi][0], cy = ff->site[oi][1], cz = ff->site[oi][2];
  const double mix = mu * ff->axis[i][0], miy = mu * ff->axis[i][1], miz = mu * ff->axis[i][2];
  double xb[3][RL_FAST_B], mj[3][RL_FAST_B], fj[3][RL_FAST_B], tj[3][RL_FAST_B];
  double fix = 0.0, fiy = 0.0, fiz = 0.0, tix = 0.0, tiy = 0.0, tiz = 0.0;
  double elj = 0.0, edip = 0.0;
  double w0 = 0, w1 = 0, w2 = 0, w3 = 0, w4 = 0, w5 = 0, w6 = 0, w7 = 0, w8 = 0;
  double bad = 0.0;
  for (int base = 0; base < len; base += RL_FAST_B) {
    int nb = len - base < RL_FAST_B ? len - base : RL_FAST_B;
    for (int k = 0; k < nb; k++) {
      int j = nbr[base + k], oj = ff->body_site_off[j];
      for (int c = 0; c < 3; c++) {
        xb[c][k] = ff->site[oj][c];
        mj[c][k] = mu * ff->axis[j][c];
      }
    }
#pragma omp simd reduction(+ : fix, fiy, fiz, tix, tiy, tiz, elj, edip, w0, w1, w2, w3, w4, w5, w6, w7, w8, bad)
    for (int k = 0; k < nb; k++) {
      double rx = cx - xb[0][k], ry = cy - xb[1][k], rz = cz - xb[2][k];
      rx -= Lx * RL_RND(rx * iLx);
      ry -= Ly * RL_RND(ry * iLy);
      rz -= Lz * RL_RND(rz * iLz);
      double r2 = rx * rx + ry * ry + rz * rz;
      const int in = r2 < rc2;
      bad += in && r2 < md2 ? 1.0 : 0.0;
      double frl, ul = lj_eval(TRUNC, T, rc, rsw, r2, &frl);
      /* dd_plain (dipole.c) */
      const double mjx = mj[0][k], mjy = mj[1][k], mjz = mj[2][k];
      double ir2 = 1.0 / r2, ir = sqrt(ir2), ir3 = ir * ir2, ir5 = ir3 * ir2;
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
      fx = in ? fx : 0.0; fy = in ? fy : 0.0; fz = in ? fz : 0.0;
      gix = in ? gix : 0.0; giy = in ? giy : 0.0; giz = in ? giz : 0.0;
      gjx = in ? gjx : 0.0; gjy = in ? gjy : 0.0; gjz = in ? gjz : 0.0;
      elj += in ? ul : 0.0;
      edip += in ? ud : 0.0;
      fix += fx; fiy += fy; fiz += fz;
      fj[0][k] = -fx; fj[1][k] = -fy; fj[2][k] = -fz;
      tix -= miy * giz - miz * giy; /* torque -mu x g */
      tiy -= miz * gix - mix * giz;
      tiz -= mix * giy - miy * gix;
      tj[0][k] = -(mjy * gjz - mjz * gjy);
      tj[1][k] = -(mjz * gjx - mjx * gjz);
      tj[2][k] = -(mjx * gjy - mjy * gjx);
      w0 += rx * fx; w1 += rx * fy; w2 += rx * fz;
      w3 += ry * fx; w4 += ry * fy; w5 += ry * fz;
      w6 += rz * fx; w7 += rz * fy; w8 += rz * fz;
    }
    for (int k = 0; k < nb; k++) {
      int j = nbr[base + k], oj = ff->body_site_off[j];
      for (int c = 0; c < 3; c++) {
        fs[oj][c] += fj[c][k];
        tq[j][c] += tj[c][k];
      }
    }
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

/* Instances: one function per (scheme, truncation) and (dipole method, truncation), each
 * compiled for AVX-512, AVX2 and baseline x86-64 and picked at load time. */
#define SITES_FN(NAME, SCHEME, TRUNC)                                                          \
  RL_CLONES static void NAME(const rl_forcefield *ff, const fast_species *K, int i,            \
                             const int *nbr, int len, double (*fs)[3], double (*tq)[3],        \
                             rl_acc *acc)                                                      \
  {                                                                                            \
    (void)tq;                                                                                  \
    sites_row(SCHEME, TRUNC, ff, K, i, nbr, len, fs, acc);                                     \
  }
SITES_FN(sites_s0, RL_CUTOFF_SITE, RL_LJ_PLAIN)
SITES_FN(sites_s1, RL_CUTOFF_SITE, RL_LJ_SHIFTED)
SITES_FN(sites_s2, RL_CUTOFF_SITE, RL_LJ_SHIFTED_FORCE)
SITES_FN(sites_s3, RL_CUTOFF_SITE, RL_LJ_SWITCHED)
SITES_FN(sites_m0, RL_CUTOFF_MOLECULE, RL_LJ_PLAIN)
SITES_FN(sites_m1, RL_CUTOFF_MOLECULE, RL_LJ_SHIFTED)
SITES_FN(sites_m2, RL_CUTOFF_MOLECULE, RL_LJ_SHIFTED_FORCE)
SITES_FN(sites_m3, RL_CUTOFF_MOLECULE, RL_LJ_SWITCHED)
#define DIPOLE_FN(NAME, DSF, TRUNC)                                                            \
  RL_CLONES static void NAME(const rl_forcefield *ff, const fast_species *K, int i,            \
                             const int *nbr, int len, double (*fs)[3], double (*tq)[3],        \
                             rl_acc *acc)                                                      \
  {                                                                                            \
    dipole_row(DSF, TRUNC, ff, K, i, nbr, len, fs, tq, acc);                                   \
  }
DIPOLE_FN(dip_r0, 0, RL_LJ_PLAIN)
DIPOLE_FN(dip_r1, 0, RL_LJ_SHIFTED)
DIPOLE_FN(dip_r2, 0, RL_LJ_SHIFTED_FORCE)
DIPOLE_FN(dip_r3, 0, RL_LJ_SWITCHED)
DIPOLE_FN(dip_f0, 1, RL_LJ_PLAIN)
DIPOLE_FN(dip_f1, 1, RL_LJ_SHIFTED)
DIPOLE_FN(dip_f2, 1, RL_LJ_SHIFTED_FORCE)
DIPOLE_FN(dip_f3, 1, RL_LJ_SWITCHED)

static const row_fn sites_fns[2][4] = {{sites_s0, sites_s1, sites_s2, sites_s3},
                                       {sites_m0, sites_m1, sites_m2, sites_m3}};
static const row_fn dipole_fns[2][4] = {{dip_r0, dip_r1, dip_r2, dip_r3},
                                        {dip_f0, dip_f1, dip_f2, dip_f3}};

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
static void classify(const rl_forcefield *ff, int k, fast_species *K)
{
  memset(K, 0, sizeof *K);
  int ns = ff->sp_nsites[k], o = ff->type_off[k];
  if (ns < 1 || ns > RL_FAST_MAXS || ff->sp_count[k] < 2) return;
  int ndip = 0, nq = 0, nlj = 0, nquad = 0;
  for (int a = 0; a < ns; a++) {
    ndip += ff->mu[o + a] != 0.0;
    nquad += ff->Q[o + a] != 0.0;
    nq += ff->q[o + a] != 0.0;
  }
  for (int a = 0; a < ns; a++)
    for (int b = 0; b < ns; b++) nlj += ff->lj[(o + a) * ff->ntypes + o + b].epsilon != 0.0;
  if (nquad) return;
  K->ns = ns;
  if (ndip) { /* stockmayer: one site at the centre, LJ + dipole, no charge */
    if (ns != 1 || nq || ff->sp_extent[k] != 0.0) { K->ns = 0; return; }
    K->kind = K_DIPOLE;
    K->mu = ff->mu[o];
    K->nterms = 1;
    term_set(ff, o, o, &K->t[0]);
    K->row = dipole_fns[ff->p.dipole_method == RL_DIPOLE_SF][ff->p.lj_truncation];
    return;
  }
  K->kind = K_SITES;
  for (int a = 0; a < ns; a++)
    for (int b = 0; b < ns; b++) {
      int lj = ff->lj[(o + a) * ff->ntypes + o + b].epsilon != 0.0;
      int qq = ff->q[o + a] != 0.0 && ff->q[o + b] != 0.0;
      if (!lj && !qq) continue;
      fast_term *T = &K->t[K->nterms++];
      T->a = a;
      T->b = b;
      T->what = lj && qq ? T_BOTH : lj ? T_LJ : T_COUL;
      term_set(ff, o + a, o + b, T);
    }
  K->row = sites_fns[ff->p.scheme == RL_CUTOFF_MOLECULE][ff->p.lj_truncation];
  (void)nlj;
}

static const char *species_name(const rl_forcefield *ff, int k, const fast_species *K)
{
  if (K->kind == K_DIPOLE) return "stockmayer";
  if (K->kind != K_SITES) return NULL;
  (void)ff;
  (void)k;
  int lj = 0, q = 0;
  for (int t = 0; t < K->nterms; t++) {
    lj += K->t[t].what == T_LJ;
    q += K->t[t].what == T_COUL;
  }
  if (K->ns == 4 && K->nterms == 10 && lj == 1 && q == 9) return "tip4p";
  return "charge-lj";
}

void rl_ff_fast_free(rl_ff_fast *f)
{
  if (!f) return;
  free(f->sk);
  rl_nlist_free(f->chk);
  free(f->fstart); free(f->gstart); free(f->fnbr); free(f->gnbr);
  free(f->tlo);
  if (f->tr)
    for (int t = 0; t < f->nthreads; t++) { free(f->tr[t].f); free(f->tr[t].g); }
  free(f->tr);
  free(f->cell_of); free(f->cell_start); free(f->cell_body);
  free(f->fsbuf); free(f->tqbuf);
  free(f->acc);
  free(f->status);
  free(f);
}

int rl_ff_fast_setup(rl_forcefield *ff)
{
  long builds = ff->fast ? rl_ff_fast_builds(ff->fast) : 0;
  rl_ff_fast_free(ff->fast);
  ff->fast = NULL;
  if (ff->p.kernel == RL_KERNEL_GENERAL || !ff->p.neighbor_list) return RL_OK;
  rl_ff_fast *f = calloc(1, sizeof *f);
  if (!f) return rl_error(RL_ENOMEM, "forcefield: out of memory");
  /* 0: OMP_NUM_THREADS if set, else one thread: threads are asked for, not assumed (as in
   * LAMMPS); on a shared 2-core machine two spinning threads ran 10x slower than one */
  const char *env = getenv("OMP_NUM_THREADS");
  int T = ff->p.threads > 0 ? ff->p.threads : env && *env ? omp_get_max_threads() : 1;
#ifndef _OPENMP
  T = 1;
#endif
  if (T < 1) T = 1;
  f->nthreads = T;
  int n = ff->n;
  f->sk = calloc((size_t)ff->nspecies, sizeof *f->sk);
  f->chk = rl_nlist_alloc(ff->skin);
  f->fstart = calloc((size_t)n + 1, sizeof(int));
  f->gstart = calloc((size_t)n + 1, sizeof(int));
  f->tlo = calloc((size_t)T + 1, sizeof(int));
  f->tr = calloc((size_t)T, sizeof *f->tr);
  f->acc = calloc((size_t)T, sizeof *f->acc);
  f->status = calloc((size_t)T, sizeof *f->status);
  f->cell_of = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  f->cell_body = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  if (T > 1) {
    f->fsbuf = malloc(sizeof *f->fsbuf * (size_t)(T - 1) * (size_t)(ff->nsites > 0 ? ff->nsites : 1));
    f->tqbuf = malloc(sizeof *f->tqbuf * (size_t)(T - 1) * (size_t)(n > 0 ? n : 1));
  }
  if (!f->sk || !f->chk || !f->fstart || !f->gstart || !f->tlo || !f->tr || !f->acc ||
      !f->status || !f->cell_of || !f->cell_body || (T > 1 && (!f->fsbuf || !f->tqbuf))) {
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
  for (int k = 0; k < ff->nspecies; k++) {
    classify(ff, k, &f->sk[k]);
    if (ff->sp_count[k] == 0 || ff->sp_nsites[k] == 0) continue;
    const char *nm = species_name(ff, k, &f->sk[k]);
    if (!nm) { general = 1; continue; }
    if (!strstr(f->namebuf, nm)) {
      int w = snprintf(p, left, "%s%s", used ? "+" : "", nm);
      if (w > 0 && (size_t)w < left) { p += w; left -= (size_t)w; }
      used = 1;
    }
  }
  if (nonempty > 1) general = 1; /* pairs of different species */
  if (general) snprintf(p, left, "%s", used ? "+general" : "general");
  f->name = f->namebuf;
  ff->fast = f;
  return RL_OK;
}

const char *rl_ff_fast_name(const rl_ff_fast *f) { return f->name; }
int rl_ff_fast_threads(const rl_ff_fast *f) { return f->nthreads; }
long rl_ff_fast_builds(const rl_ff_fast *f) { return f ? f->chk->builds : 0; }

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

static int build(rl_forcefield *ff)
{
  rl_ff_fast *f = ff->fast;
  const int n = ff->n, T = f->nthreads;
  const rl_box *box = &ff->box;
  const double rl = ff->rlist, rl2 = rl * rl;
  int nc[3];
  for (int c = 0; c < 3; c++) {
    double q = floor(box->L[c] / rl);
    nc[c] = q > 256.0 ? 256 : (int)q;
  }
  const int cells = nc[0] >= 3 && nc[1] >= 3 && nc[2] >= 3;
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
  /* rows: thread t scans i in [n t / T, n (t+1) / T); row lengths go to fstart/gstart[i+1] */
  int fail = 0;
#pragma omp parallel num_threads(T) reduction(| : fail)
  {
    int t = omp_get_thread_num();
    thread_rows *tr = &f->tr[t];
    tr->fn = tr->gn = 0;
    int i0 = (int)((long)n * t / T), i1 = (int)((long)n * (t + 1) / T);
    for (int i = i0; i < i1 && !fail; i++) {
      int ki = ff->body_species[i];
      int fast_i = f->sk[ki].kind != K_NONE;
      long f0 = tr->fn, g0 = tr->gn;
      const double *ri = ff->centre[i];
      if (ff->sp_nsites[ki] > 0) {
        if (cells) {
          int id = f->cell_of[i];
          int cx = id % nc[0], cy = (id / nc[0]) % nc[1], cz = id / (nc[0] * nc[1]);
          for (int dz = -1; dz <= 1 && !fail; dz++)
            for (int dy = -1; dy <= 1 && !fail; dy++)
              for (int dx = -1; dx <= 1 && !fail; dx++) {
                int x = (cx + dx + nc[0]) % nc[0], y = (cy + dy + nc[1]) % nc[1],
                    z = (cz + dz + nc[2]) % nc[2];
                int cc = (z * nc[1] + y) * nc[0] + x;
                for (int m = f->cell_start[cc]; m < f->cell_start[cc + 1]; m++) {
                  int j = f->cell_body[m];
                  if (j <= i || ff->sp_nsites[ff->body_species[j]] == 0) continue;
                  double d[3] = {ri[0] - ff->centre[j][0], ri[1] - ff->centre[j][1],
                                 ri[2] - ff->centre[j][2]};
                  rl_box_minimum_image(box, d);
                  if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] >= rl2) continue;
                  if (fast_i && ff->body_species[j] == ki) fail |= push(&tr->f, &tr->fcap, &tr->fn, j);
                  else fail |= push(&tr->g, &tr->gcap, &tr->gn, j);
                }
              }
        } else {
          for (int j = i + 1; j < n && !fail; j++) {
            if (ff->sp_nsites[ff->body_species[j]] == 0) continue;
            double d[3] = {ri[0] - ff->centre[j][0], ri[1] - ff->centre[j][1],
                           ri[2] - ff->centre[j][2]};
            rl_box_minimum_image(box, d);
            if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] >= rl2) continue;
            if (fast_i && ff->body_species[j] == ki) fail |= push(&tr->f, &tr->fcap, &tr->fn, j);
            else fail |= push(&tr->g, &tr->gcap, &tr->gn, j);
          }
        }
      }
      f->fstart[i + 1] = (int)(tr->fn - f0);
      f->gstart[i + 1] = (int)(tr->gn - g0);
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
  for (int t = 0; t < T; t++) {
    int i0 = (int)((long)n * t / T);
    if (f->tr[t].fn) memcpy(f->fnbr + f->fstart[i0], f->tr[t].f, sizeof(int) * (size_t)f->tr[t].fn);
    if (f->tr[t].gn) memcpy(f->gnbr + f->gstart[i0], f->tr[t].g, sizeof(int) * (size_t)f->tr[t].gn);
  }
  /* compute ranges: equal shares of cost (kernel terms per pair; 16 for a reference pair) */
  double total = 0.0;
  for (int i = 0; i < n; i++) {
    const fast_species *K = &f->sk[ff->body_species[i]];
    total += (double)(f->fstart[i + 1] - f->fstart[i]) * (K->kind == K_DIPOLE ? 4 : K->nterms + 2) +
             16.0 * (f->gstart[i + 1] - f->gstart[i]);
  }
  double run = 0.0;
  int t = 1;
  f->tlo[0] = 0;
  for (int i = 0; i < n && t < T; i++) {
    const fast_species *K = &f->sk[ff->body_species[i]];
    run += (double)(f->fstart[i + 1] - f->fstart[i]) * (K->kind == K_DIPOLE ? 4 : K->nterms + 2) +
           16.0 * (f->gstart[i + 1] - f->gstart[i]);
    while (t < T && run >= total * t / T) f->tlo[t++] = i + 1;
  }
  while (t <= T) f->tlo[t++] = n;
  /* positions at this build, for the rebuild test */
  rl_nlist *chk = f->chk;
  if (chk->n != n || chk->nsites != ff->nsites || !chk->r0) {
    double(*r0)[3] = realloc(chk->r0, sizeof *r0 * (size_t)(n > 0 ? n : 1));
    if (r0) chk->r0 = r0;
    double(*s0)[3] = realloc(chk->s0, sizeof *s0 * (size_t)(ff->nsites > 0 ? ff->nsites : 1));
    if (s0) chk->s0 = s0;
    if (!r0 || !s0) return rl_error(RL_ENOMEM, "neighbour list: out of memory for %d bodies", n);
  }
  if (n > 0) memcpy(chk->r0, ff->centre, sizeof *chk->r0 * (size_t)n);
  if (ff->nsites > 0) memcpy(chk->s0, ff->site, sizeof *chk->s0 * (size_t)ff->nsites);
  chk->n = n;
  chk->nsites = ff->nsites;
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
  for (int i = 0; i < n; i++)
    for (int c = 0; c < 3; c++)
      if (fabs(ff->centre[i][c]) * ff->box.invL[c] > 1e12) return 1;
  if (rl_nlist_needs_rebuild(f->chk, &ff->box, n, (const double(*)[3])ff->centre, ns,
                             (const double(*)[3])ff->site, NULL) ||
      f->chk->rlist != ff->rlist) {
    int st = build(ff);
    if (st) return st;
  }
#pragma omp parallel num_threads(T)
  {
    int t = omp_get_thread_num();
    double(*fs)[3] = t == 0 ? ff->fs : f->fsbuf + (size_t)(t - 1) * (size_t)ns;
    double(*tq)[3] = t == 0 ? ff->tq : f->tqbuf + (size_t)(t - 1) * (size_t)n;
    if (t > 0) {
      memset(fs, 0, sizeof *fs * (size_t)ns);
      memset(tq, 0, sizeof *tq * (size_t)n);
    }
    rl_acc *a = &f->acc[t];
    memset(a, 0, sizeof *a);
    a->fs = fs;
    a->tq = tq;
    a->site_virial = 1;
    a->quiet = 1;
    int st = RL_OK;
    for (int i = f->tlo[t]; i < f->tlo[t + 1] && !st && !a->bad; i++) {
      const fast_species *K = &f->sk[ff->body_species[i]];
      int fl = f->fstart[i + 1] - f->fstart[i];
      if (fl > 0) K->row(ff, K, i, f->fnbr + f->fstart[i], fl, fs, tq, a);
      for (int m = f->gstart[i]; m < f->gstart[i + 1] && !st; m++)
        st = rl_ff_body_pair(ff, i, f->gnbr[m], a);
    }
    f->status[t] = st;
#pragma omp barrier
    if (T > 1) { /* add the other threads' buffers, in thread order */
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
  for (int s = 0; s < ns; s++) /* molecular virial: minus sum_sites d (x) F */
    for (int x = 0; x < 3; x++)
      for (int y = 0; y < 3; y++) out->vir[3 * x + y] -= ff->dsite[s][x] * ff->fs[s][y];
  return RL_OK;
}
