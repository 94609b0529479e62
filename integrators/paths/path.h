/* Model families: how a kind of rigid body is stored and which rotation path moves it.
 * One const descriptor per family (integrators/paths/<family>.c); the leapfrog core calls `rotate` once
 * per species, after the angular momenta have been kicked to l(t+h/2).  Internal header. */
#ifndef ROTLEAP_PATH_H
#define ROTLEAP_PATH_H

#include "rotleap/error.h"
#include "rotleap/integrator.h"
#include "../../core/system_impl.h"

/* What a rotate call needs from the integrator, and what it reports back. */
typedef struct {
  double h;
  rl_rot_method method;   /* general path only: cubic, exact, quaternion or a baseline */
  double guard_tol;
  double quat_tol;
  int quat_maxit;
  double (*q)[4];         /* [nmat] quaternions for RL_ROT_QUATERNION and the baselines,
                             else NULL                                               */
  const double (*k)[3];   /* [nrot] torques k(t) (lab)                               */
  const double (*l_prev)[3]; /* [nrot] l(t-h/2) before the kick: RL_ROT_FINCHAM only   */
  long step;              /* for error messages                                  */
  long fallbacks;         /* out: guarded solves that needed Newton               */
  long quat_iterations;   /* out                                                  */
  int quat_max_iterations;/* out                                                  */
  double max_h_omega;     /* out: max h |Omega(t+h/2)|                            */
  double quat_norm_defect;/* out: RL_ROT_FINCHAM, max ||q(t+h)| - 1| rescaled away  */
  int threads;            /* OpenMP threads for the asymmetric cubic / exact solves (>= 1) */
} rl_rotation_work;

/* 1 for the baseline methods (RL_ROT_HYBRID, RL_ROT_FINCHAM, RL_ROT_NOSQUISH), which send every
 * matrix body through the general family and cannot move axis-only species. */
static inline int rl_rot_is_baseline(rl_rot_method m)
{
  return m == RL_ROT_HYBRID || m == RL_ROT_FINCHAM || m == RL_ROT_NOSQUISH;
}

/* Rotate body b (0-based in sp, a matrix body) by the baseline w->method
 * (integrators/paths/baselines.c); *hw receives its h |Omega|. */
int rl_rotate_baseline(const rl_species *sp, rl_system *s, int b, rl_rotation_work *w, double *hw);

typedef struct rl_family {
  rl_kind kind;
  const char *name;
  const char *path;       /* the rotation path, for listings                       */
  int rot_dof;
  /* Rotate every body of sp from its mid-step angular momentum (A or rho updated). */
  int (*rotate)(const rl_species *sp, rl_system *s, rl_rotation_work *w);
  /* On-step rotational kinetic energy of body b (0-based in sp) from on-step l(t). */
  double (*ke_rot)(const rl_species *sp, const rl_system *s, int b, const double lt[3]);
} rl_family;

extern const rl_family rl_family_point, rl_family_dipole, rl_family_linear,
    rl_family_spherical, rl_family_symmetric, rl_family_asymmetric;

/* The family integrating `kind` (the asymmetric family if force_general and kind stores A). */
const rl_family *rl_family_for(rl_kind kind, int force_general);

/* Shared pieces (integrators/paths/common.c). */
/* theta = J^-1 A l, body frame */
static inline void rl_body_theta(const double A[9], const double J[3], const double l[3], double th[3])
{
  for (int a = 0; a < 3; a++) th[a] = (A[3 * a] * l[0] + A[3 * a + 1] * l[1] + A[3 * a + 2] * l[2]) / J[a];
}
static inline double rl_norm3(const double a[3]) { return __builtin_sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }
static inline void rl_project_out(double l[3], const double rho[3])
{
  double d = l[0] * rho[0] + l[1] * rho[1] + l[2] * rho[2];
  l[0] -= d * rho[0]; l[1] -= d * rho[1]; l[2] -= d * rho[2];
}
/* Rotate every body of an axis species (point dipole, linear molecule): rho(t+h) is rho(t) turned
 * about omega = l(t+h/2)/J (its part perpendicular to rho if `perpendicular`, as the linear
 * molecule's Omega_Z = 0) by 2 atan(h omega/2). */
int rl_rotate_axis_species(const rl_species *sp, rl_system *s, rl_rotation_work *w, int perpendicular);
double rl_ke_rot_matrix(const rl_species *sp, const rl_system *s, int b, const double lt[3]);
double rl_ke_rot_axis(const rl_species *sp, const rl_system *s, int b, const double lt[3]);

#endif
