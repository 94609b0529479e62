/* rotleap — the rotation kernels of the revised angular-momentum leapfrog (Omelyan 1998).
 *
 * Notation and equation numbers are the paper's (../shared/seed).  Body frame = principal
 * axes; A maps lab to body (E = A e); dA/dt = W(Omega) A with W as in eq. 3; the mid-step
 * principal angular velocity Omega = Omega(t+h/2) solves eq. 28,
 *     Omega_X = theta_X + h rho_X Omega_Y Omega_Z   (and cyclic),
 *     rho_X = (J_Y - J_Z)/(2 J_X),  theta = J^-1 A(t) l(t+h/2),
 * and A(t+h) = D(Omega) A(t), D the Cayley matrix of eq. 24.
 *
 * These functions are pure (no allocation, no globals) and are what the integrators call per
 * body; they are public so that tests and benchmarks can exercise them directly. */
#ifndef ROTLEAP_ROTATION_H
#define ROTLEAP_ROTATION_H

#include "rotleap/geometry.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How the guarded solve reached its answer (rl_omega_info.path). */
enum {
  RL_OMEGA_PATH_LINEAR = 0, /* eq. 28 is linear (two equal moments): solved in closed form  */
  RL_OMEGA_PATH_CUBIC = 1,  /* quasi-analytic cubic root (eqs. 30-36) plus one Newton correction
                               on the exact eq. 28, which was below guard_tol (the guard)     */
  RL_OMEGA_PATH_NEWTON = 2, /* the correction was larger: polished by Newton on the exact eq. 28
                               to round-off (a fallback)                                      */
  RL_OMEGA_PATH_BRACKET = 3, /* Newton failed too: safeguarded bisection/Newton in a bracket */
  RL_OMEGA_PATH_CONTINUATION = 4 /* beyond the certified range (h max|rho| |theta| > ~0.42): the
                                    root was checked against the branch continued in h from
                                    h = 0, and replaced by it if it was another solution    */
};

typedef struct {
  int path;          /* RL_OMEGA_PATH_*                                         */
  int iterations;    /* Newton / fixed-point iterations used (0 for the cubic and its one
                        correction)                                             */
  double residual;   /* |eq. 28 residual| / |Omega| of the returned solution     */
  int three_real;    /* 1 if the cubic had three real roots (negative discriminant) */
  int off_branch;    /* 1 if the fast root was another solution of eq. 28, replaced by the
                        branch (path RL_OMEGA_PATH_CONTINUATION)                    */
} rl_omega_info;

/* The guard.  The cubic truncates eq. 28's quintic, so its root has an error that grows with
 * h|Omega| and with inertial anisotropy.  One Newton step on the exact eq. 28 (reduced by eq. 29)
 * from the cubic's root measures that error to first order: the step is residual over
 * derivative, so it bounds the error of the root, not the residual (a small residual of an
 * ill-conditioned equation can hide a larger error).  The step is applied; the error after it
 * is of the order of the step's square times the equation's curvature over its derivative,
 * i.e. round-off for a step below RL_OMEGA_GUARD_TOL |Omega|.  A larger step is a fallback:
 * Newton iterated to round-off (then a bracketed solve if it fails).  With the default, the
 * guarded root equals the exact one to a few ulp times the condition number of eq. 28
 * (tests/integrators/test_rotation.c, root_error_bound), and TIP4P at 1-5 fs needs no fallback. */
#define RL_OMEGA_GUARD_TOL 1e-10

/* Relative residual of eq. 28: |Omega - theta - h (rho_X Omega_Y Omega_Z, ...)|_2 / |Omega|_2
 * (0 when Omega = theta = 0).  A sanity check, not an error bound (see RL_OMEGA_GUARD_TOL). */
double rl_omega_residual(const double J[3], const double theta[3], double h,
                         const double Omega[3]);

/* Guarded quasi-analytic solve of eq. 28 (the default path for asymmetric bodies).
 * in  J[3]      principal moments J_XX, J_YY, J_ZZ (> 0, any order; the solve takes the axis of
 *               the largest moment as its Z, as the paper's J_XX < J_YY < J_ZZ)
 * in  theta[3]  J^-1 A(t) l(t+h/2)
 * in  h         time step (> 0)
 * in  guard_tol largest relative size |dOmega|/|Omega| of the Newton correction to the cubic's
 *               root that is applied as it is; larger ones trigger the Newton polish (a
 *               fallback).  <= 0: RL_OMEGA_GUARD_TOL
 * out Omega[3]  mid-step principal angular velocity: the solution of eq. 28 that continues from
 *               Omega = theta at h = 0 (eq. 28 has up to five).  A contraction bound certifies
 *               the fast root up to h max|rho| |theta| ~ 0.42 (h|theta| ~ 0.84 for water, where
 *               max|rho| ~ 1/2); beyond, it is checked against that branch followed by
 *               continuation in h, and replaced if it is another solution (Cardano's three real
 *               roots and the Newton polish can pick one from h|theta| ~ 3 on)
 * out info      how it was found (may be NULL)
 * Never returns NaN or Inf for finite input.  Returns RL_OK, or RL_ENOCONV if even the bracketed
 * solve could not bring the residual below 1e-12 (reported rather than hidden; seen only far
 * beyond any usable step, where the reduced equation overflows: Omega is then theta, finite,
 * and must not be used). */
int rl_omega_guarded(const double J[3], const double theta[3], double h, double guard_tol,
                     double Omega[3], rl_omega_info *info);

/* Real root of a3 d^3 + a2 d^2 + a1 d + a0 = 0 nearest the one that tends to 0 as h -> 0 (the
 * delta_1 of eq. 34), by Cardano's formula in a cancellation-free form; with three real roots
 * the one of smallest |d|.  *three_real (may be NULL) tells which case.  NaN if a3 = 0. */
double rl_cubic_small_root(double a0, double a1, double a2, double a3, int *three_real);

/* Reference solve of eq. 28 by full 3-D Newton iteration from Omega = theta (damped), to
 * relative change <= 1e-15.  Independent of the cubic reduction (eq. 29); for checking.  Beyond
 * the certified range (as rl_omega_guarded) its root is checked against the branch continued in h
 * by 3-D Newton, and replaced by it if it is another solution or if Newton did not converge.
 * Returns RL_ENOCONV if neither gives a solution. */
int rl_omega_exact(const double J[3], const double theta[3], double h, double Omega[3],
                   rl_omega_info *info);

/* Symmetric top, J_XX = J_YY (unique axis Z): Omega_Z = theta_Z and Omega_X, Omega_Y from
 * eq. 29 with rho_Y = -rho_X.  Closed form, exact solution of eq. 28. */
void rl_omega_symmetric(const double J[3], const double theta[3], double h, double Omega[3]);

/* The Cayley / evolution matrix D of eq. 24 for the vector w (row-major 3x3):
 *   D = [I (1 - h^2 w^2/4) + h W(w) + h^2/2 w w^T] / (1 + h^2 w^2/4),
 * exactly orthogonal; it is the rotation exp[phi W(w)/|w|] with phi = 2 atan(h |w| / 2), which is
 * the paper's arcsin form for h|w| <= 2 and continues it beyond.  For h|w| > 2 it is evaluated
 * divided through by h^2 w^2/4, so it stays finite and orthogonal for every finite h and w (it
 * tends to the rotation by pi; the undivided form overflowed to NaN from h|w| ~ 1.3e154).  The
 * same holds for rl_rotate_axis and rl_quat_rotate (tests/integrators/test_rotation.c, cayley_overflow). */
void rl_cayley(const double w[3], double h, double D[9]);

/* A <- D(Omega) A (eq. 24), A row-major 3x3. */
void rl_rotate_matrix(double A[9], const double Omega[3], double h);

/* rho <- rotation of the unit vector rho by d rho/dt = w x rho over h, Cayley form (section III.D;
 * equal to exp[-phi W(w)/w] rho with the angle above). */
void rl_rotate_axis(double rho[3], const double w[3], double h);

/* Quaternions in the paper's convention q = (xi, eta, zeta, chi) (eqs. 4-5): rl_quat_to_matrix,
 * rl_matrix_to_quat in geometry.h. */
/* q <- G(Omega) q, eq. 23. */
void rl_quat_rotate(double q[4], const double Omega[3], double h);

/* ------------------------------------------------------------------ baselines (issue 7)
 * Kernels of the comparison integrators selected by rl_integrator_params.method (see
 * docs/integrators.md).  Quaternions in the convention of eqs. 4-5 above. */

/* out = M_k q, where Q(Omega) of eq. 5 is (Omega_X M_X + Omega_Y M_Y + Omega_Z M_Z)/2 (k = 0, 1, 2
 * for X, Y, Z).  Each M_k is antisymmetric with M_k^2 = -I; for |q| = 1 the four vectors q,
 * M_X q, M_Y q, M_Z q are orthonormal. */
void rl_quat_generator(int k, const double q[4], double out[4]);

typedef struct {
  int iterations;     /* fixed-point iterations used                                         */
  double norm_defect; /* ||q(t+h)| - 1| of the converged iterate, removed by rescaling          */
  double change;      /* max |q^(n+1) - q^(n)| of the last iteration                          */
  double h_omega;     /* h |Omega(t)|                                                          */
} rl_fincham_info;

/* One step of Fincham's implicit quaternion leapfrog (eqs. 13-16):
 *   q(t+h) = q(t) + h/2 [Q(Omega(t)) q(t) + Q(Omega~(t+h)) q(t+h)],
 *   Omega(t) = J^-1 A(q(t)) l(t),  Omega~(t+h) = J^-1 A(q(t+h)) l~(t+h),
 * solved by fixed-point iteration from q^(0) = q(t) + h Q(Omega(t)) q(t) until
 * max |q^(n+1) - q^(n)| <= tol, then rescaled to |q| = 1 (Fincham's practice; the trapezoidal
 * update itself does not keep the norm).
 * in     J[3]      principal moments (> 0)
 * in     lt[3]     on-step lab angular momentum l(t) (eq. 12; thermostatted l'(t) in NVT)
 * in     lnext[3]  predicted l~(t+h) = l(t+h/2) + h/2 k(t) (eq. 16)
 * in     h, tol, maxit
 * in/out q[4]      q(t) (unit) -> q(t+h) (unit); unchanged on error
 * out    info      may be NULL
 * Returns RL_OK, or RL_ENOCONV if the iteration diverges (non-finite, or |q| > 4) or does not
 * converge in maxit iterations -- the message says which, with h |Omega(t)|. */
int rl_fincham_quat(const double J[3], const double lt[3], const double lnext[3], double h,
                    double tol, int maxit, double q[4], rl_fincham_info *info);

/* NO_SQUISH conjugate momentum of a unit quaternion for the principal angular momentum L = A l:
 * p = 2 sum_k L_k M_k q; and back, L_k = (M_k q).p / 2. */
void rl_quat_conjugate_momentum(const double q[4], const double L[3], double p[4]);
void rl_quat_body_angmom(const double q[4], const double p[4], double L[3]);

/* NO_SQUISH free rotor over h (Miller et al. 2002): the symmetric splitting
 * R_Z(h/2) R_Y(h/2) R_X(h) R_Y(h/2) R_Z(h/2), each R_k the exact flow of L_k^2/(2 J_k):
 * q <- cos(z) q + sin(z) M_k q, p <- cos(z) p + sin(z) M_k p, z = dt L_k/(2 J_k).  Symplectic,
 * time-reversible, |q| preserved to round-off; the lab angular momentum A(q)^T L(q, p) is
 * invariant under every sub-rotation. */
void rl_nosquish_free(const double J[3], double h, double q[4], double p[4]);


#ifdef __cplusplus
}
#endif
#endif
