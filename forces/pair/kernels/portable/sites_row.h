/* The "charge-lj" rows, portable: LJ and charges on up to RL_FAST_MAXS sites, one omp simd loop
 * per term.  A template: include an electrostatics with charges (../elec/) first, then
 * RL_PORTABLE_SITES_ROWS(SET) defines the rows and their row set SET. */
#ifndef ROTLEAP_PAIR_PORTABLE_SITES_ROW_H
#define ROTLEAP_PAIR_PORTABLE_SITES_ROW_H

#include "../../rsqrt.h"
#include "../batch.h"
#include "../vdw_lj.h"

#if !RL_ELEC_CHARGES
#error "include an electrostatics with charges (kernels/elec/) before this template"
#endif

typedef struct {
  double fx, fy, fz, elj, ecoul, bad, w[6];
} term_sums;

/* One term (site a of body i, site b of every neighbour in the batch) over the batch.
 * WHAT: T_LJ, T_COUL or T_BOTH.  Branch-free: the cutoff and the padding are factors. */
RL_INLINE void term_loop(const int MODE, const int TRUNC, const int WHAT, const box_consts *B,
                         const rl_kelec E, const fast_term *T, const double *pa, batch *b,
                         term_sums *s)
{
  const double rc = B->rc, rsw = B->rsw, md2 = B->md2;
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
    if (WHAT != T_LJ) { /* the electrostatics (elec/), per qq */
      double fe, ue = rl_elec_qq(E, r2, rl_rsqrt(r2), &fe);
      double fr = qq * fe;
      double u = qq * ue;
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

/* One row of a site-kernel species ("charge-lj"): rank i against the ranks nbr[0..len) (same
 * species), one loop per term. */
RL_INLINE void sites_row(const int MODE, const int TRUNC, const rl_kparams *kp, const kview *V,
                         const fast_species *K, int i, const int *nbr, int len,
                         double (*fs)[3], rl_ksums *acc)
{
  const int ns = K->ns, oi = V->soff[i];
  const box_consts B = kp->B;
  const rl_kelec E = kp->E;
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
      if (T->what == T_LJ) term_loop(MODE, TRUNC, T_LJ, &B, E, T, pa, &b, &s);
      else if (T->what == T_COUL) term_loop(MODE, TRUNC, T_COUL, &B, E, T, pa, &b, &s);
      else term_loop(MODE, TRUNC, T_BOTH, &B, E, T, pa, &b, &s);
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

/* The rows of every separation mode and LJ truncation, named S (site images), H (the centres'
 * image shifted), M (molecule cutoff) + truncation, each compiled for AVX-512, AVX2 and
 * baseline x86-64 and picked at load time; and the row set SET of them. */
#define RL_SITES_ROW(NAME, MODE, TRUNC)                                                        \
  ROW_FN(NAME, sites_row(MODE, TRUNC, kp, V, K, i, nbr, len, fs, acc))
#define RL_PORTABLE_SITES_ROWS(SET, S, H, M) RL_ROWS_ALL_MODES(SET, RL_SITES_ROW, S, H, M)

#endif
