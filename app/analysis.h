/* Sampling and analysis for rotleap run: block-averaged thermodynamics, heat capacity, mean-square
 * forces and torques, RDFs of named site pairs, correlation functions, diffusion and the
 * dielectric constant, over the equilibrated part of the run (output.discard), in
 * PREFIX.results.txt, PREFIX.rdf.csv and PREFIX.tcf.csv.
 *
 * Every input (a step's report, a sampled configuration) is a record that can be journaled: a
 * continuation replays the journal of the run so far and its results are those of an
 * uninterrupted run, bit for bit.  Calling sequence (rotleap run):
 *   fresh run:     a = analysis_alloc(...); analysis_set_journal(a, fp, path) with fp a new, empty
 *                  file; then analysis_step / analysis_sample as the run goes;
 *   checkpoint:    analysis_journal_sync(a, &nbytes), then write nbytes into the checkpoint;
 *   continuation:  a = analysis_alloc(...); analysis_replay(a, path, nbytes of the checkpoint);
 *                  cut the journal to nbytes and open it for appending (positioned at nbytes);
 *                  analysis_set_journal(a, fp, path); then step and sample as usual;
 *   at the end:    analysis_write(a, prefix, suffix, dt_sample).
 * The journal's format: docs/observables.md, "The analysis journal". */
#ifndef ROTLEAP_APP_ANALYSIS_H
#define ROTLEAP_APP_ANALYSIS_H
#include "deck.h"

#include <stdio.h>

typedef struct analysis analysis;

/* NULL with a message (rl_last_error) on a bad output.rdf pair name or out of memory. */
analysis *analysis_alloc(const rl_deck *d, const rl_molecule *mols, const rl_system *sys); /* mols[d->nspecies] */
void analysis_free(analysis *a);
/* Every step with energies: on-step values at t (info: t, potential, temperatures, total,
 * conserved, kinetic energies), pressure at t, forces and torques at t, and the box edges at t
 * (NULL: the system's; under a barostat the report's, which the step may since have changed).  RL_ENONFINITE (nothing
 * taken) for a non-finite value; a failed journal write names the journal and the reason. */
int analysis_step(analysis *a, const rl_step_info *info, double pressure, const rl_forces *F,
                  const rl_system *sys, const double *box);
/* output.tconf: the force field whose configurational temperature each sample takes (forcefield.h,
 * rl_config_temperature), before the first sample; the results say n/a where the scene has a
 * force term other than the pair term.  Does nothing without output.tconf. */
int analysis_set_tconf(analysis *a, const rl_terms *terms, const rl_forcefield *ff);
/* Every output.sample_every steps: the configuration (positions, orientations, velocities) and,
 * with output.tconf, the configurational temperature's sums. */
int analysis_sample(analysis *a, const rl_system *sys);

/* Journal every later record to fp (binary, append-only; `path` names it in messages).  A fresh
 * analysis writes the journal's header first and needs fp at position 0; after analysis_replay
 * fp must be positioned at the end of the replayed part (the file cut to the replayed bytes).
 * Writes are checked: a failure names `path` and strerror, and every later step, sample or sync
 * fails.  The analysis does not close fp. */
int analysis_set_journal(analysis *a, FILE *fp, const char *path);
/* fflush and fsync the journal; *nbytes (may be NULL) = its length so far, the number a
 * checkpoint records for analysis_replay.  Call it before writing the checkpoint. */
int analysis_journal_sync(analysis *a, long *nbytes);
/* Feed the first nbytes of the journal `path` to a fresh analysis (before analysis_set_journal,
 * before any step or sample), without journaling them again.  Refused with a message naming the
 * file and the cause: not a journal, another byte order or version, a header that differs from
 * this run's (molecules, units, model, box, run.timestep, output.energy_every, sample_every and
 * rdf), a file shorter than nbytes, nbytes not at a record boundary, a damaged record.  On
 * failure the analysis is spoiled: free it. */
int analysis_replay(analysis *a, const char *path, long nbytes);

/* run.barostat: the barostat's counts and trial sizes of the whole run (rl_barostat_stats_of),
 * reported by analysis_write (the Monte Carlo acceptance and trial step). */
void analysis_set_barostat_stats(analysis *a, const rl_barostat_stats *s);
/* PREFIX.results.txt, PREFIX.tcf.csv (with 4 samples or more) and PREFIX.rdf.csv (with an RDF
 * asked for and sampled), each with `suffix` appended to its name (NULL or "": none; ".part"
 * for the files of a failed run), each written atomically: a file that cannot be written keeps
 * its earlier version and the others are written all the same.  RL_OK, or RL_EINVAL with every
 * failure named in rl_last_error ("PREFIX.rdf.csv: cannot rename ... over it: Is a directory"). */
int analysis_write(analysis *a, const char *prefix, const char *suffix, double dt_sample);
/* A relative fluctuation (calE, calU) as text: "%.6e", or "n/a (...)" where it is undefined
 * (NaN or infinite: a quantity whose mean is 0, such as U of a gas with no pair in range). */
const char *rel_fluct_text(char *buf, size_t n, double x);
#endif
