/* The scene of a deck: molecule, system in its starting state and force field, shared by
 * `rotleap run`, `rotleap energy` and `rotleap scan`. */
#ifndef ROTLEAP_APP_SCENE_H
#define ROTLEAP_APP_SCENE_H
#include "deck.h"

#include <stddef.h>

typedef struct {
  rl_molecule mol;
  rl_system *sys;
  rl_forcefield *ff;
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
/* A force field for `sys` with the deck's interactions (and the model's geometric mixing), or
 * NULL with a message. */
rl_forcefield *scene_forcefield(const rl_deck *d, const rl_molecule *mol, const rl_system *sys);
/* The deck's relaxation phase (run.equilibrate steps; nothing for a checkpoint start). */
int scene_relax(const rl_deck *d, scene *s);
/* A blow-up ends a run at the step where it shows; RL_OK or an error naming step and cause.
 * prevE: the total energy of the previous step (NAN for the first); h the step in use, named
 * dt_name in the advice ("run.timestep"). */
int scene_blow_up_check(const rl_deck *d, const scene *s, const rl_step_info *info, long step,
                        double prevE, double h, const char *dt_name);
#endif
