/* The TIP4P rows, portable: 1 LJ + 9 charge terms in one omp simd loop.  A template: include an
 * electrostatics with charges (../elec/) first, then RL_PORTABLE_TIP4P_ROWS(SET, S, H, M) defines
 * the rows and their row set SET. */
#ifndef ROTLEAP_PAIR_PORTABLE_TIP4P_ROW_H
#define ROTLEAP_PAIR_PORTABLE_TIP4P_ROW_H

#include "../../rsqrt.h"
#include "../batch.h"
#include "../vdw_lj.h"

#if !RL_ELEC_CHARGES
#error "include an electrostatics with charges (kernels/elec/) before this template"
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
RL_INLINE void tip4p_row(const int MODE, const int TRUNC, const rl_kparams *kp,
                         const kview *V, const fast_species *K, int i, const int *nbr, int len,
                         double (*fs)[3], rl_ksums *acc)
{
  const int oi = V->soff[i];
  const box_consts B = kp->B;
  const double rp2 = prune2(MODE, &B, K);
  const int img = needs_images(MODE, &B, rp2);
  const double rc = B.rc, rsw = B.rsw, md2 = B.md2;
  const rl_kelec E = kp->E;
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
        for (int q = 0; q < 3; q++) { /* the electrostatics (elec/) */
          double dx, dy, dz;
          sep(MODE, &B, a[1 + p][0], a[1 + p][1], a[1 + p][2], &b, 1 + q, k, &dx, &dy, &dz);
          double r2 = dx * dx + dy * dy + dz * dz;
          const double in = inside(MODE, &B, &b, k, r2);
          r2min = r2 < r2min ? r2 : r2min;
          /* (qq in) x: the reference's qq x times a 0/1 factor, bit for bit, one multiply less */
          const double qin = qq[p][q] * in;
          double fe, ue = rl_elec_qq(E, r2, rl_rsqrt(r2), &fe);
          const double fr = qin * fe;
          ecoul += qin * ue;
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

/* The rows of every separation mode and LJ truncation, named S, H, M (site images, the centres'
 * image shifted, molecule cutoff) + truncation, each compiled for AVX-512, AVX2 and baseline
 * x86-64 and picked at load time; and the row set SET of them. */
#define RL_TIP4P_ROW(NAME, MODE, TRUNC)                                                        \
  ROW_FN(NAME, tip4p_row(MODE, TRUNC, kp, V, K, i, nbr, len, fs, acc))
#define RL_PORTABLE_TIP4P_ROWS(SET, S, H, M) RL_ROWS_ALL_MODES(SET, RL_TIP4P_ROW, S, H, M)

#endif
