/* The "charge-lj" rows, portable: LJ + Ewald real-space charges. */
#include "../elec/ewald.h"
#include "sites_row.h"

RL_PORTABLE_SITES_ROWS(rl_rows_portable_sites_lj_ewald, sites_s, sites_h, sites_m)
