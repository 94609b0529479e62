/* A few asymmetric bodies interacting through a smooth site-site potential in vacuum:
 * total linear and angular momentum conserved to round-off, total-energy fluctuation ~ h^2,
 * time reversibility of the coupled translation + rotation, and the isokinetic thermostat. */
#include "../cluster_util.h"

/* Mid-step totals: P = sum m v(t+h/2), L = sum m r(t) x v(t+h/2) + l(t+h/2).  Both are exact
 * invariants of the leapfrog for central pair forces: L(t+h/2) - L(t-h/2) = h sum (r x f + k)
 * because r(t) - r(t-h) = h v(t-h/2) is parallel to v(t-h/2). */
static void totals(cluster *c, const double (*rprev)[3], double P[3], double L[3])
{
  for (int k = 0; k < 3; k++) P[k] = L[k] = 0.0;
  for (int i = 0; i < NB; i++) {
    double v[3], l[3], m = rl_system_mass(c->sys, i);
    rl_system_get_velocity(c->sys, i, v);
    rl_system_get_angmom(c->sys, i, l);
    const double *r = rprev[i];
    P[0] += m * v[0]; P[1] += m * v[1]; P[2] += m * v[2];
    L[0] += m * (r[1] * v[2] - r[2] * v[1]) + l[0];
    L[1] += m * (r[2] * v[0] - r[0] * v[2]) + l[1];
    L[2] += m * (r[0] * v[1] - r[1] * v[0]) + l[2];
  }
}

static void momenta(void **state)
{
  (void)state;
  cluster c = make_cluster(0.01, RL_ROT_CUBIC, RL_THERMO_NONE, 0.0);
  double rprev[NB][3], P0[3], L0[3], P[3], L[3], dP = 0.0, dL = 0.0, scale;
  for (int s = 0; s < 20000; s++) {
    for (int i = 0; i < NB; i++) rl_system_get_position(c.sys, i, rprev[i]);
    assert_int_equal(rl_integrator_step(c.in, NULL), RL_OK);
    if (s == 0) { totals(&c, rprev, P0, L0); continue; }
    totals(&c, rprev, P, L);
    double d1[3] = {P[0] - P0[0], P[1] - P0[1], P[2] - P0[2]}, d2[3] = {L[0] - L0[0], L[1] - L0[1], L[2] - L0[2]};
    dP = fmax(dP, norm3d(d1));
    dL = fmax(dL, norm3d(d2));
  }
  /* scale for "round-off": momentum of one body, angular momentum of one body */
  scale = 18.0 * 0.05;
  CHECK_LE("cluster 2x10^4 steps: |P - P0| / (m v_typ)", dP / scale, 1e-12);
  CHECK_LE("cluster 2x10^4 steps: |L - L0| / |L0|", dL / norm3d(L0), 1e-12);
  free_cluster(&c);
}

/* Total-energy fluctuation (sd of E over a fixed time) at h, h/2, h/4, h/8: order 2 +- 0.2.
 * The window T = 4 is shorter than the time over which the chaotic cluster's trajectories at
 * different h separate (see reversibility), so every h samples the same stretch of phase space;
 * over T = 20 the ratios scatter (1.8-2.4) because the runs have decorrelated. */
static void energy_order(void **state)
{
  (void)state;
  const double T = 4.0, hs[4] = {0.04, 0.02, 0.01, 0.005};
  double sd[4];
  for (int k = 0; k < 4; k++) sd[k] = cluster_energy_sd(RL_ROT_CUBIC, hs[k], T);
  char name[96];
  for (int k = 0; k < 3; k++) {
    snprintf(name, sizeof name, "energy fluctuation order h=%g->%g (sd %.2e->%.2e)", hs[k],
             hs[k + 1], sd[k], sd[k + 1]);
    CHECK_NEAR(name, log2(sd[k] / sd[k + 1]), 2.0, 0.2);
  }
}

/* Coupled translation + rotation: N steps forward, reverse, N back.  The cluster is chaotic:
 * round-off is amplified about 1000x per doubling of the run (measured: 1e-15 at T = 2,
 * 6e-14 at 8, 3e-11 at 16, 4e-8 at 32), so N = 400 (T = 8) tests the scheme's reversibility
 * rather than the Lyapunov exponent. */
static void reversibility(void **state)
{
  (void)state;
  double worst_r, worst_A;
  cluster_reversal_error(RL_ROT_CUBIC, &worst_r, &worst_A);
  CHECK_LE("cluster reversibility: max |r_back - r_0|", worst_r, 1e-10);
  CHECK_LE("cluster reversibility: max |A_back - A_0|", worst_A, 1e-10);
}

/* Isokinetic thermostat: on-step T after scaling equals T0 (cluster_util.h). */
static void isokinetic(void **state)
{
  (void)state;
  CHECK_LE("isokinetic: on-step T after scaling = T0 (relative)",
           cluster_isokinetic_error(RL_ROT_CUBIC, 200), 1e-13);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(momenta), cmocka_unit_test(energy_order),
                                     cmocka_unit_test(reversibility), cmocka_unit_test(isokinetic)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
