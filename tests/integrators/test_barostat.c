/* The barostats (stepops.h): the Monte Carlo acceptance against a hand computation of one trial
 * (its random numbers drawn again from the same seed), the ideal gas's <V> = (N+1) kT / P0 for
 * both barostats, the C-rescale effective energy on a Lennard-Jones fluid, the checkpoint state
 * (save/load: a continuation bit for bit) and bad parameters. */
#include "expect_error.h"

#include <rotleap/stepops.h>
#include <rotleap/terms.h>
#include <gsl/gsl_rng.h>

#define assert_double_equal(a, b, tol) assert_true(fabs((a) - (b)) <= (tol))

/* ---------------------------------------------------------------- providers */

#define KTRAP 0.3

/* An isotropic trap about the origin: U = KTRAP/2 sum |r|^2 (volume-dependent through the scaled
 * centres); its virial is sum r . f. */
static int trap(void *ctx, const rl_system *sys, rl_forces *out)
{
  (void)ctx;
  for (int i = 0; i < rl_system_count(sys); i++) {
    double r[3];
    rl_system_get_position(sys, i, r);
    for (int c = 0; c < 3; c++) {
      out->f[i][c] = -KTRAP * r[c];
      out->virial[4 * c] += r[c] * out->f[i][c];
    }
    out->energy += 0.5 * KTRAP * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  }
  return RL_OK;
}

static int nothing(void *ctx, const rl_system *sys, rl_forces *out)
{
  (void)ctx; (void)sys; (void)out;
  return RL_OK;
}

/* n point particles of mass 1 at random in a cubic box L, velocities at T = 1; no dof removed. */
static rl_system *gas(int n, double L, unsigned long seed)
{
  rl_system *s = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc d = {.name = "p", .kind = RL_KIND_POINT, .mass = 1.0};
  assert_int_equal(rl_system_add_species(s, &d, n, NULL), RL_OK);
  const double box[3] = {L, L, L};
  assert_int_equal(rl_system_set_box(s, box), RL_OK);
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, seed);
  for (int i = 0; i < n; i++) {
    double x[3];
    for (int c = 0; c < 3; c++) x[c] = L * gsl_rng_uniform(r);
    assert_int_equal(rl_system_set_position(s, i, x), RL_OK);
  }
  gsl_rng_free(r);
  rl_system_set_removed_dof(s, 0);
  assert_int_equal(rl_system_maxwell_boltzmann(s, 1.0, seed), RL_OK);
  rl_system_set_removed_dof(s, 0);
  return s;
}

static rl_integrator *nvt(rl_system *s, rl_force_fn f, double h)
{
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = h;
  p.thermostat = RL_THERMO_BUSSI;
  p.T0 = 1.0;
  p.tau = 20 * h;
  p.seed = 5;
  rl_integrator *in = rl_integrator_alloc(s, &p, (rl_force_provider){f, NULL});
  assert_non_null(in);
  return in;
}

static rl_barostat_params baro(double P0, long interval, unsigned long seed)
{
  return (rl_barostat_params){.P0 = P0, .T0 = 1.0, .interval = interval, .tau_p = 1.0, .compressibility = 0.1,
                              .coupling = RL_BARO_ISOTROPIC, .seed = seed};
}

static void step_ok(rl_integrator *in)
{
  const int st = rl_integrator_step(in, NULL);
  if (st) print_message("step: %s\n", rl_last_error());
  assert_int_equal(st, RL_OK);
}

/* ---------------------------------------------------------------- Monte Carlo by hand */

/* One step with a trial after it, against the trial done by hand: the integrator without the
 * barostat gives the centres r1; the same seed gives the barostat's u1 (dV), u2 (the test).  Many
 * seeds, so that acceptances and rejections both occur; each must be the formula's. */
static void mc_acceptance_by_hand(void **state)
{
  (void)state;
  const int n = 3;
  const double L = 4.0, P0 = 0.5, trial = 0.2, V = L * L * L;
  int accepted = 0, rejected = 0;
  for (unsigned long seed = 1; seed <= 400; seed++) {
    rl_system *ref = gas(n, L, 11), *s = gas(n, L, 11);
    rl_integrator_params p;
    rl_integrator_params_default(&p);
    p.h = 0.01;
    rl_integrator *a = rl_integrator_alloc(ref, &p, (rl_force_provider){trap, NULL});
    rl_integrator *b = rl_integrator_alloc(s, &p, (rl_force_provider){trap, NULL});
    rl_barostat_params bp = baro(P0, 1, seed);
    bp.trial = trial;
    assert_int_equal(rl_integrator_add_op(b, &rl_stepop_mc_barostat, &bp), RL_OK);
    assert_int_equal(rl_integrator_init(a), RL_OK);
    assert_int_equal(rl_integrator_init(b), RL_OK);
    assert_int_equal(rl_integrator_step(a, NULL), RL_OK);
    assert_int_equal(rl_integrator_step(b, NULL), RL_OK);
    /* by hand */
    gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(g, seed);
    const double dV = trial * V * 2.0 * (gsl_rng_uniform(g) - 0.5), Vn = V + dV, f = cbrt(Vn / V);
    double U0 = 0.0, U1 = 0.0, r1[8][3];
    for (int i = 0; i < n; i++) {
      rl_system_get_position(ref, i, r1[i]);
      for (int c = 0; c < 3; c++) {
        U0 += 0.5 * KTRAP * r1[i][c] * r1[i][c];
        U1 += 0.5 * KTRAP * (f * r1[i][c]) * (f * r1[i][c]);
      }
    }
    const double w = U1 - U0 + P0 * dV - n * 1.0 * log(Vn / V); /* kT = 1 */
    const int accept = w <= 0.0 || gsl_rng_uniform(g) <= exp(-w);
    gsl_rng_free(g);
    double Lb[3];
    rl_system_box(s, Lb);
    const double want = accept ? f : 1.0;
    for (int c = 0; c < 3; c++) assert_double_equal(Lb[c], L * want, 1e-12 * L);
    for (int i = 0; i < n; i++) {
      double r[3];
      rl_system_get_position(s, i, r);
      for (int c = 0; c < 3; c++) assert_double_equal(r[c], want * r1[i][c], 1e-12);
    }
    rl_barostat_stats st;
    assert_int_equal(rl_barostat_stats_of(rl_integrator_op(b, 0), &st), RL_OK);
    assert_int_equal(st.attempted[0], 1);
    assert_int_equal(st.accepted[0], accept);
    /* the account keeps the conserved quantity continuous: -dU of an accepted move */
    assert_double_equal(rl_integrator_thermostat_work(b), accept ? -(U1 - U0) : 0.0, 1e-12);
    accepted += accept;
    rejected += !accept;
    rl_integrator_free(a);
    rl_integrator_free(b);
    rl_system_free(ref);
    rl_system_free(s);
  }
  assert_true(accepted >= 5 && rejected >= 5);
}

/* ---------------------------------------------------------------- the ideal gas */

/* <V> of n non-interacting particles at P0 = 1, kT = 1 sampled by `type` over `steps` steps:
 * the mean and its standard error from 50 blocks. */
static double ideal_gas_volume(const rl_stepop_type *type, rl_baro_coupling cpl, int n, long steps, double *sem,
                               double *acc)
{
  rl_system *s = gas(n, 2.5, 3);
  rl_integrator *in = nvt(s, nothing, 0.05);
  rl_barostat_params bp = baro(1.0, 1, 17);
  bp.coupling = cpl;
  bp.tau_p = 0.5;
  bp.compressibility = 1.0 / n; /* about the gas's, 1/P0 over (N+1)/N... order of magnitude */
  assert_int_equal(rl_integrator_add_op(in, type, &bp), RL_OK);
  assert_int_equal(rl_integrator_init(in), RL_OK);
  const long burn = steps / 20, nb = 50, per = (steps - burn) / nb;
  double bsum = 0.0, bsum2 = 0.0, shape = 0.0;
  for (long k = 0; k < burn; k++) step_ok(in);
  for (long q = 0; q < nb; q++) {
    double m = 0.0;
    for (long k = 0; k < per; k++) {
      step_ok(in);
      m += rl_system_volume(s);
      if (cpl == RL_BARO_SEMIISOTROPIC) { /* x and y scaled together, to the bit */
        double L[3];
        rl_system_box(s, L);
        if (L[0] != L[1]) fail_msg("semi-isotropic: Lx %.17g != Ly %.17g", L[0], L[1]);
        shape = fmax(shape, fabs(log(L[2] / L[0])));
      }
    }
    m /= per;
    bsum += m;
    bsum2 += m * m;
  }
  const double mean = bsum / nb;
  *sem = sqrt((bsum2 / nb - mean * mean) / (nb - 1));
  rl_barostat_stats st;
  assert_int_equal(rl_barostat_stats_of(rl_integrator_op(in, 1), &st), RL_OK);
  *acc = (double)st.accepted[0] / (double)st.attempted[0];
  if (cpl == RL_BARO_SEMIISOTROPIC) { /* z moves apart from x and y */
    print_message("semi-isotropic: largest |ln(Lz/Lx)| %.3f\n", shape);
    assert_true(shape > 0.1);
  }
  rl_integrator_free(in);
  rl_system_free(s);
  return mean;
}

static void ideal_gas(void **state)
{
  (void)state;
  const int n = 10;
  const double want = (n + 1) * 1.0 / 1.0; /* (N+1) kT / P0 */
  double sem, acc;
  double V = ideal_gas_volume(&rl_stepop_mc_barostat, RL_BARO_ISOTROPIC, n, 200000, &sem, &acc);
  print_message("MC ideal gas, N = %d: <V> = %.4f +- %.4f (want %.4f), acceptance %.3f\n", n, V, sem, want, acc);
  assert_true(fabs(V - want) < 4.0 * sem);
  assert_true(sem < 0.02 * want);
  assert_true(acc > 0.2 && acc < 0.9);
  V = ideal_gas_volume(&rl_stepop_crescale, RL_BARO_ISOTROPIC, n, 200000, &sem, &acc);
  print_message("C-rescale ideal gas, N = %d: <V> = %.4f +- %.4f (want %.4f)\n", n, V, sem, want);
  assert_true(fabs(V - want) < 4.0 * sem);
  assert_true(sem < 0.02 * want);
}

/* Semi-isotropic C-rescale: ln V moves as the isotropic one (the law V^N exp(-P0 V/kT) dV), Lx = Ly
 * throughout, and Lz apart from them (the shape of an ideal gas is free). */
static void ideal_gas_semi(void **state)
{
  (void)state;
  const int n = 10;
  const double want = (n + 1) * 1.0 / 1.0;
  double sem, acc;
  const double V = ideal_gas_volume(&rl_stepop_crescale, RL_BARO_SEMIISOTROPIC, n, 200000, &sem, &acc);
  print_message("C-rescale semi-isotropic ideal gas, N = %d: <V> = %.4f +- %.4f (want %.4f)\n", n, V, sem, want);
  assert_true(fabs(V - want) < 4.0 * sem);
  assert_true(sem < 0.02 * want);
}

/* ---------------------------------------------------------------- a Stockmayer liquid */

#define NLIQ 125
#define RC 2.0

typedef struct {
  rl_molecule mol;
  rl_species_ff sff;
  rl_system *sys;
  rl_terms *terms;
  rl_integrator *in;
} liquid;

/* 125 Stockmayer molecules at number density 0.8, T = 1.35 (Bussi), cutoff 2 (shifted force),
 * the barostat `type` at P0 (interval every steps); sys: a state to start from (cloned), or NULL
 * for a lattice. */
static void liquid_make(liquid *q, const rl_system *from, double h, const rl_stepop_type *type, double P0,
                        long every, unsigned long seed, rl_baro_coupling cpl)
{
  assert_int_equal(rl_model_build(rl_catalog_find("stockmayer"), NULL, 0, &q->mol), RL_OK);
  if (from) q->sys = rl_system_clone(from);
  else {
    q->sys = rl_system_alloc(RL_UNITS_LJ);
    rl_species_desc d;
    rl_molecule_species(&q->mol, &d);
    assert_int_equal(rl_system_add_species(q->sys, &d, NLIQ, NULL), RL_OK);
    const double L = cbrt(NLIQ / 0.8), box[3] = {L, L, L};
    assert_int_equal(rl_system_lattice(q->sys, box, RL_LATTICE_SC, 1, 3), RL_OK);
    assert_int_equal(rl_system_maxwell_boltzmann(q->sys, 1.35, 4), RL_OK);
  }
  q->sff = rl_molecule_ff(&q->mol);
  rl_pair_params pp = {.species = &q->sff, .nspecies = 1};
  rl_ff_params_default(&pp.p);
  pp.p.cutoff = RC;
  pp.p.lj_truncation = RL_LJ_SHIFTED_FORCE;
  pp.p.dipole_method = RL_DIPOLE_SF;
  q->terms = rl_terms_alloc(q->sys);
  assert_int_equal(rl_terms_add(q->terms, &rl_term_pair, &pp, NULL), RL_OK);
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = h;
  p.thermostat = RL_THERMO_BUSSI;
  p.T0 = 1.35;
  p.tau = 0.5;
  p.seed = 9;
  q->in = rl_integrator_alloc(q->sys, &p, rl_terms_provider(q->terms));
  assert_non_null(q->in);
  rl_barostat_params bp = baro(P0, every, seed);
  bp.T0 = 1.35;
  bp.tau_p = 1.0;
  bp.compressibility = 0.05;
  bp.min_edge = 2.0 * RC;
  bp.coupling = cpl;
  if (type) assert_int_equal(rl_integrator_add_op(q->in, type, &bp), RL_OK);
}

static void liquid_free(liquid *q)
{
  rl_integrator_free(q->in);
  rl_terms_free(q->terms);
  rl_system_free(q->sys);
}

/* The effective energy (total + the thermostat's and barostat's accounts) of C-rescale over a
 * time T at two steps: its drift per molecule and time unit must be small and fall with h. */
static double crescale_drift(const rl_system *start, double h, double T, rl_baro_coupling cpl, double *dV)
{
  liquid q;
  liquid_make(&q, start, h, &rl_stepop_crescale, 1.0, 1, 21, cpl);
  assert_int_equal(rl_integrator_init(q.in), RL_OK);
  const long n = lround(T / h);
  double V0 = rl_system_volume(q.sys), t0 = 0.0, c0 = 0.0, st = 0, stt = 0, sc = 0, stc = 0;
  for (long k = 0; k < n; k++) {
    rl_step_info info;
    assert_int_equal(rl_integrator_step(q.in, &info), RL_OK);
    if (k == 0) { t0 = info.t; c0 = info.conserved; }
    const double t = info.t - t0, c = info.conserved - c0; /* a least-squares slope */
    st += t; stt += t * t; sc += c; stc += t * c;
  }
  *dV = rl_system_volume(q.sys) / V0 - 1.0;
  liquid_free(&q);
  return (n * stc - st * sc) / (n * stt - st * st) / NLIQ / 1.35; /* kT per molecule per time unit */
}

static void effective_energy(rl_baro_coupling cpl)
{
  liquid q; /* an equilibrated start: 400 steps of NVT */
  liquid_make(&q, NULL, 0.005, NULL, 0.0, 1, 1, RL_BARO_ISOTROPIC);
  assert_int_equal(rl_integrator_init(q.in), RL_OK);
  for (int k = 0; k < 400; k++) step_ok(q.in);
  assert_int_equal(rl_integrator_finish(q.in), RL_OK);
  double dV1, dV2;
  const double d1 = crescale_drift(q.sys, 0.005, 10.0, cpl, &dV1), d2 = crescale_drift(q.sys, 0.0025, 10.0, cpl, &dV2);
  print_message("C-rescale (%s) effective energy drift: %.3e (h = 0.005), %.3e (h = 0.0025) kT per molecule per time "
                "unit; volume changed by %.3f, %.3f\n", cpl == RL_BARO_SEMIISOTROPIC ? "semi-isotropic" : "isotropic",
                d1, d2, dV1, dV2);
  CHECK_LE("|drift| at h = 0.0025 (kT/molecule/time)", fabs(d2), 2e-3);
  CHECK_LE("the box moved (|dV/V|)", 1e-3, fmax(fabs(dV1), fabs(dV2)));
  liquid_free(&q);
}

static void crescale_effective_energy(void **state) { (void)state; effective_energy(RL_BARO_ISOTROPIC); }
static void crescale_semi_effective_energy(void **state) { (void)state; effective_energy(RL_BARO_SEMIISOTROPIC); }

/* ------------------------------------------------------------------ continuation */

/* 2N steps in one go against N, a checkpoint of everything the app keeps (the state, the
 * thermostat's random stream and account, the barostat's saved state, the pair list's origin and
 * the box of its build: the list outlives the barostat's moves), and N more from it in a new
 * integrator: the same positions, box and velocities to the bit. */
static void continuation(const rl_stepop_type *type, long every)
{
  const long N = 60;
  liquid a, b, c;
  liquid_make(&a, NULL, 0.004, type, 1.0, every, 33, RL_BARO_ISOTROPIC);
  liquid_make(&b, NULL, 0.004, type, 1.0, every, 33, RL_BARO_ISOTROPIC);
  assert_int_equal(rl_integrator_init(a.in), RL_OK);
  assert_int_equal(rl_integrator_init(b.in), RL_OK);
  for (long k = 0; k < 2 * N; k++) step_ok(a.in);
  for (long k = 0; k < N; k++) step_ok(b.in);
  /* the checkpoint */
  rl_stepop *bo = rl_integrator_op(b.in, 1);
  const size_t size = rl_stepop_save(bo, NULL);
  assert_true(size > 0);
  void *saved = malloc(size);
  assert_int_equal(rl_stepop_save(bo, saved), size);
  const size_t nr = rl_integrator_rng_size(b.in);
  void *rng = malloc(nr);
  memcpy(rng, rl_integrator_rng_state(b.in), nr);
  const double work = rl_integrator_thermostat_work(b.in), t = rl_integrator_time(b.in);
  double(*r0)[3] = malloc(sizeof *r0 * NLIQ), L0b[3], Lb[3];
  const rl_forcefield *ffb = rl_terms_find(b.terms, &rl_term_pair);
  assert_int_equal(rl_forcefield_list_origin(ffb, r0), 1);
  assert_int_equal(rl_forcefield_list_box(ffb, L0b), 1);
  rl_system_box(b.sys, Lb);
  /* the continuation, in a new integrator on a copy of the state */
  liquid_make(&c, b.sys, 0.004, type, 1.0, every, 99, RL_BARO_ISOTROPIC); /* another seed: the saved stream replaces it */
  rl_forcefield *ffc = rl_terms_find(c.terms, &rl_term_pair);
  assert_int_equal(rl_forcefield_set_list_origin(ffc, (const double(*)[3])r0), RL_OK);
  assert_int_equal(rl_forcefield_set_list_box(ffc, L0b), RL_OK);
  print_message("%s: the list of step %ld was built in a box %s the current one\n", type->name, N,
                memcmp(L0b, Lb, sizeof Lb) ? "other than" : "equal to");
  free(r0);
  assert_int_equal(rl_stepop_load(rl_integrator_op(c.in, 1), saved, size), RL_OK);
  memcpy(rl_integrator_rng_state(c.in), rng, nr);
  assert_int_equal(rl_integrator_resume(c.in, N, t), RL_OK);
  rl_integrator_set_thermostat_work(c.in, work);
  for (long k = 0; k < N; k++) step_ok(c.in);
  double La[3], Lc[3];
  rl_system_box(a.sys, La);
  rl_system_box(c.sys, Lc);
  assert_memory_equal(La, Lc, sizeof La);
  double L0 = cbrt(NLIQ / 0.8);
  print_message("%s: box %.6f -> %.6f after %ld steps\n", type->name, L0, La[0], 2 * N);
  assert_true(La[0] != L0);
  for (int i = 0; i < NLIQ; i++) {
    double ra[3], rc[3], va[3], vc[3];
    rl_system_get_position(a.sys, i, ra);
    rl_system_get_position(c.sys, i, rc);
    rl_system_get_velocity(a.sys, i, va);
    rl_system_get_velocity(c.sys, i, vc);
    assert_memory_equal(ra, rc, sizeof ra);
    assert_memory_equal(va, vc, sizeof va);
  }
  rl_barostat_stats sa, sc;
  rl_barostat_stats_of(rl_integrator_op(a.in, 1), &sa);
  rl_barostat_stats_of(rl_integrator_op(c.in, 1), &sc);
  assert_memory_equal(&sa, &sc, sizeof sa);
  /* a damaged saved state is refused */
  EXPECT_ERROR(rl_stepop_load(rl_integrator_op(c.in, 1), saved, size - 1), RL_EINVAL, "saved state");
  free(saved);
  free(rng);
  liquid_free(&a);
  liquid_free(&b);
  liquid_free(&c);
}

static void continuation_mc(void **state) { (void)state; continuation(&rl_stepop_mc_barostat, 5); }

/* A rejected Monte Carlo trial puts back the computation it kept (rl_stepop_forces_keep) instead
 * of computing again: after every step whose trial was rejected the integrator's forces, energy
 * and the terms' energy components are those of a fresh computation at the restored state (in a
 * new sum of terms, with its own pair list: to round-off), and the components add up to the
 * energy (a component left at the trial's would not). */
static void mc_rejection_puts_back(void **state)
{
  (void)state;
  liquid q;
  liquid_make(&q, NULL, 0.004, &rl_stepop_mc_barostat, 1.0, 1, 5, RL_BARO_ISOTROPIC);
  assert_int_equal(rl_integrator_init(q.in), RL_OK);
  rl_forces fresh = {malloc(sizeof *fresh.f * NLIQ), malloc(sizeof *fresh.k * NLIQ), 0, {0}, 0};
  long rejected = 0, acc0 = 0;
  double worst = 0.0;
  for (int k = 0; k < 60; k++) {
    step_ok(q.in);
    rl_barostat_stats st;
    assert_int_equal(rl_barostat_stats_of(rl_integrator_op(q.in, 1), &st), RL_OK);
    const int rej = st.accepted[0] == acc0;
    acc0 = st.accepted[0];
    if (!rej) continue;
    rejected++;
    const rl_forces *F = rl_integrator_forces(q.in);
    rl_system *s2 = rl_system_clone(q.sys);
    liquid p = q; /* the same parameters, a new sum on the copy */
    rl_pair_params pp = {.species = &q.sff, .nspecies = 1};
    rl_ff_params_default(&pp.p);
    pp.p.cutoff = RC;
    pp.p.lj_truncation = RL_LJ_SHIFTED_FORCE;
    pp.p.dipole_method = RL_DIPOLE_SF;
    p.terms = rl_terms_alloc(s2);
    assert_int_equal(rl_terms_add(p.terms, &rl_term_pair, &pp, NULL), RL_OK);
    memset(fresh.f, 0, sizeof *fresh.f * NLIQ);
    memset(fresh.k, 0, sizeof *fresh.k * NLIQ);
    fresh.energy = 0.0;
    memset(fresh.virial, 0, sizeof fresh.virial);
    assert_int_equal(rl_terms_compute(p.terms, s2, &fresh), RL_OK);
    double fmaxv = 0.0, df = 0.0, sum = 0.0;
    for (int i = 0; i < NLIQ; i++)
      for (int c = 0; c < 3; c++) {
        fmaxv = fmax(fmaxv, fabs(fresh.f[i][c]));
        df = fmax(df, fabs(F->f[i][c] - fresh.f[i][c]));
        df = fmax(df, fabs(F->k[i][c] - fresh.k[i][c]));
      }
    double de = fabs(F->energy - fresh.energy) / fabs(fresh.energy);
    for (int j = 0; j < rl_terms_nenergies(q.terms); j++) {
      const double e = rl_terms_energy(q.terms, j), e2 = rl_terms_energy(p.terms, j);
      sum += e;
      de = fmax(de, fabs(e - e2) / fabs(fresh.energy));
    }
    de = fmax(de, fabs(sum - F->energy) / fabs(fresh.energy));
    for (int c = 0; c < 9; c++) de = fmax(de, fabs(F->virial[c] - fresh.virial[c]) / fabs(fresh.energy));
    worst = fmax(worst, fmax(df / fmaxv, de));
    rl_terms_free(p.terms);
    rl_system_free(s2);
  }
  print_message("%ld of 60 trials rejected\n", rejected);
  assert_true(rejected >= 5);
  CHECK_LE("rejected trials: forces, torques, energy components, virial against a fresh computation", worst, 1e-11);
  free(fresh.f);
  free(fresh.k);
  liquid_free(&q);
}
static void continuation_crescale(void **state) { (void)state; continuation(&rl_stepop_crescale, 2); }

/* -------------------------------------------------------------------------- refused */

static void refused(void **state)
{
  (void)state;
  rl_system *s = gas(4, 5.0, 1);
  rl_integrator *in = nvt(s, nothing, 0.01);
  rl_barostat_params bp = baro(1.0, 1, 1);
  bp.compressibility = 0.0;
  EXPECT_ERROR(rl_integrator_add_op(in, &rl_stepop_crescale, &bp), RL_EINVAL, "positive compressibility");
  bp = baro(1.0, 1, 1);
  bp.tau_p = -1.0;
  EXPECT_ERROR(rl_integrator_add_op(in, &rl_stepop_crescale, &bp), RL_EINVAL, "positive coupling time");
  bp = baro(1.0, 0, 1);
  EXPECT_ERROR(rl_integrator_add_op(in, &rl_stepop_mc_barostat, &bp), RL_EINVAL, "interval >= 1");
  bp = baro(1.0, 1, 1);
  bp.T0 = 0.0;
  EXPECT_ERROR(rl_integrator_add_op(in, &rl_stepop_mc_barostat, &bp), RL_EINVAL, "positive temperature");
  bp = baro(1.0, 1, 1);
  bp.coupling = RL_BARO_ANISOTROPIC;
  EXPECT_ERROR(rl_integrator_add_op(in, &rl_stepop_crescale, &bp), RL_EINVAL, "isotropic or semi-isotropic");
  bp = baro(1.0, 1, 1);
  bp.coupling = RL_BARO_SEMIISOTROPIC;
  EXPECT_ERROR(rl_integrator_add_op(in, &rl_stepop_mc_barostat, &bp), RL_EINVAL, "semi-isotropic coupling: C-rescale");
  rl_integrator_free(in);
  /* a non-periodic system */
  const double none[3] = {0.0, 0.0, 0.0};
  assert_int_equal(rl_system_set_box(s, none), RL_OK);
  in = nvt(s, nothing, 0.01);
  bp = baro(1.0, 1, 1);
  EXPECT_ERROR(rl_integrator_add_op(in, &rl_stepop_mc_barostat, &bp), RL_EINVAL, "periodic box");
  rl_integrator_free(in);
  rl_system_free(s);
  /* a box that would shrink below min_edge stops the step, naming it */
  s = gas(4, 5.0, 1);
  in = nvt(s, nothing, 0.01);
  bp = baro(1e6, 1, 1); /* an absurd pressure: every trial shrinks */
  bp.trial = 0.5;
  bp.min_edge = 4.9;
  assert_int_equal(rl_integrator_add_op(in, &rl_stepop_mc_barostat, &bp), RL_OK);
  assert_int_equal(rl_integrator_init(in), RL_OK);
  int st = RL_OK;
  for (int k = 0; k < 50 && !st; k++) st = rl_integrator_step(in, NULL);
  EXPECT_ERROR(st, RL_EINVAL, "below 4.9");
  rl_integrator_free(in);
  rl_system_free(s);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(mc_acceptance_by_hand), cmocka_unit_test(ideal_gas),
                                     cmocka_unit_test(ideal_gas_semi), cmocka_unit_test(crescale_semi_effective_energy),
                                     cmocka_unit_test(crescale_effective_energy), cmocka_unit_test(continuation_mc),
                                     cmocka_unit_test(continuation_crescale), cmocka_unit_test(mc_rejection_puts_back),
                                     cmocka_unit_test(refused)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
