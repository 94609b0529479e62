/* Internal: the screened interaction functions of point charges and point dipoles (ewald.h).
 *
 * With B_0 = erfc(alpha r) / r and, for l >= 1,
 *   B_l(r) = [(2l - 1) B_{l-1}(r) + (2 alpha^2)^l / (alpha sqrt(pi)) exp(-alpha^2 r^2)] / r^2
 * (B_1 = [B_0 + (2 alpha / sqrt(pi)) e^{-alpha^2 r^2}] / r^2 and B_2 = [3 B_1 + (4 alpha^3 / sqrt(pi))
 * e^{-alpha^2 r^2}] / r^2, the B and C of Allen & Tildesley, 2nd ed., section 6.2; Aguado & Madden,
 * J. Chem. Phys. 119, 7471 (2003)), the real-space energy of sites i, j at r = r_i - r_j with
 * charges q and dipoles m is
 *   U_ij = kc [G0 B_0 + G1 B_1 + G2 B_2],  G0 = q_i q_j,  G1 = q_i (m_j.r) - q_j (m_i.r) + m_i.m_j,
 *                                          G2 = -(m_i.r)(m_j.r)
 * and since dB_l/dr = -r B_{l+1}
 *   F_i = kc {(G0 B_1 + G1 B_2 + G2 B_3) r - B_1 (q_i m_j - q_j m_i) + B_2 [(m_j.r) m_i + (m_i.r) m_j]}
 *   E_i = -dU/dm_i = kc {q_j B_1 r - B_1 m_j + B_2 (m_j.r) r}.
 * The same with erf in place of erfc (and the sign of the exponential terms turned) is the part
 * of the pair that the reciprocal sum holds: the intramolecular correction removes it. */
#ifndef ROTLEAP_FORCES_EWALD_DIPOLE_H
#define ROTLEAP_FORCES_EWALD_DIPOLE_H

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* B_0..B_3 of the erfc form at r > 0, from erfc(alpha r) and exp(-alpha^2 r^2). */
static inline void ew_erfc_b4(double alpha, double r, double ec, double ex, double B[4])
{
  const double ir2 = 1.0 / (r * r), a2 = 2.0 * alpha * alpha, g = ex / (alpha * sqrt(M_PI));
  B[0] = ec / r;
  B[1] = (B[0] + a2 * g) * ir2;
  B[2] = (3.0 * B[1] + a2 * a2 * g) * ir2;
  B[3] = (5.0 * B[2] + a2 * a2 * a2 * g) * ir2;
}

/* B_0..B_2 of the erf form, with their limits 2^(l+1) alpha^(2l+1) / ((2l + 1) sqrt(pi)) at r = 0. */
static inline void ew_erf_b(double alpha, double r, double B[3])
{
  const double a2 = 2.0 * alpha * alpha, g0 = 1.0 / (alpha * sqrt(M_PI));
  if (r == 0.0) {
    B[0] = a2 * g0;
    B[1] = a2 * a2 * g0 / 3.0;
    B[2] = a2 * a2 * a2 * g0 / 5.0;
    return;
  }
  const double ir2 = 1.0 / (r * r), g = exp(-alpha * alpha * r * r) * g0;
  B[0] = erf(alpha * r) / r;
  B[1] = (B[0] - a2 * g) * ir2;
  B[2] = (3.0 * B[1] - a2 * a2 * g) * ir2;
}

#endif
