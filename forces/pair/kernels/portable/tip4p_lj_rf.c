/* The TIP4P rows (LJ + reaction-field charges), portable: every separation mode and LJ
 * truncation, each compiled for AVX-512, AVX2 and baseline x86-64 and picked at load time. */
#include "tip4p_row.h"

#define TIP4(M, P)                                                                             \
  ROW_FN(tip4p_##M##0, tip4p_row(P, RL_LJ_PLAIN, kp, V, K, i, nbr, len, fs, acc))                 \
  ROW_FN(tip4p_##M##1, tip4p_row(P, RL_LJ_SHIFTED, kp, V, K, i, nbr, len, fs, acc))               \
  ROW_FN(tip4p_##M##2, tip4p_row(P, RL_LJ_SHIFTED_FORCE, kp, V, K, i, nbr, len, fs, acc))         \
  ROW_FN(tip4p_##M##3, tip4p_row(P, RL_LJ_SWITCHED, kp, V, K, i, nbr, len, fs, acc))
TIP4(s, P_SITE)
TIP4(h, P_SHIFT)
TIP4(m, P_MOL)

const rl_row_set rl_rows_portable_tip4p_lj_rf = {{{tip4p_s0, tip4p_s1, tip4p_s2, tip4p_s3},
                                                  {tip4p_h0, tip4p_h1, tip4p_h2, tip4p_h3},
                                                  {tip4p_m0, tip4p_m1, tip4p_m2, tip4p_m3}},
                                                 {{0}}};
