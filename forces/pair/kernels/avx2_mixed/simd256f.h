/* AVX2 helpers in single precision (the mixed-precision TIP4P rows). */
#ifndef ROTLEAP_PAIR_SIMD256F_H
#define ROTLEAP_PAIR_SIMD256F_H

#include "../avx2/simd256.h"

#if RL_X512
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
#endif

#endif
