/* Ewald sums of point charges (forces/ewald/, issue 33): what the sums must give.
 *
 *   madelung          rocksalt NaCl from "ewald-real" + "ewald": the Madelung constant 1.747564594633...
 *   ewald_vs_pme      classical Ewald and smooth PME at tight settings agree (energy, forces, virial)
 *   alpha_independent the total (real + reciprocal + self + intramolecular + background) does not
 *                     depend on alpha, for a neutral mixture and for a charged one
 *   threads           1, 2 and 3 threads give the same bits; a repeat gives the same bits
 *   intramolecular    the excluded pairs' correction is a constant under rigid rotations, and its
 *                     site forces give no force and no torque on any molecule
 *   surface           the dielectric boundary adds 2 pi kc |M|^2 / ((2 eps' + 1) V)
 *   box_change        a change of the cell reaches the terms (their energies follow a fresh term's)
 *   net_force         PME's forces do not sum to zero (the mesh breaks Newton's third law); with
 *                     remove_net_force they do, to round-off, at the same energy, on any thread count */
#include "ewald_testutil.h"

/* ------------------------------------------------------------------------------- Madelung */
static void madelung(void **state)
{
  (void)state;
  /* n x n x n conventional cells of edge a = 1 (lj units: kc = 1), nearest neighbours at 1/2 */
  const int n = 2, N = 8 * n * n * n;
  ff_test_species sp[2];
  ff_ion(&sp[0], 1.0);
  ff_ion(&sp[1], -1.0);
  for (int k = 0; k < 2; k++) sp[k].desc.mass = 1.0;
  rl_system *sys = rl_system_alloc(RL_UNITS_LJ);
  assert_int_equal(rl_system_add_species(sys, &sp[0].desc, N / 2, NULL), RL_OK);
  assert_int_equal(rl_system_add_species(sys, &sp[1].desc, N / 2, NULL), RL_OK);
  const double L[3] = {n, n, n};
  assert_int_equal(rl_system_set_box(sys, L), RL_OK);
  int ip = 0, im = N / 2;
  for (int x = 0; x < 2 * n; x++)
    for (int y = 0; y < 2 * n; y++)
      for (int z = 0; z < 2 * n; z++) {
        const double r[3] = {0.5 * x + 0.013, 0.5 * y - 0.007, 0.5 * z + 0.3}; /* an offset: no site on a cell edge */
        assert_int_equal(rl_system_set_position(sys, (x + y + z) % 2 ? im++ : ip++, r), RL_OK);
      }
  rl_species_ff sff[2] = {ff_test_species_ff(&sp[0]), ff_test_species_ff(&sp[1])};
  rl_ewald_params p;
  rl_ewald_params_default(&p);
  p.species = sff;
  p.nspecies = 2;
  p.cutoff = 0.5 * n;
  p.alpha = 6.0 / p.cutoff; /* erfc(6) = 2e-17 */
  for (int c = 0; c < 3; c++) p.kmax[c] = 13 * n; /* exp(-k^2/4 alpha^2) < 1e-18 beyond */
  p.kmax_sq = 13.0 * n * 13.0 * n;
  rl_terms *t = rl_terms_alloc(sys);
  assert_int_equal(rl_terms_add(t, &rl_term_ewald_real, &p, NULL), RL_OK);
  assert_int_equal(rl_terms_add(t, &rl_term_ewald, &p, NULL), RL_OK);
  ew_result r;
  assert_int_equal(ew_eval(t, sys, &r), RL_OK);
  const double M = -r.energy * 0.5 / (N / 2), Mref = 1.7475645946331821906;
  printf("NaCl (%d ions): U = %.15f (real %.12f, recip %.12f, self %.12f): Madelung %.15f\n", N, r.energy, r.e[0], r.e[1],
         r.e[2], M);
  EW_CHECK_LE("Madelung constant of NaCl from Ewald, relative error", fabs(M - Mref) / Mref, 1e-10);
  double fm = 0;
  for (int i = 0; i < N; i++) fm = fmax(fm, norm3d(r.f[i]));
  EW_CHECK_LE("forces on the ions of a perfect lattice (kc q^2/r0^2 = 4)", fm / 4.0, 1e-12);
  /* PME at a fine mesh gets it too (to its own accuracy) */
  rl_ewald_params pp = p;
  pp.grid[0] = pp.grid[1] = pp.grid[2] = 96;
  pp.order = 10;
  rl_terms *tp = rl_terms_alloc(sys);
  assert_int_equal(rl_terms_add(tp, &rl_term_ewald_real, &pp, NULL), RL_OK);
  assert_int_equal(rl_terms_add(tp, &rl_term_pme, &pp, NULL), RL_OK);
  const double Mp = -ew_energy(tp, sys) * 0.5 / (N / 2);
  EW_CHECK_LE("Madelung constant from smooth PME (order 10, 96^3), relative error", fabs(Mp - Mref) / Mref, 1e-9);
  ew_result_free(&r);
  rl_terms_free(t);
  rl_terms_free(tp);
  rl_system_free(sys);
}

/* --------------------------------------------------------------------------- Ewald vs PME */
static void ewald_vs_pme(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {2.3, 2.5, 2.7};
  ew_scene_mixed(&s, L, 30, 8, 8, 10, 0, 7);
  s.p.cutoff = 1.0;
  s.p.alpha = 3.0;
  for (int c = 0; c < 3; c++) s.p.kmax[c] = (int)ceil(L[c] * 3.0 * 2 * sqrt(40.0) / (2 * M_PI)); /* exp(-40) */
  s.p.grid[0] = 72;
  s.p.grid[1] = 80;
  s.p.grid[2] = 84;
  s.p.order = 10;
  s.p.eps_surface = 3.0;
  rl_terms *te = ew_terms(&s, &rl_term_ewald, NULL), *tp = ew_terms(&s, &rl_term_pme, NULL);
  ew_result a, b;
  assert_int_equal(ew_eval(te, s.sys, &a), RL_OK);
  assert_int_equal(ew_eval(tp, s.sys, &b), RL_OK);
  printf("Ewald (%ld vectors): recip %.12f; PME (%d^3..., order 10): recip %.12f\n",
         rl_ewald_term_info(rl_terms_state(te, 0))->nkvec, a.e[0], s.p.grid[0], b.e[0]);
  EW_CHECK_LE("reciprocal energy, PME vs Ewald, relative", fabs(b.e[0] - a.e[0]) / fabs(a.e[0]), 1e-9);
  EW_CHECK_LE("total of the term, PME vs Ewald, relative", fabs(b.energy - a.energy) / fabs(a.energy), 1e-9);
  EW_CHECK_LE("forces, PME vs Ewald, RMS relative", ew_rel_rms((const double(*)[3])b.f, (const double(*)[3])a.f, a.n), 1e-9);
  EW_CHECK_LE("torques, PME vs Ewald, RMS relative", ew_rel_rms((const double(*)[3])b.k, (const double(*)[3])a.k, a.nrot), 1e-9);
  double dw = 0, wn = 0;
  for (int j = 0; j < 9; j++) {
    dw = fmax(dw, fabs(a.virial[j] - b.virial[j]));
    wn = fmax(wn, fabs(a.virial[j]));
  }
  EW_CHECK_LE("molecular virial, PME vs Ewald, largest element relative to the largest", dw / wn, 1e-9);
  EW_CHECK_TRUE("self, intramolecular, background and surface parts identical in both",
                a.e[1] == b.e[1] && a.e[2] == b.e[2] && a.e[3] == b.e[3] && fabs(a.e[4] - b.e[4]) <= 1e-12 * fabs(a.e[4]));
  ew_result_free(&a);
  ew_result_free(&b);
  rl_terms_free(te);
  rl_terms_free(tp);
  ew_scene_free(&s);
}

/* ------------------------------------------------------------------------ alpha independence */
static void alpha_one(int extra_ion)
{
  ew_scene s;
  const double L[3] = {2.8, 2.8, 2.8};
  ew_scene_mixed(&s, L, 16, 5, 5, 4, extra_ion, 11 + extra_ion);
  s.p.cutoff = 1.4;
  const double alphas[3] = {4.1, 4.5, 4.9};
  double U[3], F0 = 0, dF = 0, dK = 0;
  ew_result r0;
  for (int a = 0; a < 3; a++) {
    s.p.alpha = alphas[a];
    const int km = (int)ceil(L[0] * 2 * alphas[a] * sqrt(40.0) / (2 * M_PI)); /* exp(-k^2/4 alpha^2) < e^-40 */
    for (int c = 0; c < 3; c++) s.p.kmax[c] = km;
    s.p.kmax_sq = (double)km * km;
    rl_terms *t = ew_terms(&s, &rl_term_ewald_real, &rl_term_ewald);
    ew_result r;
    assert_int_equal(ew_eval(t, s.sys, &r), RL_OK);
    U[a] = r.energy;
    printf("alpha %.2f (alpha rc %.2f, kmax %d): real %+.12f recip %+.12f self %+.12f intra %+.12f background %+.12f "
           "total %+.13f\n", alphas[a], alphas[a] * s.p.cutoff, km, r.e[0], r.e[1], r.e[2], r.e[3], r.e[4], r.energy);
    if (a == 0) {
      r0 = r;
      for (int i = 0; i < r.n; i++) F0 = fmax(F0, norm3d(r.f[i]));
    } else {
      dF = fmax(dF, ff_maxdiff((const double(*)[3])r.f, (const double(*)[3])r0.f, r.n));
      dK = fmax(dK, ff_maxdiff((const double(*)[3])r.k, (const double(*)[3])r0.k, r.nrot));
      ew_result_free(&r);
    }
    rl_terms_free(t);
  }
  double dU = fmax(fabs(U[1] - U[0]), fabs(U[2] - U[0]));
  char name[128];
  snprintf(name, sizeof name, "%s: total energy at alpha 4.1, 4.5, 4.9 /nm, spread relative",
           extra_ion ? "charged mixture (+1 e)" : "neutral mixture");
  EW_CHECK_LE(name, dU / fabs(U[0]), 1e-10);
  snprintf(name, sizeof name, "%s: forces and torques, largest change relative to the largest force", extra_ion ? "charged" : "neutral");
  EW_CHECK_LE(name, fmax(dF, dK) / F0, 1e-9);
  ew_result_free(&r0);
  ew_scene_free(&s);
}

static void alpha_independent(void **state)
{
  (void)state;
  alpha_one(0);
  alpha_one(1);
}

/* ------------------------------------------------------------------------------- threads */
static void threads(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {3.2, 3.3, 3.4};
  ew_scene_mixed(&s, L, 500, 20, 20, 40, 0, 3); /* 620 bodies: the body loops go parallel too */
  s.p.cutoff = 0.9;
  s.p.eps_surface = 10.0;
  const rl_term_type *types[3] = {&rl_term_ewald_real, &rl_term_ewald, &rl_term_pme};
  for (int k = 0; k < 3; k++) {
    ew_result r[4];
    for (int T = 1; T <= 4; T++) {
      s.p.threads = T < 4 ? T : 2;
      rl_terms *t = ew_terms(&s, types[k], NULL);
      assert_int_equal(ew_eval(t, s.sys, &r[T - 1]), RL_OK);
      rl_terms_free(t);
    }
    char name[128];
    snprintf(name, sizeof name, "%s: 1, 2 and 3 threads give the same bits (energies, forces, torques, virial)", types[k]->name);
    EW_CHECK_TRUE(name, ew_same_bits(&r[0], &r[1]) && ew_same_bits(&r[0], &r[2]));
    snprintf(name, sizeof name, "%s: a second run on 2 threads gives the same bits", types[k]->name);
    EW_CHECK_TRUE(name, ew_same_bits(&r[1], &r[3]));
    for (int T = 0; T < 4; T++) ew_result_free(&r[T]);
  }
  ew_scene_free(&s);
}

/* ------------------------------------------------------------------ intramolecular correction */
static void intramolecular(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {2.4, 2.4, 2.4};
  ew_scene_mixed(&s, L, 20, 6, 6, 4, 0, 5);
  s.p.cutoff = 1.0;
  rl_terms *t = ew_terms(&s, &rl_term_pme, NULL);
  void *st = rl_terms_state(t, 0);
  ew_result r;
  assert_int_equal(ew_eval(t, s.sys, &r), RL_OK);
  const double Uc = r.e[2];
  const int n = rl_system_count(s.sys), ns = rl_system_nsites(s.sys);
  double (*fs)[3] = malloc(sizeof(double[3]) * (size_t)ns);
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 99);
  double dU = 0, dUterm = 0, fnet = 0, knet = 0, fsite = 0;
  for (int trial = 0; trial < 5; trial++) {
    if (trial)
      for (int i = 0; i < n; i++) ff_random_orientation(s.sys, i, rng); /* rigid rotations of every molecule */
    const double U = rl_ewald_intra_site_forces(st, s.sys, fs);
    dU = fmax(dU, fabs(U - Uc));
    ew_result q;
    assert_int_equal(ew_eval(t, s.sys, &q), RL_OK);
    dUterm = fmax(dUterm, fabs(q.e[2] - Uc));
    ew_result_free(&q);
    for (int a = 0; a < ns; a++) fsite = fmax(fsite, norm3d(fs[a]));
    rl_forces F = {calloc((size_t)n, sizeof(double[3])), calloc((size_t)rl_system_nrot(s.sys) + 1, sizeof(double[3])), 0, {0}, 0};
    rl_system_add_site_forces(s.sys, (const double(*)[3])fs, &F);
    fnet = fmax(fnet, ff_maxnorm((const double(*)[3])F.f, n));
    knet = fmax(knet, ff_maxnorm((const double(*)[3])F.k, rl_system_nrot(s.sys)));
    free(F.f);
    free(F.k);
  }
  printf("U_intra = %.12f kJ/mol; site forces of the correction up to %.3g kJ/mol/nm\n", Uc, fsite);
  EW_CHECK_LE("U_intra from the site pairs at 5 sets of random orientations vs the term's constant, relative", dU / fabs(Uc), 1e-13);
  EW_CHECK_TRUE("the term reports the same constant after every rotation", dUterm == 0.0);
  EW_CHECK_LE("net force of the correction on each molecule, relative to its site forces", fnet / fsite, 1e-14);
  EW_CHECK_LE("net torque of the correction on each molecule (kJ/mol), relative to site force x 0.1 nm", knet / (0.1 * fsite), 1e-13);
  free(fs);
  gsl_rng_free(rng);
  ew_result_free(&r);
  rl_terms_free(t);
  ew_scene_free(&s);
}

/* ------------------------------------------------------------------------- surface term */
static void surface(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {2.2, 2.3, 2.4};
  ew_scene_mixed(&s, L, 20, 6, 6, 4, 0, 8);
  s.p.cutoff = 1.0;
  rl_terms *tinfoil = ew_terms(&s, &rl_term_ewald, NULL);
  s.p.eps_surface = 1.0;
  rl_terms *vac = ew_terms(&s, &rl_term_ewald, NULL);
  ew_result a, b;
  assert_int_equal(ew_eval(tinfoil, s.sys, &a), RL_OK);
  assert_int_equal(ew_eval(vac, s.sys, &b), RL_OK);
  /* M from the sites, independently of the term */
  const int ns = rl_system_nsites(s.sys);
  double (*x)[3] = malloc(sizeof(double[3]) * (size_t)ns), M[3] = {0, 0, 0};
  rl_system_site_positions(s.sys, x);
  for (int i = 0, a0 = 0; i < rl_system_count(s.sys); i++) {
    const int sp = rl_system_species_of(s.sys, i);
    for (int k = 0; k < s.sff[sp].nsites; k++, a0++)
      for (int c = 0; c < 3; c++) M[c] += s.sff[sp].charge[k] * x[a0][c];
  }
  const double want = 2 * M_PI * RL_COULOMB_KJMOL_NM * (M[0] * M[0] + M[1] * M[1] + M[2] * M[2]) / (3.0 * L[0] * L[1] * L[2]);
  printf("|M| = %.6f e nm: surface term %.12f kJ/mol (vacuum), %.1f (tin foil)\n", sqrt(M[0] * M[0] + M[1] * M[1] + M[2] * M[2]),
         b.e[4], a.e[4]);
  EW_CHECK_LE("vacuum boundary minus tin foil = 2 pi kc |M|^2 / 3V, relative", fabs(b.energy - a.energy - want) / want, 1e-13);
  EW_CHECK_TRUE("tin foil: no surface energy", a.e[4] == 0.0);
  free(x);
  ew_result_free(&a);
  ew_result_free(&b);
  rl_terms_free(tinfoil);
  rl_terms_free(vac);
  ew_scene_free(&s);
}

/* ------------------------------------------------------------------------------ box change */
static void box_change(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {2.4, 2.5, 2.6};
  ew_scene_mixed(&s, L, 20, 6, 6, 4, 0, 9);
  s.p.cutoff = 1.0;
  s.p.eps_surface = 2.0;
  const rl_term_type *types[3] = {&rl_term_ewald_real, &rl_term_ewald, &rl_term_pme};
  for (int k = 0; k < 3; k++) {
    rl_terms *t = ew_terms(&s, types[k], NULL);
    ew_result r0;
    assert_int_equal(ew_eval(t, s.sys, &r0), RL_OK);
    const rl_ewald_info in0 = *rl_ewald_term_info(rl_terms_state(t, 0));
    const double L2[3] = {L[0] * 1.01, L[1] * 1.02, L[2] * 0.995};
    assert_int_equal(rl_system_set_box(s.sys, L2), RL_OK);
    ew_result r1, r2;
    assert_int_equal(ew_eval(t, s.sys, &r1), RL_OK);
    /* a fresh term with the first one's alpha, k cutoffs and mesh, on the new cell */
    rl_ewald_params q = s.p;
    q.alpha = in0.alpha;
    for (int c = 0; c < 3; c++) {
      q.kmax[c] = in0.kmax[c];
      q.grid[c] = in0.grid[c];
    }
    rl_terms *t2 = rl_terms_alloc(s.sys);
    assert_int_equal(rl_terms_add(t2, types[k], &q, NULL), RL_OK);
    assert_int_equal(ew_eval(t2, s.sys, &r2), RL_OK);
    char name[128];
    snprintf(name, sizeof name, "%s: after a change of cell, the same bits as a fresh term on the new cell", types[k]->name);
    EW_CHECK_TRUE(name, ew_same_bits(&r1, &r2) && r1.energy != r0.energy);
    assert_int_equal(rl_system_set_box(s.sys, L), RL_OK);
    ew_result_free(&r0);
    ew_result_free(&r1);
    ew_result_free(&r2);
    rl_terms_free(t);
    rl_terms_free(t2);
  }
  ew_scene_free(&s);
}

/* -------------------------------------------------------------------------- net force */
static double net_force_rel(const ew_result *r)
{
  double F[3] = {0, 0, 0}, sum = 0.0;
  for (int i = 0; i < r->n; i++) {
    for (int c = 0; c < 3; c++) F[c] += r->f[i][c];
    sum += norm3d(r->f[i]);
  }
  return norm3d(F) / sum;
}

static void net_force(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {2.2, 2.3, 2.4};
  ew_scene_mixed(&s, L, 200, 10, 10, 20, 0, 11);
  s.p.cutoff = 0.9; /* OpenMM's default tolerance: a 14 x 15 x 15 mesh */
  ew_result raw, fixed[3];
  rl_terms *t = ew_terms(&s, &rl_term_pme, NULL);
  assert_int_equal(ew_eval(t, s.sys, &raw), RL_OK);
  rl_terms_free(t);
  s.p.remove_net_force = 1;
  for (int T = 1; T <= 3; T++) {
    s.p.threads = T;
    t = ew_terms(&s, &rl_term_pme, NULL);
    assert_int_equal(ew_eval(t, s.sys, &fixed[T - 1]), RL_OK);
    rl_terms_free(t);
  }
  EW_CHECK_TRUE("pme: the forces as OpenMM computes them have a net force (> 1e-6 of sum |F|)", net_force_rel(&raw) > 1e-6);
  EW_CHECK_LE("pme, remove_net_force: |sum F| / sum |F| at round-off", net_force_rel(&fixed[0]), 1e-14);
  EW_CHECK_TRUE("pme, remove_net_force: the same energies, to the bit",
                raw.energy == fixed[0].energy && !memcmp(raw.e, fixed[0].e, sizeof(double) * (size_t)raw.ne));
  EW_CHECK_LE("pme, remove_net_force: forces change by no more than the net force's share (rel. RMS)",
              ew_rel_rms((const double(*)[3])fixed[0].f, (const double(*)[3])raw.f, raw.n), 1e-3);
  EW_CHECK_TRUE("pme, remove_net_force: 1, 2 and 3 threads give the same bits",
                ew_same_bits(&fixed[0], &fixed[1]) && ew_same_bits(&fixed[0], &fixed[2]));
  ew_result_free(&raw);
  for (int T = 0; T < 3; T++) ew_result_free(&fixed[T]);
  ew_scene_free(&s);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(madelung),       cmocka_unit_test(ewald_vs_pme), cmocka_unit_test(alpha_independent),
      cmocka_unit_test(threads),        cmocka_unit_test(intramolecular), cmocka_unit_test(surface),
      cmocka_unit_test(box_change),     cmocka_unit_test(net_force),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
