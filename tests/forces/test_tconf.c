/* The configurational temperature's sums (forcefield.h, rl_config_temperature):
 *  - its forces and torques are the force field's: sum |F|^2 and sum |tau|^2 equal those of
 *    rl_forcefield_compute (1e-10 relative) on every scene of test_ff_fd (LJ in each truncation,
 *    RF charges, dipoles RF and SF with charge-dipole, quadrupoles; site and molecule cutoffs;
 *    point, dipole, linear, spherical, symmetric and asymmetric bodies);
 *  - both Laplacians equal second differences of the energy: sum over bodies and lab axes of
 *    d2U/dx^2 (translating a centre) and d2U/dphi^2 (rotating a body about a lab axis through its
 *    centre), central differences with one Richardson step, to 1e-6 of the sum of their sizes;
 *  - the exact value: a Metropolis Monte Carlo chain (independent of any integrator) of a few
 *    molecules (Stockmayer, shifted force; TIP4P, shifted-force LJ and eps_rf = infinity) at T
 *    gives <|F|^2>/<lap_r> and <|tau|^2>/<lap_rot> equal to k_B T within 4 block errors, and the
 *    block errors are below 5 %;
 *  - rl_tconf_exact follows the force field's discontinuities at the cutoff. */
#include "ff_testutil.h"
#include "ff_scenes.h"

/* d2U/dx^2 along path (mode 0: translate body i along e_c; 1: rotate it about e_c), central
 * differences at h and h/2 with one Richardson step. */
static double fd_second(rl_forcefield *ff, rl_system *sys, int i, int mode, int c, double u0, double h)
{
  double d1 = (ff_fd_energy_at(ff, sys, i, mode, c, h) + ff_fd_energy_at(ff, sys, i, mode, c, -h) - 2.0 * u0) / (h * h);
  double d2 = (ff_fd_energy_at(ff, sys, i, mode, c, h / 2) + ff_fd_energy_at(ff, sys, i, mode, c, -h / 2) - 2.0 * u0) /
              (h * h / 4);
  return (4.0 * d2 - d1) / 3.0;
}

/* The smallest distance of a site pair (site cutoff) or a centre pair (molecule cutoff) from the
 * cutoff: the finite differences below move a body by 1e-3 at most, and must not cross it. */
static double cutoff_gap(const rl_system *sys, const rl_ff_params *p)
{
  const int n = rl_system_count(sys), ns = rl_system_nsites(sys);
  double(*x)[3] = malloc(sizeof *x * (size_t)ns), gap = INFINITY;
  rl_system_site_positions(sys, x);
  for (int i = 0; i < n; i++)
    for (int j = i + 1; j < n; j++) {
      double ri[3], rj[3];
      rl_system_get_position(sys, i, ri);
      rl_system_get_position(sys, j, rj);
      if (p->scheme == RL_CUTOFF_MOLECULE) {
        gap = fmin(gap, fabs(sqrt((ri[0] - rj[0]) * (ri[0] - rj[0]) + (ri[1] - rj[1]) * (ri[1] - rj[1]) +
                                  (ri[2] - rj[2]) * (ri[2] - rj[2])) - p->cutoff));
        continue;
      }
      const int ei = i + 1 < n ? rl_system_site_offset(sys, i + 1) : ns;
      const int ej = j + 1 < n ? rl_system_site_offset(sys, j + 1) : ns;
      for (int a = rl_system_site_offset(sys, i); a < ei; a++)
        for (int b = rl_system_site_offset(sys, j); b < ej; b++)
          gap = fmin(gap, fabs(sqrt((x[a][0] - x[b][0]) * (x[a][0] - x[b][0]) + (x[a][1] - x[b][1]) * (x[a][1] - x[b][1]) +
                                    (x[a][2] - x[b][2]) * (x[a][2] - x[b][2])) - p->cutoff));
    }
  free(x);
  return gap;
}

/* The scene `which` from the first seed (from seed0 on) whose pairs all stay 1.5e-3 away from the
 * cutoff under both schemes. */
static void scene_clear(scene *s, int which, unsigned long seed0, gsl_rng *rng)
{
  for (unsigned long seed = seed0;; seed++) {
    gsl_rng_set(rng, seed);
    scene_build(s, which, rng);
    rl_ff_params p;
    base_params(&p);
    const double g0 = cutoff_gap(s->sys, &p);
    p.scheme = RL_CUTOFF_MOLECULE;
    if (g0 > 1.5e-3 && cutoff_gap(s->sys, &p) > 1.5e-3) return;
    rl_system_free(s->sys);
    assert_true(seed < seed0 + 100);
  }
}

static void check_scene(scene *s, const rl_ff_params *p, const char *label)
{
  char name[200];
  snprintf(name, sizeof name, "%s: no pair within 1.5e-3 of the cutoff (%.3g)", label, cutoff_gap(s->sys, p));
  FF_CHECK_TRUE(name, cutoff_gap(s->sys, p) > 1.5e-3);
  rl_forcefield *ff = rl_forcefield_alloc(s->sys, p, s->sff, s->nsp);
  if (!ff) fprintf(stderr, "%s\n", rl_last_error());
  assert_non_null(ff);
  ff_result res;
  ff_result_compute(&res, ff, s->sys);
  rl_tconf_sums t;
  int st = rl_config_temperature(ff, s->sys, &t);
  if (st) fprintf(stderr, "tconf: %s\n", rl_last_error());
  assert_int_equal(st, RL_OK);
  const int n = rl_system_count(s->sys);
  double f2 = 0.0, k2 = 0.0;
  for (int i = 0; i < n; i++) {
    f2 += res.f[i][0] * res.f[i][0] + res.f[i][1] * res.f[i][1] + res.f[i][2] * res.f[i][2];
    const int r = rl_system_rot_index(s->sys, i);
    if (r >= 0) k2 += res.k[r][0] * res.k[r][0] + res.k[r][1] * res.k[r][1] + res.k[r][2] * res.k[r][2];
  }
  snprintf(name, sizeof name, "%s: sum |F|^2 vs the force field", label);
  FF_CHECK_LE(name, fabs(t.f2 - f2) / f2, 1e-10);
  snprintf(name, sizeof name, "%s: sum |tau|^2 vs the force field", label);
  FF_CHECK_LE(name, fabs(t.k2 - k2) / k2, 1e-10);
  const double u0 = res.out.energy;
  double lr = 0.0, lrot = 0.0, sr = 0.0, srot = 0.0;
  for (int i = 0; i < n; i++) {
    double bi = 0.0;
    for (int c = 0; c < 3; c++) bi += fd_second(ff, s->sys, i, 0, c, u0, 1e-3);
    lr += bi;
    sr += fabs(bi);
    if (rl_system_rot_index(s->sys, i) < 0) continue;
    bi = 0.0;
    for (int c = 0; c < 3; c++) bi += fd_second(ff, s->sys, i, 1, c, u0, 1e-3);
    lrot += bi;
    srot += fabs(bi);
  }
  snprintf(name, sizeof name, "%s: translational Laplacian vs FD (%.4g)", label, lr);
  FF_CHECK_LE(name, fabs(t.lap_r - lr) / sr, 1e-6);
  snprintf(name, sizeof name, "%s: rotational Laplacian vs FD (%.4g)", label, lrot);
  FF_CHECK_LE(name, fabs(t.lap_rot - lrot) / srot, 1e-6);
  ff_result_free(&res);
  rl_forcefield_free(ff);
}

static const char *trunc_name[] = {"plain", "shifted", "shifted-force", "switched"};

/* Every force-field case of scene `which` (ff_scene_case) on the first clear scene from `seed`. */
static void tconf_scene(int which, unsigned long seed)
{
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  scene s;
  scene_clear(&s, which, seed, rng);
  rl_ff_params p;
  char label[128];
  for (int k = 0; ff_scene_case(which, k, &p, label, sizeof label); k++) check_scene(&s, &p, label);
  rl_system_free(s.sys);
  gsl_rng_free(rng);
}

static void test_fd_lj_coulomb(void **state)
{
  (void)state;
  tconf_scene(SCENE_CHARGES, 11);
}

static void test_fd_dipoles(void **state)
{
  (void)state;
  tconf_scene(SCENE_DIPOLES, 12);
}

static void test_fd_quadrupoles(void **state)
{
  (void)state;
  tconf_scene(SCENE_QUADS, 15);
}

/* The continuity flag follows the force field's discontinuities. */
static void test_continuity_flag(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 14);
  scene s;
  scene_build(&s, SCENE_CHARGES, rng);
  for (int t = 0; t < 4; t++)
    for (int e = 0; e < 2; e++) {
      rl_ff_params p;
      base_params(&p);
      p.lj_truncation = (rl_lj_truncation)t;
      p.eps_rf = e ? INFINITY : 78.3;
      rl_forcefield *ff = rl_forcefield_alloc(s.sys, &p, s.sff, s.nsp);
      assert_non_null(ff);
      const int want = e && (t == RL_LJ_SHIFTED_FORCE || t == RL_LJ_SWITCHED);
      char name[160];
      snprintf(name, sizeof name, "continuous = %d for LJ %s, eps_rf %s", want, trunc_name[t], e ? "inf" : "78.3");
      FF_CHECK_TRUE(name, rl_tconf_exact(ff) == want);
      rl_forcefield_free(ff);
    }
  rl_system_free(s.sys);
  gsl_rng_free(rng);
}

/* ------------------------------------------------------------------ exact value: Monte Carlo */

/* A random rotation by an angle uniform in [-amax, amax] about a uniformly random axis (its
 * distribution is that of its inverse: a symmetric proposal under the invariant measure). */
static void random_rotation(gsl_rng *rng, double amax, double R[9])
{
  double n[3];
  gsl_ran_dir_3d(rng, &n[0], &n[1], &n[2]);
  ff_rotation(n, gsl_ran_flat(rng, -amax, amax), R);
}

typedef struct {
  const char *label;
  rl_units units;
  double T, L, cutoff, dmove, amove;
  long sweeps, equil;
  int n;
} mc_case;

/* Metropolis MC of sys under ff at T; block means (B blocks) of the four sums, sampled every sweep. */
static void mc_check(rl_system *sys, rl_forcefield *ff, const mc_case *c, gsl_rng *rng)
{
  enum { B = 20 };
  const double kT = c->T * rl_units_kB(c->units);
  const int n = rl_system_count(sys);
  double u = ff_energy(ff, sys);
  double blk[B][4];
  memset(blk, 0, sizeof blk);
  long acc = 0, tries = 0;
  double(*f)[3] = calloc((size_t)n + 1, sizeof *f), (*kk)[3] = calloc((size_t)rl_system_nrot(sys) + 1, sizeof *kk);
  const char *scale = getenv("TCONF_MC_SCALE"); /* longer chains by hand */
  const long per_block = c->sweeps / B * (scale ? atol(scale) : 1);
  for (long sw = 0; sw < c->equil + per_block * B; sw++) {
    for (int i = 0; i < n; i++) {
      double r0[3], A0[9], rho0[3], r[3];
      const rl_kind k = rl_system_species_kind(sys, rl_system_species_of(sys, i));
      rl_system_get_position(sys, i, r0);
      rl_system_get_orientation(sys, i, A0);
      rl_system_get_axis(sys, i, rho0);
      for (int d = 0; d < 3; d++) r[d] = r0[d] + gsl_ran_flat(rng, -c->dmove, c->dmove);
      rl_system_set_position(sys, i, r);
      if (k != RL_KIND_POINT) {
        double R[9];
        random_rotation(rng, c->amove, R);
        ff_rotate_body(sys, i, R);
      }
      int bad = 0;
      {
        memset(f, 0, sizeof *f * (size_t)n);
        memset(kk, 0, sizeof *kk * (size_t)rl_system_nrot(sys));
        rl_forces out = {f, kk, 0.0, {0}, 0};
        bad = rl_forcefield_compute(ff, sys, &out) != RL_OK; /* an overlap: rejected */
        double u1 = out.energy;
        tries++;
        if (!bad && (u1 <= u || gsl_rng_uniform(rng) < exp(-(u1 - u) / kT))) {
          u = u1;
          acc++;
          continue;
        }
      }
      rl_system_set_position(sys, i, r0);
      if (k == RL_KIND_DIPOLE || k == RL_KIND_LINEAR) rl_system_set_axis(sys, i, rho0);
      else if (k != RL_KIND_POINT) rl_system_set_orientation(sys, i, A0);
    }
    if (sw < c->equil) continue;
    rl_tconf_sums t;
    assert_int_equal(rl_config_temperature(ff, sys, &t), RL_OK);
    double *b = blk[(sw - c->equil) / per_block];
    b[0] += t.f2;
    b[1] += t.lap_r;
    b[2] += t.k2;
    b[3] += t.lap_rot;
  }
  free(f);
  free(kk);
  printf("# %s: acceptance %.2f\n", c->label, (double)acc / (double)tries);
  /* the ratio of means and its error from the spread of the block ratios */
  for (int part = 0; part < 2; part++) {
    double num = 0.0, den = 0.0, rb[B], m = 0.0, v = 0.0;
    for (int k = 0; k < B; k++) {
      num += blk[k][2 * part];
      den += blk[k][2 * part + 1];
      rb[k] = blk[k][2 * part] / blk[k][2 * part + 1];
    }
    const double ratio = num / den / kT;
    for (int k = 0; k < B; k++) m += rb[k] / B;
    for (int k = 0; k < B; k++) v += (rb[k] - m) * (rb[k] - m) / (B - 1);
    const double err = sqrt(v / B) / kT;
    char name[200];
    snprintf(name, sizeof name, "%s: T_conf %s / T = %.4f +- %.4f, |ratio - 1| / err", c->label,
             part ? "rotational" : "translational", ratio, err);
    FF_CHECK_LE(name, fabs(ratio - 1.0) / err, 4.0);
    snprintf(name, sizeof name, "%s: T_conf %s relative error", c->label, part ? "rotational" : "translational");
    FF_CHECK_LE(name, err, 0.05);
  }
}

/* n molecules of species t on a lattice in a cubic box of edge L (the system's), under p, then
 * mc_check. */
static void mc_run(const mc_case *c, ff_test_species *t, double L, rl_ff_params *p, unsigned long seed)
{
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, seed);
  rl_system *sys = rl_system_alloc(c->units);
  assert_int_equal(rl_system_add_species(sys, &t->desc, c->n, NULL), RL_OK);
  const double Lv[3] = {L, L, L};
  assert_int_equal(rl_system_lattice(sys, Lv, RL_LATTICE_SC, 1, seed), RL_OK);
  rl_species_ff sff = ff_test_species_ff(t);
  p->neighbor_list = 0;
  rl_forcefield *ff = rl_forcefield_alloc(sys, p, &sff, 1);
  assert_non_null(ff);
  mc_check(sys, ff, c, rng);
  rl_forcefield_free(ff);
  rl_system_free(sys);
  gsl_rng_free(rng);
}

static void test_mc_stockmayer(void **state)
{
  (void)state;
  const mc_case c = {"MC 16 Stockmayer (lj units, rho* 0.3, T* 1.35, mu*^2 3, SF)", RL_UNITS_LJ, 1.35, 0.0, 2.5,
                     0.3, 0.6, 6000, 300, 16};
  const double L = cbrt(c.n / 0.3);
  ff_test_species t;
  ff_species_init(&t, "sm", RL_KIND_DIPOLE, 1.0, 0.025, 0.025, 0.025, 1);
  ff_site(&t, 0, 0, 0, 0, 1.0, 1.0, 0.0);
  t.has_dipole = 1;
  t.dipole[0] = sqrt(3.0);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = fmin(2.5, 0.5 * L);
  p.lj_truncation = RL_LJ_SHIFTED_FORCE;
  p.dipole_method = RL_DIPOLE_SF;
  mc_run(&c, &t, L, &p, 41);
}

static void test_mc_water(void **state)
{
  (void)state;
  const mc_case c = {"MC 8 TIP4P-like water (450 K, 0.2 g/cm3, SF LJ, eps_rf inf)", RL_UNITS_REAL, 450.0, 0.0, 0.9,
                     0.08, 0.5, 6000, 300, 8};
  const double L = cbrt(c.n * 18.0 / 602.214 / 0.2); /* nm, from 0.2 g/cm3 */
  ff_test_species t;
  ff_water(&t);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = fmin(0.9, 0.5 * L);
  p.lj_truncation = RL_LJ_SHIFTED_FORCE;
  p.eps_rf = INFINITY;
  mc_run(&c, &t, L, &p, 42);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_fd_lj_coulomb),   cmocka_unit_test(test_fd_dipoles), cmocka_unit_test(test_fd_quadrupoles),
      cmocka_unit_test(test_continuity_flag), cmocka_unit_test(test_mc_stockmayer), cmocka_unit_test(test_mc_water),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
