/* Scenes for the file I/O tests: molecules from the catalogue plus an LJ atom, in one system. */
#ifndef ROTLEAP_IO_TESTUTIL_H
#define ROTLEAP_IO_TESTUTIL_H
#include "../testutil.h"

#include <dirent.h>
#include <rotleap/io.h>
#include <stdlib.h>
#include <unistd.h>

#define IO_MAX_SPECIES 4

typedef struct {
  rl_system *sys;
  int nspecies;
  rl_molecule mol[IO_MAX_SPECIES];
  const rl_molecule *mols[IO_MAX_SPECIES];
  double box[3];
} io_scene;

static inline void io_build_molecule(const char *name, rl_molecule *m)
{
  if (strcmp(name, "Ar") == 0) {
    static const double p0[3] = {0, 0, 0}, m1 = 39.948;
    static const char *nm[1] = {"AR"};
    rl_molecule_def ad = {.name = "Ar", .nsites = 1, .site_names = nm, .pos = p0, .mass = &m1};
    assert_int_equal(rl_molecule_build(&ad, 0, m), RL_OK);
    return;
  }
  const rl_model *md = rl_catalog_find(name);
  assert_non_null(md);
  assert_int_equal(rl_model_build(md, NULL, 0, m), RL_OK);
}

/* A system in `units` with the named species, count each; lattice + Maxwell-Boltzmann. */
static inline void io_scene_build(io_scene *s, rl_units units, const char *const *names, const int *counts,
                                  int nspecies, double L, unsigned long seed)
{
  memset(s, 0, sizeof *s);
  s->sys = rl_system_alloc(units);
  assert_non_null(s->sys);
  s->nspecies = nspecies;
  for (int k = 0; k < nspecies; k++) {
    io_build_molecule(names[k], &s->mol[k]);
    s->mols[k] = &s->mol[k];
    rl_species_desc d;
    rl_molecule_species(&s->mol[k], &d);
    assert_int_equal(rl_system_add_species(s->sys, &d, counts[k], NULL), RL_OK);
  }
  s->box[0] = s->box[1] = s->box[2] = L;
  assert_int_equal(rl_system_lattice(s->sys, s->box, RL_LATTICE_FCC, 1, seed), RL_OK);
  assert_int_equal(rl_system_maxwell_boltzmann(s->sys, units == RL_UNITS_REAL ? 300.0 : 1.5, seed + 1), RL_OK);
}

static inline void io_scene_free(io_scene *s) { rl_system_free(s->sys); }

/* A scratch directory under the test's working directory. */
static inline void io_path(char *out, size_t n, const char *name)
{
  snprintf(out, n, "io_scratch_%ld_%s", (long)getpid(), name);
}

static inline void put_text(const char *path, const char *text)
{
  FILE *fp = fopen(path, "w");
  assert_non_null(fp);
  fputs(text, fp);
  fclose(fp);
}

/* The name of a temporary file PATH.tmp.XXXXXX beside path (path in the working directory), if one
 * exists: 1 and its name in out, else 0. */
static inline int io_find_tmp(const char *path, char *out, size_t n)
{
  char prefix[512];
  snprintf(prefix, sizeof prefix, "%s.tmp.", path);
  DIR *dir = opendir(".");
  int found = 0;
  for (struct dirent *e; dir && !found && (e = readdir(dir));)
    if (strncmp(e->d_name, prefix, strlen(prefix)) == 0) {
      snprintf(out, n, "%s", e->d_name);
      found = 1;
    }
  if (dir) closedir(dir);
  return found;
}

static inline int contains(const char *hay, const char *needle) { return strstr(hay, needle) != NULL; }

#define CHECK_MSG(name, status, want_status, needle)                                               \
  do {                                                                                             \
    int s_ = (status);                                                                             \
    const char *m_ = rl_last_error();                                                              \
    int ok_ = s_ == (want_status) && contains(m_, needle);                                         \
    printf("check %-58s \"%s\" %s\n", name, m_, ok_ ? "ok" : "FAIL");                              \
    assert_true(ok_);                                                                              \
  } while (0)

#define CHECK_TRUE(name, cond)                                                                     \
  do {                                                                                             \
    int c_ = (cond);                                                                               \
    printf("check %-58s %s\n", name, c_ ? "ok" : "FAIL");                                          \
    assert_true(c_);                                                                               \
  } while (0)

#endif
