/* The Stockmayer rows, portable: LJ + reaction-field dipoles. */
#include "../elec/rf.h"
#include "dipole_row.h"

RL_PORTABLE_DIPOLE_ROWS(rl_rows_portable_dipole_lj_rf, dip_r)
