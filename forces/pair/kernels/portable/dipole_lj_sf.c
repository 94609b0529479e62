/* The Stockmayer rows (LJ + shifted-force dipoles), portable: every LJ truncation, each compiled for
 * AVX-512, AVX2 and baseline x86-64 and picked at load time. */
#include "dipole_row.h"

ROW_FN(dip_f0, dipole_row(1, RL_LJ_PLAIN, kp, V, K, i, nbr, len, fs, tq, acc))
ROW_FN(dip_f1, dipole_row(1, RL_LJ_SHIFTED, kp, V, K, i, nbr, len, fs, tq, acc))
ROW_FN(dip_f2, dipole_row(1, RL_LJ_SHIFTED_FORCE, kp, V, K, i, nbr, len, fs, tq, acc))
ROW_FN(dip_f3, dipole_row(1, RL_LJ_SWITCHED, kp, V, K, i, nbr, len, fs, tq, acc))

#define DIP4 {dip_f0, dip_f1, dip_f2, dip_f3}
const rl_row_set rl_rows_portable_dipole_lj_sf = {{DIP4, DIP4, DIP4}, {{0}}};
