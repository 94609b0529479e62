/* The TIP4P rows in AVX2 registers: LJ + Ewald real-space charges. */
#include "../elec/ewald.h"
#include "tip4p_pairs.h"
#define RL_TIP4P_PAIRS256 tip4p_pairs256
#include "tip4p_row.h"

#if RL_X512
RL_AVX2_TIP4P_ROWS(rl_rows_avx2_tip4p_lj_ewald, tip4py_h, tip4py_m, tip4pz_h, tip4pz_m)
#endif
