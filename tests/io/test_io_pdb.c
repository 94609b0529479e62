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
  char lines[256][128];
  int n;
  read_lines(path, lines, &n);
  io_scene_build(&t, RL_UNITS_REAL, w4, c8, 1, 1.0, 9);
  lines[3][0] = 'X'; /* H1 of residue 1 gone: 2 atoms */
  write_lines(path, lines, n);
  CHECK_MSG("2-atom residue read as TIP4P: atom count error", rl_pdb_read_state(path, t.sys, t.mols, 0.0, NULL, NULL),
            RL_EINVAL, ":3: residue TIP 1 (molecule 1) has 2 atoms, species 'tip4p' has 4 sites (or 3 without its massless sites)");
  lines[3][0] = 'A';
  write_lines(path, lines, n);
  io_scene_free(&t);
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

/* Rewrite the ATOM/HETATM records of a PDB: residue name (columns 18-21) and atom name (13-16)
 * through the tables {from, to, ...} (NULL-terminated; to "" drops the atom), and write the
 * residues whose (new) name is first[0], first[1], ... first, the rest after, in file order. */
static void rename_pdb(const char *in, const char *out, const char *const *res, const char *const *atoms,
                       const char *const *first)
{
  char lines[256][128], outl[256][128];
  int n, m = 0;
  read_lines(in, lines, &n);
  for (int i = 0; i < n; i++) {
    char *l = lines[i];
    if (strncmp(l, "ATOM", 4) && strncmp(l, "HETATM", 6)) continue;
    for (int j = 0; res[j]; j += 2)
      if (!strncmp(l + 17, res[j], strlen(res[j])) && l[17 + strlen(res[j])] == ' ') {
        char f[8];
        snprintf(f, sizeof f, "%-4s", res[j + 1]);
        memcpy(l + 17, f, 4);
        break;
      }
    char nm[8];
    sscanf(l + 12, "%4s", nm);
    for (int j = 0; atoms[j]; j += 2)
      if (!strcmp(nm, atoms[j])) {
        char f[8];
        if (!atoms[j + 1][0]) { l[0] = '\0'; break; }
        snprintf(f, sizeof f, strlen(atoms[j + 1]) < 4 ? " %-3s" : "%-4s", atoms[j + 1]);
        memcpy(l + 12, f, 4);
        break;
      }
  }
  int atom[256];
  for (int i = 0; i < n; i++) atom[i] = !strncmp(lines[i], "ATOM", 4) || !strncmp(lines[i], "HETATM", 6);
  for (int i = 0; i < n; i++) /* the header */
    if (!atom[i] && !strncmp(lines[i], "CRYST1", 6)) memcpy(outl[m++], lines[i], 128);
  for (int f = 0; first[f]; f++) /* the residues named first[f] */
    for (int i = 0; i < n; i++)
      if (atom[i] && lines[i][0] && !strncmp(lines[i] + 17, first[f], strlen(first[f])) &&
          lines[i][17 + strlen(first[f])] == ' ') {
        memcpy(outl[m++], lines[i], 128);
        lines[i][0] = '\0';
      }
  for (int i = 0; i < n; i++) /* the rest */
    if (atom[i] && lines[i][0]) memcpy(outl[m++], lines[i], 128);
  snprintf(outl[m++], 128, "END\n");
  write_lines(out, outl, m);
}

/* Read path into t (its state first scrambled: a lattice of another seed) and compare with s:
 * 1 if read and equal to the PDB's resolution. */
static int read_as(const io_scene *s, io_scene *t, const char *path, const rl_pdb_residue *map, int nmap)
{
  for (int i = 0; i < rl_system_count(t->sys); i++) {
    double r[3] = {0.1 * (i % 7), 0.2 * (i % 5), 0.3 * (i % 3)};
    assert_int_equal(rl_system_set_position(t->sys, i, r), RL_OK);
  }
  double rms, dr, dA;
  const int st = rl_pdb_read_state_residues(path, t->sys, t->mols, map, nmap, 0.0, &rms, NULL);
  if (st) printf("error: %s\n", rl_last_error());
  compare(s->sys, t->sys, &dr, &dA);
  return st == RL_OK && dr < 1e-4 && dA < 2e-3 && rms < 1e-4;
}

/* A mixture (water + Na+ + Cl-) read back from the names other codes write: GROMACS (SOL with
 * OW HW1 HW2 MW, NA, CL), OpenMM (HOH with O H1 H2 M and the ions first), AMBER (WAT with EPW),
 * and a 3-site file of the 4-site model (M placed by the fit); the residues of a species are
 * its molecules in file order wherever they stand.  And the errors, naming file and line. */
static void mixture(void **state)
{
  (void)state;
  const char *names[3] = {"tip4p-ew", "na-tip4pew", "cl-tip4pew"};
  const int counts[3] = {12, 3, 3};
  io_scene s, t;
  io_scene_build(&s, RL_UNITS_REAL, names, counts, 3, 1.5, 7);
  io_scene_build(&t, RL_UNITS_REAL, names, counts, 3, 1.5, 8);
  char path[256], mixp[256];
  io_path(path, sizeof path, "mix.pdb");
  io_path(mixp, sizeof mixp, "mix2.pdb");
  assert_int_equal(rl_pdb_write(path, s.sys, s.mols), RL_OK);
  static const char *const none[] = {NULL};
  static const char *const gmx_res[] = {"TIP", "SOL", "NAT", "NA", "CLT", "CL", NULL};
  static const char *const gmx_atoms[] = {"O", "OW", "H1", "HW1", "H2", "HW2", "Na", "NA", "Cl", "CL", NULL};
  rename_pdb(path, mixp, gmx_res, gmx_atoms, none);
  CHECK_TRUE("GROMACS names (SOL: OW HW1 HW2 MW; NA; CL) read", read_as(&s, &t, mixp, NULL, 0));
  static const char *const omm_res[] = {"TIP", "HOH", "NAT", "NA", "CLT", "CL", NULL};
  static const char *const omm_atoms[] = {"MW", "M", NULL};
  static const char *const ions_first[] = {"CL", "NA", NULL};
  rename_pdb(path, mixp, omm_res, omm_atoms, ions_first);
  CHECK_TRUE("OpenMM names (HOH: O H1 H2 M), Cl- and Na+ residues first in the file", read_as(&s, &t, mixp, NULL, 0));
  static const char *const amb_res[] = {"TIP", "WAT", "NAT", "Na+", "CLT", "Cl-", NULL};
  static const char *const amb_atoms[] = {"MW", "EPW", NULL};
  rename_pdb(path, mixp, amb_res, amb_atoms, none);
  CHECK_TRUE("AMBER names (WAT: O H1 H2 EPW; Na+, Cl-) read", read_as(&s, &t, mixp, NULL, 0));
  static const char *const three[] = {"MW", "", NULL};
  rename_pdb(path, mixp, omm_res, three, none);
  CHECK_TRUE("3-atom waters of the 4-site model: M placed by the fit of O, H1, H2", read_as(&s, &t, mixp, NULL, 0));

  /* a residue name no species has; then the same name mapped */
  static const char *const odd_res[] = {"TIP", "XYZ", NULL};
  rename_pdb(path, mixp, odd_res, none, none);
  CHECK_MSG("unknown residue name: error naming line and residue, and the way out",
            rl_pdb_read_state(mixp, t.sys, t.mols, 0.0, NULL, NULL), RL_EINVAL,
            ":2: residue XYZ 1: no species of the system (tip4p-ew, na-tip4pew, cl-tip4pew) has the residue name 'XYZ'; "
            "map it to one (a deck's system.residues = XYZ:SPECIES)");
  rl_pdb_residue map[1] = {{"xyz", 0}};
  CHECK_TRUE("the residue name mapped (any case) to the water", read_as(&s, &t, mixp, map, 1));
  /* one Na+ more than the system has: Cl- residues named NA */
  static const char *const na4[] = {"TIP", "HOH", "NAT", "NA", "CLT", "NA", NULL};
  rename_pdb(path, mixp, na4, none, none);
  CHECK_MSG("more residues of a species than molecules: error at the first extra",
            rl_pdb_read_state(mixp, t.sys, t.mols, 0.0, NULL, NULL), RL_EINVAL,
            ": residue NA 16 is molecule 4 of species 'na-tip4pew' (residues from line ");
  /* a two-water mixture: HOH is ambiguous */
  const char *w2[3] = {"tip4p-ew", "tip3p", "na-tip4pew"};
  io_scene u;
  io_scene_build(&u, RL_UNITS_REAL, w2, counts, 3, 1.5, 8);
  rename_pdb(path, mixp, omm_res, none, none);
  CHECK_MSG("a default alias that fits two species: error, asking for the map",
            rl_pdb_read_state(mixp, u.sys, u.mols, 0.0, NULL, NULL), RL_EINVAL,
            ":2: residue HOH 1: more than one species of the system (tip4p-ew, tip3p, na-tip4pew) has the residue name 'HOH'");
  io_scene_free(&u);
  /* an atom name no site has */
  static const char *const bad_atom[] = {"H2", "HX", NULL};
  rename_pdb(path, mixp, omm_res, bad_atom, none);
  CHECK_MSG("an atom that is no site: error naming line, residue and site",
            rl_pdb_read_state(mixp, t.sys, t.mols, 0.0, NULL, NULL), RL_EINVAL,
            ":4: residue HOH 1 atom 'HX' is not site 3 'H2' of species 'tip4p-ew'");
  unlink(mixp);
  unlink(path);
  io_scene_free(&s);
  io_scene_free(&t);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(round_trip),
      cmocka_unit_test(errors),
      cmocka_unit_test(mixture),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
