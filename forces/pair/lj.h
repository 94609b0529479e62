/* Lennard-Jones pair kernel with selectable truncation (internal).
 *
 *   u(r) = 4 eps [(sigma/r)^12 - (sigma/r)^6]
 *   plain          U = u(r)
 *   shifted        U = u(r) - u(rc)
 *   shifted force  U = u(r) - u(rc) - (r - rc) u'(rc)
 *   switched       U = u(r) S(r), S = 1 - 6x^5 + 15x^4 - 10x^3, x = (r - rsw)/(rc - rsw) for
 *                  rsw < r < rc, S = 1 below rsw, 0 from rc on (OpenMM's switching function)
 * The kernel does not apply the cutoff itself except for the switch (S = 0 for r >= rc): the
 * caller decides which pairs interact (site or molecule scheme). */
#ifndef ROTLEAP_MODELS_LJ_H
#define ROTLEAP_MODELS_LJ_H

#include "rotleap/forcefield.h"

typedef struct {
  double sigma, epsilon; /* mixed parameters                         */
  double c6, c12;        /* 4 eps sigma^6, 4 eps sigma^12             */
  double rc, rsw;        /* cutoff, switching distance                */
  double eshift, fshift; /* u(rc); u'(rc) (shifted force only)        */
  rl_lj_truncation trunc;
} rl_lj_coef;

/* out c; in sigma >= 0, epsilon >= 0, trunc, rc > 0, rsw (switched: 0 <= rsw < rc). */
void rl_lj_coef_init(rl_lj_coef *c, double sigma, double epsilon, rl_lj_truncation trunc,
                     double rc, double rsw);

/* in  c, r2 = |r_ij|^2 > 0
 * out *fscal: the force on i is fscal * r_ij (r_ij = r_i - r_j)
 * returns the pair energy. */
double rl_lj_pair(const rl_lj_coef *c, double r2, double *fscal);

/* Long-range (dispersion) correction integrals for one site pair beyond what the truncated
 * potential includes: e = int_0^inf r^2 [u(r) - U(r)] dr and w = int_0^inf r^3 d[u - U]/dr dr,
 * counting only r >= rc for plain/shifted/shifted-force (the tail of u itself) and the switch
 * region plus the tail for switched.  Energy per pair density: E_corr = 2 pi / V sum N_a N_b e;
 * pressure P_corr = -2 pi / (3 V^2) sum N_a N_b w. */
void rl_lj_tail(const rl_lj_coef *c, double *e, double *w);

#endif
