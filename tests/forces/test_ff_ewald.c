/* The pair term with the Ewald real space in its kernels (coulomb = RL_COULOMB_EWALD_REAL) against
 * the term "ewald-real" (forces/ewald/ewald_real.c, the reference routine of the real space) plus
 * the pair term without charges, which is what rotleap computed before the kernels had it: on
 * TIP4P-Ew ("tip4p" kernel), SPC/E and TIP3P ("charge-lj") liquids from the catalogue, 216
 * molecules (L = 1.86 nm < 2 (rc + 2 extent): the rows' image list) and 512 (L = 2.48 nm) at
 * rc = 0.9 nm and OpenMM's alpha for tolerance 5e-4 (and 1e-6), every row path (AVX-512, AVX2,
 * portable), 1 and 2 threads: the real-space energy, forces, torques and molecular virial to
 * 1e-12 relative, and a fixed thread count bit for bit.  Likewise the Stockmayer fluid (the
 * catalogue's, mu*^2 = 3, 500 at rho* = 0.8, rc = 2.5 sigma; the "stockmayer" kernel's
 * dipole_lj_ewald rows) against "ewald-real"'s point-dipole routine, at the alpha of Ewald for
 * tolerances 5e-4 and 1e-6 and of PME for 1e-3.  Round-off is all that differs: the two evaluate the same
 * B_1 .. B_3 from the same erfc polynomials (erfc.h) in other orders, and sum the pairs in
 * other orders (the largest seen, 1.2e-13 on the forces with the AVX2 rows, from sums of nearly cancelling pair forces; 1e-12 leaves a margin of 8). */
#include "ff_testutil.h"
#include <rotleap/rotleap.h>
#include "rotleap/ewald.h"

#include <string.h>

/* A liquid-like configuration: a simple-cubic lattice of `count` molecules at 0.995 g/cm3 with
 * random orientations, centres moved by up to 0.05 nm. */
static rl_system *liquid(const rl_molecule *mol, int count, unsigned long seed)
{
  rl_system *sys = rl_system_alloc(RL_UNITS_REAL);
  rl_species_desc d;
  rl_molecule_species(mol, &d);
  assert_int_equal(rl_system_add_species(sys, &d, count, NULL), RL_OK);
  const double edge = cbrt(count * mol->mass / (0.995 * 602.21407621));
  const double L[3] = {edge, edge, edge};
  assert_int_equal(rl_system_lattice(sys, L, RL_LATTICE_SC, 1, seed), RL_OK);
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, seed);
  for (int i = 0; i < count; i++) {
    double r[3];
    rl_system_get_position(sys, i, r);
    for (int c = 0; c < 3; c++) r[c] += gsl_ran_flat(rng, -0.05, 0.05);
    rl_system_set_position(sys, i, r);
  }
  gsl_rng_free(rng);
  return sys;
}

typedef struct {
  double (*f)[3], (*k)[3], W[9], E, coul;
  int n, nr;
} result;

/* One computation of the terms t; coul = the component named `name`. */
static void eval(rl_terms *t, rl_system *sys, const char *name, result *r)
{
  r->n = rl_system_count(sys);
  r->nr = rl_system_nrot(sys);
  r->f = calloc((size_t)r->n, sizeof(double[3]));
  r->k = calloc((size_t)r->nr + 1, sizeof(double[3]));
  rl_forces F = {r->f, r->k, 0.0, {0}, 0};
  assert_int_equal(rl_terms_compute(t, sys, &F), RL_OK);
  r->E = F.energy;
  memcpy(r->W, F.virial, sizeof r->W);
  r->coul = NAN;
  for (int j = 0; j < rl_terms_nenergies(t); j++)
    if (!strcmp(rl_terms_energy_name(t, j), name)) r->coul = rl_terms_energy(t, j);
}

static double maxrel(const double *a, const double *b, int n)
{
  double d = 0.0, s = 0.0;
  for (int i = 0; i < n; i++) {
    d = fmax(d, fabs(a[i] - b[i]));
    s = fmax(s, fabs(b[i]));
  }
  return d / s;
}

static void compare(const result *a, const result *b, const char *what, double tol)
{
  char name[320];
  snprintf(name, sizeof name, "%s: real-space energy, relative", what);
  FF_CHECK_LE(name, fabs(a->coul - b->coul) / fabs(b->coul), tol);
  snprintf(name, sizeof name, "%s: total energy, relative", what);
  FF_CHECK_LE(name, fabs(a->E - b->E) / fabs(b->E), tol);
  snprintf(name, sizeof name, "%s: max |dF| / max |F|", what);
  FF_CHECK_LE(name, ff_maxdiff((const double(*)[3])a->f, (const double(*)[3])b->f, a->n) /
                        ff_maxnorm((const double(*)[3])b->f, b->n), tol);
  snprintf(name, sizeof name, "%s: max |dtau| / max |tau|", what);
  FF_CHECK_LE(name, ff_maxdiff((const double(*)[3])a->k, (const double(*)[3])b->k, a->nr) /
                        ff_maxnorm((const double(*)[3])b->k, b->nr), tol);
  snprintf(name, sizeof name, "%s: max |dW| / max |W|", what);
  FF_CHECK_LE(name, maxrel(a->W, b->W, 9), tol);
}

static void result_free(result *r)
{
  free(r->f);
  free(r->k);
}

static const char *path_label[3] = {"", ", ROTLEAP_NO_AVX512", ", ROTLEAP_NO_AVX2 (portable rows)"};
static void set_path(int k)
{
  if (k >= 1) setenv("ROTLEAP_NO_AVX512", "1", 1);
  else unsetenv("ROTLEAP_NO_AVX512");
  if (k >= 2) setenv("ROTLEAP_NO_AVX2", "1", 1);
  else unsetenv("ROTLEAP_NO_AVX2");
}

/* Ewald parameters for one species sff, the cutoff and the tolerance. */
static rl_ewald_params params_for(const rl_species_ff *sff, double cutoff, double tolerance)
{
  rl_ewald_params ep;
  rl_ewald_params_default(&ep);
  ep.species = sff;
  ep.nspecies = 1;
  ep.cutoff = cutoff;
  ep.tolerance = tolerance;
  return ep;
}

/* The pair term with the real space in its rows (species sff, its energy component comp, the
 * kernel `kernel`) against the reference: the pair term without the electrostatics (sff0) plus
 * "ewald-real" (ep, alpha); every row path, 1 and 2 threads, and a second compute bit for bit. */
static void rows_vs_reference(rl_system *sys, const rl_species_ff *sff, const rl_species_ff *sff0, int geometric,
                              const rl_ewald_params *ep, double alpha, const char *comp, const char *kernel,
                              const char *label)
{
  rl_pair_params p0 = {{0}, sff0, 1, geometric};
  rl_ff_params_default(&p0.p);
  p0.p.cutoff = ep->cutoff;
  p0.p.threads = 1;
  rl_terms *tr = rl_terms_alloc(sys);
  assert_int_equal(rl_terms_add(tr, &rl_term_pair, &p0, NULL), RL_OK);
  assert_int_equal(rl_terms_add(tr, &rl_term_ewald_real, ep, NULL), RL_OK);
  result ref;
  eval(tr, sys, "ewald_real", &ref);
  for (int k = 0; k < 3; k++) {
    set_path(k);
    for (int th = 1; th <= 2; th++) {
      rl_pair_params pp = {p0.p, sff, 1, geometric};
      pp.p.coulomb = RL_COULOMB_EWALD_REAL;
      pp.p.ewald_alpha = alpha;
      pp.p.threads = th;
      rl_terms *t = rl_terms_alloc(sys);
      assert_int_equal(rl_terms_add(t, &rl_term_pair, &pp, NULL), RL_OK);
      const rl_forcefield *ff = rl_terms_find(t, &rl_term_pair);
      char what[240];
      snprintf(what, sizeof what, "%.120s, kernel %s, rows %s%s, %d thread%s", label, rl_forcefield_kernel(ff),
               rl_forcefield_rows(ff), path_label[k], th, th > 1 ? "s" : "");
      char nm[300];
      snprintf(nm, sizeof nm, "%s: kernel '%s'", what, kernel);
      FF_CHECK_TRUE(nm, strcmp(rl_forcefield_kernel(ff), kernel) == 0);
      result a, b;
      eval(t, sys, comp, &a);
      compare(&a, &ref, what, 1e-12);
      eval(t, sys, comp, &b); /* the same terms again: the same bits */
      snprintf(nm, sizeof nm, "%s: a second compute, bit for bit", what);
      FF_CHECK_TRUE(nm, a.E == b.E && a.coul == b.coul && !memcmp(a.f, b.f, sizeof(double[3]) * (size_t)a.n) &&
                            !memcmp(a.k, b.k, sizeof(double[3]) * (size_t)a.nr) && !memcmp(a.W, b.W, sizeof a.W));
      result_free(&a);
      result_free(&b);
      rl_terms_free(t);
    }
  }
  set_path(0);
  result_free(&ref);
  rl_terms_free(tr);
}

static void one_model(const char *model, const char *kernel)
{
  const rl_model *m = rl_catalog_find(model);
  assert_non_null(m);
  rl_molecule mol;
  assert_int_equal(rl_model_build(m, NULL, 0, &mol), RL_OK);
  const rl_species_ff sff = rl_molecule_ff(&mol);
  double no_charge[RL_MOLECULE_MAX_SITES] = {0};
  rl_species_ff sff0 = sff;
  sff0.charge = no_charge;
  for (int size = 0; size < 2; size++) {
    rl_system *sys = liquid(&mol, size ? 512 : 216, 33 + (unsigned long)size);
    for (int tol = 0; tol < 2; tol++) {
      const rl_ewald_params ep = params_for(&sff, 0.9, tol ? 1e-6 : 5e-4);
      rl_ewald_info info;
      assert_int_equal(rl_ewald_resolve(sys, &ep, RL_EWALD_PME, &info), RL_OK);
      char label[160];
      snprintf(label, sizeof label, "%s, %d molecules, tolerance %g (alpha %.4f /nm)", model, rl_system_count(sys),
               ep.tolerance, info.alpha);
      rows_vs_reference(sys, &sff, &sff0, m->geometric_mixing, &ep, info.alpha, "coulomb", kernel, label);
    }
    rl_system_free(sys);
  }
}

/* The Stockmayer fluid: 500 at rho* = 0.8 on a simple-cubic lattice, moved by up to 0.1 sigma,
 * random orientations. */
static void test_stockmayer(void **state)
{
  (void)state;
  const rl_model *m = rl_catalog_find("stockmayer");
  assert_non_null(m);
  rl_molecule mol;
  assert_int_equal(rl_model_build(m, NULL, 0, &mol), RL_OK);
  const rl_species_ff sff = rl_molecule_ff(&mol);
  rl_species_ff sff0 = sff;
  sff0.dipole = NULL;
  rl_system *sys = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc d;
  rl_molecule_species(&mol, &d);
  const int count = 500;
  assert_int_equal(rl_system_add_species(sys, &d, count, NULL), RL_OK);
  const double edge = cbrt(count / 0.8), L[3] = {edge, edge, edge};
  assert_int_equal(rl_system_lattice(sys, L, RL_LATTICE_SC, 1, 7), RL_OK);
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 7);
  for (int i = 0; i < count; i++) {
    double r[3];
    rl_system_get_position(sys, i, r);
    for (int c = 0; c < 3; c++) r[c] += gsl_ran_flat(rng, -0.1, 0.1);
    rl_system_set_position(sys, i, r);
    ff_random_orientation(sys, i, rng);
  }
  gsl_rng_free(rng);
  /* Ewald at 5e-4 and 1e-6, PME at 1e-3 (its mesh for 1e-6 at this cutoff would be 1024^3) */
  for (int how = 0; how < 3; how++) {
    const rl_ewald_params ep = params_for(&sff, 2.5, how == 1 ? 1e-6 : how == 2 ? 1e-3 : 5e-4);
    rl_ewald_info info;
    assert_int_equal(rl_ewald_resolve(sys, &ep, how & 2 ? RL_EWALD_PME : RL_EWALD_SUM, &info), RL_OK);
    char label[160];
    snprintf(label, sizeof label, "stockmayer, %d, %s tolerance %g (alpha %.4f /sigma)", count,
             how & 2 ? "pme" : "ewald", ep.tolerance, info.alpha);
    rows_vs_reference(sys, &sff, &sff0, 0, &ep, info.alpha, "dipolar", "stockmayer", label);
  }
  rl_system_free(sys);
}

static void test_tip4p_ew(void **state)
{
  (void)state;
  one_model("tip4p-ew", "tip4p");
}
static void test_spc_e(void **state)
{
  (void)state;
  one_model("spc-e", "charge-lj");
}
static void test_tip3p(void **state)
{
  (void)state;
  one_model("tip3p", "charge-lj");
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_tip4p_ew), cmocka_unit_test(test_spc_e),
                                     cmocka_unit_test(test_tip3p), cmocka_unit_test(test_stockmayer)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
