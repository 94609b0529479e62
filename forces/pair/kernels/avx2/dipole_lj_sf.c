/* The Stockmayer rows in AVX2 registers: LJ + shifted-force dipoles. */
#include "../elec/sf.h"
#include "dipole_row.h"

#if RL_X512
RL_AVX2_DIPOLE_ROWS(rl_rows_avx2_dipole_lj_sf, dipy_f, dipz_f)
#endif
