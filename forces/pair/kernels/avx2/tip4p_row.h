/* The TIP4P rows on AVX2: a template.  The including file defines RL_TIP4P_PAIRS256, the pair
 * terms of a batch (tip4p_pairs256 of ./tip4p_pairs.h in double, tip4p_pairs8f of
 * ../avx2_mixed/tip4p_pairs.h in single precision), after an electrostatics (../elec/). */
#ifndef ROTLEAP_PAIR_AVX2_TIP4P_ROW_H
#define ROTLEAP_PAIR_AVX2_TIP4P_ROW_H

#include "tip4p_pairs.h"

#ifndef RL_TIP4P_PAIRS256
#error "define RL_TIP4P_PAIRS256, the pair terms of a batch, before this template"
#endif

#if RL_X512

/* tip4p_row512 on AVX2, the pairs by RL_TIP4P_PAIRS256.  In a box that
 * needs the other images, the row's neighbours come from the image list (build_images), so the
 * fill needs no minimum image and no search for images (fill256x). */
RL_T256 RL_INLINE void tip4p_row256(const int EV, const int MODE, const int TRUNC,
                                    const rl_kparams *kp, const kview *V, const fast_species *K,
                                    int i, const int *nbr, int len, double (*fs)[3],
                                    double (*ft4)[16], rl_ksums *acc)
{
  tip_row T;
  tip_row_of(MODE, kp, V, K, i, &T);
  const __m256d z = _mm256_setzero_pd();
  tip_sums4 S;
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) S.fi[s][c] = z;
  for (int c = 0; c < 9; c++) S.w[c] = z;
  S.elj = S.ecoul = z;
  S.r2min = _mm256_set1_pd(HUGE_VAL);
  batch b;
  const double *sh[3] = {NULL, NULL, NULL};
  const int xl = MODE == P_SHIFT && T.img && V->xstart; /* the image list (build_images) */
  if (xl) {
    const int q0 = V->xstart[i];
    nbr = V->xnbr + q0;
    len = V->xstart[i + 1] - q0;
    for (int c = 0; c < 3; c++) sh[c] = V->xs[c] + q0;
  }
  for (int pos = 0; pos < len;) {
    if (xl) fill256x(V->pk4[0], 16, V->pk4[i], nbr, sh, len, &pos, T.rp2, &b);
    else fill256(V->pk4[0], 16, &T.B, V->pk4[i], nbr, len, &pos, T.rp2, T.img, &b);
    if (b.n) RL_TIP4P_PAIRS256(MODE, EV, TRUNC, T.C, &T.B, T.E, T.a, T.qq, V, &b, ft4, &S);
  }
  const int oi = V->soff[i];
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) fs[oi + K->perm[s]][c] += hsum4(S.fi[s][c]);
  if (EV) {
    acc->lj += hsum4(S.elj);
    acc->coul += hsum4(S.ecoul);
    for (int c = 0; c < 9; c++) acc->vir[c] += hsum4(S.w[c]);
  }
  /* overlap: a site pair inside the cutoff closer than the minimum distance, as tip4p_row */
  acc->bad |= _mm256_movemask_pd(_mm256_cmp_pd(S.r2min, _mm256_set1_pd(T.lim), _CMP_LT_OQ)) != 0;
}

/* The rows of both modes with the centres' image (H: P_SHIFT, M: P_MOL) and every LJ
 * truncation, with (X) and without (O: forces only) the energy and virial sums; and the row
 * set SET (site images, P_SITE, take the portable rows). */
#define RL_TIP4P256_ROW(NAME, EV, MODE, TRUNC)                                                 \
  ROW_FN_T(RL_T256 RL_SCHED __attribute__((flatten)), NAME,                                    \
           tip4p_row256(EV, MODE, TRUNC, kp, V, K, i, nbr, len, fs, ft4, acc))
#define RL_AVX2_TIP4P_ROWS(SET, XH, XM, OH, OM)                                                \
  RL_ROWS_CENTRE_IMAGE(SET, RL_TIP4P256_ROW, XH, XM, OH, OM)
#endif

#endif
