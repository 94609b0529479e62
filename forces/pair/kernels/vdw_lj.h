/* Lennard-Jones with the four truncations (rl_lj_pair), branch-free, for the rows: on scalars
 * (the portable rows' omp simd loops) and, as RL_LJ_VEC, on any vector type. */
#ifndef ROTLEAP_PAIR_VDW_LJ_H
#define ROTLEAP_PAIR_VDW_LJ_H

#include "kernel.h"

#include <math.h>

/* The LJ coefficients of one term, copied by value into the loop: a load through a pointer
 * inside an `omp simd` loop becomes a masked load after if-conversion, which AVX2 lacks and
 * which stopped GCC 12 from vectorising the whole loop. */
typedef struct {
  double c6, c12, eshift, fshift;
} lj_consts;

RL_INLINE lj_consts lj_of(const fast_term *T)
{
  lj_consts c = {T->c6, T->c12, T->eshift, T->fshift};
  return c;
}

/* rl_lj_pair, branch-free, given ir2 = 1 / r2 (a kernel that has 1 / r from rl_rsqrt passes
 * its square, and saves a divide) */
RL_INLINE double lj_eval_ir2(const int trunc, const lj_consts C, double rc, double rsw, double r2,
                             double ir2, double *fr)
{
  double ir6 = ir2 * ir2 * ir2;
  double u = (C.c12 * ir6 - C.c6) * ir6;
  double f = (12.0 * C.c12 * ir6 - 6.0 * C.c6) * ir6 * ir2;
  if (trunc == RL_LJ_SHIFTED) {
    u -= C.eshift;
  } else if (trunc == RL_LJ_SHIFTED_FORCE) {
    double r = sqrt(r2);
    u -= C.eshift + (r - rc) * C.fshift;
    f += C.fshift / r;
  } else if (trunc == RL_LJ_SWITCHED) {
    double r = sqrt(r2);
    double w = rc - rsw, x = (r - rsw) / w;
    double S = 1.0 + x * x * x * (-10.0 + x * (15.0 - 6.0 * x));
    double dS = x * x * (-30.0 + x * (60.0 - 30.0 * x)) / w;
    double fsw = f * S - u * dS / r, usw = u * S;
    int sw = r > rsw, out = r >= rc;
    f = sw ? fsw : f;
    u = sw ? usw : u;
    f = out ? 0.0 : f;
    u = out ? 0.0 : u;
  }
  *fr = f;
  return u;
}

RL_INLINE double lj_eval(const int trunc, const lj_consts C, double rc, double rsw, double r2,
                         double *fr)
{
  return lj_eval_ir2(trunc, C, rc, rsw, r2, 1.0 / r2, fr);
}

/* lj_eval_ir2 on a vector type VT (lj8, lj4), given ir2 = 1 / r^2 and, for the truncations,
 * rr = |r| and ir = 1 / |r|; V1 broadcasts, SEL(rr, a, b) is b beyond r_switch, 0 beyond the
 * cutoff, else a. */
#define RL_LJ_VEC(VT, V1, SEL)                                                                 \
  const VT ir6 = ir2 * ir2 * ir2;                                                              \
  VT ul = (V1(C.c12) * ir6 - V1(C.c6)) * ir6;                                                  \
  VT frl = (V1(12.0 * C.c12) * ir6 - V1(6.0 * C.c6)) * ir6 * ir2;                              \
  if (TRUNC == RL_LJ_SHIFTED) {                                                                \
    ul = ul - V1(C.eshift);                                                                    \
  } else if (TRUNC == RL_LJ_SHIFTED_FORCE) {                                                   \
    ul = ul - (V1(C.eshift) + (rr - V1(B->rc)) * V1(C.fshift));                                \
    frl = frl + V1(C.fshift) * ir;                                                             \
  } else if (TRUNC == RL_LJ_SWITCHED) {                                                        \
    const double w = B->rc - B->rsw;                                                           \
    const VT x = (rr - V1(B->rsw)) * V1(1.0 / w);                                              \
    const VT Sw = V1(1.0) + x * x * x * (V1(-10.0) + x * (V1(15.0) - V1(6.0) * x));           \
    const VT dS = x * x * (V1(-30.0) + x * (V1(60.0) - V1(30.0) * x)) * V1(1.0 / w);          \
    const VT fsw = frl * Sw - ul * dS * ir, usw = ul * Sw;                                     \
    frl = SEL(rr, frl, fsw);                                                                   \
    ul = SEL(rr, ul, usw);                                                                     \
  }                                                                                            \
  *u = ul;                                                                                     \
  *fr = frl

#endif
