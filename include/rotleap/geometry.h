/* rotleap — rotation geometry: quaternions in the paper's convention q = (xi, eta, zeta, chi)
 * (eqs. 4-5) and the orthonormality of a rotation matrix.  Used by the system, the file formats
 * and the integrators alike (core/geometry.c). */
#ifndef ROTLEAP_GEOMETRY_H
#define ROTLEAP_GEOMETRY_H

#ifdef __cplusplus
extern "C" {
#endif

void rl_quat_to_matrix(const double q[4], double A[9]); /* eq. 4 (no normalisation)   */
int rl_matrix_to_quat(const double A[9], double q[4]);  /* inverse of eq. 4, chi >= 0 */
/* max |A^T A - I| (elementwise). */
double rl_orthonormality_error(const double A[9]);

#ifdef __cplusplus
}
#endif
#endif
