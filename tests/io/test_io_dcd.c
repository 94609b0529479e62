/* DCD + PDB topology for MDTraj/VMD: writes io_traj.dcd, io_traj.pdb and io_traj_ref.txt (the
 * coordinates and boxes written, in Angstrom, full precision, and the time step) for
 * mdtraj_read.py (test_io_mdtraj) and mdanalysis_read.py (test_io_mdanalysis),
 * after checking the DCD's layout here: header frame count, file size per frame, and that a
 * restart (rl_dcd_append keeping 2 of 4 frames) continues the file correctly. */
#include "io_testutil.h"

#include <sys/stat.h>

static const char *NAMES[2] = {"tip4p", "Ar"};
static const int COUNTS[2] = {27, 5};

static long file_size(const char *path)
{
  struct stat st;
  return stat(path, &st) == 0 ? (long)st.st_size : -1L;
}

/* The 32-bit little-endian word at byte `off` of a file's header. */
static uint32_t header_word(const char *path, int off)
{
  FILE *fp = fopen(path, "rb");
  assert_non_null(fp);
  unsigned char b[4];
  assert_int_equal(fseek(fp, off, SEEK_SET), 0);
  assert_int_equal(fread(b, 1, 4, fp), 4);
  fclose(fp);
  return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static long header_nset(const char *path) { return (long)header_word(path, 8); }

static float header_delta(const char *path)
{
  uint32_t u = header_word(path, 44);
  float f;
  memcpy(&f, &u, 4);
  return f;
}

static void ref_frame(FILE *ref, const rl_system *sys, const double box[3])
{
  int na = rl_io_natoms(sys), ns = rl_system_nsites(sys);
  double(*x)[3] = malloc(sizeof *x * (size_t)ns);
  assert_non_null(x);
  rl_system_site_positions(sys, x); /* every species here has sites: atoms = sites */
  assert_int_equal(na, ns);
  fprintf(ref, "box %.9f %.9f %.9f\n", box[0] * 10, box[1] * 10, box[2] * 10);
  for (int a = 0; a < na; a++) fprintf(ref, "%.9f %.9f %.9f\n", x[a][0] * 10, x[a][1] * 10, x[a][2] * 10);
  free(x);
}

static void write_files(void **state)
{
  (void)state;
  io_scene s;
  io_scene_build(&s, RL_UNITS_REAL, NAMES, COUNTS, 2, 1.5, 1);
  const char *dcd = "io_traj.dcd", *pdb = "io_traj.pdb";
  assert_int_equal(rl_pdb_write(pdb, s.sys, s.mols), RL_OK);
  rl_dcd *d = rl_dcd_create(dcd, s.sys, 30, 10, 0.002, "rotleap test_io_dcd");
  assert_non_null(d);
  int na = rl_io_natoms(s.sys);
  long fb = 56L + 3L * (8L + 4L * na);
  double boxes[6][3];
  for (int f = 0; f < 4; f++) {
    double L = 1.5 + 0.01 * f;
    boxes[f][0] = L; boxes[f][1] = L + 0.1; boxes[f][2] = L + 0.2;
    assert_int_equal(rl_system_lattice(s.sys, boxes[f], RL_LATTICE_FCC, 1, 100 + (unsigned long)f), RL_OK);
    assert_int_equal((rl_system_set_box(s.sys, boxes[f]), rl_dcd_write_frame(d, s.sys)), RL_OK);
  }
  CHECK_TRUE("DCD header NSET counts frames as they are written", header_nset(dcd) == 4);
  assert_int_equal(rl_dcd_sync(d), RL_OK);
  assert_int_equal(rl_dcd_close(d), RL_OK);
  CHECK_TRUE("DCD DELTA: 0.002 ps in AKMA units (/ 0.04888821), as CHARMM and NAMD store it",
             header_delta(dcd) == (float)(0.002 / 0.04888821));
  long hb = 0, fbl = 0;
  assert_int_equal(rl_dcd_layout(dcd, &hb, &fbl), RL_OK);
  CHECK_TRUE("rl_dcd_layout: 276-byte header, frames of 56 + 3 (8 + 4 natom) bytes", hb == 276 && fbl == fb);
  CHECK_TRUE("DCD size = 276-byte header + 4 frames x (56 + 3 (8 + 4 natom))", file_size(dcd) == 276 + 4 * fb);
  long istart = -1, nsavc = -1, nframes = -1;
  assert_int_equal(rl_dcd_info(dcd, &istart, &nsavc, &nframes), RL_OK);
  CHECK_TRUE("rl_dcd_info: first step 30, a frame every 10 steps, 4 frames", istart == 30 && nsavc == 10 && nframes == 4);
  CHECK_MSG("rl_dcd_info: a PDB is not a DCD", rl_dcd_info(pdb, NULL, NULL, NULL) != RL_OK, 1, "not a little-endian CORD DCD");

  /* restart: keep 2 frames, append 2 new ones */
  d = rl_dcd_append(dcd, s.sys, 2);
  assert_non_null(d);
  CHECK_TRUE("DCD append: truncated to the 2 frames kept", header_nset(dcd) == 2 && file_size(dcd) == 276 + 2 * fb);
  for (int f = 4; f < 6; f++) {
    double L = 1.5 + 0.01 * f;
    boxes[f][0] = L; boxes[f][1] = L + 0.1; boxes[f][2] = L + 0.2;
    assert_int_equal(rl_system_lattice(s.sys, boxes[f], RL_LATTICE_FCC, 1, 100 + (unsigned long)f), RL_OK);
    assert_int_equal((rl_system_set_box(s.sys, boxes[f]), rl_dcd_write_frame(d, s.sys)), RL_OK);
  }
  assert_int_equal(rl_dcd_close(d), RL_OK);
  CHECK_TRUE("DCD append: 4 frames after the restart", header_nset(dcd) == 4 && file_size(dcd) == 276 + 4 * fb);
  CHECK_MSG("DCD append: keeping more frames than present is an error", rl_dcd_append(dcd, s.sys, 9) == NULL,
            1, "holds 4 complete frames, cannot keep 9");
  io_scene t;
  int other[2] = {27, 6};
  io_scene_build(&t, RL_UNITS_REAL, NAMES, other, 2, 1.5, 1);
  CHECK_MSG("DCD append: a different atom count is an error", rl_dcd_append(dcd, t.sys, 1) == NULL, 1,
            "DCD has 113 atoms, the system writes 114");
  io_scene_free(&t);
  const char *lj[1] = {"stockmayer"};
  int one[1] = {8};
  io_scene_build(&t, RL_UNITS_LJ, lj, one, 1, 3.0, 1);
  rl_dcd *e = rl_dcd_create("io_lj.dcd", t.sys, 0, 5, 0.004, NULL);
  assert_non_null(e);
  assert_int_equal(rl_dcd_close(e), RL_OK);
  CHECK_TRUE("DCD DELTA of an lj system: the reduced time step as it is", header_delta("io_lj.dcd") == 0.004f);
  unlink("io_lj.dcd");
  io_scene_free(&t);

  /* the reference: frames 0, 1 (kept) and 4, 5 (appended) */
  FILE *ref = fopen("io_traj_ref.txt", "w");
  assert_non_null(ref);
  fprintf(ref, "natoms %d\nnframes 4\nnresidues %d\n", na, rl_system_count(s.sys));
  fprintf(ref, "timestep_ps 0.002\ninterval 10\nfirst_step 30\n"); /* as given to rl_dcd_create */
  fprintf(ref, "names O H1 H2 MW AR\n");
  for (int f = 0; f < 6; f++) {
    if (f == 2 || f == 3) continue;
    assert_int_equal(rl_system_lattice(s.sys, boxes[f], RL_LATTICE_FCC, 1, 100 + (unsigned long)f), RL_OK);
    ref_frame(ref, s.sys, boxes[f]);
  }
  /* the PDB holds the state at write time (frame "-1": the initial lattice) */
  assert_int_equal(rl_system_lattice(s.sys, s.box, RL_LATTICE_FCC, 1, 1), RL_OK);
  fprintf(ref, "pdb\n");
  ref_frame(ref, s.sys, s.box);
  fclose(ref);
  printf("info  wrote %s, %s, io_traj_ref.txt (%d atoms)\n", dcd, pdb, na);
  io_scene_free(&s);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(write_files)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
