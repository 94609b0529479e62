/* Extended XYZ with orientation columns: write -> read for Stockmayer dipoles and 2CLJ linear
 * molecules (reduced units) and for CO2 (real units, Angstrom in the file); header format;
 * bad input (non-unit orientation, wrong species, missing orientation) names the line. */
#include "io_testutil.h"

static void check_round_trip(rl_units units, const char *const *names, const int *counts, int ns, double L,
                             const char *label)
{
  io_scene s, t;
  io_scene_build(&s, units, names, counts, ns, L, 21);
  io_scene_build(&t, units, names, counts, ns, L, 22);
  char path[256], name[128];
  io_path(path, sizeof path, "rt.xyz");
  assert_int_equal(rl_xyz_write(path, s.sys, 3.5, 700), RL_OK);
  double box[3];
  int st = rl_xyz_read_state(path, t.sys, box);
  if (st) printf("error: %s\n", rl_last_error());
  assert_int_equal(st, RL_OK);
  double dr = 0.0;
  int axes_equal = 1;
  for (int i = 0; i < rl_system_count(s.sys); i++) {
    double x[3], y[3];
    rl_system_get_position(s.sys, i, x);
    rl_system_get_position(t.sys, i, y);
    dr = fmax(dr, max_abs_diff(x, y, 3));
    rl_system_get_axis(s.sys, i, x);
    rl_system_get_axis(t.sys, i, y);
    axes_equal &= memcmp(x, y, sizeof x) == 0;
  }
  /* positions are printed with 10 decimals in file units: error <= 5e-11 file units */
  snprintf(name, sizeof name, "%s: max |r - r0| (system units)", label);
  CHECK_LE(name, dr, units == RL_UNITS_REAL ? 1e-11 : 1e-10);
  snprintf(name, sizeof name, "%s: orientation axes bit for bit (%%.17g)", label);
  CHECK_TRUE(name, axes_equal);
  snprintf(name, sizeof name, "%s: Lattice read back as the box", label);
  CHECK_TRUE(name, fabs(box[0] - L) < 1e-10 && fabs(box[1] - L) < 1e-10);
  unlink(path);
  io_scene_free(&s);
  io_scene_free(&t);
}

static void round_trip(void **state)
{
  (void)state;
  const char *lj[2] = {"stockmayer", "2clj"};
  int c[2] = {32, 16};
  check_round_trip(RL_UNITS_LJ, lj, c, 2, 4.0, "extxyz Stockmayer + 2CLJ (lj)");
  const char *re[2] = {"co2", "Ar"};
  check_round_trip(RL_UNITS_REAL, re, c, 2, 3.0, "extxyz CO2 + Ar (real, Angstrom)");
}

static void header(void **state)
{
  (void)state;
  const char *lj[1] = {"stockmayer"};
  int c[1] = {4};
  io_scene s;
  io_scene_build(&s, RL_UNITS_LJ, lj, c, 1, 2.0, 3);
  char path[256], line[512];
  io_path(path, sizeof path, "hdr.xyz");
  assert_int_equal(rl_xyz_write(path, s.sys, 0.0, 0), RL_OK);
  FILE *fp = fopen(path, "r");
  assert_non_null(fp);
  assert_non_null(fgets(line, sizeof line, fp));
  CHECK_TRUE("extxyz line 1 is the count", strcmp(line, "4\n") == 0);
  assert_non_null(fgets(line, sizeof line, fp));
  CHECK_TRUE("extxyz line 2 has Lattice= and the OVITO/ASE Properties= string",
             contains(line, "Lattice=\"2.0000000000 0 0 0 2.0000000000 0 0 0 2.0000000000\"") &&
             contains(line, "Properties=species:S:1:pos:R:3:orientation:R:3:name:S:1"));
  assert_non_null(fgets(line, sizeof line, fp));
  CHECK_TRUE("extxyz body line: X (ASE's dummy element), centre, axis, species name",
             strncmp(line, "X ", 2) == 0 && contains(line, " stockmayer\n"));
  fclose(fp);

  /* bad inputs */
  fp = fopen(path, "w");
  fprintf(fp, "4\nProperties=species:S:1:pos:R:3:orientation:R:3\n");
  fprintf(fp, "stockmayer 0 0 0 0 0 1\nstockmayer 1 0 0 0 0.5 0.5\nstockmayer 0 1 0 1 0 0\nstockmayer 1 1 0 0 1 0\n");
  fclose(fp);
  CHECK_MSG("non-unit orientation: error with the line", rl_xyz_read_state(path, s.sys, NULL), RL_EINVAL,
            ":4: orientation (0, 0.5, 0.5) is not a unit vector");
  fp = fopen(path, "w");
  fprintf(fp, "4\nProperties=species:S:1:pos:R:3\n");
  fprintf(fp, "stockmayer 0 0 0\nstockmayer 1 0 0\nstockmayer 0 1 0\nstockmayer 1 1 0\n");
  fclose(fp);
  CHECK_MSG("dipoles without an orientation column: error", rl_xyz_read_state(path, s.sys, NULL), RL_EINVAL,
            ":3: body 1 ('stockmayer', dipole) needs an orientation column");
  fp = fopen(path, "w");
  fprintf(fp, "4\ncomment\nstockmayer 0 0 0 0 0 1\nAr 1 0 0 0 0 1\n");
  fclose(fp);
  CHECK_MSG("wrong species label: error with the line", rl_xyz_read_state(path, s.sys, NULL), RL_EINVAL,
            ":4: species 'Ar', but body 2 is a 'stockmayer'");
  fp = fopen(path, "w");
  fprintf(fp, "4\ncomment\nstockmayer 0 0 0 0 0 1\nstockmayer 1 zero 0 0 0 1\n");
  fclose(fp);
  CHECK_MSG("malformed number: error with line and column", rl_xyz_read_state(path, s.sys, NULL), RL_EINVAL,
            ":4: column 3 is not a number: 'zero'");
  fp = fopen(path, "w");
  fprintf(fp, "5\ncomment\n");
  for (int i = 0; i < 5; i++) fprintf(fp, "stockmayer %d 0 0 0 0 1\n", i);
  fclose(fp);
  CHECK_MSG("count mismatch", rl_xyz_read_state(path, s.sys, NULL), RL_EINVAL, ":1: 5 particles, the system has 4");
  unlink(path);
  io_scene_free(&s);
}

/* io_ase.xyz (two frames of a Stockmayer + 2CLJ trajectory written as `rotleap run` writes one)
 * and io_ase_ref.txt (what was written, full precision) for ase_read.py (test_io_ase). */
static void for_ase(void **state)
{
  (void)state;
  const char *lj[2] = {"stockmayer", "2clj"};
  int c[2] = {6, 4};
  io_scene s;
  io_scene_build(&s, RL_UNITS_LJ, lj, c, 2, 3.0, 5);
  FILE *fp = fopen("io_ase.xyz", "w"), *ref = fopen("io_ase_ref.txt", "w");
  assert_non_null(fp);
  assert_non_null(ref);
  for (int f = 0; f < 2; f++) {
    if (f) assert_int_equal(rl_system_lattice(s.sys, s.box, RL_LATTICE_FCC, 1, 77), RL_OK);
    assert_int_equal(rl_xyz_write_frame(fp, "io_ase.xyz", s.sys, 0.25 * f, 50L * f), RL_OK);
    fprintf(ref, "frame %ld %.17g %.17g %.17g %.17g\n", 50L * f, 0.25 * f, s.box[0], s.box[1], s.box[2]);
    for (int i = 0; i < rl_system_count(s.sys); i++) {
      double r[3], o[3];
      rl_system_get_position(s.sys, i, r);
      rl_system_get_axis(s.sys, i, o);
      fprintf(ref, "%s %.17g %.17g %.17g %.17g %.17g %.17g\n", lj[rl_system_species_of(s.sys, i)], r[0], r[1], r[2],
              o[0], o[1], o[2]);
    }
  }
  fclose(fp);
  fclose(ref);
  printf("info  wrote io_ase.xyz and io_ase_ref.txt (%d bodies, 2 frames)\n", rl_system_count(s.sys));
  io_scene_free(&s);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(round_trip),
      cmocka_unit_test(header),
      cmocka_unit_test(for_ase),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
