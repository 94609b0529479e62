/* The model zoo: classification of catalogue models and of near-degenerate inertia, the fast
 * path of every family against the same molecules forced through the general asymmetric path,
 * and conservation per family in a small periodic liquid.
 *
 * Forces come from a smooth test field (the Interactions issue's kernels are tested on their
 * own): every site pair of different molecules interacts by
 *     u(r) = e0 (1 - x^2)^3 (1 - 4 x^2),  x = r/rc < 1   (repulsive core, attractive well,
 * zero with two derivatives at rc), and the point dipoles by -e0 (rho_i . rho_j) mu_i mu_j (1 - x^2)^3
 * on the centre distance, so every family feels real forces and torques. */
#include "../testutil.h"

#include <rotleap/catalog.h>
#include <gsl/gsl_statistics_double.h>

#define NMOL 27
#define MAXS (NMOL * RL_MOLECULE_MAX_SITES)

typedef struct {
  double L, rc, e0;
  const rl_molecule *mol;   /* species 0 */
  const rl_molecule *mol2;  /* species 1 (mixed scenes) or NULL */
} field;

static const rl_molecule *mol_of(const field *F, const rl_system *sys, int i)
{
  return rl_system_species_of(sys, i) == 0 ? F->mol : F->mol2;
}

static void min_image(double d[3], double L)
{
  for (int c = 0; c < 3; c++) d[c] -= L * nearbyint(d[c] / L);
}

static int test_field(void *ctx, const rl_system *sys, rl_forces *out)
{
  const field *F = ctx;
  int n = rl_system_count(sys), ns = rl_system_nsites(sys);
  static double pos[MAXS][3], fs[MAXS][3];
  static int owner[MAXS];
  memset(fs, 0, sizeof(double) * 3 * (size_t)ns);
  rl_system_site_positions(sys, pos);
  for (int i = 0; i < n; i++)
    for (int a = 0; a < mol_of(F, sys, i)->nsites; a++) owner[rl_system_site_offset(sys, i) + a] = i;
  double U = 0.0, rc2 = F->rc * F->rc;
  for (int a = 0; a < ns; a++)
    for (int b = a + 1; b < ns; b++) {
      if (owner[a] == owner[b]) continue;
      double d[3] = {pos[a][0] - pos[b][0], pos[a][1] - pos[b][1], pos[a][2] - pos[b][2]};
      min_image(d, F->L);
      double x2 = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / rc2;
      if (x2 >= 1.0) continue;
      double g = 1.0 - x2, g3 = g * g * g;
      U += F->e0 * g3 * (1.0 - 4.0 * x2);
      /* du/d(x2) = e0 [-3 g^2 (1 - 4 x2) - 4 g^3];  f = -du/dr = -2 (du/dx2) d / rc^2 */
      double dudx2 = F->e0 * (-3.0 * g * g * (1.0 - 4.0 * x2) - 4.0 * g3);
      double fr = -2.0 * dudx2 / rc2;
      for (int c = 0; c < 3; c++) { fs[a][c] += fr * d[c]; fs[b][c] -= fr * d[c]; }
    }
  rl_system_add_site_forces(sys, (const double (*)[3])fs, out);
  double (*r)[3] = rl_system_r((rl_system *)sys);
  for (int i = 0; i < n; i++)
    for (int j = i + 1; j < n; j++) {
      double mi = 0.0, mj = 0.0;
      for (int a = 0; a < mol_of(F, sys, i)->nsites; a++) mi += mol_of(F, sys, i)->dipole[a];
      for (int a = 0; a < mol_of(F, sys, j)->nsites; a++) mj += mol_of(F, sys, j)->dipole[a];
      if (mi == 0.0 || mj == 0.0) continue;
      double d[3] = {r[i][0] - r[j][0], r[i][1] - r[j][1], r[i][2] - r[j][2]}, ri[3], rj[3];
      min_image(d, F->L);
      double x2 = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / rc2;
      if (x2 >= 1.0) continue;
      rl_system_get_axis(sys, i, ri);
      rl_system_get_axis(sys, j, rj);
      double g = 1.0 - x2, g3 = g * g * g, c = ri[0] * rj[0] + ri[1] * rj[1] + ri[2] * rj[2];
      double k = F->e0 * mi * mj;
      U += -k * c * g3;
      double fr = -2.0 * (k * c * 3.0 * g * g) / rc2; /* -d/dr of -k c g^3 */
      for (int q = 0; q < 3; q++) { out->f[i][q] += fr * d[q]; out->f[j][q] -= fr * d[q]; }
      /* torque on i: -rho_i x dU/drho_i = rho_i x (k g3 rho_j) */
      double *ti = out->k[rl_system_rot_index(sys, i)], *tj = out->k[rl_system_rot_index(sys, j)];
      double t[3] = {k * g3 * (ri[1] * rj[2] - ri[2] * rj[1]), k * g3 * (ri[2] * rj[0] - ri[0] * rj[2]),
                     k * g3 * (ri[0] * rj[1] - ri[1] * rj[0])};
      for (int q = 0; q < 3; q++) { ti[q] += t[q]; tj[q] -= t[q]; }
    }
  out->energy = U;
  return RL_OK;
}

typedef struct {
  rl_molecule mol;
  field F;
  double kT;
  rl_system *sys;
  rl_integrator *in;
} liquid;

/* 27 molecules on a 3x3x3 lattice of spacing s, random orientations and thermal-ish velocities
 * and angular momenta (l perpendicular to the axis for axis molecules), all from one seed. */
static void make_liquid(liquid *q, const char *model, int force_general, double h, unsigned long seed)
{
  const rl_model *md = rl_catalog_find(model);
  assert_non_null(md);
  assert_int_equal(rl_model_build(md, NULL, force_general, &q->mol), RL_OK);
  int lj = md->units == RL_UNITS_LJ;
  double s = lj ? 1.0 : 0.35, kT = lj ? 1.0 : 2.5;
  q->kT = kT;
  q->F = (field){3.0 * s, 1.2 * s, 1.0, &q->mol, NULL};
  q->sys = rl_system_alloc(md->units);
  rl_species_desc d;
  rl_molecule_species(&q->mol, &d);
  assert_int_equal(rl_system_add_species(q->sys, &d, NMOL, NULL), RL_OK);
  rl_molecule natural;
  assert_int_equal(rl_model_build(md, NULL, 0, &natural), RL_OK);
  int axis = natural.kind == RL_KIND_LINEAR || natural.kind == RL_KIND_DIPOLE;
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, seed);
  for (int i = 0; i < NMOL; i++) {
    double x[3] = {s * (i % 3 + 0.5), s * (i / 3 % 3 + 0.5), s * (i / 9 + 0.5)}, A[9], v[3], l[3];
    random_rotation(r, A);
    for (int c = 0; c < 3; c++) {
      v[c] = gsl_ran_gaussian(r, sqrt(kT / q->mol.mass));
      l[c] = gsl_ran_gaussian(r, sqrt(kT * natural.inertia[0]));
    }
    if (axis) { /* no spin about the axis */
      double dd = l[0] * A[6] + l[1] * A[7] + l[2] * A[8];
      for (int c = 0; c < 3; c++) l[c] -= dd * A[6 + c];
    }
    assert_int_equal(rl_system_set_position(q->sys, i, x), RL_OK);
    assert_int_equal(rl_system_set_orientation(q->sys, i, A), RL_OK);
    assert_int_equal(rl_system_set_velocity(q->sys, i, v), RL_OK);
    if (q->mol.kind != RL_KIND_POINT) assert_int_equal(rl_system_set_angmom(q->sys, i, l), RL_OK);
  }
  gsl_rng_free(r);
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = h;
  q->in = rl_integrator_alloc(q->sys, &p, (rl_force_provider){test_field, &q->F});
  assert_non_null(q->in);
  assert_int_equal(rl_integrator_init(q->in), RL_OK);
}

static void free_liquid(liquid *q)
{
  rl_integrator_free(q->in);
  rl_system_free(q->sys);
}

/* ------------------------------------------------------------------ classification */

static void catalogue_families(void **state)
{
  (void)state;
  for (int i = 0; i < rl_catalog_count(); i++) {
    const rl_model *md = rl_catalog_get(i);
    rl_molecule m;
    assert_int_equal(rl_model_build(md, NULL, 0, &m), RL_OK);
    int ok = m.kind == md->family;
    printf("check %-12s classifies as %-10s (expected %-10s) %s\n", md->name, rl_kind_name(m.kind),
           rl_kind_name(md->family), ok ? "ok" : "FAIL");
    assert_true(ok);
    rl_molecule g;
    assert_int_equal(rl_model_build(md, NULL, 1, &g), RL_OK);
    assert_int_equal(g.kind, md->family == RL_KIND_POINT ? RL_KIND_POINT : RL_KIND_ASYMMETRIC); /* atoms do not rotate */
    assert_int_equal(g.natural_kind, md->family);
  }
  assert_null(rl_catalog_find("tip5p"));
  printf("check unknown model message: \"%s\" %s\n", rl_last_error(),
         strstr(rl_last_error(), "unknown model 'tip5p'") ? "ok" : "FAIL");
  assert_non_null(strstr(rl_last_error(), "unknown model 'tip5p' (known: stockmayer"));
}

/* Argon and the Joung-Cheatham ions (issue 35): one site, point family, the published numbers
 * (Rmin/2 in A and eps in kcal/mol, as AMBER's frcmod.ionsjc_* files and OpenMM's XML give them;
 * sigma = 2^(5/6) Rmin/2). */
static void catalogue_atoms_ions(void **state)
{
  (void)state;
  static const struct { const char *name; double mass, q, rmin2_A, eps_kcal; } t[] = {
      {"na-spce", 22.99, 1, 1.212, 0.3526418},  {"cl-spce", 35.45, -1, 2.711, 0.0127850},
      {"na-tip3p", 22.99, 1, 1.369, 0.0874393}, {"cl-tip3p", 35.45, -1, 2.513, 0.0355910},
      {"na-tip4pew", 22.99, 1, 1.226, 0.1684375}, {"cl-tip4pew", 35.45, -1, 2.760, 0.0116615}};
  for (size_t i = 0; i < sizeof t / sizeof t[0]; i++) {
    rl_molecule m;
    const rl_model *md = rl_catalog_find(t[i].name);
    assert_non_null(md);
    assert_int_equal(rl_model_build(md, NULL, 0, &m), RL_OK);
    const double sigma = 2.0 * t[i].rmin2_A / pow(2.0, 1.0 / 6.0) * 0.1, eps = t[i].eps_kcal * 4.184;
    const int ok = m.kind == RL_KIND_POINT && m.nsites == 1 && m.mass == t[i].mass && m.charge[0] == t[i].q &&
                   fabs(m.sigma[0] - sigma) < 1e-15 && fabs(m.epsilon[0] - eps) < 1e-15;
    printf("check %-10s sigma %.7f nm eps %.7f kJ/mol q %+g %s\n", t[i].name, m.sigma[0], m.epsilon[0], m.charge[0], ok ? "ok" : "FAIL");
    assert_true(ok);
  }
  rl_molecule ar;
  assert_int_equal(rl_model_build(rl_catalog_find("argon"), NULL, 0, &ar), RL_OK);
  const int ok = ar.kind == RL_KIND_POINT && ar.sigma[0] == 0.3405 && fabs(ar.epsilon[0] - 0.99607) < 1e-5 && ar.mass == 39.948;
  printf("check argon sigma %.4f nm eps %.6f kJ/mol (119.8 K) %s\n", ar.sigma[0], ar.epsilon[0], ok ? "ok" : "FAIL");
  assert_true(ok);
}

/* Six sites on the axes, masses (1, 1 + e, 2): J = (6 + 2e, 6, 4 + 2e) -- two moments differ
 * by 2e/6 relative.  Within RL_INERTIA_RTOL: symmetric; just outside: asymmetric. */
static rl_kind classify_axes(double e, double mz)
{
  const double pos[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const double mass[6] = {1, 1, 1 + e, 1 + e, mz, mz};
  rl_molecule_def d = {.name = "axes", .nsites = 6, .pos = &pos[0][0], .mass = mass};
  rl_molecule m;
  assert_int_equal(rl_molecule_build(&d, 0, &m), RL_OK);
  return m.kind;
}

static void near_degenerate(void **state)
{
  (void)state;
  /* relative difference 2e/6 (max moment 6): within = 0.5 tol, outside = 2 tol */
  double within = 0.5 * RL_INERTIA_RTOL * 6.0 / 2.0, outside = 2.0 * RL_INERTIA_RTOL * 6.0 / 2.0;
  rl_kind k1 = classify_axes(within, 2.0), k2 = classify_axes(outside, 2.0);
  printf("check near-symmetric within tolerance -> %s, just outside -> %s %s\n", rl_kind_name(k1),
         rl_kind_name(k2), k1 == RL_KIND_SYMMETRIC && k2 == RL_KIND_ASYMMETRIC ? "ok" : "FAIL");
  assert_int_equal(k1, RL_KIND_SYMMETRIC);
  assert_int_equal(k2, RL_KIND_ASYMMETRIC);
  /* mz = 1: J = (4 + 2e, 4, 4 + 2e) */
  within = 0.5 * RL_INERTIA_RTOL * 4.0 / 2.0;
  outside = 2.0 * RL_INERTIA_RTOL * 4.0 / 2.0;
  k1 = classify_axes(within, 1.0);
  k2 = classify_axes(outside, 1.0);
  printf("check near-spherical within tolerance -> %s, just outside -> %s %s\n", rl_kind_name(k1),
         rl_kind_name(k2), k1 == RL_KIND_SPHERICAL && k2 == RL_KIND_SYMMETRIC ? "ok" : "FAIL");
  assert_int_equal(k1, RL_KIND_SPHERICAL);
  assert_int_equal(k2, RL_KIND_SYMMETRIC);
  /* near-linear: two masses on z at +-1 and a small mass m off the axis by d: J_min = O(m d^2) */
  for (int k = 0; k < 2; k++) {
    double d = k == 0 ? 2e-6 : 2e-4; /* J_min/J_max ~ 2e-12 (within) and 2e-8 (outside) */
    const double pos[3][3] = {{0, 0, 1}, {0, 0, -1}, {d, 0, 0}};
    const double mass[3] = {1, 1, 1};
    rl_molecule_def def = {.name = "nearlin", .nsites = 3, .pos = &pos[0][0], .mass = mass};
    rl_molecule m;
    assert_int_equal(rl_molecule_build(&def, 0, &m), RL_OK);
    rl_kind want = k == 0 ? RL_KIND_LINEAR : RL_KIND_ASYMMETRIC; /* J = (2, 2 + d^2, d^2) */
    printf("check near-linear, site %g off axis -> %s %s\n", d, rl_kind_name(m.kind),
           m.kind == want ? "ok" : "FAIL");
    assert_int_equal(m.kind, want);
    if (k == 0) assert_true(m.sites[2][0] == 0.0 && m.sites[2][1] == 0.0);
  }
  /* a massless charge off the axis of a linear mass distribution cannot be integrated */
  const double pos[3][3] = {{0, 0, 1}, {0, 0, -1}, {0.1, 0, 0}};
  const double mass[3] = {1, 1, 0}, q[3] = {0, 0, 1};
  rl_molecule_def def = {.name = "bad", .nsites = 3, .pos = &pos[0][0], .mass = mass, .charge = q};
  rl_molecule m;
  int st = rl_molecule_build(&def, 0, &m);
  printf("check off-axis massless site rejected: \"%s\" %s\n", rl_last_error(),
         st == RL_EINVAL && strstr(rl_last_error(), "site 2 (X) is 0.1 off the axis") ? "ok" : "FAIL");
  assert_int_equal(st, RL_EINVAL);
  assert_non_null(strstr(rl_last_error(), "off the axis"));
}

/* --------------------------------------------- fast path = forced general path */

static void same_trajectory(const char *model, double h)
{
  liquid a, b;
  make_liquid(&a, model, 0, h, 7);
  make_liquid(&b, model, 1, h, 7);
  for (int s = 0; s < 1000; s++) {
    assert_int_equal(rl_integrator_step(a.in, NULL), RL_OK);
    assert_int_equal(rl_integrator_step(b.in, NULL), RL_OK);
  }
  double dr = 0.0, dz = 0.0, dA = 0.0;
  int matrix = a.mol.kind != RL_KIND_LINEAR && a.mol.kind != RL_KIND_DIPOLE;
  for (int i = 0; i < NMOL; i++) {
    double ra[3], rb[3], za[3], zb[3], Aa[9], Ab[9];
    rl_system_get_position(a.sys, i, ra);
    rl_system_get_position(b.sys, i, rb);
    rl_system_get_axis(a.sys, i, za);
    rl_system_get_axis(b.sys, i, zb);
    dr = fmax(dr, max_abs_diff(ra, rb, 3) / a.F.L);
    dz = fmax(dz, max_abs_diff(za, zb, 3));
    if (matrix) {
      rl_system_get_orientation(a.sys, i, Aa);
      rl_system_get_orientation(b.sys, i, Ab);
      dA = fmax(dA, max_abs_diff(Aa, Ab, 9));
    }
  }
  char name[96];
  snprintf(name, sizeof name, "%s (%s) vs general, 1000 steps: max |dr|/L", model, rl_kind_name(a.mol.kind));
  CHECK_LE(name, dr, 1e-9);
  snprintf(name, sizeof name, "%s (%s) vs general: max |d rho| (axis vs row Z of A)", model, rl_kind_name(a.mol.kind));
  CHECK_LE(name, dz, 1e-9);
  if (matrix) {
    snprintf(name, sizeof name, "%s (%s) vs general: max |dA|", model, rl_kind_name(a.mol.kind));
    CHECK_LE(name, dA, 1e-9);
  }
  printf("info  %s: general-path fallbacks %ld\n", model, rl_integrator_fallbacks(b.in));
  free_liquid(&a);
  free_liquid(&b);
}

static void fast_paths(void **state)
{
  (void)state;
  same_trajectory("stockmayer", 0.002);
  same_trajectory("2cljq", 0.002);
  same_trajectory("co2", 0.001);
  same_trajectory("ch4", 0.001);
  same_trajectory("nh3", 0.001);
}

/* ------------------------------------------------- conservation per family */

static void conservation(const char *model, double h0)
{
  double sd[3], dP = 0.0;
  const double hs[3] = {h0, h0 / 2, h0 / 4};
  for (int k = 0; k < 3; k++) {
    liquid q;
    make_liquid(&q, model, 0, hs[k], 11);
    long n = 300L << k; /* the same stretch of time at every h */
    double *E = malloc(sizeof(double) * (size_t)n), P0[3] = {0, 0, 0};
    for (long s = 0; s < n; s++) {
      rl_step_info info;
      assert_int_equal(rl_integrator_step(q.in, &info), RL_OK);
      E[s] = info.total;
      double P[3] = {0, 0, 0};
      for (int i = 0; i < NMOL; i++) {
        double v[3];
        rl_system_get_velocity(q.sys, i, v);
        for (int c = 0; c < 3; c++) P[c] += q.mol.mass * v[c];
      }
      if (s == 0) memcpy(P0, P, sizeof P);
      double d[3] = {P[0] - P0[0], P[1] - P0[1], P[2] - P0[2]};
      dP = fmax(dP, norm3d(d) / sqrt(q.kT * q.mol.mass));
    }
    sd[k] = gsl_stats_sd(E, 1, (size_t)n);
    free(E);
    free_liquid(&q);
  }
  char name[96];
  for (int k = 0; k < 2; k++) {
    snprintf(name, sizeof name, "%s: energy fluctuation order h=%g->%g", model, hs[k], hs[k + 1]);
    CHECK_NEAR(name, log2(sd[k] / sd[k + 1]), 2.0, 0.2);
  }
  snprintf(name, sizeof name, "%s: |P - P0| / (m v_thermal)", model);
  CHECK_LE(name, dP, 1e-12);
}

static void conservation_per_family(void **state)
{
  (void)state;
  conservation("stockmayer", 0.004);
  conservation("2cljq", 0.004);
  conservation("co2", 0.002);
  conservation("ch4", 0.002);
  conservation("nh3", 0.002);
  conservation("tip4p", 0.002);
}

/* A mixed scene: 18 Stockmayer molecules (rho only) and 9 LJ atoms (r, v only) in one box:
 * both species integrate together, momentum is conserved and the energy error is O(h^2). */
static void mixed_species(void **state)
{
  (void)state;
  const rl_model *md = rl_catalog_find("stockmayer");
  rl_molecule dip, atom;
  assert_int_equal(rl_model_build(md, NULL, 0, &dip), RL_OK);
  const double p0[3] = {0, 0, 0}, m1 = 1.0;
  rl_molecule_def ad = {.name = "Ar", .nsites = 1, .pos = p0, .mass = &m1};
  assert_int_equal(rl_molecule_build(&ad, 0, &atom), RL_OK);
  assert_int_equal(atom.kind, RL_KIND_POINT);
  double sd[2], dP = 0.0;
  for (int k = 0; k < 2; k++) {
    double h = 0.004 / (1 << k);
    field F = {3.0, 1.2, 1.0, &dip, &atom};
    rl_system *sys = rl_system_alloc(RL_UNITS_LJ);
    rl_species_desc d1, d2;
    rl_molecule_species(&dip, &d1);
    rl_molecule_species(&atom, &d2);
    assert_int_equal(rl_system_add_species(sys, &d1, 18, NULL), RL_OK);
    assert_int_equal(rl_system_add_species(sys, &d2, 9, NULL), RL_OK);
    assert_int_equal(rl_system_nrot(sys), 18);
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(r, 3);
    for (int i = 0; i < NMOL; i++) {
      double x[3] = {i % 3 + 0.5, i / 3 % 3 + 0.5, i / 9 + 0.5}, A[9], v[3], l[3];
      random_rotation(r, A);
      for (int c = 0; c < 3; c++) { v[c] = gsl_ran_gaussian(r, 1.0); l[c] = gsl_ran_gaussian(r, sqrt(0.025)); }
      double dd = l[0] * A[6] + l[1] * A[7] + l[2] * A[8];
      for (int c = 0; c < 3; c++) l[c] -= dd * A[6 + c];
      rl_system_set_position(sys, i, x);
      rl_system_set_velocity(sys, i, v);
      if (i < 18) { rl_system_set_orientation(sys, i, A); rl_system_set_angmom(sys, i, l); }
    }
    gsl_rng_free(r);
    rl_integrator_params p;
    rl_integrator_params_default(&p);
    p.h = h;
    rl_integrator *in = rl_integrator_alloc(sys, &p, (rl_force_provider){test_field, &F});
    assert_int_equal(rl_integrator_init(in), RL_OK);
    long n = 300L << k;
    double *E = malloc(sizeof(double) * (size_t)n), P0[3] = {0, 0, 0};
    for (long s = 0; s < n; s++) {
      rl_step_info info;
      assert_int_equal(rl_integrator_step(in, &info), RL_OK);
      E[s] = info.total;
      double P[3] = {0, 0, 0};
      for (int i = 0; i < NMOL; i++) {
        double v[3];
        rl_system_get_velocity(sys, i, v);
        for (int c = 0; c < 3; c++) P[c] += v[c];
      }
      if (s == 0) memcpy(P0, P, sizeof P);
      double dd[3] = {P[0] - P0[0], P[1] - P0[1], P[2] - P0[2]};
      dP = fmax(dP, norm3d(dd));
    }
    sd[k] = gsl_stats_sd(E, 1, (size_t)n);
    assert_int_equal(rl_system_dof(sys), 27 * 3 - 3 + 18 * 2);
    free(E);
    rl_integrator_free(in);
    rl_system_free(sys);
  }
  CHECK_NEAR("mixed stockmayer + LJ atoms: energy fluctuation order", log2(sd[0] / sd[1]), 2.0, 0.2);
  CHECK_LE("mixed stockmayer + LJ atoms: |P - P0|", dP, 1e-12);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(catalogue_families),
      cmocka_unit_test(catalogue_atoms_ions), cmocka_unit_test(near_degenerate),
                                     cmocka_unit_test(fast_paths), cmocka_unit_test(conservation_per_family),
                                     cmocka_unit_test(mixed_species)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
