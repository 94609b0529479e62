/* The TIP4P rows on AVX2 in mixed precision (the pair terms in single precision): LJ +
 * reaction-field charges. */
#include "../elec/rf.h"
#include "tip4p_pairs.h"
#define RL_TIP4P_PAIRS256 tip4p_pairs8f
#include "../avx2/tip4p_row.h"

#if RL_X512
RL_AVX2_TIP4P_ROWS(rl_rows_avx2_mixed_tip4p_lj_rf, tip4pf_h, tip4pf_m, tip4pg_h, tip4pg_m)
#endif
