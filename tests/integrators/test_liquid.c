/* The integrator with the real force field: liquids built from the catalogue, a lattice start,
 * Maxwell-Boltzmann velocities, isokinetic equilibration, then NVE from one shared state at
 * h, h/2, h/4 over the same stretch of time.  The total-energy fluctuation must fall as h^2
 * (order 2 +- 0.2) and the total momentum stay constant.  Truncations are chosen smooth (force
 * continuous at the cutoff: reaction field with eps_rf = infinity, shifted-force LJ, shifted-
 * force dipoles), so that cutoff crossings do not add an h-independent error. */
#include "../testutil.h"

#include <gsl/gsl_statistics_double.h>

typedef struct {
  const char *model;
  int n;
  double L, cutoff, T, h0, equil_h;
  long equil_steps, window_steps; /* NVE steps at h0 */
  rl_dipole_method dip;
} scene;

static rl_system *build(const scene *sc, rl_molecule *m, rl_forcefield **ff)
{
  const rl_model *md = rl_catalog_find(sc->model);
  assert_non_null(md);
  assert_int_equal(rl_model_build(md, NULL, 0, m), RL_OK);
  rl_system *sys = rl_system_alloc(md->units);
  rl_species_desc d;
  rl_molecule_species(m, &d);
  assert_int_equal(rl_system_add_species(sys, &d, sc->n, NULL), RL_OK);
  const double L[3] = {sc->L, sc->L, sc->L};
  assert_int_equal(rl_system_lattice(sys, L, RL_LATTICE_SC, 1, 17), RL_OK);
  assert_int_equal(rl_system_maxwell_boltzmann(sys, sc->T, 18), RL_OK);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = sc->cutoff;
  p.lj_truncation = RL_LJ_SHIFTED_FORCE;
  p.eps_rf = INFINITY;
  p.dipole_method = sc->dip;
  rl_species_ff sff = rl_molecule_ff(m);
  *ff = rl_forcefield_alloc(sys, &p, &sff, 1);
  if (!*ff) printf("forcefield: %s\n", rl_last_error());
  assert_non_null(*ff);
  return sys;
}

static void nve_order(const scene *sc)
{
  rl_molecule m;
  rl_forcefield *ff;
  rl_system *sys = build(sc, &m, &ff);
  /* isokinetic equilibration from the lattice */
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = sc->equil_h;
  p.thermostat = RL_THERMO_ISOKINETIC;
  p.T0 = sc->T;
  rl_integrator *in = rl_integrator_alloc(sys, &p, rl_forcefield_provider(ff));
  assert_non_null(in);
  assert_int_equal(rl_integrator_init(in), RL_OK);
  rl_step_info info;
  for (long s = 0; s < sc->equil_steps; s++) assert_int_equal(rl_integrator_step(in, &info), RL_OK);
  printf("info  %s: after equilibration U/N = %.4f, T = %.2f\n", sc->model, info.potential / sc->n, info.temperature);
  assert_int_equal(rl_integrator_finish(in), RL_OK);
  rl_integrator_free(in);

  double sd[3], Pdrift = 0.0, mean[3];
  for (int k = 0; k < 3; k++) {
    rl_system *c = rl_system_clone(sys);
    assert_non_null(c);
    rl_integrator_params q;
    rl_integrator_params_default(&q);
    q.h = sc->h0 / (1 << k);
    rl_integrator *nv = rl_integrator_alloc(c, &q, rl_forcefield_provider(ff));
    assert_non_null(nv);
    assert_int_equal(rl_integrator_init(nv), RL_OK);
    long n = sc->window_steps << k;
    double *E = malloc(sizeof(double) * (size_t)n), P0[3] = {0, 0, 0};
    for (long s = 0; s < n; s++) {
      assert_int_equal(rl_integrator_step(nv, &info), RL_OK);
      E[s] = info.total;
      double P[3] = {0, 0, 0};
      for (int i = 0; i < sc->n; i++) {
        double v[3];
        rl_system_get_velocity(c, i, v);
        for (int d = 0; d < 3; d++) P[d] += m.mass * v[d];
      }
      if (s == 0) memcpy(P0, P, sizeof P);
      double dd[3] = {P[0] - P0[0], P[1] - P0[1], P[2] - P0[2]};
      Pdrift = fmax(Pdrift, norm3d(dd) / sqrt(sc->n * m.mass * rl_system_kB(c) * sc->T));
    }
    sd[k] = gsl_stats_sd(E, 1, (size_t)n);
    mean[k] = gsl_stats_mean(E, 1, (size_t)n);
    printf("info  %s NVE h = %g: <E>/N = %.5f, sd(E)/N = %.3e, fallbacks %ld\n", sc->model, q.h,
           mean[k] / sc->n, sd[k] / sc->n, rl_integrator_fallbacks(nv));
    free(E);
    rl_integrator_free(nv);
    rl_system_free(c);
  }
  char name[96];
  for (int k = 0; k < 2; k++) {
    snprintf(name, sizeof name, "%s: energy fluctuation order h=%g->%g", sc->model, sc->h0 / (1 << k),
             sc->h0 / (2 << k));
    CHECK_NEAR(name, log2(sd[k] / sd[k + 1]), 2.0, 0.2);
  }
  snprintf(name, sizeof name, "%s: |P - P0| / sqrt(N m kT)", sc->model);
  CHECK_LE(name, Pdrift, 1e-12);
  rl_forcefield_free(ff);
  rl_system_free(sys);
}

static void tip4p(void **state)
{
  (void)state;
  /* 216 molecules at 1 g/cm^3: L^3 = 216 * 18.0154 / 602.214 nm^3 */
  scene sc = {"tip4p", 216, cbrt(216 * 18.0154 / 602.21408), 0.9, 298.0, 0.002, 0.0005, 600, 100, RL_DIPOLE_RF};
  nve_order(&sc);
}

static void stockmayer(void **state)
{
  (void)state;
  /* rho* = 0.8, T* = 1.35, mu*^2 = 3 (the catalogue default), 125 molecules */
  scene sc = {"stockmayer", 125, cbrt(125 / 0.8), 2.5, 1.35, 0.004, 0.001, 1000, 150, RL_DIPOLE_SF};
  nve_order(&sc);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(tip4p), cmocka_unit_test(stockmayer)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
