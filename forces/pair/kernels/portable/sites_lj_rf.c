/* The "charge-lj" rows, portable: LJ + reaction-field charges. */
#include "../elec/rf.h"
#include "sites_row.h"

RL_PORTABLE_SITES_ROWS(rl_rows_portable_sites_lj_rf, sites_s, sites_h, sites_m)
