/* Force providers shared by the thermostat tests (test_thermostat.c, test_langevin_dot.c): free
 * bodies; a harmonic trap on the centres, U = k r^2/2 (ctx: &k); an orienting field on the body
 * axis b (rho, or the third row of A), U = -a b.z with torque a b x z (ctx: &a). */
#ifndef ROTLEAP_TEST_FIELDS_H
#define ROTLEAP_TEST_FIELDS_H
#include "../testutil.h"

static int no_forces(void *ctx, const rl_system *sys, rl_forces *out)
{
  (void)ctx; (void)sys; (void)out;
  return RL_OK;
}

static int harmonic_trap(void *ctx, const rl_system *sys, rl_forces *out)
{
  const double k = *(const double *)ctx;
  for (int i = 0; i < rl_system_count(sys); i++) {
    double r[3];
    rl_system_get_position(sys, i, r);
    for (int c = 0; c < 3; c++) out->f[i][c] = -k * r[c];
    out->energy += 0.5 * k * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  }
  return RL_OK;
}

static int axis_field(void *ctx, const rl_system *sys, rl_forces *out)
{
  const double a = *(const double *)ctx;
  for (int i = 0; i < rl_system_count(sys); i++) {
    double b[3];
    rl_system_get_axis(sys, i, b);
    out->k[i][0] = a * b[1]; /* a b x z */
    out->k[i][1] = -a * b[0];
    out->k[i][2] = 0.0;
    out->energy -= a * b[2];
  }
  return RL_OK;
}

#endif
