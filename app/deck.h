/* Decks: INI files describing a run (the line format is deck.c's own, documented in docs/deck.md).
 * One table (deck.c) lists every key with its section, type, unit, default and meaning; it drives
 * parsing, validation, `rotleap run --help` and docs/deck.md (`rotleap deck-keys --markdown`). */
#ifndef ROTLEAP_APP_DECK_H
#define ROTLEAP_APP_DECK_H

#include <rotleap/rotleap.h>
#include <limits.h>
#include <stdio.h>

/* The path fields hold any path the system accepts: PATH_MAX bytes with the terminating NUL
 * (a longer value is refused by its key, never cut). */
#ifdef PATH_MAX
#define RL_DECK_PATH_MAX PATH_MAX
#else
#define RL_DECK_PATH_MAX 4096
#endif
/* The longest file name (a path's last part) the system accepts. */
#ifdef NAME_MAX
#define RL_DECK_NAME_MAX NAME_MAX
#else
#define RL_DECK_NAME_MAX 255
#endif
/* Every output's path is output.prefix followed by a suffix of at most this many characters
 * (".thermo.csv.part.old", ".rl-quaternion.h0.0025.scan.csv", ".tmp.<pid>", ...): the deck refuses
 * a prefix that leaves less room, so char name[RL_DECK_PATH_MAX] holds every output's path, and
 * a last path part that leaves less room below NAME_MAX (255 bytes). */
#define RL_DECK_SUFFIX_MAX 64

/* interactions.coulomb: how charges interact.  rf: the pair term's reaction field (eps_rf);
 * ewald, pme: the pair term without charges, plus the Ewald terms "ewald-real" and "ewald"
 * (k-vector sum) or "pme" (smooth PME) of rotleap/ewald.h. */
typedef enum { RL_DECK_COULOMB_RF = 0, RL_DECK_COULOMB_EWALD = 1, RL_DECK_COULOMB_PME = 2 } rl_deck_coulomb;

/* A molecule a deck defines ([molecule NAME] in the deck or in system.molecules): a model like
 * the catalogue's, whose define() builds it from these sites with rl_molecule_build.  model is
 * the first member: d->model points at it (rl_deck_user_molecule finds the rest). */
#define RL_DECK_MAX_MOLECULES 8
#define RL_DECK_SYMMETRIZE_RTOL 1e-4 /* [molecule] symmetrize = yes: moments this close (relative) are equal;
                                       the summary warns of a near miss below it */
typedef struct {
  rl_model model;
  char name[32];
  int nsites;
  char site_names[RL_MOLECULE_MAX_SITES][8];
  const char *site_ptrs[RL_MOLECULE_MAX_SITES];
  double pos[RL_MOLECULE_MAX_SITES][3], mass[RL_MOLECULE_MAX_SITES];
  double sigma[RL_MOLECULE_MAX_SITES], epsilon[RL_MOLECULE_MAX_SITES], charge[RL_MOLECULE_MAX_SITES];
  double dipole[RL_MOLECULE_MAX_SITES][3], quadrupole[RL_MOLECULE_MAX_SITES];
  double inertia[3];        /* [molecule] inertia: single-centre dipoles                 */
  int symmetrize;           /* [molecule] symmetrize = yes: RL_DECK_SYMMETRIZE_RTOL      */
} rl_deck_molecule;

/* system.species: the species of a mixture in the deck's order (system.model and count: one
 * species); interactions.pairs: LJ parameters of site pairs that replace the mixing rule's. */
#define RL_DECK_MAX_SPECIES 8
#define RL_DECK_MAX_PAIRS 16
#define RL_DECK_MAX_RESIDUES 16
typedef struct {
  const rl_model *model;    /* a catalogue model (its default parameters) or a deck molecule */
  int count;
} rl_deck_species;
typedef struct {
  int species[2], site[2];  /* indices into d->species and its molecule's sites            */
  double sigma, epsilon;
} rl_deck_pair;
typedef enum { RL_DECK_MIXING_MODEL = 0, RL_DECK_MIXING_LB = 1, RL_DECK_MIXING_GEOMETRIC = 2 } rl_deck_mixing;

typedef struct {
  /* [system] */
  const rl_model *model;    /* a catalogue model, or &molecules[i].model; species[0]'s     */
  rl_deck_species species[RL_DECK_MAX_SPECIES]; /* system.species, or {model, count}       */
  int nspecies;
  rl_deck_molecule molecules[RL_DECK_MAX_MOLECULES]; /* the deck's [molecule] sections     */
  int nmolecules;
  double params[RL_MODEL_MAX_PARAMS];
  int force_general;
  double inertia_scale;     /* system.inertia_scale: every molecule's moments times this (1)   */
  int count;               /* all molecules (the sum of the species' counts)               */
  double box[3];            /* resolved: from `box` or from `density`                   */
  rl_lattice lattice;
  int insert;               /* system.lattice = random: random insertion (scene.c)         */
  int random_orientations;
  unsigned long seed;
  double temperature;       /* initial Maxwell-Boltzmann temperature                    */
  char start[RL_DECK_PATH_MAX]; /* "" = lattice; else a .pdb, .xyz or .chk file (a regular file) */
  rl_pdb_residue residues[RL_DECK_MAX_RESIDUES]; /* system.residues: a .pdb start's names  */
  int nresidues;
  /* [interactions] */
  rl_ff_params ff;
  rl_deck_mixing mixing;    /* interactions.mixing                                        */
  rl_deck_pair pairs[RL_DECK_MAX_PAIRS]; /* interactions.pairs                            */
  int npairs;
  rl_deck_coulomb coulomb;  /* interactions.coulomb                                       */
  rl_ewald_params ewald;    /* interactions.ewald_*, pme_* (coulomb = ewald | pme): tolerance,
                               alpha, grid, order, kmax, kmax_sq, eps_surface as given (0:
                               derived); species, cutoff and threads are the scene's       */
  /* [run] */
  long steps;
  double timestep;
  rl_rot_method method;
  rl_thermostat thermostat;
  double thermostat_temperature, tau;
  double tau_rot; /* nvt-langevin-dot(-obabo): rotational friction time (default tau) */
  unsigned long thermostat_seed;
  rl_thermo_groups thermostat_groups;
  int barostat;             /* 0 none, 1 Monte Carlo, 2 C-rescale (run.barostat)          */
  double pressure;          /* run.pressure, energy/volume (real: kJ mol^-1 nm^-3)       */
  long baro_interval;       /* steps between barostat moves                              */
  double tau_p, compressibility; /* C-rescale (compressibility: volume/energy)           */
  int baro_aniso;           /* run.barostat_coupling: 0 isotropic, 1 anisotropic, 2 semiisotropic */
  long equilibrate_steps;
  double equilibrate_timestep;
  /* [output] */
  char prefix[RL_DECK_PATH_MAX]; /* leaves RL_DECK_SUFFIX_MAX characters; names a file, not a directory */
  long thermo_every;
  long energy_every;        /* potential energy and virial every this many steps        */
  long checkpoint_every;    /* 0: only at the end                                        */
  long trajectory_every;    /* 0: none                                                   */
  long sample_every;        /* configurations for RDFs and correlation functions         */
  char rdf[256];            /* "O-O, H-H": site pairs (a longer value is refused)         */
  long discard;             /* output.discard: -1 auto, else steps left out of the averages */
  int tconf;                /* output.tconf: the configurational temperature of each sample */
  int progress;             /* -1 auto (a terminal), 0 no, 1 yes                        */
  rl_units units;
  char path[RL_DECK_PATH_MAX]; /* the deck's path, as given                                */
} rl_deck;

/* The largest thread count: run.threads, and OMP_NUM_THREADS where run.threads = 0 takes it. */
#define RL_DECK_MAX_THREADS 4096

/* 1 if the molecule's trajectory is a DCD of its sites (+ a PDB topology), 0 if an extended XYZ
 * of centres and orientations (point dipoles, atoms). */
int rl_deck_site_model(const rl_molecule *m);

/* The deck's molecule behind d->model, or NULL for a catalogue model. */
const rl_deck_molecule *rl_deck_user_molecule(const rl_deck *d);
/* The deck's molecule behind model m, or NULL for a catalogue model. */
const rl_deck_molecule *rl_deck_user_model(const rl_model *m);

/* The integrators by name: run.integrator and `rotleap scan --integrators`. */
typedef struct {
  const char *name;
  rl_rot_method method;
  const char *help;
} rl_deck_integrator;
extern const rl_deck_integrator rl_deck_integrators[];
extern const int rl_deck_nintegrators;
/* Index into rl_deck_integrators, or -1. */
int rl_deck_integrator_lookup(const char *name);

/* The dielectric constant of the surroundings that the dipole-fluctuation formula of the
 * dielectric constant needs: eps_rf for the reaction field, the Ewald sum's eps' (INFINITY for
 * tin foil) under coulomb = ewald | pme.  The formula is the same (Neumann, Mol. Phys. 50, 841
 * (1983)): (eps - 1)(2 eps' + 1)/(2 eps' + eps) = 4 pi kc <dM^2>/(3 V kT). */
double rl_deck_boundary_eps(const rl_deck *d);

/* The higher of system.temperature and run.temperature (the start's and the thermostat's); *key
 * (if key is not NULL) is "" for system.temperature, " (run.temperature)" for the thermostat's,
 * for messages. */
double rl_deck_max_temperature(const rl_deck *d, const char **key);
/* The thermal angular velocity sqrt(kB T / J_min) of the deck's molecule at that temperature
 * (0 for point particles): a step with h omega > 1 cannot follow the rotation. */
double rl_deck_thermal_omega(const rl_deck *d);

/* output.rdf ("O-O, H1-H1") against the model m: up to RL_DECK_MAX_RDF pairs of site indices
 * and their names; the number of pairs, or -1 with the message set (rl_last_error) for a pair
 * that is not SITE-SITE, a site the model does not have (naming those it has), or too many. */
#define RL_DECK_MAX_RDF 8
int rl_deck_rdf_pairs(const char *spec, const rl_molecule *m, int site[][2], char name[][24]);
/* One pair of output.rdf in a deck of several species: species (indices into the species,
 * the system's order) and sites, and its name as the deck wrote it (the rdf.csv column g_NAME). */
typedef struct {
  int species[2], site[2];
  char name[48];
} rl_deck_rdf_pair;
/* output.rdf against the species mols[nspecies] (mols[k].name the species' name): each pair is
 * A-B, each side SPECIES:SITE, or a bare NAME: a site of the first species (the one-species
 * syntax, "O-O"), else a species of one site ("na-cl"); names with '-' in them (spc-e:O) are
 * read at the one '-' where both sides resolve.  The number of pairs, or -1 with the message set
 * for a side that resolves to nothing (naming the sites or species there are), a pair read two
 * ways, or too many pairs. */
int rl_deck_rdf_species_pairs(const char *spec, const rl_molecule *mols, int nspecies, rl_deck_rdf_pair *out);

/* Parse `path` with the overrides `sets` ("section.key=value", nsets of them).  Every problem is
 * reported, one line each ("FILE:LINE: message", "--set section.key: message"), to `err`;
 * returns the number of problems (0 = the deck is usable). */
int rl_deck_load(const char *path, char **sets, int nsets, rl_deck *d, FILE *err);

/* Print every key: as text (for --help) or as the Markdown of docs/deck.md. */
void rl_deck_print_keys(FILE *f, int markdown);

#endif
