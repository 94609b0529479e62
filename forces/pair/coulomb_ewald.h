/* The real-space Ewald pairs of the reference routine (internal; forcefield.c, coulomb =
 * RL_COULOMB_EWALD_REAL):
 *   U = kc q_i q_j erfc(alpha r) / r,
 *   force on i = kc q_i q_j [erfc(alpha r) / r + (2 alpha / sqrt(pi)) exp(-alpha^2 r^2)] r / r^2,
 * and point dipoles (forces/ewald/ewald_dipole.h has the B_l):
 *   U = kc [B_1 mu_i.mu_j - B_2 (mu_i.r)(mu_j.r)],
 * plain cutoff, no shift (the term "ewald-real", OpenMM's PME and Ewald, LAMMPS's
 * lj/cut/dipole/long).  It takes erfc and
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

/* in alpha > 0, kc, r = r_i - r_j (|r| > 0), mui, muj; out f = force on i, gi = dU/dmu_i,
 * gj = dU/dmu_j (as rl_dipole_dipole_rf, dipole.h); returns U. */
static inline double rl_dipole_dipole_ewald(double kc, double alpha, const double r[3], const double mui[3],
                                            const double muj[3], double f[3], double gi[3], double gj[3])
{
  const double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2], rr = sqrt(r2), ir2 = 1.0 / r2;
  const double a2 = 2.0 * alpha * alpha, g = exp(-alpha * alpha * r2) / (alpha * sqrt(M_PI));
  const double B1 = (erfc(alpha * rr) / rr + a2 * g) * ir2, B2 = (3.0 * B1 + a2 * a2 * g) * ir2,
               B3 = (5.0 * B2 + a2 * a2 * a2 * g) * ir2;
  const double pij = mui[0] * muj[0] + mui[1] * muj[1] + mui[2] * muj[2];
  const double pi = mui[0] * r[0] + mui[1] * r[1] + mui[2] * r[2], pj = muj[0] * r[0] + muj[1] * r[1] + muj[2] * r[2];
  for (int c = 0; c < 3; c++) {
    f[c] = kc * ((B2 * pij - B3 * pi * pj) * r[c] + B2 * (pj * mui[c] + pi * muj[c]));
    gi[c] = kc * (B1 * muj[c] - B2 * pj * r[c]);
    gj[c] = kc * (B1 * mui[c] - B2 * pi * r[c]);
  }
  return kc * (B1 * pij - B2 * pi * pj);
}

#endif
