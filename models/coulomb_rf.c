/* Reaction-field Coulomb pair kernel. */
#include "coulomb_rf.h"

#include <math.h>

void rl_rf_coef_init(rl_rf_coef *c, double eps_rf, double rc)
{
  double rc3 = rc * rc * rc;
  c->rc = rc;
  c->krf = isinf(eps_rf) ? 0.5 / rc3 : (eps_rf - 1.0) / ((2.0 * eps_rf + 1.0) * rc3);
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
