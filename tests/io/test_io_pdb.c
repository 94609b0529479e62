/* PDB: write -> read recovers centres and orientations through the least-squares site fit;
 * molecules split by the periodic box are made whole; malformed lines, wrong geometries and
 * wrong atom counts give errors naming the line and residue.
 *
 * Tolerance: PDB stores 3 decimals in Angstrom, so every site coordinate is rounded by up to
 * 5e-4 A (5e-5 nm).  The fitted centre averages such errors: |dr| <= 5e-5 nm per component, we
 * allow 1e-4 nm (1e-3 A).  A rotation is determined by sites ~0.5-1.2 A from the centre, so a
 * 5e-4 A error tilts it by <~ 1e-3 rad: we allow 2e-3 in each element of A (and of rho).  The RMS
 * fit error itself is a measure of the rounding (uniform, sd 2.9e-4 A per component): <= 1e-3 A. */
#include "io_testutil.h"

static const char *NAMES[4] = {"tip4p", "co2", "ch4", "Ar"};
static const int COUNTS[4] = {24, 8, 8, 8};

static void read_lines(const char *path, char lines[][128], int *n)
{
  FILE *fp = fopen(path, "r");
  assert_non_null(fp);
  *n = 0;
  while (*n < 256 && fgets(lines[*n], 128, fp)) (*n)++;
  fclose(fp);
}

static void write_lines(const char *path, char lines[][128], int n)
{
  FILE *fp = fopen(path, "w");
  assert_non_null(fp);
  for (int i = 0; i < n; i++) fputs(lines[i], fp);
  fclose(fp);
}

static void compare(const rl_system *a, const rl_system *b, double *dr, double *dA)
{
  *dr = *dA = 0.0;
  for (int i = 0; i < rl_system_count(a); i++) {
    double x[9], y[9];
    rl_system_get_position(a, i, x);
    rl_system_get_position(b, i, y);
    *dr = fmax(*dr, max_abs_diff(x, y, 3));
    rl_kind k = rl_system_species_kind(a, rl_system_species_of(a, i));
    if (k == RL_KIND_POINT) continue;
    if (k == RL_KIND_LINEAR || k == RL_KIND_DIPOLE) {
      rl_system_get_axis(a, i, x);
      rl_system_get_axis(b, i, y);
      *dA = fmax(*dA, max_abs_diff(x, y, 3));
    } else {
      rl_system_get_orientation(a, i, x);
      rl_system_get_orientation(b, i, y);
      *dA = fmax(*dA, max_abs_diff(x, y, 9));
    }
  }
}

static void round_trip(void **state)
{
  (void)state;
  io_scene s, t;
  io_scene_build(&s, RL_UNITS_REAL, NAMES, COUNTS, 4, 2.2, 7);
  io_scene_build(&t, RL_UNITS_REAL, NAMES, COUNTS, 4, 2.2, 8);
  char path[256];
  io_path(path, sizeof path, "rt.pdb");
  assert_int_equal(rl_pdb_write(path, s.sys, s.mols), RL_OK);
  int nres;
  double box[3], rms;
  assert_int_equal(rl_pdb_count(path, RL_UNITS_REAL, &nres, box), RL_OK);
  CHECK_TRUE("count: residues = molecules, CRYST1 box read back (nm)",
             nres == rl_system_count(s.sys) && fabs(box[0] - 2.2) < 1e-9 && fabs(box[2] - 2.2) < 1e-9);
  int st = rl_pdb_read_state(path, t.sys, t.mols, 0.0, &rms, box);
  if (st) printf("error: %s\n", rl_last_error());
  assert_int_equal(st, RL_OK);
  double dr, dA;
  compare(s.sys, t.sys, &dr, &dA);
  CHECK_LE("PDB round trip: max |r - r0| (nm), centres", dr, 1e-4);
  CHECK_LE("PDB round trip: max |A - A0| (water, CH4) and |rho - rho0| (CO2)", dA, 2e-3);
  CHECK_LE("PDB round trip: largest RMS site fit error (nm)", rms, 1e-4);

  /* TIP4P's massless site is written MW; names match the catalogue's sites */
  char lines[256][128];
  int n;
  read_lines(path, lines, &n);
  CHECK_TRUE("TIP4P atom names O, H1, H2, MW in residue TIP",
             contains(lines[2], " O   TIP A   1") && contains(lines[3], " H1  TIP") && contains(lines[5], " MW  TIP"));

  /* a molecule split by the periodic boundary: shift H1 of residue 1 by one box length in x */
  double x = atof(lines[3] + 30) + 22.0;
  char num[16];
  snprintf(num, sizeof num, "%8.3f", x);
  memcpy(lines[3] + 30, num, 8);
  write_lines(path, lines, n);
  assert_int_equal(rl_pdb_read_state(path, t.sys, t.mols, 0.0, &rms, NULL), RL_OK);
  compare(s.sys, t.sys, &dr, &dA);
  CHECK_LE("molecule split across the box is made whole: max |r - r0| (nm)", dr, 1e-4);
  CHECK_LE("molecule split across the box is made whole: max |A - A0|", dA, 2e-3);
  unlink(path);
  io_scene_free(&s);
  io_scene_free(&t);
}

static void errors(void **state)
{
  (void)state;
  io_scene s, t;
  const char *w3[1] = {"tip3p"}, *spce[1] = {"spc-e"}, *w4[1] = {"tip4p"};
  int c8[1] = {8};
  io_scene_build(&s, RL_UNITS_REAL, w3, c8, 1, 1.0, 7);
  char path[256];
  io_path(path, sizeof path, "err.pdb");
  assert_int_equal(rl_pdb_write(path, s.sys, s.mols), RL_OK);

  io_scene_build(&t, RL_UNITS_REAL, spce, c8, 1, 1.0, 9);
  CHECK_MSG("TIP3P geometry read as SPC/E: rejected, naming residue and line",
            rl_pdb_read_state(path, t.sys, t.mols, 0.0, NULL, NULL), RL_EINVAL,
            ":3: residue TIP 1 (molecule 1): its geometry does not match species 'spc-e': RMS fit error");
  io_scene_free(&t);
  io_scene_build(&t, RL_UNITS_REAL, w4, c8, 1, 1.0, 9);
  CHECK_MSG("3-site residues read as TIP4P: atom count error", rl_pdb_read_state(path, t.sys, t.mols, 0.0, NULL, NULL),
            RL_EINVAL, ":3: residue TIP 1 (molecule 1) has 3 atoms, species 'tip4p' has 4 sites");
  io_scene_free(&t);

  char lines[256][128];
  int n;
  read_lines(path, lines, &n);
  memcpy(lines[5] + 38, "  12.x45", 8); /* y of atom 3 */
  write_lines(path, lines, n);
  CHECK_MSG("malformed coordinate: error with the line number and columns",
            rl_pdb_read_state(path, s.sys, s.mols, 0.0, NULL, NULL), RL_EINVAL,
            ":6: y in columns 39-46 is not a number: '12.x45'");
  assert_int_equal(rl_pdb_write(path, s.sys, s.mols), RL_OK);
  read_lines(path, lines, &n);
  lines[7][40] = '\n';
  lines[7][41] = '\0';
  write_lines(path, lines, n);
  CHECK_MSG("short ATOM record: error with the line number", rl_pdb_read_state(path, s.sys, s.mols, 0.0, NULL, NULL),
            RL_EINVAL, ":8: ATOM record has 40 columns, coordinates need 54");
  assert_int_equal(rl_pdb_write(path, s.sys, s.mols), RL_OK);
  read_lines(path, lines, &n);
  memcpy(lines[1] + 33, "  60.00", 7);
  write_lines(path, lines, n);
  CHECK_MSG("non-orthorhombic CRYST1: error with the line", rl_pdb_read_state(path, s.sys, s.mols, 0.0, NULL, NULL),
            RL_EINVAL, ":2: CRYST1 angles 60.00");
  unlink(path);
  io_scene_free(&s);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(round_trip),
      cmocka_unit_test(errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
