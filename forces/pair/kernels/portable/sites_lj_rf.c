/* The "charge-lj" rows (LJ + reaction-field charges), portable: every separation mode and LJ
 * truncation, each compiled for AVX-512, AVX2 and baseline x86-64 and picked at load time. */
#include "sites_row.h"

#define SITES4(M, P)                                                                           \
  ROW_FN(sites_##M##0, sites_row(P, RL_LJ_PLAIN, kp, V, K, i, nbr, len, fs, acc))                 \
  ROW_FN(sites_##M##1, sites_row(P, RL_LJ_SHIFTED, kp, V, K, i, nbr, len, fs, acc))               \
  ROW_FN(sites_##M##2, sites_row(P, RL_LJ_SHIFTED_FORCE, kp, V, K, i, nbr, len, fs, acc))         \
  ROW_FN(sites_##M##3, sites_row(P, RL_LJ_SWITCHED, kp, V, K, i, nbr, len, fs, acc))
SITES4(s, P_SITE)
SITES4(h, P_SHIFT)
SITES4(m, P_MOL)

const rl_row_set rl_rows_portable_sites_lj_rf = {{{sites_s0, sites_s1, sites_s2, sites_s3},
                                                  {sites_h0, sites_h1, sites_h2, sites_h3},
                                                  {sites_m0, sites_m1, sites_m2, sites_m3}},
                                                 {{0}}};
