/* Linear point quadrupole-quadrupole kernel. */
#include "quadrupole.h"

#include <math.h>

double rl_quadrupole_quadrupole(double kc, const double r[3], double Qi, const double ei[3],
                                double Qj, const double ej[3], double f[3], double gi[3],
                                double gj[3])
{
  /* U = K [(1 + 2c^2) r^-5 - 5 (a^2 + b^2) r^-7 - 20 c a b r^-7 + 35 a^2 b^2 r^-9],
   * a = e_i.r, b = e_j.r, c = e_i.e_j, K = 3 kc Q_i Q_j / 4. */
  double K = 0.75 * kc * Qi * Qj;
  double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
  double ir2 = 1.0 / r2, ir5 = ir2 * ir2 / sqrt(r2), ir7 = ir5 * ir2, ir9 = ir7 * ir2,
         ir11 = ir9 * ir2;
  double a = ei[0] * r[0] + ei[1] * r[1] + ei[2] * r[2];
  double b = ej[0] * r[0] + ej[1] * r[1] + ej[2] * r[2];
  double c = ei[0] * ej[0] + ei[1] * ej[1] + ei[2] * ej[2];
  double U = (1.0 + 2.0 * c * c) * ir5 - 5.0 * (a * a + b * b) * ir7 - 20.0 * c * a * b * ir7 +
             35.0 * a * a * b * b * ir9;
  double sr = -5.0 * (1.0 + 2.0 * c * c) * ir7 + 35.0 * (a * a + b * b) * ir9 +
              140.0 * c * a * b * ir9 - 315.0 * a * a * b * b * ir11;
  double si = -10.0 * a * ir7 - 20.0 * c * b * ir7 + 70.0 * a * b * b * ir9;
  double sj = -10.0 * b * ir7 - 20.0 * c * a * ir7 + 70.0 * a * a * b * ir9;
  for (int k = 0; k < 3; k++) {
    double dr = sr * r[k] + si * ei[k] + sj * ej[k];
    f[k] = -K * dr;
    gi[k] = K * (4.0 * c * ir5 * ej[k] - 10.0 * a * ir7 * r[k] -
                 20.0 * (a * b * ej[k] + c * b * r[k]) * ir7 + 70.0 * a * b * b * ir9 * r[k]);
    gj[k] = K * (4.0 * c * ir5 * ei[k] - 10.0 * b * ir7 * r[k] -
                 20.0 * (a * b * ei[k] + c * a * r[k]) * ir7 + 70.0 * a * a * b * ir9 * r[k]);
  }
  return K * U;
}
