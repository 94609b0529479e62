/* The electrostatics of the pair rows: what each header of this folder (rf.h, sf.h) provides,
 * and the types and helpers they share.
 *
 * An electrostatics is a header of this folder that a row file includes before its row
 * template (kernels/<instruction set>/<pattern>_row.h), so that each row is compiled once per
 * electrostatics without being copied.  It provides, for the pair geometry the row has formed,
 * the pair function on each lane type the rows use, reading its parameters from rl_kelec
 * (kernel.h) by value:
 *   charges (RL_ELEC_CHARGES):  the energy and the radial force of one charge pair per kc q_a q_b
 *     double  rl_elec_qq  (E, r2, ir, &fs)        returns u; the force on i is qq fs r
 *     void    rl_elec_qq8 (E, r2, ir, &fs, &u)    AVX-512, 8 doubles
 *     void    rl_elec_qq4 (E, r2, ir, &fs, &u)    AVX2, 4 doubles
 *     void    rl_elec_qq8f(E, r2, ir, &fs, &u)    AVX2, 8 floats (mixed precision)
 *   dipoles (RL_ELEC_DIPOLES):  the dipole-dipole pair
 *     rl_dd   rl_elec_dd  (E, r, r2, ir, mu_i, mu_j)     energy, force on i, fields dU/dmu
 *     rl_dd8  rl_elec_dd8 (E, frl, rr, ir, ir2, ir3, ir5, pij, pi, pj)   AVX-512, regrouped
 *     rl_dd4  rl_elec_dd4 (the same)                                     AVX2
 * with r2 = |r|^2, ir = 1/|r| (the row's own 1/sqrt), rr = |r|.  The row applies the cutoff,
 * the charges' product, the sums and the torques.  See docs/interactions.md, "Kernels".
 *
 * With r = r_i - r_j, pij = mu_i.mu_j, pi = mu_i.r, pj = mu_j.r and U = kc [B(r) pij - C(r)
 * pi pj], a dipolar electrostatics gives the force on i, F = -dU/dr, and the fields
 * g_i = dU/dmu_i, g_j = dU/dmu_j (the row forms the torques, -mu x g). */
#ifndef ROTLEAP_PAIR_ELEC_H
#define ROTLEAP_PAIR_ELEC_H

#include "../kernel.h"

#include <math.h>

/* One pair (the portable rows): energy, force on i, fields. */
typedef struct {
  double u, fx, fy, fz, gix, giy, giz, gjx, gjy, gjz;
} rl_dd;

/* The bare terms (B = 1/r^3, C = 3/r^5): dr = d[pij/r^3 - 3 pi pj/r^5]/dr, g the bare fields,
 * g0 the bare energy. */
typedef struct {
  double pij, pi, pj, drx, dry, drz, gix, giy, giz, gjx, gjy, gjz, g0;
} rl_dd_bare;

RL_INLINE rl_dd_bare rl_dd_bare_of(double rx, double ry, double rz, double ir, double mix,
                                   double miy, double miz, double mjx, double mjy, double mjz)
{
  const double ir2 = ir * ir, ir3 = ir * ir2, ir5 = ir3 * ir2;
  rl_dd_bare t;
  const double pij = mix * mjx + miy * mjy + miz * mjz;
  const double pi = mix * rx + miy * ry + miz * rz;
  const double pj = mjx * rx + mjy * ry + mjz * rz;
  const double e15 = 15.0 * pi * pj * ir5 * ir2;
  t.pij = pij; t.pi = pi; t.pj = pj;
  t.drx = -3.0 * ir5 * (pij * rx + mix * pj + mjx * pi) + e15 * rx;
  t.dry = -3.0 * ir5 * (pij * ry + miy * pj + mjy * pi) + e15 * ry;
  t.drz = -3.0 * ir5 * (pij * rz + miz * pj + mjz * pi) + e15 * rz;
  t.gix = mjx * ir3 - 3.0 * ir5 * pj * rx; t.giy = mjy * ir3 - 3.0 * ir5 * pj * ry;
  t.giz = mjz * ir3 - 3.0 * ir5 * pj * rz;
  t.gjx = mix * ir3 - 3.0 * ir5 * pi * rx; t.gjy = miy * ir3 - 3.0 * ir5 * pi * ry;
  t.gjz = miz * ir3 - 3.0 * ir5 * pi * rz;
  t.g0 = pij * ir3 - 3.0 * pi * pj * ir5;
  return t;
}

#if RL_X512
/* The register rows' regrouped form, on 8 (rl_dd8) or 4 (rl_dd4) lanes: the force on i is
 * s r - Bj mu_i - Bi mu_j, the fields g_i = A mu_j + Bj r and g_j = A mu_i + Bi r, and the
 * energy pij A + Bi pj; s includes the row's LJ radial factor frl (its -dU/dr / r). */
typedef struct {
  __m512d A, Bi, Bj, s;
} rl_dd8;
typedef struct {
  __m256d A, Bi, Bj, s;
} rl_dd4;

/* rl_elec_dd8 and rl_elec_dd4 from BODY(VT, V1), which sets d.A, d.Bi, d.Bj, d.s from E, frl,
 * rr, ir, ir2, ir3, ir5, pij, pi, pj (V1 broadcasts a double). */
#define RL_ELEC_DD_FN(ATTR, NAME, DT, VT, V1, BODY)                                             \
  ATTR RL_INLINE DT NAME(const rl_kelec E, VT frl, VT rr, VT ir, VT ir2, VT ir3, VT ir5, VT pij,  \
                         VT pi, VT pj)                                                         \
  {                                                                                            \
    DT d;                                                                                      \
    BODY(VT, V1);                                                                              \
    return d;                                                                                  \
  }
#define RL_ELEC_DD_VEC(BODY)                                                                   \
  RL_ELEC_DD_FN(RL_T512, rl_elec_dd8, rl_dd8, __m512d, _mm512_set1_pd, BODY)                   \
  RL_ELEC_DD_FN(RL_T256, rl_elec_dd4, rl_dd4, __m256d, _mm256_set1_pd, BODY)

/* rl_elec_qq8, rl_elec_qq4 and rl_elec_qq8f from BODY(VT, V1, FMA), which sets *fs and *u from
 * E, r2 and ir (V1 broadcasts a double, FMA fuses a * b + c). */
#define RL_V1F_(x) _mm256_set1_ps((float)(x))
#define RL_ELEC_QQ_FN(ATTR, NAME, VT, V1, FMA, BODY)                                          \
  ATTR RL_INLINE void NAME(const rl_kelec E, VT r2, VT ir, VT *fs, VT *u)                       \
  {                                                                                            \
    BODY(VT, V1, FMA);                                                                         \
  }
#define RL_ELEC_QQ_VEC(BODY)                                                                   \
  RL_ELEC_QQ_FN(RL_T512, rl_elec_qq8, __m512d, _mm512_set1_pd, _mm512_fmadd_pd, BODY)          \
  RL_ELEC_QQ_FN(RL_T256, rl_elec_qq4, __m256d, _mm256_set1_pd, _mm256_fmadd_pd, BODY)          \
  RL_ELEC_QQ_FN(RL_T256, rl_elec_qq8f, __m256, RL_V1F_, _mm256_fmadd_ps, BODY)
#else
#define RL_ELEC_DD_VEC(BODY)
#define RL_ELEC_QQ_VEC(BODY)
#endif

#endif
