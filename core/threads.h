/* The OpenMP thread count asked for by a `threads` parameter (rl_ff_params, rl_integrator_params):
 * > 0 as given; 0: OMP_NUM_THREADS if set, else one thread.  Threads are asked for, not assumed
 * (as in LAMMPS): on a shared 2-core machine two spinning threads ran 10x slower than one.
 * Always 1 in a build without OpenMP. */
#ifndef ROTLEAP_CORE_THREADS_H
#define ROTLEAP_CORE_THREADS_H

#include <stdlib.h>
#ifdef _OPENMP
#include <omp.h>
#endif

/* The per-body loops (kick, drift, rotations, the force field's copies and checks) go parallel
 * from this many bodies on; below it the threads' start costs about what they save.  It was
 * 2,048: with the pair loop's threads already running, 1,000 dipoles on two threads stepped
 * 5-8 % faster at 512, and 512 dipoles or TIP4P were even within noise (ffbench time,
 * alternating runs, issue 8). */
#ifndef RL_THREAD_MIN_BODIES
#define RL_THREAD_MIN_BODIES 512
#endif

/* This thread's share [*i0, *i1) of n items, in thread order (the whole of it outside a parallel
 * region or without OpenMP). */
static inline void rl_thread_range(int n, int *i0, int *i1)
{
#ifdef _OPENMP
  const long t = omp_get_thread_num(), T = omp_get_num_threads();
  *i0 = (int)(n * t / T);
  *i1 = (int)(n * (t + 1) / T);
#else
  *i0 = 0;
  *i1 = n;
#endif
}

static inline int rl_threads_resolve(int asked)
{
#ifdef _OPENMP
  const char *env = getenv("OMP_NUM_THREADS");
  const int T = asked > 0 ? asked : env && *env ? omp_get_max_threads() : 1;
  return T > 1 ? T : 1;
#else
  (void)asked;
  return 1;
#endif
}

#endif
