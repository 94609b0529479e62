/* The run driver (run.h, issue 32 item 5): reporters are called at exactly their steps, in the
 * order they were registered, with the values of their moment (STEP: the on-step values at t_k and
 * the terms' energy components then; STATE: the state after the step); a stop flag ends the run
 * between steps; a failing reporter stops it with its message; the watch stops a blow-up; the last
 * state is reported once; a run in two calls is the run in one. */
#include "../testutil.h"

#include <rotleap/rotleap.h>

#define CHECK_TRUE(name, cond) CHECK_LE(name, (cond) ? 0.0 : 1.0, 0.0)

typedef struct {
  long calls, steps[64];
  char order[256];
  int tag;
  double first_U;          /* energy component at the first STEP report */
  double first_potential;
  long fail_at;            /* fail when reporting this step (-1: never) */
  volatile sig_atomic_t *stop;
  long stop_at;
} log_t;

static char order[512];

static int logger(void *ctx, const rl_run_report *r)
{
  log_t *l = ctx;
  if (l->calls < 64) l->steps[l->calls] = r->step;
  if (l->calls == 0 && r->info) {
    l->first_U = r->energies[0] + r->energies[1] + r->energies[2] + r->energies[3] + r->energies[4];
    l->first_potential = r->info->potential;
  }
  l->calls++;
  size_t n = strlen(order);
  if (n + 2 < sizeof order) { order[n] = (char)l->tag; order[n + 1] = '\0'; }
  if (l->stop && r->step == l->stop_at) *l->stop = 1;
  if (r->step == l->fail_at) return rl_error(RL_EINVAL, "the logger refuses step %ld", r->step);
  return RL_OK;
}

typedef struct {
  rl_molecule mol;
  rl_system *sys;
  rl_species_ff sff;
  rl_terms *terms;
  rl_integrator *in;
  rl_run *run;
} scene;

static void make(scene *s, long energy_every, double h)
{
  assert_int_equal(rl_model_build(rl_catalog_find("stockmayer"), NULL, 0, &s->mol), RL_OK);
  s->sys = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc d;
  rl_molecule_species(&s->mol, &d);
  assert_int_equal(rl_system_add_species(s->sys, &d, 64, NULL), RL_OK);
  const double L[3] = {4.31, 4.31, 4.31};
  assert_int_equal(rl_system_lattice(s->sys, L, RL_LATTICE_SC, 1, 3), RL_OK);
  assert_int_equal(rl_system_maxwell_boltzmann(s->sys, 1.35, 4), RL_OK);
  s->sff = rl_molecule_ff(&s->mol);
  rl_pair_params pp = {.species = &s->sff, .nspecies = 1};
  rl_ff_params_default(&pp.p);
  pp.p.cutoff = 2.0;
  pp.p.lj_truncation = RL_LJ_SHIFTED_FORCE;
  pp.p.dipole_method = RL_DIPOLE_SF;
  s->terms = rl_terms_alloc(s->sys);
  assert_int_equal(rl_terms_add(s->terms, &rl_term_pair, &pp, NULL), RL_OK);
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = h;
  p.energy_every = energy_every;
  s->in = rl_integrator_alloc(s->sys, &p, rl_terms_provider(s->terms));
  assert_int_equal(rl_integrator_init(s->in), RL_OK);
  rl_run_params rp = {.energy_every = energy_every, .h = h, .watch = {.T = 1.35, .window = 1.0, .drift_error = 5.0}};
  s->run = rl_run_alloc(s->sys, s->in, s->terms, &rp);
  assert_non_null(s->run);
}

static void unmake(scene *s)
{
  rl_run_free(s->run);
  rl_integrator_free(s->in);
  rl_terms_free(s->terms);
  rl_system_free(s->sys);
}

static void cadences(void **state)
{
  (void)state;
  scene s;
  make(&s, 2, 0.002);
  order[0] = '\0';
  log_t a = {.tag = 'a', .fail_at = -1}, b = {.tag = 'b', .fail_at = -1}, c = {.tag = 'c', .fail_at = -1};
  const rl_reporter ra = {"a", RL_REPORT_STEP, 4, logger, &a}, rb = {"b", RL_REPORT_STATE, 3, logger, &b},
                    rc = {"c", RL_REPORT_STEP, 2, logger, &c}, bad = {"bad", RL_REPORT_STEP, 3, logger, &c};
  CHECK_TRUE("a STEP reporter off the energy cadence is refused", rl_run_add_reporter(s.run, &bad) == RL_EINVAL);
  assert_int_equal(rl_run_add_reporter(s.run, &ra), RL_OK);
  assert_int_equal(rl_run_add_reporter(s.run, &rb), RL_OK);
  assert_int_equal(rl_run_add_reporter(s.run, &rc), RL_OK);
  long done = 0;
  assert_int_equal(rl_run_steps(s.run, 0, 12, NULL, &done), RL_OK);
  CHECK_TRUE("12 steps done", done == 12);
  CHECK_TRUE("STEP every 4: steps 0, 4, 8 (the values at t_k)", a.calls == 3 && a.steps[0] == 0 && a.steps[1] == 4 && a.steps[2] == 8);
  CHECK_TRUE("STATE every 3: after steps 2, 5, 8, 11 (reported as 3, 6, 9, 12)",
             b.calls == 4 && b.steps[0] == 3 && b.steps[1] == 6 && b.steps[2] == 9 && b.steps[3] == 12);
  CHECK_TRUE("STEP every 2: 0, 2, ..., 10", c.calls == 6 && c.steps[5] == 10);
  printf("info  order of the calls: %s\n", order);
  /* step 0: a, c; step 1: none; step 2: b (after it), c (at it); step 4: a, c; step 5: b; ... */
  CHECK_TRUE("in the order registered within a step: step 0 a c, step 2 b c, step 4 a c, step 5 b",
             !strncmp(order, "acbcacb", 7));
  CHECK_NEAR("a STEP report's energy components are those at t_k (their sum is the step's potential)", a.first_U,
             a.first_potential, 1e-12 * fabs(a.first_potential));
  assert_int_equal(rl_run_finish(s.run, 12), RL_OK);
  CHECK_TRUE("the last state is reported once, to the STEP reporters", a.calls == 4 && a.steps[3] == 12 && c.calls == 7 && b.calls == 4);
  unmake(&s);
}

static void stops(void **state)
{
  (void)state;
  scene s;
  make(&s, 1, 0.002);
  volatile sig_atomic_t stop = 0;
  log_t a = {.tag = 'a', .fail_at = -1, .stop = &stop, .stop_at = 5};
  const rl_reporter ra = {"a", RL_REPORT_STATE, 1, logger, &a};
  assert_int_equal(rl_run_add_reporter(s.run, &ra), RL_OK);
  long done = 0;
  assert_int_equal(rl_run_steps(s.run, 0, 100, &stop, &done), RL_OK);
  CHECK_TRUE("a stop flag raised after step 4 ends the run before step 5", done == 5 && rl_integrator_steps(s.in) == 5);
  log_t f = {.tag = 'f', .fail_at = 7};
  const rl_reporter rf = {"f", RL_REPORT_STEP, 1, logger, &f};
  assert_int_equal(rl_run_add_reporter(s.run, &rf), RL_OK);
  stop = 0;
  a.stop = NULL;
  const int st = rl_run_steps(s.run, 5, 100, &stop, &done);
  CHECK_TRUE("a failing reporter stops the run with its status and message",
             st == RL_EINVAL && done == 3 && strstr(rl_last_error(), "the logger refuses step 7") != NULL);
  unmake(&s);
}

static void blow_up_and_split(void **state)
{
  (void)state;
  scene s;
  make(&s, 1, 0.05); /* far too large */
  long done = 0;
  const int st = rl_run_steps(s.run, 0, 1000, NULL, &done);
  printf("info  %s\n", rl_last_error());
  CHECK_TRUE("the watch stops a blow-up, naming the step and the time step", st != RL_OK && done < 1000 &&
             strstr(rl_last_error(), "reduce the time step") != NULL);
  unmake(&s);
  /* one call of 40 steps = two of 20: the driver keeps nothing a continuation would lose */
  scene one, two;
  make(&one, 1, 0.002);
  make(&two, 1, 0.002);
  assert_int_equal(rl_run_steps(one.run, 0, 40, NULL, &done), RL_OK);
  assert_int_equal(rl_run_steps(two.run, 0, 20, NULL, &done), RL_OK);
  assert_int_equal(rl_run_steps(two.run, 20, 40, NULL, &done), RL_OK);
  double r1[3], r2[3];
  rl_system_get_position(one.sys, 17, r1);
  rl_system_get_position(two.sys, 17, r2);
  CHECK_TRUE("a run in two calls is bit for bit the run in one", !memcmp(r1, r2, sizeof r1) &&
             !memcmp(rl_run_watch(one.run), rl_run_watch(two.run), sizeof(rl_watch)));
  unmake(&one);
  unmake(&two);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(cadences), cmocka_unit_test(stops), cmocka_unit_test(blow_up_and_split)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
