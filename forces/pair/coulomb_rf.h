/* Reaction-field Coulomb pair kernel (internal), OpenMM 7.7 NonbondedForce.CutoffPeriodic:
 *   U = kc q_i q_j (1/r + krf r^2 - crf),
 *   krf = (eps_rf - 1) / ((2 eps_rf + 1) rc^3)   (1/(2 rc^3) for eps_rf = infinity),
 *   crf = 1/rc + krf rc^2.
 * krf is formed once, here (the pair loops, the kernels' rows (kernels/elec/rf.h) and the dipole terms all read
 * rl_rf_coef), from x = 1/eps_rf, so it tends continuously to the conducting limit and never
 * overflows. */
#ifndef ROTLEAP_MODELS_COULOMB_RF_H
#define ROTLEAP_MODELS_COULOMB_RF_H

typedef struct {
  double krf, crf, rc;
} rl_rf_coef;

/* out c; in eps_rf >= 1 (INFINITY allowed), rc > 0. */
void rl_rf_coef_init(rl_rf_coef *c, double eps_rf, double rc);

/* in  c, qq = kc q_i q_j, r2 = |r_ij|^2 > 0
 * out *fscal: force on i = fscal * r_ij
 * returns the pair energy. */
double rl_coulomb_rf_pair(const rl_rf_coef *c, double qq, double r2, double *fscal);

/* The reaction-field term alone, kc q_i q_j (krf r^2 - crf), which GROMACS adds for excluded
 * pairs (OpenMM 7.7 does not); in/out as rl_coulomb_rf_pair. */
double rl_coulomb_rf_excluded(const rl_rf_coef *c, double qq, double r2, double *fscal);

#endif
