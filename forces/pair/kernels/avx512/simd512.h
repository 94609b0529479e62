/* AVX-512 helpers of the register rows: transposes, 1/sqrt, LJ on 8 lanes, the centres'
 * separations of eight records. */
#ifndef ROTLEAP_PAIR_SIMD512_H
#define ROTLEAP_PAIR_SIMD512_H

#include "../batch.h"
#include "../vdw_lj.h"

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
#endif

#endif
