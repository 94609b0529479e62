/* Point-dipole pair kernels. */
#include "dipole.h"

#include <math.h>

static double dot(const double a[3], const double b[3])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* g0 and its derivatives: dg0/dr (vector), dg0/dmu_i, dg0/dmu_j. */
static double dd_plain(const double r[3], const double mui[3], const double muj[3],
                       double dr[3], double gi[3], double gj[3], double *rr)
{
  double r2 = dot(r, r), ir2 = 1.0 / r2, ir = sqrt(ir2), ir3 = ir * ir2, ir5 = ir3 * ir2;
  double pij = dot(mui, muj), pi = dot(mui, r), pj = dot(muj, r);
  for (int c = 0; c < 3; c++) {
    dr[c] = -3.0 * ir5 * (pij * r[c] + mui[c] * pj + muj[c] * pi) +
            15.0 * pi * pj * ir5 * ir2 * r[c];
    gi[c] = muj[c] * ir3 - 3.0 * ir5 * pj * r[c];
    gj[c] = mui[c] * ir3 - 3.0 * ir5 * pi * r[c];
  }
  *rr = sqrt(r2);
  return pij * ir3 - 3.0 * pi * pj * ir5;
}

double rl_dipole_dipole_rf(double kc, double krf, const double r[3], const double mui[3],
                           const double muj[3], double f[3], double gi[3], double gj[3])
{
  double dr[3], rr;
  double g0 = dd_plain(r, mui, muj, dr, gi, gj, &rr);
  for (int c = 0; c < 3; c++) {
    f[c] = -kc * dr[c];
    gi[c] = kc * (gi[c] - 2.0 * krf * muj[c]);
    gj[c] = kc * (gj[c] - 2.0 * krf * mui[c]);
  }
  return kc * (g0 - 2.0 * krf * dot(mui, muj));
}

double rl_dipole_dipole_sf(double kc, double rc, const double r[3], const double mui[3],
                           const double muj[3], double f[3], double gi[3], double gj[3])
{
  double dr[3], rr;
  double g0 = dd_plain(r, mui, muj, dr, gi, gj, &rr);
  double x = rr / rc;
  if (x >= 1.0) {
    for (int c = 0; c < 3; c++) f[c] = gi[c] = gj[c] = 0.0;
    return 0.0;
  }
  double b = 1.0 + x * x * x * (-4.0 + 3.0 * x);
  double db = x * x * (-12.0 + 12.0 * x) / rc; /* d b / d r */
  for (int c = 0; c < 3; c++) {
    f[c] = -kc * (b * dr[c] + g0 * db * r[c] / rr);
    gi[c] *= kc * b;
    gj[c] *= kc * b;
  }
  return kc * b * g0;
}

double rl_charge_dipole_rf(double kc, double krf, const double r[3], double q,
                           const double mu[3], double f[3], double g[3])
{
  double r2 = dot(r, r), ir2 = 1.0 / r2, ir3 = ir2 * sqrt(ir2), ir5 = ir3 * ir2;
  double pr = dot(mu, r), h = ir3 - 2.0 * krf;
  for (int c = 0; c < 3; c++) {
    f[c] = -kc * q * (mu[c] * h - 3.0 * pr * ir5 * r[c]);
    g[c] = kc * q * h * r[c];
  }
  return kc * q * pr * h;
}

double rl_charge_dipole_sf(double kc, double rc, const double r[3], double q,
                           const double mu[3], double f[3], double g[3])
{
  double r2 = dot(r, r), rr = sqrt(r2), x = rr / rc;
  if (x >= 1.0) {
    for (int c = 0; c < 3; c++) f[c] = g[c] = 0.0;
    return 0.0;
  }
  double ir3 = 1.0 / (r2 * rr);
  double p = 1.0 + x * x * (-3.0 + 2.0 * x);
  double h = ir3 * p;
  double dh_over_r = 3.0 * ir3 / r2 * (x * x - 1.0); /* h'(r)/r = -3 (1 - x^2) / r^5 */
  double pr = dot(mu, r);
  for (int c = 0; c < 3; c++) {
    f[c] = -kc * q * (mu[c] * h + pr * dh_over_r * r[c]);
    g[c] = kc * q * h * r[c];
  }
  return kc * q * pr * h;
}
