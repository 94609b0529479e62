/* Force terms (terms.h, issue 32 item 2): the interactions as a sum of typed terms.  The pair term
 * through the sum gives what the force field gives alone, bit for bit; a term written here (a
 * harmonic tether of the centres, not known to the library) adds to it without touching the
 * integrator or the pair term, with its energy reported by name; a change of the system's cell
 * reaches every term before the next computation; types are found by name. */
#include "../testutil.h"

#include <rotleap/rotleap.h>

#define CHECK_TRUE(name, cond) CHECK_LE(name, (cond) ? 0.0 : 1.0, 0.0)

/* A toy term: U = k/2 sum |r_i - r0_i|^2 on the centres (no torques), energy "tether". */
typedef struct { double k; } tether_params;
typedef struct { double k; int n; double (*r0)[3]; int box_calls; } tether;

static void *tether_alloc(const rl_system *sys, const void *params)
{
  tether *t = calloc(1, sizeof *t);
  t->k = ((const tether_params *)params)->k;
  t->n = rl_system_count(sys);
  t->r0 = calloc((size_t)t->n, sizeof *t->r0);
  for (int i = 0; i < t->n; i++) rl_system_get_position(sys, i, t->r0[i]);
  return t;
}

static int tether_compute(void *state, const rl_system *sys, rl_forces *out, double *energies)
{
  tether *t = state;
  double U = 0.0;
  for (int i = 0; i < t->n; i++) {
    double r[3];
    rl_system_get_position(sys, i, r);
    for (int c = 0; c < 3; c++) {
      const double x = r[c] - t->r0[i][c];
      out->f[i][c] += -t->k * x;
      U += 0.5 * t->k * x * x;
    }
  }
  if (!out->forces_only) out->energy += U;
  energies[0] = out->forces_only ? NAN : U;
  return RL_OK;
}

static int tether_box(void *state, const rl_system *sys)
{
  (void)sys;
  ((tether *)state)->box_calls++;
  return RL_OK;
}

static void tether_free(void *state)
{
  tether *t = state;
  free(t->r0);
  free(t);
}

static const rl_term_type tether_type = {"tether", "harmonic tether of the centres (a test term)", "none", 1, {"tether"},
                                         tether_alloc, tether_compute, tether_box, tether_free};

/* 64 TIP4P molecules on a lattice, and the pair term's parameters for them. */
typedef struct {
  rl_molecule mol;
  rl_system *sys;
  rl_species_ff sff;
  rl_pair_params pp;
} scene;

static void make_scene(scene *s)
{
  assert_int_equal(rl_model_build(rl_catalog_find("tip4p"), NULL, 0, &s->mol), RL_OK);
  s->sys = rl_system_alloc(RL_UNITS_REAL);
  rl_species_desc d;
  rl_molecule_species(&s->mol, &d);
  assert_int_equal(rl_system_add_species(s->sys, &d, 64, NULL), RL_OK);
  const double L[3] = {1.3, 1.3, 1.3};
  assert_int_equal(rl_system_lattice(s->sys, L, RL_LATTICE_SC, 1, 5), RL_OK);
  s->sff = rl_molecule_ff(&s->mol);
  rl_ff_params_default(&s->pp.p);
  s->pp.p.cutoff = 0.6;
  s->pp.species = &s->sff;
  s->pp.nspecies = 1;
}

static void forces_alloc(rl_forces *F, const rl_system *sys)
{
  const int n = rl_system_count(sys), nr = rl_system_nrot(sys);
  *F = (rl_forces){calloc((size_t)n, sizeof(double[3])), calloc((size_t)nr, sizeof(double[3])), 0.0, {0}, 0};
}

static void pair_through_the_sum(void **state)
{
  (void)state;
  scene s;
  make_scene(&s);
  CHECK_TRUE("the pair term is found by name", rl_term_type_find("pair") == &rl_term_pair);
  CHECK_TRUE("an unknown term is refused, naming the known ones",
             rl_term_type_find("ewald-sphere") == NULL && strstr(rl_last_error(), "known: pair") != NULL);
  rl_terms *t = rl_terms_alloc(s.sys);
  assert_int_equal(rl_terms_add(t, &rl_term_pair, &s.pp, NULL), RL_OK);
  rl_forcefield *ff = rl_forcefield_alloc(s.sys, &s.pp.p, &s.sff, 1);
  rl_forces A, B;
  forces_alloc(&A, s.sys);
  forces_alloc(&B, s.sys);
  assert_int_equal(rl_terms_compute(t, s.sys, &A), RL_OK);
  assert_int_equal(rl_forcefield_compute(ff, s.sys, &B), RL_OK);
  const int n = rl_system_count(s.sys);
  CHECK_TRUE("the pair term through the sum: energy, virial, forces and torques bit for bit the force field's",
             A.energy == B.energy && !memcmp(A.virial, B.virial, sizeof A.virial) &&
                 !memcmp(A.f, B.f, sizeof(double[3]) * (size_t)n) && !memcmp(A.k, B.k, sizeof(double[3]) * (size_t)n));
  rl_ff_energies e;
  rl_forcefield_energies(ff, &e);
  CHECK_TRUE("its components by name: lj, coulomb, dipolar, quadrupolar, dispersion",
             rl_terms_nenergies(t) == 5 && !strcmp(rl_terms_energy_name(t, 0), "lj") && rl_terms_energy(t, 0) == e.lj &&
                 !strcmp(rl_terms_energy_name(t, 1), "coulomb") && rl_terms_energy(t, 1) == e.coulomb &&
                 !strcmp(rl_terms_energy_name(t, 4), "dispersion"));
  free(A.f); free(A.k); free(B.f); free(B.k);
  rl_forcefield_free(ff);
  rl_terms_free(t);
  rl_system_free(s.sys);
}

static void a_term_of_ones_own(void **state)
{
  (void)state;
  scene s;
  make_scene(&s);
  rl_terms *pair = rl_terms_alloc(s.sys), *both = rl_terms_alloc(s.sys);
  const tether_params tp = {100.0};
  assert_int_equal(rl_terms_add(pair, &rl_term_pair, &s.pp, NULL), RL_OK);
  assert_int_equal(rl_terms_add(both, &rl_term_pair, &s.pp, NULL), RL_OK);
  int idx = -1;
  assert_int_equal(rl_terms_add(both, &tether_type, &tp, &idx), RL_OK);
  /* move the centres off their tether points */
  const int n = rl_system_count(s.sys);
  for (int i = 0; i < n; i++) {
    double r[3];
    rl_system_get_position(s.sys, i, r);
    r[0] += 0.01 * (i % 3);
    rl_system_set_position(s.sys, i, r);
  }
  rl_forces A, B;
  forces_alloc(&A, s.sys);
  forces_alloc(&B, s.sys);
  assert_int_equal(rl_terms_compute(pair, s.sys, &A), RL_OK);
  assert_int_equal(rl_terms_compute(both, s.sys, &B), RL_OK);
  double want = 0.0, worst = 0.0;
  for (int i = 0; i < n; i++) want += 0.5 * 100.0 * (0.01 * (i % 3)) * (0.01 * (i % 3));
  for (int i = 0; i < n; i++) worst = fmax(worst, fabs(B.f[i][0] - A.f[i][0] + 100.0 * 0.01 * (i % 3)));
  CHECK_TRUE("a term of one's own is the sixth energy component, named 'tether', of the second term",
             rl_terms_nenergies(both) == 6 && !strcmp(rl_terms_energy_name(both, 5), "tether") &&
                 rl_terms_energy_term(both, 5) == idx && idx == 1);
  CHECK_NEAR("its energy (k/2 sum dx^2)", rl_terms_energy(both, 5), want, 1e-12 * want);
  CHECK_NEAR("the sum's energy is the pair term's plus the tether's", B.energy, A.energy + want, 1e-9 * fabs(A.energy));
  CHECK_LE("the sum's forces are the pair term's plus -k dx", worst, 1e-9);
  /* the cell changes: every term hears of it before the next computation, once */
  tether *tt = rl_terms_state(both, idx);
  const double L2[3] = {1.35, 1.35, 1.35};
  assert_int_equal(rl_system_set_box(s.sys, L2), RL_OK);
  memset(B.f, 0, sizeof(double[3]) * (size_t)n);
  memset(B.k, 0, sizeof(double[3]) * (size_t)n);
  B.energy = 0.0;
  assert_int_equal(rl_terms_compute(both, s.sys, &B), RL_OK);
  assert_int_equal(rl_terms_compute(both, s.sys, &B), RL_OK);
  CHECK_TRUE("a change of the cell reaches the terms, once", tt->box_calls == 1);
  /* and the pair term computes in the new box: as a force field made for it */
  rl_forcefield *ff = rl_forcefield_alloc(s.sys, &s.pp.p, &s.sff, 1);
  rl_forces C, D;
  forces_alloc(&C, s.sys);
  forces_alloc(&D, s.sys);
  assert_int_equal(rl_terms_compute(pair, s.sys, &C), RL_OK);
  assert_int_equal(rl_forcefield_compute(ff, s.sys, &D), RL_OK);
  CHECK_NEAR("after the box change the pair term's energy is a new force field's in the new box", C.energy, D.energy,
             1e-12 * fabs(D.energy));
  free(A.f); free(A.k); free(B.f); free(B.k); free(C.f); free(C.k); free(D.f); free(D.k);
  rl_forcefield_free(ff);
  rl_terms_free(pair);
  rl_terms_free(both);
  rl_system_free(s.sys);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(pair_through_the_sum), cmocka_unit_test(a_term_of_ones_own)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
