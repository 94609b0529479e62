/* The TIP4P rows on AVX-512: a template.  Include an electrostatics with charges (../elec/)
 * first; RL_AVX512_TIP4P_ROWS(SET, XH, XM, OH, OM) then defines the rows and their row set. */
#ifndef ROTLEAP_PAIR_AVX512_TIP4P_ROW_H
#define ROTLEAP_PAIR_AVX512_TIP4P_ROW_H

#include "../tip4p.h"
#include "simd512.h"

#if !RL_ELEC_CHARGES
#error "include an electrostatics with charges (kernels/elec/) before this template"
#endif

#if RL_X512

/* batch_fill for the TIP4P rows with the centres' image (P_SHIFT, P_MOL), eight candidates at
 * a time: their centres are read from the first 256 bits of their records and transposed
 * (sep8), the minimum image and the pruning test run in one vector each, and the kept ones are
 * packed (vcompresspd) onto the batch in list order.  The batch gets the same neighbours in the
 * same lanes as from batch_fill, and ends where batch_fill's does (when full, or before a
 * neighbour whose images would not all fit), so the pair sums do not depend on which
 * candidates beyond rp the list holds, that is on when it was built: restarts stay bit for
 * bit (tests/cli/restart_tests.sh).  In a box that needs the other images (img), eight
 * candidates of which one has another image within rp go one by one through take_candidate,
 * which puts a neighbour's images right after it; for 256 TIP4P at rc = 0.9 nm that is about
 * one group in eight. */
RL_T512 static inline void tip4p_fill512(const kview *V, const box_consts *B, int i,
                                         const int *nbr, int len, int *pos, double rp2, int img,
                                         batch *b)
{
  const sep8_consts S = sep8_of(B, V->pk4[i]); /* the record starts with the centre */
  const __m512d Lx = S.L[0], Ly = S.L[1], Lz = S.L[2], vrp2 = _mm512_set1_pd(rp2);
  const double rp = img ? sqrt(rp2) : 0.0;
  const __m512d nx = _mm512_set1_pd(B->L[0] - rp), ny = _mm512_set1_pd(B->L[1] - rp),
                nz = _mm512_set1_pd(B->L[2] - rp), zero = _mm512_setzero_pd();
  int n = 0, p = *pos, full = 0;
  while (p < len && n < RL_FAST_B && !full) {
    const int cnt = len - p < RL_FAST_W ? len - p : RL_FAST_W;
    const __mmask8 live = (__mmask8)((1u << cnt) - 1u);
    const double *q[8];
    for (int l = 0; l < 8; l++) q[l] = V->pk4[nbr[p + (l < cnt ? l : 0)]]; /* tail: the first */
    __m512d R[3];
    sep8(&S, q, R);
    const __m512d X = R[0], Y = R[1], Z = R[2];
    const __m512d r2 = _mm512_fmadd_pd(Z, Z, _mm512_fmadd_pd(Y, Y, _mm512_mul_pd(X, X)));
    __mmask8 keep = _mm512_mask_cmp_pd_mask(live, r2, vrp2, _CMP_LT_OQ);
    if (img) { /* does any of the eight have another image within rp (other_images)? */
      const __mmask8 fx = _mm512_mask_cmp_pd_mask(live, _mm512_abs_pd(X), nx, _CMP_GT_OQ);
      const __mmask8 fy = _mm512_mask_cmp_pd_mask(live, _mm512_abs_pd(Y), ny, _CMP_GT_OQ);
      const __mmask8 fz = _mm512_mask_cmp_pd_mask(live, _mm512_abs_pd(Z), nz, _CMP_GT_OQ);
      const __m512d xs[2] = {X, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(X, zero, _CMP_GT_OQ),
                                                     _mm512_add_pd(X, Lx), _mm512_sub_pd(X, Lx))};
      const __m512d ys[2] = {Y, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(Y, zero, _CMP_GT_OQ),
                                                     _mm512_add_pd(Y, Ly), _mm512_sub_pd(Y, Ly))};
      const __m512d zs[2] = {Z, _mm512_mask_blend_pd(_mm512_cmp_pd_mask(Z, zero, _CMP_GT_OQ),
                                                     _mm512_add_pd(Z, Lz), _mm512_sub_pd(Z, Lz))};
      /* the images that shift two or three components (a corner's) only if a lane has one */
      const int nm = (fx & fy) | (fx & fz) | (fy & fz) ? 7 : 3;
      static const int order[7] = {1, 2, 4, 3, 5, 6, 7};
      __mmask8 more = 0, km[8] = {keep, 0, 0, 0, 0, 0, 0, 0}; /* km[m]: image m kept */
      for (int t = 0; t < nm; t++) {
        const int m = order[t];
        const __mmask8 far = (m & 1 ? fx : live) & (m & 2 ? fy : live) & (m & 4 ? fz : live);
        const __m512d u = xs[m & 1], v = ys[(m >> 1) & 1], w = zs[m >> 2];
        const __m512d s2 = _mm512_fmadd_pd(w, w, _mm512_fmadd_pd(v, v, _mm512_mul_pd(u, u)));
        km[m] = _mm512_mask_cmp_pd_mask(far, s2, vrp2, _CMP_LT_OQ);
        more |= km[m];
      }
      if (more) {
        /* a neighbour's images follow it, as in take_candidate: each of the eight in list
         * order, its minimum image (m = 0) then its other images m = 1 .. 7 (other_images'
         * order), from the vectors' lanes (before 2026-11-22 the eight went one by one through
         * take_candidate; other_images alone was 4 % of a 256-TIP4P step in perf) */
        _Alignas(64) double u[2][8], v[2][8], w[2][8];
        _mm512_store_pd(u[0], X); _mm512_store_pd(u[1], xs[1]);
        _mm512_store_pd(v[0], Y); _mm512_store_pd(v[1], ys[1]);
        _mm512_store_pd(w[0], Z); _mm512_store_pd(w[1], zs[1]);
        unsigned kept[8] = {0}; /* lane l: bit m if image m is kept */
        for (int m = 0; m < 8; m++)
          for (int l = 0; l < 8; l++) kept[l] |= ((km[m] >> l) & 1u) << m;
        for (int l = 0; l < cnt && n < RL_FAST_B; l++, p++) {
          if (n + __builtin_popcount(kept[l]) > RL_FAST_B) { /* the next batch takes it */
            full = 1;
            break;
          }
          for (unsigned bits = kept[l]; bits; bits &= bits - 1) {
            const int m = __builtin_ctz(bits);
            b->idx[n] = nbr[p];
            b->R[0][n] = u[m & 1][l];
            b->R[1][n] = v[(m >> 1) & 1][l];
            b->R[2][n] = w[m >> 2][l];
            n++;
          }
        }
        continue;
      }
    }
    /* the kept ones in list order, as many as fit: a batch ends where batch_fill's does */
    const __m512i id = _mm512_maskz_loadu_epi32((__mmask16)live, nbr + p);
    const int room = RL_FAST_B - n;
    if (__builtin_popcount(keep) > room) {
      while (__builtin_popcount(keep) > room) keep &= (__mmask8)~(1u << (31 - __builtin_clz(keep)));
      p += 32 - __builtin_clz(keep); /* past the last one taken */
    } else {
      p += cnt;
    }
    n = fill_append512(b, n, keep, id, X, Y, Z);
  }
  *pos = p;
  const int np = (n + RL_FAST_W - 1) / RL_FAST_W * RL_FAST_W;
  for (int k = n; k < np; k++) { /* padding: a copy of the first neighbour, masked out */
    b->idx[k] = b->idx[0];
    for (int c = 0; c < 3; c++) b->R[c][k] = b->R[c][0];
  }
  b->n = n;
  b->np = np;
}

/* The sums of a TIP4P row on AVX-512 over all its neighbours, lane by lane (tip4p_pairs512). */
typedef struct {
  __m512d fi[4][3]; /* forces on i's sites, by slot (LJ site, then charges) */
  __m512d w[9];     /* EV: R (x) F, F the pair's force on i */
  __m512d elj, ecoul;
  __m512d r2min;    /* the closest site pair of each lane's neighbours */
} tip_sums;

/* The 1 LJ + 9 Coulomb terms of a TIP4P batch (P_SHIFT or P_MOL), eight neighbours per
 * vector, in registers: each eight neighbours' records are loaded and transposed into their
 * sites, the terms formed (lj8 with a divide for 1 / r^2; the Coulomb terms as
 * rl_coulomb_rf_pair with 1/sqrt from vrsqrt14pd and two Newton steps, relative error
 * 2^-14 -> 6e-9 -> 5e-17, where the portable rows' rl_rsqrt takes four steps from a bit trick),
 * the forces on i's sites added to the row's running sums S, and the forces on the
 * neighbours' sites transposed back into records and added to the thread's buffer (ft4).
 * Until 2026-11-22 the batch went through memory between an `omp simd` LJ loop, a Coulomb
 * loop, a reduction per site component and a scatter loop, which took half of a 256-TIP4P
 * row's time (perf).  Neighbour k of a batch takes lane k mod 8 as before, and the batches end
 * where batch_fill's do, so the sums do not depend on when the list was built.  The cutoff
 * (P_SHIFT) and the padding are masks. */
RL_T512 RL_INLINE void tip4p_pairs512(const int MODE, const int EV, const int TRUNC,
                                      const lj_consts C, const box_consts *B, const rl_kelec E,
                                      const double a[4][3], const double qq[3][3],
                                      const kview *V, const batch *b, double (*ft4)[16],
                                      tip_sums *S)
{
#define V1(x) _mm512_set1_pd(x)
  const __m512d zero = _mm512_setzero_pd(), half = V1(0.5), rc2 = V1(B->rc2);
  for (int k = 0; k < b->n; k += RL_FAST_W) {
    const int cnt = b->n - k < RL_FAST_W ? b->n - k : RL_FAST_W;
    const __mmask8 live = (__mmask8)((1u << cnt) - 1u);
    const __m512d R[3] = {_mm512_load_pd(b->R[0] + k), _mm512_load_pd(b->R[1] + k),
                          _mm512_load_pd(b->R[2] + k)};
    __m512d lo[8], hi[8], A[8], H[8];
    for (int l = 0; l < 8; l++) {
      const double *q = V->pk4[b->idx[k + l]];
      lo[l] = _mm512_load_pd(q);
      hi[l] = _mm512_load_pd(q + 8);
    }
    tr8x8(lo, A); /* A[3 + 3 s + c]: site s, component c of the eight (s = 0, 1; c < 2) */
    tr8x8(hi, H); /* H[3 + 3 s + c - 8]: the rest */
    __m512d xj[4][3], gj[4][3];
    for (int s = 0; s < 4; s++)
      for (int c = 0; c < 3; c++) {
        const int e = 3 + 3 * s + c;
        xj[s][c] = e < 8 ? A[e] : H[e - 8];
      }
    { /* LJ between the LJ sites (slot 0): lj_eval */
      __m512d d[3];
      for (int c = 0; c < 3; c++) d[c] = R[c] + V1(a[0][c]) - xj[0][c];
      const __m512d r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      const __mmask8 in = MODE == P_MOL ? live : _mm512_mask_cmp_pd_mask(live, r2, rc2, _CMP_LT_OQ);
      S->r2min = _mm512_mask_min_pd(S->r2min, live, S->r2min, r2);
      const __m512d ir2 = V1(1.0) / r2;
      __m512d rr = zero, ir = zero;
      if (TRUNC == RL_LJ_SHIFTED_FORCE || TRUNC == RL_LJ_SWITCHED) {
        rr = _mm512_sqrt_pd(r2);
        ir = V1(1.0) / rr;
      }
      __m512d u, fr;
      lj8(TRUNC, C, B, ir2, rr, ir, &u, &fr);
      fr = _mm512_maskz_mov_pd(in, fr);
      if (EV) S->elj = _mm512_mask_add_pd(S->elj, in, S->elj, u);
      for (int c = 0; c < 3; c++) {
        const __m512d f = fr * d[c];
        S->fi[0][c] = S->fi[0][c] + f;
        gj[0][c] = zero - f;
      }
    }
    for (int q = 0; q < 3; q++)
      for (int c = 0; c < 3; c++) gj[1 + q][c] = zero;
    for (int p = 0; p < 3; p++) { /* charge p of i against charge q of j */
      __m512d ra[3];
      for (int c = 0; c < 3; c++) ra[c] = R[c] + V1(a[1 + p][c]);
      for (int q = 0; q < 3; q++) {
        __m512d d[3];
        for (int c = 0; c < 3; c++) d[c] = ra[c] - xj[1 + q][c];
        const __m512d r2 =
            _mm512_fmadd_pd(d[2], d[2], _mm512_fmadd_pd(d[1], d[1], _mm512_mul_pd(d[0], d[0])));
        const __mmask8 in =
            MODE == P_MOL ? live : _mm512_mask_cmp_pd_mask(live, r2, rc2, _CMP_LT_OQ);
        S->r2min = _mm512_mask_min_pd(S->r2min, live, S->r2min, r2);
        const __m512d h = half * r2;
        __m512d ir = _mm512_rsqrt14_pd(r2);
        ir = _mm512_fmadd_pd(ir, _mm512_fnmadd_pd(h, ir * ir, half), ir);
        ir = _mm512_fmadd_pd(ir, _mm512_fnmadd_pd(h, ir * ir, half), ir);
        const __m512d qv = V1(qq[p][q]);
        __m512d fe, ue; /* the electrostatics (elec/), per qq */
        rl_elec_qq8(E, r2, ir, &fe, &ue);
        const __m512d fr = _mm512_maskz_mul_pd(in, qv, fe);
        if (EV) S->ecoul = _mm512_mask3_fmadd_pd(qv, ue, S->ecoul, in);
        for (int c = 0; c < 3; c++) {
          const __m512d f = fr * d[c];
          S->fi[1 + p][c] = S->fi[1 + p][c] + f;
          gj[1 + q][c] = gj[1 + q][c] - f;
        }
      }
    }
    if (EV) /* R (x) F, F = -(sum of the forces on j's sites) the pair's force on i */
      for (int c = 0; c < 3; c++) {
        const __m512d F = zero - ((gj[0][c] + gj[1][c]) + (gj[2][c] + gj[3][c]));
        for (int r = 0; r < 3; r++) S->w[3 * r + c] = S->w[3 * r + c] + R[r] * F;
      }
    /* the forces on the neighbours' sites, as records (centre 0, sites, 0), added in order */
    const __m512d ea[8] = {zero, zero, zero, gj[0][0], gj[0][1], gj[0][2], gj[1][0], gj[1][1]};
    const __m512d eh[8] = {gj[1][2], gj[2][0], gj[2][1], gj[2][2],
                           gj[3][0], gj[3][1], gj[3][2], zero};
    tr8x8(ea, lo);
    tr8x8(eh, hi);
    for (int l = 0; l < cnt; l++) {
      double *o = ft4[b->idx[k + l]];
      _mm512_store_pd(o, _mm512_add_pd(_mm512_load_pd(o), lo[l]));
      _mm512_store_pd(o + 8, _mm512_add_pd(_mm512_load_pd(o + 8), hi[l]));
    }
  }
#undef V1
}

/* tip4p_row on AVX-512 (P_SHIFT, P_MOL): the batches from tip4p_fill512, their terms in
 * registers (tip4p_pairs512), i's site forces and (EV) the energies and R (x) F summed lane by
 * lane over the row and reduced at its end. */
RL_T512 RL_INLINE void tip4p_row512(const int EV, const int MODE, const int TRUNC,
                                    const rl_kparams *kp, const kview *V, const fast_species *K,
                                    int i, const int *nbr, int len, double (*fs)[3],
                                    double (*ft4)[16], rl_ksums *acc)
{
  tip_row T;
  tip_row_of(MODE, kp, V, K, i, &T);
  const __m512d z = _mm512_setzero_pd();
  tip_sums S;
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) S.fi[s][c] = z;
  for (int c = 0; c < 9; c++) S.w[c] = z;
  S.elj = S.ecoul = z;
  S.r2min = _mm512_set1_pd(HUGE_VAL);
  batch b;
  for (int pos = 0; pos < len;) {
    tip4p_fill512(V, &T.B, i, nbr, len, &pos, T.rp2, T.img, &b);
    if (b.n) tip4p_pairs512(MODE, EV, TRUNC, T.C, &T.B, T.E, T.a, T.qq, V, &b, ft4, &S);
  }
  const int oi = V->soff[i];
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) fs[oi + K->perm[s]][c] += _mm512_reduce_add_pd(S.fi[s][c]);
  if (EV) {
    acc->lj += _mm512_reduce_add_pd(S.elj);
    acc->coul += _mm512_reduce_add_pd(S.ecoul);
    for (int c = 0; c < 9; c++) acc->vir[c] += _mm512_reduce_add_pd(S.w[c]);
  }
  /* overlap: a site pair inside the cutoff closer than the minimum distance, as tip4p_row */
  acc->bad |= _mm512_cmp_pd_mask(S.r2min, _mm512_set1_pd(T.lim), _CMP_LT_OQ) != 0;
}

/* The rows of both modes with the centres' image (H: P_SHIFT, M: P_MOL) and every LJ
 * truncation, with (X) and without (O: forces only) the energy and virial sums; and the row
 * set SET (site images, P_SITE, take the portable rows).  flatten: the fill (with its images'
 * branch) is too large for GCC to inline on its own. */
#define RL_TIP4P512_ROW(NAME, EV, MODE, TRUNC)                                                 \
  ROW_FN_T(RL_T512 __attribute__((flatten)), NAME,                                             \
           tip4p_row512(EV, MODE, TRUNC, kp, V, K, i, nbr, len, fs, ft4, acc))
#define RL_AVX512_TIP4P_ROWS(SET, XH, XM, OH, OM)                                              \
  RL_ROWS_CENTRE_IMAGE(SET, RL_TIP4P512_ROW, XH, XM, OH, OM)
#endif

#endif
