/* Shifted-force dipoles as the electrostatics of the Stockmayer rows (Allen & Germano 2006;
 * LAMMPS lj/sf/dipole/sf; the reference is rl_dipole_dipole_sf in dipole.c): the bare
 * dipole-dipole energy times b(x) = 1 - 4 x^3 + 3 x^4, x = r / rc, which vanishes with its
 * derivative at rc.  Dipoles only (charges take the reaction field).  The interface is elec.h's. */
#ifndef ROTLEAP_PAIR_ELEC_SF_H
#define ROTLEAP_PAIR_ELEC_SF_H

#include "elec.h"

#define RL_ELEC_CHARGES 0
#define RL_ELEC_DIPOLES 1

RL_INLINE rl_dd rl_elec_dd(const rl_kelec E, double rx, double ry, double rz, double r2, double ir,
                           double mix, double miy, double miz, double mjx, double mjy, double mjz)
{
  const rl_dd_bare t = rl_dd_bare_of(rx, ry, rz, ir, mix, miy, miz, mjx, mjy, mjz);
  const double kc = E.kc, rc = E.rc;
  const double rr = sqrt(r2);
  const double x = rr / rc;
  const double bb = 1.0 + x * x * x * (-4.0 + 3.0 * x);
  const double db = x * x * (-12.0 + 12.0 * x) / rc;
  rl_dd d;
  d.fx = -kc * (bb * t.drx + t.g0 * db * rx / rr);
  d.fy = -kc * (bb * t.dry + t.g0 * db * ry / rr);
  d.fz = -kc * (bb * t.drz + t.g0 * db * rz / rr);
  d.gix = t.gix * (kc * bb); d.giy = t.giy * (kc * bb); d.giz = t.giz * (kc * bb);
  d.gjx = t.gjx * (kc * bb); d.gjy = t.gjy * (kc * bb); d.gjz = t.gjz * (kc * bb);
  d.u = kc * bb * t.g0;
  return d;
}

/* The regrouped vector form: K = kc b(x), A = K / r^3, and the radial force takes the
 * derivative of b. */
#define RL_ELEC_SF_DD(VT, V1)                                                                  \
  const VT m3 = V1(-3.0) * ir5, e15 = V1(-5.0) * m3 * pi * pj * ir2;                           \
  const VT x = rr * V1(1.0 / E.rc);                                                            \
  const VT bb = V1(1.0) + x * x * x * (V1(-4.0) + V1(3.0) * x);                                \
  const VT db = x * x * (V1(-12.0) + V1(12.0) * x) * V1(1.0 / E.rc);                           \
  const VT g0 = pij * ir3 + m3 * pi * pj;                                                      \
  const VT Kd = V1(E.kc) * bb;                                                                 \
  d.A = Kd * ir3;                                                                              \
  d.s = frl - Kd * (m3 * pij + e15) - V1(E.kc) * g0 * db * ir;                                 \
  d.Bj = Kd * m3 * pj;                                                                         \
  d.Bi = Kd * m3 * pi

RL_ELEC_DD_VEC(RL_ELEC_SF_DD)

#endif
