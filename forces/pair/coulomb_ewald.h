/* The real-space Ewald pair of the reference routine (internal; forcefield.c, coulomb =
 * RL_COULOMB_EWALD_REAL):
 *   U = kc q_i q_j erfc(alpha r) / r,
 *   force on i = kc q_i q_j [erfc(alpha r) / r + (2 alpha / sqrt(pi)) exp(-alpha^2 r^2)] r / r^2,
 * plain cutoff, no shift (the term "ewald-real" and OpenMM's PME and Ewald).  It takes erfc and
 * exp from the C library, so that the kernels' vectorised erfc (kernels/elec/ewald.h) is held to
 * an independent evaluation (tests/forces/test_ff_fast.c). */
#ifndef ROTLEAP_PAIR_COULOMB_EWALD_H
#define ROTLEAP_PAIR_COULOMB_EWALD_H

#include <math.h>

/* in alpha > 0, qq = kc q_i q_j, r2 = |r_ij|^2 > 0; out *fscal: force on i = fscal r_ij;
 * returns the pair energy. */
static inline double rl_coulomb_ewald_pair(double alpha, double qq, double r2, double *fscal)
{
  const double r = sqrt(r2), ir = 1.0 / r;
  const double u = qq * erfc(alpha * r) * ir;
  *fscal = (u + qq * (2.0 * alpha / sqrt(M_PI)) * exp(-alpha * alpha * r2)) * ir * ir;
  return u;
}

#endif
