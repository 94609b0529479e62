/* The Stockmayer rows in AVX-512 registers: LJ + reaction-field dipoles. */
#include "../elec/rf.h"
#include "dipole_row.h"

#if RL_X512
RL_AVX512_DIPOLE_ROWS(rl_rows_avx512_dipole_lj_rf, dipx_r, dipo_r)
#endif
