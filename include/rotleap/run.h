/* rotleap — the run driver: the loop that steps an integrator, evaluates the potential energy and
 * the virial on their cadence, watches for blow-ups and for drift of the conserved quantity, and
 * calls the reporters its caller registered (thermo rows, trajectory frames, checkpoints, samples
 * for an analysis, a Python callback).  `rotleap run`, `rotleap scan` and the relaxation of a
 * start all run through it; files, signals, progress lines and deck names stay with the caller.
 *
 * A step k takes the state at t_k to t_{k+1}.  Reporters are called after it, in the order they
 * were registered, each on its own cadence:
 *   RL_REPORT_STEP   the on-step values at t_k (rl_step_info: kinetic energies of eqs. 9/12,
 *                    potential, conserved quantity), with the energy components of the force
 *                    terms, the virial, pressure, forces and torques at t_k, when k is a multiple
 *                    of `every` (a multiple of the energy cadence: those values exist then);
 *   RL_REPORT_STATE  the state after the step, at t_{k+1}, when k + 1 is a multiple of `every`
 *                    (frames, samples and checkpoints: the system as it is, v and l at half steps).
 * After the last step rl_run_finish reports the on-step values of the last state once
 * (RL_REPORT_STEP with last = 1: the row of the last state).  A reporter's failure stops the run
 * with its status. */
#ifndef ROTLEAP_RUN_H
#define ROTLEAP_RUN_H

#include "rotleap/integrator.h"
#include "rotleap/terms.h"

#include <signal.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------------ the watch */

/* The names the watch's messages give the controls a user can change (a program's own: deck
 * keys for rotleap, arguments for a script).  NULL: a plain description. */
typedef struct {
  const char *timestep;  /* "run.timestep"                                                       */
  const char *relax;     /* how to relax an overlapping start ("run.equilibrate, with ...")      */
  const char *isokinetic;/* how to avoid the isokinetic scheme's undamped mode                   */
} rl_watch_names;

/* Blow-up and drift watch (its state: a checkpoint carries it, so that a continuation watches as
 * a run never stopped).  A blow-up stops the run at the step where it shows: a non-finite energy,
 * a jump of the total energy by more than 10 kT per molecule between two evaluations, or a
 * molecule moving more than the shortest box edge in one step.  A slower failure -- integration
 * error pumping energy into the system while a thermostat hides it -- shows as a drift of the
 * conserved quantity, measured over windows of `window` time units and at least 50 steps; above
 * `drift_error` kT per molecule per time unit the run stops.  kT is kB times the run's
 * temperature (the thermostat's or the start's), or the mean on-step temperature seen so far,
 * or a thousandth of |U|/N at the first evaluation, whichever is highest. */
typedef struct {
  double prevE;           /* total energy at the previous evaluation (NAN: none)               */
  double T1, T2;          /* on-step temperatures of the last two steps (NAN: none)            */
  double alt_sum;         /* sum of |T - 2 T1 + T2| / 4 over the open window, alt_n terms      */
  long alt_n;
  double alt_at_max;      /* that mean over T0 in the window of max_rate                       */
  int open;               /* a drift window is open, from step0, t0, conserved c0              */
  long step0;
  double t0, c0;
  double max_rate;        /* the largest drift seen, kT per molecule per time unit (signed)    */
  double rate_sum, rate_sum2; /* the sum of the windows' drift rates and of their squares      */
  long nwin;              /* closed windows                                                    */
  double T_sum;           /* the sum of the on-step temperatures seen, T_n of them             */
  long T_n;
  long nev;               /* steps with energies seen                                          */
  double U0;              /* the potential energy at the first of them                         */
  int relax;              /* the relaxation of a start: only a non-finite energy or a molecule
                             thrown across the box stops it (its energy may fall by any amount) */
} rl_watch;

typedef struct {
  double T;               /* the run's temperature (thermostat's, else the start's), > 0       */
  double window;          /* drift window in time units (rotleap: 1 ps, 1 reduced time unit)   */
  double drift_error;     /* kT per molecule per time unit that stops the run (rotleap: 5)     */
  double alt_mode;        /* the isokinetic mode is the cause above this alternation (0.02)    */
  int isokinetic;         /* the thermostat is the paper's isokinetic scheme                   */
  rl_watch_names names;
} rl_watch_params;

void rl_watch_init(rl_watch *w);
/* Check the step k whose on-step report is info (every: the energy cadence; h: the time step; sys:
 * its state after the step).  RL_OK or a status with a message naming the step, the cause and
 * what to change. */
int rl_watch_step(rl_watch *w, const rl_watch_params *p, const rl_system *sys, const rl_step_info *info, long k,
                  long every, double h);
/* The energy scale kT of the watch. */
double rl_watch_kT(const rl_watch *w, const rl_watch_params *p, const rl_system *sys);
/* The mean drift over the closed windows and its standard error (kT per molecule per time
 * unit); 0 with fewer than 2 windows (then *sem = NAN). */
double rl_watch_drift(const rl_watch *w, double *sem);
/* 1 if the isokinetic scheme's period-2 mode, not the time step, explains a drift whose windows
 * alternated by `alt` (alt_at_max). */
int rl_watch_isokinetic_mode(const rl_watch_params *p, double alt);

/* ----------------------------------------------------------------------------- reporters */

typedef enum { RL_REPORT_STEP = 0, RL_REPORT_STATE = 1 } rl_report_when;

typedef struct {
  long step;                   /* STEP: k, the values are at t_k; STATE: k + 1, the state at t_{k+1} */
  double time;                 /* of the values reported                                          */
  int last;                    /* the report of the last state (rl_run_finish)                     */
  const rl_step_info *info;    /* STEP: on-step values at t_k; STATE: NULL                         */
  const double *energies;      /* STEP: the terms' energy components at t_k (rl_terms order)        */
  double pressure;             /* STEP: (2 ke_trans + tr virial) / 3V at t_k, energy/volume        */
  const rl_forces *forces;     /* STEP: forces, torques, energy and virial at t_k                  */
  const rl_system *sys;        /* the system (STATE: at t_{k+1}, v and l at half steps)            */
  const rl_terms *terms;       /* the force terms (names of the energy components)                 */
} rl_run_report;

typedef struct {
  const char *name;            /* for messages                                                      */
  rl_report_when when;
  long every;                  /* cadence (> 0); STEP reporters: a multiple of the energy cadence  */
  int (*report)(void *ctx, const rl_run_report *r);
  void *ctx;
} rl_reporter;

/* ---------------------------------------------------------------------------- the driver */

typedef struct {
  long energy_every;           /* the integrator's energy cadence (rl_integrator_params)           */
  double h;                    /* its time step (for the watch's messages and displacements)        */
  rl_watch_params watch;
  /* checks the values of a STEP report before any reporter sees them (finite energies, virial,
   * pressure); NULL: the library's check.  Returns RL_OK or a status with a message. */
  int (*check)(void *ctx, const rl_run_report *r);
  void *check_ctx;
} rl_run_params;

typedef struct rl_run rl_run;

/* A driver for `in`, which moves `sys` under the force terms `terms` (the integrator's provider).
 * NULL on out of memory. */
rl_run *rl_run_alloc(rl_system *sys, rl_integrator *in, rl_terms *terms, const rl_run_params *p);
void rl_run_free(rl_run *r);
int rl_run_add_reporter(rl_run *r, const rl_reporter *rep);
/* The watch's state (for a checkpoint, and to restore it on a continuation). */
rl_watch *rl_run_watch(rl_run *r);

/* Steps k = first .. last - 1.  *stop (may be NULL) is read before each step: nonzero ends the run
 * there (RL_OK, *done says how many steps were taken).  A failed step, check, watch or reporter
 * ends it with its status and message. */
int rl_run_steps(rl_run *r, long first, long last, const volatile sig_atomic_t *stop, long *done);
/* The report of the last state, at step `step` (rl_integrator_observe: energies computed again if
 * the last step had none), to every STEP reporter with last = 1: each decides whether it takes it
 * (a thermo file's row of the last state: yes; averages over the steps: no).  The values are
 * checked first, as a step's are. */
int rl_run_finish(rl_run *r, long step);

#ifdef __cplusplus
}
#endif
#endif
