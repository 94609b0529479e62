/* 1 / sqrt(x) without the divider, for the pair kernels (kernels/). */
#ifndef ROTLEAP_MODELS_RSQRT_H
#define ROTLEAP_MODELS_RSQRT_H

#include <stdint.h>
#include <string.h>

/* 1 / sqrt(x) for 2^-1021 <= x < 2^1024 (x / 2 must be normal), within a few ulp, in
 * multiplies and adds only, so that an `omp simd` loop vectorises it.  In the TIP4P kernel a
 * vsqrtpd and a vdivpd per Coulomb term (9 per pair) kept the divider busy; this costs 14
 * multiplies and adds, which the FMA ports overlap with the rest of the loop.
 *
 * The start is the exponent-halving bit trick (relative error below 3.5e-2); each Newton step
 * y += y (1/2 - x y^2 / 2) takes the error e to about 1.5 e^2, so four steps reach ~1e-21,
 * below round-off, and the result is within a few ulp of 1 / sqrt(x)
 * (tests/forces/test_rsqrt.c checks 4 ulp over that range).  x = 0 gives a large finite
 * value, which the kernels' overlap check reports before it is used. */
static inline double rl_rsqrt(double x)
{
  uint64_t u;
  memcpy(&u, &x, sizeof u);
  u = UINT64_C(0x5fe6eb50c7b537a9) - (u >> 1);
  double y;
  memcpy(&y, &u, sizeof y);
  const double h = 0.5 * x;
  y += y * (0.5 - h * y * y);
  y += y * (0.5 - h * y * y);
  y += y * (0.5 - h * y * y);
  y += y * (0.5 - h * y * y);
  return y;
}

#endif
