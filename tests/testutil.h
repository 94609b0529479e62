/* Shared helpers for the rotleap tests (cmocka). */
#ifndef ROTLEAP_TESTUTIL_H
#define ROTLEAP_TESTUTIL_H
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <rotleap/rotleap.h>

/* One line per check, as DESIGN.md asks: "check <name>: <value> <op> <limit>". */
#define CHECK_LE(name, value, limit)                                                             \
  do {                                                                                           \
    double v_ = (value), l_ = (limit);                                                           \
    printf("check %-58s %.3e <= %.1e %s\n", name, v_, l_, v_ <= l_ ? "ok" : "FAIL");             \
    assert_true(v_ <= l_);                                                                       \
  } while (0)

#define CHECK_NEAR(name, value, target, tol)                                                     \
  do {                                                                                           \
    double v_ = (value), t_ = (target), e_ = (tol);                                              \
    printf("check %-58s %.4f = %.2f +- %.2f %s\n", name, v_, t_, e_,                             \
           fabs(v_ - t_) <= e_ ? "ok" : "FAIL");                                                 \
    assert_true(fabs(v_ - t_) <= e_);                                                            \
  } while (0)

/* Uniformly random rotation matrix (row-major) from a random unit quaternion. */
static inline void random_rotation(gsl_rng *r, double A[9])
{
  double q[4], n = 0.0;
  for (int k = 0; k < 4; k++) { q[k] = gsl_ran_gaussian(r, 1.0); n += q[k] * q[k]; }
  n = sqrt(n);
  for (int k = 0; k < 4; k++) q[k] /= n;
  rl_quat_to_matrix(q, A);
}

static inline double max_abs_diff(const double *a, const double *b, int n)
{
  double m = 0.0;
  for (int i = 0; i < n; i++) m = fmax(m, fabs(a[i] - b[i]));
  return m;
}

static inline double norm3d(const double a[3]) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

#endif
