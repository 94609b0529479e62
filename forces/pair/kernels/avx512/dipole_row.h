/* The Stockmayer rows on AVX-512: a template.  Include a dipolar electrostatics (../elec/)
 * first; RL_AVX512_DIPOLE_ROWS(SET, X, O) then defines the rows and their row set. */
#ifndef ROTLEAP_PAIR_AVX512_DIPOLE_ROW_H
#define ROTLEAP_PAIR_AVX512_DIPOLE_ROW_H

#include "../elec/elec.h"
#include "simd512.h"

#if !RL_ELEC_DIPOLES
#error "include a dipolar electrostatics (kernels/elec/) before this template"
#endif

#if RL_X512
/* The dipole rows on AVX-512 without batch arrays (issue 8): eight list entries at a time are
 * loaded from their 64-byte records (V->pk: centre, 0, mu axis, 0) and transposed with
 * shuffles; those within the cutoff are packed with vcompresspd and appended, in list order,
 * to a pending vector of up to 7 neighbours (a lane rotation and a blend).  Each time eight
 * are pending, their pair terms are formed in registers; the forces and torques on the eight
 * neighbours are transposed back into records and added to the thread's packed buffer (ft).
 * Neighbour k of the row (counting only those within the cutoff) takes lane k mod 8, so the
 * lanes, and the rounding of the row's sums, do not depend on which candidates beyond the
 * cutoff the list holds (a run restarted from a checkpoint rebuilds the list at another step
 * and continues bit for bit). */

/* The row's running sums: force and torque on i, virial, energies, overlaps. */
typedef struct {
  __m512d fx, fy, fz, tx, ty, tz, w0, w1, w2, w3, w4, w5, w6, w7, w8, elj, edip;
  __mmask8 bad;
} dip_sums;

/* The pair terms of i with the eight neighbours in lanes (X, Y, Z: centre_i - centre_j,
 * m: mu_j), of which the first nv are real (the others hold copies of lane 0 and add nothing):
 * lj_eval_ir2 and the electrostatics' dipole pair (rl_elec_dd8), as dipole_row on vectors. */
RL_T512 RL_INLINE void dip_pairs8(const int EV, const int TRUNC, const lj_consts C,
                                      const box_consts *B, const rl_kelec E,
                                      const __m512d mi[3], __m512d X, __m512d Y, __m512d Z,
                                      __m512d mjx, __m512d mjy, __m512d mjz, const int *idx,
                                      int nv, double (*ft)[8], dip_sums *S)
{
#define V1(a) _mm512_set1_pd(a)
  const __mmask8 live = (__mmask8)((1u << nv) - 1u);
  const __m512d r2 = X * X + Y * Y + Z * Z;
  S->bad |= _mm512_mask_cmp_pd_mask(live, r2, V1(B->md2), _CMP_LT_OQ);
  const __m512d ir = rsqrt8(r2), ir2 = ir * ir, ir3 = ir * ir2, ir5 = ir3 * ir2;
  const __m512d rr = r2 * ir; /* |r|, for the truncations and the shifted-force dipoles */
  __m512d ul, frl;
  lj8(TRUNC, C, B, ir2, rr, ir, &ul, &frl);
  /* the dipoles' electrostatics (elec/) in the regrouped form of rl_dd8: the force on i is
   * s R - Bj mu_i - Bi mu_j, the fields g_i = A mu_j + Bj R, g_j = A mu_i + Bi R (for the
   * reaction field about 20 fewer multiplies and adds per 8 pairs than dipole_row) */
  const __m512d pij = mi[0] * mjx + mi[1] * mjy + mi[2] * mjz;
  const __m512d pi = mi[0] * X + mi[1] * Y + mi[2] * Z;
  const __m512d pj = mjx * X + mjy * Y + mjz * Z;
  const rl_dd8 d = rl_elec_dd8(E, frl, rr, ir, ir2, ir3, ir5, pij, pi, pj);
  const __m512d A = d.A, Bi = d.Bi, Bj = d.Bj, s = d.s;
  __m512d fx = s * X - Bj * mi[0] - Bi * mjx;
  __m512d fy = s * Y - Bj * mi[1] - Bi * mjy;
  __m512d fz = s * Z - Bj * mi[2] - Bi * mjz;
  const __m512d gix = A * mjx + Bj * X, giy = A * mjy + Bj * Y, giz = A * mjz + Bj * Z;
  const __m512d gjx = A * mi[0] + Bi * X, gjy = A * mi[1] + Bi * Y, gjz = A * mi[2] + Bi * Z;
  const __m512d ud = pij * A + Bi * pj;
  /* the padding lanes add nothing */
  fx = _mm512_maskz_mov_pd(live, fx); fy = _mm512_maskz_mov_pd(live, fy);
  fz = _mm512_maskz_mov_pd(live, fz);
  /* force on i, and (EV) the energies and the virial R (x) F */
  S->fx += fx; S->fy += fy; S->fz += fz;
  if (EV) {
    S->elj = _mm512_mask_add_pd(S->elj, live, S->elj, ul);
    S->edip = _mm512_mask_add_pd(S->edip, live, S->edip, ud);
    S->w0 += X * fx; S->w1 += X * fy; S->w2 += X * fz;
    S->w3 += Y * fx; S->w4 += Y * fy; S->w5 += Y * fz;
    S->w6 += Z * fx; S->w7 += Z * fy; S->w8 += Z * fz;
  }
  /* torques -mu x g on i and on j */
  S->tx = _mm512_mask_sub_pd(S->tx, live, S->tx, mi[1] * giz - mi[2] * giy);
  S->ty = _mm512_mask_sub_pd(S->ty, live, S->ty, mi[2] * gix - mi[0] * giz);
  S->tz = _mm512_mask_sub_pd(S->tz, live, S->tz, mi[0] * giy - mi[1] * gix);
  const __m512d zero = _mm512_setzero_pd();
  const __m512d in[8] = {zero - fx, zero - fy, zero - fz, zero,
                         mjz * gjy - mjy * gjz, mjx * gjz - mjz * gjx, mjy * gjx - mjx * gjy,
                         zero};
  __m512d r[8]; /* neighbour l: (f 0 | t 0) */
  tr8x8(in, r);
  for (int l = 0; l < nv; l++) {
    double *o = ft[idx[l]];
    _mm512_store_pd(o, _mm512_add_pd(_mm512_load_pd(o), r[l]));
  }
#undef V1
}

RL_T512 RL_INLINE void dipole_row512(const int EV, const int TRUNC,
                                         const rl_kparams *kp, const kview *V,
                                         const fast_species *K, int i, const int *nbr, int len,
                                         double (*fs)[3], double (*tq)[3], double (*ft)[8],
                                         rl_ksums *acc)
{
  const box_consts B = kp->B;
  const lj_consts C = lj_of(&K->t[0]);
  const rl_kelec E = kp->E;
  const double *pi = V->pk[i]; /* i's record: centre, 0, mu axis, 0 */
  const __m512d mi[3] = {_mm512_set1_pd(pi[4]), _mm512_set1_pd(pi[5]), _mm512_set1_pd(pi[6])};
  const sep8_consts S8 = sep8_of(&B, pi);
  const __m512d rc2 = _mm512_set1_pd(B.rc2);
  const __m512i even = S8.even, odd = S8.odd;
  const __m512i iota = _mm512_set_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0);
  const __m512d z0 = _mm512_setzero_pd();
  dip_sums S = {z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, z0, 0};
  /* the pending neighbours, lanes 0 .. pn - 1 */
  __m512d pX = _mm512_setzero_pd(), pY = pX, pZ = pX, pmx = pX, pmy = pX, pmz = pX;
  __m512i pid = _mm512_setzero_si512();
  int pn = 0;
  _Alignas(64) int idx[16];
  for (int p = 0; p < len; p += RL_FAST_W) {
    const int cnt = len - p < RL_FAST_W ? len - p : RL_FAST_W;
    const double *q[8];
    if (cnt == RL_FAST_W)
      for (int l = 0; l < 8; l++) q[l] = V->pk[nbr[p + l]];
    else
      for (int l = 0; l < 8; l++) q[l] = V->pk[nbr[p + (l < cnt ? l : 0)]]; /* the first again */
    __m512d R[3], d[4]; /* d: halves (record q[l] | record q[l + 4]) of the dipole */
    sep8(&S8, q, R);
    for (int l = 0; l < 4; l++)
      d[l] = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_load_pd(q[l] + 4)),
                                _mm256_load_pd(q[l + 4] + 4), 1);
    const __m512d X = R[0], Y = R[1], Z = R[2];
    const __m512d r2 = _mm512_fmadd_pd(Z, Z, _mm512_fmadd_pd(Y, Y, _mm512_mul_pd(X, X)));
    const __mmask8 keep = _mm512_cmp_pd_mask(r2, rc2, _CMP_LT_OQ) & (__mmask8)((1u << cnt) - 1u);
    if (!keep) continue;
    const int kc8 = __builtin_popcount(keep);
    const __m512d dl01 = _mm512_unpacklo_pd(d[0], d[1]), dh01 = _mm512_unpackhi_pd(d[0], d[1]);
    const __m512d dl23 = _mm512_unpacklo_pd(d[2], d[3]), dh23 = _mm512_unpackhi_pd(d[2], d[3]);
    /* the kept ones packed, then rotated up by pn lanes: lanes pn .. 7 continue the pending
     * ones, lanes 0 .. pn + kc8 - 9 are the overflow */
    const __m512i rot = _mm512_and_si512(_mm512_sub_epi32(iota, _mm512_set1_epi32(pn)),
                                         _mm512_set1_epi32(7));
    const __m512i rot64 = _mm512_cvtepi32_epi64(_mm512_castsi512_si256(rot));
#define RL_ROT(V) _mm512_permutexvar_pd(rot64, _mm512_maskz_compress_pd(keep, V))
    const __m512d nX = RL_ROT(X), nY = RL_ROT(Y), nZ = RL_ROT(Z);
    const __m512d nmx = RL_ROT(_mm512_permutex2var_pd(dl01, even, dl23));
    const __m512d nmy = RL_ROT(_mm512_permutex2var_pd(dh01, even, dh23));
    const __m512d nmz = RL_ROT(_mm512_permutex2var_pd(dl01, odd, dl23));
#undef RL_ROT
    const __m512i id = _mm512_maskz_loadu_epi32((__mmask16)((1u << cnt) - 1u), nbr + p);
    const __m512i nid = _mm512_permutexvar_epi32(rot, _mm512_maskz_compress_epi32(keep, id));
    const __mmask8 old = (__mmask8)((1u << pn) - 1u);
    const __m512d aX = _mm512_mask_blend_pd(old, nX, pX), aY = _mm512_mask_blend_pd(old, nY, pY),
                  aZ = _mm512_mask_blend_pd(old, nZ, pZ);
    const __m512d amx = _mm512_mask_blend_pd(old, nmx, pmx),
                  amy = _mm512_mask_blend_pd(old, nmy, pmy),
                  amz = _mm512_mask_blend_pd(old, nmz, pmz);
    const __m512i aid = _mm512_mask_blend_epi32((__mmask16)old, nid, pid);
    if (pn + kc8 < RL_FAST_W) { /* still pending */
      pX = aX; pY = aY; pZ = aZ; pmx = amx; pmy = amy; pmz = amz; pid = aid;
      pn += kc8;
      continue;
    }
    _mm512_store_si512(idx, aid);
    dip_pairs8(EV, TRUNC, C, &B, E, mi, aX, aY, aZ, amx, amy, amz, idx, RL_FAST_W, ft, &S);
    pX = nX; pY = nY; pZ = nZ; pmx = nmx; pmy = nmy; pmz = nmz; pid = nid;
    pn += kc8 - RL_FAST_W;
  }
  if (pn) { /* the last ones; the other lanes repeat lane 0 */
    const __mmask8 old = (__mmask8)((1u << pn) - 1u);
    const __m512i z = _mm512_setzero_si512();
#define RL_PAD(V) _mm512_mask_blend_pd(old, _mm512_permutexvar_pd(z, V), V)
    _mm512_store_si512(idx, pid);
    dip_pairs8(EV, TRUNC, C, &B, E, mi, RL_PAD(pX), RL_PAD(pY), RL_PAD(pZ), RL_PAD(pmx),
               RL_PAD(pmy), RL_PAD(pmz), idx, pn, ft, &S);
#undef RL_PAD
  }
  /* the force and torque on i go to its record too, so the dipole ranks need no site buffers */
  (void)fs;
  (void)tq;
  ft[i][0] += _mm512_reduce_add_pd(S.fx);
  ft[i][1] += _mm512_reduce_add_pd(S.fy);
  ft[i][2] += _mm512_reduce_add_pd(S.fz);
  ft[i][4] += _mm512_reduce_add_pd(S.tx);
  ft[i][5] += _mm512_reduce_add_pd(S.ty);
  ft[i][6] += _mm512_reduce_add_pd(S.tz);
  acc->lj += _mm512_reduce_add_pd(S.elj);
  acc->dip += _mm512_reduce_add_pd(S.edip);
  const __m512d w[9] = {S.w0, S.w1, S.w2, S.w3, S.w4, S.w5, S.w6, S.w7, S.w8};
  for (int c = 0; c < 9; c++) acc->vir[c] += _mm512_reduce_add_pd(w[c]);
  acc->bad |= S.bad != 0;
}

/* The rows of every LJ truncation, with (X##0 .. X##3) and without (O##0 .. O##3: forces only)
 * the energy and virial sums, the same for every separation mode; and the row set SET. */
#define RL_DIPOLE512_ROW(NAME, EV, MODE, TRUNC)                                                \
  ROW_FN_T(RL_T512, NAME, dipole_row512(EV, TRUNC, kp, V, K, i, nbr, len, fs, tq, ft, acc))
#define RL_AVX512_DIPOLE_ROWS(SET, X, O) RL_ROWS_ANY_MODE(SET, RL_DIPOLE512_ROW, X, O)
#endif

#endif
