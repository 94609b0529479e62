/* Deck parsing and validation.  Phase 1 reads every "section.key = value" with its line (libinih
 * parses, under the line format below) and applies --set overrides; phase 2, once the model
 * fixes the unit system, converts and checks every value and the combinations.  All problems are
 * reported before anything runs. */
#include "deck.h"
#include "deck_internal.h"
#include "quantity.h"

#include <ctype.h>
#include <errno.h>
#include <ini.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>


static const key_def keys[NKEYS] = {
    [K_MODEL] = {"system", "model", K_STRING, Q_NONE, NULL, NULL, "catalogue model (rotleap models), or a molecule the deck defines in a [molecule NAME] section (here or in system.molecules; see \"Molecules\" below); required"},
    [K_MOLFILE] = {"system", "molecules", K_PATH, Q_NONE, NULL, NULL, "a molecule file: [molecule NAME] sections only, in the deck's line format, so that one file serves many decks; a relative path is taken from the deck's directory (from the current directory for a deck read from a pipe)"},
    [K_COUNT] = {"system", "count", K_INT, Q_NONE, NULL, NULL, "number of molecules; required (with system.model). A count whose memory (at least 160 bytes + 130 per site and molecule) exceeds the machine's is refused"},
    [K_SPECIES] = {"system", "species", K_STRING, Q_NONE, NULL, NULL, "a mixture, instead of system.model and system.count: NAME:COUNT for each species (\"spce:500 na:10 cl:10\"), each a catalogue model (with its default parameters) or a [molecule NAME] of the deck, all in one unit system; the molecules are numbered species by species in this order"},
    [K_BOX] = {"system", "box", K_STRING, Q_LENGTH, NULL, NULL, "box edge L, or three edges \"Lx Ly Lz\", each with its unit (\"1.8 nm 1.8 nm 2 nm\") or bare with one unit at the end (\"1.8 1.8 2 nm\"); give box or density, or neither with a start file that holds a box (a checkpoint, a PDB's CRYST1, an XYZ's Lattice=): its box"},
    [K_DENSITY] = {"system", "density", K_REAL, Q_DENSITY, NULL, NULL, "mass density (real) or number density (lj); sets a cubic box"},
    [K_START] = {"system", "start", K_PATH, Q_NONE, "lattice", NULL, "lattice, or a file: NAME.pdb (site models; molecules fitted to the model), NAME.xyz (extended XYZ with orientations), NAME.chk (a rotleap checkpoint: continue the run bit for bit; under another run.ensemble, start a new run from its state; with another run.seed, continue with a new random stream). A regular file (a link to one is followed)"},
    [K_RESIDUES] = {"system", "residues", K_STRING, Q_NONE, NULL, NULL, "residue names of a .pdb start and the species they stand for, RES:SPECIES each (\"SOL:tip4p-ew NA:na-tip4pew CL:cl-tip4pew\"; at most 16; any case). Without it a mixture's residues go by name: the species' own, or HOH WAT SOL H2O TIP3 TIP4 T3P T4P T4E SPC for the deck's one water, NA NA+ SOD for its Na+, CL CL- CLA for its Cl- (docs/files.md, PDB)"},
    [K_LATTICE] = {"system", "lattice", K_CHOICE, Q_NONE, "sc", "sc|fcc|random", "starting lattice; random: centres inserted at random (system.seed) where no LJ site pair of two molecules comes closer than 0.7 of its sigma (Lorentz-Berthelot), up to 10000 tries per molecule"},
    [K_ORIENT] = {"system", "orientations", K_CHOICE, Q_NONE, "random", "random|aligned", "starting orientations"},
    [K_SEED] = {"system", "seed", K_INT, Q_NONE, "1", NULL, "seed of the starting-state random numbers (GSL mt19937)"},
    [K_TEMP] = {"system", "temperature", K_REAL, Q_TEMPERATURE, NULL, NULL, "Maxwell-Boltzmann temperature of the start; default: the thermostat temperature, else required"},
    [K_GENERAL] = {"system", "force_general", K_BOOL, Q_NONE, "no", NULL, "integrate by the general asymmetric path whatever the family (a cross-check; linear molecules and point dipoles then get I_z = I_x and a third, free spin: 3 rotational dof each)"},
    [K_INERTIA] = {"system", "inertia_scale", K_REAL, Q_NONE, "1", NULL, "multiply every molecule's principal moments of inertia by this factor (1 to 100; masses and sites unchanged), as hydrogen mass repartitioning does for flexible models: the Boltzmann distribution of positions and orientations does not depend on the inertia, so structure, energies and pressure are those of the real model, while the librations slow by the factor's square root and a larger time step samples them accurately (docs/integrators.md, \"Heavier rotors\"). Rotational dynamics (reorientation times, the rotational kinetic temperature's time scales, and through coupling the diffusion coefficient) become those of the heavier rotor: do not read dynamics from such a run"},
    [K_CUTOFF] = {"interactions", "cutoff", K_REAL, Q_LENGTH, NULL, NULL, "cutoff radius (<= half the shortest box edge); required"},
    [K_SCHEME] = {"interactions", "scheme", K_CHOICE, Q_NONE, "site", "site|molecule", "cut site pairs by their own distance (OpenMM) or by centre distance"},
    [K_LJ] = {"interactions", "lj", K_CHOICE, Q_NONE, "plain", "plain|shifted|shifted-force|switched", "Lennard-Jones truncation"},
    [K_SWITCH] = {"interactions", "switch", K_REAL, Q_LENGTH, NULL, NULL, "switching distance for lj = switched"},
    [K_DISP] = {"interactions", "dispersion_correction", K_BOOL, Q_NONE, "no", NULL, "long-range LJ correction of energy and pressure"},
    [K_EPSRF] = {"interactions", "eps_rf", K_REAL, Q_NONE, "78.3", NULL, "reaction-field dielectric (>= 1; inf = conducting): of the charges under coulomb = rf, and of point dipoles"},
    [K_MIXING] = {"interactions", "mixing", K_CHOICE, Q_NONE, "model", "model|lorentz-berthelot|geometric", "LJ mixing rule of unlike sites: lorentz-berthelot (sigma_ab = (sigma_a + sigma_b)/2, epsilon_ab = sqrt(epsilon_a epsilon_b)), geometric (sigma_ab = sqrt(sigma_a sigma_b)), or model: the model's own (geometric for OPLS and EPM2), in a mixture geometric only if every species' model is"},
    [K_PAIRS] = {"interactions", "pairs", K_STRING, Q_NONE, NULL, NULL, "LJ parameters of site pairs that replace the mixing rule's, separated by commas: \"SPECIES:SITE SPECIES:SITE sigma S [unit] epsilon E [unit]\" (\"na:Na cl:Cl sigma 0.35 nm epsilon 0.5 kJ/mol\"); SPECIES is a name of system.species (or system.model), SITE one of its sites; at most 16"},
    [K_COULOMB] = {"interactions", "coulomb", K_CHOICE, Q_NONE, "rf", "rf|ewald|pme", "charges: reaction field (eps_rf), Ewald summation (a k-vector sum) or smooth particle-mesh Ewald (FFTW3), as OpenMM's NonbondedForce Ewald and PME: erfc(alpha r)/r within the cutoff (site pairs, pairs within a molecule excluded) plus the reciprocal sum; tin-foil boundary unless ewald_boundary says otherwise. Point dipoles too (the dipolar Ewald sum; interactions.dipole is then refused); a model with quadrupoles needs rf. The run prints alpha, the grid or k vectors and the estimated RMS force error (docs/interactions.md, Ewald)"},
    [K_ETOL] = {"interactions", "ewald_tolerance", K_REAL, Q_NONE, "5e-4", NULL, "coulomb = ewald or pme: OpenMM's ewaldErrorTolerance delta, in (0, 0.1): alpha = sqrt(-ln(2 delta)) / cutoff, the PME grid max(6, ceil(2 alpha L / (3 delta^(1/5)))) and the Ewald k vectors as OpenMM 7.7 derives them; explicit values below are checked against it"},
    [K_EALPHA] = {"interactions", "ewald_alpha", K_REAL, Q_INVLENGTH, NULL, NULL, "coulomb = ewald or pme: the splitting parameter alpha (3.2 /nm, 0.32 /A; reduced: 1/sigma, bare); default from ewald_tolerance. alpha cutoff >= 1.27 (the real-space cut leaves erfc(alpha cutoff) <= 0.1)"},
    [K_PGRID] = {"interactions", "pme_grid", K_INTS, Q_NONE, NULL, NULL, "coulomb = pme: mesh points per edge, \"nx ny nz\" or one number for all three (OpenMM's setPMEParameters); default from ewald_tolerance. Refused if too coarse for the tolerance (exp(-k^2 / 4 alpha^2) > 10 ewald_tolerance at the Nyquist vector pi K / L) or below pme_order"},
    [K_PORDER] = {"interactions", "pme_order", K_INT, Q_NONE, "5", NULL, "coulomb = pme: order of the B-splines, 3 to 12 (5: OpenMM's; GROMACS's pme-order = 4 is 4). Not given, for point dipoles alone (no charges) with the mesh derived: chosen with the mesh, 4 to 8, at least cost for the tolerance (docs/interactions.md)"},
    [K_EKMAX] = {"interactions", "ewald_kmax", K_INTS, Q_NONE, NULL, NULL, "coulomb = ewald: the k vectors 2 pi (nx/Lx, ny/Ly, nz/Lz) with abs(n_c) <= kmax_c, \"kx ky kz\" or one number; default from ewald_tolerance (OpenMM's kmax - 1: OpenMM sums abs(n_c) < kmax_c). Refused if too coarse for the tolerance"},
    [K_EKMAX2] = {"interactions", "ewald_kmax2", K_REAL, Q_NONE, NULL, NULL, "coulomb = ewald: also nx^2 + ny^2 + nz^2 <= ewald_kmax2, a sphere in units of (2 pi / L)^2 (the NIST SPC/E reference sums: ewald_kmax = 5, ewald_kmax2 = 26); default: no such limit (OpenMM's box of vectors)"},
    [K_EBOUND] = {"interactions", "ewald_boundary", K_STRING, Q_NONE, "tinfoil", NULL, "coulomb = ewald or pme: the dielectric around the sphere of periodic images: tinfoil (conducting, no surface term), vacuum (eps' = 1), or a number eps' >= 1: the surface term 2 pi kc M^2 / ((2 eps' + 1) V). The dielectric constant in PREFIX.results.txt uses it"},
    [K_DIPOLE] = {"interactions", "dipole", K_CHOICE, Q_NONE, "rf", "rf|sf", "point dipoles under coulomb = rf: reaction field (eps_rf) or shifted force; refused with coulomb = ewald or pme, whose sum includes the dipoles"},
    [K_SKIN] = {"interactions", "skin", K_REAL, Q_LENGTH, NULL, NULL, "Verlet-list skin; default 0.1 cutoff, growing at large steps as sqrt(v h / 0.0015 cutoff) (v the thermal speed sqrt(3kT/m)) up to 0.25 cutoff: 0.1 cutoff for TIP4P up to 2 fs, 0.2 at 8 fs. The summary prints the skin used"},
    [K_KERNEL] = {"interactions", "kernel", K_CHOICE, Q_NONE, "auto", "auto|general", "auto: pair kernels specialised by site pattern (TIP4P, charges+LJ, Stockmayer), threaded; general: the serial reference routine (docs/interactions.md)"},
    [K_PRECISION] = {"interactions", "precision", K_CHOICE, Q_NONE, "double", "double|mixed", "double: every pair term in double precision; mixed: the TIP4P kernel's terms in single precision on CPUs with AVX2 (sums, energies and virial double, as GROMACS's default build and OpenMM's CPU platform), about 1e-6 relative; other models and CPUs stay double. The summary prints the precision used (docs/interactions.md)"},
    [K_STEPS] = {"run", "steps", K_INT, Q_NONE, NULL, NULL, "number of steps; required"},
    [K_DT] = {"run", "timestep", K_REAL, Q_TIME, NULL, NULL, "time step h; required"},
    [K_INTEGRATOR] = {"run", "integrator", K_CHOICE, Q_NONE, "rl", "rl|rl-exact|rl-quaternion|rl-hybrid|fincham|no-squish", "revised leapfrog: guarded cubic (rl), exact solve, quaternion variant; baselines (matrix bodies only): the paper's hybrid, Fincham's implicit quaternion leapfrog, NO_SQUISH (docs/integrators.md)"},
    [K_ENSEMBLE] = {"run", "ensemble", K_CHOICE, Q_NONE, "nve", "nve|nvt-isokinetic|nvt-bussi|nvt-langevin|nvt-langevin-dot|nvt-langevin-dot-obabo", "NVE, the paper's isokinetic NVT, Bussi stochastic rescaling, Langevin in the middle of the drift (BAOAB; docs/integrators.md), or the rigid-body Langevin thermostat of Davidchack, Ouldridge & Tretyakov with its own rotational friction (run.tau_rot), its Ornstein-Uhlenbeck step in the middle of the drift (nvt-langevin-dot, B A O A B) or of the kick (nvt-langevin-dot-obabo, O B A B O). nvt-isokinetic (eqs. 17-18) holds only the on-step temperature: from a start out of equilibrium at run.temperature (a lattice, another temperature) the kinetic energy alternates from step to step without damping and the conserved sum drifts at any time step, so relax first (run.equilibrate at run.temperature) or use nvt-bussi"},
    [K_TTEMP] = {"run", "temperature", K_REAL, Q_TEMPERATURE, NULL, NULL, "thermostat temperature (NVT); required for NVT"},
    [K_TAU] = {"run", "tau", K_REAL, Q_TIME, NULL, NULL, "Bussi: relaxation time of the kinetic energy; Langevin: friction time 1/gamma (Langevin-DOT: of translation); default 100 h"},
    [K_TAUROT] = {"run", "tau_rot", K_REAL, Q_TIME, NULL, NULL, "nvt-langevin-dot(-obabo): rotational friction time 1/gamma_r, the same on each principal axis of the body-frame angular momentum; default run.tau"},
    [K_TGROUPS] = {"run", "thermostat_groups", K_CHOICE, Q_NONE, "trans-rot", "trans-rot|all", "Bussi: one thermostat for translation and one for rotation, or one for both (docs/integrators.md)"},
    [K_TSEED] = {"run", "seed", K_INT, Q_NONE, "2", NULL, "seed of the Bussi or Langevin thermostat's random numbers"},
    [K_EQSTEPS] = {"run", "equilibrate", K_INT, Q_NONE, "0", NULL, "relaxation steps before the run (Bussi, tau = 20 relaxation steps), e.g. from a lattice"},
    [K_EQDT] = {"run", "equilibrate_timestep", K_REAL, Q_TIME, NULL, NULL, "time step of the relaxation; default timestep / 4"},
    [K_THREADS] = {"run", "threads", K_INT, Q_NONE, "0", NULL, "OpenMP threads of the pair loop, the Ewald terms and the integrator's per-body loops (at most 4096); 0: OMP_NUM_THREADS if set (at most 4096 too), else 1. Results are bit-for-bit reproducible for a fixed count and change at round-off with the count (the pair loop's sums; the Ewald terms' do not depend on it)"},
    [K_BARO] = {"run", "barostat", K_CHOICE, Q_NONE, "none", "none|mc|c-rescale", "constant pressure (NPT; needs run.ensemble = nvt-bussi or nvt-langevin and a periodic box): mc, the Monte Carlo barostat (OpenMM's: trial scalings of the molecular centres, molecules rigid); c-rescale, stochastic cell rescaling (Bernetti & Bussi 2020, GROMACS's C-rescale; isotropic or semiisotropic). docs/integrators.md, \"Barostats\""},
    [K_PRESSURE] = {"run", "pressure", K_REAL, Q_PRESSURE, NULL, NULL, "target pressure of run.barostat (bar, atm, Pa, MPa; reduced for lj models); required with a barostat; at most 1e5 bar (10 GPa; 1000 reduced) either way, beyond any rigid model (a bare 101325 is bar, not Pa)"},
    [K_BINTERVAL] = {"run", "barostat_interval", K_INT, Q_NONE, NULL, NULL, "steps between barostat moves: Monte Carlo trials (default 25, OpenMM's) or C-rescale couplings (default 10, GROMACS's nstpcouple; a multiple of output.energy_every)"},
    [K_TAUP] = {"run", "tau_p", K_REAL, Q_TIME, NULL, NULL, "c-rescale: coupling time of the volume; default 1 ps (real), 1000 h (lj)"},
    [K_COMPRESS] = {"run", "compressibility", K_REAL, Q_COMPRESSIBILITY, NULL, NULL, "c-rescale: isothermal compressibility it assumes (sets the volume's relaxation, not the ensemble); default 4.5e-5 1/bar (water's), 0.1 (lj)"},
    [K_BCOUPLING] = {"run", "barostat_coupling", K_CHOICE, Q_NONE, "isotropic", "isotropic|anisotropic|semiisotropic", "isotropic: the box keeps its shape; anisotropic (mc only): one edge per trial, the three edges independent (OpenMM's MonteCarloAnisotropicBarostat); semiisotropic (c-rescale only): x and y scaled together, z alone (GROMACS's semiisotropic C-rescale; membranes, interfaces)"},
    [K_PREFIX] = {"output", "prefix", K_PATH, Q_NONE, NULL, NULL, "path prefix of every output file (PREFIX.thermo.csv, ...): a file name, in a directory if you like (out, results/run1), not a directory (results/ is refused); default: the deck's name without .ini. An output that would overwrite the deck or system.start (water.ini with start = water.pdb and a trajectory) is refused before anything is written"},
    [K_THERMO] = {"output", "thermo_every", K_INT, Q_NONE, "100", NULL, "steps between rows of PREFIX.thermo.csv"},
    [K_ENERGY] = {"output", "energy_every", K_INT, Q_NONE, "1", NULL, "steps between evaluations of the potential energy and virial (as GROMACS's nstcalcenergy): the thermo rows, the summary's averages and the energy checks use these steps, the others compute forces only (about 10 % faster for TIP4P; the trajectory is the same). thermo_every must be a multiple"},
    [K_CHECKPOINT] = {"output", "checkpoint_every", K_INT, Q_NONE, "0", NULL, "steps between checkpoints PREFIX.chk (written atomically; 0: only at the end)"},
    [K_TRAJ] = {"output", "trajectory_every", K_INT, Q_NONE, "0", NULL, "steps between trajectory frames (0: none; at most 2147483647, DCD's 32-bit interval): PREFIX.dcd + PREFIX.pdb for models with several sites (water, CO2, 2CLJ, ...), whose DCD also limits run.steps to 2147483647; PREFIX.xyz (with orientations) for point dipoles and atoms"},
    [K_SAMPLE] = {"output", "sample_every", K_INT, Q_NONE, "10", NULL, "steps between configurations sampled for RDFs, correlation functions, diffusion and the dielectric constant (0: none)"},
    [K_RDF] = {"output", "rdf", K_STRING, Q_NONE, "", NULL, "site pairs for PREFIX.rdf.csv by site name, e.g. \"O-O, H1-H1\" (rotleap models lists the sites); in a mixture also between species, each side SPECIES:SITE or the name of a species of one site: \"spc-e:O-spc-e:O, na-spce-cl-spce, spc-e:O-na-spce\" (a bare SITE is the first species'; at most 8 pairs)"},
    [K_DISCARD] = {"output", "discard", K_STRING, Q_NONE, "auto", NULL, "steps left out of every average in PREFIX.results.txt, .rdf.csv and .tcf.csv, counted from the run's first step: auto (the equilibrated region detected from U per molecule: Chodera's start that maximises the uncorrelated samples, docs/observables.md) or a whole number of steps (0: average everything)"},
    [K_TCONF] = {"output", "tconf", K_BOOL, Q_NONE, "no", NULL, "configurational temperature (translational, rotational, total) of every sampled configuration in PREFIX.results.txt: <|F|^2>/<Laplacian U> from forces and torques, independent of the velocities, so it says whether the configurations are sampled at the thermostat's T at large steps, where the on-step kinetic temperature reads low (docs/observables.md). Costs an O(N^2) pass over molecule pairs per sample; exact only for forces continuous at the cutoff (lj = shifted-force or switched, eps_rf = inf, dipole = sf)"},
    [K_PROGRESS] = {"output", "progress", K_CHOICE, Q_NONE, "auto", "auto|yes|no", "progress line on stderr (auto: when stderr is a terminal)"},
};

/* In the order of run.integrator's choices (the key table above). */
const rl_deck_integrator rl_deck_integrators[] = {
    {"rl", RL_ROT_CUBIC, "revised leapfrog, rotation matrices, guarded quasi-analytic cubic (eqs. 27-36)"},
    {"rl-exact", RL_ROT_EXACT, "revised leapfrog, rotation matrices, eq. 28 solved exactly (Newton)"},
    {"rl-quaternion", RL_ROT_QUATERNION, "revised leapfrog, quaternions, eq. 23 iterated"},
    {"rl-hybrid", RL_ROT_HYBRID, "the paper's hybrid: cubic Omega in the quaternion update (section IV)"},
    {"fincham", RL_ROT_FINCHAM, "Fincham's implicit quaternion leapfrog (eqs. 10-16)"},
    {"no-squish", RL_ROT_NOSQUISH, "NO_SQUISH symplectic splitting (Miller et al. 2002)"},
};
const int rl_deck_nintegrators = (int)(sizeof rl_deck_integrators / sizeof rl_deck_integrators[0]);

/* "a b c": the names of the sites of m, or of the species mols[ns]. */
static void site_list(const rl_molecule *m, char *buf, size_t n)
{
  buf[0] = '\0';
  for (int a = 0, at = 0; a < m->nsites && at < (int)n; a++)
    at += snprintf(buf + at, n - (size_t)at, "%s%s", a ? " " : "", m->site_names[a]);
}
static void species_list(const rl_molecule *mols, int ns, char *buf, size_t n)
{
  buf[0] = '\0';
  for (int k = 0, at = 0; k < ns && at < (int)n; k++) at += snprintf(buf + at, n - (size_t)at, "%s%s", k ? ", " : "", mols[k].name);
}

static int site_index(const rl_molecule *m, const char *name)
{
  for (int a = 0; a < m->nsites; a++)
    if (!strcmp(m->site_names[a], name)) return a;
  return -1;
}

/* One side of an output.rdf pair (rl_deck_rdf_species_pairs): 1 with *sp, *site, else 0 with why. */
static int rdf_side(const char *x, const rl_molecule *mols, int ns, int *sp, int *site, char *why, size_t n)
{
  char have[256], all[256];
  species_list(mols, ns, all, sizeof all);
  const char *colon = strchr(x, ':');
  if (colon) {
    const size_t len = (size_t)(colon - x);
    for (int k = 0; k < ns; k++)
      if (strlen(mols[k].name) == len && !strncmp(mols[k].name, x, len)) {
        if ((*site = site_index(&mols[k], colon + 1)) >= 0) { *sp = k; return 1; }
        site_list(&mols[k], have, sizeof have);
        snprintf(why, n, "species %s has no site '%s' (its sites: %s)", mols[k].name, colon + 1, have);
        return 0;
      }
    snprintf(why, n, "'%.*s' is not a species of the deck (%s)", (int)len, x, all);
    return 0;
  }
  if ((*site = site_index(&mols[0], x)) >= 0) { *sp = 0; return 1; }
  site_list(&mols[0], have, sizeof have);
  if (ns == 1) {
    snprintf(why, n, "model %s has no site '%s' (its sites: %s)", mols[0].name, x, have);
    return 0;
  }
  for (int k = 0; k < ns; k++)
    if (!strcmp(mols[k].name, x)) {
      if (mols[k].nsites == 1) { *sp = k; *site = 0; return 1; }
      site_list(&mols[k], have, sizeof have);
      snprintf(why, n, "species %s has %d sites: name one as %s:SITE (its sites: %s)", x, mols[k].nsites, x, have);
      return 0;
    }
  snprintf(why, n, "'%s' is neither a site of the first species %s (its sites: %s) nor a species of one site; "
           "write SPECIES:SITE (species: %s)", x, mols[0].name, have, all);
  return 0;
}

int rl_deck_rdf_species_pairs(const char *spec, const rl_molecule *mols, int nspecies, rl_deck_rdf_pair *out)
{
  char *buf = strdup(spec), *save;
  if (!buf) return rl_error(RL_ENOMEM, "output.rdf: out of memory"), -1;
  int n = 0;
  for (char *tok = strtok_r(buf, ", ", &save); tok; tok = strtok_r(NULL, ", ", &save)) {
    if (!strchr(tok, '-')) { rl_error(RL_EINVAL, "output.rdf: '%s' is not SITE-SITE", tok); n = -1; break; }
    if (n == RL_DECK_MAX_RDF) { rl_error(RL_EINVAL, "output.rdf: more than %d pairs", RL_DECK_MAX_RDF); n = -1; break; }
    /* every '-' as the separator: the one reading whose both sides resolve */
    char why[512] = "", first[48] = "";
    int found = 0, best = -1;
    for (char *dash = strchr(tok, '-'); dash; dash = strchr(dash + 1, '-')) {
      *dash = '\0';
      int sp[2], site[2], ok[2];
      char w[2][512];
      for (int k = 0; k < 2; k++) ok[k] = rdf_side(k ? dash + 1 : tok, mols, nspecies, &sp[k], &site[k], w[k], sizeof w[k]);
      if (ok[0] && ok[1]) {
        if (found++ == 0) {
          snprintf(first, sizeof first, "%s' - '%s", tok, dash + 1);
          rl_deck_rdf_pair *p = &out[n];
          for (int k = 0; k < 2; k++) { p->species[k] = sp[k]; p->site[k] = site[k]; }
        } else {
          rl_error(RL_EINVAL, "output.rdf: '%s-%s' reads two ways, '%s' and '%s' - '%s': write SPECIES:SITE", tok,
                   dash + 1, first, tok, dash + 1);
          *dash = '-';
          found = -1;
          break;
        }
      } else if (ok[0] + ok[1] > best) { /* the reading closest to one: its message */
        best = ok[0] + ok[1];
        snprintf(why, sizeof why, "%s", ok[0] ? w[1] : w[0]);
      }
      *dash = '-';
    }
    if (found <= 0) {
      if (found == 0) rl_error(RL_EINVAL, "output.rdf: %s", why);
      n = -1;
      break;
    }
    snprintf(out[n].name, sizeof out[n].name, "%.47s", tok);
    n++;
  }
  free(buf);
  return n;
}

int rl_deck_rdf_pairs(const char *spec, const rl_molecule *m, int site[][2], char name[][24])
{
  rl_deck_rdf_pair p[RL_DECK_MAX_RDF];
  const int n = rl_deck_rdf_species_pairs(spec, m, 1, p);
  for (int q = 0; q < n; q++) {
    site[q][0] = p[q].site[0];
    site[q][1] = p[q].site[1];
    snprintf(name[q], 24, "%.23s", p[q].name);
  }
  return n;
}

double rl_deck_max_temperature(const rl_deck *d, const char **key)
{
  const int thermo = d->thermostat_temperature > d->temperature;
  if (key) *key = thermo ? " (run.temperature)" : "";
  return thermo ? d->thermostat_temperature : d->temperature;
}

static double thermal_omega_at(const rl_deck *d, double T)
{
  rl_molecule m;
  if (!d->model || !(T > 0) || rl_model_build(d->model, d->params, 0, &m) || m.kind == RL_KIND_POINT)
    return 0.0;
  double Jmin = INFINITY;
  for (int a = 0; a < 3; a++)
    if (m.inertia[a] > 0) Jmin = fmin(Jmin, d->inertia_scale * m.inertia[a]);
  return sqrt(rl_units_kB(d->units) * T / Jmin);
}

double rl_deck_thermal_omega(const rl_deck *d) { return thermal_omega_at(d, rl_deck_max_temperature(d, NULL)); }

int rl_deck_integrator_lookup(const char *name)
{
  for (int i = 0; i < rl_deck_nintegrators; i++)
    if (!strcmp(rl_deck_integrators[i].name, name)) return i;
  return -1;
}


static void vproblem(raw_deck *r, const char *file, int line, const char *fmt, va_list ap)
{
  if (line > 0) fprintf(r->err, "%s:%d: ", file, line);
  else if (line < 0) fprintf(r->err, "--set: ");
  else fprintf(r->err, "%s: ", file);
  vfprintf(r->err, fmt, ap);
  fputc('\n', r->err);
  r->problems++;
}

void deck_problem(raw_deck *r, int line, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  vproblem(r, r->path, line, fmt, ap);
  va_end(ap);
}

/* A problem at a line of another file (a molecule file). */
void deck_problem_at(raw_deck *r, const char *file, int line, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  vproblem(r, file, line, fmt, ap);
  va_end(ap);
}

static int find_key(const char *section, const char *name)
{
  for (int k = 0; k < NKEYS; k++)
    if (!strcmp(keys[k].section, section) && !strcmp(keys[k].name, name)) return k;
  return -1;
}

/* ---- the line format ------------------------------------------------------------------------
 * libinih (Debian's libinih-dev) parses the deck: sections, keys, values.  Its build settings
 * would decide the rest silently -- it cuts a line at its 200-byte buffer and reads the rest as
 * a line of its own, takes only ";" for an inline comment, reads an indented line as more of the
 * key before it, and cuts section names at 49 characters -- so the reader that hands it the lines
 * (deck_reader) enforces these rules first (docs/deck.md states them):
 *  - A line is blank, a comment (its first non-blank character is ; or #), "[section]", or
 *    "key = value" ("key: value" too).
 *  - In every line a ; or # after a blank starts a comment that runs to the end of the line, so a
 *    value never contains " ;" or " #" (a --set value that does is refused); a ; or # with no blank
 *    before it is part of the value (prefix = run#2).
 *  - Blanks around keys, values and headers are dropped, at the start of a line too: an indented
 *    key is a key; a value never continues on the next line, and an indented line without a key
 *    is refused as such.
 *  - A line has at most DECK_LINE_MAX characters before its comment, except the line of a path key
 *    (system.start, output.prefix), whose value may be any path the system accepts (such a line is
 *    longer than libinih's buffer: the reader stores it itself); a section name at most
 *    DECK_SECTION_MAX characters.
 *  - An empty value ("prefix =") is refused; --set section.key= returns a key to its default.
 *  - The deck is a regular file or a pipe, of at most DECK_BYTES_MAX bytes and no NUL byte; a
 *    UTF-8 byte-order mark before the first line is skipped.  Reading stops after
 *    DECK_READ_PROBLEMS_MAX problems: the file is not a deck. */

const char *deck_file_kind(mode_t m)
{
  return S_ISDIR(m) ? "a directory" : S_ISCHR(m) ? "a character device" : S_ISBLK(m) ? "a block device"
       : S_ISFIFO(m) ? "a pipe" : S_ISSOCK(m) ? "a socket" : "not a plain file";
}

/* The ' ;' or ' #' that starts an inline comment in s, or NULL. */
static const char *inline_comment(const char *s)
{
  for (const char *q = *s ? s + 1 : s; *q; q++)
    if ((*q == ';' || *q == '#') && isspace((unsigned char)q[-1])) return q;
  return NULL;
}

static char *trim(char *s)
{
  while (isspace((unsigned char)*s)) s++;
  size_t n = strlen(s);
  while (n > 0 && isspace((unsigned char)s[n - 1])) s[--n] = '\0';
  return s;
}

/* What the default of key k is, for messages. */
static const char *default_text(int k)
{
  if (k == K_PREFIX) return "the deck's name without .ini";
  return !keys[k].def ? NULL : keys[k].def[0] ? keys[k].def : "none";
}


static void store(raw_deck *r, const char *section, const char *name, const char *value, int line)
{
  const int mi = deck_molecule_section(r, section);
  if (mi >= 0 || !strncmp(section, "molecule ", 9)) {
    if (line < 0) { deck_problem(r, line, "[%s] %s: a molecule is defined in its section, not from the command line", section, name); return; }
    if (mi < 0) return; /* its header was refused */
    if (r->nml == r->cap_ml) {
      const int cap = r->cap_ml ? 2 * r->cap_ml : 32;
      void *t = realloc(r->ml, (size_t)cap * sizeof *r->ml);
      if (!t) { deck_problem(r, line, "out of memory"); return; }
      r->ml = t;
      r->cap_ml = cap;
    }
    r->ml[r->nml].mol = mi;
    r->ml[r->nml].key = strdup(name);
    r->ml[r->nml].val = strdup(value);
    r->ml[r->nml].file = r->path;
    r->ml[r->nml].line = line;
    if (r->ml[r->nml].key && r->ml[r->nml].val) r->nml++;
    else { free(r->ml[r->nml].key); free(r->ml[r->nml].val); deck_problem(r, line, "out of memory"); }
    return;
  }
  if (r->molfile) { deck_problem(r, line, "[%s]: a molecule file holds [molecule NAME] sections only", section); return; }
  if (!strcmp(section, "model")) { /* model parameters, checked once the model is known */
    for (int i = 0; i < r->nmodel; i++)
      if (!strcmp(r->model_key[i], name)) {
        if (line > 0 && r->model_line[i] > 0) deck_problem(r, line, "[model] %s given twice (first at line %d)", name, r->model_line[i]);
        if (line < 0 && !value[0]) { /* --set model.name= : back to the default */
          free(r->model_key[i]);
          free(r->model_val[i]);
          r->nmodel--;
          r->model_key[i] = r->model_key[r->nmodel];
          r->model_val[i] = r->model_val[r->nmodel];
          r->model_line[i] = r->model_line[r->nmodel];
          return;
        }
        free(r->model_val[i]);
        r->model_val[i] = strdup(value);
        r->model_line[i] = line;
        return;
      }
    if (line < 0 && !value[0]) return;
    if (r->nmodel == RL_MODEL_MAX_PARAMS) { deck_problem(r, line, "[model] too many parameters (%s)", name); return; }
    r->model_key[r->nmodel] = strdup(name);
    r->model_val[r->nmodel] = strdup(value);
    r->model_line[r->nmodel++] = line;
    return;
  }
  int k = find_key(section, name);
  if (k < 0) {
    int sec_known = 0;
    for (int j = 0; j < NKEYS; j++) sec_known |= !strcmp(keys[j].section, section);
    if (!sec_known) deck_problem(r, line, "unknown section [%s] (sections: system, model, molecule NAME, interactions, run, output)", section);
    else deck_problem(r, line, "unknown key '%s' in [%s] (see rotleap run --help)", name, section);
    return;
  }
  if (line > 0 && r->line[k] > 0) deck_problem(r, line, "%s.%s given twice (first at line %d)", section, name, r->line[k]);
  free(r->val[k]);
  r->val[k] = NULL;
  r->line[k] = 0;
  r->bad[k] = 0;
  if (line < 0 && !value[0]) return; /* --set section.key= : back to the default, as if not given */
  r->val[k] = strdup(value);
  r->line[k] = line;
  if (!value[0]) { /* a deck line "key =" */
    const char *def = default_text(k);
    if (k == K_PREFIX)
      deck_problem(r, line, "output.prefix has no value: write a path prefix such as out or results/run1 (for "
              "out.thermo.csv, ...), or remove the line for the default (%s)", def);
    else if (def)
      deck_problem(r, line, "%s.%s has no value: write one, or remove the line for the default (%s)", section, name, def);
    else deck_problem(r, line, "%s.%s has no value: write one (%s)", section, name, keys[k].help);
    r->bad[k] = 1;
  }
}

/* Reads one line, to its newline or the end of the file, keeping its first `keep` characters in
 * buf; *len is the whole line's length.  1: a line; 0: the end of the file; -1: the deck is
 * refused (a NUL byte, more than DECK_BYTES_MAX bytes, a read error), reported. */
static int read_line(FILE *f, raw_deck *r, char *buf, size_t keep, size_t *len)
{
  size_t n = 0;
  int c;
  while ((c = getc(f)) != EOF) {
    if (++r->bytes > DECK_BYTES_MAX) {
      deck_problem(r, 0, "is longer than %ld bytes (1 MiB), the most a deck may have", DECK_BYTES_MAX);
      return -1;
    }
    if (c == '\n') break;
    if (c == '\0') { /* a DCD given by mistake, or /dev/zero through a pipe: its "keys" would fill screens */
      deck_problem(r, 0, "is not a text file (a NUL byte on line %d): a deck is an INI text file", r->lineno + 1);
      return -1;
    }
    if (n < keep) buf[n] = (char)c;
    n++;
  }
  if (ferror(f)) { deck_problem(r, 0, "cannot read the deck: %s", strerror(errno)); return -1; }
  if (c == EOF && n == 0) return 0;
  buf[n < keep ? n : keep] = '\0';
  *len = n;
  r->lineno++;
  return 1;
}


/* One raw line of `len` characters (the first `keep` of them in buf, modified) checked against the
 * rules above; what libinih is to parse of it is left in *out ("" for nothing: a blank line, a
 * comment, a line refused here, or a long path line stored here). */
static void check_line(raw_deck *r, char *buf, size_t len, size_t keep, const char **out)
{
  *out = "";
  char *p = buf;
  if (r->lineno == 1 && !strncmp(p, "\xEF\xBB\xBF", 3)) p += 3;
  const int indented = isspace((unsigned char)*p);
  while (isspace((unsigned char)*p)) p++;
  if (*p == ';' || *p == '#') return;
  char *cut = (char *)inline_comment(p);
  if (cut) *cut = '\0';
  const int whole = cut || len <= keep; /* the content, up to a comment, was kept */
  p = trim(p);
  const size_t n = whole ? (size_t)(p - buf) + strlen(p) : len; /* characters before a comment */
  if (!*p && whole) return;
  if (*p == '[') {
    char *close = strchr(p, ']');
    r->section_bad = 1; /* until the header is found good: the keys under a bad one are skipped */
    if (n > DECK_LINE_MAX) deck_problem(r, r->lineno, "this line has %zu characters, a deck line at most %d", n, DECK_LINE_MAX);
    else if (!close) deck_problem(r, r->lineno, "a section header needs its closing ']' (e.g. [system])");
    else {
      const char *after = trim(close + 1);
      *close = '\0';
      char *name = trim(p + 1);
      if (strlen(name) > DECK_SECTION_MAX)
        deck_problem(r, r->lineno, "the section name [%.20s...] has %zu characters, at most %d", name, strlen(name), DECK_SECTION_MAX);
      else if (*after) deck_problem(r, r->lineno, "text after [%s]: a section header stands alone on its line", name);
      else if (deck_new_molecule(r, name)) {
        r->section_bad = 0;
        free(r->section);
        r->section = strdup(name);
        memmove(buf, name, strlen(name) + 1); /* "[name]" for libinih, in place */
        memmove(buf + 1, buf, strlen(buf) + 1);
        buf[0] = '[';
        strcat(buf, "]");
        *out = buf;
      }
    }
    return;
  }
  char *eq = strpbrk(p, "=:");
  if (!eq) {
    if (indented)
      deck_problem(r, r->lineno, "an indented line does not continue the value of the line before it: a deck value "
              "is written whole on its key's line (key = value)");
    else deck_problem(r, r->lineno, "not a valid deck line (expected [section], key = value or a comment)");
    return;
  }
  const char sep = *eq;
  *eq = '\0';
  char *name = trim(p), *value = trim(eq + 1);
  const int k = *name && r->section ? find_key(r->section, name) : -1;
  if (!*name) { deck_problem(r, r->lineno, "a key is missing before the '%c'", sep); return; }
  if (r->section_bad) return;
  if (!r->section) { deck_problem(r, r->lineno, "key '%s' outside any [section]", name); return; }
  if (n > DECK_LINE_MAX) {
    if (whole && k >= 0 && keys[k].type == K_PATH) store(r, r->section, name, value, r->lineno); /* beyond libinih's buffer */
    else
      deck_problem(r, r->lineno, "this line has %zu characters, a deck line at most %d (only a comment, or the path of "
              "system.start or output.prefix, may be longer)", n, DECK_LINE_MAX);
    return;
  }
  /* "name = value" for libinih, blanks and comment dropped (it fits: n <= DECK_LINE_MAX) */
  const size_t ln = strlen(name), lv = strlen(value);
  memmove(buf, name, ln);
  buf[ln] = '=';
  memmove(buf + ln + 1, value, lv + 1);
  *out = buf;
}

/* The reader libinih pulls lines through (ini_parse_stream): each raw line of the deck is read
 * whole (read_line) and checked (check_line); libinih gets what is left to parse, and calls the
 * handler for a key right after reading its line, so r->lineno is that key's line.  NULL ends
 * the parse: the end of the file, or a deck refused while reading. */
static char *deck_reader(char *str, int num, void *stream)
{
  raw_deck *r = ((void **)stream)[1];
  FILE *f = ((void **)stream)[0];
  static _Thread_local char buf[DECK_KEEP + 1];
  size_t len;
  if (r->stopped || r->problems >= DECK_READ_PROBLEMS_MAX) {
    if (!r->stopped && r->problems >= DECK_READ_PROBLEMS_MAX)
      deck_problem(r, 0, "stopped reading at line %d after %d problems: is this a deck?", r->lineno, r->problems);
    r->stopped = 1;
    return NULL;
  }
  const int st = read_line(f, r, buf, DECK_KEEP, &len);
  if (st <= 0) {
    r->stopped = st < 0;
    return NULL;
  }
  const char *out;
  check_line(r, buf, len, DECK_KEEP, &out);
  snprintf(str, (size_t)num, "%s\n", out); /* fits: check_line leaves at most DECK_LINE_MAX characters */
  return str;
}

static int deck_handler(void *user, const char *section, const char *name, const char *value)
{
  raw_deck *r = user;
  if (!r->section_bad && section && name) store(r, section, name, value ? value : "", r->lineno);
  return 1;
}

/* Phase 1 for the deck file f: every line stored or reported.  0, or -1 when reading stopped
 * (the file is not a deck: its lines are not worth checking further). */
int deck_read(FILE *f, raw_deck *r)
{
  void *stream[2] = {f, r};
  const int line = ini_parse_stream(deck_reader, stream, deck_handler, r);
  if (line > 0 && !r->stopped) /* a line libinih could not parse after the checks: cannot happen, but said */
    deck_problem(r, line, "not a valid deck line");
  return r->stopped ? -1 : 0;
}

static const char *val(const raw_deck *r, int k) { return r->val[k] ? r->val[k] : keys[k].def; }

static int choice(raw_deck *r, int k)
{
  const char *v = val(r, k), *c = keys[k].choices;
  int idx = 0;
  if (r->bad[k]) return 0;
  size_t n = strlen(v);
  for (const char *p = c; *p;) {
    const char *e = strchr(p, '|');
    size_t len = e ? (size_t)(e - p) : strlen(p);
    if (len == n && !strncmp(p, v, n)) return idx;
    idx++;
    if (!e) break;
    p = e + 1;
  }
  deck_problem(r, r->line[k], "%s.%s: '%s' is not one of %s", keys[k].section, keys[k].name, v, c);
  r->bad[k] = 1;
  return 0;
}

static double number(raw_deck *r, int k, rl_units u, int allow_inf, double fallback)
{
  const char *v = val(r, k);
  if (!v || r->bad[k]) return fallback;
  double x;
  char msg[256];
  if (rl_parse_quantity(v, keys[k].dim, u, allow_inf, &x, msg, sizeof msg)) {
    deck_problem(r, r->line[k], "%s.%s: %s", keys[k].section, keys[k].name, msg);
    r->bad[k] = 1;
    return fallback;
  }
  return x;
}

static long integer_in(raw_deck *r, int k, long lo, long hi, long fallback)
{
  const char *v = val(r, k);
  if (!v || r->bad[k]) return fallback;
  char *end;
  errno = 0;
  long x = strtol(v, &end, 10);
  const int range = errno == ERANGE;
  while (*end == ' ' || *end == '\t') end++;
  if (end == v || *end) { deck_problem(r, r->line[k], "%s.%s: '%s' is not a whole number", keys[k].section, keys[k].name, v); r->bad[k] = 1; return fallback; }
  if (range && x == LONG_MIN) { deck_problem(r, r->line[k], "%s.%s: %s is below the minimum %ld", keys[k].section, keys[k].name, v, lo); r->bad[k] = 1; return fallback; }
  if (range || x > hi) { deck_problem(r, r->line[k], "%s.%s: %s is above the maximum %ld", keys[k].section, keys[k].name, v, hi); r->bad[k] = 1; return fallback; }
  if (x < lo) { deck_problem(r, r->line[k], "%s.%s: %ld is below the minimum %ld", keys[k].section, keys[k].name, x, lo); r->bad[k] = 1; return fallback; }
  return x;
}

static long integer(raw_deck *r, int k, long lo, long fallback) { return integer_in(r, k, lo, LONG_MAX, fallback); }

static int boolean(raw_deck *r, int k)
{
  const char *v = val(r, k);
  if (r->bad[k]) return 0;
  if (!strcmp(v, "yes") || !strcmp(v, "true") || !strcmp(v, "1") || !strcmp(v, "on")) return 1;
  if (!strcmp(v, "no") || !strcmp(v, "false") || !strcmp(v, "0") || !strcmp(v, "off")) return 0;
  deck_problem(r, r->line[k], "%s.%s: '%s' is not yes or no", keys[k].section, keys[k].name, v);
  r->bad[k] = 1;
  return 0;
}

void deck_require(raw_deck *r, int k)
{
  if (!r->val[k]) deck_problem(r, 0, "%s.%s is required (%s)", keys[k].section, keys[k].name, keys[k].help);
}

int rl_deck_site_model(const rl_molecule *m)
{
  return m->kind != RL_KIND_POINT && m->kind != RL_KIND_DIPOLE && m->nsites > 1;
}

/* system.count against what the machine can hold, before anything is allocated: a run needs at
 * least 160 bytes per molecule and 130 per site (half of what 32,000 and 128,000 TIP4P and
 * Stockmayer molecules took in rotleap energy: 1.4 and 0.6 kB), and the library counts sites
 * with an int. */
static void count_fits(raw_deck *r, int count, const rl_molecule *m)
{
  const int ns = m->nsites > 0 ? m->nsites : 1;
  const double need = (double)count * (160.0 + 130.0 * ns);
  const double have = (double)sysconf(_SC_PHYS_PAGES) * (double)sysconf(_SC_PAGESIZE);
  if ((double)count * ns > INT_MAX)
    deck_problem(r, r->line[K_COUNT], "system.count = %d: %.3g sites (%d per molecule of %s), more than the %d the "
            "library counts", count, (double)count * ns, ns, m->name, INT_MAX);
  else if (have > 0 && need > have)
    deck_problem(r, r->line[K_COUNT], "system.count = %d needs at least %.3g GB of memory (%.0f bytes per molecule of %s), "
            "more than this machine's %.3g GB", count, need * 1e-9, need / count, m->name, have * 1e-9);
}

/* 1 if the text of a number ("1.8", "1.8nm", "1.8 nm") has a unit after it; its start in *unit. */
static int has_unit(const char *q, const char **unit)
{
  char *end;
  (void)strtod(q, &end);
  end += strspn(end, " \t");
  *unit = end;
  return *end != '\0';
}

/* system.box: one edge or three, each with its unit or bare: "1.8 nm 1.8 nm 2 nm", "1.8nm 1.8nm
 * 2nm", or "1.8 1.8 2 nm" (the last edge's unit applies to the bare ones).  Every problem is
 * reported once; box is left 0 on any. */
static void box_edges(raw_deck *r, rl_units u, double box[3])
{
  char *tmp = strdup(r->val[K_BOX]), *save, *num[3] = {NULL, NULL, NULL};
  const char *unit[3] = {NULL, NULL, NULL}; /* an edge's unit: a token of its own, or its number's suffix */
  int suffix[3] = {0, 0, 0};                /* the unit is the number's suffix: num[c] is the quantity */
  if (!tmp) { deck_problem(r, r->line[K_BOX], "system.box: out of memory"); return; }
  int n = 0, bad = 0;
  for (char *tok = strtok_r(tmp, " \t", &save); tok && !bad; tok = strtok_r(NULL, " \t", &save)) {
    char *end;
    (void)strtod(tok, &end);
    if (end != tok && n == 3) { /* a number (nan and inf too: refused below, by name) starts an edge */
      deck_problem(r, r->line[K_BOX], "system.box: more than three edges");
      bad = 1;
    } else if (end != tok) {
      num[n] = tok;
      suffix[n] = has_unit(tok, &unit[n]);
      if (!suffix[n]) unit[n] = NULL;
      n++;
    } else if (n > 0 && !unit[n - 1]) { /* the unit of the number before it */
      unit[n - 1] = tok;
    } else {
      deck_problem(r, r->line[K_BOX], "system.box: '%s' is not a number%s", tok,
              n > 0 ? " (one unit per edge: \"1.8 nm 1.8 nm 2 nm\" or \"1.8 1.8 2 nm\")" : "");
      bad = 1;
    }
  }
  if (!bad && n != 1 && n != 3) { deck_problem(r, r->line[K_BOX], "system.box: give one edge or three (got %d)", n); bad = 1; }
  double L[3];
  for (int c = 0; c < n && !bad; c++) {
    const char *un = suffix[c] ? "" : unit[c] ? unit[c] : unit[n - 1] ? unit[n - 1] : ""; /* bare: the last edge's */
    char msg[256], *q = malloc(strlen(num[c]) + strlen(un) + 2);
    if (!q) { deck_problem(r, r->line[K_BOX], "system.box: out of memory"); bad = 1; break; }
    sprintf(q, "%s%s%s", num[c], *un ? " " : "", un);
    if (rl_parse_quantity(q, Q_LENGTH, u, 0, &L[c], msg, sizeof msg)) {
      deck_problem(r, r->line[K_BOX], "system.box: %s", msg);
      bad = 1;
    } else if (!(L[c] > 0)) {
      deck_problem(r, r->line[K_BOX], "system.box: %s%g must be positive", n == 1 ? "edge " : c == 0 ? "x edge "
              : c == 1 ? "y edge " : "z edge ", L[c]);
      bad = 1;
    }
    free(q);
  }
  if (!bad && !(isfinite(L[0] * L[1 % n] * L[2 % n]) && L[0] * L[1 % n] * L[2 % n] > 0)) {
    deck_problem(r, r->line[K_BOX], "system.box: the volume of %s is out of range", r->val[K_BOX]);
    bad = 1;
  }
  if (!bad)
    for (int c = 0; c < 3; c++) box[c] = L[n == 1 ? 0 : c];
  free(tmp);
}

/* The model does not build from the [model] parameters: reported at the line of the one whose own
 * value is the cause (the model builds with it at its default, the others as given). */
static void model_problem(raw_deck *r, const rl_deck *d)
{
  char *msg = strdup(rl_last_error());
  int culprit = -1;
  for (int i = 0; i < r->nmodel && culprit < 0; i++) {
    const int k = rl_model_param_index(d->model, r->model_key[i]);
    double p[RL_MODEL_MAX_PARAMS];
    rl_molecule m;
    memcpy(p, d->params, sizeof p);
    if (k < 0 || p[k] == d->model->param_defaults[k]) continue;
    p[k] = d->model->param_defaults[k];
    if (!rl_model_build(d->model, p, 0, &m)) culprit = i;
  }
  if (culprit >= 0)
    deck_problem(r, r->model_line[culprit], "[model] %s: model %s: %s", r->model_key[culprit], d->model->name,
            msg ? msg : "does not build");
  else deck_problem(r, 0, "model %s: %s", d->model->name, msg ? msg : "does not build");
  free(msg);
}

/* A step h no rotation can follow: h times the thermal angular velocity at T above 1. */
static void step_resolves_rotation(raw_deck *r, const rl_deck *d, int k, double h, double T, const char *tkey)
{
  const double hw = h * thermal_omega_at(d, T);
  if (hw > 1.0)
    deck_problem(r, r->line[k], "%s.%s %g %s is too large for %s at %g %s%s: h times the thermal angular velocity "
            "is %.3g > 1, no step can follow the rotation", keys[k].section, keys[k].name, h,
            rl_dim_unit(Q_TIME, d->units), d->model->name, T, rl_dim_unit(Q_TEMPERATURE, d->units), tkey, hw);
}

/* output.prefix, or its default (the deck's path without .ini), into d->prefix: whole (never cut),
 * leaving room for the outputs' suffixes in a path and in a file name, and naming a file, not a
 * directory ("", "dir/", "." and ".." would make hidden files such as dir/.thermo.csv). */
/* A K_INTS key: one whole number in [lo, hi] for all three axes, or three; 1 if given and good. */
static int ints3(raw_deck *r, int k, int lo, int hi, int out[3])
{
  const char *v = r->val[k];
  if (!v || r->bad[k]) return 0;
  long x[4];
  int n = 0;
  const char *p = v;
  while (*p) {
    char *end;
    errno = 0;
    const long y = strtol(p, &end, 10);
    if (end == p || (*end && !isspace((unsigned char)*end)) || n == 3) {
      deck_problem(r, r->line[k], "%s.%s: '%s' is not one whole number or three (\"%s = 24\" or \"24 24 32\")", keys[k].section,
              keys[k].name, v, keys[k].name);
      r->bad[k] = 1;
      return 0;
    }
    x[n++] = errno == ERANGE ? LONG_MAX : y;
    p = end + strspn(end, " \t");
  }
  if (n == 2) {
    deck_problem(r, r->line[k], "%s.%s: '%s' has two numbers: give one for all three axes, or three", keys[k].section, keys[k].name, v);
    r->bad[k] = 1;
    return 0;
  }
  for (int c = 0; c < 3; c++) {
    const long y = x[n == 1 ? 0 : c];
    if (y < lo || y > hi) {
      deck_problem(r, r->line[k], "%s.%s: %ld is outside %d..%d", keys[k].section, keys[k].name, y, lo, hi);
      r->bad[k] = 1;
      return 0;
    }
    out[c] = (int)y;
  }
  return 1;
}

/* The key of [interactions] that a message of rl_ewald_resolve ("pme: grid[0] = 8 is too
 * coarse ...", "ewald: kmax_sq = ...") is about: the parameter it names first, as given in the
 * deck; the keys whose defaults a derived value comes from (cutoff, ewald_tolerance) otherwise. */
static int ewald_message_key(const raw_deck *r, const char *msg)
{
  const char *p = strstr(msg, ": ");
  p = p ? p + 2 : msg;
  static const struct { const char *param; int key, fallback; } map[] = {
      {"tolerance", K_ETOL, K_ETOL},   {"cutoff", K_CUTOFF, K_CUTOFF},   {"alpha", K_EALPHA, K_CUTOFF},
      {"kmax_sq", K_EKMAX2, K_EKMAX2}, {"kmax", K_EKMAX, K_EKMAX2},      {"grid", K_PGRID, K_CUTOFF},
      {"a grid", K_PGRID, K_CUTOFF},   {"order", K_PORDER, K_PORDER},    {"eps_surface", K_EBOUND, K_EBOUND}};
  for (size_t i = 0; i < sizeof map / sizeof map[0]; i++) {
    const size_t n = strlen(map[i].param);
    if (strncmp(p, map[i].param, n) || isalnum((unsigned char)p[n]) || p[n] == '_') continue;
    if (r->val[map[i].key]) return map[i].key;
    return map[i].key == K_EKMAX && !r->val[K_EKMAX2] ? K_CUTOFF : map[i].fallback; /* derived kmax: the cutoff's */
  }
  return K_COULOMB; /* the model: no charges, dipoles or quadrupoles */
}

/* interactions.coulomb and the Ewald keys: each used only where it means something, each value
 * checked, and then the whole choice resolved as the terms will resolve it (rl_ewald_resolve on a
 * system of one molecule in the deck's box: alpha, the grid or k vectors against the tolerance,
 * the model's charges), its message at the line of the key it is about. */
static void ewald_keys(raw_deck *r, rl_deck *d, rl_units u)
{
  static const int pme_only[] = {K_PGRID, K_PORDER}, ewald_only[] = {K_EKMAX, K_EKMAX2},
                   either[] = {K_ETOL, K_EALPHA, K_EBOUND};
  rl_ewald_params_default(&d->ewald);
  d->coulomb = (rl_deck_coulomb)choice(r, K_COULOMB);
  if (r->bad[K_COULOMB]) return;
  const char *cv = val(r, K_COULOMB);
  for (size_t i = 0; i < sizeof either / sizeof either[0]; i++)
    if (r->val[either[i]] && d->coulomb == RL_DECK_COULOMB_RF)
      deck_problem(r, r->line[either[i]], "interactions.%s is only used with coulomb = ewald or pme (coulomb = rf here)", keys[either[i]].name);
  for (size_t i = 0; i < 2; i++) {
    if (r->val[pme_only[i]] && d->coulomb != RL_DECK_COULOMB_PME)
      deck_problem(r, r->line[pme_only[i]], "interactions.%s is only used with coulomb = pme (coulomb = %s here)", keys[pme_only[i]].name, cv);
    if (r->val[ewald_only[i]] && d->coulomb != RL_DECK_COULOMB_EWALD)
      deck_problem(r, r->line[ewald_only[i]], "interactions.%s is only used with coulomb = ewald (coulomb = %s here)", keys[ewald_only[i]].name, cv);
  }
  if (d->coulomb == RL_DECK_COULOMB_RF) return;
  if (r->val[K_EPSRF])
    deck_problem(r, r->line[K_EPSRF], "interactions.eps_rf is only used with coulomb = rf (coulomb = %s here: the Ewald sum's "
            "surroundings are interactions.ewald_boundary)", cv);
  if (r->val[K_DIPOLE])
    deck_problem(r, r->line[K_DIPOLE], "interactions.dipole is only used with coulomb = rf (coulomb = %s here: the point dipoles "
            "are in the Ewald sum, real and reciprocal parts, with no reaction field or shifted force)", cv);
  if (d->ff.scheme == RL_CUTOFF_MOLECULE && !r->bad[K_SCHEME])
    deck_problem(r, r->line[K_SCHEME], "interactions.scheme = molecule does not go with coulomb = %s: the real-space Ewald sum "
            "cuts every site pair by its own distance (scheme = site)", cv);
  const int before = r->problems;
  d->ewald.tolerance = number(r, K_ETOL, u, 0, 5e-4);
  if (r->val[K_EALPHA]) {
    d->ewald.alpha = number(r, K_EALPHA, u, 0, 0.0);
    if (!r->bad[K_EALPHA] && !(d->ewald.alpha > 0)) deck_problem(r, r->line[K_EALPHA], "interactions.ewald_alpha must be positive");
  }
  ints3(r, K_PGRID, 1, 4096, d->ewald.grid);
  d->ewald.order = (int)integer_in(r, K_PORDER, 3, 12, 5);
  ints3(r, K_EKMAX, 1, 4096, d->ewald.kmax);
  if (r->val[K_EKMAX2]) {
    d->ewald.kmax_sq = number(r, K_EKMAX2, u, 0, 0.0);
    if (!r->bad[K_EKMAX2] && !(d->ewald.kmax_sq >= 1)) deck_problem(r, r->line[K_EKMAX2], "interactions.ewald_kmax2 must be >= 1 (it bounds nx^2 + ny^2 + nz^2)");
  }
  const char *b = val(r, K_EBOUND);
  if (!strcmp(b, "tinfoil")) d->ewald.eps_surface = INFINITY;
  else if (!strcmp(b, "vacuum")) d->ewald.eps_surface = 1.0;
  else {
    char msg[256];
    if (rl_parse_quantity(b, Q_NONE, u, 1, &d->ewald.eps_surface, msg, sizeof msg) || !(d->ewald.eps_surface >= 1.0))
      deck_problem(r, r->line[K_EBOUND], "interactions.ewald_boundary: '%s' is not tinfoil, vacuum or a dielectric constant >= 1", b);
  }
  if (r->problems > before || !d->model || !(d->box[0] > 0) || !(d->ff.cutoff > 0) || r->bad[K_CUTOFF] ||
      d->ff.cutoff > 0.5 * fmin(d->box[0], fmin(d->box[1], d->box[2])))
    return; /* reported already: the resolution would only repeat it */
  rl_molecule m;
  if (rl_model_build(d->model, d->params, 0, &m)) return; /* reported with the model */
  /* point dipoles alone under pme, pme_order not given: the library chooses the order with the
   * mesh (order 0, forces/ewald/ewald_params.c). With charges the library would take 0 as 5 too,
   * but the deck keeps writing 5, so that the run records of charged PME decks (pme_order = 5)
   * stay as they were and their checkpoints continue */
  int charged = 0;
  for (int k = 0; k < m.nsites; k++) charged |= m.charge[k] != 0.0;
  if (d->coulomb == RL_DECK_COULOMB_PME && !r->val[K_PORDER] && m.has_dipole && !charged && d->nspecies <= 1)
    d->ewald.order = 0;
  rl_species_desc sd;
  rl_molecule_species(&m, &sd);
  rl_species_ff sff = rl_molecule_ff(&m);
  rl_system *sys = rl_system_alloc(u);
  rl_ewald_params p = d->ewald;
  p.species = &sff;
  p.nspecies = 1;
  p.cutoff = d->ff.cutoff;
  rl_ewald_info info;
  /* one molecule for charges (OpenMM's choices do not depend on the count); all of them with
   * point dipoles, whose derived alpha and mesh follow from sum mu^2 / sqrt(N) */
  int st = !sys || rl_system_add_species(sys, &sd, m.has_dipole && d->count > 0 ? d->count : 1, NULL) || rl_system_set_box(sys, d->box);
  if (!st) st = rl_ewald_resolve(sys, &p, d->coulomb == RL_DECK_COULOMB_PME ? RL_EWALD_PME : RL_EWALD_SUM, &info);
  if (st) {
    const char *msg = rl_last_error(), *tail = strstr(msg, ": ");
    const int k = ewald_message_key(r, msg);
    if (k == K_COULOMB)
      deck_problem(r, r->line[k], "interactions.coulomb = %s needs point charges: model %s: %s", cv, d->model->name, tail ? tail + 2 : msg);
    else if (r->val[k]) deck_problem(r, r->line[k], "interactions.%s = %s: %s", keys[k].name, r->val[k], tail ? tail + 2 : msg);
    else deck_problem(r, r->line[k], "interactions.%s (default %s): %s", keys[k].name, default_text(k), tail ? tail + 2 : msg);
  }
  rl_system_free(sys);
}

double rl_deck_boundary_eps(const rl_deck *d) { return d->coulomb == RL_DECK_COULOMB_RF ? d->ff.eps_rf : d->ewald.eps_surface; }

static void output_prefix(raw_deck *r, rl_deck *d, const char *path)
{
  if (r->bad[K_PREFIX]) return; /* no value: reported */
  const char *v = r->val[K_PREFIX], *what = v ? "output.prefix" : "the default output.prefix (the deck's name without .ini)";
  const int line = v ? r->line[K_PREFIX] : 0;
  size_t n = v ? strlen(v) : strlen(path);
  if (!v && n > 4 && !strcmp(path + n - 4, ".ini")) n -= 4;
  if (n > RL_DECK_PATH_MAX - 1 - RL_DECK_SUFFIX_MAX) {
    deck_problem(r, line, "%s has %zu characters: with the suffixes of its outputs (up to %d characters) their paths would "
            "pass the system's limit of %d; give a shorter one", what, n, RL_DECK_SUFFIX_MAX, RL_DECK_PATH_MAX - 1);
    return;
  }
  memcpy(d->prefix, v ? v : path, n);
  d->prefix[n] = '\0';
  const char *slash = strrchr(d->prefix, '/'), *base = slash ? slash + 1 : d->prefix;
  if (!*base || !strcmp(base, ".") || !strcmp(base, ".."))
    deck_problem(r, line, "%s '%s' names a directory: the outputs would be hidden files (%s.thermo.csv); write %s%sNAME "
            "for NAME.thermo.csv, ... there", what, d->prefix, d->prefix, d->prefix,
            *base && (!slash || slash[1]) ? "/" : "");
  else if (strlen(base) + RL_DECK_SUFFIX_MAX > RL_DECK_NAME_MAX)
    deck_problem(r, line, "%s: its last part has %zu characters: with the suffixes of its outputs (up to %d characters) "
            "their file names would pass the system's limit of %d; give a shorter one", what, strlen(base),
            RL_DECK_SUFFIX_MAX, RL_DECK_NAME_MAX);
}

/* system.start = a file (not "lattice"): whole (never cut), a .pdb, .xyz or .chk, and a regular
 * file (links followed) that can be read; nothing else is opened. */
static void start_file(raw_deck *r, rl_deck *d, const char *v)
{
  const int line = r->line[K_START];
  const size_t n = strlen(v);
  if (n >= sizeof d->start) {
    deck_problem(r, line, "system.start: the path has %zu characters, more than the system's limit of %d", n,
            RL_DECK_PATH_MAX - 1);
    return;
  }
  memcpy(d->start, v, n + 1);
  const char *ext = n > 4 ? d->start + n - 4 : "";
  struct stat sb;
  FILE *t;
  if (strcmp(ext, ".pdb") && strcmp(ext, ".xyz") && strcmp(ext, ".chk"))
    deck_problem(r, line, "system.start: '%s' is not lattice or a .pdb, .xyz or .chk file", d->start);
  else if (stat(d->start, &sb)) deck_problem(r, line, "system.start: cannot open %s: %s", d->start, strerror(errno));
  else if (!S_ISREG(sb.st_mode))
    deck_problem(r, line, "system.start: %s is not a regular file (%s)", d->start, deck_file_kind(sb.st_mode));
  else if (!(t = fopen(d->start, "rb"))) deck_problem(r, line, "system.start: cannot open %s: %s", d->start, strerror(errno));
  else fclose(t);
}

/* Neither system.box nor system.density: the box of the start file, as other codes take it (a
 * checkpoint's box, a PDB's CRYST1, an XYZ's Lattice), in the deck's units.  A file that cannot be
 * opened is left to start_file's message; one without a box is a problem here. */
static void start_box(raw_deck *r, rl_units u, const char *path, double box[3])
{
  const int line = r->line[K_START];
  const size_t n = strlen(path);
  const char *ext = n > 4 ? path + n - 4 : "";
  struct stat sb;
  box[0] = box[1] = box[2] = 0.0;
  if ((strcmp(ext, ".pdb") && strcmp(ext, ".xyz") && strcmp(ext, ".chk")) || stat(path, &sb) || !S_ISREG(sb.st_mode) ||
      access(path, R_OK))
    return; /* start_file names the problem */
  int st, nres;
  if (!strcmp(ext, ".chk")) {
    rl_checkpoint_meta meta;
    memset(&meta, 0, sizeof meta);
    rl_system *s = rl_checkpoint_load(path, &meta);
    st = !s;
    if (s) memcpy(box, meta.box, sizeof meta.box);
    free((void *)meta.blob);
    rl_system_free(s);
  } else if (!strcmp(ext, ".pdb")) st = rl_pdb_count(path, u, &nres, box);
  else st = rl_xyz_box(path, u, box);
  if (st) deck_problem(r, line, "system.start: no system.box or system.density, and %s", rl_last_error());
  else if (!(box[0] > 0 && box[1] > 0 && box[2] > 0))
    deck_problem(r, line, "system.start: %s holds no box (%s): give system.box or system.density", path,
                 !strcmp(ext, ".pdb") ? "no CRYST1 record" : !strcmp(ext, ".xyz") ? "no Lattice= on its second line"
                                                                                  : "a checkpoint without a box");
}

/* the values the handler stored (strdup'd) */
static void raw_deck_free(raw_deck *r)
{
  for (int i = 0; i < r->nmol; i++) free(r->mol[i].name);
  for (int i = 0; i < r->nml; i++) { free(r->ml[i].key); free(r->ml[i].val); }
  free(r->ml);
  free(r->molpath);
  for (int k = 0; k < NKEYS; k++) free(r->val[k]);
  for (int i = 0; i < r->nmodel; i++) { free(r->model_key[i]); free(r->model_val[i]); }
  free(r->section);
}


/* run.barostat and its keys (after run.ensemble and output.energy_every): values in the system's
 * units, each problem naming its key. */
static void baro_keys(raw_deck *r, rl_deck *d, rl_units u, int ens, int ens_ok)
{
  static const int their[] = {K_PRESSURE, K_BINTERVAL, K_TAUP, K_COMPRESS, K_BCOUPLING};
  d->barostat = choice(r, K_BARO);
  if (r->bad[K_BARO]) return;
  const int mc = d->barostat == 1, lj = u == RL_UNITS_LJ;
  if (!d->barostat) {
    for (size_t k = 0; k < sizeof their / sizeof their[0]; k++)
      if (r->val[their[k]])
        deck_problem(r, r->line[their[k]], "run.%s is only used with a barostat (run.barostat = mc or c-rescale)", keys[their[k]].name);
    return;
  }
  if (ens_ok && ens < 2)
    deck_problem(r, r->line[K_BARO] ? r->line[K_BARO] : r->line[K_ENSEMBLE], "run.barostat = %s needs a stochastic thermostat "
            "(run.ensemble = nvt-bussi or nvt-langevin[-dot[-obabo]]): the barostat samples at run.temperature", val(r, K_BARO));
  if (!r->val[K_PRESSURE]) deck_problem(r, r->line[K_BARO], "run.barostat = %s needs run.pressure", val(r, K_BARO));
  d->pressure = number(r, K_PRESSURE, u, 0, 0.0);
  /* beyond 10 GPa (1e3 reduced) no rigid-molecule model applies: most likely a unit left out
   * (101325 read as bar, not Pa) */
  const double pmax = lj ? 1e3 : 1e5 * 0.0602214076;
  if (r->val[K_PRESSURE] && !r->bad[K_PRESSURE] && !(fabs(d->pressure) <= pmax))
    deck_problem(r, r->line[K_PRESSURE], "run.pressure = %s is beyond %s: no rigid-molecule model holds there (a pressure in "
            "Pa or atm needs its unit: \"101325 Pa\", \"1 atm\")", val(r, K_PRESSURE), lj ? "+-1000 (reduced)" : "+-1e5 bar (10 GPa)");
  d->baro_interval = integer(r, K_BINTERVAL, 1, mc ? 25 : 10);
  if (!mc && !r->bad[K_BINTERVAL] && d->energy_every > 0 && d->baro_interval % d->energy_every)
    deck_problem(r, r->line[K_BINTERVAL] ? r->line[K_BINTERVAL] : r->line[K_ENERGY], "run.barostat_interval = %ld must be a "
            "multiple of output.energy_every = %ld (C-rescale needs the virial on its steps)", d->baro_interval, d->energy_every);
  d->tau_p = number(r, K_TAUP, u, 0, lj ? 1000.0 * d->timestep : 1.0);
  if (r->val[K_TAUP] && mc) deck_problem(r, r->line[K_TAUP], "run.tau_p is only used with run.barostat = c-rescale");
  else if (!r->bad[K_TAUP] && !(d->tau_p > 0)) deck_problem(r, r->line[K_TAUP], "run.tau_p must be positive");
  d->compressibility = number(r, K_COMPRESS, u, 0, lj ? 0.1 : 4.5e-5 / 0.0602214076);
  if (r->val[K_COMPRESS] && mc) deck_problem(r, r->line[K_COMPRESS], "run.compressibility is only used with run.barostat = c-rescale");
  else if (!r->bad[K_COMPRESS] && !(d->compressibility > 0)) deck_problem(r, r->line[K_COMPRESS], "run.compressibility must be positive");
  d->baro_aniso = choice(r, K_BCOUPLING);
  if (d->baro_aniso == 1 && !mc)
    deck_problem(r, r->line[K_BCOUPLING], "run.barostat_coupling = anisotropic needs run.barostat = mc (C-rescale is isotropic or semiisotropic)");
  if (d->baro_aniso == 2 && mc)
    deck_problem(r, r->line[K_BCOUPLING], "run.barostat_coupling = semiisotropic needs run.barostat = c-rescale (mc is isotropic or anisotropic)");
}


int rl_deck_load(const char *path, char **sets, int nsets, rl_deck *d, FILE *err)
{
  raw_deck r;
  memset(&r, 0, sizeof r);
  memset(d, 0, sizeof *d);
  r.path = path;
  r.err = err;
  if (strlen(path) >= sizeof d->path) {
    deck_problem(&r, 0, "the deck's path has %zu characters, more than the system's limit of %d", strlen(path),
            RL_DECK_PATH_MAX - 1);
    return r.problems;
  }
  memcpy(d->path, path, strlen(path) + 1);
  /* a regular file or a pipe (a deck from a process: /dev/stdin, <(...)), links followed; never
   * a device (/dev/zero would be read forever), checked before it is opened and again after */
  struct stat sb;
  FILE *f = NULL;
  for (int pass = 0; pass < 2; pass++) {
    if (pass ? fstat(fileno(f), &sb) : stat(path, &sb)) break;
    if (!S_ISREG(sb.st_mode) && !S_ISFIFO(sb.st_mode))
      deck_problem(&r, 0, S_ISDIR(sb.st_mode) ? "is a directory, not a deck" : "is not a regular file (%s): a deck is a text file",
              deck_file_kind(sb.st_mode));
    else if (S_ISREG(sb.st_mode) && sb.st_size > DECK_BYTES_MAX)
      deck_problem(&r, 0, "is %lld bytes, more than the %ld bytes (1 MiB) a deck may have", (long long)sb.st_size, DECK_BYTES_MAX);
    if (r.problems || (!pass && !(f = fopen(path, "r")))) break;
  }
  if (!r.problems && !f) deck_problem(&r, 0, "cannot open the deck: %s", strerror(errno));
  const int read = r.problems ? -1 : deck_read(f, &r);
  if (f) fclose(f);
  if (read < 0) { /* not a deck: its lines are not checked further */
    raw_deck_free(&r);
    return r.problems;
  }
  for (int i = 0; i < nsets; i++) { /* --set section.key=value */
    char *eq = strchr(sets[i], '='), *dot = strchr(sets[i], '.');
    if (!eq || !dot || dot > eq) { deck_problem(&r, -1, "'%s' is not section.key=value", sets[i]); continue; }
    char *sec = strndup(sets[i], (size_t)(dot - sets[i])), *name = strndup(dot + 1, (size_t)(eq - dot - 1)),
         *value = strdup(eq + 1);
    if (!sec || !name || !value) deck_problem(&r, -1, "out of memory");
    else {
      const char *v = trim(value), *c = inline_comment(v);
      if (c) /* what a deck line would read as a comment is not a value from the command line either */
        deck_problem(&r, -1, "%s.%s: '%s' contains ' %c', which starts a comment in a deck line: a value cannot "
                "contain it", trim(sec), trim(name), v, *c);
      else store(&r, trim(sec), trim(name), v, -1);
    }
    free(sec);
    free(name);
    free(value);
  }

  /* the model decides the unit system */
  deck_resolve_model(&r, d);
  rl_units u = d->model ? d->model->units : RL_UNITS_REAL;
  d->units = u;
  if (d->model) {
    for (int k = 0; k < d->model->nparams; k++) d->params[k] = d->model->param_defaults[k];
    for (int i = 0; i < r.nmodel; i++) {
      int k = rl_model_param_index(d->model, r.model_key[i]);
      char *end;
      double x = strtod(r.model_val[i], &end);
      if (k < 0) deck_problem(&r, r.model_line[i], "[model] %s: model %s has no parameter '%s'%s", r.model_key[i],
                         d->model->name, r.model_key[i], d->model->nparams ? "" : " (it has none)");
      else if (end == r.model_val[i] || *end || !isfinite(x) || x < 0)
        deck_problem(&r, r.model_line[i], "[model] %s: '%s' must be a number >= 0 (in %s)", r.model_key[i],
                r.model_val[i], d->model->param_units[k]);
      else if (!isfinite(x * x)) /* mu = 1e155: mu^2 is inf, and the dipoles silently dropped out */
        deck_problem(&r, r.model_line[i], "[model] %s: %s %s is out of range: its square, which the energies "
                "use, overflows", r.model_key[i], r.model_val[i], d->model->param_units[k]);
      else d->params[k] = x;
    }
  }
  /* [system] */
  if (!r.val[K_SPECIES]) {
    deck_require(&r, K_COUNT);
    d->count = (int)integer_in(&r, K_COUNT, 1, INT_MAX, 1);
    if (d->model) d->species[0] = (rl_deck_species){d->model, d->count}, d->nspecies = 1;
  }
  const int lattice = choice(&r, K_LATTICE);
  d->lattice = lattice == 1 ? RL_LATTICE_FCC : RL_LATTICE_SC;
  d->insert = lattice == 2;
  d->random_orientations = choice(&r, K_ORIENT) == 0;
  d->seed = (unsigned long)integer(&r, K_SEED, 0, 1);
  d->force_general = boolean(&r, K_GENERAL);
  d->inertia_scale = number(&r, K_INERTIA, d->units, 0, 1.0);
  if (!r.bad[K_INERTIA] && !(d->inertia_scale >= 1.0 && d->inertia_scale <= 100.0))
    deck_problem(&r, r.line[K_INERTIA], "system.inertia_scale = %s: must be between 1 (the real rotor) and 100", val(&r, K_INERTIA));
  double mass = 0.0;
  if (d->model) {
    rl_molecule m;
    if (rl_model_build(d->model, d->params, 0, &m)) model_problem(&r, d);
    else if (!r.val[K_SPECIES]) {
      mass = m.mass;
      if (!r.bad[K_COUNT] && r.val[K_COUNT]) count_fits(&r, d->count, &m);
    } else { /* the mean mass of a molecule; the species built in deck_resolve_model */
      for (int k = 0; k < d->nspecies; k++) {
        rl_molecule mk;
        if (!rl_model_build(d->species[k].model, NULL, 0, &mk)) mass += mk.mass * d->species[k].count;
      }
      mass /= d->count;
    }
  }
  if (r.bad[K_BOX] || r.bad[K_DENSITY]) {
    /* reported: no value */
  } else if (r.val[K_BOX] && r.val[K_DENSITY]) {
    char at[32] = "from --set";
    if (r.line[K_BOX] >= 0) snprintf(at, sizeof at, "at line %d", r.line[K_BOX]);
    deck_problem(&r, r.line[K_DENSITY], "give system.box or system.density, not both (box %s)", at);
  } else if (r.val[K_BOX]) {
    box_edges(&r, u, d->box);
  } else if (r.val[K_DENSITY]) {
    double rho = number(&r, K_DENSITY, u, 0, 0.0);
    if (!(rho > 0)) {
      if (!r.bad[K_DENSITY]) deck_problem(&r, r.line[K_DENSITY], "system.density must be positive");
    }
    else if (d->model && !r.bad[K_COUNT]) { /* real: mass density amu/nm^3 -> volume N m / rho; lj: number density */
      double V = u == RL_UNITS_LJ ? d->count / rho : d->count * mass / rho;
      d->box[0] = d->box[1] = d->box[2] = cbrt(V);
      if (!(isfinite(d->box[0]) && d->box[0] > 0)) {
        deck_problem(&r, r.line[K_DENSITY], "system.density %s gives a box edge of %g %s for %d molecules: out of range",
                val(&r, K_DENSITY), d->box[0], rl_dim_unit(Q_LENGTH, u), d->count);
        d->box[0] = d->box[1] = d->box[2] = 0.0;
      }
    }
  } else if (!r.bad[K_START] && strcmp(val(&r, K_START), "lattice")) {
    start_box(&r, u, val(&r, K_START), d->box);
  } else deck_problem(&r, 0, "give system.box or system.density");

  /* [interactions] */
  rl_ff_params_default(&d->ff);
  deck_require(&r, K_CUTOFF);
  d->ff.cutoff = number(&r, K_CUTOFF, u, 0, 0.0);
  double Lmin = fmin(d->box[0], fmin(d->box[1], d->box[2]));
  if (r.val[K_CUTOFF] && !r.bad[K_CUTOFF] && !(d->ff.cutoff > 0)) deck_problem(&r, r.line[K_CUTOFF], "interactions.cutoff must be positive");
  else if (Lmin > 0 && d->ff.cutoff > 0.5 * Lmin)
    deck_problem(&r, r.line[K_CUTOFF], "interactions.cutoff %g is larger than half the shortest box edge (%g)", d->ff.cutoff, 0.5 * Lmin);
  d->ff.scheme = choice(&r, K_SCHEME) ? RL_CUTOFF_MOLECULE : RL_CUTOFF_SITE;
  d->ff.lj_truncation = (rl_lj_truncation)choice(&r, K_LJ);
  if (d->ff.lj_truncation == RL_LJ_SWITCHED) {
    if (!r.val[K_SWITCH]) deck_problem(&r, r.line[K_LJ], "interactions.lj = switched needs interactions.switch");
    else {
      d->ff.r_switch = number(&r, K_SWITCH, u, 0, 0.0);
      if (!r.bad[K_SWITCH] && !r.bad[K_CUTOFF] && !(d->ff.r_switch >= 0 && d->ff.r_switch < d->ff.cutoff))
        deck_problem(&r, r.line[K_SWITCH], "interactions.switch %g must lie in [0, cutoff)", d->ff.r_switch);
    }
  } else if (r.val[K_SWITCH] && !r.bad[K_LJ]) deck_problem(&r, r.line[K_SWITCH], "interactions.switch is only used with lj = switched");
  d->ff.dispersion_correction = boolean(&r, K_DISP);
  d->ff.eps_rf = number(&r, K_EPSRF, u, 1, 78.3);
  d->mixing = (rl_deck_mixing)choice(&r, K_MIXING);
  if (r.val[K_PAIRS] && !r.bad[K_PAIRS] && d->nspecies) deck_pairs(&r, d);
  if (!(d->ff.eps_rf >= 1.0)) deck_problem(&r, r.line[K_EPSRF], "interactions.eps_rf %g must be >= 1", d->ff.eps_rf);
  d->ff.dipole_method = choice(&r, K_DIPOLE) ? RL_DIPOLE_SF : RL_DIPOLE_RF;
  d->ff.kernel = choice(&r, K_KERNEL) ? RL_KERNEL_GENERAL : RL_KERNEL_AUTO;
  d->ff.precision = choice(&r, K_PRECISION) ? RL_PRECISION_MIXED : RL_PRECISION_DOUBLE;
  if (r.val[K_SKIN]) {
    d->ff.skin = number(&r, K_SKIN, u, 0, -1.0);
    if (!r.bad[K_SKIN] && !(d->ff.skin >= 0)) deck_problem(&r, r.line[K_SKIN], "interactions.skin must be >= 0");
  }
  ewald_keys(&r, d, u);

  /* [run] */
  deck_require(&r, K_STEPS);
  deck_require(&r, K_DT);
  d->steps = integer(&r, K_STEPS, 0, 0);
  d->timestep = number(&r, K_DT, u, 0, 0.0);
  if (r.val[K_DT] && !r.bad[K_DT] && !(d->timestep > 0)) {
    deck_problem(&r, r.line[K_DT], "run.timestep %g must be positive", d->timestep);
    r.bad[K_DT] = 1;
  }
  /* a missing timestep is reported once, by require: the defaults derived from it (tau,
   * equilibrate_timestep) are not reported again */
  if (!r.val[K_DT]) r.bad[K_DT] = 1;
  d->method = rl_deck_integrators[choice(&r, K_INTEGRATOR)].method;
  int ens = choice(&r, K_ENSEMBLE);
  const int ens_ok = !r.bad[K_ENSEMBLE]; /* an unknown ensemble is its one problem: nothing is checked against it */
  static const rl_thermostat ensembles[] = {RL_THERMO_NONE, RL_THERMO_ISOKINETIC, RL_THERMO_BUSSI, RL_THERMO_LANGEVIN,
                                            RL_THERMO_LANGEVIN_DOT, RL_THERMO_LANGEVIN_DOT_OBABO};
  d->thermostat = ensembles[ens];
  const int stochastic = ens >= 2;
  d->thermostat_temperature = number(&r, K_TTEMP, u, 0, 0.0);
  if (ens > 0 && !r.val[K_TTEMP]) deck_problem(&r, r.line[K_ENSEMBLE], "run.ensemble = %s needs run.temperature", val(&r, K_ENSEMBLE));
  else if (ens > 0 && !r.bad[K_TTEMP] && !(d->thermostat_temperature > 0)) deck_problem(&r, r.line[K_TTEMP], "run.temperature must be positive");
  if (ens == 0 && ens_ok && r.val[K_TTEMP]) deck_problem(&r, r.line[K_TTEMP], "run.temperature is only used with an NVT ensemble");
  d->tau = number(&r, K_TAU, u, 0, 100.0 * d->timestep);
  if (r.val[K_TAU] && !stochastic && ens_ok) deck_problem(&r, r.line[K_TAU], "run.tau is only used with ensemble = nvt-bussi or nvt-langevin[-dot[-obabo]]");
  d->tau_rot = number(&r, K_TAUROT, u, 0, d->tau);
  if (r.val[K_TAUROT] && ens < 4 && ens_ok) deck_problem(&r, r.line[K_TAUROT], "run.tau_rot is only used with ensemble = nvt-langevin-dot or nvt-langevin-dot-obabo");
  else if (r.val[K_TAUROT] && !r.bad[K_TAUROT] && !(d->tau_rot > 0)) deck_problem(&r, r.line[K_TAUROT], "run.tau_rot must be positive");
  d->thermostat_groups = choice(&r, K_TGROUPS) ? RL_THERMO_GROUPS_ALL : RL_THERMO_GROUPS_TRANS_ROT;
  if (r.val[K_TGROUPS] && ens != 2 && ens_ok)
    deck_problem(&r, r.line[K_TGROUPS], "run.thermostat_groups is only used with ensemble = nvt-bussi");
  if (!(d->tau > 0) && stochastic && !r.bad[K_TAU] && (r.val[K_TAU] || !r.bad[K_DT]))
    deck_problem(&r, r.line[K_TAU], "run.tau must be positive");
  d->equilibrate_steps = integer(&r, K_EQSTEPS, 0, 0);
  d->equilibrate_timestep = number(&r, K_EQDT, u, 0, 0.25 * d->timestep);
  if (!(d->equilibrate_timestep > 0) && !r.bad[K_EQDT] && (r.val[K_EQDT] || !r.bad[K_DT]))
    deck_problem(&r, r.line[K_EQDT], "run.equilibrate_timestep must be positive");
  d->temperature = number(&r, K_TEMP, u, 0, d->thermostat_temperature);
  if (!r.val[K_TEMP] && (r.bad[K_TTEMP] || !ens_ok)) r.bad[K_TEMP] = 1; /* its default is reported there */
  if (!r.val[K_TEMP] && ens == 0 && ens_ok) deck_problem(&r, 0, "system.temperature is required for an NVE run: it draws the starting velocities, and "
                 "sets the default neighbour-list skin and the kT of the blow-up checks (from a checkpoint, give "
                 "the first run's value: the same skin continues bit for bit)");
  else if (!r.bad[K_TEMP] && !(d->temperature > 0) && (r.val[K_TEMP] || !(ens > 0 && !r.val[K_TTEMP])))
    deck_problem(&r, r.line[K_TEMP], "system.temperature must be positive");
  if (d->equilibrate_steps > 0 && !r.bad[K_TEMP] && !(d->temperature > 0)) deck_problem(&r, r.line[K_EQSTEPS], "run.equilibrate needs a temperature");
  /* an absurd step: the run's at the start's temperature or at the thermostat's, whichever is
   * higher; the relaxation's (a given one: the default, timestep / 4, passes when the run's does)
   * at the start's, which its thermostat keeps */
  if (d->model && d->timestep > 0) {
    const char *tkey;
    const double T = rl_deck_max_temperature(d, &tkey);
    step_resolves_rotation(&r, d, K_DT, d->timestep, T, tkey);
  }
  if (d->model && d->equilibrate_steps > 0 && r.val[K_EQDT] && !r.bad[K_EQDT] && d->equilibrate_timestep > 0 &&
      !r.bad[K_TEMP] && d->temperature > 0)
    step_resolves_rotation(&r, d, K_EQDT, d->equilibrate_timestep, d->temperature,
                           " (system.temperature, the relaxation's)");
  d->ff.skin = r.val[K_SKIN] ? d->ff.skin : -1.0;
  d->thermostat_seed = (unsigned long)integer(&r, K_TSEED, 0, 2);
  d->ff.threads = (int)integer_in(&r, K_THREADS, 0, RL_DECK_MAX_THREADS, 0);
  const char *omp = getenv("OMP_NUM_THREADS"); /* what run.threads = 0 takes: the same cap */
  if (d->ff.threads == 0 && !r.bad[K_THREADS] && omp && *omp) {
    char *end;
    errno = 0;
    const long t = strtol(omp, &end, 10);
    if (end != omp && (errno == ERANGE || t > RL_DECK_MAX_THREADS))
      deck_problem(&r, r.line[K_THREADS], "OMP_NUM_THREADS = %s (taken by run.threads = 0) is above the maximum %d threads",
              omp, RL_DECK_MAX_THREADS);
  }
  /* [output] */
  output_prefix(&r, d, path);
  d->thermo_every = integer(&r, K_THERMO, 1, 100);
  d->energy_every = integer(&r, K_ENERGY, 1, 1);
  if (d->thermo_every % d->energy_every)
    deck_problem(&r, r.line[K_ENERGY] ? r.line[K_ENERGY] : r.line[K_THERMO],
            "output.thermo_every = %ld must be a multiple of output.energy_every = %ld (a thermo row "
            "needs the energies)", d->thermo_every, d->energy_every);
  baro_keys(&r, d, u, ens, ens_ok);
  d->checkpoint_every = integer(&r, K_CHECKPOINT, 0, 0);
  d->trajectory_every = integer_in(&r, K_TRAJ, 0, INT32_MAX, 0);
  if (d->trajectory_every > 0 && d->steps > INT32_MAX && d->model) { /* DCD's ISTART, NSTEP: int32 */
    rl_molecule m;
    if (!rl_model_build(d->model, d->params, 0, &m) && rl_deck_site_model(&m))
      deck_problem(&r, r.line[K_STEPS], "run.steps = %ld: the DCD trajectory of %s (output.trajectory_every) numbers steps "
              "with 32-bit integers, at most %ld", d->steps, d->model->name, (long)INT32_MAX);
  }
  for (int k = 0; k < d->nspecies && d->nspecies > 1 && d->trajectory_every > 0; k++) {
    rl_molecule m; /* the DCD's PDB topology is one molecule's */
    if (!rl_model_build(d->species[k].model, k ? NULL : d->params, 0, &m) && rl_deck_site_model(&m)) {
      deck_problem(&r, r.line[K_TRAJ], "output.trajectory_every: a mixture's trajectory is an XYZ of centres and "
                   "orientations, for point dipoles and atoms only; species %s is a site model (its DCD is not "
                   "written for mixtures yet): set output.trajectory_every = 0", d->species[k].model->name);
      break;
    }
  }
  d->sample_every = integer(&r, K_SAMPLE, 0, 10);
  const char *rdf = val(&r, K_RDF);
  if (!r.bad[K_RDF] && strlen(rdf) >= sizeof d->rdf)
    deck_problem(&r, r.line[K_RDF], "output.rdf has %zu characters, at most %zu", strlen(rdf), sizeof d->rdf - 1);
  else if (!r.bad[K_RDF]) {
    memcpy(d->rdf, rdf, strlen(rdf) + 1);
    if (d->rdf[0] && d->model) { /* the pairs against the species' sites, before anything runs */
      rl_molecule m[RL_DECK_MAX_SPECIES];
      rl_deck_rdf_pair pairs[RL_DECK_MAX_RDF];
      int built = d->nspecies > 0;
      for (int k = 0; k < d->nspecies && built; k++)
        built = !rl_model_build(d->species[k].model, k ? NULL : d->params, 0, &m[k]);
      if (built && rl_deck_rdf_species_pairs(d->rdf, m, d->nspecies, pairs) < 0)
        deck_problem(&r, r.line[K_RDF], "%s", rl_last_error());
    }
  }
  d->discard = strcmp(val(&r, K_DISCARD), "auto") ? integer(&r, K_DISCARD, 0, 0) : -1;
  d->tconf = boolean(&r, K_TCONF);
  if (!r.bad[K_START] && strcmp(val(&r, K_START), "lattice")) start_file(&r, d, val(&r, K_START));
  if (r.val[K_RESIDUES] && !r.bad[K_RESIDUES] && d->nspecies) deck_residues(&r, d);
  int pr = choice(&r, K_PROGRESS);
  d->progress = pr == 0 ? -1 : pr == 1 ? 1 : 0;

  raw_deck_free(&r);
  return r.problems;
}


void rl_deck_print_keys(FILE *f, int md)
{
  const char *sec = "";
  if (md)
    fprintf(f, "# Deck keys\n\nGenerated by `rotleap deck-keys --markdown` from the key table in "
               "`app/deck.c`; `tests` checks that this file matches it.\n\n"
               "A deck is an INI file. Numbers take a unit suffix in real units (`2 fs`, `0.9 nm`, "
               "`9 A`, `298 K`, `1 g/cm3`); a bare number is in the default unit shown. Reduced "
               "(lj) models take bare numbers only. `--set section.key=value` overrides any key; `--set section.key=` returns it to its default. "
               "Model parameters go in `[model]` (see `rotleap models`).\n\n"
               "## Format\n\n"
               "Decks are parsed by libinih (Debian's `libinih-dev`); rotleap checks each line against these "
               "rules before libinih reads it, so that none of them depends on how the library was built.\n\n"
               "- A line is blank, a comment (its first non-blank character is `;` or `#`), a `[section]` "
               "header (a name of at most %d characters), or `key = value` (`key: value` also works).\n"
               "- In every line, a `;` or `#` after a blank (space or tab) starts a comment that runs to the "
               "end of the line: `prefix = out # a note` is `out`, `temperature = 298 K ; room` is `298 K`. "
               "A `;` or `#` with no blank before it belongs to the value (`prefix = run#2`). So no value "
               "contains ` ;` or ` #`, and `--set` refuses one that does.\n"
               "- Blanks around keys, values and headers are ignored, at the start of a line too: an "
               "indented key is a key. A value never continues on the next line: an indented line without "
               "a key is refused at its line.\n"
               "- An empty value (`prefix =`) is refused: remove the line for the default.\n"
               "- A line has at most %d characters before its comment (a comment may be of any length), "
               "except a `start` or `prefix` line, whose path may have up to %d characters, the system's "
               "limit. Paths are never cut: a longer one is refused by its key, and so is an `output.prefix` "
               "that leaves less than %d characters for the suffixes of the outputs in a path, or in a file "
               "name (at most %d characters), or that names a directory (`results/`, `..`).\n"
               "- The deck is a regular file (a link to one is followed) or a pipe (`/dev/stdin`), of at most "
               "1 MiB and without NUL bytes: a binary file or a device is refused at once. A UTF-8 byte-order "
               "mark is skipped. Reading stops after %d problems.\n",
            DECK_SECTION_MAX, DECK_LINE_MAX, RL_DECK_PATH_MAX - 1, RL_DECK_SUFFIX_MAX, RL_DECK_NAME_MAX,
            DECK_READ_PROBLEMS_MAX);
  for (int k = 0; k < NKEYS; k++) {
    const key_def *K = &keys[k];
    if (strcmp(sec, K->section)) {
      sec = K->section;
      if (md) fprintf(f, "\n## [%s]\n\n| key | type | unit (real) | default | meaning |\n|---|---|---|---|---|\n", sec);
      else fprintf(f, "\n[%s]\n", sec);
    }
    const char *type = K->type == K_CHOICE ? K->choices : K->type == K_INT ? "integer" : K->type == K_INTS ? "integers" : K->type == K_BOOL ? "yes/no"
                     : K->type == K_REAL ? "number" : K->type == K_PATH ? "path" : K->dim == Q_LENGTH ? "lengths" : "text";
    const char *unit = K->dim == Q_NONE ? "" : rl_dim_unit(K->dim, RL_UNITS_REAL);
    if (md) fprintf(f, "| `%s` | %s | %s | %s | %s |\n", K->name, type, unit, K->def ? K->def : "", K->help);
    else fprintf(f, "  %-22s %-34s %-7s default %-8s %s\n", K->name, type, unit, K->def ? K->def : "-", K->help);
  }
  if (md)
    fprintf(f, "\n## [model]\n\nAdjustable parameters of reduced models, by name, for example "
               "`mu = 1.5` for `stockmayer` (see `rotleap models`). A parameter must be a number >= 0 "
               "whose square is a finite double (the energies use it: `mu = 1e155` is refused).\n");
  if (md)
    fprintf(f, "\n## Molecules: [molecule NAME]\n\n"
               "A deck runs a catalogue model or a rigid molecule of its own, defined by its sites in a "
               "`[molecule NAME]` section of the deck or of the file `system.molecules` names (a file of such "
               "sections only, in the deck's line format, so that one file serves many decks; a relative path is "
               "taken from the deck's directory). `system.model = NAME` runs it. rotleap computes the centre of "
               "mass, the inertia tensor and the principal axes, classifies the molecule to the cheapest exact "
               "family (point, dipole, linear, spherical, symmetric, asymmetric: docs/integrators.md) and picks the "
               "pair kernel from its site pattern as for the catalogue: TIP4P written out site by site runs bit for "
               "bit as `model = tip4p` (tests/cli/molecule_tests.sh). The summary's `species` line gives the family, "
               "the rotation path and the relative differences of the principal moments.\n\n"
               "```\n[molecule water]\nunits = real\n"
               "site = O  0 0 0 nm                 mass 15.9994 sigma 0.315365 nm epsilon 0.155 kcal/mol\n"
               "site = H1 0.0756950 0 0.0585882 nm mass 1.008   charge 0.52\n"
               "site = H2 -0.0756950 0 0.0585882 nm mass 1.008  charge 0.52\n"
               "site = M  0 0 0.015 nm             mass 0       charge -1.04\n```\n\n"
               "| key | meaning |\n|---|---|\n"
               "| `site` | one line per site, in order: `NAME x y z [unit]` then any of `mass M` (required; 0 for a "
               "massless site such as TIP4P's M), `charge Q`, `sigma S [unit]` and `epsilon E [unit]` (together), "
               "`dipole dx dy dz [unit]` (a point dipole; along the molecular axis), `quadrupole Q [unit]` (a linear "
               "point quadrupole, along the axis of a linear molecule or dipole). Positions in any frame (an example "
               "geometry in the lab is fine). Units as the deck's quantities: lengths nm, A, pm; energies kJ/mol, "
               "kcal/mol, K; mass amu; charge e; dipole e*nm, D, e*A; quadrupole e*nm^2, D*A, e*A^2; a bare number is "
               "in the first; in lj units every value is bare (reduced). A unit follows the numbers it applies to, "
               "as a word of its own (`0.1 0 0 nm`) or attached (`3.15A`). At most %d sites; site names of at most 7 "
               "characters, each once |\n"
               "| `units` | real (default) or lj: the deck's unit system, as a catalogue model's |\n"
               "| `inertia` | a single-centre point dipole's moment I (or `I I I`), amu nm^2 or m sigma^2 |\n"
               "| `mixing` | lorentz-berthelot (default) or geometric: the sigma of unlike LJ sites |\n"
               "| `symmetrize` | yes: principal moments within %g relative count as equal and are replaced by their "
               "mean (the sites stay where they are), for a symmetric top whose rounded coordinates miss the %g "
               "tolerance; the summary warns of such a near miss and names this key |\n"
               "| `description` | free text |\n\n"
               "Refused, each at its file and line: a site without a mass, a molecule of no mass, coincident "
               "sites, a negative mass, sigma or epsilon, a value that is not finite, an unknown unit or key, a "
               "dipole off the molecular axis, a linear molecule with a site off its axis (beyond %g of its size), "
               "a name the catalogue has, a molecule defined twice, another section in a molecule file.\n",
            RL_MOLECULE_MAX_SITES, RL_DECK_SYMMETRIZE_RTOL, RL_INERTIA_RTOL, RL_AXIS_RTOL);
  if (md)
    fprintf(f, "\n## Mixtures: system.species\n\n"
               "`system.species` replaces `system.model` and `system.count`: each species is `NAME:COUNT`, a "
               "catalogue model (with its default parameters) or a `[molecule NAME]`, all in one unit system, at "
               "most %d. The molecules are numbered species by species in the order given (the numbering of "
               "checkpoints, XYZ and PDB files); on a lattice the species take the lattice sites at random "
               "(system.seed), `system.lattice = random` inserts the molecules at random centres, an XYZ start names each body's species, a PDB start's residue names give them (water, Na+ and Cl- by the names GROMACS, OpenMM and AMBER write; others by `system.residues`; docs/files.md). Unlike LJ sites mix by `interactions.mixing` "
               "(Lorentz-Berthelot unless every species' model mixes geometrically, as OPLS and EPM2 do), and "
               "`interactions.pairs` sets single site pairs (at most %d). The summary has one `species` line per "
               "species (family, rotation path); the pair kernel line names the kernels of the whole mixture and `pair_kernels_by_species` which "
               "kernel takes the pairs of each two species (`spc-e/spc-e: charge-lj; spc-e/na-spce: general`: bodies "
               "of one species take its kernel, pairs of two species the reference routine). In a mixture "
               "`output.rdf` takes pairs between the species' sites (`spc-e:O-na-spce`), the thermo file has each "
               "species' `t_trans_NAME` and, if it rotates, `t_rot_NAME`, PREFIX.results.txt its temperatures and "
               "`self_diffusion_NAME`, PREFIX.tcf.csv its MSD (docs/observables.md, \"Mixtures\").\n\n"
               "```\n[system]\nspecies = stockmayer:27 lj:81\ndensity = 0.8\nlattice = fcc\n"
               "[molecule lj]\nunits = lj\nsite = A 0 0 0 mass 1 sigma 1.2 epsilon 0.8\n"
               "[interactions]\ncutoff = 2.0\nmixing = lorentz-berthelot\n"
               "pairs = stockmayer:S lj:A sigma 1.1 epsilon 0.9\n```\n\n"
               "Refused: a species given twice or with a count below 1 (leave it out), a name that is neither a "
               "catalogue model nor a molecule of the deck, species in real and lj units together, system.species "
               "with system.model, system.count or [model] parameters, a pair override naming a species that is not "
               "in the mixture or a site its molecule does not have (the message lists those it has).\n",
            RL_DECK_MAX_SPECIES, RL_DECK_MAX_PAIRS);
}
