/* Why the kernels copy neighbours with scalar loads: AVX-512 gathers against scalar loads.
 *
 * Reads the same doubles in the same pseudo-random order (the pattern of a neighbour list: an
 * index array into a table that fits in L1) two ways, alternating rounds and keeping the best of
 * each, and prints ns per element and the ratio.  On the 2-core development VM the gather was
 * the slower one, which is why ff_fast.c fills its batches with scalar loads.
 *
 *   ./build/bench/gather [rounds=7]
 *
 * Prints "no AVX-512" and exits 0 on a CPU without it. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define N 4096   /* table and index length (32 KiB of doubles: L1-resident) */
#define REPS 2000

static double now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
__attribute__((target("avx512f"), noinline)) static double sum_gather(const double *a, const int *idx)
{
  __m512d s0 = _mm512_setzero_pd(), s1 = _mm512_setzero_pd();
  for (int r = 0; r < REPS; r++)
    for (int k = 0; k < N; k += 16) {
      s0 = _mm512_add_pd(s0, _mm512_i32gather_pd(_mm256_loadu_si256((const __m256i *)(idx + k)), a, 8));
      s1 = _mm512_add_pd(s1, _mm512_i32gather_pd(_mm256_loadu_si256((const __m256i *)(idx + k + 8)), a, 8));
    }
  return _mm512_reduce_add_pd(_mm512_add_pd(s0, s1));
}
#define HAVE_GATHER 1
#endif

__attribute__((noinline)) static double sum_scalar(const double *a, const int *idx)
{
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  for (int r = 0; r < REPS; r++)
    for (int k = 0; k < N; k += 4) {
      s0 += a[idx[k]];
      s1 += a[idx[k + 1]];
      s2 += a[idx[k + 2]];
      s3 += a[idx[k + 3]];
    }
  return (s0 + s1) + (s2 + s3);
}

int main(int argc, char **argv)
{
#ifdef HAVE_GATHER
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx512f")) {
    printf("no AVX-512\n");
    return 0;
  }
  const int rounds = argc > 1 ? atoi(argv[1]) : 7;
  static double a[N];
  static int idx[N];
  for (int i = 0; i < N; i++) {
    a[i] = i;
    idx[i] = (int)((37u * (unsigned)i + 11u) % N); /* a permutation: every element once */
  }
  double tg = 1e30, ts = 1e30, xg = 0.0, xs = 0.0;
  for (int r = 0; r < rounds; r++) {
    double t0 = now();
    xg = sum_gather(a, idx);
    double t1 = now();
    xs = sum_scalar(a, idx);
    double t2 = now();
    if (t1 - t0 < tg) tg = t1 - t0;
    if (t2 - t1 < ts) ts = t2 - t1;
  }
  if (xg != xs) {
    fprintf(stderr, "gather: sums differ (%.17g vs %.17g)\n", xg, xs);
    return 1;
  }
  const double per = 1e9 / ((double)N * REPS);
  printf("| load | ns per element |\n|---|---|\n");
  printf("| AVX-512 gather (vgatherdpd, 8 lanes) | %.3f |\n", tg * per);
  printf("| scalar loads | %.3f |\n", ts * per);
  printf("gather / scalar = %.2f\n", tg / ts);
#else
  (void)argc; (void)argv;
  printf("no AVX-512\n");
#endif
  return 0;
}
