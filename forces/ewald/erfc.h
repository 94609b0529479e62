/* erfc(x) and exp(-x^2) for the real-space Ewald sum, written to vectorise: straight-line code
 * (no calls, no branches, no table) that GCC turns into SIMD inside `omp simd` loops.
 * The pair kernels take it from here (the Ewald real-space rows); forces/ewald/ewald_real.c is its
 * reference user.
 *
 *   erfc(x) = exp(-x^2) g(x),  g(x) = exp(x^2) erfc(x)
 *
 * g is smooth and bounded (1 at 0, ~1/(x sqrt(pi)) for large x).  In s = 1/(1 + x) it is one
 * polynomial of degree 18 on [0, 1.2] and another on [1.2, 6.5], interpolated at Chebyshev nodes
 * in 40-digit arithmetic (erfc_table.py writes erfc_coef.h); a point takes its piece's
 * coefficients by one comparison, a blend in SIMD (no table, no gather: GCC 12 does not vectorise
 * gathers under its generic tuning).  exp(-x^2) uses the exact square of x split in two halves
 * (Dekker), Cody-Waite reduction by ln 2, a degree-13 Taylor polynomial on |r| <= ln2/2
 * (truncation < 4e-18) and 2^k from the exponent bits.  Cost: one division, 31 multiply-adds.
 * Errors (tests/forces/ewald/test_ewald_erfc.c: every x = i 1e-5 on [0, 6.5) and 10^6 random
 * points): erfc against the C library's <= 1e-15 relative, exp(-x^2) against exp of the exact
 * square <= 1e-15 relative (the C library's exp(-x*x) itself is off by up to x^2 1.1e-16, from
 * rounding x*x).  Compiled with -ffp-contract=fast the split may be fused away; the error of
 * exp(-x^2) then grows to about x^2 1.1e-16 (4.6e-15 at x = 6.5).
 *
 * Range: 0 <= x.  From x = 6.5 on (erfc(6.5) = 3.8e-20) both results are 0.  The Ewald
 * argument alpha r stays below alpha rc = sqrt(-ln(2 tolerance)) = 6.5 for every tolerance
 * down to 1e-18. */
#ifndef ROTLEAP_FORCES_EWALD_ERFC_H
#define ROTLEAP_FORCES_EWALD_ERFC_H

#include "erfc_coef.h"

#if RL_ERFC_DEGREE != 18
#error "rl_erfc_exp writes out Horner for degree 18"
#endif

#include <stdint.h>
#include <string.h>

/* erfc(x) for x >= 0; *expmx2 receives exp(-x^2) (both 0 from RL_ERFC_XMAX on). */
static inline double rl_erfc_exp(double x, double *expmx2)
{
  const double in = x < RL_ERFC_XMAX ? 1.0 : 0.0;
  x = x < RL_ERFC_XMAX ? x : 0.0; /* out of range: any in-range x, the result is masked */
  /* exp(-x^2): x = xh + xl with xh of 26 bits, so -xh^2 is exact and -x^2 = yh + yl */
  const double c = 134217729.0 * x; /* 2^27 + 1 */
  const double xh = c - (c - x);
  const double xl = x - xh;
  const double yh = -(xh * xh);
  const double yl = -(xl * (xh + x));
  const double magic = 6755399441055744.0; /* 1.5 2^52: adding it rounds to an integer */
  const double kt = yh * 1.4426950408889634 + magic;
  const double k = kt - magic;
  /* ln 2 = LN2_HI + LN2_LO with LN2_HI's low 32 bits zero: k LN2_HI is exact for |k| < 2^20 */
  const double r = (yh - k * 6.93147180369123816490e-01) - k * 1.90821492927058770002e-10 + yl;
  double p = 1.0 / 6227020800.0; /* 1/13! ... 1/0!, Horner */
  p = p * r + 1.0 / 479001600.0;
  p = p * r + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * r + 1.0;
  p = p * r + 1.0;
  int64_t kb, magb, sb;
  memcpy(&kb, &kt, sizeof kb);
  memcpy(&magb, &magic, sizeof magb);
  sb = (kb - magb + 1023) << 52; /* 2^k, k in [-62, 0] */
  double scale;
  memcpy(&scale, &sb, sizeof scale);
  const double e = p * scale * in;
  /* g(x): the piece's polynomial in t */
  const int hi = x >= RL_ERFC_XSPLIT;
  const double s = 1.0 / (1.0 + x);
  const double t = hi ? (s - RL_ERFC_SC1) * RL_ERFC_SIH1 : (s - RL_ERFC_SC0) * RL_ERFC_SIH0;
#define RL_ERFC_C(j) (hi ? rl_erfc_c1[j] : rl_erfc_c0[j])
  double g = RL_ERFC_C(18); /* Horner, written out: GCC vectorises no inner loop */
  g = g * t + RL_ERFC_C(17);
  g = g * t + RL_ERFC_C(16);
  g = g * t + RL_ERFC_C(15);
  g = g * t + RL_ERFC_C(14);
  g = g * t + RL_ERFC_C(13);
  g = g * t + RL_ERFC_C(12);
  g = g * t + RL_ERFC_C(11);
  g = g * t + RL_ERFC_C(10);
  g = g * t + RL_ERFC_C(9);
  g = g * t + RL_ERFC_C(8);
  g = g * t + RL_ERFC_C(7);
  g = g * t + RL_ERFC_C(6);
  g = g * t + RL_ERFC_C(5);
  g = g * t + RL_ERFC_C(4);
  g = g * t + RL_ERFC_C(3);
  g = g * t + RL_ERFC_C(2);
  g = g * t + RL_ERFC_C(1);
  g = g * t + RL_ERFC_C(0);
#undef RL_ERFC_C
  *expmx2 = e;
  return e * g;
}

#endif
