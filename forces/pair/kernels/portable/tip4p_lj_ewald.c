/* The TIP4P rows, portable: LJ + Ewald real-space charges. */
#include "../elec/ewald.h"
#include "tip4p_row.h"

RL_PORTABLE_TIP4P_ROWS(rl_rows_portable_tip4p_lj_ewald, tip4p_s, tip4p_h, tip4p_m)
