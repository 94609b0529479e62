/* The scene of a deck: molecule, system in its starting state and force field, shared by
 * `rotleap run`, `rotleap energy` and `rotleap scan`. */
#ifndef ROTLEAP_APP_SCENE_H
#define ROTLEAP_APP_SCENE_H
#include "deck.h"

#include <signal.h>
#include <stddef.h>

typedef struct {
  rl_molecule mol;      /* the first species' (the only one without system.species)        */
  rl_molecule mols[RL_DECK_MAX_SPECIES]; /* every species', d->nspecies of them; mols[0] = mol */
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
/* The lightest of the species' molecules mols[d->nspecies] (it moves farthest per step: the
 * skin of a mixture is its). */
const rl_molecule *scene_lightest(const rl_deck *d, const rl_molecule *mols);
/* The interactions of the deck for `sys`, whose species are mols[d->nspecies]: the pair term
 * (with interactions.mixing and interactions.pairs), or NULL with a message. */
rl_terms *scene_terms(const rl_deck *d, const rl_molecule *mols, const rl_system *sys);
/* With interactions.coulomb = ewald | pme, the terms are the pair term without charges (LJ,
 * dispersion), "ewald-real" and "ewald" or "pme" (rotleap/ewald.h), one parameter block
 * (interactions.ewald_*, pme_*, the cutoff, run.threads).  scene_electrostatics: the reciprocal
 * term's one-line description (alpha, grid or k vectors, boundary, estimated RMS force error) in
 * buf, and 1; 0 (buf empty) with the reaction field.  scene_ewald_warnings: its setup warnings
 * (a net charge), as rl_ewald_warnings. */
int scene_electrostatics(const rl_deck *d, rl_terms *t, char *buf, size_t size);
int scene_ewald_warnings(rl_terms *t, rl_ff_warning *out, int max);
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
/* The run driver's watch (run.h) as rotleap runs it: windows of 1 ps (real) or 1 time unit (lj),
 * a drift above 5 kT per molecule per time unit stops the run and one above 0.5 is warned about
 * in the summary, the isokinetic scheme's mode is the cause above an alternation of 2 % of
 * run.temperature (the CLI audit of the integrators: 256 Stockmayer molecules started at 1.6 for
 * 1.35 drifted 12.8 kT per molecule per time unit at h = 0.002 and 56.8 at h / 4; a relaxed start
 * alternates by about 0.5 %), and the messages name the deck's keys. */
#define SCENE_WINDOW 1.0
#define SCENE_DRIFT_ERROR 5.0
#define SCENE_DRIFT_WARN 0.5
#define SCENE_ALT_MODE 0.02
void scene_watch_params(const rl_deck *d, int relax, rl_watch_params *w);
/* The integrator parameters of the deck, the one place they are built: for the production run
 * (SCENE_RUN), the relaxation (SCENE_RELAX: Bussi with tau = 20 relaxation steps at
 * run.equilibrate_timestep and system.temperature), or the on-step completion of a checkpoint's
 * half-step velocities (SCENE_ONSTEP: run.timestep, no thermostat). */
typedef enum { SCENE_RUN, SCENE_RELAX, SCENE_ONSTEP } scene_purpose;
void scene_integrator_params(const rl_deck *d, scene_purpose what, rl_integrator_params *p);
/* The driver of a production run of the deck over the scene's system, terms and `in`, with
 * rotleap's watch and checks (scene_check_finite); NULL with a message. */
rl_run *scene_run_driver(const rl_deck *d, scene *s, rl_integrator *in);
/* The deck's barostat (run.barostat) added to the production integrator in, before its init or
 * resume: RL_OK (nothing without one) or the operator's error.  Its random stream is seeded with
 * run.seed + SCENE_BARO_SEED (not the thermostat's stream); a move that would bring a box edge below
 * twice the cutoff stops the run. */
#define SCENE_BARO_SEED 1000003ul
int scene_add_barostat(const rl_deck *d, rl_integrator *in);
/* The system's mass in the unit whose ratio to the volume is the deck's density (g/cm3 for real
 * units: amu / 602.214076; reduced: the mass). */
double scene_density_mass(const rl_deck *d, const rl_system *sys);
/* The barostat of the production integrator in (its operator), or NULL. */
rl_stepop *scene_barostat(const rl_deck *d, rl_integrator *in);
/* RL_OK if every energy component comp (of the terms t), the nine virial elements (virial may
 * be NULL) and the pressure are finite; else RL_ENONFINITE with a message naming the first that
 * is not ("the dispersion correction is -nan") and the interactions that produce it. */
int scene_check_finite(const rl_deck *d, const rl_terms *t, const double *comp, const double *virial, double pressure);
/* 1 if a drift of the conserved energy comes from the isokinetic thermostat's undamped mode
 * (eqs. 17-18 hold only the on-step temperature; a start out of equilibrium excites a period-2
 * alternation of the kinetic energy) rather than the time step: under run.ensemble =
 * nvt-isokinetic, when the windows alternated by more than SCENE_ALT_MODE of run.temperature. */
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
