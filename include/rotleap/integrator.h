/* rotleap — the leapfrog core: translation (eqs. 8-9) and the revised angular-momentum
 * rotation (eqs. 19-36, section III.D), with step operators (thermostats: the paper's isokinetic
 * scheme of eqs. 17-18, Bussi, Langevin) called at named points of the step (rotleap/stepops.h).
 *
 * Staggering: positions and orientations live at whole steps t; v and l at half steps.  The
 * state given to the system is on-step; rl_integrator_init computes the forces at t and moves v
 * and l back half a step (v(t-h/2) = v(t) - h/2 f/m), so that the on-step interpolation (eqs. 9,
 * 12) of the first step returns exactly what was given.
 *
 * One call of rl_integrator_step advances t -> t+h and reports the on-step quantities at the
 * time t it started from (kinetic energy by eqs. 9/12, potential energy at t), which is when
 * both half-step velocities that define them are known. */
#ifndef ROTLEAP_INTEGRATOR_H
#define ROTLEAP_INTEGRATOR_H

#include "rotleap/forces.h"
#include "rotleap/system.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------- integrator */

typedef enum {
  RL_ROT_CUBIC = 0,      /* revised leapfrog, matrix, guarded quasi-analytic cubic (default)   */
  RL_ROT_EXACT = 1,      /* revised leapfrog, matrix, eq. 28 solved by 3-D Newton (checking)   */
  RL_ROT_QUATERNION = 2, /* revised leapfrog, quaternions, eq. 23 iterated to quat_tol          */
  /* Baselines, for comparison (docs/integrators.md).  Under these every matrix body (spherical,
   * symmetric, asymmetric) goes through the baseline algorithm, never a fast path; species
   * stored as an axis (point dipoles, linear molecules) are refused by rl_integrator_alloc. The
   * state stays A: each step takes q(t) from A(t) and returns A(t+h) = A(q(t+h)), so restarts
   * are bit for bit.  The translation and the kick of l are rotleap's leapfrog in all cases. */
  RL_ROT_HYBRID = 3,     /* the paper's hybrid (section IV): Omega(t+h/2) from the matrix
                            equation 28 (guarded cubic), then the quaternion Cayley update
                            q(t+h) = G(Omega) q(t) of eq. 23.  Second order, but it turns by
                            4 atan(h|Omega|/4) where eq. 24 turns by 2 atan(h|Omega|/2): not
                            time-reversible, energy not conserved for a free top            */
  RL_ROT_FINCHAM = 4,    /* Fincham's implicit quaternion leapfrog (eqs. 10-16, the paper's
                            "standard" scheme): trapezoidal q update with on-step l(t) and the
                            extrapolated l~(t+h) = l(t+h/2) + h/2 k(t), iterated to quat_tol
                            (quat_maxit), q rescaled to unit norm after each step              */
  RL_ROT_NOSQUISH = 5    /* NO_SQUISH (Miller, Eleftheriou, Pattnaik, Ndirango, Newns &
                            Martyna, J. Chem. Phys. 116, 8649 (2002)): symplectic, reversible
                            splitting of the free rotor into exact rotations about the principal
                            axes, Z(h/2) Y(h/2) X(h) Y(h/2) Z(h/2), in quaternion + conjugate
                            momentum form, between rotleap's kicks of l                        */
} rl_rot_method;

/* "rl", "rl-exact", "rl-quaternion", "rl-hybrid", "fincham", "no-squish" (NULL if unknown). */
const char *rl_rot_method_name(rl_rot_method m);

typedef enum {
  RL_THERMO_NONE = 0,       /* NVE                                                          */
  RL_THERMO_ISOKINETIC = 1, /* the paper's isokinetic scaling (eqs. 17-18, III.B), as
                               published: the on-step T is T0 exactly, but a start at
                               T(0) = r0^2 T0 leaves an undamped period-2 mode, T alternating
                               r0^2 T0, (2 - r0)^2 T0 for free bodies (docs/integrators.md,
                               "The isokinetic scheme's period-2 mode"); start near T0      */
  RL_THERMO_BUSSI = 2,      /* canonical stochastic velocity rescaling, Bussi, Donadio &
                               Parrinello, J. Chem. Phys. 126, 014101 (2007): the on-step
                               mid-step v and l are rescaled after the kick by alpha, alpha^2
                               drawn from the canonical relaxation of their kinetic energy
                               over tau                                                        */
  RL_THERMO_LANGEVIN = 3,   /* Langevin dynamics in the middle of the drift (BAOAB, Leimkuhler
                               & Matthews, Appl. Math. Res. Express 2013, 34; OpenMM's
                               LangevinMiddleIntegrator): kick l and v by h, drift r and rotate
                               by h/2, an Ornstein-Uhlenbeck step on every translational and
                               body-frame rotational component (friction 1/tau), then drift and
                               rotate by h/2 again.  Positions in a harmonic potential are
                               sampled exactly at any stable h; librations in a field to 0.2 %
                               at h omega = 0.5 (tests/integrators/test_thermostat.c; docs/integrators.md,
                               "Langevin in the middle of the drift").  The noise moves the
                               centre of mass, so all 3N translational dof count
                               (rl_integrator_dof); the system's removed dof is left as it is,
                               for whatever thermostat continues from the state.  Not with the
                               baseline rotation methods                                      */
  RL_THERMO_LANGEVIN_DOT = 4, /* the rigid-body Langevin thermostat of Davidchack, Ouldridge &
                               Tretyakov (J. Chem. Phys. 130, 234101 (2009); 142, 144114
                               (2015); 147, 224103 (2017)) on rotleap's leapfrog: an exact
                               Ornstein-Uhlenbeck step on v (friction 1/tau) and on the
                               body-frame angular momentum (friction 1/tau_rot on each principal
                               axis, noise sqrt(kT I_k (1 - exp(-2 h / tau_rot)))) in the middle
                               of the drift (B A O A B).  With tau_rot = tau it is
                               RL_THERMO_LANGEVIN's dynamics.  docs/integrators.md, "The
                               Davidchack-Ouldridge-Tretyakov Langevin thermostat"           */
  RL_THERMO_LANGEVIN_DOT_OBABO = 5 /* the same Ornstein-Uhlenbeck step in the middle of the kick
                               instead (O B A B O: between the half kicks, at the on-step v(t),
                               l(t) and A(t)); works with every rotation method            */
} rl_thermostat;

/* Which degrees of freedom share one Bussi thermostat.  RL_THERMO_GROUPS_TRANS_ROT (the default):
 * the translational and the rotational kinetic energies are rescaled by two thermostats, each to
 * T0 over its own dof, with independent random numbers (as LAMMPS's fix rigid/nvt and Kamberaj,
 * Low & Neal, J. Chem. Phys. 122, 224114 (2005) thermostat them apart).  At large steps the
 * leapfrog's shadow dynamics holds more mid-step kinetic energy in the fast librations than in
 * translation; one thermostat over both keeps only the sum at T0 and so runs translation cold.
 * RL_THERMO_GROUPS_ALL: one thermostat over every dof (the only choice before this option).
 * Both sample the canonical ensemble as h -> 0; docs/integrators.md ("Bussi thermostat groups")
 * has the measurement. */
typedef enum {
  RL_THERMO_GROUPS_TRANS_ROT = 0,
  RL_THERMO_GROUPS_ALL = 1
} rl_thermo_groups;

/* "trans-rot", "all" (NULL if unknown). */
const char *rl_thermo_groups_name(rl_thermo_groups g);
/* "none", "isokinetic", "Bussi", "Langevin", "Langevin-DOT", "Langevin-DOT-OBABO" (NULL if unknown). */
const char *rl_thermostat_name(rl_thermostat t);

typedef struct {
  double h;               /* time step (> 0), in the system's time unit                       */
  rl_rot_method method;   /* default RL_ROT_CUBIC                                              */
  double guard_tol;       /* the largest Newton correction to the cubic root of eq. 28, relative to
                             |Omega|, applied directly; above it Newton is iterated to round-off
                             and counted as a fallback (default RL_OMEGA_GUARD_TOL = 1e-10)     */
  double quat_tol;        /* quaternion iteration relative tolerance (default 1e-12)           */
  int quat_maxit;         /* default 100                                                       */
  int force_general;      /* 1: every matrix body goes through the general asymmetric path    */
  rl_thermostat thermostat; /* rl_integrator_alloc adds the matching step operator
                             (rotleap/stepops.h: rl_stepop_isokinetic, _bussi, _langevin) with
                             T0, tau, seed and groups as its parameters, as the first operator;
                             more are added by rl_integrator_add_op                         */
  double T0;              /* target temperature for the thermostat                             */
  double tau;             /* Bussi: relaxation time of the kinetic energy; Langevin: friction
                             time 1/gamma (as GROMACS's tau-t for sd and LAMMPS's damp).  > 0.
                             Note the factor 2: Bussi's tau relaxes K, so its velocities relax
                             over 2 tau                                                        */
  unsigned long seed;     /* Bussi / Langevin random stream (GSL mt19937)                      */
  rl_thermo_groups groups; /* Bussi: default RL_THERMO_GROUPS_TRANS_ROT                         */
  int threads;            /* OpenMP threads for the asymmetric bodies' rotation solves (the
                             default cubic and exact paths); 0 (default): OMP_NUM_THREADS if
                             set, else 1, as the force field's threads.  The results do not
                             depend on the count                                               */
  long energy_every;      /* potential energy and virial at the steps that are multiples of
                             this (and at init and resume); the other steps ask the provider
                             for forces only (rl_forces.forces_only), as GROMACS's
                             nstcalcenergy and LAMMPS's thermo steps do.  0 or 1 (default):
                             every step.  The trajectory does not depend on it             */
  double tau_rot;         /* Langevin-DOT: rotational friction time 1/gamma_r (> 0); 0 (the
                             default): tau                                                     */
} rl_integrator_params;

void rl_integrator_params_default(rl_integrator_params *p);

/* The on-step kinetic energies and temperatures of one species (rl_step_info.species). */
typedef struct {
  double ke_trans, ke_rot; /* its bodies' sums m v^2/2 and J Omega^2/2 (eqs. 9, 12)         */
  double t_trans, t_rot;   /* 2 K / (g kB): g_rot = count x the kind's rotational dof (0: no
                              rotational temperature, t_rot = 0); g_trans = the integrator's
                              translational dof x count / bodies (the constraints of the total
                              momentum shared in proportion to the bodies, as GROMACS shares
                              them among its groups), so that sum g T over the species is the
                              system's g T, translational and rotational                     */
} rl_species_kinetic;

/* On-step report for the time t a step starts from. */
typedef struct {
  double t;              /* time of these on-step values                                   */
  double ke_trans;       /* sum m v^2/2, v(t) by eq. 9                                      */
  double ke_rot;         /* sum J Omega^2/2, Omega(t) = J^-1 A(t) l(t), l(t) by eq. 12      */
  int has_energy;        /* 1 if U(t) was computed (energy_every); if 0, potential, total
                            and conserved are NaN                                          */
  double potential;      /* U(t)                                                            */
  double total;          /* ke_trans + ke_rot + potential                                   */
  double temperature;    /* 2 KE / (dof kB)                                                 */
  double t_trans, t_rot; /* translational / rotational temperatures                         */
  double t_trans_mid, t_rot_mid; /* temperatures of the mid-step v(t+h/2) and l(t+h/2) as the
                            dynamics makes them, before any thermostat acts: the plain kick
                            v(t-h/2) + h f/m, l(t-h/2) + h k (l with A(t)) for NVE, Bussi
                            (before its rescaling) and isokinetic (not eqs. 17-18's
                            (2 beta - 1) v(t) + h/2 f/m, which is what is carried forward);
                            at the middle of the drift (l with the half-rotated A), before
                            the Ornstein-Uhlenbeck step, for Langevin, where BAOAB makes
                            them exactly canonical for harmonic modes.  At large h they
                            differ from the on-step t_trans, t_rot by the leapfrog's O(h^2)
                            shadow terms (1/(1 - h^2 omega^2/4) for a harmonic mode).  For
                            free bodies under the isokinetic scheme they equal the on-step
                            temperature before scaling, which alternates (docs/
                            integrators.md, "The isokinetic scheme's period-2 mode")      */
  double beta;           /* thermostat scaling factor applied at t (1 for NVE): isokinetic
                            beta of eqs. 17-18; Bussi alpha applied to v(t+h/2) (and to
                            l(t+h/2) with RL_THERMO_GROUPS_ALL); Langevin: sqrt(K'/K) of the
                            translational kinetic energy across the step's OU update      */
  double beta_rot;       /* Bussi alpha applied to l(t+h/2); equal to beta unless the
                            groups are RL_THERMO_GROUPS_TRANS_ROT; Langevin: sqrt(K'/K) of
                            the rotational kinetic energy                                  */
  double conserved;      /* total + energy taken out by the thermostat before t: the total
                            energy (NVE), the conserved quantity of Bussi and of Langevin
                            (the thermostat's work accounted; it drifts only by the
                            integration error); for the
                            isokinetic scheme the same sum with (1 - beta^2) KE(t), a
                            diagnostic that is not conserved: the period-2 mode alone makes
                            it climb by (r0 - 1)^2 g kB T0 / 2 per step                  */
  double max_h_omega;    /* max over bodies of h |Omega(t+h/2)|: > 1 means poorly resolved */
  long fallbacks;        /* guarded solves that needed Newton in this step                  */
  long quat_iterations;  /* quaternion iterations in this step (sum over bodies)            */
  int quat_max_iterations;
  double quat_norm_defect; /* RL_ROT_FINCHAM: max over bodies of ||q(t+h)| - 1| that the step's
                              rescaling removed (the scheme's own norm error); else 0         */
  int nspecies;          /* entries of species: the system's species at rl_integrator_alloc */
  const rl_species_kinetic *species; /* [nspecies] in the system's order, owned by the
                            integrator: valid until its next step, observe or free           */
} rl_step_info;

typedef struct rl_integrator rl_integrator;

/* Validates h, thermostat and the system (moments, orientations).  The integrator keeps a
 * pointer to sys and to the provider. */
rl_integrator *rl_integrator_alloc(rl_system *sys, const rl_integrator_params *p,
                                   rl_force_provider provider);
void rl_integrator_free(rl_integrator *in); /* accepts NULL */

/* Forces at the current time, and v, l staggered back half a step.  The centre of mass as the
 * thermostat needs it: under every thermostat but Langevin the total momentum is conserved or
 * scaled and carries no heat, so when the system's count removes it (rl_system_set_removed_dof,
 * 3 by default) a total momentum above round-off (|P| > 1e-10 sum m|v|, as a Langevin run leaves
 * it) is subtracted from the velocities; Langevin counts and keeps it (rl_integrator_dof). */
int rl_integrator_init(rl_integrator *in);
/* Continue from a state whose v and l are already the half-step values v(t-h/2), l(t-h/2) (as a
 * stepping integrator leaves them, and as a checkpoint stores them): forces at t are computed,
 * nothing is staggered or projected, and the step counter and time are set, so that a restart
 * continues bit for bit.  The centre of mass is treated as by init (a state from a Langevin run
 * continued under another thermostat loses its total momentum; one at round-off is untouched).
 * Restore the thermostat account and RNG state after this call. */
int rl_integrator_resume(rl_integrator *in, long step, double t);
/* t -> t + h.  info (may be NULL) receives the on-step values at the starting time t.
 * RL_ENONFINITE if the on-step or mid-step kinetic energy or a new position or orientation is
 * not finite (velocities or angular momenta beyond the range of doubles): a step never returns
 * RL_OK with a NaN or Inf in the state or the report.  After such an error the state may be
 * partly advanced and is not to be continued. */
int rl_integrator_step(rl_integrator *in, rl_step_info *info);
/* The on-step values at the current time, as the next rl_integrator_step would report them
 * (energies, on-step kinetic energies of eqs. 9/12, the conserved quantity, the mid-step
 * temperatures its kick would give), without stepping: for the last state of a run.  If the
 * current forces were computed without energies (energy_every), they are computed again with
 * them; the forces are the same, so what follows is unchanged. */
int rl_integrator_observe(rl_integrator *in, rl_step_info *info);
/* Time reversal at the current time: on-step v and l are negated (mid-step values become
 * -(v + h f/m), -(l + h k)); stepping N more times then retraces the trajectory. */
int rl_integrator_reverse(rl_integrator *in);

/* Finish at the current time: put on-step v(t) = v(t-h/2) + h/2 f/m and l(t) back into the
 * system (so it can be cloned, written or handed to another integrator) and require a new
 * rl_integrator_init before stepping again. */
int rl_integrator_finish(rl_integrator *in);

/* Thermostat bookkeeping, for checkpoints: the energy removed so far (the sum of the step
 * operators' accounts, rotleap/stepops.h; set puts it all in the first operator's, the
 * thermostat's when there is one) and the RNG state of the first operator that draws random
 * numbers (the Bussi or Langevin thermostat's; rl_integrator_rng_size bytes, 0 if none). */
double rl_integrator_thermostat_work(const rl_integrator *in);
void rl_integrator_set_thermostat_work(rl_integrator *in, double w);
size_t rl_integrator_rng_size(const rl_integrator *in);
void *rl_integrator_rng_state(rl_integrator *in);

/* Degrees of freedom of the temperatures the integrator reports (total; translational and
 * rotational parts, either pointer may be NULL): rl_system_dof's count, except under Langevin
 * (a step operator with RL_STEPOP_THERMAL_COM), which counts all 3N translational ones. */
int rl_integrator_dof(const rl_integrator *in, int *translational, int *rotational);

/* The rotation path that moves the bodies of `species` under this integrator's method: the
 * family's fast path (system.h, rl_kind_rotation_path), the general path's solve (cubic, exact
 * or quaternion), or a baseline.  NULL for a species out of range. */
const char *rl_integrator_path(const rl_integrator *in, int species);

/* Cumulative counters since init. */
long rl_integrator_fallbacks(const rl_integrator *in);
long rl_integrator_quat_iterations(const rl_integrator *in);
long rl_integrator_steps(const rl_integrator *in);
double rl_integrator_time(const rl_integrator *in);
/* Forces/torques/energy at the current time (valid after init; energy and virial are 0 where
 * forces_only is set, between the steps of energy_every). */
const rl_forces *rl_integrator_forces(const rl_integrator *in);
/* On-step velocity / angular momentum at the current time would need the next forces; these
 * return the stored mid-step values v(t-h/2), l(t-h/2). */
void rl_integrator_mid_velocity(const rl_integrator *in, int body, double v[3]);
void rl_integrator_mid_angmom(const rl_integrator *in, int body, double l[3]);
/* Quaternion of a matrix body (eq. 4: A = A(q)).  Under RL_ROT_QUATERNION: the iterated q of the
 * general path, or, for the spherical and symmetric tops that keep their fast paths (which
 * advance A), the q of their current A (chi >= 0).  Under the baselines: the q(t+h) the last step
 * produced (the periodic round-off polish of A does not update it).  RL_ESTATE for the other
 * methods and for bodies without an orientation matrix (points, point dipoles, linear
 * molecules); RL_EINVAL for a body out of range. */
int rl_integrator_quaternion(const rl_integrator *in, int body, double q[4]);

#ifdef __cplusplus
}
#endif
#endif
