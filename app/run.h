/* The run driver behind `rotleap run` and `rotleap energy`. */
#ifndef ROTLEAP_APP_RUN_H
#define ROTLEAP_APP_RUN_H
#include "deck.h"
/* Run the deck; progress and errors to stderr.  Returns 0 or 1. */
int rl_app_run(const rl_deck *d);
/* Evaluate the starting configuration once: energies by term, virial, pressure and per-molecule
 * force and torque, as CSV (default) or one JSON object, on stdout. */
int rl_app_energy(const rl_deck *d, int json);
#endif
