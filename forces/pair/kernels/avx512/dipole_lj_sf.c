/* The Stockmayer rows in AVX-512 registers: LJ + shifted-force dipoles. */
#include "../elec/sf.h"
#include "dipole_row.h"

#if RL_X512
RL_AVX512_DIPOLE_ROWS(rl_rows_avx512_dipole_lj_sf, dipx_f, dipo_f)
#endif
