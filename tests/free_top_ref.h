/* The free asymmetric top shared by test_free_top and test_baselines: one body, zero forces,
 * the gsl_odeiv2 (rk8pd) reference solution of dA/dt = W(J^-1 A l) A with l constant. */
#ifndef ROTLEAP_TEST_FREE_TOP_REF_H
#define ROTLEAP_TEST_FREE_TOP_REF_H
#include "testutil.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

static const double J0[3] = {1.0, 1.6, 2.3};   /* asymmetric, triangle inequality holds */
static const double L0[3] = {1.0, 0.6, -0.8};  /* lab = body at t = 0; |Omega| ~ 1 */

static inline int zero_forces(void *ctx, const rl_system *sys, rl_forces *out)
{
  (void)ctx; (void)sys; (void)out;
  return RL_OK;
}

/* dA/dt = W(Omega) A, Omega = J^-1 A l, l constant (eqs. 2, 6, 19 in continuous time) */
static inline int rhs(double t, const double y[], double dy[], void *params)
{
  (void)t; (void)params;
  double Om[3];
  for (int a = 0; a < 3; a++) Om[a] = (y[3 * a] * L0[0] + y[3 * a + 1] * L0[1] + y[3 * a + 2] * L0[2]) / J0[a];
  double W[9] = {0, Om[2], -Om[1], -Om[2], 0, Om[0], Om[1], -Om[0], 0};
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      dy[3 * i + j] = W[3 * i] * y[j] + W[3 * i + 1] * y[3 + j] + W[3 * i + 2] * y[6 + j];
  return GSL_SUCCESS;
}

static inline void reference(double T, double tol, double A[9])
{
  gsl_odeiv2_system sys = {rhs, NULL, 9, NULL};
  gsl_odeiv2_driver *d = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, 1e-4, tol, tol);
  double y[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, t = 0.0;
  assert_int_equal(gsl_odeiv2_driver_apply(d, &t, T, y), GSL_SUCCESS);
  memcpy(A, y, sizeof y);
  gsl_odeiv2_driver_free(d);
}

typedef struct {
  rl_system *sys;
  rl_integrator *in;
} top;

static inline top make_top_tol(double h, rl_rot_method m, const double *L, double quat_tol)
{
  top t;
  t.sys = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc d = {.name = "top", .kind = RL_KIND_ASYMMETRIC, .mass = 1.0,
                       .inertia = {J0[0], J0[1], J0[2]}};
  assert_int_equal(rl_system_add_species(t.sys, &d, 1, NULL), RL_OK);
  rl_system_set_removed_dof(t.sys, 0);
  assert_int_equal(rl_system_set_angmom(t.sys, 0, L ? L : L0), RL_OK);
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = h;
  p.method = m;
  if (quat_tol > 0.0) p.quat_tol = quat_tol;
  t.in = rl_integrator_alloc(t.sys, &p, (rl_force_provider){zero_forces, NULL});
  assert_non_null(t.in);
  assert_int_equal(rl_integrator_init(t.in), RL_OK);
  return t;
}

static inline top make_top(double h, rl_rot_method m, const double *L)
{
  return make_top_tol(h, m, L, 0.0);
}

static inline void free_top(top *t)
{
  rl_integrator_free(t->in);
  rl_system_free(t->sys);
}

static inline double frob_diff(const double *a, const double *b)
{
  double s = 0.0;
  for (int i = 0; i < 9; i++) s += (a[i] - b[i]) * (a[i] - b[i]);
  return sqrt(s);
}

/* Global error of A(T) at four step sizes; order from successive halvings, 2.00 +- tol. */
static inline void free_top_order(rl_rot_method m, const char *label, double tol)
{
  const double T = 4.0;
  double Aref[9], Aref2[9];
  reference(T, 1e-14, Aref);
  reference(T, 1e-13, Aref2);
  double refdiff = frob_diff(Aref, Aref2);
  const double hs[4] = {0.04, 0.02, 0.01, 0.005};
  double err[4];
  for (int k = 0; k < 4; k++) {
    top t = make_top(hs[k], m, NULL);
    long n = lround(T / hs[k]);
    for (long s = 0; s < n; s++) assert_int_equal(rl_integrator_step(t.in, NULL), RL_OK);
    double A[9];
    rl_system_get_orientation(t.sys, 0, A);
    err[k] = frob_diff(A, Aref);
    free_top(&t);
  }
  char name[96];
  snprintf(name, sizeof name, "%s: reference accuracy (1e-13 vs 1e-14 tol)", label);
  CHECK_LE(name, refdiff, 1e-3 * err[3]);
  for (int k = 0; k < 3; k++) {
    snprintf(name, sizeof name, "%s: order h=%g->%g (err %.2e->%.2e)", label, hs[k], hs[k + 1],
             err[k], err[k + 1]);
    CHECK_NEAR(name, log2(err[k] / err[k + 1]), 2.0, tol);
  }
}

/* Forward n steps, reverse, n steps back: max |A_back - A_0| and |l_back + l_0|. */
static inline void free_top_reverse_error(rl_rot_method m, const double L[3], double quat_tol, double *eA, double *el)
{
  top t = make_top_tol(0.05, m, L, quat_tol);
  double A0[9], A[9], l[3];
  rl_system_get_orientation(t.sys, 0, A0);
  for (int s = 0; s < 1000; s++) assert_int_equal(rl_integrator_step(t.in, NULL), RL_OK);
  assert_int_equal(rl_integrator_reverse(t.in), RL_OK);
  for (int s = 0; s < 1000; s++) assert_int_equal(rl_integrator_step(t.in, NULL), RL_OK);
  rl_system_get_orientation(t.sys, 0, A);
  rl_system_get_angmom(t.sys, 0, l);
  double dl[3] = {l[0] + L[0], l[1] + L[1], l[2] + L[2]};
  *eA = max_abs_diff(A, A0, 9);
  *el = norm3d(dl);
  free_top(&t);
}

#endif
