/* The run record a checkpoint of `rotleap run` carries besides the state (rl_checkpoint_meta's
 * blob): what a continuation needs to go on bit for bit, and to know it is the same run.
 *
 * Version 5 (this rotleap): a magic, then tagged sections, each a 4-character tag, a 64-bit
 * length and its bytes, little-endian (docs/files.md, "The run record"):
 *   BOOK  the averages' accumulators, the thermostat's account, the steps done, thermostat, seed
 *   RNG   the thermostat's random state                (omitted without one)
 *   LIST  the neighbour list's origin                  (omitted before the first list)
 *   LBOX  the box of the list's build, 3 edges          (omitted while it is the system's: the
 *         list outlives a barostat's scaling, forcefield.h)
 *   PHYS  the settings that define the simulation, as "key = value" lines: a continuation
 *         whose deck gives other values is another simulation
 *   MARK  per output stream: where it was, its length and hash (outputs.h)
 *   WTCH  the blow-up and drift watch (rl_watch, run.h)
 *   RLAX  present when the checkpoint was written during the relaxation: its step and time
 *   OPST  every step operator's account and own state (a barostat's random stream, trial size,
 *         counts), by operator name                (omitted unless one keeps a state)
 * Versions 1 to 4 (a fixed struct, older rotleap) are read for the state's bookkeeping only. */
#ifndef ROTLEAP_APP_RUNREC_H
#define ROTLEAP_APP_RUNREC_H

#include "outputs.h"
#include "scene.h"

#include <stddef.h>

#define RUNREC_MAX_OPS 8

/* Welford running mean and variance. */
typedef struct { long n; double mean, m2; } running;
void running_add(running *r, double x);
double running_sd(const running *r);

typedef struct {
  int version;            /* 5; 1-4 for records of older rotleap (decode only)                */
  double thermo_work;     /* energy the thermostat removed                                    */
  running E, U, T, Tt, Tr, P; /* the summary's averages: conserved energy, potential, T, T_trans,
                                 T_rot, pressure                                              */
  long done;              /* steps of the run so far                                          */
  long thermostat;        /* rl_thermostat of the run; -1: not recorded (version 1)           */
  unsigned long seed;     /* run.seed of its random stream                                    */
  const unsigned char *rng; size_t rng_size; /* the thermostat's random state                 */
  long list_count;        /* 0 or the number of bodies                                        */
  const double (*list)[3];/* the neighbour list's origin [list_count][3]                      */
  int has_list_box;       /* LBOX: the box of the list's build differs from the system's      */
  double list_box[3];
  const char *physics;    /* PHYS text, physics_len bytes (not NUL-terminated when decoded;
                             NULL for versions 1-4)                                         */
  size_t physics_len;
  out_mark marks[OUT_NSTREAMS];
  int has_watch;
  rl_watch watch;
  int nops;               /* OPST: the operators' saved states (rl_stepop_save)              */
  struct {
    const char *name;     /* the operator's type name (not NUL-terminated when decoded)          */
    size_t name_len;
    const unsigned char *bytes;
    size_t size;
    double work;          /* its account (rl_stepop.work): restored one by one, so that their sum
                             is the uninterrupted run's to the bit                                 */
  } ops[RUNREC_MAX_OPS];
  long relax_step;        /* -1: production; else the relaxation's step of the checkpoint      */
  double relax_time;
} run_record;

/* Serialise (version 5) into a malloc'd buffer.  RL_ENOMEM. */
int runrec_encode(const run_record *r, unsigned char **buf, size_t *size);
/* Parse and validate a record of any version; pointers in r point into blob.  nbodies: the
 * system's body count (the list origin must have 0 or that many entries).  RL_EINVAL naming
 * the file (path) and the field for anything malformed or out of range. */
int runrec_decode(const void *blob, size_t size, int nbodies, const char *path, run_record *r);

/* The settings that define the simulation of a deck (the PHYS section), malloc'd; NULL on out of
 * memory. */
char *runrec_physics(const rl_deck *d);
/* Write the checkpoint of sys at `step`, `time` with the run record r, whose thermostat account,
 * random state, list origin and operator states are taken here from `in` and `ff`.  RL_OK or a
 * status with a message naming path. */
int runrec_write_checkpoint(const char *path, const rl_system *sys, const rl_forcefield *ff, rl_integrator *in,
                            run_record *r, long step, double time);

/* The lines of the PHYS text old (len bytes) that now_text gives otherwise, as "key: X -> Y; ..."
 * in msg (cap bytes); their number.  outputs_only: the output.* lines only (the sampling of the
 * files), else the others (the simulation). */
int runrec_physics_diff(const char *old, size_t len, const char *now_text, int outputs_only, char *msg, size_t cap);
/* 1 if the record's run is another simulation than the one of the deck settings `physics`
 * (runrec_physics) with this thermostat, the differences in diff (cap bytes): the PHYS lines
 * other than output.* (version 5), the thermostat (older records); else 0. */
int runrec_other_simulation(const run_record *rec, const char *physics, rl_thermostat thermostat, char *diff, size_t cap);
/* The neighbour list the record's run had, its origin (and its box under a barostat), set on the
 * scene's force field before the first force computation, so that the pair sums keep their
 * order. */
int runrec_restore_list(const run_record *rec, scene *s);
/* A continuation: the record's state into `in`, the production integrator of the scene built
 * from its checkpoint: the neighbour list, `in` resumed at the start's step and time, the
 * thermostat's random state, its account and every step operator's state (a barostat's).  A
 * run.seed other than the record's (`seed`) asks for a new random stream: `in` keeps the one of
 * its own seed, and note (cap bytes) says so ("" otherwise).  RL_EINVAL naming path when the
 * record is not this integrator's (another thermostat, an operator's state missing). */
int runrec_restore(const run_record *rec, scene *s, rl_integrator *in, unsigned long seed, const char *path,
                   char *note, size_t cap);

#endif
