/* Sampling and analysis for rotleap run: block-averaged thermodynamics, heat capacity, mean-square
 * forces and torques, RDFs of named site pairs, correlation functions, diffusion and the
 * dielectric constant.  Results cover the samples of this invocation (PREFIX.results.txt,
 * PREFIX.rdf.csv, PREFIX.tcf.csv). */
#ifndef ROTLEAP_APP_ANALYSIS_H
#define ROTLEAP_APP_ANALYSIS_H
#include "deck.h"

typedef struct analysis analysis;

/* NULL with a message (rl_last_error) on a bad output.rdf pair name or out of memory. */
analysis *analysis_alloc(const rl_deck *d, const rl_molecule *mol, const rl_system *sys);
void analysis_free(analysis *a);
/* Every step: on-step values at t, pressure at t, forces and torques at t. */
int analysis_step(analysis *a, const rl_step_info *info, double pressure, const rl_forces *F,
                  const rl_system *sys);
/* Every output.sample_every steps: the configuration (positions, orientations, velocities). */
int analysis_sample(analysis *a, const rl_system *sys);
/* PREFIX.results.txt, PREFIX.tcf.csv (with 4 samples or more) and PREFIX.rdf.csv (with an RDF
 * asked for and sampled), each written atomically: a file that cannot be written keeps its earlier
 * version and the others are written all the same.  RL_OK, or RL_EINVAL with every failure named
 * in rl_last_error ("PREFIX.rdf.csv: cannot rename ... over it: Is a directory"). */
int analysis_write(analysis *a, const char *prefix, double dt_sample);
/* A relative fluctuation (calE, calU) as text: "%.6e", or "n/a (...)" where it is undefined
 * (NaN or infinite: a quantity whose mean is 0, such as U of a gas with no pair in range). */
const char *rel_fluct_text(char *buf, size_t n, double x);
#endif
