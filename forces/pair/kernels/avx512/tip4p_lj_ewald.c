/* The TIP4P rows in AVX-512 registers: LJ + Ewald real-space charges. */
#include "../elec/ewald.h"
#include "tip4p_row.h"

#if RL_X512
RL_AVX512_TIP4P_ROWS(rl_rows_avx512_tip4p_lj_ewald, tip4px_h, tip4px_m, tip4po_h, tip4po_m)
#endif
