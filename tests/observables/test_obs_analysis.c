/* rotleap run's analysis layer (app/analysis.c) fed by hand-made configurations and step reports:
 * which vector the P1/P2 columns follow (molecular dipole, molecular axis, or n/a with a reason),
 * the MSD of wrapped positions, the NVT fluctuation formulas at the thermostat's target T0 (NVE
 * keeps Lebowitz-Percus-Verlet), the dielectric constant's error bar and its short-run note, and
 * failed writes of PREFIX.results.txt, .rdf.csv and .tcf.csv. */
#include "../testutil.h"

#include "analysis.h"

#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#define WORK "analysis_work"

typedef struct {
  rl_deck d;
  rl_molecule mol;
  rl_system *sys;
  analysis *a;
  char prefix[256];
} fixture;

/* A deck NAME.ini under WORK with `body` (its [output] prefix is WORK/NAME), the system it
 * describes on its lattice, and the analysis of it. */
static void setup(fixture *fx, const char *name, const char *body)
{
  memset(fx, 0, sizeof *fx);
  mkdir(WORK, 0777);
  char path[300];
  snprintf(path, sizeof path, WORK "/%s.ini", name);
  snprintf(fx->prefix, sizeof fx->prefix, WORK "/%s", name);
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  /* every sample averaged (output.discard = 0) unless the test says otherwise */
  fprintf(f, "%s\n[output]\nprefix = %s\nprogress = no\n%s", body, fx->prefix, strstr(body, "discard") ? "" : "discard = 0\n");
  fclose(f);
  assert_int_equal(rl_deck_load(path, NULL, 0, &fx->d, stderr), 0);
  assert_int_equal(rl_model_build(fx->d.model, fx->d.params, fx->d.force_general, &fx->mol), RL_OK);
  fx->sys = rl_system_alloc(fx->d.units);
  rl_species_desc sd;
  rl_molecule_species(&fx->mol, &sd);
  assert_int_equal(rl_system_add_species(fx->sys, &sd, fx->d.count, NULL), RL_OK);
  assert_int_equal(rl_system_lattice(fx->sys, fx->d.box, fx->d.lattice, 1, 7), RL_OK);
  fx->a = analysis_alloc(&fx->d, &fx->mol, fx->sys);
  assert_non_null(fx->a);
}

static void teardown(fixture *fx)
{
  analysis_free(fx->a);
  rl_system_free(fx->sys);
}

/* Turn every body to a random orientation (axis bodies: a random axis). */
static void randomise(fixture *fx, gsl_rng *rng)
{
  const rl_kind k = rl_system_species_kind(fx->sys, 0);
  for (int i = 0; i < rl_system_count(fx->sys); i++) {
    double A[9];
    random_rotation(rng, A);
    if (k == RL_KIND_LINEAR || k == RL_KIND_DIPOLE) assert_int_equal(rl_system_set_axis(fx->sys, i, A + 6), RL_OK);
    else if (k != RL_KIND_POINT) assert_int_equal(rl_system_set_orientation(fx->sys, i, A), RL_OK);
  }
}

/* One step report: potential U (whole system), kinetic energy K, on-step T = 2K/(g kB). */
static void step(fixture *fx, double U, double K, int g)
{
  rl_step_info info;
  memset(&info, 0, sizeof info);
  info.has_energy = 1;
  info.potential = U;
  info.ke_trans = 0.6 * K;
  info.ke_rot = 0.4 * K;
  info.total = U + K;
  info.conserved = info.total;
  info.temperature = 2.0 * K / (g * rl_units_kB(fx->d.units));
  info.t_trans = info.t_rot = info.temperature;
  const int n = rl_system_count(fx->sys), nrot = rl_system_nrot(fx->sys);
  double(*fo)[3] = calloc((size_t)n, sizeof *fo), (*to)[3] = calloc((size_t)(nrot > 0 ? nrot : 1), sizeof *to);
  rl_forces F = {fo, to, 0.0, {0}, 0};
  assert_int_equal(analysis_step(fx->a, &info, 1.0, &F, fx->sys, NULL), RL_OK);
  free(fo);
  free(to);
}

static char *slurp(const char *path)
{
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  char *s = calloc(1, 1 << 22);
  size_t n = fread(s, 1, (1 << 22) - 1, f);
  s[n] = '\0';
  fclose(f);
  return s;
}

static char *output(const fixture *fx, const char *ext)
{
  char p[300];
  snprintf(p, sizeof p, "%s.%s", fx->prefix, ext);
  return slurp(p);
}

/* The number after "KEY = " at the start of a line of text, NAN if there is none. */
static double value_of(const char *text, const char *key)
{
  char pat[80];
  snprintf(pat, sizeof pat, "\n%s = ", key);
  const char *p = strstr(text, pat);
  if (!p) return NAN;
  char *end;
  double x = strtod(p + strlen(pat), &end);
  return end == p + strlen(pat) ? NAN : x;
}

static const char *line_of(const char *text, const char *key, char *buf, size_t n)
{
  char pat[80];
  snprintf(pat, sizeof pat, "\n%s = ", key);
  const char *p = strstr(text, pat);
  buf[0] = '\0';
  if (p) {
    size_t k = strcspn(p + 1, "\n");
    snprintf(buf, n, "%.*s", (int)(k < n - 1 ? k : n - 1), p + 1);
  }
  return buf;
}

/* ------------------------------------------------------------------ P1/P2: which vector */

static void orientation_columns(void **state)
{
  (void)state;
  static const struct {
    const char *model, *header, *p1_0, *why;
  } cases[] = {
      /* charged, no net dipole, linear: the axis rho (the dipoles were all zero: D1) */
      {"co2", "lag_time_ps,axis_P1,axis_P2,", "1", "molecular axis rho"},
      /* a molecular dipole where the molecules have one */
      {"tip4p", "lag_time_ps,dipole_P1,dipole_P2,", "1", "molecular dipole"},
      {"nh3", "lag_time_ps,dipole_P1,dipole_P2,", "1", "molecular dipole"},
      /* no charges, linear: the axis rho, named so */
      {"n2", "lag_time_ps,axis_P1,axis_P2,", "1", "molecular axis rho"},
      /* no net dipole, spherical top: no vector to follow */
      {"ch4", "lag_time_ps,dipole_P1,dipole_P2,", "n/a", "n/a (model ch4 has no net dipole"},
  };
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 11);
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    char body[400];
    snprintf(body, sizeof body, "[system]\nmodel = %s\ncount = 8\nbox = 3 nm\n[interactions]\ncutoff = 0.9 nm\n"
             "[run]\nsteps = 10\ntimestep = 2 fs\nensemble = nvt-bussi\ntemperature = 250 K\n", cases[c].model);
    fixture fx;
    char name[40];
    snprintf(name, sizeof name, "orient_%s", cases[c].model);
    setup(&fx, name, body);
    const int g = rl_system_dof(fx.sys);
    for (int k = 0; k < 12; k++) {
      randomise(&fx, rng);
      step(&fx, -100.0 + k, 0.5 * g * rl_units_kB(fx.d.units) * 250.0, g);
      assert_int_equal(analysis_sample(fx.a, fx.sys), RL_OK);
    }
    assert_int_equal(analysis_write(fx.a, fx.prefix, NULL, 0.02), RL_OK);
    char *tcf = output(&fx, "tcf.csv"), *res = output(&fx, "results.txt"), line[400];
    assert_non_null(tcf);
    assert_non_null(res);
    const int header_ok = strncmp(tcf, cases[c].header, strlen(cases[c].header)) == 0;
    char want[40];
    snprintf(want, sizeof want, "\n0,%s,%s,", cases[c].p1_0, cases[c].p1_0); /* lag 0: P1 = P2 = 1 */
    const int row_ok = strstr(tcf, want) != NULL;
    line_of(res, "orientation_vector", line, sizeof line);
    printf("check %-8s tcf header %s, lag 0 %s; results: %s\n", cases[c].model, header_ok ? "ok" : "FAIL",
           row_ok ? "ok" : "FAIL", line);
    assert_true(header_ok);
    assert_true(row_ok);
    assert_non_null(strstr(line, cases[c].why));
    free(tcf);
    free(res);
    teardown(&fx);
  }
  gsl_rng_free(rng);
}

/* ------------------------------------------------------------------ MSD of wrapped positions */

static void msd_wrapped(void **state)
{
  (void)state;
  fixture fx;
  setup(&fx, "msd", "[system]\nmodel = stockmayer\ncount = 8\nbox = 10\ntemperature = 1.35\n[interactions]\ncutoff = 2.5\n"
                    "[run]\nsteps = 10\ntimestep = 0.002\n");
  const int n = 8, frames = 12;
  const double L = 10.0, v[3] = {3.1, -2.3, 1.7}; /* per sample: below L/2, crossing the box */
  double r0[8][3];
  for (int i = 0; i < n; i++) rl_system_get_position(fx.sys, i, r0[i]);
  for (int k = 0; k < frames; k++) {
    for (int i = 0; i < n; i++) {
      double r[3];
      for (int d = 0; d < 3; d++) {
        r[d] = fmod(r0[i][d] + k * v[d], L);
        if (r[d] < 0.0) r[d] += L; /* the image in [0, L): wrapped as a trajectory writer would */
      }
      assert_int_equal(rl_system_set_position(fx.sys, i, r), RL_OK);
    }
    step(&fx, -40.0, 10.0, 40);
    assert_int_equal(analysis_sample(fx.a, fx.sys), RL_OK);
  }
  assert_int_equal(analysis_write(fx.a, fx.prefix, NULL, 0.1), RL_OK);
  char *tcf = output(&fx, "tcf.csv");
  assert_non_null(tcf);
  /* msd is the last column; lag k: (k |v|)^2 exactly */
  double err = 0.0;
  int rows = 0;
  const char *p = strchr(tcf, '\n');
  for (long k = 0; p && p[1]; k++, p = strchr(p + 1, '\n')) {
    const char *last = p + 1 + strcspn(p + 1, "\n");
    const char *c = last;
    while (c > p && *c != ',') c--;
    const double msd = strtod(c + 1, NULL), want = k * k * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    err = fmax(err, fabs(msd - want) / fmax(want, 1.0));
    rows++;
  }
  CHECK_NEAR("MSD rows (lags 0..frames/2)", rows, frames / 2 + 1, 0.0);
  CHECK_LE("MSD of wrapped positions vs (k |v|)^2, relative", err, 1e-5);
  /* the Einstein window docs/observables.md gives: lags L/5..L, L = frames/2 */
  char *res = output(&fx, "results.txt");
  printf("check Einstein window of %d samples: %s\n", frames, strstr(res, "(Einstein, MSD lags 1-6 samples;") ? "lags 1-6 ok" : "FAIL");
  assert_non_null(strstr(res, "(Einstein, MSD lags 1-6 samples;"));
  free(res);
  free(tcf);
  teardown(&fx);
}

/* ------------------------------------------------------------------ fluctuation formulas */

/* A Stockmayer deck for the fluctuation tests; its thermostat target is T0 = 1.35. */
#define SM_DECK(ensemble)                                                                          \
  "[system]\nmodel = stockmayer\ncount = 8\nbox = 10\ntemperature = 1.35\n[interactions]\ncutoff = 2.5\n" \
  "dipole = rf\neps_rf = 10\n[run]\nsteps = 10\ntimestep = 0.002\nensemble = " ensemble "\n"

static void nvt_uses_target_temperature(void **state)
{
  (void)state;
  static const char *ensembles[] = {SM_DECK("nvt-bussi\ntemperature = 1.35"), SM_DECK("nvt-langevin\ntemperature = 1.35"),
                                    SM_DECK("nvt-isokinetic\ntemperature = 1.35")};
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 5);
  for (int e = 0; e < 3; e++) {
    fixture fx;
    char name[32];
    snprintf(name, sizeof name, "nvt%d", e);
    setup(&fx, name, ensembles[e]);
    const int g = rl_system_dof(fx.sys), n = rl_system_count(fx.sys);
    const double T0 = 1.35, Tlow = 0.9 * T0; /* the on-step temperature reads low (large steps) */
    rl_series *U = rl_series_alloc();
    rl_dipole_acc *M = rl_dipole_acc_alloc();
    rl_species_ff sff = rl_molecule_ff(&fx.mol);
    for (int k = 0; k < 400; k++) {
      const double u = -50.0 + 3.0 * sin(0.37 * k) + gsl_ran_gaussian(rng, 1.0);
      const double K = 0.5 * g * Tlow * (1.0 + 0.05 * gsl_ran_gaussian(rng, 1.0));
      rl_series_add(U, u);
      step(&fx, u, K, g);
      if (k % 4 == 0) {
        randomise(&fx, rng);
        double Mk[3];
        assert_int_equal(rl_system_dipoles(fx.sys, &sff, 1, NULL, Mk), RL_OK);
        rl_dipole_acc_add(M, Mk);
        assert_int_equal(analysis_sample(fx.a, fx.sys), RL_OK);
      }
    }
    assert_int_equal(analysis_write(fx.a, fx.prefix, NULL, 0.02), RL_OK);
    char *res = output(&fx, "results.txt");
    assert_non_null(res);
    const double sdU = rl_series_sd(U);
    const double cv_want = (0.5 * g + sdU * sdU / (T0 * T0)) / n; /* f kB/2 + <dU^2>/(kB T0^2), kB = 1 */
    double eps_want;
    assert_int_equal(rl_dielectric_constant(rl_dipole_acc_fluct(M, NULL), 1000.0, T0, 10.0, RL_UNITS_LJ, 0.0, &eps_want),
                     RL_OK);
    const double cv = value_of(res, "heat_capacity_per_molecule"), eps = value_of(res, "dielectric_constant");
    printf("check %s: C_V/N %.6g (want %.6g), eps %.5g (want %.5g at T0)\n", fx.d.thermostat == RL_THERMO_BUSSI ? "bussi"
           : fx.d.thermostat == RL_THERMO_LANGEVIN ? "langevin" : "isokinetic", cv, cv_want, eps, eps_want);
    CHECK_LE("C_V per molecule at T0, relative", fabs(cv - cv_want) / cv_want, 1e-5);
    CHECK_LE("dielectric constant at T0, relative", fabs(eps - eps_want) / eps_want, 1e-3);
    if (e < 2) assert_non_null(strstr(res, "(canonical formula)"));
    free(res);
    rl_series_free(U);
    rl_dipole_acc_free(M);
    teardown(&fx);
  }
  gsl_rng_free(rng);
}

static void nve_keeps_lpv(void **state)
{
  (void)state;
  fixture fx;
  setup(&fx, "nve", SM_DECK("nve"));
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 6);
  const int g = rl_system_dof(fx.sys), n = rl_system_count(fx.sys);
  rl_series *K = rl_series_alloc();
  for (int k = 0; k < 400; k++) {
    const double kin = 0.5 * g * 1.2 * (1.0 + 0.1 * gsl_ran_gaussian(rng, 1.0));
    rl_series_add(K, kin);
    step(&fx, -50.0 - kin, kin, g); /* E conserved */
  }
  assert_int_equal(analysis_write(fx.a, fx.prefix, NULL, 0.02), RL_OK);
  char *res = output(&fx, "results.txt");
  assert_non_null(res);
  double cv_want;
  assert_int_equal(rl_heat_capacity_nve(rl_series_mean(K), rl_series_sd(K) * rl_series_sd(K), g, 1.0, &cv_want), RL_OK);
  cv_want /= n;
  CHECK_LE("NVE C_V per molecule: Lebowitz-Percus-Verlet, relative", fabs(value_of(res, "heat_capacity_per_molecule") - cv_want) / cv_want, 1e-5);
  assert_non_null(strstr(res, "Lebowitz-Percus-Verlet"));
  free(res);
  rl_series_free(K);
  gsl_rng_free(rng);
  teardown(&fx);
}

/* ------------------------------------------------------------------ dielectric: error and note */

static void dielectric_short_run(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 9);
  /* 8: too short for the blocking to find a plateau; 20: a plateau, but an error above 10 % of
   * eps - 1 (sd(M^2)/<M^2> ~ 0.8 for 8 random dipoles); 4000: enough, no note */
  static const int samples[3] = {8, 20, 4000};
  static const char *note_has[3] = {"found no plateau", "% of eps - 1", NULL};
  for (int c = 0; c < 3; c++) {
    fixture fx;
    char name[32];
    snprintf(name, sizeof name, "eps%d", samples[c]);
    setup(&fx, name, SM_DECK("nvt-bussi\ntemperature = 1.35"));
    const int g = rl_system_dof(fx.sys);
    for (int k = 0; k < samples[c]; k++) { /* independent orientations: tau = 1/2 sample */
      randomise(&fx, rng);
      step(&fx, -50.0 + gsl_ran_gaussian(rng, 1.0), 0.5 * g * 1.35, g);
      assert_int_equal(analysis_sample(fx.a, fx.sys), RL_OK);
    }
    assert_int_equal(analysis_write(fx.a, fx.prefix, NULL, 0.02), RL_OK);
    char *res = output(&fx, "results.txt"), line[400], note[400];
    line_of(res, "dielectric_constant", line, sizeof line);
    line_of(res, "dielectric_note", note, sizeof note);
    printf("check %d samples: %s | %s\n", samples[c], line, note[0] ? note : "(no note)");
    assert_non_null(strstr(line, " +- ")); /* a block error, never a bare number */
    if (note_has[c]) assert_non_null(strstr(note, note_has[c]));
    else assert_true(note[0] == '\0');
    if (c == 2) { /* random orientations: <dM^2> = N mu^2 = 8 x 3 exactly; the error bar covers it */
      double exact, eps = value_of(res, "dielectric_constant"), err = strtod(strstr(line, " +- ") + 4, NULL);
      assert_int_equal(rl_dielectric_constant(24.0, 1000.0, 1.35, 10.0, RL_UNITS_LJ, 0.0, &exact), RL_OK);
      printf("check eps %.5g +- %.2g against the exact %.5g\n", eps, err, exact);
      CHECK_LE("|eps - exact| / its error bar (4000 independent samples)", fabs(eps - exact) / err, 4.0);
      CHECK_LE("its error bar, relative to eps - 1", err / (exact - 1.0), 0.05);
    }
    free(res);
    teardown(&fx);
  }
  gsl_rng_free(rng);
}

/* ------------------------------------------------------------------ failed writes (CLI audit D6) */

static int tmp_files_left(void)
{
  DIR *dir = opendir(WORK);
  int n = 0;
  for (struct dirent *e; dir && (e = readdir(dir));) n += strstr(e->d_name, "wf.") && strstr(e->d_name, ".tmp.");
  if (dir) closedir(dir);
  return n;
}

static void write_failures(void **state)
{
  (void)state;
  static const char *which[] = {"rdf.csv", "tcf.csv", "results.txt"};
  for (int w = 0; w < 3; w++) {
    fixture fx;
    setup(&fx, "wf", "[system]\nmodel = stockmayer\ncount = 8\nbox = 10\ntemperature = 1.35\n[interactions]\ncutoff = 2.5\n"
                     "[run]\nsteps = 10\ntimestep = 0.002\n[output]\nrdf = S-S\n");
    for (int k = 0; k < 3; k++) {
      char p[300];
      snprintf(p, sizeof p, "%s.%s", fx.prefix, which[k]);
      remove(p);
      rmdir(p);
      if (k == w) assert_int_equal(mkdir(p, 0777), 0); /* stands for any failure: EISDIR on the rename */
    }
    for (int k = 0; k < 8; k++) {
      step(&fx, -40.0, 10.0, 40);
      assert_int_equal(analysis_sample(fx.a, fx.sys), RL_OK);
    }
    const int st = analysis_write(fx.a, fx.prefix, NULL, 0.02);
    const char *msg = rl_last_error();
    printf("check %s unwritable: status %d, message: %s\n", which[w], st, st ? msg : "");
    assert_int_not_equal(st, RL_OK);
    assert_non_null(strstr(msg, which[w]));
    assert_non_null(strstr(msg, strerror(EISDIR)));
    assert_int_equal(tmp_files_left(), 0);
    for (int k = 0; k < 3; k++) { /* the others are written whatever failed */
      char p[300];
      struct stat sb;
      snprintf(p, sizeof p, "%s.%s", fx.prefix, which[k]);
      assert_int_equal(stat(p, &sb), 0);
      assert_true(k == w ? S_ISDIR(sb.st_mode) : S_ISREG(sb.st_mode) && sb.st_size > 0);
    }
    if (w < 2) { /* results.txt says which file is missing, and why */
      char *res = output(&fx, "results.txt");
      assert_non_null(strstr(res, "# could not write"));
      assert_non_null(strstr(res, which[w]));
      free(res);
    }
    char p[300];
    snprintf(p, sizeof p, "%s.%s", fx.prefix, which[w]);
    rmdir(p);
    teardown(&fx);
  }
}

/* An RDF asked for, no configuration sampled (output.sample_every = 0): rl_rdf_get refuses, and
 * the file used to be written from uninitialised memory. */
static void rdf_without_samples(void **state)
{
  (void)state;
  fixture fx;
  setup(&fx, "nosample", "[system]\nmodel = stockmayer\ncount = 8\nbox = 10\ntemperature = 1.35\n"
                         "[interactions]\ncutoff = 2.5\n[run]\nsteps = 10\ntimestep = 0.002\n[output]\nrdf = S-S\n");
  remove(WORK "/nosample.rdf.csv");
  for (int k = 0; k < 8; k++) step(&fx, -40.0, 10.0, 40);
  assert_int_equal(analysis_write(fx.a, fx.prefix, NULL, 0.02), RL_OK);
  char *rdf = output(&fx, "rdf.csv"), *res = output(&fx, "results.txt");
  printf("check no sample: rdf.csv %s; results: %s\n", rdf ? "WRITTEN (FAIL)" : "absent", strstr(res, "\nrdf = n/a") ? "rdf = n/a" : "FAIL");
  assert_null(rdf);
  assert_non_null(strstr(res, "\nrdf = n/a ("));
  free(res);
  teardown(&fx);
}

/* ------------------------------------------------------------------ the journal (issue 30 item 13) */

/* The inputs of step k (the state sampled after it, every 4th step, and the step's report) are
 * drawn from a generator seeded with k, so that any run of steps [from, to) sees the same. */
static void feed(fixture *fx, long from, long to)
{
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  const int n = rl_system_count(fx->sys), g = rl_system_dof(fx->sys);
  for (long k = from; k < to; k++) {
    gsl_rng_set(rng, 1000 + (unsigned long)k);
    /* a relaxation (U from -30 to -50 over 100 steps) and noise */
    const double U = -50.0 + 20.0 * exp(-k / 100.0) + gsl_ran_gaussian(rng, 1.0);
    const double K = 0.5 * g * 1.35 * (1.0 + 0.05 * gsl_ran_gaussian(rng, 1.0));
    rl_step_info info;
    memset(&info, 0, sizeof info);
    info.t = k * fx->d.timestep;
    info.potential = U;
    info.ke_trans = 0.6 * K;
    info.ke_rot = 0.4 * K;
    info.total = U + K;
    info.conserved = info.total - 0.01 * k; /* the thermostat's work */
    info.temperature = info.t_trans = info.t_rot = 2.0 * K / (g * rl_units_kB(fx->d.units));
    double(*fo)[3] = calloc((size_t)n, sizeof *fo), (*to_)[3] = calloc((size_t)n, sizeof *to_);
    for (int i = 0; i < n; i++)
      for (int d = 0; d < 3; d++) {
        fo[i][d] = gsl_ran_gaussian(rng, 10.0);
        to_[i][d] = gsl_ran_gaussian(rng, 3.0);
      }
    rl_forces F = {fo, to_, 0.0, {0}, 0};
    assert_int_equal(analysis_step(fx->a, &info, gsl_ran_gaussian(rng, 1.0), &F, fx->sys, NULL), RL_OK);
    free(fo);
    free(to_);
    if ((k + 1) % 4) continue;
    randomise(fx, rng);
    for (int i = 0; i < n; i++) {
      double r[3], v[3], l[3];
      rl_system_get_position(fx->sys, i, r);
      for (int d = 0; d < 3; d++) {
        r[d] = fmod(2.5 * (i % 2 + 2 * (i / 2 % 2)) + (d == i % 3 ? 2.5 : 0.0) + 1.3 * d +
                    0.02 * k * (d + 1) + gsl_ran_gaussian(rng, 0.3) + 10.0, 10.0);
        v[d] = gsl_ran_gaussian(rng, 1.0);
        l[d] = gsl_ran_gaussian(rng, 0.5);
      }
      double rho[3];
      rl_system_get_axis(fx->sys, i, rho);
      const double lr = l[0] * rho[0] + l[1] * rho[1] + l[2] * rho[2];
      for (int d = 0; d < 3; d++) l[d] -= lr * rho[d]; /* no spin about the dipole's axis */
      assert_int_equal(rl_system_set_position(fx->sys, i, r), RL_OK);
      assert_int_equal(rl_system_set_velocity(fx->sys, i, v), RL_OK);
      assert_int_equal(rl_system_set_angmom(fx->sys, i, l), RL_OK);
    }
    assert_int_equal(analysis_sample(fx->a, fx->sys), RL_OK);
  }
  gsl_rng_free(rng);
}

#define JOURNAL_DECK                                                                                 \
  "[system]\nmodel = stockmayer\ncount = 8\nbox = 10\ntemperature = 1.35\n[interactions]\ncutoff = 2.5\n" \
  "dipole = rf\neps_rf = 10\n[run]\nsteps = 10\ntimestep = 0.002\nensemble = nvt-bussi\ntemperature = 1.35\n" \
  "[output]\nrdf = S-S\ndiscard = auto\n"

static int same_file(const char *a, const char *b)
{
  char *x = slurp(a), *y = slurp(b);
  const int same = x && y && !strcmp(x, y);
  free(x);
  free(y);
  return same;
}

static long file_size(const char *path)
{
  struct stat sb;
  return stat(path, &sb) ? -1 : (long)sb.st_size;
}

/* Steps 0..M-1 fed directly, and steps 0..K-1 journaled (and some beyond the checkpoint, as a
 * killed run leaves them), replayed into a fresh analysis up to the checkpoint's byte count and
 * continued to M: the same results, RDF and correlation files byte for byte, and the same
 * journal. */
static void journal_continuation(void **state)
{
  (void)state;
  const long M = 900, K = 517, KILLED = 530;
  fixture direct, first, cont;
  char jd[300], jj[300];
  setup(&direct, "jdirect", JOURNAL_DECK);
  snprintf(jd, sizeof jd, "%s.journal", direct.prefix);
  FILE *fd = fopen(jd, "wb");
  assert_int_equal(analysis_set_journal(direct.a, fd, jd), RL_OK);
  feed(&direct, 0, M);
  fclose(fd);
  assert_int_equal(analysis_write(direct.a, direct.prefix, NULL, 0.008), RL_OK);

  setup(&first, "jcont", JOURNAL_DECK);
  snprintf(jj, sizeof jj, "%s.journal", first.prefix);
  FILE *fj = fopen(jj, "wb");
  assert_int_equal(analysis_set_journal(first.a, fj, jj), RL_OK);
  feed(&first, 0, K);
  long nbytes = -1;
  assert_int_equal(analysis_journal_sync(first.a, &nbytes), RL_OK); /* the checkpoint records nbytes */
  feed(&first, K, KILLED); /* journaled after the checkpoint: a continuation drops them */
  fclose(fj);
  teardown(&first);
  printf("check the journal: %ld bytes at the checkpoint (step %ld), %ld in the file\n", nbytes, K, file_size(jj));
  assert_true(file_size(jj) > nbytes);

  setup(&cont, "jcont", JOURNAL_DECK);
  assert_int_equal(analysis_replay(cont.a, jj, nbytes), RL_OK);
  assert_int_equal(truncate(jj, nbytes), 0);
  fj = fopen(jj, "r+b");
  assert_non_null(fj);
  FILE *wrong = fopen(jj, "rb"); /* at byte 0, not where the replay ended */
  assert_int_equal(analysis_set_journal(cont.a, wrong, jj), RL_EINVAL);
  printf("check a journal not positioned at the replayed end is refused: %s\n", rl_last_error());
  assert_non_null(strstr(rl_last_error(), "cut it to"));
  fclose(wrong);
  assert_int_equal(fseek(fj, 0, SEEK_END), 0);
  assert_int_equal(analysis_set_journal(cont.a, fj, jj), RL_OK);
  feed(&cont, K, M);
  fclose(fj);
  assert_int_equal(analysis_write(cont.a, cont.prefix, NULL, 0.008), RL_OK);
  static const char *ext[] = {"results.txt", "rdf.csv", "tcf.csv"};
  for (int e = 0; e < 3; e++) {
    char a[300], b[300];
    snprintf(a, sizeof a, "%s.%s", direct.prefix, ext[e]);
    snprintf(b, sizeof b, "%s.%s", cont.prefix, ext[e]);
    const int same = same_file(a, b);
    printf("check %s of the continuation = the uninterrupted run's, byte for byte: %s\n", ext[e], same ? "ok" : "FAIL");
    assert_true(same);
  }
  const int same = same_file(jd, jj);
  printf("check the continued journal = the uninterrupted run's: %s\n", same ? "ok" : "FAIL");
  assert_true(same);
  char *res = output(&cont, "results.txt");
  assert_non_null(strstr(res, "steps with energies")); /* every step, not this invocation's */
  assert_non_null(strstr(res, "900 steps with energies"));
  free(res);
  teardown(&direct);
  teardown(&cont);
}

/* A journal that is cut short, cut inside a record, of another run, damaged or not a journal is
 * refused with a message naming the file and the cause; a write that fails is named too. */
static void journal_refused(void **state)
{
  (void)state;
  fixture fx;
  char jp[300];
  setup(&fx, "jbad", JOURNAL_DECK);
  snprintf(jp, sizeof jp, "%s.journal", fx.prefix);
  FILE *fp = fopen(jp, "wb");
  assert_int_equal(analysis_set_journal(fx.a, fp, jp), RL_OK);
  feed(&fx, 0, 40);
  long nbytes = -1;
  assert_int_equal(analysis_journal_sync(fx.a, &nbytes), RL_OK);
  fclose(fp);
  teardown(&fx);
  char deck[300];
  snprintf(deck, sizeof deck, "%s.ini", fx.prefix);
  /* a damaged copy: the second record's tag overwritten */
  char damaged[320];
  snprintf(damaged, sizeof damaged, "%s.damaged", jp);
  {
    char *buf = malloc((size_t)nbytes);
    FILE *in = fopen(jp, "rb"), *out = fopen(damaged, "wb");
    assert_int_equal(fread(buf, 1, (size_t)nbytes, in), (size_t)nbytes);
    /* header, first record (a step: 16 + 88 bytes), then the second's tag */
    long hdr = nbytes;
    fixture probe;
    setup(&probe, "jprobe", JOURNAL_DECK);
    char pp[300];
    snprintf(pp, sizeof pp, "%s.journal", probe.prefix);
    FILE *pf = fopen(pp, "wb");
    assert_int_equal(analysis_set_journal(probe.a, pf, pp), RL_OK);
    assert_int_equal(analysis_journal_sync(probe.a, &hdr), RL_OK);
    fclose(pf);
    teardown(&probe);
    assert_int_equal(hdr, 236); /* docs/observables.md, "The analysis journal" */
    memcpy(buf + hdr + 16 + 88, "XXXX", 4);
    fwrite(buf, 1, (size_t)nbytes, out);
    fclose(in);
    fclose(out);
    free(buf);
  }
  static const struct {
    const char *name, *body, *which, *want;
    long cut;
  } cases[] = {
      {"longer than the file", JOURNAL_DECK, "journal", "fewer than", 1},
      {"inside a record", JOURNAL_DECK, "journal", "not at a record boundary", -7},
      {"not a journal", JOURNAL_DECK, "deck", "is not a rotleap analysis journal", 0},
      {"another system", "[system]\nmodel = stockmayer\ncount = 27\nbox = 10\ntemperature = 1.35\n[interactions]\n"
                         "cutoff = 2.5\ndipole = rf\neps_rf = 10\n[run]\nsteps = 10\ntimestep = 0.002\nensemble = "
                         "nvt-bussi\ntemperature = 1.35\n[output]\nrdf = S-S\ndiscard = auto\n",
       "journal", "written for a system of 8 molecules, this run has 27", 0},
      {"other rdf pairs", "[system]\nmodel = stockmayer\ncount = 8\nbox = 10\ntemperature = 1.35\n[interactions]\n"
                          "cutoff = 2.5\ndipole = rf\neps_rf = 10\n[run]\nsteps = 10\ntimestep = 0.002\nensemble = "
                          "nvt-bussi\ntemperature = 1.35\n[output]\ndiscard = auto\n",
       "journal", "output.rdf with 1 pairs, this run has 0", 0},
      {"a damaged record", JOURNAL_DECK, "damaged", "is damaged or of another run", 0},
  };
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    fixture r;
    setup(&r, "jreplay", cases[c].body);
    const char *path = !strcmp(cases[c].which, "deck") ? deck : !strcmp(cases[c].which, "damaged") ? damaged : jp;
    const int st = analysis_replay(r.a, path, nbytes + cases[c].cut);
    printf("check %s: refused (%d): %s\n", cases[c].name, st, rl_last_error());
    assert_int_not_equal(st, RL_OK);
    assert_non_null(strstr(rl_last_error(), cases[c].want));
    assert_non_null(strstr(rl_last_error(), path));
    teardown(&r);
  }
  /* a write that fails (a full disk): the journal's name and the system's reason */
  fixture w;
  setup(&w, "jfull", JOURNAL_DECK);
  FILE *full = fopen("/dev/full", "wb");
  if (full) {
    assert_int_equal(analysis_set_journal(w.a, full, "/dev/full"), RL_OK);
    feed(&w, 0, 3);
    const int st = analysis_journal_sync(w.a, NULL);
    printf("check a full disk: %s\n", rl_last_error());
    assert_int_not_equal(st, RL_OK);
    assert_non_null(strstr(rl_last_error(), "/dev/full"));
    assert_non_null(strstr(rl_last_error(), strerror(ENOSPC)));
    rl_step_info info;
    memset(&info, 0, sizeof info);
    rl_forces F = {NULL, NULL, 0.0, {0}, 0};
    assert_int_not_equal(analysis_step(w.a, &info, 0.0, &F, w.sys, NULL), RL_OK); /* and every later record */
    fclose(full);
  }
  teardown(&w);
}

/* analysis_write(a, prefix, ".part", dt): NAME.results.txt.part and the others, nothing else. */
static void write_with_suffix(void **state)
{
  (void)state;
  fixture fx;
  setup(&fx, "suffix", JOURNAL_DECK);
  feed(&fx, 0, 40);
  static const char *ext[] = {"results.txt", "rdf.csv", "tcf.csv"};
  for (int e = 0; e < 3; e++) {
    char p[300];
    snprintf(p, sizeof p, "%s.%s", fx.prefix, ext[e]);
    remove(p);
  }
  assert_int_equal(analysis_write(fx.a, fx.prefix, ".part", 0.008), RL_OK);
  for (int e = 0; e < 3; e++) {
    char p[300], q[300];
    snprintf(p, sizeof p, "%s.%s.part", fx.prefix, ext[e]);
    snprintf(q, sizeof q, "%s.%s", fx.prefix, ext[e]);
    printf("check %s.part written, %s not: %s\n", ext[e], ext[e], file_size(p) > 0 && file_size(q) < 0 ? "ok" : "FAIL");
    assert_true(file_size(p) > 0 && file_size(q) < 0);
  }
  teardown(&fx);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(orientation_columns), cmocka_unit_test(msd_wrapped),
                                     cmocka_unit_test(nvt_uses_target_temperature), cmocka_unit_test(nve_keeps_lpv),
                                     cmocka_unit_test(dielectric_short_run),
                                     cmocka_unit_test(write_failures), cmocka_unit_test(rdf_without_samples),
                                     cmocka_unit_test(journal_continuation), cmocka_unit_test(journal_refused),
                                     cmocka_unit_test(write_with_suffix)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
