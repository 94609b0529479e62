/* rl_rsqrt (forces/pair/rsqrt.h), the divider-free 1 / sqrt(x) of the pair kernels, against a
 * long-double reference over the whole range it promises (2^-1021 <= x < 2^1024): at most 4 ulp.
 * Three Newton steps instead of four leave ~3e-11 relative error (~2e5 ulp), so the bound
 * catches a truncated iteration or a wrong start constant. */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <cmocka.h>
#include <gsl/gsl_rng.h>

#include "../../forces/pair/rsqrt.h"

/* |y - 1/sqrt(x)| in units of the last place of the correctly rounded result */
static double ulp_error(double x, double y)
{
  const long double ref = 1.0L / sqrtl((long double)x);
  const double r = (double)ref;
  const double ulp = nextafter(r, INFINITY) - r;
  return (double)(fabsl((long double)y - ref) / ulp);
}

static void test_rsqrt_ulp(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  double worst = 0.0, worst_x = 0.0;
  for (int e = -1021; e <= 1023; e++) {
    const double p = ldexp(1.0, e);
    /* each binade: its ends, and random mantissas (the start's error depends on the mantissa
     * and the exponent's parity) */
    double xs[66];
    int n = 0;
    xs[n++] = p;
    xs[n++] = e < 1023 ? nextafter(2.0 * p, 0.0) : DBL_MAX;
    while (n < 66) xs[n++] = p * (1.0 + gsl_rng_uniform(rng));
    for (int k = 0; k < n; k++) {
      const double u = ulp_error(xs[k], rl_rsqrt(xs[k]));
      if (!(u <= worst)) { worst = u; worst_x = xs[k]; }
    }
  }
  printf("rl_rsqrt: worst error %.2f ulp at x = %.17g\n", worst, worst_x);
  assert_true(worst <= 4.0);
  gsl_rng_free(rng);
}

static void test_rsqrt_values(void **state)
{
  (void)state;
  /* exact squares of powers of two come out exact or within an ulp */
  assert_true(ulp_error(1.0, rl_rsqrt(1.0)) <= 1.0);
  assert_true(ulp_error(4.0, rl_rsqrt(4.0)) <= 1.0);
  assert_true(ulp_error(0.25, rl_rsqrt(0.25)) <= 1.0);
  /* the kernels' working range: squared distances in nm^2 or sigma^2 */
  for (double x = 1e-4; x < 1e3; x *= 1.001) assert_true(ulp_error(x, rl_rsqrt(x)) <= 4.0);
  /* x = 0: finite (the overlap check reports the pair; no inf or NaN reaches a sum) */
  assert_true(isfinite(rl_rsqrt(0.0)));
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_rsqrt_ulp),
      cmocka_unit_test(test_rsqrt_values),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
