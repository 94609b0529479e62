/* The Stockmayer rows on AVX2: a template.  Include a dipolar electrostatics (../elec/) first;
 * RL_AVX2_DIPOLE_ROWS(SET, X, O) then defines the rows and their row set. */
#ifndef ROTLEAP_PAIR_AVX2_DIPOLE_ROW_H
#define ROTLEAP_PAIR_AVX2_DIPOLE_ROW_H

#include "../elec/elec.h"
#include "simd256.h"

#if !RL_ELEC_DIPOLES
#error "include a dipolar electrostatics (kernels/elec/) before this template"
#endif

#if RL_X512
/* dipole_row512 on AVX2: the neighbours within the cutoff from fill256 (records V->pk:
 * centre, 0, mu axis, 0), four at a time; the terms as dip_pairs8. */
RL_T256 RL_INLINE void dipole_row256(const int EV, const int TRUNC,
                                     const rl_kparams *kp, const kview *V,
                                     const fast_species *K, int i, const int *nbr, int len,
                                     double (*ft)[8], rl_ksums *acc)
{
#define V1(a) _mm256_set1_pd(a)
  const box_consts B = kp->B;
  const lj_consts C = lj_of(&K->t[0]);
  const rl_kelec E = kp->E;
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
      /* the dipoles' electrostatics (elec/), regrouped as in dip_pairs8 */
      const __m256d pij = mi[0] * mjx + mi[1] * mjy + mi[2] * mjz;
      const __m256d pi = mi[0] * X + mi[1] * Y + mi[2] * Z;
      const __m256d pj = mjx * X + mjy * Y + mjz * Z;
      const rl_dd4 d = rl_elec_dd4(E, frl, rr, ir, ir2, ir3, ir5, pij, pi, pj);
      const __m256d A = d.A, Bi = d.Bi, Bj = d.Bj, s = d.s;
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

/* The rows of every LJ truncation, with (X##0 .. X##3) and without (O##0 .. O##3: forces only)
 * the energy and virial sums, the same for every separation mode; and the row set SET. */
#define RL_DIPOLE256_ROW(NAME, EV, MODE, TRUNC)                                                \
  ROW_FN_T(RL_T256, NAME, dipole_row256(EV, TRUNC, kp, V, K, i, nbr, len, ft, acc))
#define RL_AVX2_DIPOLE_ROWS(SET, X, O) RL_ROWS_ANY_MODE(SET, RL_DIPOLE256_ROW, X, O)
#endif

#endif
