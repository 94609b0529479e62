/* libFuzzer target for the PDB reader: rl_pdb_count, then rl_pdb_read_state into TIP4P waters
 * (names checked against the molecule) and into one-site LJ atoms (no molecule), as many as the
 * file has residues (up to 256).  Any crash, hang, leak or sanitizer report is a bug. */
#include "fuzz_io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  const char *path = fuzz_file("pdb", data, size);
  if (!path) return 0;
  int n = 0;
  double box[3], rms;
  if (rl_pdb_count(path, RL_UNITS_REAL, &n, box) == RL_OK && n > 0 && n <= 256) {
    const char *names[2] = {"tip4p", "ar"};
    for (int k = 0; k < 2; k++) {
      rl_system *s = fuzz_system(RL_UNITS_REAL, names[k], n);
      const rl_molecule *mols[1] = {fuzz_molecule(names[k])};
      rl_pdb_read_state(path, s, k == 0 ? mols : NULL, 0.0, &rms, box);
      rl_system_free(s);
    }
  }
  remove(path);
  return 0;
}
