/* bench/barostat_cost: the barostats' share of a step (issue 34, acceptance 5: <= 5 % at N >= 2048).
 *
 *   barostat_cost [N=2048] [STEPS=400] [ROUNDS=5] [ENERGY_EVERY=1] [MC_INTERVAL=25] [CR_INTERVAL=10]
 *
 * A Stockmayer fluid (rho* 0.8, T* 1.35, mu* 1.5, cutoff 2.5, shifted-force LJ and dipole, h
 * 0.004, Bussi tau 0.5, one thread) is relaxed once (NVT), its mean pressure P taken, and that
 * state cloned for three integrators: NVT, NVT + the Monte Carlo barostat (isotropic, every
 * MC_INTERVAL steps: OpenMM's default 25) and NVT + C-rescale (isotropic, every CR_INTERVAL
 * steps: GROMACS's default 10, kappa 0.05, tau_p 1), both at P0 = P so that the volume stays
 * near the NVT one (the pair loop's cost follows the density).  Each round times STEPS steps of
 * each, in turn (alternated, as bench/ab_time.sh: the host is shared); the median over rounds of
 * the barostat run's time per step over the NVT one's is the barostat's cost, printed with the
 * MC acceptance, the volume's change and the pair list's builds.  Wall-clock and CPU time (of
 * the process: one thread) are both timed; on a host loaded by other programs the CPU time is
 * the steadier.  Each round continues the three runs. */
#include <rotleap/catalog.h>
#include <rotleap/forcefield.h>
#include <rotleap/rotleap.h>
#include <rotleap/stepops.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define RC 2.5
#define TEMP 1.35
#define HSTEP 0.004

static double clock_of(clockid_t id)
{
  struct timespec t;
  clock_gettime(id, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void die(const char *what)
{
  fprintf(stderr, "barostat_cost: %s: %s\n", what, rl_last_error());
  exit(1);
}

typedef struct {
  rl_system *sys;
  rl_terms *terms;
  rl_integrator *in;
  double t[64], cpu[64]; /* ms per step per round: wall clock, CPU */
} variant;

static rl_species_ff sff;

/* A run of `from` (cloned) with the barostat `type` (NULL: none). */
static void make(variant *v, const rl_system *from, const rl_stepop_type *type, double P0, long interval, long ev)
{
  memset(v, 0, sizeof *v);
  if (!(v->sys = rl_system_clone(from))) die("clone");
  rl_pair_params pp = {.species = &sff, .nspecies = 1};
  rl_ff_params_default(&pp.p);
  pp.p.cutoff = RC;
  pp.p.lj_truncation = RL_LJ_SHIFTED_FORCE;
  pp.p.dipole_method = RL_DIPOLE_SF;
  pp.p.threads = 1;
  v->terms = rl_terms_alloc(v->sys);
  if (!v->terms || rl_terms_add(v->terms, &rl_term_pair, &pp, NULL)) die("terms");
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = HSTEP;
  p.thermostat = RL_THERMO_BUSSI;
  p.T0 = TEMP;
  p.tau = 0.5;
  p.seed = 9;
  p.energy_every = ev;
  if (!(v->in = rl_integrator_alloc(v->sys, &p, rl_terms_provider(v->terms)))) die("integrator");
  if (type) {
    const rl_barostat_params bp = {.P0 = P0, .T0 = TEMP, .interval = interval, .tau_p = 1.0, .compressibility = 0.05,
                                   .coupling = RL_BARO_ISOTROPIC, .min_edge = 2.0 * RC, .seed = 77};
    if (rl_integrator_add_op(v->in, type, &bp)) die("barostat");
  }
  if (rl_integrator_init(v->in)) die("init");
}

static int cmp(const void *a, const void *b)
{
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median(const double *x, int n)
{
  double s[64];
  memcpy(s, x, sizeof *x * (size_t)n);
  qsort(s, (size_t)n, sizeof *s, cmp);
  return n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
}

static double best_of(const double *x, int n)
{
  double b = x[0];
  for (int q = 1; q < n; q++) b = fmin(b, x[q]);
  return b;
}

int main(int argc, char **argv)
{
  const int n = argc > 1 ? atoi(argv[1]) : 2048;
  const long steps = argc > 2 ? atol(argv[2]) : 400;
  int rounds = argc > 3 ? atoi(argv[3]) : 5;
  const long ev = argc > 4 ? atol(argv[4]) : 1, mc_every = argc > 5 ? atol(argv[5]) : 25,
             cr_every = argc > 6 ? atol(argv[6]) : 10;
  if (n < 8 || steps < 1 || rounds < 1 || ev < 1 || mc_every < 1 || cr_every < 1 || cr_every % ev) {
    fprintf(stderr, "usage: barostat_cost [N] [STEPS] [ROUNDS] [ENERGY_EVERY] [MC_INTERVAL] [CR_INTERVAL "
                    "(a multiple of ENERGY_EVERY)]\n");
    return 2;
  }
  if (rounds > 64) rounds = 64;
  rl_molecule mol;
  if (rl_model_build(rl_catalog_find("stockmayer"), NULL, 0, &mol)) die("model");
  sff = rl_molecule_ff(&mol);
  rl_system *s0 = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc d;
  rl_molecule_species(&mol, &d);
  const double L = cbrt(n / 0.8), box[3] = {L, L, L};
  if (!s0 || rl_system_add_species(s0, &d, n, NULL) || rl_system_lattice(s0, box, RL_LATTICE_SC, 1, 3) ||
      rl_system_maxwell_boltzmann(s0, TEMP, 4))
    die("system");
  /* relax (NVT) and take the mean pressure of the second half */
  variant r;
  make(&r, s0, NULL, 0.0, 1, 1);
  double Psum = 0.0;
  const long relax = 1000;
  for (long k = 0; k < relax; k++) {
    rl_step_info info;
    if (rl_integrator_step(r.in, &info)) die("relax");
    if (k >= relax / 2) Psum += rl_forces_pressure(r.sys, rl_integrator_forces(r.in), info.ke_trans);
  }
  if (rl_integrator_finish(r.in)) die("finish");
  const double P0 = Psum / (double)(relax - relax / 2);
  variant v[3];
  make(&v[0], r.sys, NULL, 0.0, 1, ev);
  make(&v[1], r.sys, &rl_stepop_mc_barostat, P0, mc_every, ev);
  make(&v[2], r.sys, &rl_stepop_crescale, P0, cr_every, ev);
  const double V0 = rl_system_volume(r.sys);
  printf("# barostat_cost: %d Stockmayer, rho* 0.8, T* 1.35, cutoff %.1f, h %.3f, energy every %ld step(s), one "
         "thread; P0 = %.4f (the NVT mean); %d rounds of %ld steps, variants alternated\n",
         n, RC, HSTEP, ev, P0, rounds, steps);
  for (int q = 0; q < rounds; q++)
    for (int k = 0; k < 3; k++) {
      const double t0 = clock_of(CLOCK_MONOTONIC), c0 = clock_of(CLOCK_PROCESS_CPUTIME_ID);
      for (long j = 0; j < steps; j++)
        if (rl_integrator_step(v[k].in, NULL)) die("step");
      v[k].cpu[q] = 1e3 * (clock_of(CLOCK_PROCESS_CPUTIME_ID) - c0) / (double)steps;
      v[k].t[q] = 1e3 * (clock_of(CLOCK_MONOTONIC) - t0) / (double)steps;
    }
  static const char *name[3] = {"nvt", "mc", "c-rescale"};
  const long every[3] = {0, mc_every, cr_every};
  const double m0 = median(v[0].t, rounds), c0 = median(v[0].cpu, rounds);
  const long steps_all = steps * rounds;
  for (int k = 0; k < 3; k++) {
    double ratios[64], cratios[64];
    for (int q = 0; q < rounds; q++) {
      ratios[q] = v[k].t[q] / v[0].t[q];
      cratios[q] = v[k].cpu[q] / v[0].cpu[q];
    }
    const double best = best_of(v[k].t, rounds), cbest = best_of(v[k].cpu, rounds);
    const double m = median(v[k].t, rounds), rm = median(ratios, rounds), c = median(v[k].cpu, rounds);
    const long builds = rl_forcefield_rebuilds(rl_terms_find(v[k].terms, &rl_term_pair));
    printf("variant=%s interval=%ld ms_per_step_median=%.4f ms_per_step_best=%.4f ratio_median=%.4f "
           "ratio_of_medians=%.4f cpu_ms_median=%.4f cpu_ms_best=%.4f cpu_ratio_median=%.4f cpu_ratio_of_medians=%.4f "
           "cpu_ratio_of_bests=%.4f list_builds=%ld steps_per_build=%.1f V_over_V0=%.4f",
           name[k], every[k], m, best, rm, m / m0, c, cbest, median(cratios, rounds), c / c0,
           cbest / best_of(v[0].cpu, rounds),
           builds, (double)steps_all / (double)(builds > 0 ? builds : 1), rl_system_volume(v[k].sys) / V0);
    if (k == 1) {
      rl_barostat_stats st;
      for (int o = 0; o < rl_integrator_nops(v[k].in); o++)
        if (!rl_barostat_stats_of(rl_integrator_op(v[k].in, o), &st))
          printf(" acceptance=%.3f", st.attempted[0] ? (double)st.accepted[0] / (double)st.attempted[0] : 0.0);
    }
    printf("\n");
  }
  for (int k = 0; k < 3; k++) {
    rl_integrator_free(v[k].in);
    rl_terms_free(v[k].terms);
    rl_system_free(v[k].sys);
  }
  rl_integrator_free(r.in);
  rl_terms_free(r.terms);
  rl_system_free(r.sys);
  rl_system_free(s0);
  return 0;
}
