/* rotleap — step operators: what acts on the state at named points of a leapfrog step, beside
 * the dynamics (thermostats today; barostats next).  One const descriptor per operator (GSL's
 * "type" plus an instance): its name and reference, its parameters, alloc/free, the hooks it
 * runs at the points of the step, how it counts degrees of freedom and treats the centre of
 * mass, its account of the energy it exchanges (for the conserved quantity) and its random state
 * (for checkpoints).  The leapfrog core (integrators/leapfrog.c) calls the hooks and knows
 * nothing of a particular operator; rl_integrator_params.thermostat adds the matching built-in
 * operator, and rl_integrator_add_op adds any other.  docs/integrators.md, "Step operators", has
 * the points with the equations they sit between and how to add an operator. */
#ifndef ROTLEAP_STEPOPS_H
#define ROTLEAP_STEPOPS_H

#include "rotleap/forces.h"
#include "rotleap/integrator.h"
#include "rotleap/system.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The points of a step t -> t+h at which operators act, in the order the core reaches them
 * (eq. numbers of Omelyan's paper).  At every point the system holds the state as it is there:
 *
 *   RL_STEP_BEFORE_KICK  r(t), A(t); v(t-h/2), l(t-h/2); forces at t; the on-step values of
 *                        eqs. 9 and 12 in info (ke_trans, ke_rot, temperature) and in K.  An
 *                        operator with RL_STEPOP_SCALES_KICK sets kick_beta: the kick is then
 *                        eqs. 17-18, v(t+h/2) = (2 beta - 1) v(t) + h/2 f/m (likewise l).
 *   (kick: eqs. 8 and 10, or 17-18)
 *   RL_STEP_AFTER_KICK   r(t), A(t); v(t+h/2), l(t+h/2); K their kinetic energies (rotational
 *                        part with A(t)).
 *   (drift r += h v (eq. 8) and rotation by h (eqs. 19-36, III.D); split into two halves of h/2
 *    when any operator has a RL_STEP_MID_DRIFT hook)
 *   RL_STEP_MID_DRIFT    r(t+h/2) = r(t) + h/2 v(t+h/2), A rotated by h/2 from l(t+h/2).
 *   (the second half drift and rotation, from the v and l the operators leave)
 *   RL_STEP_AFTER_DRIFT  r(t+h), A(t+h); v(t+h/2), l(t+h/2); forces still those at t.
 *   (forces at t+h; energy and virial on the steps of energy_every)
 *   RL_STEP_END          forces at t+h: the state a checkpoint stores. */
typedef enum {
  RL_STEP_BEFORE_KICK = 0,
  RL_STEP_AFTER_KICK = 1,
  RL_STEP_MID_DRIFT = 2,
  RL_STEP_AFTER_DRIFT = 3,
  RL_STEP_END = 4,
  RL_STEP_NPOINTS = 5
} rl_step_point;

/* "before-kick", "after-kick", "mid-drift", "after-drift", "end" (NULL if unknown). */
const char *rl_step_point_name(rl_step_point pt);

/* Descriptor flags. */
enum {
  /* The operator moves the centre of mass at random (Langevin's noise): all 3N translational
   * degrees of freedom count (rl_integrator_dof), and rl_integrator_init and resume leave the
   * total momentum as it is.  Without any such operator the system's removed dof come off and a
   * total momentum above round-off is removed at init and resume (rl_integrator_init). */
  RL_STEPOP_THERMAL_COM = 1u << 0,
  /* The operator holds a temperature: the integrator is refused if the system has no degree of
   * freedom. */
  RL_STEPOP_HOLDS_TEMPERATURE = 1u << 1,
  /* The operator sets kick_beta at RL_STEP_BEFORE_KICK (eqs. 17-18); at most one per integrator. */
  RL_STEPOP_SCALES_KICK = 1u << 2
};

/* One parameter of an operator, for listings: name, unit (or "" if none) and what it does. */
typedef struct {
  const char *name, *unit, *doc;
} rl_stepop_param;

typedef struct rl_stepop_type rl_stepop_type;

/* An operator carried by an integrator.  The integrator owns it (rl_integrator_op returns it). */
typedef struct {
  const rl_stepop_type *type;
  void *par;     /* the integrator's copy of the parameters (type->params_size bytes)            */
  void *state;   /* what type->alloc made (random state, workspace), or NULL                     */
  double work;   /* energy the operator has taken out of the system since init or resume: the
                    conserved quantity is the total energy plus the sum of the operators' work */
} rl_stepop;

/* What a hook sees.  The integrator fills it once per step; hooks read it and may write the
 * fields marked out. */
typedef struct {
  rl_integrator *in;              /* the integrator (rl_integrator_forces, rl_integrator_dof)   */
  rl_system *sys;                 /* the state at the point (see rl_step_point); raw arrays:
                                     rl_system_r, rl_system_v; l by rl_system_get/set_angmom    */
  const rl_integrator_params *p;  /* h, method, threads, ...                                    */
  long step;                      /* the step's number (0 for the first after init)             */
  double t;                       /* the time t the step starts from                            */
  const rl_forces *forces;        /* forces and torques at t; at RL_STEP_END at t+h             */
  int dof_trans, dof_rot;         /* the integrator's count (rl_integrator_dof)                 */
  double K[2];                    /* in/out: translational and rotational kinetic energy at
                                     RL_STEP_BEFORE_KICK (on-step, eqs. 9 and 12) and at
                                     RL_STEP_AFTER_KICK (of v(t+h/2), l(t+h/2) with A(t): the
                                     plain kick's; an operator that changes v or l there updates
                                     them for the next); NAN elsewhere (rl_stepop_kinetic)     */
  double kick_beta;               /* out, RL_STEP_BEFORE_KICK, RL_STEPOP_SCALES_KICK only: the
                                     beta of eqs. 17-18 (1: the plain kick)                     */
  rl_step_info *info;             /* out: the step's report.  The core sets beta = beta_rot = 1,
                                     conserved (before any hook of this step adds work) and
                                     t_trans_mid, t_rot_mid of the plain kick; an operator
                                     reports its factors in beta, beta_rot and may report the
                                     mid-step temperatures where it acts (Langevin)            */
} rl_stepop_ctx;

/* A hook: RL_OK, or an error set with rl_error (the step stops and returns it; the state may be
 * partly advanced, as after any step error). */
typedef int (*rl_stepop_hook)(rl_stepop *op, rl_stepop_ctx *c);

struct rl_stepop_type {
  const char *name;                /* look-up name: "bussi"                                      */
  const char *label;               /* in messages: "Bussi thermostat"                           */
  const char *reference;           /* the literature                                            */
  const rl_stepop_param *params;   /* the fields of the parameter block, {NULL} terminated      */
  size_t params_size;              /* bytes of the parameter block (copied by the integrator)   */
  unsigned flags;                  /* RL_STEPOP_*                                               */
  /* Parameters against the integrator's settings and the system (may be NULL): RL_OK or an
   * error naming the parameter.  Called by rl_integrator_alloc/add_op, init and resume. */
  int (*check)(const void *par, const rl_system *sys, const rl_integrator_params *p);
  int (*alloc)(rl_stepop *op);     /* op->state from op->par (may be NULL)                      */
  void (*free)(rl_stepop *op);     /* frees op->state (may be NULL)                             */
  rl_stepop_hook hook[RL_STEP_NPOINTS]; /* NULL where the operator does nothing                 */
  /* What the operator reports for the current time without stepping (rl_integrator_observe):
   * writes c->info only (may be NULL). */
  void (*observe)(const rl_stepop *op, rl_stepop_ctx *c);
  /* The random state to checkpoint: its bytes and their count, or NULL (may be NULL).  Only the
   * first operator with one is the integrator's (rl_integrator_rng_state: the thermostat's). */
  void *(*rng_state)(rl_stepop *op, size_t *size);
  /* The operator's own state for a checkpoint, beyond rng_state: a barostat's random stream,
   * adapted trial size and counters (both may be NULL: nothing to keep).  save writes it into buf
   * and returns its size in bytes (buf NULL: the size only); load puts back what save wrote
   * (RL_EINVAL, naming the operator, for bytes of another size or out of range). */
  size_t (*save)(const rl_stepop *op, void *buf);
  int (*load)(rl_stepop *op, const void *buf, size_t size);
};

/* The operator's checkpoint state (type->save): its size, written into buf unless NULL; 0 if it
 * keeps none. */
size_t rl_stepop_save(const rl_stepop *op, void *buf);
/* Put it back (type->load); RL_EINVAL if the operator keeps none and size > 0. */
int rl_stepop_load(rl_stepop *op, const void *buf, size_t size);

/* The most operators one integrator carries. */
#define RL_STEPOP_MAX 8

/* Add an operator (its parameters are copied) after those the integrator has; it acts after them
 * at each point.  Before rl_integrator_init or rl_integrator_resume (RL_ESTATE after, until
 * rl_integrator_finish).  RL_EINVAL for bad parameters (type->check), a RL_STEP_MID_DRIFT hook
 * under a baseline rotation method (they rotate once over h), a second RL_STEPOP_SCALES_KICK or
 * more than RL_STEPOP_MAX operators. */
int rl_integrator_add_op(rl_integrator *in, const rl_stepop_type *type, const void *params);
int rl_integrator_nops(const rl_integrator *in);
rl_stepop *rl_integrator_op(rl_integrator *in, int k); /* NULL if k is out of range */

/* The current translational and rotational kinetic energies of the stored v and l (with the
 * stored A): the mid-step values between the kick and the forces. */
void rl_stepop_kinetic(const rl_stepop_ctx *c, double K[2]);
/* Forces (and energy and virial if `energy`) again for the current configuration, for an
 * operator that moved the bodies (a Monte Carlo move at RL_STEP_END); c->forces then holds them. */
int rl_stepop_forces(rl_stepop_ctx *c, int energy);
/* Keep the current computation (c->forces: forces, torques, energy, virial, and for a provider of
 * force terms their energy components, rl_terms_keep) before an operator moves the bodies;
 * rl_stepop_forces_put_back puts it back after the operator has put the configuration back (a
 * rejected Monte Carlo move), or, for a provider that cannot keep its report, computes again
 * (with the energy and virial if `energy`).  RL_OK, RL_ENOMEM, or the computation's status. */
int rl_stepop_forces_keep(rl_stepop_ctx *c);
int rl_stepop_forces_put_back(rl_stepop_ctx *c, int energy);

/* ------------------------------------------------------------ the built-in thermostats */

/* The parameter block of the built-in thermostats (rl_integrator_params' fields of the same names). */
typedef struct {
  double T0;               /* target temperature (> 0)                                           */
  double tau;              /* Bussi: relaxation time of K; Langevin: friction time 1/gamma (> 0) */
  unsigned long seed;      /* Bussi, Langevin: GSL mt19937 seed                                  */
  rl_thermo_groups groups; /* Bussi only                                                         */
  double tau_rot;          /* Langevin-DOT: rotational friction time (> 0; 0: tau)                */
} rl_thermostat_params;

/* isokinetic (RL_STEP_BEFORE_KICK, eqs. 17-18), bussi (RL_STEP_AFTER_KICK), langevin
 * (RL_STEP_MID_DRIFT); rl_integrator.h's rl_thermostat has what each does. */
extern const rl_stepop_type rl_stepop_isokinetic, rl_stepop_bussi, rl_stepop_langevin;
/* langevin-dot (RL_STEP_MID_DRIFT) and langevin-dot-obabo (RL_STEP_BEFORE_KICK): rl_integrator.h's
 * RL_THERMO_LANGEVIN_DOT, RL_THERMO_LANGEVIN_DOT_OBABO. */
extern const rl_stepop_type rl_stepop_langevin_dot, rl_stepop_langevin_dot_obabo;

/* The descriptor named `name` ("isokinetic", "bussi", "langevin", "langevin-dot", "langevin-dot-obabo",
 * "mc-barostat", "c-rescale"), or NULL. */
const rl_stepop_type *rl_stepop_find(const char *name);
/* The operator rl_integrator_params.thermostat = t adds (NULL for RL_THERMO_NONE or unknown). */
const rl_stepop_type *rl_stepop_for_thermostat(rl_thermostat t);

/* ------------------------------------------------------------------------- the barostats */

/* How a barostat changes the cell: every edge by one factor, one edge at a time (Monte Carlo:
 * OpenMM's MonteCarloAnisotropicBarostat), or x and y together and z alone (stochastic cell
 * rescaling, semi-isotropic, as GROMACS's C-rescale semiisotropic). */
typedef enum {
  RL_BARO_ISOTROPIC = 0,
  RL_BARO_ANISOTROPIC = 1,
  RL_BARO_SEMIISOTROPIC = 2
} rl_baro_coupling;

/* The parameter block of the barostats (integrators/stepops/barostat.c).  Energies, volumes and
 * pressures in the system's units (real: kJ/mol, nm^3, kJ mol^-1 nm^-3 = 16.6054 bar). */
typedef struct {
  double P0;               /* target pressure (any finite value; > 0 for an ideal gas)            */
  double T0;               /* temperature of the ensemble (> 0): the thermostat's                 */
  long interval;           /* steps between moves (>= 1): Monte Carlo trials; C-rescale couplings  */
  double tau_p;            /* C-rescale: coupling time (> 0)                                       */
  double compressibility;  /* C-rescale: the isothermal compressibility it assumes (> 0), 1/pressure */
  double trial;            /* Monte Carlo: first trial size as a fraction of V (0: 0.01, OpenMM's) */
  rl_baro_coupling coupling;
  double min_edge;         /* a move to a box edge below this stops the run (0: no check; rotleap:
                              twice the cutoff, the least the pair term can follow)               */
  unsigned long seed;      /* GSL mt19937 seed of the barostat's own stream                       */
} rl_barostat_params;

/* Monte Carlo barostat (RL_STEP_END, every `interval` steps): a random change of the volume
 * dV uniform in [-s, s] (a walk in V, as OpenMM's), the centres of mass scaled by (V'/V)^(1/3)
 * (anisotropic: one edge, picked at random, by V'/V), the molecules rigid with their
 * orientations and velocities kept; accepted with min(1, exp(-w/kT)),
 * w = dU + P0 dV - N kT ln(V'/V), N the molecules.  s (one per edge when anisotropic) starts at
 * trial V and is adapted as OpenMM does: after every 10 trials, divided by 1.1 below 25 %
 * acceptance, multiplied by 1.1 (at most 0.3 V) above 75 %.  The account takes -dU of an
 * accepted move (the conserved quantity stays continuous; it is not conserved under MC). */
extern const rl_stepop_type rl_stepop_mc_barostat;
/* Stochastic cell rescaling (Bernetti & Bussi 2020), isotropic, at RL_STEP_AFTER_DRIFT of every
 * `interval`-th step: with the molecular pressure P(t) = (2 K_trans(t) + tr W(t)) / 3V and
 * dt = interval h, eps = ln V moves by
 *   d eps = -(kappa dt / tau_p) (P0 - P) + sqrt(2 kT kappa dt / (V tau_p)) xi
 * (xi a standard normal; the stationary law of this Ito walk is V^N exp(-(U + P0 V)/kT) dV with P's
 * kinetic part N kT/V, the Monte Carlo barostat's: docs/integrators.md, "Barostats"),
 * the centres r(t+h) and the box are scaled by mu = exp(d eps / 3) and v(t+h/2) by 1/mu.  The
 * account takes the energy the move changes, -(dK + dU) with dK exact and dU the trapezoid
 * -(tr W + tr W') ln mu / 2 (W' the virial in the new box at RL_STEP_END, computed there if the
 * step has no energy), so that the total energy plus the accounts is the effective energy of the
 * paper, conserved up to the integration error (with dU to first order only, -tr W ln mu, the
 * noise's second-order term drifts at a rate that does not fall with h).  Needs the virial at t on
 * its steps: interval must be a multiple of the integrator's energy_every. */
extern const rl_stepop_type rl_stepop_crescale;

/* A barostat's counts: Monte Carlo trials and acceptances (per edge when anisotropic: [0..2],
 * isotropic in [0]), the current trial sizes; C-rescale: moves in attempted[0], accepted = moves. */
typedef struct {
  long attempted[3], accepted[3];
  double trial[3];
} rl_barostat_stats;
/* RL_EINVAL if op is not a barostat. */
int rl_barostat_stats_of(const rl_stepop *op, rl_barostat_stats *out);

#ifdef __cplusplus
}
#endif
#endif
