/* The Stockmayer rows (LJ + shifted-force dipoles) in AVX2 registers: every LJ truncation, with
 * (dipy_*) and without (dipz_*) the energy and virial sums. */
#include "dipole_row.h"

#if RL_X512
#define DIP1(INST, R, DSF, EV)                                                                 \
  INST(R##0, DSF, EV, RL_LJ_PLAIN)                                                             \
  INST(R##1, DSF, EV, RL_LJ_SHIFTED)                                                           \
  INST(R##2, DSF, EV, RL_LJ_SHIFTED_FORCE)                                                     \
  INST(R##3, DSF, EV, RL_LJ_SWITCHED)
#define DIP_ALL(R) {{R##0, R##1, R##2, R##3}, {R##0, R##1, R##2, R##3}, {R##0, R##1, R##2, R##3}}
#define DIP256(NAME, DSF, EV, TRUNC)                                                           \
  ROW_FN_T(RL_T256, NAME, (void)fs; dipole_row256(DSF, EV, TRUNC, kp, V, K, i, nbr, len, ft, acc))
DIP1(DIP256, dipy_f, 1, 1)
DIP1(DIP256, dipz_f, 1, 0)

const rl_row_set rl_rows_avx2_dipole_lj_sf = {DIP_ALL(dipy_f), DIP_ALL(dipz_f)};
#endif
