/* The small chaotic cluster shared by test_cluster and test_baselines: NB asymmetric,
 * water-like bodies interacting through a smooth site-site potential in vacuum. */
#ifndef ROTLEAP_TEST_CLUSTER_UTIL_H
#define ROTLEAP_TEST_CLUSTER_UTIL_H
#include "testutil.h"

#include <gsl/gsl_statistics_double.h>

/* u(r) = e1 exp(-r^2/a^2) - e2 exp(-r^2/b^2): a smooth soft core with an attractive well, so
 * the cluster stays bound and no cutoff breaks smoothness.  Units: reduced. */
static const double E1 = 4.0, A2 = 0.25, E2 = 1.0, B2 = 1.0;

#define NB 4
#define NS 3
/* a water-like asymmetric body: three sites, centre of mass at the origin */
static const double SITES[NS][3] = {{0.0, 0.0, -0.0656}, {0.4, 0.0, 0.5204}, {-0.4, 0.0, 0.5204}};

/* An initialised integrator for sys: step h, method m, thermostat th at T0, forces by f. */
static inline rl_integrator *start_integrator(rl_system *sys, double h, rl_rot_method m, rl_thermostat th,
                                              double T0, rl_force_fn f)
{
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = h;
  p.method = m;
  p.thermostat = th;
  p.T0 = T0;
  rl_integrator *in = rl_integrator_alloc(sys, &p, (rl_force_provider){f, NULL});
  assert_non_null(in);
  assert_int_equal(rl_integrator_init(in), RL_OK);
  return in;
}

static inline int smooth_forces(void *ctx, const rl_system *sys, rl_forces *out)
{
  (void)ctx;
  int ns = rl_system_nsites(sys);
  double pos[NB * NS][3], fs[NB * NS][3];
  memset(fs, 0, sizeof fs);
  rl_system_site_positions(sys, pos);
  double U = 0.0;
  for (int a = 0; a < ns; a++)
    for (int b = a + 1; b < ns; b++) {
      if (a / NS == b / NS) continue; /* rigid: no intramolecular pairs */
      double d[3] = {pos[a][0] - pos[b][0], pos[a][1] - pos[b][1], pos[a][2] - pos[b][2]};
      double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      double g1 = E1 * exp(-r2 / A2), g2 = E2 * exp(-r2 / B2);
      U += g1 - g2;
      double fr = 2.0 * g1 / A2 - 2.0 * g2 / B2; /* -du/dr / r */
      for (int c = 0; c < 3; c++) { fs[a][c] += fr * d[c]; fs[b][c] -= fr * d[c]; }
    }
  out->energy = U;
  rl_system_add_site_forces(sys, (const double (*)[3])fs, out);
  return RL_OK;
}

typedef struct {
  rl_system *sys;
  rl_integrator *in;
} cluster;

static inline cluster make_cluster(double h, rl_rot_method m, rl_thermostat th, double T0)
{
  cluster c;
  c.sys = rl_system_alloc(RL_UNITS_LJ);
  /* principal moments of the three sites with masses 16, 1, 1 would do; any asymmetric set is
   * fine for the dynamics test */
  rl_species_desc d = {.name = "w", .kind = RL_KIND_ASYMMETRIC, .mass = 18.0,
                       .inertia = {0.35, 0.62, 0.95}, .nsites = NS, .sites = &SITES[0][0]};
  assert_int_equal(rl_system_add_species(c.sys, &d, NB, NULL), RL_OK);
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, 21);
  const double pos[NB][3] = {{0, 0, 0}, {1.3, 0, 0}, {0.65, 1.1, 0}, {0.65, 0.37, 1.05}};
  double P[3] = {0, 0, 0};
  for (int i = 0; i < NB; i++) {
    double A[9], v[3], l[3];
    random_rotation(r, A);
    for (int k = 0; k < 3; k++) { v[k] = gsl_ran_gaussian(r, 0.05); l[k] = gsl_ran_gaussian(r, 0.3); }
    assert_int_equal(rl_system_set_position(c.sys, i, pos[i]), RL_OK);
    assert_int_equal(rl_system_set_orientation(c.sys, i, A), RL_OK);
    assert_int_equal(rl_system_set_velocity(c.sys, i, v), RL_OK);
    assert_int_equal(rl_system_set_angmom(c.sys, i, l), RL_OK);
    for (int k = 0; k < 3; k++) P[k] += v[k] / NB;
  }
  for (int i = 0; i < NB; i++) { /* zero total momentum */
    double v[3];
    rl_system_get_velocity(c.sys, i, v);
    for (int k = 0; k < 3; k++) v[k] -= P[k];
    rl_system_set_velocity(c.sys, i, v);
  }
  gsl_rng_free(r);
  c.in = start_integrator(c.sys, h, m, th, T0, smooth_forces);
  return c;
}

static inline void free_cluster(cluster *c)
{
  rl_integrator_free(c->in);
  rl_system_free(c->sys);
}

/* 400 steps at h = 0.02 forward, reverse, 400 back with rotation method m: the worst
 * |r_back - r_0| and |A_back - A_0| over the bodies. */
static inline void cluster_reversal_error(rl_rot_method m, double *worst_r, double *worst_A)
{
  cluster c = make_cluster(0.02, m, RL_THERMO_NONE, 0.0);
  double r0[NB][3], A0[NB][9];
  *worst_r = *worst_A = 0.0;
  for (int i = 0; i < NB; i++) {
    rl_system_get_position(c.sys, i, r0[i]);
    rl_system_get_orientation(c.sys, i, A0[i]);
  }
  for (int s = 0; s < 400; s++) assert_int_equal(rl_integrator_step(c.in, NULL), RL_OK);
  assert_int_equal(rl_integrator_reverse(c.in), RL_OK);
  for (int s = 0; s < 400; s++) assert_int_equal(rl_integrator_step(c.in, NULL), RL_OK);
  for (int i = 0; i < NB; i++) {
    double r[3], A[9];
    rl_system_get_position(c.sys, i, r);
    rl_system_get_orientation(c.sys, i, A);
    *worst_r = fmax(*worst_r, max_abs_diff(r, r0[i], 3));
    *worst_A = fmax(*worst_A, max_abs_diff(A, A0[i], 9));
  }
  free_cluster(&c);
}

/* Standard deviation of the on-step total energy over T at step h. */
static inline double cluster_energy_sd(rl_rot_method m, double h, double T)
{
  cluster c = make_cluster(h, m, RL_THERMO_NONE, 0.0);
  long n = lround(T / h);
  double *E = malloc(sizeof(double) * (size_t)n);
  for (long s = 0; s < n; s++) {
    rl_step_info info;
    assert_int_equal(rl_integrator_step(c.in, &info), RL_OK);
    E[s] = info.total;
  }
  double sd = gsl_stats_sd(E, 1, (size_t)n);
  free(E);
  free_cluster(&c);
  return sd;
}

/* Isokinetic thermostat: the on-step temperature built from v(t-h/2) and the modified
 * v'(t+h/2) (eqs. 17-18) and likewise for l equals T0 exactly (section III.B).  Returns the
 * worst relative |T - T0| over `steps` steps at h = 0.01 with rotation method m. */
static inline double cluster_isokinetic_error(rl_rot_method m, int steps)
{
  const double T0 = 0.05;
  cluster c = make_cluster(0.01, m, RL_THERMO_ISOKINETIC, T0);
  const rl_system *s = c.sys;
  double worst = 0.0;
  for (int step = 0; step < steps; step++) {
    double vold[NB][3], lold[NB][3], Aold[NB][9];
    for (int i = 0; i < NB; i++) {
      rl_system_get_velocity(s, i, vold[i]);
      rl_system_get_angmom(s, i, lold[i]);
      rl_system_get_orientation(s, i, Aold[i]);
    }
    assert_int_equal(rl_integrator_step(c.in, NULL), RL_OK);
    double ke = 0.0;
    for (int i = 0; i < NB; i++) {
      double v[3], l[3], J[3], m = rl_system_mass(s, i);
      rl_system_get_velocity(s, i, v);
      rl_system_get_angmom(s, i, l);
      rl_system_inertia(s, i, J);
      for (int k = 0; k < 3; k++) {
        double vt = 0.5 * (vold[i][k] + v[k]);
        ke += 0.5 * m * vt * vt;
      }
      double lt[3] = {0.5 * (lold[i][0] + l[0]), 0.5 * (lold[i][1] + l[1]), 0.5 * (lold[i][2] + l[2])};
      for (int a = 0; a < 3; a++) {
        const double *A = Aold[i];
        double Om = (A[3 * a] * lt[0] + A[3 * a + 1] * lt[1] + A[3 * a + 2] * lt[2]) / J[a];
        ke += 0.5 * J[a] * Om * Om;
      }
    }
    int g = rl_system_dof(s);
    assert_int_equal(g, 6 * NB - 3);
    double T = 2.0 * ke / (g * rl_system_kB(s));
    worst = fmax(worst, fabs(T - T0) / T0);
  }
  free_cluster(&c);
  return worst;
}

#endif
