/* The Stockmayer rows in AVX2 registers: LJ + reaction-field dipoles. */
#include "../elec/rf.h"
#include "dipole_row.h"

#if RL_X512
RL_AVX2_DIPOLE_ROWS(rl_rows_avx2_dipole_lj_rf, dipy_r, dipz_r)
#endif
