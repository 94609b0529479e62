/* The Stockmayer rows, portable: LJ + shifted-force dipoles. */
#include "../elec/sf.h"
#include "dipole_row.h"

RL_PORTABLE_DIPOLE_ROWS(rl_rows_portable_dipole_lj_sf, dip_f)
