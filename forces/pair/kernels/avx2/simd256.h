/* AVX2 helpers of the register rows: transposes, 1/sqrt, LJ on 4 lanes, the fills. */
#ifndef ROTLEAP_PAIR_SIMD256_H
#define ROTLEAP_PAIR_SIMD256_H

#include "../batch.h"
#include "../vdw_lj.h"

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

#endif

#endif
