/* The run driver: deck -> system, force field, integrator -> loop -> outputs.  Thin by design:
 * the physics lives in the library. */
#include "run.h"
#include "quantity.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define BAR_PER_KJMOL_NM3 16.605390671738467 /* 1 kJ/mol/nm^3 in bar (1e3 / N_A / 1e-27 / 1e5) */

typedef struct {
  rl_molecule mol;
  rl_system *sys;
  rl_forcefield *ff;
} scene;

static void scene_free(scene *s)
{
  rl_forcefield_free(s->ff);
  rl_system_free(s->sys);
}

static int build(const rl_deck *d, scene *s)
{
  memset(s, 0, sizeof *s);
  if (rl_model_build(d->model, d->params, d->force_general, &s->mol)) return 1;
  s->sys = rl_system_alloc(d->units);
  rl_species_desc sd;
  rl_molecule_species(&s->mol, &sd);
  if (!s->sys || rl_system_add_species(s->sys, &sd, d->count, NULL)) return 1;
  if (rl_system_lattice(s->sys, d->box, d->lattice, d->random_orientations, d->seed)) return 1;
  if (rl_system_maxwell_boltzmann(s->sys, d->temperature, d->seed + 1)) return 1;
  rl_species_ff sff = rl_molecule_ff(&s->mol);
  s->ff = rl_forcefield_alloc(s->sys, &d->ff, &sff, 1);
  if (!s->ff) return 1;
  if (d->model->geometric_mixing) /* OPLS, EPM2: sigma_ab = sqrt(sigma_a sigma_b) */
    for (int a = 0; a < s->mol.nsites; a++)
      for (int b = a; b < s->mol.nsites; b++)
        if (s->mol.epsilon[a] > 0 && s->mol.epsilon[b] > 0 &&
            rl_forcefield_set_lj_pair(s->ff, 0, a, 0, b, sqrt(s->mol.sigma[a] * s->mol.sigma[b]),
                                      sqrt(s->mol.epsilon[a] * s->mol.epsilon[b])))
          return 1;
  return 0;
}

static double pressure_out(const rl_deck *d, double p) { return d->units == RL_UNITS_REAL ? p * BAR_PER_KJMOL_NM3 : p; }
static const char *pressure_unit(const rl_deck *d) { return d->units == RL_UNITS_REAL ? "bar" : "reduced"; }
static const char *energy_unit(const rl_deck *d) { return d->units == RL_UNITS_REAL ? "kJ/mol" : "reduced"; }

int rl_app_energy(const rl_deck *d, int json)
{
  scene s;
  if (build(d, &s)) { fprintf(stderr, "rotleap energy: %s\n", rl_last_error()); scene_free(&s); return 1; }
  int n = rl_system_count(s.sys), nr = rl_system_nrot(s.sys);
  rl_forces F = {calloc((size_t)n, sizeof(double[3])), calloc((size_t)(nr > 0 ? nr : 1), sizeof(double[3])), 0.0, {0}};
  int st = F.f && F.k ? rl_forcefield_compute(s.ff, s.sys, &F) : RL_ENOMEM;
  if (st) {
    fprintf(stderr, "rotleap energy: %s\n", rl_last_error());
    free(F.f); free(F.k); scene_free(&s);
    return 1;
  }
  rl_ff_energies e;
  rl_forcefield_energies(s.ff, &e);
  double ke = 0.0;
  for (int i = 0; i < n; i++) {
    double v[3];
    rl_system_get_velocity(s.sys, i, v);
    ke += 0.5 * s.mol.mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  double P = pressure_out(d, rl_forcefield_pressure(s.ff, &F, ke));
  const char *L = d->units == RL_UNITS_REAL ? "nm" : "reduced";
  if (json) {
    printf("{\"units\": {\"energy\": \"%s\", \"length\": \"%s\", \"force\": \"%s/%s\", \"torque\": \"%s\", "
           "\"pressure\": \"%s\"},\n \"energy\": {\"total\": %.17g, \"lj\": %.17g, \"coulomb\": %.17g, "
           "\"dipolar\": %.17g, \"quadrupolar\": %.17g, \"dispersion\": %.17g},\n \"virial\": [",
           energy_unit(d), L, energy_unit(d), L, energy_unit(d), pressure_unit(d), e.total, e.lj,
           e.coulomb, e.dipolar, e.quadrupolar, e.dispersion);
    for (int k = 0; k < 9; k++) printf("%.17g%s", F.virial[k], k < 8 ? ", " : "");
    printf("],\n \"pressure\": %.17g,\n \"molecules\": [", P);
    for (int i = 0; i < n; i++) {
      int ri = rl_system_rot_index(s.sys, i);
      double z[3] = {0, 0, 0};
      const double *k = ri >= 0 ? F.k[ri] : z;
      printf("%s\n  {\"force\": [%.17g, %.17g, %.17g], \"torque\": [%.17g, %.17g, %.17g]}", i ? "," : "",
             F.f[i][0], F.f[i][1], F.f[i][2], k[0], k[1], k[2]);
    }
    printf("\n ]}\n");
  } else {
    printf("# energies in %s, forces in %s/%s, torques in %s, pressure in %s\n", energy_unit(d),
           energy_unit(d), L, energy_unit(d), pressure_unit(d));
    printf("term,value\ntotal,%.17g\nlj,%.17g\ncoulomb,%.17g\ndipolar,%.17g\nquadrupolar,%.17g\n"
           "dispersion,%.17g\npressure,%.17g\n", e.total, e.lj, e.coulomb, e.dipolar, e.quadrupolar,
           e.dispersion, P);
    printf("\nmolecule,fx,fy,fz,tx,ty,tz\n");
    for (int i = 0; i < n; i++) {
      int ri = rl_system_rot_index(s.sys, i);
      double z[3] = {0, 0, 0};
      const double *k = ri >= 0 ? F.k[ri] : z;
      printf("%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", i, F.f[i][0], F.f[i][1], F.f[i][2], k[0], k[1], k[2]);
    }
  }
  free(F.f); free(F.k); scene_free(&s);
  return 0;
}

static double now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* Welford running mean and variance. */
typedef struct { long n; double mean, m2; } running;
static void run_add(running *r, double x)
{
  r->n++;
  double d = x - r->mean;
  r->mean += d / r->n;
  r->m2 += d * (x - r->mean);
}
static double run_sd(const running *r) { return r->n > 1 ? sqrt(r->m2 / (r->n - 1)) : 0.0; }

/* Write `text` to path atomically (temporary file + rename). */
static int write_atomic(const char *path, const char *text)
{
  char tmp[1200];
  snprintf(tmp, sizeof tmp, "%s.tmp.%d", path, (int)getpid());
  FILE *f = fopen(tmp, "w");
  if (!f) return -1;
  int ok = fputs(text, f) >= 0;
  ok = (fflush(f) == 0) && ok && fsync(fileno(f)) == 0;
  ok = (fclose(f) == 0) && ok;
  if (!ok || rename(tmp, path)) { remove(tmp); return -1; }
  return 0;
}

int rl_app_run(const rl_deck *d)
{
  scene s;
  char thermo_path[600], part[700], summary_path[600];
  snprintf(thermo_path, sizeof thermo_path, "%s.thermo.csv", d->prefix);
  snprintf(part, sizeof part, "%s.part", thermo_path);
  snprintf(summary_path, sizeof summary_path, "%s.summary.txt", d->prefix);
  FILE *thermo = fopen(part, "w");
  if (!thermo) {
    fprintf(stderr, "rotleap run: cannot write %s: %s (output.prefix = %s)\n", part, strerror(errno), d->prefix);
    return 1;
  }
  if (build(d, &s)) {
    fprintf(stderr, "rotleap run: %s\n", rl_last_error());
    fclose(thermo); remove(part); scene_free(&s);
    return 1;
  }
  int progress = d->progress < 0 ? isatty(fileno(stderr)) : d->progress;
  rl_integrator_params p;
  rl_integrator *in = NULL;
  int st = RL_OK, n = d->count;
  if (d->equilibrate_steps > 0) { /* isokinetic relaxation from the lattice */
    rl_integrator_params_default(&p);
    p.h = d->equilibrate_timestep;
    p.thermostat = RL_THERMO_ISOKINETIC;
    p.T0 = d->temperature;
    in = rl_integrator_alloc(s.sys, &p, rl_forcefield_provider(s.ff));
    st = in ? rl_integrator_init(in) : RL_EINVAL;
    for (long k = 0; !st && k < d->equilibrate_steps; k++) st = rl_integrator_step(in, NULL);
    if (!st) st = rl_integrator_finish(in);
    rl_integrator_free(in);
    in = NULL;
    if (st) fprintf(stderr, "rotleap run: during equilibration: %s\n", rl_last_error());
  }
  rl_integrator_params_default(&p);
  p.h = d->timestep;
  p.method = d->method;
  p.thermostat = d->thermostat;
  p.T0 = d->thermostat_temperature;
  p.tau = d->tau;
  p.seed = d->thermostat_seed;
  p.force_general = d->force_general;
  if (!st) {
    in = rl_integrator_alloc(s.sys, &p, rl_forcefield_provider(s.ff));
    st = in ? rl_integrator_init(in) : RL_EINVAL;
    if (st) fprintf(stderr, "rotleap run: %s\n", rl_last_error());
  }
  fprintf(thermo, "step,time,total,potential,lj,coulomb,dipolar,quadrupolar,dispersion,ke_trans,ke_rot,"
                  "temperature,t_trans,t_rot,pressure,conserved,calE\n");
  running E = {0}, U = {0}, T = {0}, Tt = {0}, Tr = {0}, P = {0};
  double t0 = now(), last_progress = 0.0;
  long done = 0, fallbacks = 0;
  for (long k = 0; !st && k < d->steps; k++) {
    rl_ff_energies e;
    rl_forcefield_energies(s.ff, &e); /* terms at the current time t */
    const rl_forces *F = rl_integrator_forces(in);
    double virial[9];
    memcpy(virial, F->virial, sizeof virial);
    rl_step_info info;
    st = rl_integrator_step(in, &info);
    if (st) {
      fprintf(stderr, "rotleap run: step %ld (t = %g %s): %s\n", k, info.t, rl_dim_unit(Q_TIME, d->units), rl_last_error());
      break;
    }
    rl_forces Ft = {NULL, NULL, 0.0, {0}};
    memcpy(Ft.virial, virial, sizeof virial);
    double pr = pressure_out(d, rl_forcefield_pressure(s.ff, &Ft, info.ke_trans));
    run_add(&E, info.total);
    run_add(&U, info.potential);
    run_add(&T, info.temperature);
    run_add(&Tt, info.t_trans);
    run_add(&Tr, info.t_rot);
    run_add(&P, pr);
    done++;
    if (k % d->thermo_every == 0)
      fprintf(thermo, "%ld,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.6g,%.6g,%.6g,%.6g,%.10g,%.4e\n",
              k, info.t, info.total, info.potential, e.lj, e.coulomb, e.dipolar, e.quadrupolar, e.dispersion,
              info.ke_trans, info.ke_rot, info.temperature, info.t_trans, info.t_rot, pr, info.conserved,
              E.n > 1 ? run_sd(&E) / fabs(E.mean) : 0.0);
    if (progress && now() - last_progress > 0.5) {
      double el = now() - t0, frac = (double)(k + 1) / d->steps;
      double nsday = d->units == RL_UNITS_REAL ? (k + 1) * d->timestep * 1e-3 / el * 86400.0 : 0.0;
      fprintf(stderr, "\r%5.1f%%  step %ld/%ld  ETA %.0f s%s%.2f%s   ", 100.0 * frac, k + 1, d->steps,
              el / frac - el, d->units == RL_UNITS_REAL ? "  " : "", nsday, d->units == RL_UNITS_REAL ? " ns/day" : "");
      last_progress = now();
    }
  }
  if (in) fallbacks = rl_integrator_fallbacks(in);
  if (progress) fputc('\n', stderr);
  double wall = now() - t0;
  /* the rows already written are kept whatever happened: close and rename */
  int io_ok = fclose(thermo) == 0 && rename(part, thermo_path) == 0;
  if (!io_ok) fprintf(stderr, "rotleap run: cannot write %s: %s\n", thermo_path, strerror(errno));
  char text[4096];
  snprintf(text, sizeof text,
           "# rotleap %s summary of %s\n"
           "status = %s\nsteps = %ld of %ld\nmodel = %s\nmolecules = %d\nunits = %s\n"
           "timestep = %g %s\nwall_seconds = %.3f\nfallbacks = %ld\n"
           "U_per_molecule = %.8g +- sd %.3g %s\n"
           "temperature = %.6g (translational %.6g, rotational %.6g) %s\n"
           "pressure = %.6g +- sd %.3g %s\n"
           "calE = %.6e\ncalU = %.6e\ncalE_over_calU = %.6e\n",
           ROTLEAP_VERSION, d->path, st ? "error" : "ok", done, d->steps, d->model->name, n,
           d->units == RL_UNITS_LJ ? "lj" : "real", d->timestep, rl_dim_unit(Q_TIME, d->units), wall, fallbacks,
           U.mean / n, run_sd(&U) / n, energy_unit(d), T.mean, Tt.mean, Tr.mean,
           d->units == RL_UNITS_LJ ? "" : "K", P.mean, run_sd(&P), pressure_unit(d),
           E.n > 1 ? run_sd(&E) / fabs(E.mean) : 0.0, U.n > 1 ? run_sd(&U) / fabs(U.mean) : 0.0,
           U.n > 1 && run_sd(&U) > 0 ? (run_sd(&E) / fabs(E.mean)) / (run_sd(&U) / fabs(U.mean)) : 0.0);
  if (write_atomic(summary_path, text)) {
    fprintf(stderr, "rotleap run: cannot write %s: %s\n", summary_path, strerror(errno));
    io_ok = 0;
  }
  if (!st) fputs(text, stdout);
  rl_integrator_free(in);
  scene_free(&s);
  return st || !io_ok ? 1 : 0;
}
