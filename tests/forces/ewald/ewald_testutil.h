/* Helpers for the Ewald tests: periodic scenes of charged rigid bodies, the Ewald terms through a
 * sum, finite differences. */
#ifndef ROTLEAP_EWALD_TESTUTIL_H
#define ROTLEAP_EWALD_TESTUTIL_H

#include "../ff_testutil.h"
#include "rotleap/ewald.h"

#define EW_CHECK_LE FF_CHECK_LE
#define EW_CHECK_TRUE FF_CHECK_TRUE

static inline double norm3d(const double a[3]) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/* A scene: its species (at most 6), the system and an Ewald parameter block for it. */
typedef struct {
  ff_test_species sp[6];
  rl_species_ff sff[6];
  int nsp;
  rl_system *sys;
  rl_ewald_params p;
} ew_scene;

/* Centres at random in the box, minimum-image centre distances >= dmin, random orientations. */
static inline void ew_place(rl_system *sys, gsl_rng *rng, double dmin)
{
  double L[3];
  rl_system_box(sys, L);
  const int n = rl_system_count(sys);
  double (*r)[3] = malloc(sizeof *r * (size_t)n);
  for (int i = 0; i < n; i++) {
    for (int tries = 0;; tries++) {
      assert_true(tries < 1000000);
      double x[3];
      for (int c = 0; c < 3; c++) x[c] = gsl_ran_flat(rng, 0.0, L[c]);
      int ok = 1;
      for (int j = 0; j < i && ok; j++) {
        double d2 = 0.0;
        for (int c = 0; c < 3; c++) {
          double d = x[c] - r[j][c];
          d -= L[c] * nearbyint(d / L[c]);
          d2 += d * d;
        }
        ok = d2 >= dmin * dmin;
      }
      if (ok) {
        memcpy(r[i], x, sizeof x);
        break;
      }
    }
    assert_int_equal(rl_system_set_position(sys, i, r[i]), RL_OK);
    ff_random_orientation(sys, i, rng);
  }
  free(r);
}

/* A scene of the species s->sp[0..nsp) (filled by the caller), counts[k] bodies of each, placed at
 * random (centres >= dmin apart) in a box L; the parameter block at its defaults. */
static inline void ew_scene_build(ew_scene *s, int nsp, const int *counts, const double L[3], double dmin, unsigned long seed)
{
  s->nsp = nsp;
  for (int k = 0; k < s->nsp; k++) s->sff[k] = ff_test_species_ff(&s->sp[k]);
  s->sys = rl_system_alloc(RL_UNITS_REAL);
  for (int k = 0; k < nsp; k++) assert_int_equal(rl_system_add_species(s->sys, &s->sp[k].desc, counts[k], NULL), RL_OK);
  assert_int_equal(rl_system_set_box(s->sys, L), RL_OK);
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, seed);
  ew_place(s->sys, rng, dmin);
  gsl_rng_free(rng);
  rl_ewald_params_default(&s->p);
  s->p.species = s->sff;
  s->p.nspecies = s->nsp;
}

/* The mixed scene: TIP4P-like waters (asymmetric, with a massless charge), tetrahedral spherical
 * tops, linear CO2, and point ions +1 / -1, in a non-cubic box; neutral unless `extra_ion` adds
 * one more cation. */
static inline void ew_scene_mixed(ew_scene *s, const double L[3], int nwater, int ntetra, int nco2, int nion,
                                  int extra_ion, unsigned long seed)
{
  memset(s, 0, sizeof *s);
  ff_water(&s->sp[0]);
  ff_tetra(&s->sp[1]);
  ff_co2(&s->sp[2]);
  ff_ion(&s->sp[3], 1.0);
  ff_ion(&s->sp[4], -1.0);
  const int counts[5] = {nwater, ntetra, nco2, nion + extra_ion, nion};
  ew_scene_build(s, 5, counts, L, 0.32, seed);
}

/* Random point ions (n/2 cations, n/2 anions of charge q) in a box. */
static inline void ew_scene_ions(ew_scene *s, const double L[3], int n, double q, double dmin, unsigned long seed)
{
  memset(s, 0, sizeof *s);
  ff_ion(&s->sp[0], q);
  ff_ion(&s->sp[1], -q);
  const int counts[2] = {n / 2, n - n / 2};
  ew_scene_build(s, 2, counts, L, dmin, seed);
}

static inline void ew_scene_free(ew_scene *s) { rl_system_free(s->sys); }

/* Results of one computation of a sum of terms. */
typedef struct {
  int n, nrot;
  double (*f)[3], (*k)[3];
  double energy, virial[9];
  double e[64]; /* the components */
  int ne;
} ew_result;

static inline void ew_result_free(ew_result *r)
{
  free(r->f);
  free(r->k);
}

/* Whether two results are the same to the bit (energies, components, forces, torques, virial). */
static inline int ew_same_bits(const ew_result *a, const ew_result *b)
{
  return a->energy == b->energy && !memcmp(a->virial, b->virial, sizeof a->virial) &&
         !memcmp(a->f, b->f, sizeof(double[3]) * (size_t)a->n) && !memcmp(a->k, b->k, sizeof(double[3]) * (size_t)a->nrot) &&
         !memcmp(a->e, b->e, sizeof(double) * (size_t)a->ne);
}

static inline int ew_eval(rl_terms *t, rl_system *sys, ew_result *r)
{
  r->n = rl_system_count(sys);
  r->nrot = rl_system_nrot(sys);
  r->f = calloc((size_t)r->n + 1, sizeof(double[3]));
  r->k = calloc((size_t)r->nrot + 1, sizeof(double[3]));
  rl_forces F = {r->f, r->k, 0.0, {0}, 0};
  const int st = rl_terms_compute(t, sys, &F);
  r->energy = F.energy;
  memcpy(r->virial, F.virial, sizeof F.virial);
  r->ne = rl_terms_nenergies(t);
  for (int j = 0; j < r->ne && j < 64; j++) r->e[j] = rl_terms_energy(t, j);
  return st;
}

static inline double ew_energy(rl_terms *t, rl_system *sys)
{
  ew_result r;
  assert_int_equal(ew_eval(t, sys, &r), RL_OK);
  ew_result_free(&r);
  return r.energy;
}

/* One term of `type` (or, with type2, two) on s's parameters. */
static inline rl_terms *ew_terms(ew_scene *s, const rl_term_type *type, const rl_term_type *type2)
{
  rl_terms *t = rl_terms_alloc(s->sys);
  assert_non_null(t);
  if (rl_terms_add(t, type, &s->p, NULL)) {
    printf("rl_terms_add: %s\n", rl_last_error());
    fail();
  }
  if (type2) assert_int_equal(rl_terms_add(t, type2, &s->p, NULL), RL_OK);
  return t;
}

/* sqrt(sum |a - b|^2 / sum |b|^2) over n vectors */
static inline double ew_rel_rms(const double (*a)[3], const double (*b)[3], int n)
{
  double num = 0.0, den = 0.0;
  for (int i = 0; i < n; i++)
    for (int c = 0; c < 3; c++) {
      num += (a[i][c] - b[i][c]) * (a[i][c] - b[i][c]);
      den += b[i][c] * b[i][c];
    }
  return sqrt(num / (den > 0 ? den : 1.0));
}

/* Finite differences of the energy of a sum, Richardson-extrapolated central differences:
 * mode 0 moves body i along axis c (returns dU/dx = -F_c), mode 1 turns it about lab axis c
 * (dU/dphi = -K_c), mode 2 scales every centre and the box along axis c at fixed orientations
 * (dU/d strain = -W_cc). */
static inline double ew_fd_energy_at(rl_terms *t, rl_system *sys, int i, int mode, int c, double h)
{
  double r0[3], A0[9], L0[3];
  const int n = rl_system_count(sys);
  double (*R0)[3] = NULL;
  rl_kind kind = RL_KIND_POINT;
  if (mode == 0) {
    rl_system_get_position(sys, i, r0);
    double r[3] = {r0[0], r0[1], r0[2]};
    r[c] += h;
    assert_int_equal(rl_system_set_position(sys, i, r), RL_OK);
  } else if (mode == 1) {
    kind = rl_system_species_kind(sys, rl_system_species_of(sys, i));
    rl_system_get_orientation(sys, i, A0);
    double nvec[3] = {0, 0, 0}, R[9];
    nvec[c] = 1.0;
    ff_rotation(nvec, h, R);
    ff_rotate_body(sys, i, R);
  } else {
    rl_system_box(sys, L0);
    R0 = malloc(sizeof(double[3]) * (size_t)n);
    double L[3] = {L0[0], L0[1], L0[2]};
    L[c] *= 1.0 + h;
    assert_int_equal(rl_system_set_box(sys, L), RL_OK);
    for (int j = 0; j < n; j++) {
      rl_system_get_position(sys, j, R0[j]);
      double r[3] = {R0[j][0], R0[j][1], R0[j][2]};
      r[c] *= 1.0 + h;
      assert_int_equal(rl_system_set_position(sys, j, r), RL_OK);
    }
  }
  const double U = ew_energy(t, sys);
  if (mode == 0) {
    assert_int_equal(rl_system_set_position(sys, i, r0), RL_OK);
  } else if (mode == 1) {
    if (kind == RL_KIND_DIPOLE || kind == RL_KIND_LINEAR) {
      const double rho[3] = {A0[6], A0[7], A0[8]};
      assert_int_equal(rl_system_set_axis(sys, i, rho), RL_OK);
    } else {
      assert_int_equal(rl_system_set_orientation(sys, i, A0), RL_OK);
    }
  } else {
    assert_int_equal(rl_system_set_box(sys, L0), RL_OK);
    for (int j = 0; j < n; j++) assert_int_equal(rl_system_set_position(sys, j, R0[j]), RL_OK);
    free(R0);
  }
  return U;
}

static inline double ew_fd(rl_terms *t, rl_system *sys, int i, int mode, int c, double h)
{
  const double d1 = (ew_fd_energy_at(t, sys, i, mode, c, h) - ew_fd_energy_at(t, sys, i, mode, c, -h)) / (2 * h);
  const double d2 = (ew_fd_energy_at(t, sys, i, mode, c, h / 2) - ew_fd_energy_at(t, sys, i, mode, c, -h / 2)) / h;
  return (4 * d2 - d1) / 3;
}

#endif
