/* libFuzzer target for the extended XYZ reader: rl_xyz_count, then rl_xyz_read_state into
 * Stockmayer dipoles (lj units: an axis kind) and TIP4P waters (real units: a matrix kind), as
 * many as the first line announces (up to 512). */
#include "fuzz_io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  const char *path = fuzz_file("xyz", data, size);
  if (!path) return 0;
  int n = 0;
  if (rl_xyz_count(path, &n) == RL_OK && n > 0 && n <= 512) {
    double box[3];
    rl_system *s = fuzz_system(RL_UNITS_LJ, "stockmayer", n);
    rl_xyz_read_state(path, s, box);
    rl_system_free(s);
    s = fuzz_system(RL_UNITS_REAL, "tip4p", n);
    rl_xyz_read_state(path, s, box);
    rl_system_free(s);
  }
  remove(path);
  return 0;
}
