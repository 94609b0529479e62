/* The TIP4P pair terms on AVX2 (double): a template (include an electrostatics with charges,
 * ../elec/, first). */
#ifndef ROTLEAP_PAIR_AVX2_TIP4P_PAIRS_H
#define ROTLEAP_PAIR_AVX2_TIP4P_PAIRS_H

#include "../tip4p.h"
#include "simd256.h"

#if !RL_ELEC_CHARGES
#error "include an electrostatics with charges (kernels/elec/) before this template"
#endif

#if RL_X512
/* The sums of a TIP4P row on AVX2, lane by lane, as tip_sums. */
typedef struct {
  __m256d fi[4][3], w[9], elj, ecoul, r2min;
} tip_sums4;

/* tip4p_pairs512 on four lanes. */
RL_T256 RL_INLINE void tip4p_pairs256(const int MODE, const int EV, const int TRUNC,
                                      const lj_consts C, const box_consts *B, const rl_kelec E,
                                      const double a[4][3], const double qq[3][3],
                                      const kview *V, const batch *b, double (*ft4)[16],
                                      tip_sums4 *S)
{
#define V1(x) _mm256_set1_pd(x)
  const __m256d zero = _mm256_setzero_pd(), rc2 = V1(B->rc2);
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
    for (int p = 0; p < 3; p++) { /* charge p of i against charge q of j */
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
        __m256d fe, ue; /* the electrostatics (elec/), per qq */
        rl_elec_qq4(E, r2, rsqrt4(r2), &fe, &ue);
        const __m256d qv = _mm256_and_pd(in, V1(qq[p][q]));
        const __m256d fr = qv * fe;
        if (EV) S->ecoul = _mm256_fmadd_pd(qv, ue, S->ecoul);
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
#endif

#endif
