/* Helpers for the interaction tests: scenes of mixed rigid bodies, finite differences. */
#ifndef ROTLEAP_FF_TESTUTIL_H
#define ROTLEAP_FF_TESTUTIL_H
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <rotleap/rotleap.h>
#include <rotleap/forcefield.h>

/* One line per check: "check <name>: <value> <= <limit> ok|FAIL". */
#define FF_CHECK_LE(name, value, limit)                                                         \
  do {                                                                                          \
    double v_ = (value), l_ = (limit);                                                          \
    printf("check %-70s %.3e <= %.1e %s\n", name, v_, l_, v_ <= l_ ? "ok" : "FAIL");            \
    assert_true(v_ <= l_);                                                                      \
  } while (0)

#define FF_CHECK_TRUE(name, cond)                                                               \
  do {                                                                                          \
    int c_ = (cond);                                                                            \
    printf("check %-70s %s\n", name, c_ ? "ok" : "FAIL");                                       \
    assert_true(c_);                                                                            \
  } while (0)

/* ------------------------------------------------------------------ species catalogue */

typedef struct {
  rl_species_desc desc;
  double sites[8][3];
  double sigma[8], epsilon[8], charge[8], dipole[8], quadrupole[8];
  int has_dipole, has_quad;
} ff_test_species;

static inline rl_species_ff ff_test_species_ff(const ff_test_species *s)
{
  rl_species_ff f = {s->desc.nsites, s->sigma, s->epsilon, s->charge,
                     s->has_dipole ? s->dipole : NULL, s->has_quad ? s->quadrupole : NULL};
  return f;
}

static inline void ff_species_init(ff_test_species *s, const char *name, rl_kind kind, double m,
                                   double J0, double J1, double J2, int nsites)
{
  memset(s, 0, sizeof *s);
  s->desc.name = name;
  s->desc.kind = kind;
  s->desc.mass = m;
  s->desc.inertia[0] = J0; s->desc.inertia[1] = J1; s->desc.inertia[2] = J2;
  s->desc.nsites = nsites;
  s->desc.sites = &s->sites[0][0];
}

static inline void ff_site(ff_test_species *s, int a, double x, double y, double z, double sig,
                           double eps, double q)
{
  s->sites[a][0] = x; s->sites[a][1] = y; s->sites[a][2] = z;
  s->sigma[a] = sig; s->epsilon[a] = eps; s->charge[a] = q;
}

/* Point ion (real units): one LJ site with a charge. */
static inline void ff_ion(ff_test_species *s, double q)
{
  ff_species_init(s, "ion", RL_KIND_POINT, 23.0, 0, 0, 0, 1);
  ff_site(s, 0, 0, 0, 0, 0.26, 0.4, q);
}
/* TIP4P-like asymmetric water with its centre of mass at the origin. */
static inline void ff_water(ff_test_species *s)
{
  ff_species_init(s, "water", RL_KIND_ASYMMETRIC, 18.0, 0.6, 1.2, 1.5, 4);
  ff_site(s, 0, 0, 0, -0.0066, 0.3154, 0.6485, 0.0);
  ff_site(s, 1, 0.0757, 0, 0.0520, 0, 0, 0.52);
  ff_site(s, 2, -0.0757, 0, 0.0520, 0, 0, 0.52);
  ff_site(s, 3, 0, 0, 0.0084, 0, 0, -1.04);
}
/* Spherical top: 5-site tetrahedral charged molecule. */
static inline void ff_tetra(ff_test_species *s)
{
  double d = 0.109 / sqrt(3.0);
  ff_species_init(s, "tetra", RL_KIND_SPHERICAL, 16.0, 3.2, 3.2, 3.2, 5);
  ff_site(s, 0, 0, 0, 0, 0.35, 0.28, -0.4);
  ff_site(s, 1, d, d, d, 0.25, 0.12, 0.1);
  ff_site(s, 2, -d, -d, d, 0.25, 0.12, 0.1);
  ff_site(s, 3, -d, d, -d, 0.25, 0.12, 0.1);
  ff_site(s, 4, d, -d, -d, 0.25, 0.12, 0.1);
}
/* Linear: CO2-like, 3 charged LJ sites on Z. */
static inline void ff_co2(ff_test_species *s)
{
  ff_species_init(s, "co2", RL_KIND_LINEAR, 44.0, 4.3, 4.3, 0.0, 3);
  ff_site(s, 0, 0, 0, 0, 0.28, 0.23, 0.7);
  ff_site(s, 1, 0, 0, 0.116, 0.30, 0.66, -0.35);
  ff_site(s, 2, 0, 0, -0.116, 0.30, 0.66, -0.35);
}
/* Point dipole (Stockmayer, real units). */
static inline void ff_stockmayer(ff_test_species *s, double mu)
{
  ff_species_init(s, "stockmayer", RL_KIND_DIPOLE, 30.0, 0.5, 0.5, 0.5, 1);
  ff_site(s, 0, 0, 0, 0, 0.3, 1.0, 0.0);
  s->has_dipole = 1;
  s->dipole[0] = mu;
}
/* Symmetric top (NH3-like) with a dipole on an off-centre site along body Z and charges. */
static inline void ff_symtop(ff_test_species *s)
{
  ff_species_init(s, "symtop", RL_KIND_SYMMETRIC, 17.0, 1.7, 1.7, 2.7, 4);
  ff_site(s, 0, 0, 0, 0.02, 0.34, 0.7, 0.0);
  ff_site(s, 1, 0.094, 0, -0.03, 0.0, 0.0, 0.2);
  ff_site(s, 2, -0.047, 0.0814, -0.03, 0.0, 0.0, 0.2);
  ff_site(s, 3, -0.047, -0.0814, -0.03, 0.0, 0.0, -0.4);
  s->has_dipole = 1;
  s->dipole[0] = 0.03;
}
/* 2CLJQ linear molecule: two LJ sites and a quadrupole at the centre. */
static inline void ff_2cljq(ff_test_species *s, double Q)
{
  ff_species_init(s, "2cljq", RL_KIND_LINEAR, 28.0, 8.5, 8.5, 0.0, 3);
  ff_site(s, 0, 0, 0, 0.055, 0.33, 0.3, 0.0);
  ff_site(s, 1, 0, 0, -0.055, 0.33, 0.3, 0.0);
  ff_site(s, 2, 0, 0, 0, 0.0, 0.0, 0.0);
  s->has_quad = 1;
  s->quadrupole[2] = Q;
}

/* ------------------------------------------------------------------------ scenes */

/* Random orientation for every rotating body. */
static inline void ff_random_orientation(rl_system *sys, int i, gsl_rng *rng)
{
  rl_kind k = rl_system_species_kind(sys, rl_system_species_of(sys, i));
  if (k == RL_KIND_POINT) return;
  double q[4], n = 0.0, A[9];
  for (int c = 0; c < 4; c++) { q[c] = gsl_ran_gaussian(rng, 1.0); n += q[c] * q[c]; }
  for (int c = 0; c < 4; c++) q[c] /= sqrt(n);
  rl_quat_to_matrix(q, A);
  if (k == RL_KIND_DIPOLE || k == RL_KIND_LINEAR) {
    double rho[3] = {A[6], A[7], A[8]};
    double nn = sqrt(rho[0] * rho[0] + rho[1] * rho[1] + rho[2] * rho[2]);
    for (int c = 0; c < 3; c++) rho[c] /= nn;
    assert_int_equal(rl_system_set_axis(sys, i, rho), RL_OK);
  } else {
    assert_int_equal(rl_system_set_orientation(sys, i, A), RL_OK);
  }
}

/* Place bodies at random in a sphere of radius R about c, centres at least dmin apart. */
static inline void ff_place_cluster(rl_system *sys, gsl_rng *rng, const double c[3], double R,
                                    double dmin)
{
  int n = rl_system_count(sys);
  double(*r)[3] = malloc(sizeof *r * (size_t)n);
  for (int i = 0; i < n; i++) {
    for (int tries = 0;; tries++) {
      assert_true(tries < 100000);
      double x[3];
      do {
        for (int k = 0; k < 3; k++) x[k] = gsl_ran_flat(rng, -R, R);
      } while (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] > R * R);
      int ok = 1;
      for (int j = 0; j < i && ok; j++) {
        double d2 = 0.0;
        for (int k = 0; k < 3; k++) d2 += (x[k] + c[k] - r[j][k]) * (x[k] + c[k] - r[j][k]);
        ok = d2 >= dmin * dmin;
      }
      if (ok) {
        for (int k = 0; k < 3; k++) r[i][k] = x[k] + c[k];
        break;
      }
    }
    assert_int_equal(rl_system_set_position(sys, i, r[i]), RL_OK);
    ff_random_orientation(sys, i, rng);
  }
  free(r);
}

/* Energy only (forces discarded). */
static inline double ff_energy(rl_forcefield *ff, rl_system *sys)
{
  int n = rl_system_count(sys), nr = rl_system_nrot(sys);
  double(*f)[3] = calloc((size_t)n + 1, sizeof *f);
  double(*k)[3] = calloc((size_t)nr + 1, sizeof *k);
  rl_forces out = {f, k, 0.0, {0}, 0};
  int st = rl_forcefield_compute(ff, sys, &out);
  if (st) fprintf(stderr, "compute: %s\n", rl_last_error());
  assert_int_equal(st, RL_OK);
  free(f);
  free(k);
  return out.energy;
}

typedef struct {
  int n, nrot;
  double (*f)[3], (*k)[3];
  rl_forces out;
} ff_result;

static inline void ff_result_compute(ff_result *res, rl_forcefield *ff, rl_system *sys)
{
  res->n = rl_system_count(sys);
  res->nrot = rl_system_nrot(sys);
  res->f = calloc((size_t)res->n + 1, sizeof *res->f);
  res->k = calloc((size_t)res->nrot + 1, sizeof *res->k);
  rl_forces o = {res->f, res->k, 0.0, {0}, 0};
  int st = rl_forcefield_compute(ff, sys, &o);
  if (st) fprintf(stderr, "compute: %s\n", rl_last_error());
  assert_int_equal(st, RL_OK);
  res->out = o;
}

static inline void ff_result_free(ff_result *res)
{
  free(res->f);
  free(res->k);
}

/* Largest |a_i| and largest |a_i - b_i| over n vectors. */
static inline double ff_maxnorm(const double (*a)[3], int n)
{
  double m = 0.0;
  for (int i = 0; i < n; i++)
    m = fmax(m, sqrt(a[i][0] * a[i][0] + a[i][1] * a[i][1] + a[i][2] * a[i][2]));
  return m;
}

static inline double ff_maxdiff(const double (*a)[3], const double (*b)[3], int n)
{
  double m = 0.0;
  for (int i = 0; i < n; i++) {
    double d[3] = {a[i][0] - b[i][0], a[i][1] - b[i][1], a[i][2] - b[i][2]};
    m = fmax(m, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
  }
  return m;
}

/* Rotation matrix exp(eps [n]x) (Rodrigues), n a unit vector. */
static inline void ff_rotation(const double n[3], double eps, double R[9])
{
  double s = sin(eps), c = 1.0 - cos(eps);
  double K[9] = {0, -n[2], n[1], n[2], 0, -n[0], -n[1], n[0], 0};
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      double k2 = 0.0;
      for (int m = 0; m < 3; m++) k2 += K[3 * a + m] * K[3 * m + b];
      R[3 * a + b] = (a == b) + s * K[3 * a + b] + c * k2;
    }
}

/* Rotate body i in the lab by R about its centre: A <- A R^T, rho <- R rho. */
static inline void ff_rotate_body(rl_system *sys, int i, const double R[9])
{
  rl_kind k = rl_system_species_kind(sys, rl_system_species_of(sys, i));
  if (k == RL_KIND_POINT) return;
  if (k == RL_KIND_DIPOLE || k == RL_KIND_LINEAR) {
    double rho[3], r2[3];
    rl_system_get_axis(sys, i, rho);
    for (int a = 0; a < 3; a++) r2[a] = R[3 * a] * rho[0] + R[3 * a + 1] * rho[1] + R[3 * a + 2] * rho[2];
    double nn = sqrt(r2[0] * r2[0] + r2[1] * r2[1] + r2[2] * r2[2]);
    for (int a = 0; a < 3; a++) r2[a] /= nn;
    assert_int_equal(rl_system_set_axis(sys, i, r2), RL_OK);
  } else {
    double A[9], B[9];
    rl_system_get_orientation(sys, i, A);
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) {
        double s = 0.0;
        for (int m = 0; m < 3; m++) s += A[3 * a + m] * R[3 * b + m];
        B[3 * a + b] = s;
      }
    assert_int_equal(rl_system_set_orientation(sys, i, B), RL_OK);
  }
}

/* Central difference of the energy along a path, Richardson-extrapolated:
 * mode 0: translate body i along e_c; mode 1: rotate body i about lab axis e_c. */
static inline double ff_fd_energy_at(rl_forcefield *ff, rl_system *sys, int i, int mode, int c,
                                     double x)
{
  double r0[3], A0[9], rho0[3];
  rl_kind k = rl_system_species_kind(sys, rl_system_species_of(sys, i));
  rl_system_get_position(sys, i, r0);
  rl_system_get_orientation(sys, i, A0);
  rl_system_get_axis(sys, i, rho0);
  if (mode == 0) {
    double r[3] = {r0[0], r0[1], r0[2]};
    r[c] += x;
    rl_system_set_position(sys, i, r);
  } else {
    double n[3] = {0, 0, 0}, R[9];
    n[c] = 1.0;
    ff_rotation(n, x, R);
    ff_rotate_body(sys, i, R);
  }
  double e = ff_energy(ff, sys);
  rl_system_set_position(sys, i, r0);
  if (k == RL_KIND_DIPOLE || k == RL_KIND_LINEAR) rl_system_set_axis(sys, i, rho0);
  else if (k != RL_KIND_POINT) rl_system_set_orientation(sys, i, A0);
  return e;
}

static inline double ff_fd_derivative(rl_forcefield *ff, rl_system *sys, int i, int mode, int c,
                                      double h)
{
  double d1 = (ff_fd_energy_at(ff, sys, i, mode, c, h) - ff_fd_energy_at(ff, sys, i, mode, c, -h)) /
              (2.0 * h);
  double d2 = (ff_fd_energy_at(ff, sys, i, mode, c, h / 2) -
               ff_fd_energy_at(ff, sys, i, mode, c, -h / 2)) / h;
  return (4.0 * d2 - d1) / 3.0;
}

#endif
