/* ewald_point: single points of the Ewald terms through the library, as JSON, for the OpenMM
 * comparisons and the accuracy and speed scripts in validate/ (issue 33).  `rotleap energy`
 * does not know these terms yet (the deck keys come later).
 *
 * A configuration is one of
 *   --checkpoint FILE --model NAME   a rotleap checkpoint of catalogue molecules (r and A bit for bit)
 *   --lattice NAME COUNT DENSITY SEED  COUNT molecules on a simple-cubic lattice at DENSITY g/cm3,
 *                                    random orientations (for timing)
 *   --ions COUNT EDGE SEED           COUNT random point ions of charge +1 / -1 (alternately) in a
 *                                    cube of EDGE nm, centres at least 0.25 nm apart
 *   --dipoles FILE                   point dipoles in LJ units (kc = 1): FILE has "N L MU" (count,
 *                                    cube edge, dipole moment) and then N lines "x y z ex ey ez"
 *                                    (centre and unit axis); for the LAMMPS comparison
 * and the Ewald parameters (rl_ewald_params):
 *   --method pme|ewald  --cutoff RC  [--tolerance D] [--alpha A] [--grid NX NY NZ] [--order P]
 *   [--kmax KX KY KZ] [--kmax-sq S] [--eps-surface E] [--threads T]
 * Output: the resolved parameters and estimated errors, the energy by component ("ewald_real" +
 * the reciprocal term's five) and its total, the molecular forces and torques; with --sites the
 * force on every site (with the intramolecular correction's site forces, which the terms leave out); with --repeat N also the time per evaluation of each term (best of N) and,
 * with --pair, that of the pair term (reaction field, the specialised kernels) on the same
 * configuration for comparison. */
#include <rotleap/rotleap.h>
#include "rotleap/ewald.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static void die(const char *what)
{
  fprintf(stderr, "ewald_point: %s: %s\n", what, rl_last_error());
  exit(1);
}

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* JSON has no NaN: the error estimates that do not apply (charges' with dipoles alone, dipoles' with
 * charges alone) as -1 then */
static double finite_or(double x) { return isfinite(x) ? x : -1.0; }

static void vec(const char *name, const double *v, int last)
{
  printf("\"%s\": [%.17g, %.17g, %.17g]%s", name, v[0], v[1], v[2], last ? "" : ", ");
}

int main(int argc, char **argv)
{
  const char *chk = NULL, *model = NULL, *lattice = NULL, *method = "pme", *dipoles = NULL;
  int count = 0, nions = 0, sites = 0, repeat = 0, pair = 0;
  double density = 0, ion_edge = 0;
  unsigned long seed = 1;
  rl_ewald_params p;
  rl_ewald_params_default(&p);
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
#define NEED(k) if (i + (k) >= argc) { fprintf(stderr, "ewald_point: %s needs %d values\n", a, k); return 2; }
    if (!strcmp(a, "--checkpoint")) { NEED(1); chk = argv[++i]; }
    else if (!strcmp(a, "--model")) { NEED(1); model = argv[++i]; }
    else if (!strcmp(a, "--lattice")) { NEED(4); lattice = argv[++i]; count = atoi(argv[++i]); density = atof(argv[++i]); seed = strtoul(argv[++i], NULL, 10); }
    else if (!strcmp(a, "--ions")) { NEED(3); nions = atoi(argv[++i]); ion_edge = atof(argv[++i]); seed = strtoul(argv[++i], NULL, 10); }
    else if (!strcmp(a, "--dipoles")) { NEED(1); dipoles = argv[++i]; }
    else if (!strcmp(a, "--method")) { NEED(1); method = argv[++i]; }
    else if (!strcmp(a, "--cutoff")) { NEED(1); p.cutoff = atof(argv[++i]); }
    else if (!strcmp(a, "--tolerance")) { NEED(1); p.tolerance = atof(argv[++i]); }
    else if (!strcmp(a, "--alpha")) { NEED(1); p.alpha = atof(argv[++i]); }
    else if (!strcmp(a, "--grid")) { NEED(3); for (int c = 0; c < 3; c++) p.grid[c] = atoi(argv[++i]); }
    else if (!strcmp(a, "--order")) { NEED(1); p.order = atoi(argv[++i]); }
    else if (!strcmp(a, "--kmax")) { NEED(3); for (int c = 0; c < 3; c++) p.kmax[c] = atoi(argv[++i]); }
    else if (!strcmp(a, "--kmax-sq")) { NEED(1); p.kmax_sq = atof(argv[++i]); }
    else if (!strcmp(a, "--eps-surface")) { NEED(1); p.eps_surface = atof(argv[++i]); }
    else if (!strcmp(a, "--threads")) { NEED(1); p.threads = atoi(argv[++i]); }
    else if (!strcmp(a, "--sites")) sites = 1;
    else if (!strcmp(a, "--repeat")) { NEED(1); repeat = atoi(argv[++i]); }
    else if (!strcmp(a, "--pair")) pair = 1;
    else { fprintf(stderr, "ewald_point: unknown option %s (see the source's header)\n", a); return 2; }
#undef NEED
  }
  const rl_term_type *recip = !strcmp(method, "ewald") ? &rl_term_ewald : !strcmp(method, "pme") ? &rl_term_pme : NULL;
  if (!recip) { fprintf(stderr, "ewald_point: --method must be pme or ewald\n"); return 2; }
  rl_system *sys = NULL;
  rl_molecule mol;
  rl_species_ff sff[2];
  double ionq[2] = {1.0, -1.0}, zero[2] = {0, 0}, sig[2] = {0.25, 0.25}, mu = 0.0;
  int nsp = 1;
  if (chk || lattice) {
    const rl_model *m = rl_catalog_find(chk ? model : lattice);
    if (!m || rl_model_build(m, NULL, 0, &mol)) die("model");
    sff[0] = rl_molecule_ff(&mol);
    if (chk) {
      rl_checkpoint_meta meta;
      sys = rl_checkpoint_load(chk, &meta);
      if (!sys) die("checkpoint");
      free((void *)meta.blob);
      if (!rl_system_periodic(sys) && rl_system_set_box(sys, meta.box)) die("box");
    } else {
      sys = rl_system_alloc(m->units);
      rl_species_desc d;
      rl_molecule_species(&mol, &d);
      if (rl_system_add_species(sys, &d, count, NULL)) die("species");
      const double edge = cbrt(count * mol.mass / (density * 602.21407621)); /* g/cm3 = 602.214 amu/nm^3 */
      const double L[3] = {edge, edge, edge};
      if (rl_system_lattice(sys, L, RL_LATTICE_SC, 1, seed)) die("lattice");
    }
  } else if (dipoles) {
    FILE *in = fopen(dipoles, "r");
    int nd = 0;
    double edge = 0;
    if (!in || fscanf(in, "%d %lf %lf", &nd, &edge, &mu) != 3 || nd < 1) { fprintf(stderr, "ewald_point: cannot read %s\n", dipoles); return 2; }
    sys = rl_system_alloc(RL_UNITS_LJ);
    const rl_species_desc d = {"stockmayer", RL_KIND_DIPOLE, 1.0, {0.025, 0.025, 0.025}, 1, (const double[3]){0, 0, 0}};
    if (rl_system_add_species(sys, &d, nd, NULL)) die("dipoles");
    sff[0] = (rl_species_ff){1, sig, zero, zero, &mu, NULL};
    const double L[3] = {edge, edge, edge};
    if (rl_system_set_box(sys, L)) die("box");
    for (int i = 0; i < nd; i++) {
      double r[3], e[3];
      if (fscanf(in, "%lf %lf %lf %lf %lf %lf", r, r + 1, r + 2, e, e + 1, e + 2) != 6) { fprintf(stderr, "ewald_point: %s: line %d\n", dipoles, i + 2); return 2; }
      if (rl_system_set_position(sys, i, r) || rl_system_set_axis(sys, i, e)) die("dipole");
    }
    fclose(in);
  } else if (nions > 0) {
    sys = rl_system_alloc(RL_UNITS_REAL);
    for (int s = 0; s < 2; s++) {
      const rl_species_desc d = {s ? "anion" : "cation", RL_KIND_POINT, 23.0, {0, 0, 0}, 1, (const double[3]){0, 0, 0}};
      if (rl_system_add_species(sys, &d, s ? nions / 2 : nions - nions / 2, NULL)) die("ions");
      sff[s] = (rl_species_ff){1, sig + s, zero + s, ionq + s, NULL, NULL};
    }
    nsp = 2;
    const double L[3] = {ion_edge, ion_edge, ion_edge};
    if (rl_system_set_box(sys, L)) die("box");
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, seed);
    double (*r)[3] = malloc(sizeof(double[3]) * (size_t)nions);
    for (int i = 0; i < nions; i++) {
      for (int ok = 0; !ok;) {
        for (int c = 0; c < 3; c++) r[i][c] = gsl_rng_uniform(rng) * ion_edge;
        ok = 1;
        for (int j = 0; j < i && ok; j++) {
          double d2 = 0;
          for (int c = 0; c < 3; c++) {
            double d = r[i][c] - r[j][c];
            d -= ion_edge * nearbyint(d / ion_edge);
            d2 += d * d;
          }
          ok = d2 >= 0.25 * 0.25;
        }
      }
      if (rl_system_set_position(sys, i, r[i])) die("position");
    }
    free(r);
    gsl_rng_free(rng);
  } else {
    fprintf(stderr, "ewald_point: give --checkpoint FILE --model NAME, --lattice ..., --ions ... or --dipoles FILE\n");
    return 2;
  }
  if (rl_system_nspecies(sys) != nsp) { fprintf(stderr, "ewald_point: one species expected\n"); return 2; }
  p.species = sff;
  p.nspecies = nsp;
  rl_terms *t = rl_terms_alloc(sys);
  int kreal, krecip;
  if (!t || rl_terms_add(t, &rl_term_ewald_real, &p, &kreal) || rl_terms_add(t, recip, &p, &krecip)) die("terms");
  const int n = rl_system_count(sys), nr = rl_system_nrot(sys), ns = rl_system_nsites(sys);
  double (*f)[3] = calloc((size_t)n, sizeof(double[3])), (*k)[3] = calloc((size_t)nr + 1, sizeof(double[3]));
  rl_forces F = {f, k, 0.0, {0}, 0};
  if (rl_terms_compute(t, sys, &F)) die("compute");
  const rl_ewald_info *in = rl_ewald_term_info(rl_terms_state(t, krecip));
  char text[1024];
  rl_ewald_describe(in, rl_system_units(sys), text, sizeof text);
  printf("{\"describe\": \"%s\",\n", text);
  printf("\"params\": {\"method\": \"%s\", \"alpha\": %.17g, \"cutoff\": %.17g, \"tolerance\": %.17g, \"kmax\": [%d, %d, %d], "
         "\"kmax_sq\": %.17g, \"nkvec\": %ld, \"grid\": [%d, %d, %d], \"order\": %d, \"err_real\": %.6g, \"err_recip\": %.6g, "
         "\"err_total\": %.6g, \"nsites_charged\": %d, \"sum_q2\": %.17g, \"nsites_dipolar\": %d, \"sum_mu2\": %.17g, "
         "\"dip_err_real\": %.6g, \"dip_err_recip\": %.6g, \"dip_err_total\": %.6g, \"dip_terr_real\": %.6g, "
         "\"dip_terr_recip\": %.6g, \"dip_terr_total\": %.6g, \"dip_target\": %.6g},\n",
         method, in->alpha, in->cutoff, in->tolerance, in->kmax[0], in->kmax[1], in->kmax[2], in->kmax_sq, in->nkvec,
         in->grid[0], in->grid[1], in->grid[2], in->order, finite_or(in->err_real), finite_or(in->err_recip),
         finite_or(in->err_total), in->nsites_charged, in->sum_q2, in->nsites_dipolar, in->sum_mu2,
         finite_or(in->dip_err_real), finite_or(in->dip_err_recip), finite_or(in->dip_err_total), finite_or(in->dip_terr_real),
         finite_or(in->dip_terr_recip), finite_or(in->dip_terr_total), in->dip_target);
  double L[3];
  rl_system_box(sys, L);
  printf("\"box\": [%.17g, %.17g, %.17g], \"count\": %d,\n\"energy\": {", L[0], L[1], L[2], n);
  for (int j = 0; j < rl_terms_nenergies(t); j++) printf("\"%s\": %.17g, ", rl_terms_energy_name(t, j), rl_terms_energy(t, j));
  printf("\"total\": %.17g},\n\"virial\": [", F.energy);
  for (int j = 0; j < 9; j++) printf("%.17g%s", F.virial[j], j < 8 ? ", " : "],\n");
  printf("\"molecules\": [\n");
  for (int i = 0; i < n; i++) {
    const int ri = rl_system_rot_index(sys, i);
    const double zero3[3] = {0, 0, 0};
    printf("{");
    vec("force", f[i], 0);
    vec("torque", ri >= 0 ? k[ri] : zero3, 1);
    printf("}%s\n", i < n - 1 ? "," : "");
  }
  printf("]");
  if (sites) {
    /* real space + reciprocal part + the intramolecular correction's site forces (which the terms
     * leave out: they cancel on each rigid body, not on its sites): the forces of the Coulomb
     * interactions between sites of different bodies, whatever alpha */
    double (*fs)[3] = calloc((size_t)ns, sizeof(double[3])), (*fr)[3] = calloc((size_t)ns, sizeof(double[3]));
    double (*fi)[3] = calloc((size_t)ns, sizeof(double[3]));
    if (rl_ewald_site_forces(rl_terms_state(t, kreal), sys, fs, NULL, NULL) ||
        rl_ewald_site_forces(rl_terms_state(t, krecip), sys, fr, NULL, NULL) ||
        isnan(rl_ewald_intra_site_forces(rl_terms_state(t, krecip), sys, fi)))
      die("site forces");
    printf(",\n\"sites\": [\n");
    for (int a = 0; a < ns; a++)
      printf("[%.17g, %.17g, %.17g]%s\n", fs[a][0] + fr[a][0] + fi[a][0], fs[a][1] + fr[a][1] + fi[a][1],
             fs[a][2] + fr[a][2] + fi[a][2], a < ns - 1 ? "," : "");
    printf("]");
    free(fs);
    free(fr);
    free(fi);
  }
  if (repeat > 0) {
    /* time per evaluation of each term alone (best of `repeat`) */
    rl_terms *one[3] = {rl_terms_alloc(sys), rl_terms_alloc(sys), NULL};
    if (rl_terms_add(one[0], &rl_term_ewald_real, &p, NULL) || rl_terms_add(one[1], recip, &p, NULL)) die("terms");
    rl_pair_params pp;
    if (pair) {
      rl_ff_params_default(&pp.p);
      pp.p.cutoff = p.cutoff;
      pp.p.threads = p.threads;
      pp.species = sff;
      pp.nspecies = nsp;
      pp.geometric_mixing = 0;
      one[2] = rl_terms_alloc(sys);
      if (rl_terms_add(one[2], &rl_term_pair, &pp, NULL)) die("pair term");
    }
    double best[3] = {INFINITY, INFINITY, INFINITY};
    for (int r = 0; r < repeat; r++)
      for (int j = 0; j < 3; j++) {
        if (!one[j]) continue;
        memset(f, 0, sizeof(double[3]) * (size_t)n);
        memset(k, 0, sizeof(double[3]) * (size_t)(nr + 1));
        rl_forces G = {f, k, 0.0, {0}, 0};
        const double t0 = now();
        if (rl_terms_compute(one[j], sys, &G)) die("compute");
        const double dt = now() - t0;
        if (dt < best[j]) best[j] = dt;
      }
    printf(",\n\"time\": {\"ewald_real\": %.6g, \"%s\": %.6g", best[0], recip->name, best[1]);
    if (pair) printf(", \"pair_rf\": %.6g", best[2]);
    printf(", \"repeat\": %d, \"threads\": %d}", repeat, p.threads);
    for (int j = 0; j < 3; j++) rl_terms_free(one[j]);
  }
  printf("\n}\n");
  free(f);
  free(k);
  rl_terms_free(t);
  rl_system_free(sys);
  return 0;
}
