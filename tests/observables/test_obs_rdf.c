/* Observables: radial distribution functions.  Ideal gas -> 1 within counting noise; a simple-
 * cubic lattice (built by rl_system_lattice) has its first peak at the spacing with 6 neighbours
 * and 12 in the second shell; intramolecular exclusion for site pairs (TIP4P H-H); the RDF
 * distance; bad input. */
#include "../testutil.h"

#include <rotleap/observables.h>

static void ideal_gas(void **state)
{
  (void)state;
  const int n = 1000, frames = 20, nbins = 50;
  const double L[3] = {10.0, 11.0, 12.0}, rmax = 5.0;
  double(*x)[3] = malloc(sizeof(double[3]) * n);
  int *mol = malloc(sizeof(int) * n);
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 5);
  rl_rdf *g = rl_rdf_alloc(rmax, nbins), *g2 = rl_rdf_alloc(rmax, nbins);
  assert_non_null(g);
  for (int i = 0; i < n; i++) mol[i] = i;
  for (int f = 0; f < 2 * frames; f++) {
    for (int i = 0; i < n; i++)
      for (int d = 0; d < 3; d++) x[i][d] = (gsl_rng_uniform(rng) - 0.3) * L[d]; /* any image */
    assert_int_equal(rl_rdf_add(f < frames ? g : g2, L, (const double(*)[3])x, n, mol, (const double(*)[3])x, n, mol),
                     RL_OK);
  }
  double r[50], gr[50], chi2 = 0.0, maxz = 0.0, wsum = 0.0, gsum = 0.0;
  int ndof = 0;
  assert_int_equal(rl_rdf_get(g, r, gr), RL_OK);
  double rho = (n - 1) / (L[0] * L[1] * L[2]), dr = rmax / nbins;
  for (int k = 0; k < nbins; k++) {
    double expect = frames * n * rho * 4.0 / 3.0 * M_PI * (pow(k + 1, 3) - pow(k, 3)) * dr * dr * dr;
    if (expect < 100.0) continue;
    /* pair counts of a same-set histogram come in pairs: variance 2 x Poisson */
    double sig = sqrt(2.0 / expect);
    double z = (gr[k] - 1.0) / sig;
    chi2 += z * z;
    ndof++;
    maxz = fmax(maxz, fabs(z));
    wsum += expect;
    gsum += gr[k] * expect;
  }
  printf("info  ideal gas: %d bins checked, chi2/ndof = %.3f\n", ndof, chi2 / ndof);
  CHECK_LE("ideal gas: max |g - 1| / sigma over bins", maxz, 4.5);
  CHECK_NEAR("ideal gas: chi2 / ndof (tol 0.5)", chi2 / ndof, 1.0, 0.5);
  CHECK_NEAR("ideal gas: count-weighted mean g (tol 0.3%)", gsum / wsum, 1.0, 0.003);
  double d;
  assert_int_equal(rl_rdf_distance(g, g2, &d), RL_OK);
  printf("info  ideal gas: distance between two independent halves = %.4f\n", d);
  CHECK_LE("RDF distance of two ideal-gas estimates / r_max", d / rmax, 0.05);
  assert_int_equal(rl_rdf_distance(g, g, &d), RL_OK);
  CHECK_LE("RDF distance of an RDF to itself", d, 0.0);
  /* bad input */
  const double Lsmall[3] = {9.0, 12.0, 12.0};
  assert_int_equal(rl_rdf_add(g, Lsmall, (const double(*)[3])x, n, mol, (const double(*)[3])x, n, mol), RL_EINVAL);
  printf("info  message: %s\n", rl_last_error());
  assert_null(rl_rdf_alloc(-1.0, 10));
  rl_rdf *h = rl_rdf_alloc(rmax, 10);
  assert_int_equal(rl_rdf_get(h, r, gr), RL_ESTATE);
  assert_int_equal(rl_rdf_distance(g, h, &d), RL_EINVAL);
  rl_rdf_free(h);
  rl_rdf_free(NULL);
  rl_rdf_free(g);
  rl_rdf_free(g2);
  gsl_rng_free(rng);
  free(x);
  free(mol);
}

static void sc_lattice(void **state)
{
  (void)state;
  const rl_model *md = rl_catalog_find("stockmayer");
  rl_molecule m;
  assert_int_equal(rl_model_build(md, NULL, 0, &m), RL_OK);
  rl_system *sys = rl_system_alloc(md->units);
  rl_species_desc desc;
  rl_molecule_species(&m, &desc);
  assert_int_equal(rl_system_add_species(sys, &desc, 216, NULL), RL_OK);
  const double L[3] = {6.0, 6.0, 6.0};
  assert_int_equal(rl_system_lattice(sys, L, RL_LATTICE_SC, 1, 3), RL_OK);
  const int nbins = 125; /* dr = 0.024: r = 1 and sqrt 2 fall inside bins, not on edges */
  rl_rdf *g = rl_rdf_alloc(3.0, nbins);
  assert_int_equal(rl_rdf_add_sites(g, sys, 0, 0, 0, 0), RL_OK);
  double r[125], gr[125];
  assert_int_equal(rl_rdf_get(g, r, gr), RL_OK);
  int kmax = 0;
  for (int k = 0; k < nbins; k++)
    if (gr[k] > 0.0) {
      kmax = k;
      break;
    }
  printf("info  sc lattice: first non-zero bin at r = %.3f, g = %.1f\n", r[kmax], gr[kmax]);
  CHECK_LE("sc lattice: |first peak - spacing| / bin width", fabs(r[kmax] - 1.0) / (3.0 / nbins), 0.5);
  CHECK_NEAR("sc lattice: first-shell coordination (0 .. 1.2)", rl_rdf_coordination(g, 0.0, 1.2), 6.0, 1e-12);
  CHECK_NEAR("sc lattice: second-shell coordination (1.2 .. 1.6)", rl_rdf_coordination(g, 1.2, 1.6), 12.0, 1e-12);
  /* out-of-range site and species */
  assert_int_equal(rl_rdf_add_sites(g, sys, 0, 1, 0, 0), RL_EINVAL);
  assert_int_equal(rl_rdf_add_sites(g, sys, 1, 0, 0, 0), RL_EINVAL);
  rl_rdf_free(g);
  rl_system_free(sys);
}

/* TIP4P H-H: sites 1 and 2 are the hydrogens.  With one molecule in a large box, every H-H pair is
 * intramolecular and excluded; with two molecules the H1-H1 RDF counts only the other molecule. */
static void water_exclusion(void **state)
{
  (void)state;
  const rl_model *md = rl_catalog_find("tip4p");
  rl_molecule m;
  assert_int_equal(rl_model_build(md, NULL, 0, &m), RL_OK);
  assert_string_equal(m.site_names[1], "H1");
  rl_system *sys = rl_system_alloc(md->units);
  rl_species_desc desc;
  rl_molecule_species(&m, &desc);
  assert_int_equal(rl_system_add_species(sys, &desc, 2, NULL), RL_OK);
  const double L[3] = {3.0, 3.0, 3.0}, r0[3] = {0, 0, 0}, r1[3] = {0.5, 0, 0};
  rl_system_set_position(sys, 0, r0);
  rl_system_set_position(sys, 1, r1);
  assert_int_equal(rl_system_set_box(sys, L), RL_OK);
  rl_rdf *g = rl_rdf_alloc(1.5, 150);
  assert_int_equal(rl_rdf_add_sites(g, sys, 0, 1, 0, 2), RL_OK); /* H1-H2 */
  /* identity orientations: H1 of 0 to H2 of 1 and H1 of 1 to H2 of 0 - the intramolecular
     H1-H2 distance (0.1514 nm) must not appear */
  double bond = 0.0;
  for (int d = 0; d < 3; d++) bond += (m.sites[1][d] - m.sites[2][d]) * (m.sites[1][d] - m.sites[2][d]);
  bond = sqrt(bond);
  CHECK_NEAR("TIP4P H1-H2: intramolecular pair excluded", rl_rdf_coordination(g, bond - 0.02, bond + 0.02), 0.0, 0.0);
  CHECK_NEAR("TIP4P H1-H2: one intermolecular neighbour per H1", rl_rdf_coordination(g, 0.0, 1.5), 1.0, 0.0);
  rl_rdf_free(g);
  rl_system_free(sys);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(ideal_gas), cmocka_unit_test(sc_lattice),
                                     cmocka_unit_test(water_exclusion)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
