/* What deck.c and deck_molecule.c share: the key table's types and indices, the raw deck of
 * phase 1, the line-format limits, and the few helpers both use (private to app/deck*.c). */
#ifndef ROTLEAP_APP_DECK_INTERNAL_H
#define ROTLEAP_APP_DECK_INTERNAL_H

#include "deck.h"
#include "quantity.h"

#include <stdio.h>
#include <sys/stat.h>

typedef enum { K_STRING, K_PATH, K_INT, K_REAL, K_BOOL, K_CHOICE, K_INTS } key_type; /* K_PATH: any path the system accepts;
                                                                                 K_INTS: one whole number or three */

typedef struct {
  const char *section, *name;
  key_type type;
  rl_dim dim;
  const char *def;       /* default as text; NULL = required or no default            */
  const char *choices;   /* K_CHOICE: "a|b|c"                                          */
  const char *help;
} key_def;

enum {
  K_MODEL, K_MOLFILE, K_COUNT, K_SPECIES, K_BOX, K_DENSITY, K_START, K_RESIDUES, K_LATTICE, K_ORIENT, K_SEED, K_TEMP, K_GENERAL, K_INERTIA,
  K_CUTOFF, K_SCHEME, K_LJ, K_SWITCH, K_DISP, K_EPSRF, K_MIXING, K_PAIRS, K_COULOMB, K_ETOL, K_EALPHA, K_PGRID, K_PORDER, K_EKMAX,
  K_EKMAX2, K_EBOUND, K_DIPOLE, K_SKIN, K_KERNEL, K_PRECISION,
  K_STEPS, K_DT, K_INTEGRATOR, K_ENSEMBLE, K_TTEMP, K_TAU, K_TAUROT, K_TGROUPS, K_TSEED, K_EQSTEPS, K_EQDT, K_THREADS,
  K_BARO, K_PRESSURE, K_BINTERVAL, K_TAUP, K_COMPRESS, K_BCOUPLING,
  K_PREFIX, K_THERMO, K_ENERGY, K_CHECKPOINT, K_TRAJ, K_SAMPLE, K_RDF, K_DISCARD, K_TCONF, K_PROGRESS, NKEYS
};

typedef struct {
  char *val[NKEYS];
  int line[NKEYS];                  /* 0 = default, -1 = --set                                */
  int bad[NKEYS];                   /* reported already (no value, or one that could not be
                                       parsed): skip the checks built on it                   */
  char *model_key[RL_MODEL_MAX_PARAMS], *model_val[RL_MODEL_MAX_PARAMS];
  int model_line[RL_MODEL_MAX_PARAMS], nmodel;
  const char *path;
  int lineno, problems;
  long bytes;                       /* read so far                                            */
  char *section;                    /* the current [section]; NULL before the first           */
  int section_bad;                  /* its header was refused: its keys are skipped           */
  int stopped;                      /* reading was stopped: the file is not a deck            */
  FILE *err;
  /* [molecule NAME] sections: their headers and key lines, in order, with file and line */
  struct { char *name; const char *file; int line; } mol[RL_DECK_MAX_MOLECULES];
  int nmol;
  struct { int mol; char *key, *val; const char *file; int line; } *ml;
  int nml, cap_ml;
  int molfile;                      /* reading system.molecules: [molecule] sections only      */
  char *molpath;                    /* its path as opened (messages name it)                  */
} raw_deck;

/* The line format's limits (deck.c, "the line format"). */
#define DECK_LINE_MAX 199 /* libinih's INI_MAX_LINE (200) less its terminator */
#define DECK_SECTION_MAX 49 /* libinih's MAX_SECTION (50) less its terminator */
#define DECK_BYTES_MAX 1048576L
#define DECK_READ_PROBLEMS_MAX 100
#define DECK_KEEP (RL_DECK_PATH_MAX + 64) /* characters kept of a line: a path key's */

/* A problem at a line of the deck (line 0: the file, -1: --set), or of another file (a molecule
 * file); counted in r->problems. */
void deck_problem(raw_deck *r, int line, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
void deck_problem_at(raw_deck *r, const char *file, int line, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
/* What a file that is not a plain file is, for messages. */
const char *deck_file_kind(mode_t m);
/* A problem if key k was not given. */
void deck_require(raw_deck *r, int k);
/* Read a deck (or a molecule file) from f into r: 0, or -1 if reading stopped (not a deck). */
int deck_read(FILE *f, raw_deck *r);

/* deck_molecule.c: [molecule NAME] sections. */
/* The molecule a [molecule NAME] section defines: its index, or -1 if section is not one. */
int deck_molecule_section(const raw_deck *r, const char *section);
/* A section header [name]: 1 if its keys are to be read (registers a [molecule NAME]). */
int deck_new_molecule(raw_deck *r, const char *name);
/* Every [molecule] section parsed into d->molecules; system.model resolved among them first,
 * then in the catalogue. */
void deck_resolve_model(raw_deck *r, rl_deck *d);
/* interactions.pairs against the resolved species (units: d->units). */
void deck_pairs(raw_deck *r, rl_deck *d);
/* system.residues against the resolved species (a .pdb start only). */
void deck_residues(raw_deck *r, rl_deck *d);

#endif
