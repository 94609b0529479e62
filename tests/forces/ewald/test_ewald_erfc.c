/* The vectorised erfc of the Ewald real space (forces/ewald/erfc.h) against the C library:
 *   erfc(x)      relative error <= 1e-15 at every x = i 1e-5 on [0, 6.5) and at 10^6 random points
 *                (the range alpha r takes for every tolerance down to 1e-18)
 *   exp(-x^2)    relative error <= 1e-15 against expl of the exact square (long double)
 *   x >= 6.5     both 0 (erfc(6.5) = 3.8e-20)
 * and, for information, its speed against erfc() + exp() of the C library in one loop (cloned for
 * AVX-512, AVX2 and the baseline, as the real-space term is). */
#include "ewald_testutil.h"
#include "ewald/erfc.h"

#include <time.h>

static double exact_exp_mx2(double x) /* exp(-x^2) with x^2 split exactly, in long double */
{
  const double c = 134217729.0 * x, xh = c - (c - x), xl = x - xh;
  return (double)expl(-((long double)xh * xh) - (long double)xl * (xh + x));
}

static void accuracy(void **state)
{
  (void)state;
  double we = 0, wx = 0, xe = 0, xx = 0;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 1);
  for (long i = 0; i < 650000 + 1000000; i++) {
    const double x = i < 650000 ? i * 1e-5 : gsl_rng_uniform(rng) * RL_ERFC_XMAX;
    double e;
    const double v = rl_erfc_exp(x, &e), r = erfc(x), ee = exact_exp_mx2(x);
    if (fabs(v - r) / r > we) {
      we = fabs(v - r) / r;
      xe = x;
    }
    if (fabs(e - ee) / ee > wx) {
      wx = fabs(e - ee) / ee;
      xx = x;
    }
  }
  gsl_rng_free(rng);
  printf("largest errors: erfc %.3g at x = %.6f, exp(-x^2) %.3g at x = %.6f\n", we, xe, wx, xx);
  EW_CHECK_LE("erfc(x) vs the C library on [0, 6.5), relative", we, 1e-15);
  EW_CHECK_LE("exp(-x^2) vs expl of the exact square on [0, 6.5), relative", wx, 1e-15);
  double e1, e2;
  const double v1 = rl_erfc_exp(6.5, &e1), v2 = rl_erfc_exp(30.0, &e2);
  EW_CHECK_TRUE("x >= 6.5: erfc and exp(-x^2) are 0", v1 == 0.0 && e1 == 0.0 && v2 == 0.0 && e2 == 0.0);
}

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(ROTLEAP_NO_CLONES)
__attribute__((target_clones("avx512f", "avx2", "default")))
#endif
static void erfc_loop(int n, const double *x, double *y, double *z)
{
#pragma omp simd
  for (int i = 0; i < n; i++) {
    double e;
    y[i] = rl_erfc_exp(x[i], &e);
    z[i] = e;
  }
}

static void libm_loop(int n, const double *x, double *y, double *z)
{
  for (int i = 0; i < n; i++) {
    y[i] = erfc(x[i]);
    z[i] = exp(-x[i] * x[i]);
  }
}

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void speed(void **state)
{
  (void)state;
  enum { N = 4096, R = 200 };
  double *x = malloc(sizeof(double) * N), *y = malloc(sizeof(double) * N), *z = malloc(sizeof(double) * N), sink = 0;
  for (int i = 0; i < N; i++) x[i] = 0.5 + 3.0 * i / N; /* alpha r over a water cutoff */
  double t[2] = {0, 0};
  for (int rep = 0; rep < 3; rep++)
    for (int k = 0; k < 2; k++) {
      const double t0 = now();
      for (int r = 0; r < R; r++) {
        (k ? libm_loop : erfc_loop)(N, x, y, z);
        sink += y[r] + z[r];
      }
      const double dt = (now() - t0) / ((double)N * R) * 1e9;
      if (!rep || dt < t[k]) t[k] = dt;
    }
  printf("erfc + exp(-x^2) per value: vectorised %.2f ns, C library %.2f ns (best of 3; %g)\n", t[0], t[1], sink > 0 ? 1.0 : 0.0);
  EW_CHECK_TRUE("timed (information only)", t[0] > 0 && t[1] > 0);
  free(x);
  free(y);
  free(z);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(accuracy), cmocka_unit_test(speed)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
