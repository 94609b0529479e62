/* Ewald parameters (forces/ewald/ewald_params.c, issue 33):
 *   openmm_choices  alpha, the PME grid and the Ewald kmax derived from a tolerance are OpenMM 7.7's
 *                   (numbers from its getPMEParametersInContext and, for kmax, from the energies
 *                   of validate/ewald_openmm.py), to the bit
 *   describe        the one-line description and the estimated errors
 *   warnings        a net charge is named; a neutral system has no warning
 *   bad_input       every refused input, with a message naming the parameter
 *   lookup          the term types are found by name */
#include "ewald_testutil.h"

/* two point ions of charge +1 and -1 in a box */
static rl_system *pair_system(const double L[3], ff_test_species sp[2], rl_species_ff sff[2])
{
  ff_ion(&sp[0], 1.0);
  ff_ion(&sp[1], -1.0);
  rl_system *sys = rl_system_alloc(RL_UNITS_REAL);
  for (int k = 0; k < 2; k++) {
    assert_int_equal(rl_system_add_species(sys, &sp[k].desc, 1, NULL), RL_OK);
    sff[k] = ff_test_species_ff(&sp[k]);
  }
  assert_int_equal(rl_system_set_box(sys, L), RL_OK);
  const double r[3] = {0.5, 0.6, 0.7};
  assert_int_equal(rl_system_set_position(sys, 1, r), RL_OK);
  return sys;
}

static void openmm_choices(void **state)
{
  (void)state;
  /* box, cutoff, tolerance -> OpenMM 7.7's alpha and grid (Reference platform,
   * NonbondedForce::getPMEParametersInContext) */
  const struct {
    double L[3], rc, tol, alpha;
    int grid[3];
  } pme[] = {
      {{1.8625827908797699, 1.8625827908797699, 1.8625827908797699}, 0.9, 5e-4, 2.9202898720871846, {17, 17, 17}},
      {{1.55, 1.60, 1.70}, 0.75, 5e-4, 3.5043478465046212, {17, 18, 19}},
      {{3.948, 3.948, 3.948}, 0.9, 5e-4, 2.9202898720871846, {36, 36, 36}},
      {{5.0, 5.0, 5.0}, 1.2, 1e-5, 2.741119282287687, {92, 92, 92}},
      {{2.5, 3.1, 4.7}, 1.0, 1e-3, 2.4929115705179337, {17, 21, 32}},
      {{2.0, 2.0, 2.0}, 0.95, 0.09, 1.3784243395760438, {6, 6, 6}},
  };
  int good = 1;
  for (size_t c = 0; c < sizeof pme / sizeof pme[0]; c++) {
    ff_test_species sp[2];
    rl_species_ff sff[2];
    rl_system *sys = pair_system(pme[c].L, sp, sff);
    rl_ewald_params p;
    rl_ewald_params_default(&p);
    p.species = sff;
    p.nspecies = 2;
    p.cutoff = pme[c].rc;
    p.tolerance = pme[c].tol;
    rl_ewald_info in;
    assert_int_equal(rl_ewald_resolve(sys, &p, RL_EWALD_PME, &in), RL_OK);
    const int same = in.alpha == pme[c].alpha && !memcmp(in.grid, pme[c].grid, sizeof in.grid) && in.order == 5;
    printf("  box %.4g %.4g %.4g, rc %g, tolerance %g: alpha %.17g grid %d %d %d%s\n", pme[c].L[0], pme[c].L[1], pme[c].L[2],
           pme[c].rc, pme[c].tol, in.alpha, in.grid[0], in.grid[1], in.grid[2], same ? "" : "  (OpenMM's differ)");
    good &= same;
    rl_system_free(sys);
  }
  EW_CHECK_TRUE("PME from a tolerance: alpha (to the bit), grid and order 5 as OpenMM 7.7 chooses, 6 cases", good);
  /* Ewald: OpenMM's kmax - 1, found by the energies agreeing with OpenMM (validate/ewald_openmm.py) */
  const struct {
    double L[3], rc, tol;
    int kmax[3];
  } ew[] = {
      {{1.8625827908797699, 1.8625827908797699, 1.8625827908797699}, 0.9, 5e-4, {4, 4, 4}},
      {{1.8625827908797699, 1.8625827908797699, 1.8625827908797699}, 0.9, 1e-5, {8, 8, 8}},
      {{1.55, 1.60, 1.70}, 0.75, 5e-4, {4, 4, 6}},
      {{1.55, 1.60, 1.70}, 0.75, 1e-5, {8, 8, 8}},
  };
  good = 1;
  for (size_t c = 0; c < sizeof ew / sizeof ew[0]; c++) {
    ff_test_species sp[2];
    rl_species_ff sff[2];
    rl_system *sys = pair_system(ew[c].L, sp, sff);
    rl_ewald_params p;
    rl_ewald_params_default(&p);
    p.species = sff;
    p.nspecies = 2;
    p.cutoff = ew[c].rc;
    p.tolerance = ew[c].tol;
    rl_ewald_info in;
    assert_int_equal(rl_ewald_resolve(sys, &p, RL_EWALD_SUM, &in), RL_OK);
    good &= !memcmp(in.kmax, ew[c].kmax, sizeof in.kmax) && in.kmax_sq == 0.0 &&
            in.nkvec == ((2L * in.kmax[0] + 1) * (2 * in.kmax[1] + 1) * (2 * in.kmax[2] + 1) - 1) / 2;
    rl_system_free(sys);
  }
  EW_CHECK_TRUE("Ewald from a tolerance: |n_c| <= OpenMM's kmax - 1, the whole box of vectors, 4 cases", good);
}

static void describe(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {2.0, 2.0, 2.0};
  ew_scene_mixed(&s, L, 10, 2, 2, 2, 0, 4);
  s.p.cutoff = 0.9;
  rl_ewald_info in;
  char text[512];
  assert_int_equal(rl_ewald_resolve(s.sys, &s.p, RL_EWALD_PME, &in), RL_OK);
  rl_ewald_describe(&in, RL_UNITS_REAL, text, sizeof text);
  printf("  %s\n", text);
  EW_CHECK_TRUE("PME description: method, alpha from the tolerance, grid, order, boundary, estimated error",
                strstr(text, "smooth PME: alpha = 2.92029 /nm (from tolerance 0.0005 and cutoff 0.9 nm)") &&
                    strstr(text, "grid 18 x 18 x 18 (from the tolerance), order 5, tin-foil boundary") &&
                    strstr(text, "estimated RMS force error on a charge"));
  EW_CHECK_TRUE("estimated errors: positive, total = root sum of squares",
                in.err_real > 0 && in.err_recip > 0 && fabs(in.err_total - hypot(in.err_real, in.err_recip)) < 1e-12 * in.err_total);
  s.p.kmax[0] = s.p.kmax[1] = s.p.kmax[2] = 7;
  s.p.kmax_sq = 50;
  s.p.alpha = 3.5;
  s.p.eps_surface = 1.0;
  assert_int_equal(rl_ewald_resolve(s.sys, &s.p, RL_EWALD_SUM, &in), RL_OK);
  rl_ewald_describe(&in, RL_UNITS_REAL, text, sizeof text);
  printf("  %s\n", text);
  EW_CHECK_TRUE("Ewald description: given alpha, |n| and n^2 limits, the vector count, the dielectric boundary",
                strstr(text, "Ewald: alpha = 3.5 /nm (given; tolerance 0.0005 and cutoff 0.9 nm)") &&
                    strstr(text, "|n| <= 7 7 7, n^2 <= 50 (given;") && strstr(text, "dielectric boundary eps' = 1"));
  /* the spherical limit counts what it should: n in the half space with |n_c| <= 7 and n^2 <= 50 */
  long count = 0;
  for (int x = -7; x <= 7; x++)
    for (int y = -7; y <= 7; y++)
      for (int z = -7; z <= 7; z++) count += (x || y || z) && x * x + y * y + z * z <= 50;
  EW_CHECK_TRUE("vectors with n^2 <= kmax_sq: half of those in the sphere", in.nkvec == count / 2);
  ew_scene_free(&s);
}

static void warnings(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {2.0, 2.1, 2.2};
  ew_scene_mixed(&s, L, 6, 2, 2, 2, 1, 4);
  s.p.cutoff = 0.9;
  rl_terms *t = ew_terms(&s, &rl_term_pme, &rl_term_ewald_real);
  rl_ff_warning w[2];
  const int nw = rl_ewald_warnings(rl_terms_state(t, 0), w, 2);
  printf("  %s\n", nw ? w[0].text : "(none)");
  EW_CHECK_TRUE("a net charge of +1 e: one warning naming it and the background",
                nw == 1 && strstr(w[0].text, "net charge of 1 e") && strstr(w[0].text, "neutralising background"));
  EW_CHECK_TRUE("the real-space term warns of nothing", rl_ewald_warnings(rl_terms_state(t, 1), w, 2) == 0);
  rl_terms_free(t);
  ew_scene_free(&s);
  ew_scene_mixed(&s, L, 6, 2, 2, 2, 0, 4);
  s.p.cutoff = 0.9;
  t = ew_terms(&s, &rl_term_ewald, NULL);
  EW_CHECK_TRUE("a neutral system: no warning", rl_ewald_warnings(rl_terms_state(t, 0), w, 2) == 0);
  rl_terms_free(t);
  ew_scene_free(&s);
}

/* Expect alloc (through rl_terms_add) to fail with a message containing `want`. */
static int refused(rl_system *sys, const rl_term_type *type, const rl_ewald_params *p, const char *want)
{
  rl_terms *t = rl_terms_alloc(sys);
  const int st = rl_terms_add(t, type, p, NULL);
  rl_terms_free(t);
  const int ok = st != RL_OK && strstr(rl_last_error(), want) != NULL;
  printf("  %s: %s%s\n", type->name, rl_last_error(), ok ? "" : "   <-- expected a refusal naming: ");
  if (!ok) printf("      %s\n", want);
  return ok;
}

static void bad_input(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {1.86, 1.86, 1.86};
  ew_scene_mixed(&s, L, 12, 2, 2, 2, 0, 4);
  s.p.cutoff = 0.9;
  rl_ewald_params p = s.p;
  int ok = 1;
  const double bad_tol[4] = {0.0, 0.1, -1e-3, NAN};
  for (int k = 0; k < 4; k++) {
    p = s.p;
    p.tolerance = bad_tol[k];
    ok &= refused(s.sys, &rl_term_pme, &p, "tolerance = ") && strstr(rl_last_error(), "must lie in (0, 0.1)");
  }
  EW_CHECK_TRUE("tolerance outside (0, 0.1): 0, 0.1, -1e-3, NaN refused, naming tolerance", ok);
  p = s.p;
  p.cutoff = 0.0;
  ok = refused(s.sys, &rl_term_ewald_real, &p, "cutoff = 0 must be positive");
  p.cutoff = 0.95;
  ok &= refused(s.sys, &rl_term_ewald, &p, "cutoff = 0.95 exceeds half the box edge x = 1.86");
  EW_CHECK_TRUE("cutoff not positive, or beyond half an edge: refused, naming cutoff", ok);
  p = s.p;
  p.alpha = 1.2;
  ok = refused(s.sys, &rl_term_ewald_real, &p, "alpha = 1.2 with cutoff = 0.9: alpha cutoff = 1.08 is below sqrt(-ln 0.2)");
  EW_CHECK_TRUE("a cutoff that makes alpha meaningless (alpha rc < 1.27): refused, naming alpha and cutoff", ok);
  p = s.p;
  p.cutoff = 0.02; /* alpha = 131 /nm: an 800-point grid per edge */
  ok = refused(s.sys, &rl_term_pme, &p, "follows from the cutoff and tolerance: the cutoff is too short");
  p.cutoff = 0.03; /* alpha = 88 /nm: 2.3e7 vectors */
  ok &= refused(s.sys, &rl_term_ewald, &p, "the cutoff is too short for the tolerance");
  EW_CHECK_TRUE("a cutoff so short that the reciprocal sum explodes: refused, naming the cutoff", ok);
  p = s.p;
  p.alpha = 3.3;
  p.grid[0] = 8;
  p.grid[1] = p.grid[2] = 24;
  ok = refused(s.sys, &rl_term_pme, &p, "grid[0] = 8 is too coarse for tolerance 0.0005");
  p.grid[0] = 4;
  ok &= refused(s.sys, &rl_term_pme, &p, "grid[0] = 4 is below the spline order 5");
  p = s.p;
  p.kmax[0] = p.kmax[1] = p.kmax[2] = 2;
  ok &= refused(s.sys, &rl_term_ewald, &p, "kmax = 2 2 2, kmax_sq = 0 is too coarse for tolerance 0.0005");
  p = s.p;
  p.kmax[0] = p.kmax[1] = p.kmax[2] = 8;
  p.kmax_sq = 4;
  ok &= refused(s.sys, &rl_term_ewald, &p, "kmax_sq = 4 is too coarse");
  EW_CHECK_TRUE("a grid or k-vector set too coarse for the tolerance, or below the spline order: refused, naming it", ok);
  p = s.p;
  p.order = 2;
  ok = refused(s.sys, &rl_term_pme, &p, "order = 2 must lie in 3..12");
  p.order = 13;
  ok &= refused(s.sys, &rl_term_pme, &p, "order = 13 must lie in 3..12");
  p = s.p;
  p.grid[1] = -3;
  ok &= refused(s.sys, &rl_term_pme, &p, "grid[1] = -3 must be >= 0");
  p = s.p;
  p.kmax[2] = -1;
  ok &= refused(s.sys, &rl_term_ewald, &p, "kmax[2] = -1 must be >= 0");
  p = s.p;
  p.kmax_sq = -2;
  ok &= refused(s.sys, &rl_term_ewald, &p, "kmax_sq = -2 must be >= 0");
  p = s.p;
  p.eps_surface = 0.5;
  ok &= refused(s.sys, &rl_term_pme, &p, "eps_surface = 0.5 must be >= 1");
  p = s.p;
  p.alpha = -1;
  ok &= refused(s.sys, &rl_term_pme, &p, "alpha = -1 must be positive");
  p = s.p;
  p.coulomb_constant = -1;
  ok &= refused(s.sys, &rl_term_pme, &p, "coulomb_constant = -1 must be positive");
  EW_CHECK_TRUE("order, negative counts, eps' < 1, negative alpha or kc: refused, naming each", ok);
  p = s.p;
  p.nspecies = 2;
  ok = refused(s.sys, &rl_term_pme, &p, "species: 2 given, the system has 5");
  ff_test_species extra;
  ff_stockmayer(&extra, 0.05);
  rl_species_ff sff[6];
  memcpy(sff, s.sff, sizeof(rl_species_ff) * 5);
  sff[1] = ff_test_species_ff(&s.sp[0]); /* four sites for the tetrahedron's five */
  p = s.p;
  p.species = sff;
  ok &= refused(s.sys, &rl_term_pme, &p, "species 1 (tetra): 4 sites given, the system has 5");
  EW_CHECK_TRUE("a species table that does not match the system: refused", ok);
  ew_scene_free(&s);
  /* a non-finite dipole, quadrupoles, no charges or dipoles, no box */
  rl_system *sys = rl_system_alloc(RL_UNITS_REAL);
  ff_test_species sp[3];
  ff_stockmayer(&sp[0], 0.05);
  ff_2cljq(&sp[1], 0.01);
  ff_ion(&sp[2], 0.0);
  rl_species_ff f3[3];
  for (int k = 0; k < 3; k++) {
    assert_int_equal(rl_system_add_species(sys, &sp[k].desc, 2, NULL), RL_OK);
    f3[k] = ff_test_species_ff(&sp[k]);
  }
  rl_ewald_params_default(&p);
  p.species = f3;
  p.nspecies = 3;
  p.cutoff = 0.9;
  ok = refused(sys, &rl_term_pme, &p, "the system has no periodic box");
  assert_int_equal(rl_system_set_box(sys, L), RL_OK);
  sp[0].dipole[0] = NAN; /* point dipoles are summed (test_ewald_dipole.c); a non-finite one is refused */
  ok &= refused(sys, &rl_term_pme, &p, "species 0 (stockmayer), site 0: dipole nan is not finite");
  sp[0].dipole[0] = 0.05;
  ok &= refused(sys, &rl_term_pme, &p, "species 1 (2cljq), site 2 carries a quadrupole");
  f3[0].dipole = NULL;
  f3[1].quadrupole = NULL;
  ok &= refused(sys, &rl_term_pme, &p, "no site carries a charge or a point dipole");
  EW_CHECK_TRUE("no box, a non-finite dipole, quadrupoles (a quadrupole-only model), no charges or dipoles: refused", ok);
  rl_system_free(sys);
}

static void runtime_errors(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {1.9, 1.9, 1.9};
  ew_scene_mixed(&s, L, 12, 2, 2, 2, 0, 4);
  s.p.cutoff = 0.9;
  rl_terms *t = ew_terms(&s, &rl_term_ewald_real, &rl_term_pme);
  ew_result r;
  const double L2[3] = {1.7, 1.9, 1.9};
  assert_int_equal(rl_system_set_box(s.sys, L2), RL_OK);
  int st = ew_eval(t, s.sys, &r);
  ew_result_free(&r);
  EW_CHECK_TRUE("a new cell whose edge is below twice the cutoff: the terms cannot follow, and say why",
                st == RL_EINVAL && strstr(rl_last_error(), "cannot follow the new box") && strstr(rl_last_error(), "cutoff = 0.9 exceeds half the box edge x = 1.7"));
  assert_int_equal(rl_system_set_box(s.sys, L), RL_OK);
  double x[3];
  rl_system_get_position(s.sys, 3, x);
  const double bad[3] = {x[0], NAN, x[2]};
  rl_system_r(s.sys)[3][1] = bad[1]; /* the setter refuses NaN: a blow-up writes it directly */
  st = ew_eval(t, s.sys, &r);
  ew_result_free(&r);
  EW_CHECK_TRUE("a non-finite position: RL_ENONFINITE naming the body", st == RL_ENONFINITE && strstr(rl_last_error(), "body 3"));
  assert_int_equal(rl_system_set_position(s.sys, 3, x), RL_OK);
  ff_test_species more;
  ff_ion(&more, 1.0);
  assert_int_equal(rl_system_add_species(s.sys, &more.desc, 1, NULL), RL_OK);
  st = ew_eval(t, s.sys, &r);
  ew_result_free(&r);
  EW_CHECK_TRUE("a system that changed after alloc: RL_ESTATE", st == RL_ESTATE && strstr(rl_last_error(), "the system has changed"));
  rl_terms_free(t);
  ew_scene_free(&s);
}

static void lookup(void **state)
{
  (void)state;
  EW_CHECK_TRUE("ewald-real, ewald and pme found by name",
                rl_term_type_find("ewald-real") == &rl_term_ewald_real && rl_term_type_find("ewald") == &rl_term_ewald &&
                    rl_term_type_find("pme") == &rl_term_pme);
  EW_CHECK_TRUE("their components: ewald_real; ewald_recip, _self, _intra, _background, _surface",
                rl_term_ewald_real.nenergies == 1 && !strcmp(rl_term_ewald_real.energy_names[0], "ewald_real") &&
                    rl_term_pme.nenergies == 5 && !strcmp(rl_term_pme.energy_names[4], "ewald_surface") &&
                    !strcmp(rl_term_ewald.energy_names[2], "ewald_intra"));
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(openmm_choices), cmocka_unit_test(describe),       cmocka_unit_test(warnings),
      cmocka_unit_test(bad_input),      cmocka_unit_test(runtime_errors), cmocka_unit_test(lookup),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
