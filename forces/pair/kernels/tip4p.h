/* What the TIP4P register rows (AVX-512, AVX2, mixed precision) share: the constants of a row.
 * The term layout of a TIP4P species: t[0] the LJ term between the LJ sites (slot 0), t[1 + 3 p
 * + q] the charge pair p, q (slots 1 + p of i, 1 + q of j). */
#ifndef ROTLEAP_PAIR_TIP4P_H
#define ROTLEAP_PAIR_TIP4P_H

#include "batch.h"
#include "vdw_lj.h"

/* What a TIP4P register row (tip4p_row512, tip4p_row256) needs of row i: the box, the
 * electrostatics' parameters, the pruning radius, the LJ and charge-pair constants, i's sites
 * relative to its centre (from its record: it alone is fresh, the site buffers are not), and
 * the overlap limit (as tip4p_row's). */
typedef struct {
  box_consts B;
  rl_kelec E;
  double rp2, lim, a[4][3], qq[3][3];
  int img;
  lj_consts C;
} tip_row;

RL_INLINE void tip_row_of(const int MODE, const rl_kparams *kp, const kview *V,
                          const fast_species *K, int i, tip_row *T)
{
  T->B = kp->B;
  T->E = kp->E;
  T->rp2 = prune2(MODE, &T->B, K);
  T->img = needs_images(MODE, &T->B, T->rp2);
  T->C = lj_of(&K->t[0]);
  for (int s = 0; s < 4; s++)
    for (int c = 0; c < 3; c++) T->a[s][c] = V->pk4[i][3 + 3 * s + c];
  for (int p = 0; p < 3; p++)
    for (int q = 0; q < 3; q++) T->qq[p][q] = K->t[1 + 3 * p + q].qq;
  T->lim = MODE == P_MOL || T->B.md2 < T->B.rc2 ? T->B.md2 : T->B.rc2;
}

#endif
