/* rotleap — interactions: a force field over an rl_system in its orthorhombic periodic cell.
 *
 * Kernels (forces/pair/): Lennard-Jones (Lorentz-Berthelot with per-pair overrides; plain, shifted,
 * shifted-force or OpenMM-switched truncation; optional long-range dispersion correction),
 * reaction-field Coulomb exactly as OpenMM 7.7 NonbondedForce.CutoffPeriodic (intramolecular pairs
 * excluded: they contribute nothing, as in OpenMM), point dipoles along body Z
 * (dipole-dipole and charge-dipole, reaction field a la Barker-Watts or shifted force as LAMMPS
 * lj/sf/dipole/sf) and linear point quadrupoles along body Z (2CLJQ).  Formulas, units and the
 * OpenMM finding: docs/interactions.md.
 *
 * Units: those of the system.  real: nm, kJ/mol, e; dipole e nm; quadrupole e nm^2; Coulomb
 * constant RL_COULOMB_KJMOL_NM.  lj: reduced, Coulomb constant 1.
 *
 * A force field becomes an rl_force_provider (integrator.h) for the system it was made for. */
#ifndef ROTLEAP_FORCEFIELD_H
#define ROTLEAP_FORCEFIELD_H

#include "rotleap/forces.h"
#include "rotleap/terms.h"
#include "rotleap/system.h"
#include "rotleap/molecule.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Interaction sites of one species.  Site a sits where the system puts site a of the species. */
typedef struct {
  int nsites;                /* must equal the species' nsites in the rl_system              */
  const double *sigma;       /* [nsites] LJ sigma (>= 0)                                      */
  const double *epsilon;     /* [nsites] LJ epsilon (>= 0; 0 = no LJ on that site)            */
  const double *charge;      /* [nsites] charge                                               */
  const double *dipole;      /* [nsites] or NULL: point dipole moment along body Z at the site */
  const double *quadrupole;  /* [nsites] or NULL: linear quadrupole Q = sum q z^2 along body Z */
} rl_species_ff;

/* The interaction sites of a molecule type (pointers into m: keep m alive). */
rl_species_ff rl_molecule_ff(const rl_molecule *m);

typedef enum {
  RL_CUTOFF_SITE = 0,    /* every site pair cut by its own (minimum-image) distance (OpenMM)  */
  RL_CUTOFF_MOLECULE = 1 /* all site pairs of two molecules whose centres are within cutoff   */
} rl_cutoff_scheme;

typedef enum {
  RL_LJ_PLAIN = 0,         /* u(r)                                                         */
  RL_LJ_SHIFTED = 1,       /* u(r) - u(rc)                                                 */
  RL_LJ_SHIFTED_FORCE = 2, /* u(r) - u(rc) - (r - rc) u'(rc)                               */
  RL_LJ_SWITCHED = 3       /* u(r) S(r), OpenMM's switching function from r_switch to rc   */
} rl_lj_truncation;

typedef enum {
  RL_DIPOLE_RF = 0, /* reaction field (Barker-Watts) with eps_rf; eps_rf = 1 is plain truncation */
  RL_DIPOLE_SF = 1  /* shifted force (Allen & Germano 2006, LAMMPS lj/sf/dipole/sf)             */
} rl_dipole_method;

typedef enum {
  RL_COULOMB_RF = 0,        /* reaction field with eps_rf (OpenMM 7.7 CutoffPeriodic), the default */
  RL_COULOMB_EWALD_REAL = 1 /* the real-space part of an Ewald sum, kc q_a q_b erfc(alpha r) / r
                               with a plain cutoff (no shift), as the term "ewald-real" and OpenMM's
                               PME and Ewald compute it (rotleap/ewald.h; the reciprocal part is a
                               term of its own).  Needs alpha > 0, the site cutoff, no point
                               dipoles and intramolecular_rf = 0                               */
} rl_coulomb_method;

typedef enum {
  RL_KERNEL_AUTO = 0,   /* specialised pair kernels where a species' site pattern allows (below),
                           threaded with OpenMP; the reference routine for every other pair     */
  RL_KERNEL_GENERAL = 1 /* the reference path only: one general site-site routine, serial       */
} rl_kernel_choice;

typedef enum {
  RL_PRECISION_DOUBLE = 0, /* every pair term in double precision (default)                  */
  RL_PRECISION_MIXED = 1   /* the "tip4p" kernel's pair terms in single precision, with double
                              centre separations and sums (below); every other term double  */
} rl_precision;

/* Kernel choice (p.kernel = RL_KERNEL_AUTO, with the neighbour list on).  The choice is made
 * once, at rl_forcefield_alloc (and again after rl_forcefield_set_lj_pair), from each species'
 * site pattern; pairs of two bodies of one such species use its kernel, every other pair the
 * general site-site routine:
 *   "tip4p"      4 sites: one LJ site without charge, three charges without LJ, no dipoles or
 *                quadrupoles (TIP4P, TIP4P-Ew, TIP4P/2005): 1 LJ + 9 charge pairs, no site loop
 *   "charge-lj"  any other species with only LJ and charges on at most 8 sites (SPC/E, TIP3P,
 *                linear CO2, CH4, ...): every site pair, LJ and reaction field together
 * ("tip4p" and "charge-lj" compute the charges' Ewald real space instead of the reaction field
 * with coulomb = RL_COULOMB_EWALD_REAL, in the same pass, with a vectorised erfc)
 *   "stockmayer" one site at the centre with LJ and a point dipole, no charge (Stockmayer):
 *                LJ + dipole-dipole (RF or SF), no site loop
 * The results are those of the general routine up to round-off (tests/forces/
 * test_ff_fast.c: <= 1e-12 relative), overlaps are reported with the same message, and both
 * cutoff schemes and all LJ truncations are supported.  Without a neighbour list
 * (neighbor_list = 0) the reference path runs.
 *
 * Threads: the pair loop runs on `threads` OpenMP threads (0: OMP_NUM_THREADS if it is set,
 * else 1 -- threads are asked for, not assumed, as in LAMMPS), each
 * with its own force buffers, summed in thread order.  For a fixed thread count the results are
 * bit-for-bit reproducible; a different thread count sums in another order and changes them
 * at round-off (about 1e-15 relative).  Built without OpenMP, everything runs on one thread. */

typedef struct {
  double cutoff;                  /* rc (> 0, <= half the shortest edge)                        */
  rl_cutoff_scheme scheme;        /* default RL_CUTOFF_SITE                                     */
  rl_lj_truncation lj_truncation; /* default RL_LJ_PLAIN                                        */
  double r_switch;                /* switched: 0 <= r_switch < cutoff                           */
  int dispersion_correction;      /* 1: add the LJ long-range energy and pressure (default 0)   */
  double eps_rf;                  /* reaction-field dielectric >= 1, INFINITY allowed (default
                                     78.3, OpenMM's default)                                    */
  rl_dipole_method dipole_method; /* default RL_DIPOLE_RF                                       */
  int intramolecular_rf;          /* 0 (default): pairs within a molecule contribute nothing, as
                                     OpenMM 7.7 does for excluded pairs (validate/
                                     openmm_rf_intramolecular.py); 1: add the GROMACS-style
                                     excluded-pair term kc q_a q_b (krf r^2 - crf) (a constant
                                     for rigid bodies; central forces, no net force/torque)     */
  double coulomb_constant;        /* kc; 0 (default): RL_COULOMB_KJMOL_NM (real) or 1 (lj).
                                     OpenMM 7.7 uses 138.93545764438198 (see docs)             */
  int neighbor_list;              /* 1 (default): Verlet list of molecule pairs; 0: O(N^2) sum  */
  double skin;                    /* Verlet skin (>= 0); < 0 (default): 0.1 cutoff              */
  double min_distance;            /* site pairs closer than this are an error (overlap);
                                     < 0 (default): 1e-3 cutoff                                 */
  rl_kernel_choice kernel;        /* default RL_KERNEL_AUTO (see above)                         */
  int threads;                    /* OpenMP threads for the pair loop; 0 (default):
                                     OMP_NUM_THREADS if set, else 1                            */
  rl_precision precision;         /* default RL_PRECISION_DOUBLE (see below)                    */
  rl_coulomb_method coulomb;      /* the charges' electrostatics; default RL_COULOMB_RF         */
  double ewald_alpha;             /* RL_COULOMB_EWALD_REAL: the splitting parameter alpha > 0
                                     (1/length), e.g. rl_ewald_info's alpha of the reciprocal
                                     term it goes with; ignored otherwise (default 0)            */
} rl_ff_params;

/* Mixed precision (p.precision = RL_PRECISION_MIXED), as GROMACS's default build and OpenMM's
 * CPU platform compute nonbonded terms: the "tip4p" kernel forms its 10 terms per pair in single
 * precision, eight pairs to a 256-bit vector, on CPUs with AVX2 and FMA (its AVX2 rows, also on
 * CPUs with AVX-512).  The centres' separations (the minimum image), the list, the sums of the
 * forces on each body, the energies and the virial stay double.  Forces, energies and virial
 * then agree with the double kernels to about 1e-6 relative (tests/forces/test_ff_fast.c
 * states the bounds it checks).  Other kernels, the reference path, and CPUs without AVX2 (or
 * with ROTLEAP_NO_AVX2 set) compute in double, and so does the Ewald real space
 * (RL_COULOMB_EWALD_REAL): rl_forcefield_precision says what is in use. */

/* The Verlet skin `rotleap run` takes when none is given: 0.1 cutoff, and at large steps
 * 0.1 sqrt(x) cutoff with x = v h / (0.0015 cutoff), v = sqrt(3 kT / mass) the thermal speed, up
 * to 0.25 cutoff (the minimum of a cost linear in the skin plus one in v h / skin; docs/performance.md,
 * "Skin").  kT in energy units, h in time units of the system; 0.1 cutoff if kT, mass or h is not
 * positive. */
double rl_ff_skin_for_step(double cutoff, double kT, double mass, double h);

/* Energies of the last compute, split by term.  Sum = total = the energy added to rl_forces. */
typedef struct {
  double lj;          /* Lennard-Jones (truncated as chosen)                                  */
  double coulomb;     /* Coulomb between charges (reaction field, intermolecular + intramolecular;
                         or, with RL_COULOMB_EWALD_REAL, the Ewald real-space energy U_real)  */
  double coulomb_intra; /* intramolecular reaction-field part of `coulomb` (0 unless
                           intramolecular_rf = 1)                                             */
  double dipolar;     /* dipole-dipole and charge-dipole                                      */
  double quadrupolar; /* quadrupole-quadrupole                                                */
  double dispersion;  /* LJ long-range correction (0 unless enabled)                          */
  double total;
  double pressure_dispersion; /* LJ long-range pressure correction (already in the virial)   */
} rl_ff_energies;

typedef struct rl_forcefield rl_forcefield;

void rl_ff_params_default(rl_ff_params *p);

/* Validate and build a force field for `sys` (its species table and its periodic cell as they
 * are now).
 * in  sys, p, species[nspecies] (nspecies = rl_system_nspecies(sys)); the arrays are copied.
 * Returns NULL with rl_last_error() naming the problem (a system without a periodic cell,
 * cutoff too long for the box, nsites mismatch, missing arrays, negative or non-finite
 * sigma/epsilon, dipoles on point bodies, ...). */
rl_forcefield *rl_forcefield_alloc(const rl_system *sys, const rl_ff_params *p,
                                   const rl_species_ff *species, int nspecies);
void rl_forcefield_free(rl_forcefield *ff); /* accepts NULL */

/* Override the Lorentz-Berthelot LJ parameters of one site pair (species_a, site_a) -
 * (species_b, site_b) (symmetric).  sigma, epsilon >= 0. */
int rl_forcefield_set_lj_pair(rl_forcefield *ff, int species_a, int site_a, int species_b,
                              int site_b, double sigma, double epsilon);

/* The box is the system's: rl_system_set_box (a barostat, a checkpoint) changes it, and the next
 * rl_forcefield_compute takes the new cell (its version, system.h, tells), checks the cutoff
 * against it and rebuilds the neighbour lists.  rl_forcefield_get_box: the edges in use. */
void rl_forcefield_get_box(const rl_forcefield *ff, double L[3]);

/* Add forces, torques, energy and molecular virial of the current configuration to `out`
 * (f [n][3], k [nrot][3]; the caller zeroes them, as the provider contract says).  The virial
 * is sum over molecule pairs of r_ij (x) f_ij with r_ij the centre-centre vector (minimum
 * image consistent with the site pair) and includes the isotropic dispersion correction.
 * With out->forces_only set, energy and virial are not added (the kernels skip their sums; the
 * forces are the same to the bit).
 * Errors: RL_ESTATE if sys no longer matches (counts), RL_ENONFINITE for non-finite positions
 * or orientations (body named), RL_EINVAL for overlapping sites (bodies and sites named) and
 * for a system cell, changed since the last compute, that is too small for the cutoff or
 * none (the force field keeps its box then). */
int rl_forcefield_compute(rl_forcefield *ff, const rl_system *sys, rl_forces *out);

/* The force field as a provider for rl_integrator_alloc (ctx = ff). */
rl_force_provider rl_forcefield_provider(rl_forcefield *ff);

/* The force field as a force term (terms.h): the term type "pair", whose state is an
 * rl_forcefield built by rl_forcefield_alloc from this parameter block, on the system's cell
 * (whose changes it follows).  Its energy components: lj, coulomb, dipolar, quadrupolar,
 * dispersion. */
typedef struct {
  rl_ff_params p;
  const rl_species_ff *species; /* [nspecies], as rl_forcefield_alloc takes them              */
  int nspecies;
  int geometric_mixing;         /* 1: every LJ site pair of one species takes sqrt(sigma_a sigma_b),
                                   sqrt(eps_a eps_b) (OPLS, EPM2) through rl_forcefield_set_lj_pair */
} rl_pair_params;
extern const rl_term_type rl_term_pair;

/* Energies of the last successful compute (NaN after one with out->forces_only set). */
void rl_forcefield_energies(const rl_forcefield *ff, rl_ff_energies *e);

/* Molecular pressure P = (2 ke_trans + tr virial) / (3 V), with ke_trans the centre-of-mass
 * kinetic energy and `f` the result of a compute (virial incl. dispersion correction).
 * Units: energy / volume (real: kJ mol^-1 nm^-3 = 16.6054 bar). */
double rl_forcefield_pressure(const rl_forcefield *ff, const rl_forces *f, double ke_trans);

/* Neighbour-list builds so far (0 with neighbor_list = 0), and the list radius in use. */
long rl_forcefield_rebuilds(const rl_forcefield *ff);
/* The kernels in use, e.g. "tip4p", "stockmayer+general", "general" (the reference path), and
 * the number of threads of the pair loop (1 for the reference path). */
const char *rl_forcefield_kernel(const rl_forcefield *ff);
/* The kernel that computes the pairs of a body of species a with one of species b: a
 * specialised one ("tip4p", "charge-lj", "stockmayer") for two bodies of one species whose site
 * pattern has one (and at least 2 bodies), else "general", the reference routine (every pair of
 * two species today); NULL for a species out of range. */
const char *rl_forcefield_pair_kernel(const rl_forcefield *ff, int a, int b);
/* Which instruction set the dipole and TIP4P kernels' rows use: "avx512" or "avx2" (their
 * register rows, chosen at alloc from the CPU; ROTLEAP_NO_AVX512=1 and ROTLEAP_NO_AVX2=1 in the
 * environment rule either out), or "portable" (compiler-vectorised loops, also for every other
 * kernel and the reference path).  The three agree to round-off (about 1e-15 relative). */
const char *rl_forcefield_rows(const rl_forcefield *ff);
/* "mixed" when some pairs run in single precision (p.precision = RL_PRECISION_MIXED and a
 * "tip4p" kernel on AVX2 rows), else "double". */
const char *rl_forcefield_precision(const rl_forcefield *ff);
int rl_forcefield_threads(const rl_forcefield *ff);
double rl_forcefield_list_radius(const rl_forcefield *ff);

/* The neighbour list's origin: the centres at its last build, and the box then.  The list (its
 * pairs, their order and the threads' shares of rows) is a function of those centres and that
 * box, and so is the order of every sum over pairs.  The list outlives a change of the box (a
 * barostat's scaling of the centres) while its skin allows: its displacements are measured from
 * the origin scaled with the box, and the box's shrinking uses up skin (docs/interactions.md).
 * A checkpoint that stores the origin (and the box, when it is not the current one) lets a
 * restart build the same list and continue bit for bit: rl_forcefield_list_origin fills r0
 * [n][3] and rl_forcefield_list_box the edges L0[3], each returning 1 (0, nothing written, while
 * there is no list); rl_forcefield_set_list_origin (before the first compute) makes the next
 * build use r0 instead of the current centres, in the current box or, when
 * rl_forcefield_set_list_box follows it, in the box L0; the usual test then decides whether to
 * build again at once.  RL_EINVAL for non-finite r0, or an L0 not positive or shorter than twice
 * the cutoff. */
int rl_forcefield_list_origin(const rl_forcefield *ff, double (*r0)[3]);
int rl_forcefield_list_box(const rl_forcefield *ff, double L0[3]);
int rl_forcefield_set_list_origin(rl_forcefield *ff, const double (*r0)[3]);
int rl_forcefield_set_list_box(rl_forcefield *ff, const double L0[3]);

/* ------------------------------------------------------------- setup warnings, cutoff checks
 * The library never prints: these return text for the caller to show (rotleap prints them before
 * a run).  Each line is one sentence, at most RL_FF_TEXT - 1 characters. */
#define RL_FF_TEXT 256

typedef struct {
  char text[RL_FF_TEXT];
} rl_ff_warning;

/* Setup problems that are not errors: the cutoff is shorter than 2^(1/6) sigma (the LJ minimum)
 * of some site pair with epsilon > 0 that can interact, so the attractive well is cut (and
 * below sigma most of the repulsion too); and, after a compute, that no site pair at all was
 * within the cutoff (every intermolecular energy and force is zero).  Writes the first `max`
 * warnings to out (out may be NULL when max = 0) and returns how many there are. */
int rl_forcefield_warnings(const rl_forcefield *ff, rl_ff_warning *out, int max);

/* What the cutoff does to each interaction term of this force field (its species, parameters,
 * LJ overrides, truncation, cutoff scheme, eps_rf and dipole method; docs/interactions.md has
 * the derivation).  A pair energy that jumps where a pair crosses the cutoff by an amount that
 * depends on orientation makes the dynamics non-conservative: an NVE run drifts (the dipolar
 * reaction field heats) whatever the time step, and a thermostat hides it as heating.  A force
 * that jumps while the energy is continuous gives an energy error that falls with the time
 * step. */
typedef struct {
  const char *term;   /* "lj", "coulomb", "charge-dipole", "dipole-dipole", "quadrupole",
                         "coulomb-intramolecular" (static strings)                        */
  int energy_jumps;   /* 1: the pair energy is discontinuous at the cutoff                 */
  int heats;          /* 1: and the jump depends on the orientations (dipoles, quadrupoles,
                         off-centre sites cut by the molecule cutoff), so the forces and torques
                         are not the gradient of any energy: an NVE run drifts (heats) at any
                         time step.  0 with energy_jumps: the jump is the same at every crossing
                         (plain LJ): the run conserves the shifted energy, and the reported one
                         differs from it by the jump times the pairs within the cutoff (calE
                         reads high, no drift)                                             */
  int force_jumps;    /* 1: the pair force is discontinuous at the cutoff (whether or not the
                         energy is: with energy_jumps = 0 only the force jumps)              */
  double energy_jump; /* the largest jump of one pair's energy (a site pair under the site
                         cutoff, a molecule pair under the molecule cutoff), energy units;
                         0 if continuous.  Closed form for site pairs (orientations over the
                         axis-aligned ones, where the dipole and quadrupole maxima lie);
                         sampled over orientations for molecule pairs                       */
  double force_jump;  /* the same for the force (energy / length)                          */
  char text[RL_FF_TEXT]; /* one sentence: the term, what jumps and by how much, what that does
                            to energy conservation, and the continuous alternative         */
} rl_ff_discontinuity;

/* One entry per interaction term present (a term needs two sites of bodies that can meet: of
 * two species, or of one species with two bodies or more); continuous terms are listed too, with
 * both flags 0.  Writes the first `max` entries to out (out may be NULL when max = 0) and returns
 * how many there are.  The terms' order: lj, coulomb, dipole-dipole, charge-dipole, quadrupole,
 * coulomb-intramolecular. */
int rl_forcefield_discontinuities(const rl_forcefield *ff, rl_ff_discontinuity *out, int max);


/* ------------------------------------------------------------- configurational temperature
 * k_B T_conf = <|grad U|^2> / <Laplacian U> (Rugh 1997; Butler, Ayton, Jepps & Evans, Mol. Phys.
 * 93, 875 (1998)), for rigid bodies split into a translational part (gradients with respect to
 * the centres: the forces) and a rotational one (with respect to small rotations of each body
 * about the lab axes through its centre: the torques).  rl_config_temperature returns the sums
 * over bodies of one configuration; the temperature is a ratio of their means over samples:
 *   k_B T_trans = <f2> / <lap_r>,  k_B T_rot = <k2> / <lap_rot>,
 *   k_B T_conf  = <f2 + k2> / <lap_r + lap_rot>.
 * The rotational Laplacian of body i is sum_a d^2 U / d phi_a^2 at phi = 0 for the rotation
 * exp(phi [e_a]x) about the body's centre (the divergence of the torque field under the
 * invariant measure of the orientations); for coordinates x_p of the body (its sites' offsets
 * d from the centre, its axis e) with gradient g_p and Hessian blocks H_pq:
 *   lap_rot = sum_pq [(x_p . x_q) tr H_pq - x_q^T H_pq x_p] - 2 sum_p g_p . x_p
 * (docs/observables.md, "Configurational temperature").  Every pair term of the force field is
 * included (LJ in each truncation, reaction-field charges, point dipoles RF and SF, charge-
 * dipole, linear quadrupoles); the dispersion correction and the intramolecular reaction field
 * are constants of a rigid configuration and add nothing.  Computed by a serial O(N^2) loop over
 * body pairs with the reference potentials (not the specialised kernels).
 *
 * The estimator is exact only where the forces are continuous at the cutoff: a force that
 * jumps there puts a delta function into the Laplacian (a surface term this pointwise sum
 * leaves out) and an energy jump one more.  rl_tconf_exact says which case holds (from
 * rl_forcefield_discontinuities, whose sampling of orientations makes it a setup-time call): the
 * shifted-force and switched LJ, eps_rf = infinity and the shifted-force dipoles are
 * continuous under the site cutoff; the Laplacian of a shifted-force term jumps at the cutoff,
 * which is harmless (no delta function). */
typedef struct {
  double f2;      /* sum_i |F_i|^2 over all bodies                        (energy/length)^2 */
  double lap_r;   /* sum_i Laplacian of U in the centre R_i                 energy/length^2 */
  double k2;      /* sum_i |tau_i|^2 over rotating bodies                           energy^2 */
  double lap_rot; /* sum_i rotational Laplacian of U (per rad^2)                      energy */
} rl_tconf_sums;

/* The sums of the configuration of sys under the force field ff (the system it was made for;
 * its box is the force field's).  RL_OK; RL_ESTATE if sys no longer matches, RL_EINVAL for
 * overlapping sites or a force field whose Coulomb is the Ewald real space (RL_COULOMB_EWALD_REAL:
 * its Laplacian is not written), RL_ENOMEM. */
int rl_config_temperature(const rl_forcefield *ff, const rl_system *sys, rl_tconf_sums *out);
/* 1 if every force of ff is continuous at the cutoff (the sums give an exact estimator), else 0. */
int rl_tconf_exact(const rl_forcefield *ff);

#ifdef __cplusplus
}
#endif
#endif
