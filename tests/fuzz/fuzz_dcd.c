/* libFuzzer target for the DCD reader: rl_dcd_info and rl_dcd_layout, then the read path of
 * rl_dcd_append on the scratch copy (header checks, atom count, truncation to half its frames)
 * with a system of as many LJ atoms as the header announces (up to 512), one frame appended. */
#include "fuzz_io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  const char *path = fuzz_file("dcd", data, size);
  if (!path) return 0;
  long first, every, frames, header, frame;
  if (rl_dcd_info(path, &first, &every, &frames) == RL_OK && rl_dcd_layout(path, &header, &frame) == RL_OK) {
    long natoms = (frame - 56 - 24) / 12; /* frames with a unit cell: 56 + 3 (8 + 4 N) bytes */
    if (natoms > 0 && natoms <= 512) {
      rl_system *s = fuzz_system(RL_UNITS_REAL, "ar", (int)natoms);
      rl_dcd *d = rl_dcd_append(path, s, frames / 2);
      if (d) {
        const double box[3] = {5, 5, 5};
        rl_system_set_box(s, box);
        rl_dcd_write_frame(d, s);
        rl_dcd_sync(d);
        rl_dcd_close(d);
      }
      rl_system_free(s);
    }
  }
  remove(path);
  return 0;
}
