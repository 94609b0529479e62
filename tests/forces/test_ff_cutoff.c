/* What the cutoff does to each interaction term (rl_forcefield_discontinuities) and the setup
 * warnings (rl_forcefield_warnings).
 *
 * Per configuration (LJ in each truncation; reaction-field charges with eps_rf = 1, 78.3, Inf;
 * dipole-dipole and charge-dipole RF and SF; quadrupoles; water under the molecule cutoff; the
 * intramolecular term), the flags must be those derived in docs/interactions.md, and they are
 * measured: two bodies in a large box, at centre distance rc - d (d = 1e-9 rc) over orientation
 * pairs (the 24 x 24 rotations of the cube, which hold the dipole and quadrupole extremes, and
 * 200 random pairs), with nothing at rc + d (the pair does not interact).  The pair's energy
 * there is the jump; it is orientation dependent iff the term "heats"; a force at rc - d is the
 * force jump.  A continuous energy (force) there is O(d) or smaller: below 2e-7 (6e-7) here,
 * where every jump is above 2e-5 (3e-3); the thresholds are 1e-6 (1e-5).  The library's sizes
 * must match the measured ones: site pairs to 1e-6 (the maxima lie at the cube orientations,
 * which both sample), molecule pairs within 30 % (sampled over other random orientations).
 *
 * Optionally the consequence: a small NVE Stockmayer liquid with the dipolar reaction field heats
 * at any step, with shifted-force dipoles it does not (NVE_HEATING below). */
#include "ff_testutil.h"

#include <rotleap/catalog.h>

#define RC 0.9
#define LBOX 4.0

enum { LJ, COUL, DD, QD, QQ, INTRA, NT };
static const char *const term_name[NT] = {"lj", "coulomb", "dipole-dipole", "charge-dipole",
                                          "quadrupole", "coulomb-intramolecular"};

typedef struct {
  const char *name;
  int species[2];   /* catalogue below; -1: a single species with two bodies */
  rl_cutoff_scheme scheme;
  rl_lj_truncation lj;
  double eps_rf;
  rl_dipole_method dip;
  int intra;
  /* expected flags per term: -1 absent, else energy_jumps * 4 + heats * 2 + force_jumps */
  int want[NT];
} config;

enum { SP_ATOM, SP_ION_P, SP_ION_M, SP_DIP, SP_QUAD, SP_WATER, SP_WATER_Q, SP_WATER_LJ, SP_STOCK };

static void make_species(int which, ff_test_species *s)
{
  switch (which) {
  case SP_ATOM:
    ff_species_init(s, "atom", RL_KIND_POINT, 40.0, 0, 0, 0, 1);
    ff_site(s, 0, 0, 0, 0, 0.34, 1.0, 0.0);
    break;
  case SP_ION_P:
  case SP_ION_M:
    ff_species_init(s, which == SP_ION_P ? "cation" : "anion", RL_KIND_POINT, 23.0, 0, 0, 0, 1);
    ff_site(s, 0, 0, 0, 0, 0.0, 0.0, which == SP_ION_P ? 1.0 : -1.0);
    break;
  case SP_DIP: /* a point dipole without LJ */
    ff_stockmayer(s, 0.05);
    s->epsilon[0] = 0.0;
    break;
  case SP_QUAD: /* a linear quadrupole at the centre, without LJ */
    ff_species_init(s, "quad", RL_KIND_LINEAR, 28.0, 8.5, 8.5, 0.0, 1);
    ff_site(s, 0, 0, 0, 0, 0.0, 0.0, 0.0);
    s->has_quad = 1;
    s->quadrupole[0] = 0.02;
    break;
  case SP_WATER:
  case SP_WATER_Q:
  case SP_WATER_LJ:
    ff_water(s);
    for (int a = 0; a < 4; a++) {
      if (which == SP_WATER_Q) s->epsilon[a] = 0.0;
      if (which == SP_WATER_LJ) s->charge[a] = 0.0;
    }
    break;
  default: /* Stockmayer: LJ and a dipole at the centre */
    ff_stockmayer(s, 0.05);
    break;
  }
}

#define E_ 4
#define H_ 2
#define F_ 1
#define NO -1

static const config configs[] = {
    /* name, species, scheme, lj, eps_rf, dipole, intra,   lj coul dd qd qq intra */
    {"LJ plain", {SP_ATOM, -1}, RL_CUTOFF_SITE, RL_LJ_PLAIN, 78.3, RL_DIPOLE_RF, 0, {E_ + F_, NO, NO, NO, NO, NO}},
    {"LJ shifted", {SP_ATOM, -1}, RL_CUTOFF_SITE, RL_LJ_SHIFTED, 78.3, RL_DIPOLE_RF, 0, {F_, NO, NO, NO, NO, NO}},
    {"LJ shifted-force", {SP_ATOM, -1}, RL_CUTOFF_SITE, RL_LJ_SHIFTED_FORCE, 78.3, RL_DIPOLE_RF, 0, {0, NO, NO, NO, NO, NO}},
    {"LJ switched", {SP_ATOM, -1}, RL_CUTOFF_SITE, RL_LJ_SWITCHED, 78.3, RL_DIPOLE_RF, 0, {0, NO, NO, NO, NO, NO}},
    {"LJ plain, molecule cutoff, site at the centre", {SP_ATOM, -1}, RL_CUTOFF_MOLECULE, RL_LJ_PLAIN, 78.3, RL_DIPOLE_RF, 0, {E_ + F_, NO, NO, NO, NO, NO}},
    {"charges RF eps 78.3", {SP_ION_P, SP_ION_M}, RL_CUTOFF_SITE, RL_LJ_PLAIN, 78.3, RL_DIPOLE_RF, 0, {NO, F_, NO, NO, NO, NO}},
    {"charges RF eps 1", {SP_ION_P, SP_ION_M}, RL_CUTOFF_SITE, RL_LJ_PLAIN, 1.0, RL_DIPOLE_RF, 0, {NO, F_, NO, NO, NO, NO}},
    {"charges RF eps inf", {SP_ION_P, SP_ION_M}, RL_CUTOFF_SITE, RL_LJ_PLAIN, INFINITY, RL_DIPOLE_RF, 0, {NO, 0, NO, NO, NO, NO}},
    {"dipoles RF eps 78.3", {SP_DIP, -1}, RL_CUTOFF_SITE, RL_LJ_PLAIN, 78.3, RL_DIPOLE_RF, 0, {NO, NO, E_ + H_ + F_, NO, NO, NO}},
    {"dipoles RF eps inf", {SP_DIP, -1}, RL_CUTOFF_SITE, RL_LJ_PLAIN, INFINITY, RL_DIPOLE_RF, 0, {NO, NO, E_ + H_ + F_, NO, NO, NO}},
    {"dipoles RF eps 1 (plain)", {SP_DIP, -1}, RL_CUTOFF_SITE, RL_LJ_PLAIN, 1.0, RL_DIPOLE_RF, 0, {NO, NO, E_ + H_ + F_, NO, NO, NO}},
    {"dipoles SF", {SP_DIP, -1}, RL_CUTOFF_SITE, RL_LJ_PLAIN, INFINITY, RL_DIPOLE_SF, 0, {NO, NO, 0, NO, NO, NO}},
    {"charge-dipole RF eps 78.3", {SP_ION_P, SP_DIP}, RL_CUTOFF_SITE, RL_LJ_PLAIN, 78.3, RL_DIPOLE_RF, 0, {NO, NO, NO, E_ + H_ + F_, NO, NO}},
    {"charge-dipole RF eps inf", {SP_ION_P, SP_DIP}, RL_CUTOFF_SITE, RL_LJ_PLAIN, INFINITY, RL_DIPOLE_RF, 0, {NO, NO, NO, F_, NO, NO}},
    {"charge-dipole SF", {SP_ION_P, SP_DIP}, RL_CUTOFF_SITE, RL_LJ_PLAIN, 78.3, RL_DIPOLE_SF, 0, {NO, NO, NO, 0, NO, NO}},
    {"quadrupoles", {SP_QUAD, -1}, RL_CUTOFF_SITE, RL_LJ_PLAIN, 78.3, RL_DIPOLE_RF, 0, {NO, NO, NO, NO, E_ + H_ + F_, NO}},
    {"Stockmayer SF, molecule cutoff (all at the centre)", {SP_STOCK, -1}, RL_CUTOFF_MOLECULE, RL_LJ_SHIFTED_FORCE, INFINITY, RL_DIPOLE_SF, 0, {0, NO, 0, NO, NO, NO}},
    {"water, molecule cutoff, shifted-force LJ, eps inf", {SP_WATER, -1}, RL_CUTOFF_MOLECULE, RL_LJ_SHIFTED_FORCE, INFINITY, RL_DIPOLE_RF, 0, {E_ + H_ + F_, E_ + H_ + F_, NO, NO, NO, NO}},
    {"water charges, molecule cutoff, eps inf", {SP_WATER_Q, -1}, RL_CUTOFF_MOLECULE, RL_LJ_SHIFTED_FORCE, INFINITY, RL_DIPOLE_RF, 0, {NO, E_ + H_ + F_, NO, NO, NO, NO}},
    {"water LJ (O 0.0066 nm off the centre), molecule cutoff, shifted-force", {SP_WATER_LJ, -1}, RL_CUTOFF_MOLECULE, RL_LJ_SHIFTED_FORCE, INFINITY, RL_DIPOLE_RF, 0, {E_ + H_ + F_, NO, NO, NO, NO, NO}},
    {"water, site cutoff, shifted-force LJ, eps inf, intramolecular", {SP_WATER, -1}, RL_CUTOFF_SITE, RL_LJ_SHIFTED_FORCE, INFINITY, RL_DIPOLE_RF, 1, {0, 0, NO, NO, NO, 0}},
};

/* A two-body system of the configuration, its force field, and its discontinuity entries. */
typedef struct {
  ff_test_species sp[2];
  rl_species_ff sff[2];
  rl_system *sys;
  rl_forcefield *ff;
  rl_ff_discontinuity d[8];
  int nd;
} setup;

static void setup_make(setup *u, const config *c)
{
  memset(u, 0, sizeof *u);
  u->sys = rl_system_alloc(RL_UNITS_REAL);
  const int nsp = c->species[1] < 0 ? 1 : 2;
  for (int k = 0; k < nsp; k++) {
    make_species(c->species[k], &u->sp[k]);
    u->sp[k].desc.sites = &u->sp[k].sites[0][0];
    assert_int_equal(rl_system_add_species(u->sys, &u->sp[k].desc, nsp == 1 ? 2 : 1, NULL), RL_OK);
    u->sff[k] = ff_test_species_ff(&u->sp[k]);
  }
  const double box[3] = {LBOX, LBOX, LBOX};
  assert_int_equal(rl_system_set_box(u->sys, box), RL_OK);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = RC;
  p.scheme = c->scheme;
  p.lj_truncation = c->lj;
  p.r_switch = 0.7;
  p.eps_rf = c->eps_rf;
  p.dipole_method = c->dip;
  p.intramolecular_rf = c->intra;
  p.neighbor_list = 0;
  u->ff = rl_forcefield_alloc(u->sys, &p, u->sff, nsp);
  assert_non_null(u->ff);
  u->nd = rl_forcefield_discontinuities(u->ff, u->d, 8);
  assert_true(u->nd <= 8);
}

static void setup_free(setup *u)
{
  rl_forcefield_free(u->ff);
  rl_system_free(u->sys);
}

static void orient(rl_system *sys, int i, const double R[9])
{
  rl_kind k = rl_system_species_kind(sys, rl_system_species_of(sys, i));
  if (k == RL_KIND_POINT) return;
  if (k == RL_KIND_DIPOLE || k == RL_KIND_LINEAR) {
    const double e[3] = {R[2], R[5], R[8]};
    assert_int_equal(rl_system_set_axis(sys, i, e), RL_OK);
  } else {
    const double At[9] = {R[0], R[3], R[6], R[1], R[4], R[7], R[2], R[5], R[8]}; /* A = R^T */
    assert_int_equal(rl_system_set_orientation(sys, i, At), RL_OK);
  }
}

/* Rotation sample k: the 24 rotations of the cube, then random ones. */
static void sample(gsl_rng *rng, int k, double R[9])
{
  if (k >= 24) {
    double q[4], n = 0.0;
    for (int c = 0; c < 4; c++) { q[c] = gsl_ran_gaussian(rng, 1.0); n += q[c] * q[c]; }
    for (int c = 0; c < 4; c++) q[c] /= sqrt(n);
    rl_quat_to_matrix(q, R);
    return;
  }
  static const int perm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
  for (int idx = 0, found = 0; idx < 48; idx++) {
    const int p = idx / 8, sg = idx % 8, neg = (sg & 1) + (sg >> 1 & 1) + (sg >> 2 & 1);
    if ((p >= 3) != (neg % 2)) continue;
    if (found++ < k) continue;
    memset(R, 0, 9 * sizeof *R);
    for (int r = 0; r < 3; r++) R[3 * r + perm[p][r]] = (sg >> r & 1) ? -1.0 : 1.0;
    return;
  }
}

typedef struct {
  double emax, emin, fmax, outside;
} measured;

/* The pair at centre distance RC - d along z over orientation pairs: the largest and smallest
 * energy and the largest force on body 1; `outside` the largest |E| at RC + d. */
static measured measure(setup *u)
{
  const double d = 1e-9 * RC, c0[3] = {1.0, 1.0, 1.0};
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 4);
  measured m = {-INFINITY, INFINITY, 0.0, 0.0};
  assert_int_equal(rl_system_set_position(u->sys, 0, c0), RL_OK);
  for (int k = 0; k < 24 * 24 + 200; k++) {
    double Ri[9], Rj[9];
    sample(rng, k < 576 ? k / 24 : 24, Ri);
    sample(rng, k < 576 ? k % 24 : 24, Rj);
    orient(u->sys, 0, Ri);
    orient(u->sys, 1, Rj);
    for (int side = -1; side <= 1; side += 2) {
      const double c1[3] = {c0[0], c0[1], c0[2] + RC + side * d};
      assert_int_equal(rl_system_set_position(u->sys, 1, c1), RL_OK);
      ff_result r;
      ff_result_compute(&r, u->ff, u->sys);
      rl_ff_energies e;
      rl_forcefield_energies(u->ff, &e);
      const double E = e.total - e.coulomb_intra; /* the intramolecular term is a constant */
      if (side < 0) {
        m.emax = fmax(m.emax, E);
        m.emin = fmin(m.emin, E);
        m.fmax = fmax(m.fmax, ff_maxnorm((const double(*)[3])r.f + 1, 1));
      } else {
        m.outside = fmax(m.outside, fabs(E));
      }
      ff_result_free(&r);
    }
  }
  gsl_rng_free(rng);
  return m;
}

static void discontinuities(void **state)
{
  (void)state;
  for (size_t c = 0; c < sizeof configs / sizeof *configs; c++) {
    const config *cf = &configs[c];
    setup u;
    setup_make(&u, cf);
    printf("info  %s:\n", cf->name);
    for (int k = 0; k < u.nd; k++)
      printf("info    [%s] %s\n", u.d[k].term, u.d[k].text);
    /* the entries: exactly the present terms, in the documented order, with the derived flags */
    int n = 0;
    for (int t = 0; t < NT; t++) {
      if (cf->want[t] < 0) continue;
      assert_true(n < u.nd);
      const rl_ff_discontinuity *d = &u.d[n++];
      const int got = d->energy_jumps * 4 + d->heats * 2 + d->force_jumps;
      char name[160];
      snprintf(name, sizeof name, "%s: %s flags E%d H%d F%d as derived", cf->name, term_name[t],
               cf->want[t] >> 2, cf->want[t] >> 1 & 1, cf->want[t] & 1);
      FF_CHECK_TRUE(name, !strcmp(d->term, term_name[t]) && got == cf->want[t]);
      FF_CHECK_TRUE("  the text is whole (shorter than RL_FF_TEXT - 1)", strlen(d->text) < RL_FF_TEXT - 1);
    }
    FF_CHECK_TRUE("  no other entries", n == u.nd);
    /* measured, for configurations with one term between the two bodies (the intramolecular
     * one aside) */
    int terms = 0;
    for (int t = 0; t < INTRA; t++)
      terms += cf->want[t] >= 0;
    if (terms == 1) {
      const rl_ff_discontinuity *d = &u.d[0];
      const measured m = measure(&u);
      const double jump = fmax(fabs(m.emax), fabs(m.emin));
      printf("info    measured at rc - 1e-9 rc: |E| up to %.6g (%.6g to %.6g), |F| up to %.6g; "
             "library: %.6g, %.6g\n", jump, m.emin, m.emax, m.fmax, d->energy_jump, d->force_jump);
      FF_CHECK_LE("  nothing at rc + 1e-9 rc", m.outside, 0.0);
      FF_CHECK_TRUE("  energy jump measured iff flagged", (jump > 1e-6) == d->energy_jumps);
      FF_CHECK_TRUE("  orientation-dependent jump iff heats", (d->energy_jumps && m.emax - m.emin > 1e-6) == d->heats);
      FF_CHECK_TRUE("  force jump measured iff flagged", (m.fmax > 1e-5) == d->force_jumps);
      const double tol = cf->scheme == RL_CUTOFF_MOLECULE && d->heats ? 0.3 : 1e-6;
      if (d->energy_jumps)
        FF_CHECK_LE("  |energy jump - measured| / measured", fabs(d->energy_jump - jump) / jump, tol);
      if (d->force_jumps)
        FF_CHECK_LE("  |force jump - measured| / measured", fabs(d->force_jump - m.fmax) / m.fmax, tol);
    }
    setup_free(&u);
  }
}

/* Setup warnings: water (sigma_O = 0.3154 nm) with a cutoff of 0.125 nm, shorter than any site
 * distance (issue 30: U/N = 0 without a word), and of 0.34 nm (between sigma and the minimum
 * 2^(1/6) sigma); none at 0.9 nm. */
static int warnings_at(double rc, int compute, rl_ff_warning *w, int max)
{
  ff_test_species s;
  ff_water(&s);
  rl_system *sys = rl_system_alloc(RL_UNITS_REAL);
  assert_int_equal(rl_system_add_species(sys, &s.desc, 2, NULL), RL_OK);
  const double r0[3] = {1.0, 1.0, 1.0}, r1[3] = {1.0, 1.0, 1.3};
  assert_int_equal(rl_system_set_position(sys, 0, r0), RL_OK);
  assert_int_equal(rl_system_set_position(sys, 1, r1), RL_OK);
  rl_species_ff sff = ff_test_species_ff(&s);
  const double box[3] = {3.0, 3.0, 3.0};
  assert_int_equal(rl_system_set_box(sys, box), RL_OK);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = rc;
  rl_forcefield *ff = rl_forcefield_alloc(sys, &p, &sff, 1);
  assert_non_null(ff);
  if (compute) {
    ff_result r;
    ff_result_compute(&r, ff, sys);
    printf("info  cutoff %g nm: E = %g kJ/mol\n", rc, r.out.energy);
    ff_result_free(&r);
  }
  const int n = rl_forcefield_warnings(ff, w, max);
  assert_int_equal(rl_forcefield_warnings(ff, NULL, 0), n);
  for (int k = 0; k < n && k < max; k++) printf("info  cutoff %g nm: warning: %s\n", rc, w[k].text);
  rl_forcefield_free(ff);
  rl_system_free(sys);
  return n;
}

static void warnings(void **state)
{
  (void)state;
  rl_ff_warning w[4];
  int n = warnings_at(0.125, 0, w, 4);
  FF_CHECK_TRUE("cutoff 0.125 nm, before a compute: one warning, sigma", n == 1 &&
                strstr(w[0].text, "shorter than the sigma") && strstr(w[0].text, "most of the repulsion"));
  n = warnings_at(0.125, 1, w, 4);
  FF_CHECK_TRUE("cutoff 0.125 nm, after a compute: and no pair within the cutoff", n == 2 &&
                strstr(w[1].text, "no pair of sites was within the cutoff 0.125 nm"));
  n = warnings_at(0.125, 1, w, 1);
  FF_CHECK_TRUE("cutoff 0.125 nm, room for one: 2 returned, the first written", n == 2 &&
                strstr(w[0].text, "sigma"));
  n = warnings_at(0.34, 1, w, 4);
  FF_CHECK_TRUE("cutoff 0.34 nm: the well is cut (sigma < rc < 2^(1/6) sigma)", n == 1 &&
                strstr(w[0].text, "minimum at 2^(1/6) sigma") && strstr(w[0].text, "attractive well is cut"));
  n = warnings_at(0.9, 1, w, 4);
  FF_CHECK_TRUE("cutoff 0.9 nm: no warning", n == 0);
}

/* The consequence (issue 31 item 2): 125 Stockmayer molecules (rho* = 0.8, T* = 1.35, mu*^2 = 3,
 * I* = 0.025, rc = 2.5, shifted-force LJ), equilibrated with shifted-force dipoles, then NVE
 * from the same state for 3 time units: with the dipolar reaction field (eps_rf = Inf) the
 * total energy rises at h = 0.002 and at h = 0.001 alike (the library says it heats), with
 * shifted-force dipoles it stays (the library says it is continuous). */
static double nve_slope(rl_system *start, rl_forcefield *ff, double h, double tmax)
{
  rl_system *c = rl_system_clone(start);
  assert_non_null(c);
  rl_integrator_params q;
  rl_integrator_params_default(&q);
  q.h = h;
  rl_integrator *in = rl_integrator_alloc(c, &q, rl_forcefield_provider(ff));
  assert_non_null(in);
  assert_int_equal(rl_integrator_init(in), RL_OK);
  const long n = lround(tmax / h);
  const int N = rl_system_count(c);
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  rl_step_info info;
  for (long k = 0; k < n; k++) {
    assert_int_equal(rl_integrator_step(in, &info), RL_OK);
    const double t = k * h, e = info.total / N;
    sx += t; sy += e; sxx += t * t; sxy += t * e;
  }
  rl_integrator_free(in);
  rl_system_free(c);
  return (n * sxy - sx * sy) / (n * sxx - sx * sx); /* least squares, per molecule and time unit */
}

static void nve_heating(void **state)
{
  (void)state;
  const rl_model *md = rl_catalog_find("stockmayer");
  assert_non_null(md);
  rl_molecule m;
  assert_int_equal(rl_model_build(md, NULL, 0, &m), RL_OK);
  rl_system *sys = rl_system_alloc(md->units);
  rl_species_desc d;
  rl_molecule_species(&m, &d);
  const int n = 125;
  assert_int_equal(rl_system_add_species(sys, &d, n, NULL), RL_OK);
  const double Lb = cbrt(n / 0.8), L[3] = {Lb, Lb, Lb};
  assert_int_equal(rl_system_lattice(sys, L, RL_LATTICE_SC, 1, 17), RL_OK);
  assert_int_equal(rl_system_maxwell_boltzmann(sys, 1.35, 18), RL_OK);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = 2.5;
  p.lj_truncation = RL_LJ_SHIFTED_FORCE;
  p.eps_rf = INFINITY;
  rl_species_ff sff = rl_molecule_ff(&m);
  p.dipole_method = RL_DIPOLE_SF;
  rl_forcefield *sf = rl_forcefield_alloc(sys, &p, &sff, 1);
  p.dipole_method = RL_DIPOLE_RF;
  rl_forcefield *rf = rl_forcefield_alloc(sys, &p, &sff, 1);
  assert_non_null(sf);
  assert_non_null(rf);
  rl_ff_discontinuity dr[4], ds[4];
  assert_int_equal(rl_forcefield_discontinuities(rf, dr, 4), 2);
  assert_int_equal(rl_forcefield_discontinuities(sf, ds, 4), 2);
  FF_CHECK_TRUE("Stockmayer: RF dipoles flagged as heating, SF dipoles continuous",
                dr[1].heats && !ds[1].energy_jumps && !ds[1].force_jumps);
  /* equilibration: Bussi at T* = 1.35 with shifted-force dipoles, 2 time units */
  rl_integrator_params q;
  rl_integrator_params_default(&q);
  q.h = 0.002;
  q.thermostat = RL_THERMO_BUSSI;
  q.T0 = 1.35;
  q.tau = 0.1;
  rl_integrator *eq = rl_integrator_alloc(sys, &q, rl_forcefield_provider(sf));
  assert_non_null(eq);
  assert_int_equal(rl_integrator_init(eq), RL_OK);
  for (int k = 0; k < 1000; k++) assert_int_equal(rl_integrator_step(eq, NULL), RL_OK);
  assert_int_equal(rl_integrator_finish(eq), RL_OK);
  rl_integrator_free(eq);
  const double s_rf2 = nve_slope(sys, rf, 0.002, 3.0), s_rf1 = nve_slope(sys, rf, 0.001, 3.0);
  const double s_sf2 = nve_slope(sys, sf, 0.002, 3.0);
  printf("info  NVE drift of E/N (epsilon per tau): dipole RF %.4f (h 0.002), %.4f (h 0.001); "
         "dipole SF %.5f (h 0.002)\n", s_rf2, s_rf1, s_sf2);
  FF_CHECK_TRUE("dipole RF heats at h = 0.002 (drift > 0.02 epsilon/tau)", s_rf2 > 0.02);
  FF_CHECK_TRUE("dipole RF heats at h = 0.001 as much (within a factor 2)", s_rf1 > 0.5 * s_rf2);
  FF_CHECK_LE("dipole SF: |drift| in epsilon/tau", fabs(s_sf2), 0.005);
  rl_forcefield_free(rf);
  rl_forcefield_free(sf);
  rl_system_free(sys);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(discontinuities),
      cmocka_unit_test(warnings),
      cmocka_unit_test(nve_heating),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
