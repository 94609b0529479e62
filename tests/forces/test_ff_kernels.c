/* Kernel physics: multipole kernels against explicit charge distributions, truncation
 * properties at the cutoff, dispersion-correction closed forms, and the molecular virial against
 * -dU/dV under affine scaling of the centres. */
#include "ff_testutil.h"

#include "../../forces/pair/coulomb_rf.h"
#include "../../forces/pair/dipole.h"
#include "../../forces/pair/lj.h"
#include "../../forces/pair/quadrupole.h"

static double coulomb_sum(const double (*ra)[3], const double *qa, int na, const double (*rb)[3],
                          const double *qb, int nb)
{
  /* long double: the multipole energies are small differences of O(1) terms */
  long double e = 0.0L;
  for (int a = 0; a < na; a++)
    for (int b = 0; b < nb; b++) {
      long double d[3] = {(long double)ra[a][0] - rb[b][0], (long double)ra[a][1] - rb[b][1],
                          (long double)ra[a][2] - rb[b][2]};
      e += (long double)qa[a] * qb[b] / sqrtl(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
  return (double)e;
}

static void unit_random(gsl_rng *rng, double e[3])
{
  double n = 0.0;
  for (int c = 0; c < 3; c++) { e[c] = gsl_ran_gaussian(rng, 1.0); n += e[c] * e[c]; }
  for (int c = 0; c < 3; c++) e[c] /= sqrt(n);
}

static void test_multipoles_vs_charges(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 5);
  const double d = 1e-4, q = 1.0;
  double worst_dd = 0, worst_qd = 0, worst_qq = 0;
  for (int t = 0; t < 20; t++) {
    double ei[3], ej[3], r[3], f[3], gi[3], gj[3];
    unit_random(rng, ei);
    unit_random(rng, ej);
    unit_random(rng, r);
    /* dipole = +q at +d/2 e, -q at -d/2 e: mu = q d e */
    double pi[2][3], pj[2][3], qd[2] = {q, -q};
    for (int c = 0; c < 3; c++) {
      pi[0][c] = r[c] + 0.5 * d * ei[c]; pi[1][c] = r[c] - 0.5 * d * ei[c];
      pj[0][c] = 0.5 * d * ej[c]; pj[1][c] = -0.5 * d * ej[c];
    }
    double mui[3], muj[3];
    for (int c = 0; c < 3; c++) { mui[c] = q * d * ei[c]; muj[c] = q * d * ej[c]; }
    double ref = coulomb_sum((const double(*)[3])pi, qd, 2, (const double(*)[3])pj, qd, 2);
    double e = rl_dipole_dipole_rf(1.0, 0.0, r, mui, muj, f, gi, gj);
    worst_dd = fmax(worst_dd, fabs(e - ref) / fabs(ref));
    /* charge q at r, dipole j at 0 */
    double qc[1] = {q}, pc[1][3] = {{r[0], r[1], r[2]}};
    ref = coulomb_sum((const double(*)[3])pc, qc, 1, (const double(*)[3])pj, qd, 2);
    e = rl_charge_dipole_rf(1.0, 0.0, r, q, muj, f, gj);
    worst_qd = fmax(worst_qd, fabs(e - ref) / fabs(ref));
    /* linear quadrupole: +q at +-dq e, -2q at 0, Q = 2 q dq^2.  The charge sum per Q^2 is
     * U/Q^2 + O(dq^2); one Richardson step (dq, dq/2) removes the O(dq^2) term.  Errors are
     * measured against K = 3 Q^2 / (4 r^5), the scale of U (U itself has zeros in angle). */
    double ext[2];
    for (int h = 0; h < 2; h++) {
      double dq = h ? 5e-3 : 1e-2, Q = 2 * q * dq * dq;
      double li[3][3], lj3[3][3], ql[3] = {q, q, -2 * q};
      for (int c = 0; c < 3; c++) {
        li[0][c] = r[c] + dq * ei[c]; li[1][c] = r[c] - dq * ei[c]; li[2][c] = r[c];
        lj3[0][c] = dq * ej[c]; lj3[1][c] = -dq * ej[c]; lj3[2][c] = 0.0;
      }
      ext[h] = coulomb_sum((const double(*)[3])li, ql, 3, (const double(*)[3])lj3, ql, 3) / (Q * Q);
    }
    ref = (4.0 * ext[1] - ext[0]) / 3.0;
    e = rl_quadrupole_quadrupole(1.0, r, 1.0, ei, 1.0, ej, f, gi, gj);
    double K = 0.75 / pow(sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]), 5.0);
    worst_qq = fmax(worst_qq, fabs(e - ref) / K);
  }
  FF_CHECK_LE("kernel dipole-dipole (eps_rf 1) vs two charge pairs, d = 1e-4", worst_dd, 1e-6);
  FF_CHECK_LE("kernel charge-dipole (eps_rf 1) vs charges, d = 1e-4", worst_qd, 1e-6);
  FF_CHECK_LE("kernel quadrupole-quadrupole vs charge triples (Richardson), err / K", worst_qq, 1e-6);
  gsl_rng_free(rng);
}

static void test_truncations(void **state)
{
  (void)state;
  const double rc = 1.0, rsw = 0.8, sig = 0.32, eps = 0.65;
  rl_lj_coef c;
  double fs, e;
  rl_lj_coef_init(&c, sig, eps, RL_LJ_SHIFTED, rc, rsw);
  e = rl_lj_pair(&c, rc * rc, &fs);
  FF_CHECK_LE("LJ shifted: |U(rc)|", fabs(e), 1e-15);
  rl_lj_coef_init(&c, sig, eps, RL_LJ_SHIFTED_FORCE, rc, rsw);
  e = rl_lj_pair(&c, rc * rc, &fs);
  FF_CHECK_LE("LJ shifted-force: |U(rc)|", fabs(e), 1e-15);
  FF_CHECK_LE("LJ shifted-force: |F(rc)|", fabs(fs * rc), 1e-14);
  rl_lj_coef_init(&c, sig, eps, RL_LJ_SWITCHED, rc, rsw);
  double r1 = rc - 1e-7;
  e = rl_lj_pair(&c, r1 * r1, &fs);
  FF_CHECK_LE("LJ switched: |U(rc - 1e-7)|", fabs(e), 1e-12);
  FF_CHECK_LE("LJ switched: |F(rc - 1e-7)|", fabs(fs * r1), 1e-9);
  rl_lj_coef p;
  rl_lj_coef_init(&p, sig, eps, RL_LJ_PLAIN, rc, rsw);
  double fp, ep = rl_lj_pair(&p, rsw * rsw, &fp);
  e = rl_lj_pair(&c, rsw * rsw, &fs);
  FF_CHECK_LE("LJ switched: U(r_switch) = u(r_switch)", fabs(e - ep), 1e-15);

  rl_rf_coef rf;
  rl_rf_coef_init(&rf, INFINITY, rc);
  e = rl_coulomb_rf_pair(&rf, 1.0, rc * rc, &fs);
  FF_CHECK_LE("RF eps inf: |U(rc)|", fabs(e), 1e-15);
  FF_CHECK_LE("RF eps inf: |F(rc)|", fabs(fs * rc), 1e-15);
  FF_CHECK_LE("RF eps inf: krf = 1/(2 rc^3)", fabs(rf.krf - 0.5), 1e-15);
  rl_rf_coef_init(&rf, 78.3, rc);
  e = rl_coulomb_rf_pair(&rf, 1.0, rc * rc, &fs);
  FF_CHECK_LE("RF eps 78.3: |U(rc)|", fabs(e), 1e-15);
  FF_CHECK_LE("RF eps 78.3: krf = 77.3 / 157.6", fabs(rf.krf - 77.3 / 157.6), 1e-15);

  double r[3] = {0.0, 0.0, rc - 1e-7}, mui[3] = {0.3, 0.1, 0.9}, muj[3] = {-0.4, 0.8, 0.2};
  double f[3], gi[3], gj[3];
  e = rl_dipole_dipole_sf(1.0, rc, r, mui, muj, f, gi, gj);
  FF_CHECK_LE("dipole SF: |U(rc - 1e-7)|", fabs(e), 1e-12);
  FF_CHECK_LE("dipole SF: |F(rc - 1e-7)|", sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]), 1e-6);
  FF_CHECK_LE("dipole SF: |dU/dmu_i (rc - 1e-7)|", sqrt(gi[0] * gi[0] + gi[1] * gi[1] + gi[2] * gi[2]),
              1e-12);
  e = rl_charge_dipole_sf(1.0, rc, r, 1.0, muj, f, gj);
  FF_CHECK_LE("charge-dipole SF: |U(rc - 1e-7)|", fabs(e), 1e-12);
  FF_CHECK_LE("charge-dipole SF: |F(rc - 1e-7)|", sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]),
              1e-6);
  /* dipole RF with eps_rf = inf: energy of a head-to-tail pair at rc is -2 + (-1) (mu = 1) */
  double z[3] = {0, 0, 1}, rz[3] = {0, 0, rc};
  e = rl_dipole_dipole_rf(1.0, 0.5, rz, z, z, f, gi, gj);
  FF_CHECK_LE("dipole RF eps inf: head-to-tail U(rc) = -2 - 1", fabs(e + 3.0), 1e-15);
}

/* One-component LJ fluid: dispersion corrections against the textbook closed forms. */
static void test_dispersion(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 3);
  ff_test_species a;
  ff_species_init(&a, "lj", RL_KIND_POINT, 1.0, 0, 0, 0, 1);
  ff_site(&a, 0, 0, 0, 0, 1.0, 1.0, 0.0);
  rl_system *sys = rl_system_alloc(RL_UNITS_LJ);
  int n = 100;
  assert_int_equal(rl_system_add_species(sys, &a.desc, n, NULL), RL_OK);
  for (int i = 0; i < n; i++) {
    double r[3] = {(i % 5) * 1.2, ((i / 5) % 5) * 1.2, (i / 25) * 1.2 + gsl_ran_flat(rng, 0, 0.1)};
    rl_system_set_position(sys, i, r);
  }
  rl_species_ff sff = ff_test_species_ff(&a);
  const double box[3] = {6.0, 6.0, 4.8};
  assert_int_equal(rl_system_set_box(sys, box), RL_OK);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = 2.3;
  p.dispersion_correction = 1;
  p.lj_truncation = RL_LJ_SHIFTED;
  rl_forcefield *ff = rl_forcefield_alloc(sys, &p, &sff, 1);
  assert_non_null(ff);
  ff_energy(ff, sys);
  rl_ff_energies e;
  rl_forcefield_energies(ff, &e);
  double V = 6.0 * 6.0 * 4.8, x3 = pow(1.0 / 2.3, 3.0), x9 = x3 * x3 * x3;
  double npair = n * (n - 1.0) / 2.0;
  double eref = npair / V * (16.0 / 3.0) * M_PI * (x9 / 3.0 - x3);
  double pref = npair / (V * V) * (32.0 / 3.0) * M_PI * (2.0 / 3.0 * x9 - x3);
  FF_CHECK_LE("dispersion: E_tail vs 8/3 pi N rho eps sigma^3 [x^9/3 - x^3]",
              fabs(e.dispersion - eref) / fabs(eref), 1e-13);
  FF_CHECK_LE("dispersion: P_tail vs 16/3 pi rho^2 eps sigma^3 [2/3 x^9 - x^3]",
              fabs(e.pressure_dispersion - pref) / fabs(pref), 1e-13);
  rl_forcefield_free(ff);
  /* switched: E_corr = int_rsw^rc r^2 u (1 - S) + tail; compare with composite Simpson */
  p.lj_truncation = RL_LJ_SWITCHED;
  p.r_switch = 1.9;
  ff = rl_forcefield_alloc(sys, &p, &sff, 1);
  assert_non_null(ff);
  ff_energy(ff, sys);
  rl_forcefield_energies(ff, &e);
  int m = 20000;
  double h = (2.3 - 1.9) / m, s = 0.0;
  for (int k = 0; k <= m; k++) {
    double r = 1.9 + k * h, x = (r - 1.9) / 0.4;
    double S = 1.0 + x * x * x * (-10.0 + x * (15.0 - 6.0 * x));
    double u = 4.0 * (pow(r, -12.0) - pow(r, -6.0));
    double w = (k == 0 || k == m) ? 1.0 : (k % 2 ? 4.0 : 2.0);
    s += w * r * r * u * (1.0 - S);
  }
  s *= h / 3.0;
  double eref2 = eref + 2.0 * M_PI / V * n * (n - 1.0) * s;
  FF_CHECK_LE("dispersion switched: E_corr incl. switch region vs Simpson",
              fabs(e.dispersion - eref2) / fabs(eref2), 1e-10);
  rl_forcefield_free(ff);
  rl_system_free(sys);
  gsl_rng_free(rng);
}

/* Molecular virial: tr W / (3V) = -dU/dV for affine scaling of the centres (rigid molecules). */
static double scaled_energy(rl_forcefield *ff, rl_system *sys, const double L0[3], double s)
{
  int n = rl_system_count(sys);
  double L[3] = {L0[0] * s, L0[1] * s, L0[2] * s};
  assert_int_equal(rl_system_set_box(sys, L), RL_OK); /* the force field follows */
  for (int i = 0; i < n; i++) {
    double r[3];
    rl_system_get_position(sys, i, r);
    for (int c = 0; c < 3; c++) r[c] *= s;
    rl_system_set_position(sys, i, r);
  }
  double e = ff_energy(ff, sys);
  for (int i = 0; i < n; i++) {
    double r[3];
    rl_system_get_position(sys, i, r);
    for (int c = 0; c < 3; c++) r[c] /= s;
    rl_system_set_position(sys, i, r);
  }
  assert_int_equal(rl_system_set_box(sys, L0), RL_OK);
  return e;
}

/* 60 waters, 20 point dipoles and 6 ions (every charge and dipole term) in a random cluster. */
static rl_system *mixed_system(ff_test_species sp[3], rl_species_ff sff[3], unsigned long seed)
{
  ff_water(&sp[0]);
  ff_stockmayer(&sp[1], 0.04);
  ff_ion(&sp[2], 0.6);
  rl_system *sys = rl_system_alloc(RL_UNITS_REAL);
  const int cnt[3] = {60, 20, 6};
  for (int k = 0; k < 3; k++) {
    assert_int_equal(rl_system_add_species(sys, &sp[k].desc, cnt[k], NULL), RL_OK);
    sff[k] = ff_test_species_ff(&sp[k]);
  }
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, seed);
  const double c[3] = {0.8, 0.8, 0.8};
  ff_place_cluster(sys, rng, c, 1.05, 0.26);
  gsl_rng_free(rng);
  return sys;
}

static void test_virial(void **state)
{
  (void)state;
  ff_test_species sp[3];
  rl_species_ff sff[3];
  rl_system *sys = mixed_system(sp, sff, 9);
  for (int sc = 0; sc < 2; sc++) {
    double L0[3] = {1.9, 2.0, 2.1};
    assert_int_equal(rl_system_set_box(sys, L0), RL_OK);
    rl_ff_params p;
    rl_ff_params_default(&p);
    p.cutoff = 0.8;
    p.scheme = (rl_cutoff_scheme)sc;
    p.lj_truncation = RL_LJ_SWITCHED;
    p.r_switch = 0.6;
    p.eps_rf = INFINITY;
    p.dipole_method = RL_DIPOLE_SF;
    p.dispersion_correction = 1;
    rl_forcefield *ff = rl_forcefield_alloc(sys, &p, sff, 3);
    assert_non_null(ff);
    ff_result res;
    ff_result_compute(&res, ff, sys);
    double V = L0[0] * L0[1] * L0[2];
    double pv = rl_forcefield_pressure(ff, &res.out, 0.0);
    double h = 1e-5;
    /* U(V s^3): dU/dV = dU/ds / (3 V) at s = 1; Richardson */
    double d1 = (scaled_energy(ff, sys, L0, 1 + h) - scaled_energy(ff, sys, L0, 1 - h)) / (2 * h);
    double d2 = (scaled_energy(ff, sys, L0, 1 + h / 2) - scaled_energy(ff, sys, L0, 1 - h / 2)) / h;
    double pfd = -((4 * d2 - d1) / 3) / (3 * V);
    char name[160];
    snprintf(name, sizeof name, "virial %s cutoff: tr W/(3V) vs -dU/dV (P = %.4g kJ/mol/nm^3)",
             sc ? "molecule" : "site", pv);
    FF_CHECK_LE(name, fabs(pv - pfd) / fabs(pfd), 1e-6);
    ff_result_free(&res);
    rl_forcefield_free(ff);
  }
  rl_system_free(sys);
}

/* The reaction field's conducting limit: every RF constant (charge-charge, charge-dipole,
 * dipole-dipole, the intramolecular term) is formed so that a large eps_rf tends to eps_rf = Inf
 * continuously and exactly.  Water, point dipoles and ions (every RF term, the tip4p and
 * stockmayer kernels and the general path), both cutoff schemes: energies, forces and torques at
 * eps_rf = 1e30, 1e300 and 1e308 equal those at Inf to round-off (1e308 overflowed 2 eps + 1 and
 * gave krf = 0, the eps = 1 energy), and at 1e3 and 1e6 they differ from them by an amount that
 * scales as 1/eps (E and F are linear in krf, and krf - krf(Inf) = -3/(2 (2 eps + 1) rc^3)). */
static void test_rf_conducting_limit(void **state)
{
  (void)state;
  ff_test_species sp[3];
  rl_species_ff sff[3];
  rl_system *sys = mixed_system(sp, sff, 21);
  const double eps[5] = {1e3, 1e6, 1e30, 1e300, 1e308};
  for (int sc = 0; sc < 2; sc++) {
    const double box[3] = {1.9, 2.0, 2.1};
    assert_int_equal(rl_system_set_box(sys, box), RL_OK);
    rl_ff_params p;
    rl_ff_params_default(&p);
    p.cutoff = 0.8;
    p.scheme = (rl_cutoff_scheme)sc;
    p.intramolecular_rf = 1;
    p.eps_rf = INFINITY;
    rl_forcefield *ff = rl_forcefield_alloc(sys, &p, sff, 3);
    assert_non_null(ff);
    ff_result ref;
    ff_result_compute(&ref, ff, sys);
    const double fn = ff_maxnorm((const double(*)[3])ref.f, ref.n);
    const double kn = ff_maxnorm((const double(*)[3])ref.k, ref.nrot);
    rl_forcefield_free(ff);
    double d[5];
    for (int k = 0; k < 5; k++) {
      p.eps_rf = eps[k];
      ff = rl_forcefield_alloc(sys, &p, sff, 3);
      assert_non_null(ff);
      ff_result res;
      ff_result_compute(&res, ff, sys);
      const double dE = fabs(res.out.energy - ref.out.energy) / fabs(ref.out.energy);
      const double dF = ff_maxdiff((const double(*)[3])res.f, (const double(*)[3])ref.f, res.n) / fn;
      const double dK = ff_maxdiff((const double(*)[3])res.k, (const double(*)[3])ref.k, res.nrot) / kn;
      d[k] = fmax(dE, fmax(dF, dK));
      printf("info  %s cutoff, eps_rf = %g: E = %.12g (Inf: %.12g); relative differences from "
             "Inf: E %.2e, F %.2e, torque %.2e\n", sc ? "molecule" : "site", eps[k],
             res.out.energy, ref.out.energy, dE, dF, dK);
      ff_result_free(&res);
      rl_forcefield_free(ff);
    }
    char name[120];
    for (int k = 2; k < 5; k++) {
      snprintf(name, sizeof name, "RF %s cutoff: eps_rf = %g vs Inf (E, F, torque, relative)",
               sc ? "molecule" : "site", eps[k]);
      FF_CHECK_LE(name, d[k], 1e-14);
    }
    /* 1/eps: the exact ratio of krf - krf(Inf) at 1e6 and 1e3 is (2e3 + 1)/(2e6 + 1) */
    const double want = (2e3 + 1.0) / (2e6 + 1.0);
    snprintf(name, sizeof name, "RF %s cutoff: difference from Inf at 1e6 / at 1e3, vs 1/eps",
             sc ? "molecule" : "site");
    FF_CHECK_LE(name, fabs(d[1] / d[0] / want - 1.0), 1e-6);
    FF_CHECK_TRUE("RF: the difference at eps_rf = 1e6 is seen (> 1e-9)", d[1] > 1e-9);
    ff_result_free(&ref);
  }
  rl_system_free(sys);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_multipoles_vs_charges),
      cmocka_unit_test(test_truncations),
      cmocka_unit_test(test_dispersion),
      cmocka_unit_test(test_virial),
      cmocka_unit_test(test_rf_conducting_limit),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
