/* The scene of a deck: molecule, system in its starting state and force field, shared by
 * `rotleap run`, `rotleap energy` and `rotleap scan`. */
#ifndef ROTLEAP_APP_SCENE_H
#define ROTLEAP_APP_SCENE_H
#include "deck.h"

#include <signal.h>
#include <stddef.h>

typedef struct {
  rl_molecule mol;
  rl_system *sys;
  rl_terms *terms;      /* the interactions, a sum of force terms (terms.h)               */
  rl_forcefield *ff;    /* the pair term's state (in terms): its kernels, list and checks  */
  int restart;          /* started from a checkpoint                                  */
  long step0;           /* the checkpoint's step and time                             */
  double t0;
  void *blob;           /* the checkpoint's run record (owned)                        */
  size_t blob_size;
} scene;

/* Molecule, system (lattice, PDB, XYZ or checkpoint start; Maxwell-Boltzmann velocities unless
 * restarting) and force field.  1 with rl_last_error() set; call scene_free either way. */
int scene_build(const rl_deck *d, scene *s);
void scene_free(scene *s);
/* RL_OK unless one of the n output paths is the deck or system.start (the same file: device and
 * inode); then an error naming both, for the caller to stop before anything is written.  A .chk
 * output may be a .chk start: that is a continuation. */
int scene_check_outputs(const rl_deck *d, const char *const *paths, int n);
/* The interactions of the deck for `sys`: the pair term (with the model's geometric mixing),
 * or NULL with a message. */
/* The Verlet skin: interactions.skin, or if not given 0.1 cutoff, the fastest in the scans at
 * 2 fs for TIP4P and h* = 0.002 for Stockmayer (bench/skin_*.csv), where a molecule's thermal
 * displacement per step v h (v = sqrt(3 kT / m), T the thermostat's or the start's) is about
 * 0.0015 cutoff.  At larger steps the list is rebuilt more often (every few steps at 8 fs, where
 * the builds took 8.5 % of a 256-TIP4P step), so the skin grows as sqrt(v h / (0.0015 cutoff)),
 * the minimum of a cost linear in the skin plus one in v h / skin, up to 0.25 cutoff.  The skin
 * changes the speed, and with a cell grid (edges >= 2.5 list radii) the cells and so the order
 * of the pair sums (round-off); the kernels' sums do not depend on the candidates beyond the
 * cutoff. */
double scene_skin(const rl_deck *d, const rl_molecule *mol);
rl_terms *scene_terms(const rl_deck *d, const rl_molecule *mol, const rl_system *sys);
/* The deck's relaxation phase (run.equilibrate steps at run.equilibrate_timestep under Bussi with
 * tau = 20 steps; nothing for a checkpoint start).  scene_relax runs all of it (rotleap scan);
 * rotleap run drives it in parts so that a signal can stop it and a checkpoint continue it. */
int scene_relax(const rl_deck *d, scene *s);
typedef struct scene_relaxation scene_relaxation;
/* Begin the relaxation at its step k0: 0 from the start's on-step state, or k0 > 0 from a
 * checkpoint written during it at time t0 (v, l at half steps; restore the thermostat's account
 * and random state through scene_relax_integrator).  NULL with a message. */
scene_relaxation *scene_relax_begin(const rl_deck *d, scene *s, long k0, double t0);
/* Step until the relaxation is done or *stop is nonzero (then RL_OK with steps left). */
int scene_relax_run(const rl_deck *d, scene *s, scene_relaxation *r, const volatile sig_atomic_t *stop);
long scene_relax_step(const scene_relaxation *r);     /* steps done                           */
rl_integrator *scene_relax_integrator(scene_relaxation *r);
/* With `finish`, put on-step v and l back into the system for the production; then free. */
int scene_relax_end(scene_relaxation *r, int finish);
/* Watching a run for blow-ups (scene.c says what and why). */
#define SCENE_WINDOW 1.0       /* drift window: 1 ps (real), 1 time unit (lj)              */
#define SCENE_DRIFT_ERROR 5.0  /* kT per molecule per time unit: the run is stopped        */
#define SCENE_DRIFT_WARN 0.5   /* kT per molecule per time unit: the summary warns         */
#define SCENE_ALT_MODE 0.02 /* see scene_drift_mode                                        */
typedef struct {
  double prevE;           /* total energy of the previous step (NAN: none)                */
  double T1, T2;          /* the on-step temperatures of the last two steps (NAN: none)     */
  double alt_sum;         /* sum of |T - 2 T1 + T2| / 4 over the open window, alt_n terms   */
  long alt_n;
  double alt_at_max;      /* that mean over run.temperature in the window of max_rate       */
  int open;               /* a drift window is open, from step0, t0, conserved c0         */
  long step0;
  double t0, c0;
  double max_rate;        /* the largest drift seen, kT per molecule per time unit (signed) */
  double rate_sum, rate_sum2; /* the sum of the windows' drift rates and of their squares   */
  long nwin;              /* closed windows                                                */
  double T_sum;           /* the sum of the on-step temperatures seen, T_n of them: the     */
  long T_n;               /*   scale kT is kB max(the deck's T, their mean) (scene_watch_kT) */
  long nev;               /* steps with energies seen                                     */
  double U0;              /* the potential energy at the first of them                    */
  int relax;              /* the relaxation of a start: its energy may fall by any amount,
                             so only a non-finite energy or a jump across the box stops it */
} scene_watch;
void scene_watch_init(scene_watch *w);
/* The energy scale of the watch, "kT": kB times the deck's temperature (the thermostat's, else the
 * start's), or times the mean on-step temperature seen so far, or a thousandth of |U|/N at the
 * first step with energies, whichever is highest: a start near 0 K (1e-30 K) is not unstable
 * because the kinetic energy is tiny, and heats as its potential energy turns kinetic. */
double scene_watch_kT(const rl_deck *d, const scene_watch *w);
/* The mean drift of the conserved energy over the closed windows and its standard error (kT
 * per molecule per time unit); 0 with fewer than 2 windows (then *sem = NAN). */
double scene_watch_drift(const scene_watch *w, double *sem);
/* RL_OK, or an error naming the step, the cause and dt_name ("run.timestep") to reduce.  The
 * energy checks run on the steps that are multiples of every (output.energy_every; their info
 * has its energies) and compare with the previous such step; the displacement check on every
 * step. */
int scene_watch_step(const rl_deck *d, const scene *s, scene_watch *w, const rl_step_info *info, long step,
                     long every, double h, const char *dt_name);
/* RL_OK if every energy term, the nine virial elements (virial may be NULL) and the pressure
 * are finite; else RL_ENONFINITE with a message naming the first that is not ("the dispersion
 * energy is -nan") and the interactions that produce it. */
int scene_check_finite(const rl_deck *d, const rl_terms *t, const double *comp, const double *virial, double pressure);
/* 1 if a drift of the conserved energy comes from the isokinetic thermostat (eqs. 17-18) rather
 * than from the time step: under run.ensemble = nvt-isokinetic the scheme pins only the on-step
 * temperature and leaves a period-2 mode of the kinetic energy undamped; a start far from
 * run.temperature excites it, the temperature then alternates from step to step and the
 * 'conserved' sum drifts whatever the step (the CLI audit of the integrators: 256 Stockmayer
 * molecules started at 1.6 for 1.35 drifted 12.8 kT per molecule per time unit at h = 0.002 and
 * 56.8 at h / 4).  alt is the alternation measured (scene_watch's alt_at_max): the mean of
 * |T - 2 T1 + T2| / 4 (the amplitude of a period-2 oscillation) over run.temperature; a relaxed
 * start alternates by about 0.5 %, and above SCENE_ALT_MODE the mode is taken as the cause. */
int scene_drift_mode(const rl_deck *d, double alt);
/* Pressure from kJ/mol/nm^3 to the deck's output unit (bar for real units). */
double scene_pressure_out(const rl_deck *d, double p);
/* A checkpoint stores the half-step v(t - h/2), l(t - h/2) of the run that wrote it; for a new
 * start (scan) they are completed to on-step values with that run's h = run.timestep.  Nothing
 * for other starts. */
int scene_onstep(const rl_deck *d, scene *s);
/* Worst deviation from rigidity: max |A A^T - I| (matrix bodies), ||rho| - 1| (axis bodies). */
double scene_rigidity_error(const rl_system *s);
#endif
