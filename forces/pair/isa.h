/* Which instruction sets this build compiles for the pair term (internal): the per-CPU clones of
 * the portable rows, the AVX-512 and AVX2 register rows, and the list build's vector scans.  GCC
 * on x86-64 only, and not with ROTLEAP_NO_CLONES (sanitizer builds, the build without OpenMP):
 * there every row is compiled once, portable.  Also the minimum image the rows and the kernels'
 * list share (RL_RND). */
#ifndef ROTLEAP_PAIR_ISA_H
#define ROTLEAP_PAIR_ISA_H

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(ROTLEAP_NO_CLONES)
#define RL_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define RL_CLONES
#endif
#define RL_INLINE static inline __attribute__((always_inline))

/* The dipole and TIP4P rows in AVX-512 registers (dipole_row512, tip4p_row512), picked at
 * setup when the CPU has AVX-512F and ROTLEAP_NO_AVX512 is not set in the environment. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(ROTLEAP_NO_CLONES)
#define RL_X512 1
#include <immintrin.h>
#define RL_T512 __attribute__((target("avx512f")))
#else
#define RL_X512 0
#define RL_T512
#endif
#if RL_X512
#define RL_T256 __attribute__((target("avx2,fma")))
/* The TIP4P rows on AVX2 are scheduled before register allocation, with an eye on register
 * pressure (GCC's -fschedule-insns -fsched-pressure, off by default on x86): with 16 vector
 * registers the row's 12 site-force sums, its neighbours' 12 site coordinates and 12 site
 * forces do not fit, and GCC's default order spilled about a fifth of its instructions to the
 * stack.  ffbench kernel tip4p 256 1, A/B on an AMD EPYC (Zen 3) guest: 0.76 -> 0.63 ms; the
 * dipole rows, with fewer live values, gained nothing. */
#define RL_SCHED __attribute__((optimize("schedule-insns", "sched-pressure")))
#else
#define RL_T256
#define RL_SCHED
#endif


/* nearbyint(x) for |x| < 2^51 in the default rounding mode, written so it vectorises:
 * x + 1.5 2^52 has unit spacing, so the sum rounds x to the nearest integer (ties to even). */
#define RL_RND(x) (((x) + 6755399441055744.0) - 6755399441055744.0)

#endif
