/* The reaction field as the electrostatics of the pair rows (OpenMM 7.7 CutoffPeriodic; the
 * reference is coulomb_rf.c and dipole.c): charge pairs kc q_a q_b (1/r + krf r^2 - crf),
 * dipole pairs kc [mu_i.mu_j / r^3 - 3 (mu_i.r)(mu_j.r) / r^5 - 2 krf mu_i.mu_j].  The
 * interface is elec.h's. */
#ifndef ROTLEAP_PAIR_ELEC_RF_H
#define ROTLEAP_PAIR_ELEC_RF_H

#include "elec.h"

#define RL_ELEC_CHARGES 1
#define RL_ELEC_DIPOLES 1

/* rl_coulomb_rf_pair per qq: u = 1/r + krf r^2 - crf, fs = 1/r^3 - 2 krf */
RL_INLINE double rl_elec_qq(const rl_kelec E, double r2, double ir, double *fs)
{
  *fs = ir * ir * ir - 2.0 * E.krf;
  return ir + E.krf * r2 - E.crf;
}

/* The same on vectors of type VT (V1 broadcasts a double, FMA fuses a * b + c; RL_ELEC_QQ_VEC). */
#define RL_ELEC_RF_QQ(VT, V1, FMA)                                                             \
  *fs = ir * ir * ir - V1(2.0 * E.krf);                                                        \
  *u = FMA(V1(E.krf), r2, ir) - V1(E.crf)

/* rl_dipole_dipole_rf (dd_plain in dipole.c): the bare dipolar terms of elec.h, less 2 krf per
 * mu_i.mu_j in the energy and the fields */
RL_INLINE rl_dd rl_elec_dd(const rl_kelec E, double rx, double ry, double rz, double r2, double ir,
                           double mix, double miy, double miz, double mjx, double mjy, double mjz)
{
  const rl_dd_bare t = rl_dd_bare_of(rx, ry, rz, ir, mix, miy, miz, mjx, mjy, mjz);
  const double kc = E.kc, krf = E.krf;
  rl_dd d;
  d.fx = -kc * t.drx; d.fy = -kc * t.dry; d.fz = -kc * t.drz;
  d.gix = kc * (t.gix - 2.0 * krf * mjx); d.giy = kc * (t.giy - 2.0 * krf * mjy);
  d.giz = kc * (t.giz - 2.0 * krf * mjz);
  d.gjx = kc * (t.gjx - 2.0 * krf * mix); d.gjy = kc * (t.gjy - 2.0 * krf * miy);
  d.gjz = kc * (t.gjz - 2.0 * krf * miz);
  d.u = kc * (t.g0 - 2.0 * krf * t.pij);
  (void)r2;
  return d;
}

/* The regrouped vector form (rl_dd8 in elec.h): K = kc, A = kc (1/r^3 - 2 krf). */
#define RL_ELEC_RF_DD(VT, V1)                                                                  \
  const VT m3 = V1(-3.0) * ir5, e15 = V1(-5.0) * m3 * pi * pj * ir2;                           \
  const VT Kd = V1(E.kc);                                                                      \
  d.A = Kd * (ir3 - V1(2.0 * E.krf));                                                          \
  d.s = frl - Kd * (m3 * pij + e15);                                                           \
  d.Bj = Kd * m3 * pj;                                                                         \
  d.Bi = Kd * m3 * pi;                                                                         \
  (void)rr;                                                                                    \
  (void)ir

RL_ELEC_QQ_VEC(RL_ELEC_RF_QQ)

RL_ELEC_DD_VEC(RL_ELEC_RF_DD)

#endif
