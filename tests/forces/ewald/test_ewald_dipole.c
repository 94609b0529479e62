/* Point dipoles in the Ewald terms (forces/ewald/, issue 33): a Stockmayer box, and a mixture of
 * Stockmayer dipoles, NH3-like symmetric tops (a dipole on one site and three charges: the
 * intramolecular charge-dipole correction) and point ions, in a non-cubic box:
 *   fd         forces, torques (turns about each lab axis) and the molecular virial (strain of the
 *              box and the centres along each axis, orientations fixed) against Richardson-
 *              extrapolated central differences of the energy, for "ewald-real" and "ewald"
 *              with a dielectric boundary (eps' = 4); limits 1e-8 of the largest value
 *   alpha      real + reciprocal sum independent of alpha (5.5 and 6.5 / nm, converged k sums):
 *              energy 1e-10, forces and torques 1e-8 RMS relative
 *   threads    1, 2 and 3 threads give the same bits (600 bodies: the body loops go parallel)
 *   surface    the eps' term against 2 pi kc |M|^2 / ((2 eps' + 1) V), M = sum q r + sum mu, and
 *              its torque mu x (-4 pi kc M / ((2 eps' + 1) V)); the self term's value
 *   resolve    the count and sum of mu^2; values derived from a tolerance reach the dipolar target
 *   estimates  the dipolar force and torque error estimates (real-space cut, k sum, mesh) within a
 *              factor 2 of the errors measured against a converged sum
 *   choice     pme from a tolerance (dipoles alone): the measured error within the estimate, the
 *              mesh FFT-friendly and no finer than the estimate needs */
#include "ewald_testutil.h"

#define TOL_CHOICE 3e-6

/* Stockmayer dipoles (0.04 e nm), symmetric tops and ions. */
static void scene_dip(ew_scene *s, const double L[3], int ndip, int ntop, int nion, unsigned long seed)
{
  memset(s, 0, sizeof *s);
  ff_stockmayer(&s->sp[0], 0.04);
  ff_symtop(&s->sp[1]);
  ff_ion(&s->sp[2], 1.0);
  ff_ion(&s->sp[3], -1.0);
  const int counts[4] = {ndip, ntop, nion, nion};
  ew_scene_build(s, 4, counts, L, 0.3, seed);
}

static void fd_one(const char *what, const rl_term_type *type, int ntop, int nion)
{
  ew_scene s;
  const double L[3] = {2.2, 2.3, 2.4};
  scene_dip(&s, L, 20, ntop, nion, 5);
  s.p.cutoff = 1.0;
  s.p.alpha = 3.0;
  s.p.eps_surface = 4.0;
  for (int c = 0; c < 3; c++) {
    s.p.kmax[c] = 9;
    s.p.grid[c] = 24 + 2 * c;
  }
  s.p.order = 6;
  rl_terms *t = ew_terms(&s, type, NULL);
  ew_result r;
  assert_int_equal(ew_eval(t, s.sys, &r), RL_OK);
  double F = 0, K = 0, dF = 0, dK = 0;
  for (int i = 0; i < r.n; i++) {
    F = fmax(F, norm3d(r.f[i]));
    const int ri = rl_system_rot_index(s.sys, i);
    if (ri >= 0) K = fmax(K, norm3d(r.k[ri]));
    for (int c = 0; c < 3; c++) {
      dF = fmax(dF, fabs(ew_fd(t, s.sys, i, 0, c, 1e-4) + r.f[i][c]));
      if (ri >= 0) dK = fmax(dK, fabs(ew_fd(t, s.sys, i, 1, c, 1e-4) + r.k[ri][c]));
    }
  }
  double dW = 0, Wn = 0;
  for (int c = 0; c < 3; c++) {
    dW = fmax(dW, fabs(ew_fd(t, s.sys, 0, 2, c, 1e-4) + r.virial[4 * c]));
    Wn = fmax(Wn, fabs(r.virial[4 * c]));
  }
  printf("%s: U = %.10g, |F| <= %.4g, |K| <= %.4g, W = %.6g %.6g %.6g\n", what, r.energy, F, K, r.virial[0], r.virial[4], r.virial[8]);
  char name[160];
  snprintf(name, sizeof name, "%s: forces vs -dU/dx (largest difference / largest force)", what);
  EW_CHECK_LE(name, dF / F, 1e-8);
  snprintf(name, sizeof name, "%s: torques vs -dU/dphi (largest difference / largest torque)", what);
  EW_CHECK_LE(name, dK / K, 1e-8);
  snprintf(name, sizeof name, "%s: molecular virial W_cc vs -dU/d strain_cc", what);
  EW_CHECK_LE(name, dW / Wn, 1e-8);
  double sum = 0;
  for (int j = 0; j < r.ne; j++) sum += r.e[j];
  snprintf(name, sizeof name, "%s: its components add up to its energy", what);
  EW_CHECK_LE(name, fabs(sum - r.energy) / fabs(r.energy), 1e-13);
  ew_result_free(&r);
  rl_terms_free(t);
  ew_scene_free(&s);
}

typedef struct {
  const char *what;
  const rl_term_type *type;
  int ntop, nion;
} fd_case;

static void fd(void **state)
{
  const fd_case *c = *state;
  fd_one(c->what, c->type, c->ntop, c->nion);
}

static const fd_case fd_cases[6] = {{"ewald-real, Stockmayer", &rl_term_ewald_real, 0, 0},
                                    {"ewald, Stockmayer (eps' 4)", &rl_term_ewald, 0, 0},
                                    {"pme, Stockmayer (24 x 26 x 28, order 6, eps' 4)", &rl_term_pme, 0, 0},
                                    {"ewald-real, dipoles + tops + ions", &rl_term_ewald_real, 8, 4},
                                    {"ewald, dipoles + tops + ions (eps' 4)", &rl_term_ewald, 8, 4},
                                    {"pme, dipoles + tops + ions (eps' 4)", &rl_term_pme, 8, 4}};

/* ------------------------------------------------------------------------- pme against ewald */
static void pme_vs_ewald(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {2.4, 2.5, 2.6};
  scene_dip(&s, L, 40, 10, 6, 13);
  s.p.cutoff = 1.1;
  s.p.alpha = 3.5;
  s.p.eps_surface = 4.0;
  s.p.order = 10;
  for (int c = 0; c < 3; c++) {
    s.p.kmax[c] = 14;
    s.p.grid[c] = 64 + 4 * c;
  }
  ew_result r[2];
  const rl_term_type *types[2] = {&rl_term_ewald, &rl_term_pme};
  for (int j = 0; j < 2; j++) {
    rl_terms *t = ew_terms(&s, types[j], NULL);
    assert_int_equal(ew_eval(t, s.sys, &r[j]), RL_OK);
    rl_terms_free(t);
  }
  printf("ewald %.15g, pme %.15g (recip %.15g, %.15g)\n", r[0].energy, r[1].energy, r[0].e[0], r[1].e[0]);
  EW_CHECK_LE("pme (order 10, 64 x 68 x 72) against ewald (kmax 14), dipoles + tops + ions: energy, relative",
              fabs(r[0].energy - r[1].energy) / fabs(r[0].energy), 1e-9);
  EW_CHECK_LE("... forces, RMS relative", ew_rel_rms((const double(*)[3])r[1].f, (const double(*)[3])r[0].f, r[0].n), 1e-8);
  EW_CHECK_LE("... torques, RMS relative", ew_rel_rms((const double(*)[3])r[1].k, (const double(*)[3])r[0].k, r[0].nrot), 1e-8);
  double dW = 0, Wn = 0;
  for (int j = 0; j < 9; j++) {
    dW = fmax(dW, fabs(r[1].virial[j] - r[0].virial[j]));
    Wn = fmax(Wn, fabs(r[0].virial[j]));
  }
  EW_CHECK_LE("... virial (all nine), largest difference relative to the largest", dW / Wn, 1e-8);
  for (int j = 0; j < 2; j++) ew_result_free(&r[j]);
  ew_scene_free(&s);
}

/* ------------------------------------------------------------------------------------ alpha */
static void alpha(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {2.4, 2.5, 2.6};
  scene_dip(&s, L, 40, 10, 6, 9);
  s.p.cutoff = 1.1;
  ew_result r[2];
  const double al[2] = {5.5, 6.5};
  for (int j = 0; j < 2; j++) {
    s.p.alpha = al[j];
    for (int c = 0; c < 3; c++) s.p.kmax[c] = (int)ceil(2.0 * al[j] * sqrt(36.0) * L[c] / (2 * M_PI));
    rl_terms *t = ew_terms(&s, &rl_term_ewald_real, &rl_term_ewald);
    assert_int_equal(ew_eval(t, s.sys, &r[j]), RL_OK);
    rl_terms_free(t);
  }
  printf("alpha 5.5: U = %.15g (real %.10g, recip %.10g, self %.10g, intra %.10g); alpha 6.5: U = %.15g\n", r[0].energy,
         r[0].e[0], r[0].e[1], r[0].e[2], r[0].e[3], r[1].energy);
  EW_CHECK_LE("real + reciprocal: energy at alpha 5.5 and 6.5 /nm, relative difference", fabs(r[0].energy - r[1].energy) / fabs(r[0].energy), 1e-10);
  EW_CHECK_LE("forces at alpha 5.5 and 6.5, RMS relative", ew_rel_rms((const double(*)[3])r[0].f, (const double(*)[3])r[1].f, r[0].n), 1e-8);
  EW_CHECK_LE("torques at alpha 5.5 and 6.5, RMS relative", ew_rel_rms((const double(*)[3])r[0].k, (const double(*)[3])r[1].k, r[0].nrot), 1e-8);
  EW_CHECK_LE("molecular virial xx, relative", fabs(r[0].virial[0] - r[1].virial[0]) / fabs(r[0].virial[0]), 1e-8);
  EW_CHECK_LE("molecular virial xy, relative to xx", fabs(r[0].virial[1] - r[1].virial[1]) / fabs(r[0].virial[0]), 1e-8);
  EW_CHECK_LE("molecular virial yx, relative to xx", fabs(r[0].virial[3] - r[1].virial[3]) / fabs(r[0].virial[0]), 1e-8);
  for (int j = 0; j < 2; j++) ew_result_free(&r[j]);
  ew_scene_free(&s);
}

/* ---------------------------------------------------------------------------------- threads */
static void threads(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {3.2, 3.3, 3.4};
  scene_dip(&s, L, 500, 60, 20, 3);
  s.p.cutoff = 0.9;
  s.p.eps_surface = 10.0;
  const rl_term_type *types[3] = {&rl_term_ewald_real, &rl_term_ewald, &rl_term_pme};
  for (int k = 0; k < 3; k++) {
    ew_result r[3];
    for (int T = 1; T <= 3; T++) {
      s.p.threads = T;
      rl_terms *t = ew_terms(&s, types[k], NULL);
      assert_int_equal(ew_eval(t, s.sys, &r[T - 1]), RL_OK);
      rl_terms_free(t);
    }
    char name[128];
    snprintf(name, sizeof name, "%s with dipoles: 1, 2 and 3 threads give the same bits", types[k]->name);
    EW_CHECK_TRUE(name, ew_same_bits(&r[0], &r[1]) && ew_same_bits(&r[0], &r[2]));
    for (int T = 0; T < 3; T++) ew_result_free(&r[T]);
  }
  ew_scene_free(&s);
}

/* ---------------------------------------------------------------------------- surface, self */
static void surface(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {2.2, 2.3, 2.4};
  scene_dip(&s, L, 20, 6, 4, 11);
  s.p.cutoff = 1.0;
  s.p.alpha = 3.0;
  for (int c = 0; c < 3; c++) s.p.kmax[c] = 7;
  ew_result r[2];
  const double eps = 4.0;
  for (int j = 0; j < 2; j++) {
    s.p.eps_surface = j ? eps : INFINITY;
    rl_terms *t = ew_terms(&s, &rl_term_ewald, NULL);
    assert_int_equal(ew_eval(t, s.sys, &r[j]), RL_OK);
    rl_terms_free(t);
  }
  /* M from the sites and axes, as the formula says */
  const int ns = rl_system_nsites(s.sys), n = rl_system_count(s.sys);
  double (*x)[3] = malloc(sizeof(double[3]) * (size_t)ns), M[3] = {0, 0, 0}, sq = 0, smu = 0;
  rl_system_site_positions(s.sys, x);
  int site = 0;
  for (int i = 0; i < n; i++) {
    const int sp = rl_system_species_of(s.sys, i);
    double e[3];
    rl_system_get_axis(s.sys, i, e);
    for (int a = 0; a < s.sp[sp].desc.nsites; a++, site++) {
      const double q = s.sp[sp].charge[a], mu = s.sp[sp].has_dipole ? s.sp[sp].dipole[a] : 0.0;
      for (int c = 0; c < 3; c++) M[c] += q * x[site][c] + mu * e[c];
      sq += q * q;
      smu += mu * mu;
    }
  }
  const double kc = RL_COULOMB_KJMOL_NM, V = L[0] * L[1] * L[2], cs = 2 * M_PI * kc / ((2 * eps + 1) * V);
  const double Us = cs * (M[0] * M[0] + M[1] * M[1] + M[2] * M[2]);
  printf("surface: %.15g (formula %.15g); tin foil %.3g\n", r[1].e[4], Us, r[0].e[4]);
  EW_CHECK_LE("eps' 4: the surface energy against 2 pi kc |M|^2 / ((2 eps' + 1) V)", fabs(r[1].e[4] - Us) / Us, 1e-12);
  EW_CHECK_TRUE("tin foil: no surface energy", r[0].e[4] == 0.0);
  /* torque on the Stockmayer bodies: mu e x (-2 cs M) */
  double dk = 0, kn = 0;
  for (int i = 0; i < 20; i++) {
    const int ri = rl_system_rot_index(s.sys, i);
    double e[3];
    rl_system_get_axis(s.sys, i, e);
    const double m[3] = {0.04 * e[0], 0.04 * e[1], 0.04 * e[2]}, E[3] = {-2 * cs * M[0], -2 * cs * M[1], -2 * cs * M[2]};
    const double k[3] = {m[1] * E[2] - m[2] * E[1], m[2] * E[0] - m[0] * E[2], m[0] * E[1] - m[1] * E[0]};
    for (int c = 0; c < 3; c++) dk = fmax(dk, fabs(r[1].k[ri][c] - r[0].k[ri][c] - k[c]));
    kn = fmax(kn, norm3d(k));
  }
  EW_CHECK_LE("eps' 4: the surface torque on each dipole mu x (-4 pi kc M / ((2 eps' + 1) V))", dk / kn, 1e-9);
  const double a = 3.0, self = -kc * (a / sqrt(M_PI) * sq + 2 * a * a * a / (3 * sqrt(M_PI)) * smu);
  EW_CHECK_LE("self term -kc (alpha/sqrt(pi) sum q^2 + 2 alpha^3/(3 sqrt(pi)) sum mu^2)", fabs(r[0].e[1] - self) / fabs(self), 1e-14);
  free(x);
  for (int j = 0; j < 2; j++) ew_result_free(&r[j]);
  ew_scene_free(&s);
}

static void resolve(void **state)
{
  (void)state;
  ew_scene s;
  const double L[3] = {2.2, 2.3, 2.4};
  scene_dip(&s, L, 10, 0, 0, 1);
  s.p.cutoff = 1.0;
  rl_ewald_info in;
  EW_CHECK_TRUE("ewald and pme take point dipoles alone: their count and sum of mu^2",
                rl_ewald_resolve(s.sys, &s.p, RL_EWALD_SUM, &in) == RL_OK && in.nsites_dipolar == 10 && in.nsites_charged == 0 &&
                    fabs(in.sum_mu2 - 10 * 0.04 * 0.04) < 1e-15 && rl_ewald_resolve(s.sys, &s.p, RL_EWALD_PME, &in) == RL_OK);
  char line[512];
  rl_ewald_describe(&in, RL_UNITS_REAL, line, sizeof line);
  printf("%s\n", line);
  EW_CHECK_TRUE("the description gives the dipoles' estimated force and torque errors",
                strstr(line, "smooth PME of point dipoles: alpha") && strstr(line, "estimated RMS error on a dipole: force"));
  /* the values derived from the tolerance reach the dipolar target (tolerance x the force between
   * unit charges 1 A apart), alpha from the real-space estimate, the k cutoff or mesh from the
   * reciprocal one */
  s.p.tolerance = 2e-6;
  for (int m = 0; m < 2; m++) {
    const rl_ewald_method meth = m ? RL_EWALD_PME : RL_EWALD_SUM;
    assert_int_equal(rl_ewald_resolve(s.sys, &s.p, meth, &in), RL_OK);
    rl_ewald_describe(&in, RL_UNITS_REAL, line, sizeof line);
    printf("%s\n", line);
    const double target = 2e-6 * RL_COULOMB_KJMOL_NM * 100.0;
    EW_CHECK_TRUE(m ? "pme, derived: real-space force estimate at the target, reciprocal below it"
                    : "ewald, derived: real-space force estimate at the target, reciprocal below it",
                  fabs(in.dip_target - target) < 1e-12 * target && fabs(in.dip_err_real - target) < 1e-6 * target &&
                      in.dip_err_recip <= target && in.dip_terr_total > 0 && isnan(in.err_total));
  }
  ew_scene_free(&s);
}

/* 150 random Stockmayer dipoles in a 3 nm cube and their converged sum (rc 1.5 nm, alpha 4 /nm,
 * |n| <= 24): the reference of `estimates` and `choice`. */
static void converged_150(ew_scene *s, ew_result *ref)
{
  const double L[3] = {3.0, 3.0, 3.0};
  scene_dip(s, L, 150, 0, 0, 21);
  s->p.cutoff = 1.5;
  s->p.alpha = 4.0;
  s->p.tolerance = 0.09;
  for (int c = 0; c < 3; c++) s->p.kmax[c] = 24;
  s->p.kmax_sq = 576;
  rl_terms *t = ew_terms(s, &rl_term_ewald_real, &rl_term_ewald);
  assert_int_equal(ew_eval(t, s->sys, ref), RL_OK);
  rl_terms_free(t);
}

/* The dipolar error estimates against the errors measured against a converged sum (150 random
 * Stockmayer dipoles; each part alone: the real-space cut with a converged k sum, the k sum or
 * the mesh with the reference's cutoff): estimated over measured RMS force and torque within a
 * factor 2 (1.0-1.3 here; validate/ewald_convergence.py gives the table over tolerances). */
static void estimates(void **state)
{
  (void)state;
  ew_scene s;
  ew_result ref;
  converged_150(&s, &ref);
  rl_terms *t;
  static const struct { const char *what; const rl_term_type *type; double rc, alpha; int k, order; } cases[] = {
      {"real-space cut (rc 0.8 nm, alpha 3 /nm)", &rl_term_ewald, 0.8, 3.0, 24, 0},
      {"k sum (kmax 9)", &rl_term_ewald, 1.5, 4.0, 9, 0},
      {"mesh (24^3, order 5)", &rl_term_pme, 1.5, 4.0, 24, 5},
      {"mesh (20^3, order 7)", &rl_term_pme, 1.5, 4.0, 20, 7}};
  for (size_t j = 0; j < sizeof cases / sizeof cases[0]; j++) {
    s.p.cutoff = cases[j].rc;
    s.p.alpha = cases[j].alpha;
    s.p.order = cases[j].order;
    for (int c = 0; c < 3; c++) {
      s.p.kmax[c] = cases[j].type == &rl_term_ewald ? cases[j].k : 0;
      s.p.grid[c] = cases[j].type == &rl_term_pme ? cases[j].k : 0;
    }
    s.p.kmax_sq = 0;
    ew_result r;
    t = ew_terms(&s, &rl_term_ewald_real, cases[j].type);
    assert_int_equal(ew_eval(t, s.sys, &r), RL_OK);
    const rl_ewald_info *in = rl_ewald_term_info(rl_terms_state(t, 1));
    double df = 0, dt = 0;
    for (int i = 0; i < r.n; i++)
      for (int c = 0; c < 3; c++) {
        df += (r.f[i][c] - ref.f[i][c]) * (r.f[i][c] - ref.f[i][c]);
        dt += (r.k[i][c] - ref.k[i][c]) * (r.k[i][c] - ref.k[i][c]);
      }
    df = sqrt(df / r.n);
    dt = sqrt(dt / r.n);
    printf("%s: force est %.3g meas %.3g, torque est %.3g meas %.3g\n", cases[j].what, in->dip_err_total, df,
           in->dip_terr_total, dt);
    char what[160];
    snprintf(what, sizeof what, "%s: estimated / measured RMS force and torque within a factor 2", cases[j].what);
    EW_CHECK_TRUE(what, in->dip_err_total >= 0.5 * df && in->dip_err_total <= 2 * df && in->dip_terr_total >= 0.5 * dt &&
                            in->dip_terr_total <= 2 * dt);
    rl_terms_free(t);
    ew_result_free(&r);
  }
  ew_result_free(&ref);
  ew_scene_free(&s);
}

static int fft_friendly(int n)
{
  for (int f = 2; f <= 7; f++)
    while (n % f == 0) n /= f;
  return n == 1;
}

/* Point dipoles alone, pme, alpha and mesh (and order) from the tolerance (ewald_params.c,
 * dip_pme_choose): the reciprocal estimate within the target and the measured RMS force error
 * within the estimated total; the mesh FFT-friendly (factors 2, 3, 5, 7: the old choice, the
 * smallest integer, gave 43^3 here) and no finer than needed: the next-coarser FFT-friendly mesh
 * at the chosen alpha and order exceeds the target by the estimate. */
static void choice(void **state)
{
  (void)state;
  ew_scene s;
  ew_result ref, r;
  converged_150(&s, &ref);
  rl_terms *t;
  s.p = (rl_ewald_params){.species = s.p.species, .nspecies = s.p.nspecies, .cutoff = 1.2, .tolerance = TOL_CHOICE,
                          .eps_surface = INFINITY};
  t = ew_terms(&s, &rl_term_ewald_real, &rl_term_pme);
  assert_int_equal(ew_eval(t, s.sys, &r), RL_OK);
  const rl_ewald_info in = *rl_ewald_term_info(rl_terms_state(t, 1));
  rl_terms_free(t);
  double df = 0;
  for (int i = 0; i < r.n; i++)
    for (int c = 0; c < 3; c++) df += (r.f[i][c] - ref.f[i][c]) * (r.f[i][c] - ref.f[i][c]);
  df = sqrt(df / r.n);
  char line[512];
  rl_ewald_describe(&in, RL_UNITS_REAL, line, sizeof line);
  printf("%s\nmeasured RMS force error %.3g (target %.3g)\n", line, df, in.dip_target);
  EW_CHECK_TRUE("reciprocal estimate within the target, measured error within the total estimate",
                in.dip_err_recip <= in.dip_target && df <= in.dip_err_total);
  EW_CHECK_TRUE("the mesh is a cube of FFT-friendly size", in.grid[0] == in.grid[1] && in.grid[1] == in.grid[2] && fft_friendly(in.grid[0]));
  int down = in.grid[0] - 1;
  while (!fft_friendly(down)) down--;
  s.p.alpha = in.alpha;
  s.p.order = in.order;
  s.p.tolerance = 0.09; /* the coarse-grid check of explicit meshes is for charges */
  for (int c = 0; c < 3; c++) s.p.grid[c] = down;
  rl_ewald_info coarser;
  assert_int_equal(rl_ewald_resolve(s.sys, &s.p, RL_EWALD_PME, &coarser), RL_OK);
  printf("next coarser mesh %d^3 order %d: reciprocal estimate %.3g\n", down, in.order, coarser.dip_err_recip);
  EW_CHECK_TRUE("the next-coarser FFT-friendly mesh at the chosen alpha and order exceeds the target",
                coarser.dip_err_recip > in.dip_target);
  ew_result_free(&r);
  ew_result_free(&ref);
  ew_scene_free(&s);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test_prestate(fd, (void *)&fd_cases[0]), cmocka_unit_test_prestate(fd, (void *)&fd_cases[1]),
      cmocka_unit_test_prestate(fd, (void *)&fd_cases[2]), cmocka_unit_test_prestate(fd, (void *)&fd_cases[3]),
      cmocka_unit_test_prestate(fd, (void *)&fd_cases[4]), cmocka_unit_test_prestate(fd, (void *)&fd_cases[5]),
      cmocka_unit_test(pme_vs_ewald),                      cmocka_unit_test(alpha),
      cmocka_unit_test(threads),                           cmocka_unit_test(surface),
      cmocka_unit_test(resolve),                         cmocka_unit_test(estimates),
      cmocka_unit_test(choice)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
