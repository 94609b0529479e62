/* libFuzzer target for the checkpoint reader: rl_checkpoint_load builds a system from the file's
 * species table; when it does, rl_checkpoint_read reads the same file into it.  Inputs need a
 * valid CRC-32 to get past the checksum: the seeds have one, and a mutation that keeps the
 * header's length is rewritten with its CRC recomputed half of the time (when its last byte is even), so
 * the field checks behind the checksum are fuzzed too. */
#include "fuzz_io.h"

static uint32_t crc32_le(const uint8_t *p, size_t n)
{
  uint32_t c = 0xFFFFFFFFu;
  for (size_t i = 0; i < n; i++) {
    c ^= p[i];
    for (int k = 0; k < 8; k++) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
  }
  return ~c;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  uint8_t *b = malloc(size ? size : 1);
  if (!b) return 0;
  if (size) memcpy(b, data, size);
  if (size >= 28 && (b[size - 1] & 1) == 0) { /* the input decides, not a random draw */
    uint32_t c = crc32_le(b, size - 4);
    for (int k = 0; k < 4; k++) b[size - 4 + (size_t)k] = (uint8_t)(c >> (8 * k));
  }
  const char *path = fuzz_file("chk", b, size);
  free(b);
  if (!path) return 0;
  rl_checkpoint_meta m = {0}, m2 = {0};
  rl_system *s = rl_checkpoint_load(path, &m);
  if (s) {
    rl_checkpoint_read(path, s, &m2);
    free((void *)m2.blob);
  }
  free((void *)m.blob);
  rl_system_free(s);
  remove(path);
  return 0;
}
