/* The Ewald real-space pair function of the kernel rows (forces/pair/kernels/elec/ewald.h) against
 * the C library: u = erfc(alpha r)/r and fs = (u + 2 alpha/sqrt(pi) exp(-alpha^2 r^2))/r^2 on
 * the scalar path (rl_elec_qq, the portable rows) and on the register rows' vectors (rl_elec_qq8,
 * AVX-512; rl_elec_qq4, AVX2; where the CPU has them), at alpha = 1 for every x = alpha r =
 * 1e-3 + i 1e-4 up to 6.5 (and 0 beyond).  The rows' flags (-ffp-contract=fast) as pair.cmake. */
#include "ff_testutil.h"
#include "pair/kernels/elec/ewald.h"

#include <string.h>

#define NX 64990

static void ref(double x, double *u, double *fs)
{
  *u = erfc(x) / x;
  *fs = (*u + 2.0 / sqrt(M_PI) * exp(-x * x)) / (x * x);
}

/* max relative error of u and fs over the points, from the values computed in uu, ff */
static void check(const char *what, const double *xs, const double *uu, const double *ff)
{
  double eu = 0.0, ef = 0.0, xu = 0.0, xf = 0.0, eu2 = 0.0;
  for (int i = 0; i < NX; i++) {
    double u, fs;
    ref(xs[i], &u, &fs);
    const double du = fabs(uu[i] - u) / u, df = fabs(ff[i] - fs) / fs;
    if (du > eu) { eu = du; xu = xs[i]; }
    if (df > ef) { ef = df; xf = xs[i]; }
    if (xs[i] < 3.0) eu2 = fmax(eu2, du); /* alpha rc = 2.6 at tolerance 5e-4 */
  }
  printf("%s: largest at x = %.4f (erfc(x)/x) and %.4f (force); below x = 3: %.2e\n", what, xu, xf, eu2);
  char name[160];
  snprintf(name, sizeof name, "%s: erfc(x)/x against the C library, max relative", what);
  FF_CHECK_LE(name, eu, 5e-14);
  snprintf(name, sizeof name, "%s: the force factor against the C library, max relative", what);
  FF_CHECK_LE(name, ef, 5e-14);
}

#if RL_X512
RL_T512 static void vec8(const rl_kelec E, const double *xs, double *uu, double *ff)
{
  for (int i = 0; i + 8 <= NX; i += 8) {
    const __m512d x = _mm512_loadu_pd(xs + i), r2 = x * x, ir = _mm512_set1_pd(1.0) / x;
    __m512d u, fs;
    rl_elec_qq8(E, r2, ir, &fs, &u);
    _mm512_storeu_pd(uu + i, u);
    _mm512_storeu_pd(ff + i, fs);
  }
}
RL_T256 static void vec4(const rl_kelec E, const double *xs, double *uu, double *ff)
{
  for (int i = 0; i + 4 <= NX; i += 4) {
    const __m256d x = _mm256_loadu_pd(xs + i), r2 = x * x, ir = _mm256_set1_pd(1.0) / x;
    __m256d u, fs;
    rl_elec_qq4(E, r2, ir, &fs, &u);
    _mm256_storeu_pd(uu + i, u);
    _mm256_storeu_pd(ff + i, fs);
  }
}
#endif

static void test_pair_function(void **state)
{
  (void)state;
  rl_kelec E;
  memset(&E, 0, sizeof E);
  E.alpha = 1.0;
  E.c2a = 2.0 / sqrt(M_PI);
  static double xs[NX], uu[NX], ff[NX];
  for (int i = 0; i < NX; i++) xs[i] = 1e-3 + i * 1e-4; /* NX is a multiple of 8 less 0: 64990 = 8 * 8123 + 6 */
  for (int i = 0; i < NX; i++) uu[i] = rl_elec_qq(E, xs[i] * xs[i], 1.0 / xs[i], &ff[i]);
  check("scalar (portable rows)", xs, uu, ff);
  double fs;
  FF_CHECK_TRUE("x = 6.5 and beyond: 0", rl_elec_qq(E, 6.5 * 6.5, 1.0 / 6.5, &fs) == 0.0 && fs == 0.0 &&
                                           rl_elec_qq(E, 100.0, 0.1, &fs) == 0.0 && fs == 0.0);
#if RL_X512
  const int n8 = NX / 8 * 8;
  if (__builtin_cpu_supports("avx512f")) {
    memset(uu, 0, sizeof uu);
    vec8(E, xs, uu, ff);
    for (int i = n8; i < NX; i++) uu[i] = rl_elec_qq(E, xs[i] * xs[i], 1.0 / xs[i], &ff[i]);
    check("AVX-512 (rl_elec_qq8)", xs, uu, ff);
  }
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    const int n4 = NX / 4 * 4;
    memset(uu, 0, sizeof uu);
    vec4(E, xs, uu, ff);
    for (int i = n4; i < NX; i++) uu[i] = rl_elec_qq(E, xs[i] * xs[i], 1.0 / xs[i], &ff[i]);
    check("AVX2 (rl_elec_qq4)", xs, uu, ff);
  }
#endif
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_pair_function)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
