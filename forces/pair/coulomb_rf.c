/* Reaction-field Coulomb pair kernel. */
#include "coulomb_rf.h"

#include <math.h>

void rl_rf_coef_init(rl_rf_coef *c, double eps_rf, double rc)
{
  /* krf = (eps - 1) / ((2 eps + 1) rc^3), formed in x = 1/eps as (1 - x) / ((2 + x) rc^3): nothing
   * overflows (2 eps + 1 did from eps ~ 9e307 on, and krf became 0, the eps = 1 value), eps = Inf
   * gives x = 0 and the conducting 1/(2 rc^3) exactly, and as eps grows krf tends to it
   * continuously, by -3x/(2 (2 + x) rc^3), until x is below round-off of 2 (eps > ~1e16), where
   * it is that number. */
  const double rc3 = rc * rc * rc, x = 1.0 / eps_rf;
  c->rc = rc;
  c->krf = (1.0 - x) / ((2.0 + x) * rc3);
  c->crf = 1.0 / rc + c->krf * rc * rc;
}

double rl_coulomb_rf_pair(const rl_rf_coef *c, double qq, double r2, double *fscal)
{
  double ir = 1.0 / sqrt(r2);
  *fscal = qq * (ir * ir * ir - 2.0 * c->krf);
  return qq * (ir + c->krf * r2 - c->crf);
}

double rl_coulomb_rf_excluded(const rl_rf_coef *c, double qq, double r2, double *fscal)
{
  *fscal = -2.0 * qq * c->krf;
  return qq * (c->krf * r2 - c->crf);
}
