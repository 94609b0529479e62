/* The TIP4P rows (LJ + reaction-field charges) in AVX2 registers: the centres' image
 * (P_SHIFT, P_MOL), every LJ truncation, with (tip4py_*) and without (tip4pz_*) the energy and
 * virial sums. */
#include "tip4p_row.h"

#if RL_X512
#define TIP_EV(INST, H, M, EV)                                                                 \
  INST(H##0, EV, P_SHIFT, RL_LJ_PLAIN)                                                         \
  INST(H##1, EV, P_SHIFT, RL_LJ_SHIFTED)                                                       \
  INST(H##2, EV, P_SHIFT, RL_LJ_SHIFTED_FORCE)                                                 \
  INST(H##3, EV, P_SHIFT, RL_LJ_SWITCHED)                                                      \
  INST(M##0, EV, P_MOL, RL_LJ_PLAIN)                                                           \
  INST(M##1, EV, P_MOL, RL_LJ_SHIFTED)                                                         \
  INST(M##2, EV, P_MOL, RL_LJ_SHIFTED_FORCE)                                                   \
  INST(M##3, EV, P_MOL, RL_LJ_SWITCHED)
#define TIP256(NAME, EV, MODE, TRUNC)                                                          \
  ROW_FN_T(RL_T256 RL_SCHED __attribute__((flatten)), NAME,                                    \
           tip4p_row256(0, EV, MODE, TRUNC, kp, V, K, i, nbr, len, fs, ft4, acc))
TIP_EV(TIP256, tip4py_h, tip4py_m, 1)
TIP_EV(TIP256, tip4pz_h, tip4pz_m, 0)

#define TIP_MODES(H, M) {{NULL, NULL, NULL, NULL}, {H##0, H##1, H##2, H##3}, {M##0, M##1, M##2, M##3}}
const rl_row_set rl_rows_avx2_tip4p_lj_rf = {TIP_MODES(tip4py_h, tip4py_m),
                                             TIP_MODES(tip4pz_h, tip4pz_m)};
#endif
