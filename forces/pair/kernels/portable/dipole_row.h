/* The Stockmayer rows, portable: LJ + point dipoles at the centre.  A template: include a
 * dipolar electrostatics (../elec/) first, then RL_PORTABLE_DIPOLE_ROWS(SET, R) defines the rows
 * R##0 .. R##3 (by LJ truncation) and their row set SET. */
#ifndef ROTLEAP_PAIR_PORTABLE_DIPOLE_ROW_H
#define ROTLEAP_PAIR_PORTABLE_DIPOLE_ROW_H

#include "../../rsqrt.h"
#include "../batch.h"
#include "../vdw_lj.h"

#if !RL_ELEC_DIPOLES
#error "include a dipolar electrostatics (kernels/elec/) before this template"
#endif

/* LJ + point dipoles, one site at the centre, so r = R, the centres' minimum image, for both
 * cutoff schemes; the dipole pair as the electrostatics gives it (rl_elec_dd: reaction field,
 * shifted force).  The portable rows (AVX2, baseline, ROTLEAP_NO_AVX512); dipole_row512 is the
 * same on AVX-512. */
RL_INLINE void dipole_row(const int TRUNC, const rl_kparams *kp,
                          const kview *V, const fast_species *K, int i, const int *nbr, int len,
                          double (*fs)[3], double (*tq)[3], rl_ksums *acc)
{
  const int oi = V->soff[i];
  const box_consts B = kp->B;
  const double rc = B.rc, rc2 = B.rc2, rsw = B.rsw, md2 = B.md2;
  const rl_kelec E = kp->E;
  const double mu = K->mu;
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
      /* LJ, then the dipoles' electrostatics (elec/) */
      const double mjx = b.m[0][k], mjy = b.m[1][k], mjz = b.m[2][k];
      double ir = rl_rsqrt(r2), ir2 = ir * ir;
      double frl, ul = lj_eval_ir2(TRUNC, C, rc, rsw, r2, ir2, &frl);
      const rl_dd d = rl_elec_dd(E, rx, ry, rz, r2, ir, mix, miy, miz, mjx, mjy, mjz);
      double fx = frl * rx, fy = frl * ry, fz = frl * rz; /* site_pair: LJ, then the dipoles */
      fx += d.fx; fy += d.fy; fz += d.fz;
      fx *= in; fy *= in; fz *= in;
      const double gix = d.gix * in, giy = d.giy * in, giz = d.giz * in;
      const double gjx = d.gjx * in, gjy = d.gjy * in, gjz = d.gjz * in;
      const double ud = d.u;
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

/* The rows of every LJ truncation (the same for every separation mode: r = R), each compiled
 * for AVX-512, AVX2 and baseline x86-64 and picked at load time; and the row set SET. */
#define RL_DIPOLE_ROW(NAME, MODE, TRUNC)                                                       \
  ROW_FN(NAME, dipole_row(TRUNC, kp, V, K, i, nbr, len, fs, tq, acc))
#define RL_PORTABLE_DIPOLE_ROWS(SET, R)                                                        \
  RL_ROWS_MODE(RL_DIPOLE_ROW, R, P_MOL)                                                        \
  const rl_row_set SET = {RL_SET_MODES(R, R, R), {{0}}};

#endif
