/* The scene of a deck (scene.h). */
#include "scene.h"
#include "quantity.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* A mixture on a lattice: the lattice fills the bodies in order, species after species; the
 * species take the lattice sites at random instead (Fisher-Yates over the positions, a
 * splitmix64 stream seeded by system.seed; the orientations stay each body's). */
static uint64_t splitmix64(uint64_t *x)
{
  uint64_t z = (*x += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

static int shuffle_species(rl_system *sys, unsigned long seed)
{
  uint64_t x = (uint64_t)seed ^ 0x5EC1E5ull;
  for (int i = rl_system_count(sys) - 1; i > 0; i--) {
    const int j = (int)(splitmix64(&x) % (uint64_t)(i + 1));
    double ri[3], rj[3];
    rl_system_get_position(sys, i, ri);
    rl_system_get_position(sys, j, rj);
    if (rl_system_set_position(sys, i, rj) || rl_system_set_position(sys, j, ri)) return 1;
  }
  return 0;
}

/* system.lattice = random: each body in turn at a random centre (its orientation the lattice's),
 * refused while an LJ site pair with a body placed before is closer than 0.8 sigma_ab.  1 with a
 * message naming the body that did not fit. */
#define SCENE_INSERT_TRIES 10000
#define SCENE_INSERT_SIGMA 0.7
static int insert_random(rl_system *sys, const rl_molecule *mols, unsigned long seed)
{
  const int n = rl_system_count(sys), ns = rl_system_site_offset(sys, n - 1) + mols[rl_system_species_of(sys, n - 1)].nsites;
  double (*x)[3] = malloc((size_t)ns * sizeof *x);
  if (!x) return rl_error(RL_ENOMEM, "out of memory for the random insertion");
  uint64_t st = (uint64_t)seed ^ 0x1A5E27ull;
  double L[3];
  rl_system_box(sys, L);
  for (int i = 0; i < n; i++) {
    const rl_molecule *mi = &mols[rl_system_species_of(sys, i)];
    const int oi = rl_system_site_offset(sys, i);
    int ok = 0;
    for (int t = 0; t < SCENE_INSERT_TRIES && !ok; t++) {
      double r[3];
      for (int c = 0; c < 3; c++) r[c] = L[c] * (double)(splitmix64(&st) >> 11) * 0x1.0p-53;
      if (rl_system_set_position(sys, i, r)) { free(x); return 1; }
      rl_system_site_positions_of(sys, i, i + 1, x);
      ok = 1;
      for (int j = 0; j < i && ok; j++) {
        const rl_molecule *mj = &mols[rl_system_species_of(sys, j)];
        const int oj = rl_system_site_offset(sys, j);
        for (int a = 0; a < mi->nsites && ok; a++)
          for (int b = 0; b < mj->nsites && ok; b++) {
            if (!(mi->epsilon[a] > 0 && mj->epsilon[b] > 0)) continue;
            double r2 = 0.0;
            for (int c = 0; c < 3; c++) {
              double dx = x[oi + a][c] - x[oj + b][c];
              dx -= L[c] * nearbyint(dx / L[c]);
              r2 += dx * dx;
            }
            const double dmin = SCENE_INSERT_SIGMA * 0.5 * (mi->sigma[a] + mj->sigma[b]);
            ok = r2 >= dmin * dmin;
          }
      }
    }
    if (!ok) {
      free(x);
      return rl_error(RL_EINVAL, "system.lattice = random: molecule %d of %d (%s) found no place in %d tries where "
                      "no LJ site pair comes closer than %g sigma: the box is too full for random insertion (lower "
                      "the density, or use system.lattice = sc or fcc)", i + 1, n, mi->name, SCENE_INSERT_TRIES,
                      SCENE_INSERT_SIGMA);
    }
  }
  free(x);
  return 0;
}

int scene_build(const rl_deck *d, scene *s)
{
  memset(s, 0, sizeof *s);
  if (rl_model_build(d->model, d->params, d->force_general, &s->mol)) return 1;
  s->mols[0] = s->mol;
  for (int k = 1; k < d->nspecies; k++) /* system.species: each model's defaults */
    if (rl_model_build(d->species[k].model, NULL, d->force_general, &s->mols[k])) return 1;
  for (int k = 0; k < d->nspecies; k++) /* system.inertia_scale: heavier rotors, same configurations */
    for (int a = 0; a < 3; a++) s->mols[k].inertia[a] *= d->inertia_scale;
  s->mol = s->mols[0];
  s->sys = rl_system_alloc(d->units);
  if (!s->sys) return 1;
  for (int k = 0; k < d->nspecies; k++) {
    rl_species_desc sd;
    rl_molecule_species(&s->mols[k], &sd);
    if (rl_system_add_species(s->sys, &sd, d->species[k].count, NULL)) return 1;
  }
  size_t n = strlen(d->start);
  const char *ext = n > 4 ? d->start + n - 4 : "";
  double box[3] = {0, 0, 0};
  if (!d->start[0]) {
    if (rl_system_lattice(s->sys, d->box, d->lattice, d->random_orientations, d->seed) ||
        (d->nspecies > 1 && !d->insert && shuffle_species(s->sys, d->seed))) return 1;
    if (d->insert && (rl_system_set_box(s->sys, d->box) || insert_random(s->sys, s->mols, d->seed))) return 1;
  } else if (!strcmp(ext, ".chk")) {
    rl_checkpoint_meta meta;
    memset(&meta, 0, sizeof meta);
    if (rl_checkpoint_read(d->start, s->sys, &meta)) {
      if (strstr(rl_last_error(), ": moment J")) { /* the likeliest cause, named */
        char msg[512];
        snprintf(msg, sizeof msg, "%s", rl_last_error());
        rl_error(RL_EINVAL, "%s (the moments are the model's times system.inertia_scale, %g in this deck: a run "
                 "continues with the scale it was started with)", msg, d->inertia_scale);
      }
      return 1;
    }
    s->restart = 1;
    s->step0 = meta.step;
    s->t0 = meta.time;
    s->blob = (void *)meta.blob;
    s->blob_size = meta.blob_size;
    memcpy(box, meta.box, sizeof box);
  } else if (!strcmp(ext, ".pdb")) {
    const rl_molecule *mols[RL_DECK_MAX_SPECIES];
    for (int k = 0; k < d->nspecies; k++) mols[k] = &s->mols[k];
    double rms;
    if (rl_pdb_read_state_residues(d->start, s->sys, mols, d->residues, d->nresidues, 0.0, &rms, box)) return 1;
  } else if (rl_xyz_read_state(d->start, s->sys, box)) return 1;
  /* the start's box must be the deck's, to the precision its file holds: a PDB's CRYST1 has
   * 0.001 file units (A, or sigma in reduced units; GROMACS and OpenMM write it so too), so the
   * box a deck with a density writes to PDB (1.24172 nm as 12.417 A) starts that deck again.  A
   * checkpoint and rotleap's XYZ (%.10f) hold the box to 1e-6 relative and better.  The run uses
   * the deck's box. */
  const int pdb = !strcmp(ext, ".pdb");
  const double file_unit = d->units == RL_UNITS_REAL ? 0.1 : 1.0; /* A or sigma, in nm or sigma */
  /* under a barostat the box is part of the state: the start's, whatever the deck's was */
  const int own_box = d->barostat && box[0] > 0;
  for (int c = 0; c < 3 && !own_box; c++) {
    const double tol = pdb ? 1e-3 * file_unit * (1.0 + 1e-9) : 1e-6 * d->box[c];
    if (box[0] > 0 && !(fabs(box[c] - d->box[c]) <= tol)) {
      const char *lu = rl_dim_unit(Q_LENGTH, d->units);
      return rl_error(RL_EINVAL, "the box of %s (%g %g %g %s) differs from the deck's (%g %g %g %s) by more than %s",
                      d->start, box[0], box[1], box[2], lu, d->box[0], d->box[1], d->box[2], lu,
                      pdb ? (d->units == RL_UNITS_REAL ? "0.001 A, the resolution of its CRYST1 record"
                                                       : "0.001 sigma, the resolution of its CRYST1 record")
                          : "1e-6 relative");
    }
  }
  if (rl_system_set_box(s->sys, own_box ? box : d->box)) return 1; /* the system owns it from here on */
  if (!s->restart && rl_system_maxwell_boltzmann(s->sys, d->temperature, d->seed + 1)) return 1;
  if (!(s->terms = scene_terms(d, s->mols, s->sys))) return 1;
  s->ff = rl_terms_find(s->terms, &rl_term_pair);
  return 0;
}

static int ends_with(const char *s, const char *tail)
{
  const size_t n = strlen(s), m = strlen(tail);
  return n >= m && !strcmp(s + n - m, tail);
}

int scene_check_outputs(const rl_deck *d, const char *const *paths, int n)
{
  struct stat sd, ss, so;
  const int deck = stat(d->path, &sd) == 0, start = d->start[0] && stat(d->start, &ss) == 0;
  for (int i = 0; i < n; i++) {
    if (stat(paths[i], &so)) continue; /* not there: it cannot be either */
    if (deck && so.st_dev == sd.st_dev && so.st_ino == sd.st_ino)
      return rl_error(RL_EINVAL, "the output %s would overwrite the deck %s: give another output.prefix (now %s)",
                      paths[i], d->path, d->prefix);
    if (start && so.st_dev == ss.st_dev && so.st_ino == ss.st_ino && !(ends_with(paths[i], ".chk") && ends_with(d->start, ".chk")))
      return rl_error(RL_EINVAL, "the output %s would overwrite system.start = %s: give another output.prefix (now %s)",
                      paths[i], d->start, d->prefix);
  }
  return RL_OK;
}

double scene_skin(const rl_deck *d, const rl_molecule *mol)
{
  if (d->ff.skin >= 0.0) return d->ff.skin;
  const double T = d->thermostat_temperature > 0 ? d->thermostat_temperature : d->temperature;
  return rl_ff_skin_for_step(d->ff.cutoff, rl_units_kB(d->units) * T, mol->mass, d->timestep);
}

const rl_molecule *scene_lightest(const rl_deck *d, const rl_molecule *mols)
{
  int light = 0;
  for (int k = 1; k < d->nspecies; k++)
    if (mols[k].mass < mols[light].mass) light = k;
  return &mols[light];
}

/* The geometric rule for every unlike pair: interactions.mixing, or the models' own (all of
 * them geometric). */
static int geometric(const rl_deck *d)
{
  if (d->mixing != RL_DECK_MIXING_MODEL) return d->mixing == RL_DECK_MIXING_GEOMETRIC;
  int g = 1;
  for (int k = 0; k < d->nspecies; k++) g &= d->species[k].model->geometric_mixing != 0;
  return g;
}

/* Unlike species under the geometric rule (the pair term mixes within each species), then
 * interactions.pairs. */
static int mix_pairs(const rl_deck *d, rl_forcefield *ff, const rl_species_ff *sff)
{
  for (int ka = 0; ka < d->nspecies && geometric(d); ka++)
    for (int kb = ka + 1; kb < d->nspecies; kb++)
      for (int a = 0; a < sff[ka].nsites; a++)
        for (int b = 0; b < sff[kb].nsites; b++)
          if (sff[ka].epsilon[a] > 0 && sff[kb].epsilon[b] > 0 &&
              rl_forcefield_set_lj_pair(ff, ka, a, kb, b, sqrt(sff[ka].sigma[a] * sff[kb].sigma[b]),
                                        sqrt(sff[ka].epsilon[a] * sff[kb].epsilon[b])))
            return 1;
  for (int i = 0; i < d->npairs; i++) {
    const rl_deck_pair *p = &d->pairs[i];
    if (rl_forcefield_set_lj_pair(ff, p->species[0], p->site[0], p->species[1], p->site[1], p->sigma, p->epsilon)) return 1;
  }
  return 0;
}

rl_terms *scene_terms(const rl_deck *d, const rl_molecule *mols, const rl_system *sys)
{
  const int ns = d->nspecies;
  rl_species_ff sff[RL_DECK_MAX_SPECIES], pair_sff[RL_DECK_MAX_SPECIES];
  int has_dipole = 0, point_dipoles = 1; /* point_dipoles: every dipole a one-site species', no charges */
  for (int k = 0; k < ns; k++) {
    sff[k] = pair_sff[k] = rl_molecule_ff(&mols[k]);
    has_dipole |= mols[k].has_dipole;
    point_dipoles &= !mols[k].has_dipole || mols[k].nsites == 1;
    for (int a = 0; a < mols[k].nsites; a++) point_dipoles &= mols[k].charge[a] == 0.0;
  }
  double no_charge[RL_MOLECULE_MAX_SITES] = {0};
  const int ewald = d->coulomb != RL_DECK_COULOMB_RF;
  /* within each species the pair term's rule (OPLS, EPM2: geometric mixing); unlike species in mix_pairs */
  rl_pair_params pp = {d->ff, pair_sff, ns, geometric(d)};
  pp.p.skin = scene_skin(d, scene_lightest(d, mols));
  rl_ewald_params ep = d->ewald;
  ep.species = sff;
  ep.nspecies = ns;
  ep.cutoff = d->ff.cutoff;
  ep.threads = d->ff.threads;
  ep.remove_net_force = 1; /* the mesh's net force off: the total momentum stays zero, a continuation bit for bit */
  const rl_term_type *recip = d->coulomb == RL_DECK_COULOMB_PME ? &rl_term_pme : &rl_term_ewald;
  /* Ewald: the real space of charges, or of Stockmayer point dipoles (one site at the centre, no
   * charges: the "stockmayer" kernel's dipole_lj_ewald rows), in the pair term's kernels (its
   * coulomb or dipolar component, with the LJ in one pass; the deck allows the site cutoff
   * only), with the alpha the reciprocal term resolves; the term "ewald-real" remains the
   * reference, and does the real space of other dipolar molecules (off-centre dipoles, dipoles
   * with charges).  With the molecule cutoff it would be the term too. */
  const int real_in_pair = ewald && d->ff.scheme == RL_CUTOFF_SITE && (!has_dipole || point_dipoles);
  rl_ewald_info ei;
  if (real_in_pair && rl_ewald_resolve(sys, &ep, recip == &rl_term_pme ? RL_EWALD_PME : RL_EWALD_SUM, &ei)) return NULL;
  if (real_in_pair) {
    pp.p.coulomb = RL_COULOMB_EWALD_REAL;
    pp.p.ewald_alpha = ei.alpha;
    pp.p.intramolecular_rf = 0;
  } else if (ewald) { /* the charges and point dipoles are the Ewald terms': no reaction field in the pair term */
    for (int k = 0; k < ns; k++) {
      pair_sff[k].charge = no_charge;
      pair_sff[k].dipole = NULL;
    }
  }
  rl_terms *t = rl_terms_alloc(sys);
  if (!t || rl_terms_add(t, &rl_term_pair, &pp, NULL) ||
      (ewald && !real_in_pair && rl_terms_add(t, &rl_term_ewald_real, &ep, NULL)) ||
      (ewald && rl_terms_add(t, recip, &ep, NULL)) || mix_pairs(d, rl_terms_find(t, &rl_term_pair), sff)) {
    rl_terms_free(t);
    return NULL;
  }
  const rl_forcefield *ff = rl_terms_find(t, &rl_term_pair);
  if (pp.p.precision == RL_PRECISION_MIXED && strcmp(rl_forcefield_precision(ff), "mixed") != 0)
    fprintf(stderr, "rotleap: interactions.precision = mixed has no effect here: only the TIP4P "
                    "kernel (model %s: kernel '%s') on a CPU with AVX2 (rows '%s') has single-precision "
                    "terms; the pair terms run in double\n",
            d->model->name, rl_forcefield_kernel(ff), rl_forcefield_rows(ff));
  return t;
}

int scene_electrostatics(const rl_deck *d, rl_terms *t, char *buf, size_t size)
{
  for (int k = 0; k < rl_terms_count(t); k++) {
    const rl_term_type *type = rl_terms_type(t, k);
    if (type == &rl_term_pme || type == &rl_term_ewald)
      return rl_ewald_describe(rl_ewald_term_info(rl_terms_state(t, k)), d->units, buf, size) > 0;
  }
  if (size) buf[0] = '\0';
  return 0;
}

int scene_ewald_warnings(rl_terms *t, rl_ff_warning *out, int max)
{
  for (int k = 0; k < rl_terms_count(t); k++) {
    const rl_term_type *type = rl_terms_type(t, k);
    if (type == &rl_term_pme || type == &rl_term_ewald) return rl_ewald_warnings(rl_terms_state(t, k), out, max);
  }
  return 0;
}

void scene_free(scene *s)
{
  free(s->blob);
  rl_terms_free(s->terms);
  rl_system_free(s->sys);
}

struct scene_relaxation {
  rl_integrator *in;
  rl_run *drv;
  long k;        /* steps done */
};

/* The relaxation's message gives t without a unit: say which, and the step that was used. */
static int relax_error(const rl_deck *d, int st)
{
  const char *tu = rl_dim_unit(Q_TIME, d->units);
  return rl_error_wrap(st, "during equilibration (run.equilibrate_timestep = %g %s; t in %s)", d->equilibrate_timestep,
                       tu, d->units == RL_UNITS_LJ ? "reduced units" : tu);
}

scene_relaxation *scene_relax_begin(const rl_deck *d, scene *s, long k0, double t0)
{
  /* relaxation from the start: Bussi with tau = 20 steps, which rescales the half-step
   * velocities and stays sane however far T is from T0 (the isokinetic eqs. 17-18 do not) */
  scene_relaxation *r = calloc(1, sizeof *r);
  if (!r) { rl_error(RL_ENOMEM, "out of memory"); return NULL; }
  rl_integrator_params p;
  scene_integrator_params(d, SCENE_RELAX, &p);
  r->in = rl_integrator_alloc(s->sys, &p, rl_terms_provider(s->terms));
  int st = !r->in ? RL_EINVAL : k0 > 0 ? rl_integrator_resume(r->in, k0, t0) : rl_integrator_init(r->in);
  /* a relaxation that blows up stops here, named, rather than handing the run a broken start;
   * its energy may fall steeply (that is its purpose), so only non-finite energies and
   * molecules thrown across the box count (the watch's relax mode) */
  rl_run_params rp = {.energy_every = 1, .h = d->equilibrate_timestep};
  scene_watch_params(d, 1, &rp.watch);
  if (!st && !(r->drv = rl_run_alloc(s->sys, r->in, s->terms, &rp))) st = RL_ENOMEM;
  if (st) {
    relax_error(d, st);
    rl_run_free(r->drv);
    rl_integrator_free(r->in);
    free(r);
    return NULL;
  }
  rl_run_watch(r->drv)->relax = 1;
  r->k = k0;
  return r;
}

int scene_relax_run(const rl_deck *d, scene *s, scene_relaxation *r, const volatile sig_atomic_t *stop)
{
  (void)s;
  long done = 0;
  const int st = rl_run_steps(r->drv, r->k, d->equilibrate_steps, stop, &done);
  r->k += done;
  return st ? relax_error(d, st) : RL_OK;
}

long scene_relax_step(const scene_relaxation *r) { return r->k; }
rl_integrator *scene_relax_integrator(scene_relaxation *r) { return r->in; }

int scene_relax_end(scene_relaxation *r, int finish)
{
  if (!r) return RL_OK;
  const int st = finish ? rl_integrator_finish(r->in) : RL_OK;
  rl_run_free(r->drv);
  rl_integrator_free(r->in);
  free(r);
  return st;
}

int scene_relax(const rl_deck *d, scene *s)
{
  if (d->equilibrate_steps <= 0 || s->restart) return RL_OK;
  scene_relaxation *r = scene_relax_begin(d, s, 0, 0.0);
  if (!r) return RL_EINVAL;
  int st = scene_relax_run(d, s, r, NULL);
  const int fin = scene_relax_end(r, !st);
  return st ? st : fin;
}

int scene_drift_mode(const rl_deck *d, double alt)
{
  return d->thermostat == RL_THERMO_ISOKINETIC && alt > SCENE_ALT_MODE;
}

void scene_watch_params(const rl_deck *d, int relax, rl_watch_params *w)
{
  memset(w, 0, sizeof *w);
  w->T = d->thermostat_temperature > 0 ? d->thermostat_temperature : d->temperature;
  w->window = SCENE_WINDOW;
  w->drift_error = SCENE_DRIFT_ERROR;
  w->alt_mode = SCENE_ALT_MODE;
  w->isokinetic = d->thermostat == RL_THERMO_ISOKINETIC;
  w->names.timestep = relax ? "run.equilibrate_timestep" : "run.timestep";
  w->names.relax = "run.equilibrate, with a small run.equilibrate_timestep";
  w->names.isokinetic = "Relax the start at run.temperature first (run.equilibrate, with system.temperature = "
                        "run.temperature or not given), or use run.ensemble = nvt-bussi";
}

void scene_integrator_params(const rl_deck *d, scene_purpose what, rl_integrator_params *p)
{
  rl_integrator_params_default(p);
  p->threads = d->ff.threads; /* run.threads: the rotation solves too */
  switch (what) {
  case SCENE_RELAX:
    p->h = d->equilibrate_timestep;
    p->thermostat = RL_THERMO_BUSSI;
    p->tau = 20.0 * d->equilibrate_timestep;
    p->seed = d->seed + 2;
    p->T0 = d->temperature;
    break;
  case SCENE_ONSTEP:
    p->h = d->timestep;
    p->threads = 0;
    break;
  case SCENE_RUN:
    p->h = d->timestep;
    p->method = d->method;
    p->thermostat = d->thermostat;
    p->T0 = d->thermostat_temperature;
    p->tau = d->tau;
    p->tau_rot = d->tau_rot;
    p->seed = d->thermostat_seed;
    p->groups = d->thermostat_groups;
    p->force_general = d->force_general;
    p->energy_every = d->energy_every;
    break;
  }
}

/* rotleap's check of a step's values: the energy components, the total, the pressure in the
 * deck's unit and the virial finite, a non-finite one named with what produces it. */
static int run_check(void *ctx, const rl_run_report *r)
{
  const rl_deck *d = ctx;
  return scene_check_finite(d, r->terms, r->energies, r->forces->virial, scene_pressure_out(d, r->pressure));
}

rl_run *scene_run_driver(const rl_deck *d, scene *s, rl_integrator *in)
{
  rl_run_params rp = {.energy_every = d->energy_every, .h = d->timestep, .check = run_check, .check_ctx = (void *)d};
  scene_watch_params(d, 0, &rp.watch);
  return rl_run_alloc(s->sys, in, s->terms, &rp);
}

int scene_add_barostat(const rl_deck *d, rl_integrator *in)
{
  if (!d->barostat) return RL_OK;
  const rl_barostat_params bp = {.P0 = d->pressure, .T0 = d->thermostat_temperature, .interval = d->baro_interval,
                                 .tau_p = d->tau_p, .compressibility = d->compressibility,
                                 .coupling = d->baro_aniso == 1 ? RL_BARO_ANISOTROPIC
                                             : d->baro_aniso == 2 ? RL_BARO_SEMIISOTROPIC : RL_BARO_ISOTROPIC,
                                 .min_edge = 2.0 * d->ff.cutoff, .seed = d->thermostat_seed + SCENE_BARO_SEED};
  return rl_integrator_add_op(in, d->barostat == 1 ? &rl_stepop_mc_barostat : &rl_stepop_crescale, &bp);
}

double scene_density_mass(const rl_deck *d, const rl_system *sys)
{
  double m = 0.0;
  for (int i = 0; i < rl_system_count(sys); i++) m += rl_system_mass(sys, i);
  return d->units == RL_UNITS_REAL ? m / 602.214076 : m;
}

rl_stepop *scene_barostat(const rl_deck *d, rl_integrator *in)
{
  const rl_stepop_type *T = d->barostat == 1 ? &rl_stepop_mc_barostat : d->barostat == 2 ? &rl_stepop_crescale : NULL;
  for (int k = 0; T && in && k < rl_integrator_nops(in); k++)
    if (rl_integrator_op(in, k)->type == T) return rl_integrator_op(in, k);
  return NULL;
}

/* Worst deviation from rigidity: max |A A^T - I| (matrix bodies), ||rho| - 1| (axis bodies). */
double scene_rigidity_error(const rl_system *s)
{
  double worst = 0.0;
  for (int i = 0; i < rl_system_count(s); i++) {
    rl_kind k = rl_system_species_kind(s, rl_system_species_of(s, i));
    if (k == RL_KIND_POINT) continue;
    if (k == RL_KIND_DIPOLE || k == RL_KIND_LINEAR) {
      double r[3];
      rl_system_get_axis(s, i, r);
      worst = fmax(worst, fabs(sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) - 1.0));
      continue;
    }
    double A[9];
    rl_system_get_orientation(s, i, A);
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++)
        worst = fmax(worst, fabs(A[3 * a] * A[3 * b] + A[3 * a + 1] * A[3 * b + 1] + A[3 * a + 2] * A[3 * b + 2] -
                                 (a == b)));
  }
  return worst;
}

int scene_check_finite(const rl_deck *d, const rl_terms *t, const double *comp, const double *virial, double pressure)
{
  char disp[96];
  snprintf(disp, sizeof disp, "interactions.dispersion_correction at interactions.cutoff = %g", d->ff.cutoff);
  /* what produces each component the pair term reports, for the message */
  static const struct { const char *component, *name, *from; } known[] = {
      {"lj", "Lennard-Jones energy", "the model's LJ sites, interactions.lj"},
      {"coulomb", "Coulomb energy", "the model's charges, interactions.eps_rf"},
      {"dipolar", "dipolar energy", "the model's dipoles"},
      {"quadrupolar", "quadrupolar energy", "the model's quadrupoles"},
      {"dispersion", "dispersion correction", NULL}};
  double total = 0.0;
  for (int j = 0; j < rl_terms_nenergies(t); j++) {
    const char *c = rl_terms_energy_name(t, j);
    const double x = comp[j];
    total += x;
    if (isfinite(x)) continue;
    for (size_t k = 0; k < sizeof known / sizeof known[0]; k++)
      if (!strcmp(c, known[k].component))
        return rl_error(RL_ENONFINITE, "the %s is %g, not finite (%s)", known[k].name, x, known[k].from ? known[k].from : disp);
    return rl_error(RL_ENONFINITE, "the %s energy of the %s term is %g, not finite", c,
                    rl_terms_type(t, rl_terms_energy_term(t, j))->name, x);
  }
  if (!isfinite(total)) return rl_error(RL_ENONFINITE, "the total energy is %g, not finite (the sum of the terms)", total);
  if (!isfinite(pressure)) return rl_error(RL_ENONFINITE, "the pressure is %g, not finite (the virial)", pressure);
  for (int k = 0; virial && k < 9; k++)
    if (!isfinite(virial[k]))
      return rl_error(RL_ENONFINITE, "virial element %d%d is %g: not finite", k / 3 + 1, k % 3 + 1, virial[k]);
  return RL_OK;
}

double scene_pressure_out(const rl_deck *d, double p)
{
  return d->units == RL_UNITS_REAL ? p * 16.605390671738467 : p; /* kJ/mol/nm^3 -> bar: 1e3/N_A/1e-27/1e5 */
}

int scene_onstep(const rl_deck *d, scene *s)
{
  if (!s->restart) return RL_OK;
  rl_integrator_params p;
  scene_integrator_params(d, SCENE_ONSTEP, &p);
  rl_integrator *in = rl_integrator_alloc(s->sys, &p, rl_terms_provider(s->terms));
  int st = in ? rl_integrator_resume(in, s->step0, s->t0) : RL_EINVAL;
  if (!st) st = rl_integrator_finish(in);
  rl_integrator_free(in);
  return st;
}
