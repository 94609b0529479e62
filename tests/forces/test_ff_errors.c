/* Bad input: every error names the problem and the bodies / species / keys involved. */
#include "ff_testutil.h"

/* Check status and that the message contains every fragment (NULL-terminated list). */
static void expect(const char *label, int status, int want, ...)
{
  const char *msg = rl_last_error();
  int ok = status == want;
  va_list ap;
  va_start(ap, want);
  for (const char *frag = va_arg(ap, const char *); frag; frag = va_arg(ap, const char *))
    if (!strstr(msg, frag)) ok = 0;
  va_end(ap);
  printf("check %-44s [%s] \"%s\" %s\n", label, rl_strerror(status), status ? msg : "",
         ok ? "ok" : "FAIL");
  assert_true(ok);
}

typedef struct {
  ff_test_species w, s;
  rl_species_ff sff[2];
  rl_system *sys;
  rl_ff_params p;
} setup;

static void setup_init(setup *u)
{
  memset(u, 0, sizeof *u);
  ff_water(&u->w);
  ff_stockmayer(&u->s, 0.04);
  u->sys = rl_system_alloc(RL_UNITS_REAL);
  assert_int_equal(rl_system_add_species(u->sys, &u->w.desc, 3, NULL), RL_OK);
  assert_int_equal(rl_system_add_species(u->sys, &u->s.desc, 2, NULL), RL_OK);
  for (int i = 0; i < 5; i++) {
    double r[3] = {0.5 + 0.4 * i, 1.0, 1.0};
    rl_system_set_position(u->sys, i, r);
  }
  u->sff[0] = ff_test_species_ff(&u->w);
  u->sff[1] = ff_test_species_ff(&u->s);
  const double L[3] = {3.0, 2.4, 3.0};
  assert_int_equal(rl_system_set_box(u->sys, L), RL_OK);
  rl_ff_params_default(&u->p);
  u->p.cutoff = 1.0;
}

static int alloc_status(setup *u)
{
  rl_error_clear();
  rl_forcefield *ff = rl_forcefield_alloc(u->sys, &u->p, u->sff, 2);
  int st = ff ? RL_OK : RL_EINVAL;
  if (ff && strlen(rl_last_error()) == 0) st = RL_OK;
  rl_forcefield_free(ff);
  return st;
}

static int compute_status(setup *u)
{
  rl_forcefield *ff = rl_forcefield_alloc(u->sys, &u->p, u->sff, 2);
  assert_non_null(ff);
  double f[8][3], k[8][3];
  rl_forces out = {f, k, 0.0, {0}, 0};
  memset(f, 0, sizeof f);
  memset(k, 0, sizeof k);
  int st = rl_forcefield_compute(ff, u->sys, &out);
  rl_forcefield_free(ff);
  return st;
}

static void test_params(void **state)
{
  (void)state;
  setup u;
  setup_init(&u);
  assert_int_equal(alloc_status(&u), RL_OK);

  u.p.cutoff = 1.3;
  expect("cutoff > half the shortest box edge", alloc_status(&u), RL_EINVAL, "cutoff 1.3",
         "larger than half the shortest box edge", "Ly = 2.4", NULL);
  u.p.cutoff = 1.0;

  /* the box is the system's */
  const double none[3] = {0.0, 0.0, 0.0}, L[3] = {3.0, 2.4, 3.0};
  assert_int_equal(rl_system_set_box(u.sys, none), RL_OK);
  expect("a system without a periodic box", alloc_status(&u), RL_EINVAL, "no periodic box",
         "rl_system_set_box", NULL);
  const double neg[3] = {3.0, 2.4, -1.0};
  expect("a negative box edge is refused by the system", rl_system_set_box(u.sys, neg), RL_EINVAL, NULL);
  assert_int_equal(rl_system_set_box(u.sys, L), RL_OK);
  expect("the system's box accepted", alloc_status(&u), RL_OK, NULL);

  u.p.cutoff = NAN;
  expect("non-finite cutoff", alloc_status(&u), RL_EINVAL, "cutoff", "finite", NULL);
  u.p.cutoff = 1.0;

  u.p.lj_truncation = RL_LJ_SWITCHED;
  u.p.r_switch = 1.2;
  expect("switch distance beyond the cutoff", alloc_status(&u), RL_EINVAL, "r_switch 1.2",
         "cutoff 1", NULL);
  u.p.lj_truncation = RL_LJ_PLAIN;

  u.p.eps_rf = 0.5;
  expect("eps_rf < 1", alloc_status(&u), RL_EINVAL, "eps_rf 0.5", NULL);
  u.p.eps_rf = NAN;
  expect("eps_rf NaN", alloc_status(&u), RL_EINVAL, "eps_rf nan", NULL);
  u.p.eps_rf = -INFINITY;
  expect("eps_rf -infinity", alloc_status(&u), RL_EINVAL, "eps_rf -inf", NULL);
  u.p.eps_rf = INFINITY;
  expect("eps_rf = infinity accepted", alloc_status(&u), RL_OK, NULL);
  u.p.eps_rf = 1e308; /* the conducting limit, not an overflow (test_ff_kernels) */
  expect("eps_rf = 1e308 accepted", alloc_status(&u), RL_OK, NULL);
  rl_system_free(u.sys);
}

static void test_species_tables(void **state)
{
  (void)state;
  setup u;
  setup_init(&u);

  rl_error_clear();
  rl_forcefield *ff = rl_forcefield_alloc(u.sys, &u.p, u.sff, 1);
  expect("too few species parameter sets", ff ? RL_OK : RL_EINVAL, RL_EINVAL, "1 species",
         "system has 2 species", NULL);

  u.sff[0].nsites = 3;
  expect("nsites mismatch", alloc_status(&u), RL_EINVAL, "species 0", "nsites = 3",
         "has 4 sites", NULL);
  u.sff[0].nsites = 4;

  u.w.sigma[2] = -0.3;
  expect("negative sigma", alloc_status(&u), RL_EINVAL, "species 0", "sigma[2] = -0.3",
         "negative", NULL);
  u.w.sigma[2] = 0.0;

  u.s.epsilon[0] = -1.0;
  expect("negative epsilon", alloc_status(&u), RL_EINVAL, "species 1", "epsilon[0] = -1",
         "negative", NULL);
  u.s.epsilon[0] = 1.0;

  u.w.charge[1] = NAN;
  expect("non-finite charge", alloc_status(&u), RL_EINVAL, "species 0", "charge[1]",
         "not finite", NULL);
  u.w.charge[1] = 0.52;

  u.sff[0].charge = NULL;
  expect("missing charge array", alloc_status(&u), RL_EINVAL, "species 0",
         "missing array charge", NULL);
  u.sff[0].charge = u.w.charge;
  u.sff[1].sigma = NULL;
  expect("missing sigma array", alloc_status(&u), RL_EINVAL, "species 1",
         "missing array sigma", NULL);
  u.sff[1].sigma = u.s.sigma;

  /* a quadrupole in a scene with charges */
  double quad[4] = {0, 0, 0, 0.01};
  u.sff[0].quadrupole = quad;
  expect("quadrupole mixed with charges", alloc_status(&u), RL_EINVAL,
         "species 0 site 3 carries a quadrupole", "not supported", NULL);
  u.sff[0].quadrupole = NULL;
  rl_system_free(u.sys);

  /* a dipole on a point body */
  rl_system *sys = rl_system_alloc(RL_UNITS_REAL);
  ff_test_species ion;
  ff_ion(&ion, 1.0);
  ion.has_dipole = 1;
  ion.dipole[0] = 0.02;
  assert_int_equal(rl_system_add_species(sys, &ion.desc, 2, NULL), RL_OK);
  rl_species_ff sff = ff_test_species_ff(&ion);
  const double L[3] = {3.0, 3.0, 3.0};
  assert_int_equal(rl_system_set_box(sys, L), RL_OK);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = 1.0;
  rl_error_clear();
  ff = rl_forcefield_alloc(sys, &p, &sff, 1);
  expect("dipole on a point body", ff ? RL_OK : RL_EINVAL, RL_EINVAL,
         "species 0 is a point species", "site 0 carries a dipole", NULL);
  rl_system_free(sys);
}

static void test_pair_overrides_and_box(void **state)
{
  (void)state;
  setup u;
  setup_init(&u);
  rl_forcefield *ff = rl_forcefield_alloc(u.sys, &u.p, u.sff, 2);
  assert_non_null(ff);
  expect("pair override accepted", rl_forcefield_set_lj_pair(ff, 0, 0, 1, 0, 0.32, 0.9), RL_OK,
         NULL);
  expect("pair override with negative epsilon",
         rl_forcefield_set_lj_pair(ff, 0, 0, 1, 0, 0.32, -0.9), RL_EINVAL,
         "species 0 site 0 - species 1 site 0", "epsilon -0.9", NULL);
  expect("pair override for a missing site", rl_forcefield_set_lj_pair(ff, 0, 7, 1, 0, 0.3, 0.1),
         RL_EINVAL, "species 0 site 7", "no such site", NULL);
  expect("pair override for a missing species",
         rl_forcefield_set_lj_pair(ff, 2, 0, 1, 0, 0.3, 0.1), RL_EINVAL, "species 2",
         "no such species", NULL);
  /* the system's box shrinks below twice the cutoff: the next compute says so, and again */
  double f[8][3], k[8][3];
  rl_forces out = {f, k, 0.0, {0}, 0};
  memset(f, 0, sizeof f);
  memset(k, 0, sizeof k);
  const double L[3] = {3.0, 3.0, 1.5};
  assert_int_equal(rl_system_set_box(u.sys, L), RL_OK);
  expect("box shrunk below twice the cutoff", rl_forcefield_compute(ff, u.sys, &out), RL_EINVAL,
         "cutoff 1", "Lz = 1.5", NULL);
  expect("... at every compute until it grows", rl_forcefield_compute(ff, u.sys, &out), RL_EINVAL,
         "cutoff 1", "Lz = 1.5", NULL);
  const double none[3] = {0.0, 0.0, 0.0};
  assert_int_equal(rl_system_set_box(u.sys, none), RL_OK);
  expect("box removed", rl_forcefield_compute(ff, u.sys, &out), RL_EINVAL,
         "no longer has a periodic box", NULL);
  rl_forcefield_free(ff);
  rl_system_free(u.sys);
}

static void test_configurations(void **state)
{
  (void)state;
  setup u;
  setup_init(&u);
  assert_int_equal(compute_status(&u), RL_OK);

  /* overlapping sites: body 3 (a point dipole) on top of body 1's oxygen */
  double r1[3], r3[3];
  rl_system_get_position(u.sys, 1, r1);
  rl_system_get_position(u.sys, 3, r3);
  double o[3] = {r1[0], r1[1], r1[2] - 0.0066};
  rl_system_set_position(u.sys, 3, o);
  expect("overlapping sites", compute_status(&u), RL_EINVAL, "overlapping sites",
         "site 0 of body 1", "site 0 of body 3", NULL);
  rl_system_set_position(u.sys, 3, r3);

  /* the same with the molecule scheme and the brute-force path */
  u.p.scheme = RL_CUTOFF_MOLECULE;
  u.p.neighbor_list = 0;
  rl_system_set_position(u.sys, 3, o);
  expect("overlapping sites (molecule scheme, brute force)", compute_status(&u), RL_EINVAL,
         "overlapping sites", "body 1", "body 3", NULL);
  rl_system_set_position(u.sys, 3, r3);
  u.p.scheme = RL_CUTOFF_SITE;
  u.p.neighbor_list = 1;

  /* non-finite coordinates, written behind the setters' back */
  double(*r)[3] = rl_system_r(u.sys);
  double keep = r[2][1];
  r[2][1] = NAN;
  expect("non-finite position", compute_status(&u), RL_ENONFINITE, "body 2 (species 0)",
         "non-finite position", NULL);
  r[2][1] = INFINITY;
  expect("infinite position", compute_status(&u), RL_ENONFINITE, "body 2", "non-finite", NULL);
  r[2][1] = keep;
  assert_int_equal(compute_status(&u), RL_OK);

  /* the system grew after the force field was made */
  rl_forcefield *ff = rl_forcefield_alloc(u.sys, &u.p, u.sff, 2);
  assert_non_null(ff);
  assert_int_equal(rl_system_add_species(u.sys, &u.s.desc, 1, NULL), RL_OK);
  double f[8][3] = {{0}}, k[8][3] = {{0}};
  rl_forces out = {f, k, 0.0, {0}, 0};
  expect("system changed after alloc", rl_forcefield_compute(ff, u.sys, &out), RL_ESTATE,
         "system changed", "5 bodies", NULL);
  rl_forcefield_free(ff);
  rl_system_free(u.sys);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_params),
      cmocka_unit_test(test_species_tables),
      cmocka_unit_test(test_pair_overrides_and_box),
      cmocka_unit_test(test_configurations),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
