/* The real-space part of the Ewald sum as the electrostatics of the pair rows (issue 33; the
 * reference is rl_coulomb_ewald_pair in coulomb_ewald.h, with the C library's erfc, and the term
 * "ewald-real", forces/ewald/ewald_real.c): charge pairs kc q_a q_b erfc(alpha r) / r with a
 * plain cutoff (no shift, as OpenMM's PME and Ewald), the force on i
 * kc q_a q_b [erfc(alpha r) / r + (2 alpha / sqrt(pi)) exp(-alpha^2 r^2)] r / r^2.  Charges only
 * (point dipoles with Ewald are refused at setup).  The interface is elec.h's; alpha and
 * c2a = 2 alpha / sqrt(pi) are members of rl_kelec.
 *
 * erfc(x) = exp(-x^2) g(x), both from forces/ewald/erfc.h (<= 1e-15 relative against the C
 * library, tests/forces/ewald/test_ewald_erfc.c): the portable rows call rl_erfc_exp, which
 * vectorises under omp simd; the register rows (AVX-512, AVX2) evaluate the same polynomials
 * here in intrinsics, with the exact square of x from one FMA (x^2 = p + e, e = fma(x, x, -p))
 * instead of Dekker's split, which -ffp-contract=fast (the rows' flag) could fuse away.  No
 * single-precision (mixed) rows: the mixed precision's TIP4P rows stay reaction field only. */
#ifndef ROTLEAP_PAIR_ELEC_EWALD_H
#define ROTLEAP_PAIR_ELEC_EWALD_H

#include "elec.h"
#include "../../../ewald/erfc.h"

#define RL_ELEC_CHARGES 1
#define RL_ELEC_DIPOLES 0

/* u = erfc(alpha r) / r, fs = (u + c2a exp(-alpha^2 r^2)) / r^2 with r = r2 ir */
RL_INLINE double rl_elec_qq(const rl_kelec E, double r2, double ir, double *fs)
{
  double ex;
  const double u = rl_erfc_exp(E.alpha * (r2 * ir), &ex) * ir;
  *fs = (u + E.c2a * ex) * ir * ir;
  return u;
}

#if RL_X512
/* The same on vectors: VT the lanes, VI the integer lanes of the same width (for 2^k), MT a
 * mask, LT(a, b) the mask a < b, SEL(m, a, b) a where m else b, FMA(a, b, c) = a b + c. */
#define RL_EW_STEP(FMA, SEL, V1, j) g = FMA(g, t, SEL(lo, V1(rl_erfc_c0[j]), V1(rl_erfc_c1[j])))
#define RL_ELEC_EWALD_QQ_FN(ATTR, NAME, VT, VI, MT, V1, FMA, LT, SEL)                          \
  ATTR RL_INLINE void NAME(const rl_kelec E, VT r2, VT ir, VT *fs, VT *u)                       \
  {                                                                                            \
    const VT zero = V1(0.0), magic = V1(6755399441055744.0); /* 1.5 2^52 */                    \
    VT x = V1(E.alpha) * (r2 * ir);                                                            \
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
    RL_EW_STEP(FMA, SEL, V1, 1); RL_EW_STEP(FMA, SEL, V1, 0);                                  \
    *u = e * g * ir;                                                                           \
    *fs = FMA(V1(E.c2a), e, *u) * ir * ir;                                                     \
  }
#define RL_EW_LT8(a, b) _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ)
#define RL_EW_SEL8(m, a, b) _mm512_mask_blend_pd(m, b, a)
#define RL_EW_LT4(a, b) _mm256_cmp_pd(a, b, _CMP_LT_OQ)
#define RL_EW_SEL4(m, a, b) _mm256_blendv_pd(b, a, m)
RL_ELEC_EWALD_QQ_FN(RL_T512, rl_elec_qq8, __m512d, __m512i, __mmask8, _mm512_set1_pd, _mm512_fmadd_pd,
                    RL_EW_LT8, RL_EW_SEL8)
RL_ELEC_EWALD_QQ_FN(RL_T256, rl_elec_qq4, __m256d, __m256i, __m256d, _mm256_set1_pd, _mm256_fmadd_pd,
                    RL_EW_LT4, RL_EW_SEL4)
#endif

#endif
