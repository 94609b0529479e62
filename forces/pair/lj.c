/* Lennard-Jones pair kernel. */
#include "lj.h"

#include <math.h>

static double lj_u(const rl_lj_coef *c, double r, double *du)
{
  double ir2 = 1.0 / (r * r), ir6 = ir2 * ir2 * ir2;
  if (du) *du = (-12.0 * c->c12 * ir6 + 6.0 * c->c6) * ir6 / r;
  return (c->c12 * ir6 - c->c6) * ir6;
}

void rl_lj_coef_init(rl_lj_coef *c, double sigma, double epsilon, rl_lj_truncation trunc,
                     double rc, double rsw)
{
  double s6 = pow(sigma, 6.0);
  c->sigma = sigma;
  c->epsilon = epsilon;
  c->c6 = 4.0 * epsilon * s6;
  c->c12 = 4.0 * epsilon * s6 * s6;
  c->rc = rc;
  c->rsw = rsw;
  c->trunc = trunc;
  c->eshift = 0.0;
  c->fshift = 0.0;
  if (trunc == RL_LJ_SHIFTED || trunc == RL_LJ_SHIFTED_FORCE) c->eshift = lj_u(c, rc, &c->fshift);
  if (trunc != RL_LJ_SHIFTED_FORCE) c->fshift = 0.0;
}

double rl_lj_pair(const rl_lj_coef *c, double r2, double *fscal)
{
  double ir2 = 1.0 / r2, ir6 = ir2 * ir2 * ir2;
  double u = (c->c12 * ir6 - c->c6) * ir6;
  double fr = (12.0 * c->c12 * ir6 - 6.0 * c->c6) * ir6 * ir2; /* -u'(r)/r */
  switch (c->trunc) {
  case RL_LJ_PLAIN: break;
  case RL_LJ_SHIFTED: u -= c->eshift; break;
  case RL_LJ_SHIFTED_FORCE: {
    double r = sqrt(r2);
    u -= c->eshift + (r - c->rc) * c->fshift;
    fr += c->fshift / r;
    break;
  }
  case RL_LJ_SWITCHED: {
    double r = sqrt(r2);
    if (r >= c->rc) { *fscal = 0.0; return 0.0; }
    if (r > c->rsw) {
      double w = c->rc - c->rsw, x = (r - c->rsw) / w;
      double S = 1.0 + x * x * x * (-10.0 + x * (15.0 - 6.0 * x));
      double dS = x * x * (-30.0 + x * (60.0 - 30.0 * x)) / w;
      fr = fr * S - u * dS / r;
      u *= S;
    }
    break;
  }
  }
  *fscal = fr;
  return u;
}

/* Gauss-Legendre, 20 points, on [a, b] of the switch-region integrands. */
static void switch_region(const rl_lj_coef *c, double *e, double *w)
{
  static const double xg[10] = {0.0765265211334973, 0.2277858511416451, 0.3737060887154195,
                                0.5108670019508271, 0.6360536807265150, 0.7463319064601508,
                                0.8391169718222188, 0.9122344282513259, 0.9639719272779138,
                                0.9931285991850949};
  static const double wg[10] = {0.1527533871307258, 0.1491729864726037, 0.1420961093183820,
                                0.1316886384491766, 0.1181945319615184, 0.1019301198172404,
                                0.0832767415767048, 0.0626720483341091, 0.0406014298003869,
                                0.0176140071391521};
  double a = c->rsw, b = c->rc, h = 0.5 * (b - a), m = 0.5 * (a + b);
  double se = 0.0, sw = 0.0;
  for (int k = 0; k < 20; k++) {
    double r = m + h * (k < 10 ? -xg[k] : xg[k - 10]), wk = wg[k % 10];
    double du, u = lj_u(c, r, &du);
    double x = (r - a) / (b - a);
    double S = 1.0 + x * x * x * (-10.0 + x * (15.0 - 6.0 * x));
    double dS = x * x * (-30.0 + x * (60.0 - 30.0 * x)) / (b - a);
    /* u - U = u (1 - S);  d/dr = u' (1 - S) - u S' */
    se += wk * r * r * u * (1.0 - S);
    sw += wk * r * r * r * (du * (1.0 - S) - u * dS);
  }
  *e += h * se;
  *w += h * sw;
}

void rl_lj_tail(const rl_lj_coef *c, double *e, double *w)
{
  /* int_rc^inf r^2 u dr = c12/(9 rc^9) - c6/(3 rc^3);
   * int_rc^inf r^3 u' dr = -12 c12/(9 rc^9) + 6 c6/(3 rc^3). */
  double rc3 = c->rc * c->rc * c->rc, rc9 = rc3 * rc3 * rc3;
  *e = c->c12 / (9.0 * rc9) - c->c6 / (3.0 * rc3);
  *w = -12.0 * c->c12 / (9.0 * rc9) + 2.0 * c->c6 / rc3;
  if (c->trunc == RL_LJ_SWITCHED && c->rsw < c->rc) switch_region(c, e, w);
}
