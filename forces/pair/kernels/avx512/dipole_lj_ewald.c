/* The Stockmayer rows in AVX-512 registers: LJ + Ewald real-space dipoles. */
#include "../elec/ewald.h"
#include "dipole_row.h"

#if RL_X512
RL_AVX512_DIPOLE_ROWS(rl_rows_avx512_dipole_lj_ewald, dipx_e, dipo_e)
#endif
