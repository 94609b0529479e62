/* The Stockmayer rows, portable: LJ + Ewald real-space dipoles. */
#include "../elec/ewald.h"
#include "dipole_row.h"

RL_PORTABLE_DIPOLE_ROWS(rl_rows_portable_dipole_lj_ewald, dip_e)
