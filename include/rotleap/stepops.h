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
  /* The random state to checkpoint: its bytes and their count, or NULL (may be NULL). */
  void *(*rng_state)(rl_stepop *op, size_t *size);
};

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

/* ------------------------------------------------------------ the built-in thermostats */

/* The parameter block of the three thermostats (rl_integrator_params' fields of the same names). */
typedef struct {
  double T0;               /* target temperature (> 0)                                           */
  double tau;              /* Bussi: relaxation time of K; Langevin: friction time 1/gamma (> 0) */
  unsigned long seed;      /* Bussi, Langevin: GSL mt19937 seed                                  */
  rl_thermo_groups groups; /* Bussi only                                                         */
} rl_thermostat_params;

/* isokinetic (RL_STEP_BEFORE_KICK, eqs. 17-18), bussi (RL_STEP_AFTER_KICK), langevin
 * (RL_STEP_MID_DRIFT); rl_integrator.h's rl_thermostat has what each does. */
extern const rl_stepop_type rl_stepop_isokinetic, rl_stepop_bussi, rl_stepop_langevin;

/* The descriptor named `name` ("isokinetic", "bussi", "langevin"), or NULL. */
const rl_stepop_type *rl_stepop_find(const char *name);
/* The operator rl_integrator_params.thermostat = t adds (NULL for RL_THERMO_NONE or unknown). */
const rl_stepop_type *rl_stepop_for_thermostat(rl_thermostat t);

#ifdef __cplusplus
}
#endif
#endif
