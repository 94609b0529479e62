/* The Stockmayer rows in AVX2 registers: LJ + Ewald real-space dipoles. */
#include "../elec/ewald.h"
#include "dipole_row.h"

#if RL_X512
RL_AVX2_DIPOLE_ROWS(rl_rows_avx2_dipole_lj_ewald, dipy_e, dipz_e)
#endif
