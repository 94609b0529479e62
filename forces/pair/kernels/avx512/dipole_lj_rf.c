/* The Stockmayer rows (LJ + reaction-field dipoles) in AVX-512 registers: every LJ truncation, with
 * (dipx_*) and without (dipo_*) the energy and virial sums. */
#include "dipole_row.h"

#if RL_X512
#define DIP1(INST, R, DSF, EV)                                                                 \
  INST(R##0, DSF, EV, RL_LJ_PLAIN)                                                             \
  INST(R##1, DSF, EV, RL_LJ_SHIFTED)                                                           \
  INST(R##2, DSF, EV, RL_LJ_SHIFTED_FORCE)                                                     \
  INST(R##3, DSF, EV, RL_LJ_SWITCHED)
#define DIP_ALL(R) {{R##0, R##1, R##2, R##3}, {R##0, R##1, R##2, R##3}, {R##0, R##1, R##2, R##3}}
#define DIP512(NAME, DSF, EV, TRUNC)                                                           \
  ROW_FN_T(RL_T512, NAME, dipole_row512(DSF, EV, TRUNC, kp, V, K, i, nbr, len, fs, tq, ft, acc))
DIP1(DIP512, dipx_r, 0, 1)
DIP1(DIP512, dipo_r, 0, 0)

const rl_row_set rl_rows_avx512_dipole_lj_rf = {DIP_ALL(dipx_r), DIP_ALL(dipo_r)};
#endif
