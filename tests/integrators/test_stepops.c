/* Step operators (rotleap/stepops.h) added through the public interface, without touching the
 * leapfrog core: a toy operator that scales the velocities, hooked at each point of the step in
 * turn, must act exactly there (the state after one step and what the hook sees differ from one
 * point to the next); operators are carried together and in order; an operator that moves the
 * bodies at the end of the step gets the forces recomputed; the centre-of-mass flag changes the
 * count and the momentum treatment; bad additions are refused with a message. */
#include "expect_error.h"

#include <rotleap/stepops.h>

/* ------------------------------------------------------------------ a harmonic trap */

#define KSPRING 1.5
#define MASS 2.0
#define H 0.1

static int trap(void *ctx, const rl_system *sys, rl_forces *out)
{
  (void)ctx;
  for (int i = 0; i < rl_system_count(sys); i++) {
    double r[3];
    rl_system_get_position(sys, i, r);
    for (int c = 0; c < 3; c++) out->f[i][c] = -KSPRING * r[c];
    out->energy += 0.5 * KSPRING * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  }
  return RL_OK;
}

static const double R0[3] = {1.0, 0.5, -0.2}, V0[3] = {0.3, -0.1, 0.2};

/* One point particle at R0 with on-step velocity V0; nothing removed from its dof. */
static rl_system *one_particle(void)
{
  rl_system *s = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc d = {.name = "p", .kind = RL_KIND_POINT, .mass = MASS};
  assert_int_equal(rl_system_add_species(s, &d, 1, NULL), RL_OK);
  assert_int_equal(rl_system_set_position(s, 0, R0), RL_OK);
  assert_int_equal(rl_system_set_velocity(s, 0, V0), RL_OK);
  rl_system_set_removed_dof(s, 0);
  return s;
}

/* -------------------------------------------------------------------- the toy operator */

typedef struct {
  double scale; /* v <- scale v */
} toy_params;

typedef struct {
  int calls;
  double r[3], f[3]; /* body 0's position and force as the hook saw them */
  double K[2];       /* c->K as the hook saw it */
  long step;
} toy_state;

static int toy_check(const void *par, const rl_system *sys, const rl_integrator_params *p)
{
  (void)sys; (void)p;
  const toy_params *tp = par;
  if (!(tp->scale >= 0.0)) return rl_error(RL_EINVAL, "toy operator: scale %g must be >= 0", tp->scale);
  return RL_OK;
}

static int toy_alloc(rl_stepop *op)
{
  op->state = calloc(1, sizeof(toy_state));
  return op->state ? RL_OK : rl_error(RL_ENOMEM, "toy operator: out of memory");
}

static void toy_free(rl_stepop *op) { free(op->state); }

/* Record what is seen, then v <- s v for every body, accounting (1 - s^2) of the kinetic energy. */
static int toy_scale(rl_stepop *op, rl_stepop_ctx *c)
{
  toy_state *st = op->state;
  const double s = ((const toy_params *)op->par)->scale;
  st->calls++;
  st->step = c->step;
  rl_system_get_position(c->sys, 0, st->r);
  memcpy(st->f, c->forces->f[0], sizeof st->f);
  memcpy(st->K, c->K, sizeof st->K);
  double K[2];
  rl_stepop_kinetic(c, K);
  double (*v)[3] = rl_system_v(c->sys);
  for (int i = 0; i < rl_system_count(c->sys); i++)
    for (int k = 0; k < 3; k++) v[i][k] *= s;
  op->work += (1.0 - s * s) * K[0];
  return RL_OK;
}

static const rl_stepop_param toy_doc[] = {{"scale", "", "v <- scale v"}, {NULL, NULL, NULL}};

#define TOY(pt, fl)                                                                              \
  {.name = "toy", .label = "toy operator", .reference = "this test", .params = toy_doc,         \
   .params_size = sizeof(toy_params), .flags = (fl), .check = toy_check, .alloc = toy_alloc,    \
   .free = toy_free, .hook = {[pt] = toy_scale}}
/* One descriptor per point (a descriptor's hooks are fixed). */
static const rl_stepop_type toy_at[RL_STEP_NPOINTS] = {
    TOY(RL_STEP_BEFORE_KICK, 0), TOY(RL_STEP_AFTER_KICK, 0), TOY(RL_STEP_MID_DRIFT, 0),
    TOY(RL_STEP_AFTER_DRIFT, 0), TOY(RL_STEP_END, 0)};
static const rl_stepop_type toy_thermal = TOY(RL_STEP_END, RL_STEPOP_THERMAL_COM);

/* ------------------------------------------------------------------------------ tests */

/* What one leapfrog step from R0, V0 in the trap gives with v <- s v at point pt: the new
 * position, the stored mid-step velocity, and what the hook sees (position, force, c->K). */
typedef struct {
  double r1[3], vh[3], rseen[3], fseen[3], Kseen;
} expect;

static expect expected(int pt, double s)
{
  expect e;
  for (int c = 0; c < 3; c++) {
    const double f0 = -KSPRING * R0[c], vm = V0[c] - 0.5 * H * f0 / MASS; /* init's stagger */
    const double vk = vm + H * f0 / MASS;                                  /* the plain kick  */
    e.fseen[c] = f0;
    switch (pt) {
    case RL_STEP_BEFORE_KICK:
      e.vh[c] = s * vm + H * f0 / MASS;
      e.r1[c] = R0[c] + H * e.vh[c];
      e.rseen[c] = R0[c];
      break;
    case RL_STEP_AFTER_KICK:
      e.vh[c] = s * vk;
      e.r1[c] = R0[c] + H * e.vh[c];
      e.rseen[c] = R0[c];
      break;
    case RL_STEP_MID_DRIFT:
      e.vh[c] = s * vk;
      e.rseen[c] = R0[c] + 0.5 * H * vk;
      e.r1[c] = e.rseen[c] + 0.5 * H * e.vh[c];
      break;
    default: /* after the drift, end */
      e.vh[c] = s * vk;
      e.r1[c] = R0[c] + H * vk;
      e.rseen[c] = e.r1[c];
      if (pt == RL_STEP_END) e.fseen[c] = -KSPRING * e.r1[c];
    }
  }
  double kk = 0.0;
  for (int c = 0; c < 3; c++) {
    const double f0 = -KSPRING * R0[c], vm = V0[c] - 0.5 * H * f0 / MASS;
    kk += pt == RL_STEP_BEFORE_KICK ? V0[c] * V0[c] : (vm + H * f0 / MASS) * (vm + H * f0 / MASS);
  }
  /* c->K: on-step before the kick, the kick's after it, NAN elsewhere */
  e.Kseen = pt <= RL_STEP_AFTER_KICK ? 0.5 * MASS * kk : NAN;
  return e;
}

static double dist3(const double a[3], const double b[3])
{
  return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

static void toy_at_each_point(void **state)
{
  (void)state;
  const double s = 0.5;
  for (int pt = 0; pt < RL_STEP_NPOINTS; pt++) {
    rl_system *sys = one_particle();
    rl_integrator_params p;
    rl_integrator_params_default(&p);
    p.h = H;
    rl_integrator *in = rl_integrator_alloc(sys, &p, (rl_force_provider){trap, NULL});
    assert_non_null(in);
    const toy_params tp = {s};
    assert_int_equal(rl_integrator_add_op(in, &toy_at[pt], &tp), RL_OK);
    assert_int_equal(rl_integrator_nops(in), 1);
    assert_int_equal(rl_integrator_init(in), RL_OK);
    rl_step_info info;
    assert_int_equal(rl_integrator_step(in, &info), RL_OK);
    double r1[3], vh[3];
    rl_system_get_position(sys, 0, r1);
    rl_integrator_mid_velocity(in, 0, vh);
    const rl_stepop *op = rl_integrator_op(in, 0);
    const toy_state *ts = op->state;
    const expect e = expected(pt, s);
    char name[96];
    snprintf(name, sizeof name, "%s: r(t+h), v(t+h/2) as at this point", rl_step_point_name(pt));
    CHECK_LE(name, fmax(dist3(r1, e.r1), dist3(vh, e.vh)), 1e-14);
    snprintf(name, sizeof name, "%s: the hook sees r and f of this point", rl_step_point_name(pt));
    CHECK_LE(name, fmax(dist3(ts->r, e.rseen), dist3(ts->f, e.fseen)), 1e-14);
    assert_int_equal(ts->calls, 1);
    assert_int_equal(ts->step, 0);
    if (pt <= RL_STEP_AFTER_KICK) {
      snprintf(name, sizeof name, "%s: c->K, on-step or of the kick", rl_step_point_name(pt));
      CHECK_LE(name, fabs(ts->K[0] - e.Kseen), 1e-14);
    } else {
      assert_true(isnan(ts->K[0]) && isnan(ts->K[1]));
    }
    /* and not as at any other point: the points give different states or sightings */
    for (int q = 0; q < RL_STEP_NPOINTS; q++) {
      if (q == pt) continue;
      const expect o = expected(q, s);
      const double d = fmax(fmax(dist3(r1, o.r1), dist3(vh, o.vh)), fmax(dist3(ts->r, o.rseen), dist3(ts->f, o.fseen)));
      snprintf(name, sizeof name, "%s: unlike %s", rl_step_point_name(pt), rl_step_point_name(q));
      printf("check %-58s %.3e >= 1e-3 %s\n", name, d, d >= 1e-3 ? "ok" : "FAIL");
      assert_true(d >= 1e-3);
    }
    /* the account: (1 - s^2) of the kinetic energy the hook scaled, in the conserved quantity */
    double K = 0.0;
    for (int c = 0; c < 3; c++) K += 0.5 * MASS * (e.vh[c] / s) * (e.vh[c] / s);
    if (pt == RL_STEP_BEFORE_KICK) {
      K = 0.0;
      for (int c = 0; c < 3; c++) {
        const double vm = V0[c] + 0.5 * H * KSPRING * R0[c] / MASS;
        K += 0.5 * MASS * vm * vm;
      }
    }
    CHECK_LE("the operator's account is the integrator's work", fabs(rl_integrator_thermostat_work(in) - (1.0 - s * s) * K), 1e-15);
    rl_step_info next;
    assert_int_equal(rl_integrator_observe(in, &next), RL_OK);
    CHECK_LE("conserved = total + the operator's account", fabs(next.conserved - (next.total + op->work)), 0.0);
    rl_integrator_free(in);
    rl_system_free(sys);
  }
}

/* An identity operator after the kick takes the drift out of the kick's loop: the trajectory
 * must not change by a bit.  An operator after the Bussi thermostat acts after it and sees the
 * rescaled kinetic energy; the integrator's work is the sum of the two accounts. */
static void operators_together(void **state)
{
  (void)state;
  rl_system *a = one_particle(), *b = one_particle();
  const double r2[3] = {-0.4, 0.9, 0.1}, v2[3] = {-0.2, 0.4, 0.0};
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = H;
  rl_integrator *ia = rl_integrator_alloc(a, &p, (rl_force_provider){trap, NULL});
  rl_integrator *ib = rl_integrator_alloc(b, &p, (rl_force_provider){trap, NULL});
  const toy_params one = {1.0};
  assert_int_equal(rl_integrator_add_op(ib, &toy_at[RL_STEP_AFTER_KICK], &one), RL_OK);
  assert_int_equal(rl_integrator_init(ia), RL_OK);
  assert_int_equal(rl_integrator_init(ib), RL_OK);
  for (int k = 0; k < 100; k++) {
    assert_int_equal(rl_integrator_step(ia, NULL), RL_OK);
    assert_int_equal(rl_integrator_step(ib, NULL), RL_OK);
  }
  double ra[3], rb[3];
  rl_system_get_position(a, 0, ra);
  rl_system_get_position(b, 0, rb);
  CHECK_LE("identity operator after the kick: same r after 100 steps", dist3(ra, rb), 0.0);
  rl_integrator_free(ia);
  rl_integrator_free(ib);
  rl_system_free(a);
  rl_system_free(b);

  /* Bussi (from the parameters, first) and the toy after it, on two particles */
  rl_system *s = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc d = {.name = "p", .kind = RL_KIND_POINT, .mass = MASS};
  assert_int_equal(rl_system_add_species(s, &d, 2, NULL), RL_OK);
  rl_system_set_position(s, 0, R0);
  rl_system_set_velocity(s, 0, V0);
  rl_system_set_position(s, 1, r2);
  rl_system_set_velocity(s, 1, v2);
  rl_system_set_removed_dof(s, 0);
  p.thermostat = RL_THERMO_BUSSI;
  p.T0 = 1.0;
  p.tau = 0.5;
  p.seed = 7;
  rl_integrator *in = rl_integrator_alloc(s, &p, (rl_force_provider){trap, NULL});
  const toy_params half = {0.5};
  assert_int_equal(rl_integrator_add_op(in, &toy_at[RL_STEP_AFTER_KICK], &half), RL_OK);
  assert_int_equal(rl_integrator_nops(in), 2);
  assert_ptr_equal(rl_integrator_op(in, 0)->type, &rl_stepop_bussi);
  assert_null(rl_integrator_op(in, 2));
  assert_int_equal(rl_integrator_init(in), RL_OK);
  rl_step_info info;
  assert_int_equal(rl_integrator_step(in, &info), RL_OK);
  const rl_stepop *bussi = rl_integrator_op(in, 0), *toy = rl_integrator_op(in, 1);
  const toy_state *ts = toy->state;
  /* the toy saw K after Bussi's alpha^2: Kmid alpha^2 = (the kinetic energy now) / s^2 */
  double v[3], Know = 0.0;
  for (int i = 0; i < 2; i++) {
    rl_integrator_mid_velocity(in, i, v);
    Know += 0.5 * MASS * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  CHECK_LE("second operator sees the first's rescaled K", fabs(ts->K[0] - Know / 0.25) / Know, 1e-14);
  assert_true(info.beta != 1.0); /* Bussi reported its alpha */
  CHECK_LE("work = sum of the accounts", fabs(rl_integrator_thermostat_work(in) - (bussi->work + toy->work)), 0.0);
  assert_true(rl_integrator_rng_size(in) > 0); /* Bussi's stream, the first with one */
  rl_integrator_set_thermostat_work(in, 2.5);
  CHECK_LE("set: all in the first operator's account", fabs(bussi->work - 2.5) + fabs(toy->work), 0.0);
  rl_integrator_free(in);
  rl_system_free(s);
}

/* An operator at the end of the step that moves the bodies (as a Monte Carlo barostat will) gets
 * the forces of the new configuration from rl_stepop_forces. */
static int shift_and_recompute(rl_stepop *op, rl_stepop_ctx *c)
{
  (void)op;
  double (*r)[3] = rl_system_r(c->sys);
  r[0][0] += 0.25;
  return rl_stepop_forces(c, 1);
}

static void end_of_step_moves(void **state)
{
  (void)state;
  static const rl_stepop_type shifter = {.name = "shift", .label = "shift operator",
                                         .hook = {[RL_STEP_END] = shift_and_recompute}};
  rl_system *sys = one_particle();
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = H;
  rl_integrator *in = rl_integrator_alloc(sys, &p, (rl_force_provider){trap, NULL});
  assert_int_equal(rl_integrator_add_op(in, &shifter, NULL), RL_OK);
  assert_int_equal(rl_integrator_init(in), RL_OK);
  assert_int_equal(rl_integrator_step(in, NULL), RL_OK);
  double r[3];
  rl_system_get_position(sys, 0, r);
  const rl_forces *F = rl_integrator_forces(in);
  CHECK_LE("forces recomputed for the moved body", fabs(F->f[0][0] + KSPRING * r[0]), 0.0);
  CHECK_LE("energy recomputed for the moved body",
           fabs(F->energy - 0.5 * KSPRING * (r[0] * r[0] + r[1] * r[1] + r[2] * r[2])), 1e-15);
  rl_integrator_free(in);
  rl_system_free(sys);
}

/* RL_STEPOP_THERMAL_COM: all 3N translational dof count and init keeps the total momentum. */
static void centre_of_mass_flag(void **state)
{
  (void)state;
  for (int thermal = 0; thermal < 2; thermal++) {
    rl_system *s = rl_system_alloc(RL_UNITS_LJ);
    rl_species_desc d = {.name = "p", .kind = RL_KIND_POINT, .mass = MASS};
    assert_int_equal(rl_system_add_species(s, &d, 2, NULL), RL_OK);
    const double v[3] = {1.0, 0.0, 0.0}, r1[3] = {1.0, 0.0, 0.0};
    rl_system_set_velocity(s, 0, v);
    rl_system_set_velocity(s, 1, v);
    rl_system_set_position(s, 1, r1); /* removed_dof 3: the total momentum is not a dof */
    rl_integrator_params p;
    rl_integrator_params_default(&p);
    p.h = H;
    rl_integrator *in = rl_integrator_alloc(s, &p, (rl_force_provider){trap, NULL});
    const toy_params one = {1.0};
    assert_int_equal(rl_integrator_add_op(in, thermal ? &toy_thermal : &toy_at[RL_STEP_END], &one), RL_OK);
    int gt;
    rl_integrator_dof(in, &gt, NULL);
    assert_int_equal(gt, thermal ? 6 : 3);
    assert_int_equal(rl_integrator_init(in), RL_OK);
    assert_int_equal(rl_integrator_finish(in), RL_OK);
    double P = 0.0, w[3];
    for (int i = 0; i < 2; i++) {
      rl_system_get_velocity(s, i, w);
      P += MASS * w[0];
    }
    printf("check %-58s %g\n", thermal ? "THERMAL_COM: P kept" : "no THERMAL_COM: P removed", P);
    assert_true(thermal ? fabs(P - 2.0 * MASS) < 1e-12 : fabs(P) < 1e-12);
    rl_integrator_free(in);
    rl_system_free(s);
  }
}

static void refused(void **state)
{
  (void)state;
  rl_system *s = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc d = {.name = "top", .kind = RL_KIND_ASYMMETRIC, .mass = 1.0, .inertia = {0.6, 1.2, 1.7}};
  assert_int_equal(rl_system_add_species(s, &d, 2, NULL), RL_OK);
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = 0.01;
  rl_integrator *in = rl_integrator_alloc(s, &p, (rl_force_provider){trap, NULL});
  const toy_params bad = {-1.0}, ok = {1.0};
  EXPECT_ERROR(rl_integrator_add_op(in, &toy_at[RL_STEP_END], &bad), RL_EINVAL, "scale -1 must be >= 0");
  EXPECT_ERROR(rl_integrator_add_op(in, &toy_at[RL_STEP_END], NULL), RL_EINVAL, "toy operator needs parameters");
  assert_int_equal(rl_integrator_nops(in), 0);
  for (int k = 0; k < RL_STEPOP_MAX; k++) assert_int_equal(rl_integrator_add_op(in, &toy_at[RL_STEP_END], &ok), RL_OK);
  EXPECT_ERROR(rl_integrator_add_op(in, &toy_at[RL_STEP_END], &ok), RL_EINVAL, "the most it can");
  rl_integrator_free(in);

  /* a second kick scaler, and an operator added after init */
  p.thermostat = RL_THERMO_ISOKINETIC;
  p.T0 = 1.0;
  in = rl_integrator_alloc(s, &p, (rl_force_provider){trap, NULL});
  const rl_thermostat_params tp = {.T0 = 1.0};
  EXPECT_ERROR(rl_integrator_add_op(in, &rl_stepop_isokinetic, &tp), RL_EINVAL, "only one may");
  assert_int_equal(rl_integrator_init(in), RL_OK);
  EXPECT_ERROR(rl_integrator_add_op(in, &toy_at[RL_STEP_END], &ok), RL_ESTATE, "before rl_integrator_init");
  assert_int_equal(rl_integrator_finish(in), RL_OK);
  assert_int_equal(rl_integrator_add_op(in, &toy_at[RL_STEP_END], &ok), RL_OK);
  rl_integrator_free(in);

  /* the middle of the drift under a baseline, which rotates once over h */
  p.thermostat = RL_THERMO_NONE;
  p.method = RL_ROT_NOSQUISH;
  in = rl_integrator_alloc(s, &p, (rl_force_provider){trap, NULL});
  EXPECT_ERROR(rl_integrator_add_op(in, &toy_at[RL_STEP_MID_DRIFT], &ok), RL_EINVAL,
               "the toy operator splits the rotation into two half steps, which the baseline no-squish");
  rl_integrator_free(in);
  rl_system_free(s);
}

/* The built-in descriptors: look-up, the thermostat each rl_thermostat adds, their documentation. */
static void builtins(void **state)
{
  (void)state;
  const rl_thermostat th[3] = {RL_THERMO_ISOKINETIC, RL_THERMO_BUSSI, RL_THERMO_LANGEVIN};
  const char *names[3] = {"isokinetic", "bussi", "langevin"};
  const rl_step_point where[3] = {RL_STEP_BEFORE_KICK, RL_STEP_AFTER_KICK, RL_STEP_MID_DRIFT};
  for (int k = 0; k < 3; k++) {
    const rl_stepop_type *T = rl_stepop_find(names[k]);
    assert_non_null(T);
    assert_ptr_equal(T, rl_stepop_for_thermostat(th[k]));
    assert_non_null(T->hook[where[k]]);
    assert_true(T->reference && T->reference[0] && T->label && T->params && !strcmp(T->params[0].name, "T0"));
    printf("check %-12s %-22s at %-11s %s\n", T->name, T->label, rl_step_point_name(where[k]), T->reference);
  }
  assert_null(rl_stepop_find("nose-hoover"));
  assert_null(rl_stepop_for_thermostat(RL_THERMO_NONE));
  assert_null(rl_step_point_name(RL_STEP_NPOINTS));
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(toy_at_each_point), cmocka_unit_test(operators_together),
                                     cmocka_unit_test(end_of_step_moves), cmocka_unit_test(centre_of_mass_flag),
                                     cmocka_unit_test(refused), cmocka_unit_test(builtins)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
