/* The Stockmayer rows (LJ + reaction-field dipoles), portable: every LJ truncation, each compiled for
 * AVX-512, AVX2 and baseline x86-64 and picked at load time. */
#include "dipole_row.h"

ROW_FN(dip_r0, dipole_row(0, RL_LJ_PLAIN, kp, V, K, i, nbr, len, fs, tq, acc))
ROW_FN(dip_r1, dipole_row(0, RL_LJ_SHIFTED, kp, V, K, i, nbr, len, fs, tq, acc))
ROW_FN(dip_r2, dipole_row(0, RL_LJ_SHIFTED_FORCE, kp, V, K, i, nbr, len, fs, tq, acc))
ROW_FN(dip_r3, dipole_row(0, RL_LJ_SWITCHED, kp, V, K, i, nbr, len, fs, tq, acc))

#define DIP4 {dip_r0, dip_r1, dip_r2, dip_r3}
const rl_row_set rl_rows_portable_dipole_lj_rf = {{DIP4, DIP4, DIP4}, {{0}}};
