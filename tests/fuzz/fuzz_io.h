/* Shared by the file-reader fuzz targets (fuzz_pdb.c, fuzz_xyz.c, fuzz_dcd.c, fuzz_checkpoint.c):
 * the readers take paths, so each input is written to a scratch file first; systems are built
 * from catalogue molecules, once per process.  Built with libFuzzer by run_fuzz.sh and, with
 * replay_main.c instead of libFuzzer, as CTest programs that replay the checked-in corpora. */
#ifndef ROTLEAP_FUZZ_IO_H
#define ROTLEAP_FUZZ_IO_H

#include <rotleap/catalog.h>
#include <rotleap/error.h>
#include <rotleap/io.h>
#include <rotleap/molecule.h>
#include <rotleap/system.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A scratch file NAME-<pid>.EXT in $TMPDIR (default /tmp) holding the input. */
static inline const char *fuzz_file(const char *ext, const uint8_t *data, size_t size)
{
  static char path[512];
  const char *dir = getenv("TMPDIR");
  snprintf(path, sizeof path, "%s/rotleap-fuzz-%ld.%s", dir && *dir ? dir : "/tmp", (long)getpid(), ext);
  FILE *f = fopen(path, "wb");
  if (!f) return NULL;
  if (size && fwrite(data, 1, size, f) != size) { fclose(f); remove(path); return NULL; }
  if (fclose(f)) { remove(path); return NULL; }
  return path;
}

/* A catalogue molecule, or "ar" (one LJ site at the centre: a point body), built once. */
static inline const rl_molecule *fuzz_molecule(const char *name)
{
  static struct { const char *name; rl_molecule m; } cache[8];
  for (int k = 0; k < 8; k++) {
    if (cache[k].name && strcmp(cache[k].name, name) == 0) return &cache[k].m;
    if (!cache[k].name) {
      static const double p0[3] = {0, 0, 0}, mass = 39.948;
      static const char *an[1] = {"AR"};
      const rl_molecule_def ad = {.name = "ar", .nsites = 1, .site_names = an, .pos = p0, .mass = &mass};
      const rl_model *md = strcmp(name, "ar") == 0 ? NULL : rl_catalog_find(name);
      int st = md ? rl_model_build(md, NULL, 0, &cache[k].m) : rl_molecule_build(&ad, 0, &cache[k].m);
      if (st) abort(); /* a bug in the harness */
      cache[k].name = name;
      return &cache[k].m;
    }
  }
  abort();
}

/* count bodies of one catalogue molecule, on a lattice (NULL if count is 0). */
static inline rl_system *fuzz_system(rl_units units, const char *name, int count)
{
  if (count <= 0) return NULL;
  rl_system *s = rl_system_alloc(units);
  rl_species_desc d;
  rl_molecule_species(fuzz_molecule(name), &d);
  double box[3] = {5.0, 5.0, 5.0};
  if (!s || rl_system_add_species(s, &d, count, NULL) || rl_system_lattice(s, box, RL_LATTICE_FCC, 0, 1)) abort();
  return s;
}

#endif
