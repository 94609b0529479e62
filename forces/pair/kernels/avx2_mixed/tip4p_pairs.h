/* The TIP4P pair terms in single precision on AVX2: a template (include an electrostatics with
 * charges, ../elec/, first). */
#ifndef ROTLEAP_PAIR_AVX2_MIXED_TIP4P_PAIRS_H
#define ROTLEAP_PAIR_AVX2_MIXED_TIP4P_PAIRS_H

#include "../avx2/tip4p_pairs.h"
#include "simd256f.h"

#if RL_X512

/* tip4p_pairs256 in single precision, eight lanes: the neighbours' sites from their float
 * records (V->pk4f), the centres' separations rounded to float, the terms in float; the forces
 * on the neighbours' sites go back to their double records, the forces on i's sites, the
 * energies and the virial are summed in double per batch. */
RL_T256 RL_INLINE void tip4p_pairs8f(const int MODE, const int EV, const int TRUNC,
                                     const lj_consts C, const box_consts *B, const rl_kelec E,
                                     const double a[4][3], const double qq[3][3],
                                     const kview *V, const batch *b, double (*ft4)[16],
                                     tip_sums4 *S)
{
#define V1 RL_V1F
  const __m256 zero = _mm256_setzero_ps(), rc2 = V1(B->rc2);
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
        __m256 fe, ue; /* the electrostatics (elec/), per qq */
        rl_elec_qq8f(E, r2, rsqrt8f(r2), &fe, &ue);
        const __m256 qv = _mm256_and_ps(in, V1(qq[p][q]));
        const __m256 fr = qv * fe;
        if (EV) ec = _mm256_fmadd_ps(qv, ue, ec);
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
#endif

#endif
