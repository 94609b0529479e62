/* Rotation geometry shared by the system, the file formats and the integrators (geometry.h). */
#include "rotleap/geometry.h"
#include "rotleap/error.h"

#include <math.h>

void rl_quat_to_matrix(const double q[4], double A[9])
{
  double x = q[0], e = q[1], z = q[2], c = q[3]; /* xi, eta, zeta, chi */
  A[0] = -x * x + e * e - z * z + c * c;
  A[1] = 2.0 * (z * c - x * e);
  A[2] = 2.0 * (e * z + x * c);
  A[3] = -2.0 * (x * e + z * c);
  A[4] = x * x - e * e - z * z + c * c;
  A[5] = 2.0 * (e * c - x * z);
  A[6] = 2.0 * (e * z - x * c);
  A[7] = -2.0 * (x * z + e * c);
  A[8] = -x * x - e * e + z * z + c * c;
}

int rl_matrix_to_quat(const double A[9], double q[4])
{
  /* From eq. 4: 4 chi^2 = 1 + tr A, 4 eta^2 = 1 + A11 - A22 - A33, 4 xi^2 = 1 - A11 + A22 - A33,
   * 4 zeta^2 = 1 - A11 - A22 + A33; A12 - A21 = 4 zeta chi, A13 - A31 = 4 xi chi,
   * A23 - A32 = 4 eta chi, A12 + A21 = -4 xi eta, A13 + A31 = 4 eta zeta, A23 + A32 = -4 xi zeta.
   * Take the largest square first (Shepperd), for accuracy. */
  double s[4] = {1.0 - A[0] + A[4] - A[8], 1.0 + A[0] - A[4] - A[8], 1.0 - A[0] - A[4] + A[8],
                 1.0 + A[0] + A[4] + A[8]};
  int k = 0;
  for (int i = 1; i < 4; i++)
    if (s[i] > s[k]) k = i;
  if (!(s[k] > 0.0)) return rl_error(RL_EORTHO, "rl_matrix_to_quat: not a rotation matrix");
  double v = 0.5 * sqrt(s[k]), f = 0.25 / v; /* f = 1/(4 v) */
  double x, e, z, c;
  switch (k) {
  case 0: x = v; e = -(A[1] + A[3]) * f; z = -(A[5] + A[7]) * f; c = (A[2] - A[6]) * f; break;
  case 1: e = v; x = -(A[1] + A[3]) * f; z = (A[2] + A[6]) * f; c = (A[5] - A[7]) * f; break;
  case 2: z = v; x = -(A[5] + A[7]) * f; e = (A[2] + A[6]) * f; c = (A[1] - A[3]) * f; break;
  default: c = v; x = (A[2] - A[6]) * f; e = (A[5] - A[7]) * f; z = (A[1] - A[3]) * f; break;
  }
  if (c < 0.0) { x = -x; e = -e; z = -z; c = -c; }
  q[0] = x; q[1] = e; q[2] = z; q[3] = c;
  return RL_OK;
}

double rl_orthonormality_error(const double A[9])
{
  double m = 0.0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double s = A[i] * A[j] + A[3 + i] * A[3 + j] + A[6 + i] * A[6 + j] - (i == j ? 1.0 : 0.0);
      if (fabs(s) > m) m = fabs(s);
    }
  return m;
}
