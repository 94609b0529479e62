/* Driver for inject_tests.sh: one output of the library written the way `rotleap run` writes it,
 * so that strace can fail its Nth write, pwrite, fsync, ftruncate, rename or close.
 *
 *   io_inject MODE OUT      MODE: dcd (create, 3 frames, sync, close), dcdappend (keep 2 frames
 *                           of an existing OUT, 2 more, sync, close), xyz (rl_file_create + 3
 *                           frames + fclose), pdb, xyzsnap, chk (atomic whole files)
 *
 * Prints nothing and exits 0 on success.  On failure it prints the library's message once
 * ("error: ..."), then, like a caller that cleans up, closes what it opened; a close that
 * reports a different message is printed too (the test counts the reports).  Exit 1. */
#include <rotleap/catalog.h>
#include <rotleap/error.h>
#include <rotleap/io.h>
#include <rotleap/molecule.h>
#include <rotleap/system.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char first[1024];

static int report(int st)
{
  if (st && !first[0]) {
    snprintf(first, sizeof first, "%s", rl_last_error());
    fprintf(stderr, "error: %s\n", first);
  } else if (st && strcmp(first, rl_last_error()) != 0) {
    fprintf(stderr, "error: %s\n", rl_last_error());
  }
  return st;
}

int main(int argc, char **argv)
{
  /* A marker for inject_tests.sh: the calls strace sees before it are the dynamic loader's and the
   * sanitizer runtime's (19 more closes under ASan than without), not the library's outputs */
  (void)getppid();
  if (argc != 3) { fprintf(stderr, "usage: io_inject dcd|dcdappend|xyz|pdb|xyzsnap|chk OUT\n"); return 2; }
  const char *mode = argv[1], *out = argv[2];
  const int dipoles = strcmp(mode, "xyz") == 0 || strcmp(mode, "xyzsnap") == 0;
  rl_molecule mol;
  const rl_model *md = rl_catalog_find(dipoles ? "stockmayer" : "tip4p");
  if (!md || rl_model_build(md, NULL, 0, &mol)) { fprintf(stderr, "model: %s\n", rl_last_error()); return 2; }
  rl_system *sys = rl_system_alloc(dipoles ? RL_UNITS_LJ : RL_UNITS_REAL);
  rl_species_desc d;
  rl_molecule_species(&mol, &d);
  double box[3] = {dipoles ? 4.0 : 1.6, dipoles ? 4.0 : 1.6, dipoles ? 4.0 : 1.6};
  if (!sys || rl_system_add_species(sys, &d, 32, NULL) || rl_system_lattice(sys, box, RL_LATTICE_FCC, 1, 7)) {
    fprintf(stderr, "system: %s\n", rl_last_error());
    return 2;
  }
  const rl_molecule *mols[1] = {&mol};
  int st = 0;
  if (!strcmp(mode, "dcd") || !strcmp(mode, "dcdappend")) {
    const int append = mode[3] != '\0';
    rl_dcd *t = append ? rl_dcd_append(out, sys, 2) : rl_dcd_create(out, sys, 10, 10, 0.002, NULL);
    if (!t) st = report(1);
    for (int f = 0; f < (append ? 2 : 3) && t && !st; f++) st = report(rl_dcd_write_frame(t, sys));
    if (t && !st) st = report(rl_dcd_sync(t));
    if (t && report(rl_dcd_close(t))) st = 1;
  } else if (!strcmp(mode, "xyz")) {
    int fd;
    FILE *fp = NULL;
    if (report(rl_file_create(out, &fd))) st = 1;
    else if (!(fp = fdopen(fd, "w"))) st = report(rl_error(RL_EINVAL, "%s: fdopen: %s", out, strerror(errno)));
    for (int f = 0; f < 3 && fp && !st; f++) st = report(rl_xyz_write_frame(fp, out, sys, 0.1 * f, 10L * f));
    if (fp && fclose(fp) != 0 && report(rl_error(RL_EINVAL, "%s: cannot close: %s", out, strerror(errno)))) st = 1;
  } else if (!strcmp(mode, "pdb")) {
    st = report(rl_pdb_write(out, sys, mols));
  } else if (!strcmp(mode, "xyzsnap")) {
    st = report(rl_xyz_write(out, sys, 1.0, 100));
  } else if (!strcmp(mode, "chk")) {
    static char blob[100000];
    rl_checkpoint_meta m = {1.0, 100, {box[0], box[1], box[2]}, blob, sizeof blob};
    st = report(rl_checkpoint_write(out, sys, &m));
  } else {
    fprintf(stderr, "unknown mode %s\n", mode);
    return 2;
  }
  rl_system_free(sys);
  return st ? 1 : 0;
}
