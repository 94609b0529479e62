/* The real-space part of the Ewald sum as the electrostatics of the pair rows (issue 33; the
 * reference is rl_coulomb_ewald_pair and rl_dipole_dipole_ewald in coulomb_ewald.h, with the C
 * library's erfc, and the term "ewald-real", forces/ewald/ewald_real.c), plain cutoff (no shift,
 * as OpenMM's PME and Ewald and LAMMPS's lj/cut/dipole/long):
 *   charge pairs kc q_a q_b erfc(alpha r) / r, the force on i
 *     kc q_a q_b [erfc(alpha r) / r + (2 alpha / sqrt(pi)) exp(-alpha^2 r^2)] r / r^2;
 *   point-dipole pairs (the Stockmayer rows) kc [B_1(r) mu_i.mu_j - B_2(r) (mu_i.r)(mu_j.r)] with
 *     the screened B_l of forces/ewald/ewald_dipole.h (Allen & Tildesley's B and C):
 *     B_0 = erfc(alpha r) / r, B_l = [(2l - 1) B_{l-1} + (2 alpha^2)^(l-1) c2a exp(-alpha^2 r^2)] / r^2;
 *     the force on i kc {[B_2 mu_i.mu_j - B_3 (mu_i.r)(mu_j.r)] r + B_2 [(mu_j.r) mu_i + (mu_i.r) mu_j]},
 *     the fields dU/dmu_i = kc [B_1 mu_j - B_2 (mu_j.r) r] (and i, j swapped).
 * No charge-dipole pairs (the pair term refuses them with Ewald).  The interface is elec.h's;
 * alpha and c2a = 2 alpha / sqrt(pi) are members of rl_kelec.
 *
 * erfc(x) = exp(-x^2) g(x), both from forces/ewald/erfc.h (<= 1e-15 relative against the C
 * library, tests/forces/ewald/test_ewald_erfc.c): the portable rows call rl_erfc_exp, which
 * vectorises under omp simd; the register rows (AVX-512, AVX2) evaluate the same polynomials
 * here in intrinsics (RL_EW_EXP_G), with the exact square of x from one FMA (x^2 = p + e,
 * e = fma(x, x, -p)) instead of Dekker's split, which -ffp-contract=fast (the rows' flag) could
 * fuse away.  No single-precision (mixed) rows: the mixed precision's TIP4P rows stay reaction
 * field only. */
#ifndef ROTLEAP_PAIR_ELEC_EWALD_H
#define ROTLEAP_PAIR_ELEC_EWALD_H

#include "elec.h"
#include "../../../ewald/erfc.h"

#define RL_ELEC_CHARGES 1
#define RL_ELEC_DIPOLES 1

/* u = erfc(alpha r) / r, fs = (u + c2a exp(-alpha^2 r^2)) / r^2 with r = r2 ir */
RL_INLINE double rl_elec_qq(const rl_kelec E, double r2, double ir, double *fs)
{
  double ex;
  const double u = rl_erfc_exp(E.alpha * (r2 * ir), &ex) * ir;
  *fs = (u + E.c2a * ex) * ir * ir;
  return u;
}

/* rl_dipole_dipole_ewald (coulomb_ewald.h) with erfc.h's erfc */
RL_INLINE rl_dd rl_elec_dd(const rl_kelec E, double rx, double ry, double rz, double r2, double ir,
                           double mix, double miy, double miz, double mjx, double mjy, double mjz)
{
  double ex;
  const double ec = rl_erfc_exp(E.alpha * (r2 * ir), &ex), ir2 = ir * ir;
  const double ce = E.c2a * ex, a2 = 2.0 * E.alpha * E.alpha;
  const double B1 = (ec * ir + ce) * ir2, B2 = (3.0 * B1 + a2 * ce) * ir2, B3 = (5.0 * B2 + a2 * a2 * ce) * ir2;
  const double kc = E.kc;
  const double pij = mix * mjx + miy * mjy + miz * mjz;
  const double pi = mix * rx + miy * ry + miz * rz;
  const double pj = mjx * rx + mjy * ry + mjz * rz;
  const double s = kc * (B2 * pij - B3 * pi * pj), ki = kc * B2 * pi, kj = kc * B2 * pj, k1 = kc * B1;
  rl_dd d;
  d.fx = s * rx + kj * mix + ki * mjx;
  d.fy = s * ry + kj * miy + ki * mjy;
  d.fz = s * rz + kj * miz + ki * mjz;
  d.gix = k1 * mjx - kj * rx; d.giy = k1 * mjy - kj * ry; d.giz = k1 * mjz - kj * rz;
  d.gjx = k1 * mix - ki * rx; d.gjy = k1 * miy - ki * ry; d.gjz = k1 * miz - ki * rz;
  d.u = kc * (B1 * pij - B2 * pi * pj);
  return d;
}

#if RL_X512
/* The same on vectors: VT the lanes, VI the integer lanes of the same width (for 2^k), MT a
 * mask, LT(a, b) the mask a < b, SEL(m, a, b) a where m else b, FMA(a, b, c) = a b + c. */
#define RL_EW_STEP(FMA, SEL, V1, j) g = FMA(g, t, SEL(lo, V1(rl_erfc_c0[j]), V1(rl_erfc_c1[j])))
/* From x = alpha r (VT, assignable): e = exp(-x^2) and g = g(x) (erfc(x) = e g), both 0 from
 * RL_ERFC_XMAX on. */
#define RL_EW_EXP_G(VT, VI, MT, V1, FMA, LT, SEL)                                              \
    const VT zero = V1(0.0), magic = V1(6755399441055744.0); /* 1.5 2^52 */                    \
    const MT in = LT(x, V1(RL_ERFC_XMAX));                                                     \
    x = SEL(in, x, zero);                                                                      \
    /* exp(-x^2): -x^2 = yh + yl exactly */                                                    \
    const VT yh = zero - x * x, yl = zero - FMA(x, x, yh);                                     \
    const VT kt = FMA(yh, V1(1.4426950408889634), magic), k = kt - magic;                      \
    const VT r = FMA(k, V1(-1.90821492927058770002e-10), FMA(k, V1(-6.93147180369123816490e-01), yh)) + yl; \
    VT p = V1(1.0 / 6227020800.0);                                                             \
    p = FMA(p, r, V1(1.0 / 479001600.0));                                                      \
    p = FMA(p, r, V1(1.0 / 39916800.0));                                                       \
    p = FMA(p, r, V1(1.0 / 3628800.0));                                                        \
    p = FMA(p, r, V1(1.0 / 362880.0));                                                         \
    p = FMA(p, r, V1(1.0 / 40320.0));                                                          \
    p = FMA(p, r, V1(1.0 / 5040.0));                                                           \
    p = FMA(p, r, V1(1.0 / 720.0));                                                            \
    p = FMA(p, r, V1(1.0 / 120.0));                                                            \
    p = FMA(p, r, V1(1.0 / 24.0));                                                             \
    p = FMA(p, r, V1(1.0 / 6.0));                                                              \
    p = FMA(p, r, V1(0.5));                                                                    \
    p = FMA(p, r, V1(1.0));                                                                    \
    p = FMA(p, r, V1(1.0));                                                                    \
    const VI sb = (((VI)kt - (VI)magic) + 1023) << 52; /* 2^k */                               \
    const VT e = SEL(in, p * (VT)sb, zero);                                                    \
    /* g(x): the piece's polynomial in t, s = 1 / (1 + x) */                                   \
    const MT lo = LT(x, V1(RL_ERFC_XSPLIT));                                                   \
    const VT s = V1(1.0) / (V1(1.0) + x);                                                      \
    const VT t = (s - SEL(lo, V1(RL_ERFC_SC0), V1(RL_ERFC_SC1))) *                             \
                 SEL(lo, V1(RL_ERFC_SIH0), V1(RL_ERFC_SIH1));                                  \
    VT g = SEL(lo, V1(rl_erfc_c0[18]), V1(rl_erfc_c1[18]));                                    \
    RL_EW_STEP(FMA, SEL, V1, 17); RL_EW_STEP(FMA, SEL, V1, 16); RL_EW_STEP(FMA, SEL, V1, 15); RL_EW_STEP(FMA, SEL, V1, 14);\
    RL_EW_STEP(FMA, SEL, V1, 13); RL_EW_STEP(FMA, SEL, V1, 12); RL_EW_STEP(FMA, SEL, V1, 11); RL_EW_STEP(FMA, SEL, V1, 10);\
    RL_EW_STEP(FMA, SEL, V1, 9); RL_EW_STEP(FMA, SEL, V1, 8); RL_EW_STEP(FMA, SEL, V1, 7); RL_EW_STEP(FMA, SEL, V1, 6);\
    RL_EW_STEP(FMA, SEL, V1, 5); RL_EW_STEP(FMA, SEL, V1, 4); RL_EW_STEP(FMA, SEL, V1, 3); RL_EW_STEP(FMA, SEL, V1, 2);\
    RL_EW_STEP(FMA, SEL, V1, 1); RL_EW_STEP(FMA, SEL, V1, 0)
#define RL_ELEC_EWALD_QQ_FN(ATTR, NAME, VT, VI, MT, V1, FMA, LT, SEL)                          \
  ATTR RL_INLINE void NAME(const rl_kelec E, VT r2, VT ir, VT *fs, VT *u)                       \
  {                                                                                            \
    VT x = V1(E.alpha) * (r2 * ir);                                                            \
    RL_EW_EXP_G(VT, VI, MT, V1, FMA, LT, SEL);                                                 \
    *u = e * g * ir;                                                                           \
    *fs = FMA(V1(E.c2a), e, *u) * ir * ir;                                                     \
  }
/* The dipole pair in the regrouped form of elec.h (rl_dd8, rl_dd4): A = kc B_1,
 * Bi = -kc B_2 (mu_i.r), Bj = -kc B_2 (mu_j.r), s = frl + kc [B_2 mu_i.mu_j - B_3 (mu_i.r)(mu_j.r)]. */
#define RL_ELEC_EWALD_DD_FN(ATTR, NAME, DT, VT, VI, MT, V1, FMA, LT, SEL)                      \
  ATTR RL_INLINE DT NAME(const rl_kelec E, VT frl, VT rr, VT ir, VT ir2, VT ir3, VT ir5, VT pij,  \
                         VT pi, VT pj)                                                         \
  {                                                                                            \
    VT x = V1(E.alpha) * rr;                                                                   \
    RL_EW_EXP_G(VT, VI, MT, V1, FMA, LT, SEL);                                                 \
    const VT ce = V1(E.c2a) * e, a2 = V1(2.0 * E.alpha * E.alpha);                             \
    const VT B1 = (e * g * ir + ce) * ir2, B2 = (V1(3.0) * B1 + a2 * ce) * ir2;                 \
    const VT B3 = (V1(5.0) * B2 + a2 * a2 * ce) * ir2, Kd = V1(E.kc), KB2 = Kd * B2;            \
    DT d;                                                                                      \
    d.A = Kd * B1;                                                                             \
    d.Bi = zero - KB2 * pi;                                                                    \
    d.Bj = zero - KB2 * pj;                                                                    \
    d.s = frl + Kd * (B2 * pij - B3 * pi * pj);                                                \
    (void)ir3;                                                                                 \
    (void)ir5;                                                                                 \
    return d;                                                                                  \
  }
#define RL_EW_LT8(a, b) _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ)
#define RL_EW_SEL8(m, a, b) _mm512_mask_blend_pd(m, b, a)
#define RL_EW_LT4(a, b) _mm256_cmp_pd(a, b, _CMP_LT_OQ)
#define RL_EW_SEL4(m, a, b) _mm256_blendv_pd(b, a, m)
RL_ELEC_EWALD_QQ_FN(RL_T512, rl_elec_qq8, __m512d, __m512i, __mmask8, _mm512_set1_pd, _mm512_fmadd_pd,
                    RL_EW_LT8, RL_EW_SEL8)
RL_ELEC_EWALD_QQ_FN(RL_T256, rl_elec_qq4, __m256d, __m256i, __m256d, _mm256_set1_pd, _mm256_fmadd_pd,
                    RL_EW_LT4, RL_EW_SEL4)
RL_ELEC_EWALD_DD_FN(RL_T512, rl_elec_dd8, rl_dd8, __m512d, __m512i, __mmask8, _mm512_set1_pd,
                    _mm512_fmadd_pd, RL_EW_LT8, RL_EW_SEL8)
RL_ELEC_EWALD_DD_FN(RL_T256, rl_elec_dd4, rl_dd4, __m256d, __m256i, __m256d, _mm256_set1_pd,
                    _mm256_fmadd_pd, RL_EW_LT4, RL_EW_SEL4)
#endif

#endif
