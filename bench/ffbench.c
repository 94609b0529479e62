/* bench/ffbench: the cost of a whole MD step with the force field (issue 8).
 *
 *   ffbench time MODEL N THREADS STEPS [auto|general] [--dump FILE] [--nve STEPS2] [--langevin]
 *                [--energy-every E]
 *       MODEL tip4p: TIP4P, 298 K, 1 g/cm3, RF eps_rf 78.3, site cutoff 0.9 nm, plain LJ, h 2 fs.
 *       MODEL stockmayer: rho* 0.8, T* 1.35, mu*^2 3, I* 0.025, cutoff 2.5, plain LJ and plain
 *       dipole truncation (RF with eps_rf = 1; LAMMPS lj/cut/dipole/cut), h = 0.002.
 *       Builds a lattice with random orientations, relaxes it (Bussi), then times STEPS steps and
 *       prints one line of key=value: ms per step, the force field's share of the step (the
 *       provider is wrapped and timed), memory per molecule (resident set growth / N), pairs.
 *       --dump FILE writes the relaxed state for the OpenMM / LAMMPS drivers (bench/openmm_tip4p.py, bench/lammps_stockmayer.py);
 *       --nve S2 then runs S2 NVE steps and reports the energy drift and fluctuation.
 *       --energy-every E: the potential energy and virial every E steps only (the integrator's
 *       energy_every; the other steps compute forces only, as OpenMM's step() and LAMMPS
 *       between thermo steps do); U_per_molecule is computed again after the timed steps.
 *       --mixed: the force field in mixed precision (rl_ff_params.precision).
 *       --skin auto: the Verlet skin `rotleap run` takes at the step --h (rl_ff_skin_for_step);
 *       --skin S: S (nm or sigma); default the force field's, 0.1 rc.
 *       --pme TOL (MODEL tip4p-ew, TIP4P-Ew at 1 g/cm3): charges by smooth PME at OpenMM's
 *       ewaldErrorTolerance TOL (alpha and grid as OpenMM chooses them, order 5; MODEL stockmayer:
 *       the dipolar PME, alpha and grid from rotleap's dipolar estimates, dip_err_*): the real space
 *       in the pair term's rows, LJ + erfc in one pass (rl_ff_params.coulomb), the term "pme" for
 *       the mesh; recip_share = its share of the step.  --real-term: the real space by the term
 *       "ewald-real" instead, the pair term without charges (what rotleap ran before the rows
 *       had it); its time counts as the force field's, not recip_share.
 *   ffbench scaling MODEL THREADS [NMAX]
 *       Cost per step against N (256 .. NMAX = 65536, x2 each), auto and general kernels side by
 *       side (every size set up first, then 5 rounds visiting each in turn; best round kept),
 *       the log-log slope of the auto kernel, memory per molecule.
 *       Writes bench/scaling_MODEL.csv (or $ROTLEAP_BENCH_CSV).
 *   ffbench kernel MODEL N THREADS [ROUNDS] [--ab ENV=VALUE|mixed]
 *       The force field alone, called repeatedly on one relaxed configuration (no list rebuilds),
 *       the fastest round's ms per call.  --ab: a second copy with an environment variable set
 *       (ROTLEAP_NO_AVX512=1), or with --ab mixed in mixed precision, rounds alternating, and the
 *       median ratio of the two.
 * Read ratios: the machine is shared. */
#include <rotleap/catalog.h>
#include <rotleap/ewald.h>
#include <rotleap/forcefield.h>
#include <rotleap/rotleap.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static double now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

static double rss_bytes(void)
{
  long pages = 0, res = 0;
  FILE *f = fopen("/proc/self/statm", "r");
  if (!f) return 0.0;
  if (fscanf(f, "%ld %ld", &pages, &res) != 2) res = 0;
  fclose(f);
  return (double)res * (double)sysconf(_SC_PAGESIZE);
}

/* The force field wrapped: time spent in it (t), and with --pme in the Ewald terms: the real
 * space's term if it is one (rterms, counted in t) and the mesh (recip, trecip). */
typedef struct {
  rl_forcefield *ff;
  rl_terms *rterms, *recip;
  double t, trecip, recip_share;
} timed_ff;

static int timed_compute(void *ctx, const rl_system *sys, rl_forces *out)
{
  timed_ff *w = ctx;
  double t0 = now();
  int st = rl_forcefield_compute(w->ff, sys, out);
  if (!st && w->rterms) st = rl_terms_compute(w->rterms, sys, out);
  const double t1 = now();
  w->t += t1 - t0;
  if (!st && w->recip) {
    st = rl_terms_compute(w->recip, sys, out);
    w->trecip += now() - t1;
  }
  return st;
}

typedef struct {
  int tip4p;
  rl_system *sys;
  rl_forcefield *ff;
  rl_integrator *in;
  timed_ff w;
  rl_molecule m;
  double L, h, T0;
  double mem_per_molecule;
} bench_sys;

/* the force fields' precision (--mixed) */
static rl_precision bench_precision = RL_PRECISION_DOUBLE;
/* --pme TOL (0: reaction field) and --real-term */
static double bench_pme = 0.0;
static int bench_real_term = 0;
static rl_ewald_info bench_ewald;

static void die(const char *what)
{
  fprintf(stderr, "ffbench: %s: %s\n", what, rl_last_error());
  exit(1);
}

/* skin < 0: the force field's default (0.1 rc) */
static void setup_skin(bench_sys *b, const char *model, int n, int threads,
                       rl_kernel_choice kernel, double skin)
{
  memset(b, 0, sizeof *b);
  b->tip4p = strcmp(model, "tip4p") == 0 || strcmp(model, "tip4p-ew") == 0;
  if (!b->tip4p && strcmp(model, "stockmayer") != 0) { fprintf(stderr, "ffbench: model tip4p|tip4p-ew|stockmayer\n"); exit(2); }
  if ((bench_pme > 0.0 && strcmp(model, "stockmayer") != 0) != (strcmp(model, "tip4p-ew") == 0)) { fprintf(stderr, "ffbench: --pme TOL with model tip4p-ew or stockmayer, and only there\n"); exit(2); }
  double rss0 = rss_bytes();
  const rl_model *md = rl_catalog_find(model);
  if (!md || rl_model_build(md, NULL, 0, &b->m)) die("model");
  rl_species_desc d;
  rl_molecule_species(&b->m, &d);
  b->sys = rl_system_alloc(md->units);
  if (rl_system_add_species(b->sys, &d, n, NULL)) die("species");
  double rho = b->tip4p ? 1.0e-21 / (b->m.mass * 1.66053906660e-24) /* per nm3 at 1 g/cm3 */ : 0.8;
  b->L = cbrt(n / rho);
  b->T0 = b->tip4p ? 298.0 : 1.35;
  b->h = b->tip4p ? 0.002 : 0.002;
  double kT = b->T0 * rl_units_kB(md->units);
  int side = (int)ceil(cbrt((double)n) - 1e-9);
  double a = b->L / side;
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, 2026);
  for (int i = 0; i < n; i++) {
    double x[3] = {a * (i % side + 0.5), a * ((i / side) % side + 0.5), a * (i / (side * side) + 0.5)};
    double q[4], nq = 0.0, A[9], v[3], l[3];
    for (int k = 0; k < 4; k++) { q[k] = gsl_ran_gaussian(r, 1); nq += q[k] * q[k]; }
    for (int k = 0; k < 4; k++) q[k] /= sqrt(nq);
    rl_quat_to_matrix(q, A);
    for (int c = 0; c < 3; c++) {
      v[c] = gsl_ran_gaussian(r, sqrt(kT / b->m.mass));
      l[c] = gsl_ran_gaussian(r, sqrt(kT * b->m.inertia[1]));
    }
    rl_system_set_position(b->sys, i, x);
    rl_system_set_velocity(b->sys, i, v);
    if (b->m.kind == RL_KIND_DIPOLE) {
      double rho3[3] = {A[6], A[7], A[8]}, dd = l[0] * A[6] + l[1] * A[7] + l[2] * A[8];
      for (int c = 0; c < 3; c++) l[c] -= dd * A[6 + c];
      rl_system_set_axis(b->sys, i, rho3);
    } else {
      rl_system_set_orientation(b->sys, i, A);
    }
    rl_system_set_angmom(b->sys, i, l);
  }
  gsl_rng_free(r);
  const double box[3] = {b->L, b->L, b->L};
  if (rl_system_set_box(b->sys, box)) die("box");
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.kernel = kernel;
  p.threads = threads;
  p.skin = skin;
  p.precision = bench_precision;
  if (b->tip4p) {
    p.cutoff = 0.9;
    p.eps_rf = 78.3;
    p.coulomb_constant = 138.93545764438198; /* OpenMM 7.7's */
  } else {
    p.cutoff = 2.5;
    p.eps_rf = 1.0; /* plain truncation of the dipole terms, as lj/cut/dipole/cut */
  }
  rl_species_ff sf = rl_molecule_ff(&b->m);
  static rl_species_ff sf_ew; /* the Ewald terms keep a pointer */
  double no_charge[RL_MOLECULE_MAX_SITES] = {0};
  rl_species_ff sf_pair = sf;
  if (bench_pme > 0.0) {
    sf_ew = sf;
    rl_ewald_params ep;
    rl_ewald_params_default(&ep);
    ep.species = &sf_ew;
    ep.nspecies = 1;
    ep.cutoff = p.cutoff;
    ep.tolerance = bench_pme;
    ep.coulomb_constant = p.coulomb_constant;
    ep.threads = threads;
    ep.remove_net_force = 1; /* as rotleap run */
    if (rl_ewald_resolve(b->sys, &ep, RL_EWALD_PME, &bench_ewald)) die("ewald");
    b->w.recip = rl_terms_alloc(b->sys);
    if (!b->w.recip || rl_terms_add(b->w.recip, &rl_term_pme, &ep, NULL)) die("pme");
    if (bench_real_term) {
      sf_pair.charge = no_charge;
      sf_pair.dipole = NULL;
      b->w.rterms = rl_terms_alloc(b->sys);
      if (!b->w.rterms || rl_terms_add(b->w.rterms, &rl_term_ewald_real, &ep, NULL)) die("ewald-real");
    } else {
      p.coulomb = RL_COULOMB_EWALD_REAL;
      p.ewald_alpha = bench_ewald.alpha;
    }
  }
  b->ff = rl_forcefield_alloc(b->sys, &p, &sf_pair, 1);
  if (!b->ff) die("forcefield");
  b->w.ff = b->ff;
  rl_integrator_params ip;
  rl_integrator_params_default(&ip);
  ip.h = b->tip4p ? 0.0005 : 0.0005; /* relaxation from the lattice at a short step */
  ip.thermostat = RL_THERMO_BUSSI;
  ip.T0 = b->T0;
  ip.tau = 20 * ip.h;
  ip.seed = 7;
  b->in = rl_integrator_alloc(b->sys, &ip, (rl_force_provider){timed_compute, &b->w});
  if (!b->in || rl_integrator_init(b->in)) die("integrator");
  b->mem_per_molecule = (rss_bytes() - rss0) / n;
}

static void setup(bench_sys *b, const char *model, int n, int threads, rl_kernel_choice kernel)
{
  setup_skin(b, model, n, threads, kernel, -1.0);
}

/* The skin `rotleap run` takes at the production step h (rl_ff_skin_for_step). */
static double run_skin(const char *model, double h)
{
  const rl_model *md = rl_catalog_find(model);
  rl_molecule m;
  if (!md || rl_model_build(md, NULL, 0, &m)) die("model");
  const int tip4p = strcmp(model, "tip4p") == 0;
  return rl_ff_skin_for_step(tip4p ? 0.9 : 2.5, (tip4p ? 298.0 : 1.35) * rl_units_kB(md->units), m.mass, h);
}

/* Continue at the production step (NVE, Bussi, or Langevin if langevin) from the relaxed state. */
static void restart_every(bench_sys *b, int nve, int langevin, long energy_every)
{
  rl_integrator_free(b->in);
  rl_integrator_params ip;
  rl_integrator_params_default(&ip);
  ip.h = b->h;
  ip.energy_every = energy_every;
  ip.threads = rl_forcefield_threads(b->ff); /* the rotation solves on the pair loop's threads */
  if (!nve) {
    ip.thermostat = langevin ? RL_THERMO_LANGEVIN : RL_THERMO_BUSSI;
    ip.T0 = b->T0;
    ip.tau = 50 * ip.h;
    ip.seed = 8;
  }
  b->in = rl_integrator_alloc(b->sys, &ip, (rl_force_provider){timed_compute, &b->w});
  if (!b->in || rl_integrator_init(b->in)) die("integrator");
}

static void restart(bench_sys *b, int nve, int langevin) { restart_every(b, nve, langevin, 1); }

static void run(bench_sys *b, int steps, rl_step_info *last)
{
  rl_step_info info;
  for (int s = 0; s < steps; s++)
    if (rl_integrator_step(b->in, &info)) die("step");
  if (last) *last = info;
}

static void teardown(bench_sys *b)
{
  rl_integrator_free(b->in);
  rl_forcefield_free(b->ff);
  rl_terms_free(b->w.rterms);
  rl_terms_free(b->w.recip);
  rl_system_free(b->sys);
}

/* Timed steps: returns seconds per step, *share = force field time / step time. */
static double timed(bench_sys *b, int steps, double *share)
{
  b->w.t = b->w.trecip = 0.0;
  double t0 = now();
  run(b, steps, NULL);
  double t = now() - t0;
  if (share) *share = b->w.t / t;
  b->w.recip_share = b->w.trecip / t;
  return t / steps;
}

static void dump(bench_sys *b, const char *path)
{
  FILE *f = fopen(path, "w");
  if (!f) { perror(path); exit(1); }
  int n = rl_system_count(b->sys), ns = rl_system_nsites(b->sys);
  double(*s)[3] = malloc(sizeof *s * (size_t)ns);
  rl_system_site_positions(b->sys, s);
  fprintf(f, "%s %d %d %.17g\n", b->tip4p ? b->m.name : "stockmayer", n, ns / n, b->L);
  for (int i = 0; i < n; i++) {
    double r[3], v[3], l[3], ax[3];
    rl_system_get_position(b->sys, i, r);
    rl_system_get_velocity(b->sys, i, v);
    rl_system_get_angmom(b->sys, i, l);
    rl_system_get_axis(b->sys, i, ax);
    fprintf(f, "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g", r[0], r[1],
            r[2], v[0], v[1], v[2], l[0] / b->m.inertia[0], l[1] / b->m.inertia[0],
            l[2] / b->m.inertia[0], ax[0], ax[1], ax[2]);
    for (int a = 0; a < ns / n; a++)
      fprintf(f, " %.17g %.17g %.17g", s[i * (ns / n) + a][0], s[i * (ns / n) + a][1], s[i * (ns / n) + a][2]);
    fprintf(f, "\n");
  }
  free(s);
  fclose(f);
}

static int cmd_time(int argc, char **argv)
{
  if (argc < 6) { fprintf(stderr, "usage: ffbench time MODEL N THREADS STEPS [auto|general] [--dump FILE] [--nve S] [--langevin] [--energy-every E] [--h STEP] [--relax K] [--mixed] [--skin auto|S]\n"); return 2; }
  const char *model = argv[2];
  int n = atoi(argv[3]), threads = atoi(argv[4]), steps = atoi(argv[5]), nve = 0, langevin = 0;
  long energy_every = 1;
  double h = 0.002; /* ps for tip4p, reduced for stockmayer */
  int relax = n >= 16384 ? 20 : 200; /* relaxation steps from the lattice (20: enough for timing 2 fs) */
  rl_kernel_choice kernel = RL_KERNEL_AUTO;
  const char *dumpfile = NULL, *skin_arg = NULL;
  for (int k = 6; k < argc; k++) {
    if (!strcmp(argv[k], "general")) kernel = RL_KERNEL_GENERAL;
    else if (!strcmp(argv[k], "auto")) kernel = RL_KERNEL_AUTO;
    else if (!strcmp(argv[k], "--dump") && k + 1 < argc) dumpfile = argv[++k];
    else if (!strcmp(argv[k], "--nve") && k + 1 < argc) nve = atoi(argv[++k]);
    else if (!strcmp(argv[k], "--langevin")) langevin = 1; /* the timed steps under Langevin, not Bussi */
    else if (!strcmp(argv[k], "--energy-every") && k + 1 < argc) energy_every = atol(argv[++k]);
    else if (!strcmp(argv[k], "--h") && k + 1 < argc) h = atof(argv[++k]); /* the production step */
    else if (!strcmp(argv[k], "--relax") && k + 1 < argc) relax = atoi(argv[++k]); /* steps of 0.5 fs */
    else if (!strcmp(argv[k], "--mixed")) bench_precision = RL_PRECISION_MIXED;
    else if (!strcmp(argv[k], "--skin") && k + 1 < argc) skin_arg = argv[++k]; /* auto or nm */
    else if (!strcmp(argv[k], "--pme") && k + 1 < argc) bench_pme = atof(argv[++k]);
    else if (!strcmp(argv[k], "--real-term")) bench_real_term = 1;
    else { fprintf(stderr, "ffbench time: unknown argument %s\n", argv[k]); return 2; }
  }
  if (!(h > 0.0 && h < 1.0)) {
    fprintf(stderr, "ffbench time: --h must be a time step in the model's unit (ps for tip4p), 0 < h < 1\n");
    return 2;
  }
  if (energy_every < 1 || (nve > 0 && energy_every != 1)) {
    fprintf(stderr, "ffbench time: --energy-every must be >= 1, and 1 with --nve (its energies)\n");
    return 2;
  }
  double skin = -1.0; /* the force field's default, 0.1 rc */
  if (skin_arg) {
    skin = !strcmp(skin_arg, "auto") ? run_skin(model, h) : atof(skin_arg);
    if (!(skin >= 0.0)) { fprintf(stderr, "ffbench time: --skin auto or a skin >= 0\n"); return 2; }
  }
  bench_sys b;
  setup_skin(&b, model, n, threads, kernel, skin);
  if (relax < 0) { fprintf(stderr, "ffbench time: --relax must be >= 0\n"); return 2; }
  run(&b, relax, NULL);
  b.h = h;
  restart_every(&b, nve > 0, langevin, energy_every);
  run(&b, 5, NULL); /* warm-up at the production step */
  double share, t = timed(&b, steps, &share);
  rl_ff_energies e;
  { /* the energy at the end, computed again (the last step's may have been forces only) */
    rl_forces F = {calloc((size_t)n, sizeof(double[3])), calloc((size_t)n, sizeof(double[3])), 0.0, {0}, 0};
    if (rl_forcefield_compute(b.ff, b.sys, &F)) die("compute");
    rl_forcefield_energies(b.ff, &e);
    free(F.f);
    free(F.k);
  }
  printf("model=%s N=%d threads=%d kernel=%s rows=%s precision=%s thermostat=%s h=%g skin=%g energy_every=%ld ms_per_step=%.4f ff_share=%.4f integrator_share=%.4f "
         "mem_per_molecule=%.0f rebuilds=%ld U_per_molecule=%.6f\n",
         model, n, rl_forcefield_threads(b.ff), rl_forcefield_kernel(b.ff), rl_forcefield_rows(b.ff),
         rl_forcefield_precision(b.ff),
         nve > 0 ? "none" : langevin ? "Langevin" : "Bussi", b.h, skin >= 0.0 ? skin : 0.1 * (b.tip4p ? 0.9 : 2.5), energy_every, 1e3 * t, share,
         1.0 - share - b.w.recip_share, b.mem_per_molecule, rl_forcefield_rebuilds(b.ff), e.total / n);
  if (bench_pme > 0.0)
    printf("pme_tolerance=%g alpha=%.6f grid=%dx%dx%d order=%d real_space=%s recip_share=%.4f\n", bench_pme,
           bench_ewald.alpha, bench_ewald.grid[0], bench_ewald.grid[1], bench_ewald.grid[2], bench_ewald.order,
           bench_real_term ? "term" : "rows", b.w.recip_share);
  if (bench_pme > 0.0 && bench_ewald.nsites_dipolar > 0)
    printf("dip_err_total=%.4g dip_err_real=%.4g dip_err_recip=%.4g\n", bench_ewald.dip_err_total,
           bench_ewald.dip_err_real, bench_ewald.dip_err_recip);
  if (dumpfile) {
    /* the energy of exactly the dumped configuration */
    rl_forces F = {calloc((size_t)n, sizeof(double[3])), calloc((size_t)n, sizeof(double[3])), 0.0, {0}, 0};
    if (rl_forcefield_compute(b.ff, b.sys, &F)) die("compute");
    rl_forcefield_energies(b.ff, &e);
    printf("dump=%s U=%.15g U_lj=%.15g U_coulomb=%.15g U_dipolar=%.15g\n", dumpfile, e.total, e.lj,
           e.coulomb, e.dipolar);
    free(F.f);
    free(F.k);
    dump(&b, dumpfile);
  }
  if (nve > 0) {
    rl_step_info info;
    double e0 = 0.0, emin = INFINITY, emax = -INFINITY, s1 = 0.0, s2 = 0.0;
    for (int s = 0; s < nve; s++) {
      if (rl_integrator_step(b.in, &info)) die("step");
      if (s == 0) e0 = info.total;
      emin = fmin(emin, info.total);
      emax = fmax(emax, info.total);
      s1 += info.total;
      s2 += info.total * info.total;
    }
    double mean = s1 / nve, sd = sqrt(fmax(0.0, s2 / nve - mean * mean));
    printf("nve_steps=%d dt=%g drift_per_molecule=%.6e sd_per_molecule=%.6e range_per_molecule=%.6e\n",
           nve, b.h, (info.total - e0) / n, sd / n, (emax - emin) / n);
  }
  teardown(&b);
  return 0;
}

static int cmd_scaling(int argc, char **argv)
{
  if (argc < 4) { fprintf(stderr, "usage: ffbench scaling MODEL THREADS [NMAX]\n"); return 2; }
  const char *model = argv[2];
  int threads = atoi(argv[3]), nmax = argc > 4 ? atoi(argv[4]) : 65536;
  char csvname[256];
  snprintf(csvname, sizeof csvname, "bench/scaling_%s.csv", model);
  const char *cn = getenv("ROTLEAP_BENCH_CSV") ? getenv("ROTLEAP_BENCH_CSV") : csvname;
  char part[300];
  snprintf(part, sizeof part, "%s.part", cn); /* renamed to cn when whole */
  FILE *csv = fopen(part, "w");
  if (csv) fprintf(csv, "model,N,threads,auto_us_per_molecule_step,general_us_per_molecule_step,speedup,ff_share,mem_per_molecule,rows\n");
  printf("%s, %d thread(s): cost per molecule-step against N (best of 5 rounds, the sizes and the two paths\n"
         "alternating within each round)\n\n", model, threads);
  printf("%8s %14s %14s %8s %9s %12s %s\n", "N", "auto us", "general us", "speedup", "ff share", "bytes/mol", "rows");
  /* Every size is set up first and the rounds then visit the sizes in turn, so a slow phase of
     this shared host (they last seconds to minutes) lands on every N alike instead of on the
     sizes timed while it lasted; the best round of each size is kept. */
  enum { NS_MAX = 16, ROUNDS = 5 };
  bench_sys a[NS_MAX], g[NS_MAX];
  int ns = 0, nn[NS_MAX], steps[NS_MAX], general[NS_MAX];
  double mem[NS_MAX], ta[NS_MAX], tg[NS_MAX], share[NS_MAX];
  for (int n = 256; n <= nmax && ns < NS_MAX; n *= 2, ns++) {
    nn[ns] = n;
    setup(&a[ns], model, n, threads, RL_KERNEL_AUTO);
    mem[ns] = a[ns].mem_per_molecule;
    int relax = n >= 16384 ? 10 : 50;
    run(&a[ns], relax, NULL);
    restart(&a[ns], 0, 0);
    general[ns] = n <= 16384; /* the reference path is slow: up to 16384 */
    if (general[ns]) {
      setup(&g[ns], model, n, 1, RL_KERNEL_GENERAL);
      run(&g[ns], relax, NULL);
      restart(&g[ns], 0, 0);
    }
    /* at least 30 timed steps: several periods of the list rebuilds (every 7-11 steps at these
       states), so that a window does not hold none or one by chance; 3 steps at 65,536 did */
    steps[ns] = (int)fmax(30.0, 200000.0 / n);
    ta[ns] = tg[ns] = INFINITY;
    share[ns] = 0.0;
  }
  for (int round = 0; round < ROUNDS; round++)
    for (int k = 0; k < ns; k++) {
      double sh, t = timed(&a[k], steps[k], &sh);
      if (t < ta[k]) { ta[k] = t; share[k] = sh; }
      if (general[k]) tg[k] = fmin(tg[k], timed(&g[k], (steps[k] + 3) / 4, NULL));
    }
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int m = 0;
  for (int k = 0; k < ns; k++) {
    int n = nn[k];
    double ua = 1e6 * ta[k] / n, ug = general[k] ? 1e6 * tg[k] / n : NAN;
    const char *rows = rl_forcefield_rows(a[k].ff);
    printf("%8d %14.3f %14.3f %8.2f %9.3f %12.0f %s\n", n, ua, ug, ug / ua, share[k], mem[k], rows);
    if (csv) fprintf(csv, "%s,%d,%d,%.4f,%.4f,%.3f,%.4f,%.0f,%s\n", model, n, threads, ua, ug, ug / ua, share[k], mem[k], rows);
    double x = log((double)n), y = log(ta[k]);
    sx += x; sy += y; sxx += x * x; sxy += x * y; m++;
    teardown(&a[k]);
    if (general[k]) teardown(&g[k]);
  }
  double slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
  printf("\nlog-log slope of time per step against N (auto kernels): %.3f (target <= 1.05: %s)\n", slope,
         slope <= 1.05 ? "met" : "MISSED");
  if (csv) {
    fprintf(csv, "# slope,%.4f\n", slope);
    if (fclose(csv) || rename(part, cn)) fprintf(stderr, "ffbench: cannot write %s: %s\n", cn, strerror(errno));
    else printf("written: %s\n", cn);
  }
  return 0;
}

/* The Verlet skin: time per step and rebuilds per 100 steps for skins of 0.025-0.25 rc, all
 * systems relaxed from the same lattice and seeds, timed alternately, best of 3 rounds. */
static int cmd_skin(int argc, char **argv)
{
  if (argc < 5) { fprintf(stderr, "usage: ffbench skin MODEL N THREADS\n"); return 2; }
  const char *model = argv[2];
  int n = atoi(argv[3]), threads = atoi(argv[4]);
  static const double frac[] = {0.025, 0.05, 0.1, 0.15, 0.25};
  enum { NS = sizeof frac / sizeof frac[0] };
  bench_sys b[NS];
  double best[NS], rebuilds[NS];
  int steps = (int)fmax(100.0, 400000.0 / n); /* several list lifetimes per round */
  const double rc = strcmp(model, "tip4p") == 0 ? 0.9 : 2.5; /* setup_skin's cutoffs */
  for (int k = 0; k < NS; k++) {
    setup_skin(&b[k], model, n, threads, RL_KERNEL_AUTO, frac[k] * rc);
    run(&b[k], n >= 16384 ? 20 : 200, NULL);
    restart(&b[k], 0, 0);
    run(&b[k], 5, NULL);
    best[k] = INFINITY;
  }
  for (int round = 0; round < 3; round++)
    for (int k = 0; k < NS; k++) {
      long r0 = rl_forcefield_rebuilds(b[k].ff);
      best[k] = fmin(best[k], timed(&b[k], steps, NULL));
      rebuilds[k] = 100.0 * (double)(rl_forcefield_rebuilds(b[k].ff) - r0) / steps; /* last round */
    }
  char csvname[256];
  snprintf(csvname, sizeof csvname, "bench/skin_%s.csv", model);
  const char *cn = getenv("ROTLEAP_BENCH_CSV") ? getenv("ROTLEAP_BENCH_CSV") : csvname;
  char part[300];
  snprintf(part, sizeof part, "%s.part", cn); /* renamed to cn when whole */
  FILE *csv = fopen(part, "w");
  if (csv) fprintf(csv, "model,N,threads,skin_over_rc,skin,ms_per_step,ratio_to_default,rebuilds_per_100_steps\n");
  printf("%s, N = %d, %d thread(s): Verlet skin (best of 3 alternating rounds of %d steps)\n\n",
         model, n, threads, steps);
  printf("%10s %10s %12s %16s %14s\n", "skin/rc", "skin", "ms/step", "vs 0.1 rc", "rebuilds/100");
  for (int k = 0; k < NS; k++) {
    double ratio = best[k] / best[2];
    printf("%10.3f %10.4f %12.3f %16.3f %14.1f\n", frac[k], frac[k] * rc, 1e3 * best[k], ratio,
           rebuilds[k]);
    if (csv)
      fprintf(csv, "%s,%d,%d,%.3f,%.5f,%.4f,%.4f,%.1f\n", model, n, threads, frac[k], frac[k] * rc,
              1e3 * best[k], ratio, rebuilds[k]);
    teardown(&b[k]);
  }
  if (csv) {
    if (fclose(csv) || rename(part, cn)) fprintf(stderr, "ffbench: cannot write %s: %s\n", cn, strerror(errno));
    else printf("written: %s\n", cn);
  }
  return 0;
}

/* The force field alone on one relaxed configuration, for A/B tests of kernel changes: the same
 * work each call.  With --ab ENV=VALUE a second copy of the system is set up with that variable
 * set (ROTLEAP_NO_AVX512=1: the dipole rows' portable fill and scatter), and the rounds alternate
 * between the two in this one process, so both see the same share of time stolen by the host. */
static int cmd_kernel(int argc, char **argv)
{
  if (argc < 5) { fprintf(stderr, "usage: ffbench kernel MODEL N THREADS [ROUNDS] [--ab ENV=VALUE|mixed]\n"); return 2; }
  const char *model = argv[2], *ab = NULL;
  int n = atoi(argv[3]), threads = atoi(argv[4]), rounds = 40;
  for (int k = 5; k < argc; k++) {
    if (!strcmp(argv[k], "--ab") && k + 1 < argc) ab = argv[++k];
    else rounds = atoi(argv[k]);
  }
  if (rounds < 1) rounds = 1;
  const int nb = ab ? 2 : 1;
  bench_sys b[2];
  for (int v = 0; v < nb; v++) {
    char env[256] = "";
    if (v == 1 && !strcmp(ab, "mixed")) {
      bench_precision = RL_PRECISION_MIXED;
    } else if (v == 1) {
      snprintf(env, sizeof env, "%s", ab);
      char *eq = strchr(env, '=');
      if (!eq) { fprintf(stderr, "ffbench: --ab ENV=VALUE\n"); return 2; }
      *eq = '\0';
      setenv(env, eq + 1, 1);
    }
    setup(&b[v], model, n, threads, RL_KERNEL_AUTO);
    run(&b[v], n >= 16384 ? 20 : 200, NULL);
    if (v == 1 && env[0]) unsetenv(env);
    bench_precision = RL_PRECISION_DOUBLE;
  }
  rl_forces F = {calloc((size_t)n, sizeof(double[3])), calloc((size_t)n, sizeof(double[3])), 0.0, {0}, 0};
  double *t = malloc(sizeof *t * (size_t)rounds * 2);
  if (!F.f || !F.k || !t) die("memory");
  const int per = (int)fmax(1.0, 20000.0 / n); /* calls per round: ~10 ms or more */
  for (int r = 0; r < rounds; r++)
    for (int v = 0; v < nb; v++) {
      double t0 = now();
      for (int c = 0; c < per; c++)
        if (rl_forcefield_compute(b[v].ff, b[v].sys, &F)) die("compute");
      t[2 * r + v] = (now() - t0) / per;
    }
  for (int v = 0; v < nb; v++) {
    double best = INFINITY;
    for (int r = 0; r < rounds; r++) best = fmin(best, t[2 * r + v]);
    rl_ff_energies e;
    rl_forcefield_energies(b[v].ff, &e);
    printf("model=%s N=%d threads=%d kernel=%s rows=%s%s%s ms_per_compute_min=%.4f rounds=%d "
           "calls_per_round=%d U_per_molecule=%.9f\n",
           model, n, rl_forcefield_threads(b[v].ff), rl_forcefield_kernel(b[v].ff),
           rl_forcefield_rows(b[v].ff), v ? " ab=" : "",
           v ? ab : "", 1e3 * best, rounds, per, e.total / n);
  }
  if (nb == 2) { /* the median of the per-round ratios: robust to slow phases of the host */
    double *q = malloc(sizeof *q * (size_t)rounds);
    if (!q) die("memory");
    for (int r = 0; r < rounds; r++) q[r] = t[2 * r] / t[2 * r + 1];
    for (int a = 1; a < rounds; a++)
      for (int c = a; c > 0 && q[c - 1] > q[c]; c--) { double x = q[c]; q[c] = q[c - 1]; q[c - 1] = x; }
    printf("ratio default/env: median %.4f (quartiles %.4f %.4f) over %d rounds\n", q[rounds / 2],
           q[rounds / 4], q[(3 * rounds) / 4], rounds);
    free(q);
  }
  free(t);
  free(F.f);
  free(F.k);
  for (int v = 0; v < nb; v++) teardown(&b[v]);
  return 0;
}

int main(int argc, char **argv)
{
  if (argc > 1 && !strcmp(argv[1], "time")) return cmd_time(argc, argv);
  if (argc > 1 && !strcmp(argv[1], "scaling")) return cmd_scaling(argc, argv);
  if (argc > 1 && !strcmp(argv[1], "skin")) return cmd_skin(argc, argv);
  if (argc > 1 && !strcmp(argv[1], "kernel")) return cmd_kernel(argc, argv);
  fprintf(stderr, "usage: ffbench time MODEL N THREADS STEPS [auto|general] [--dump FILE] [--nve S] [--langevin]\n"
                  "       ffbench scaling MODEL THREADS [NMAX]\n"
                  "       ffbench skin MODEL N THREADS\n"
                  "       ffbench kernel MODEL N THREADS [ROUNDS] [--ab ENV=VALUE|mixed]\n");
  return 2;
}
