/* bench/paths: integrator-only cost of every model family's fast path against the same
 * molecules forced through the general asymmetric path, and the state each keeps per molecule.
 *
 *   bench/paths [N molecules = 4096] [steps = 200] [rounds = 7]
 *
 * Forces are zero (the provider does nothing), so the time is the leapfrog itself: the on-step
 * kinetic energy, kicks, drift and rotation.  Fast and general runs alternate round by round in
 * one process and the fastest round of each is kept, so machine noise hits both alike; the
 * ratio is the figure to read.  Writes bench/paths.csv beside the table (or $ROTLEAP_BENCH_CSV). */
#include <rotleap/catalog.h>
#include <rotleap/rotleap.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static int no_forces(void *ctx, const rl_system *sys, rl_forces *out)
{
  (void)ctx; (void)sys; (void)out;
  return RL_OK;
}

static double now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

typedef struct {
  rl_system *sys;
  rl_integrator *in;
  int bytes;
  rl_kind kind;
} setup;

static int make(const char *model, int general, int n, setup *su)
{
  const rl_model *md = rl_catalog_find(model);
  rl_molecule m, nat;
  if (!md || rl_model_build(md, NULL, general, &m) || rl_model_build(md, NULL, 0, &nat)) return 1;
  su->sys = rl_system_alloc(md->units);
  rl_species_desc d;
  rl_molecule_species(&m, &d);
  if (rl_system_add_species(su->sys, &d, n, NULL)) return 1;
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(r, 5);
  double kT = md->units == RL_UNITS_LJ ? 1.0 : 2.48;
  for (int i = 0; i < n; i++) {
    double q[4], nq = 0, A[9], l[3], v[3];
    for (int k = 0; k < 4; k++) { q[k] = gsl_ran_gaussian(r, 1); nq += q[k] * q[k]; }
    for (int k = 0; k < 4; k++) q[k] /= sqrt(nq);
    rl_quat_to_matrix(q, A);
    for (int c = 0; c < 3; c++) {
      l[c] = gsl_ran_gaussian(r, sqrt(kT * nat.inertia[0]));
      v[c] = gsl_ran_gaussian(r, sqrt(kT / m.mass));
    }
    double dd = l[0] * A[6] + l[1] * A[7] + l[2] * A[8];
    if (nat.kind == RL_KIND_LINEAR || nat.kind == RL_KIND_DIPOLE)
      for (int c = 0; c < 3; c++) l[c] -= dd * A[6 + c];
    rl_system_set_orientation(su->sys, i, A);
    rl_system_set_velocity(su->sys, i, v);
    if (nat.kind != RL_KIND_POINT) rl_system_set_angmom(su->sys, i, l);
  }
  gsl_rng_free(r);
  rl_integrator_params p;
  rl_integrator_params_default(&p);
  p.h = md->units == RL_UNITS_LJ ? 0.002 : 0.002;
  su->in = rl_integrator_alloc(su->sys, &p, (rl_force_provider){no_forces, NULL});
  if (!su->in || rl_integrator_init(su->in)) return 1;
  su->bytes = rl_system_state_bytes(su->sys, 0);
  su->kind = m.kind;
  return 0;
}

static double run(setup *su, int steps)
{
  double t0 = now();
  for (int s = 0; s < steps; s++)
    if (rl_integrator_step(su->in, NULL)) { fprintf(stderr, "paths: %s\n", rl_last_error()); exit(1); }
  return now() - t0;
}

int main(int argc, char **argv)
{
  int n = argc > 1 ? atoi(argv[1]) : 4096, steps = argc > 2 ? atoi(argv[2]) : 200,
      rounds = argc > 3 ? atoi(argv[3]) : 7;
  if (n < 1 || steps < 1 || rounds < 1) { fprintf(stderr, "usage: paths [N] [steps] [rounds]\n"); return 2; }
  const char *csvname = getenv("ROTLEAP_BENCH_CSV") ? getenv("ROTLEAP_BENCH_CSV") : "bench/paths.csv";
  FILE *csv = fopen(csvname, "w");
  const struct { const char *family, *model; } rows[] = {
      {"point", NULL}, {"dipole", "stockmayer"}, {"linear", "co2"}, {"spherical", "ch4"},
      {"symmetric", "nh3"}, {"asymmetric", "tip4p"}};
  printf("integrator-only cost per molecule-step, N = %d, %d steps, best of %d alternating rounds\n\n", n, steps, rounds);
  printf("%-11s %-11s %12s %12s %8s %12s %12s\n", "family", "model", "fast ns", "general ns", "ratio",
         "fast bytes", "general bytes");
  if (csv) fprintf(csv, "family,model,fast_ns,general_ns,ratio,fast_bytes,general_bytes\n");
  int worse = 0;
  for (size_t k = 0; k < sizeof rows / sizeof rows[0]; k++) {
    if (!rows[k].model) { /* point particles: translation only, there is no general path */
      rl_system *s = rl_system_alloc(RL_UNITS_REAL);
      rl_species_desc d = {.name = "atom", .kind = RL_KIND_POINT, .mass = 40.0};
      rl_system_add_species(s, &d, 1, NULL);
      printf("%-11s %-11s %12s %12s %8s %12d %12s\n", "point", "(atom)", "-", "-", "-", rl_system_state_bytes(s, 0), "-");
      if (csv) fprintf(csv, "point,atom,,,,%d,\n", rl_system_state_bytes(s, 0));
      rl_system_free(s);
      continue;
    }
    setup fast, gen;
    if (make(rows[k].model, 0, n, &fast) || make(rows[k].model, 1, n, &gen)) {
      fprintf(stderr, "paths: %s\n", rl_last_error());
      return 1;
    }
    double bf = INFINITY, bg = INFINITY;
    run(&fast, steps / 4 + 1); /* warm up */
    run(&gen, steps / 4 + 1);
    for (int r = 0; r < rounds; r++) {
      bf = fmin(bf, run(&fast, steps));
      bg = fmin(bg, run(&gen, steps));
    }
    double nf = 1e9 * bf / ((double)n * steps), ng = 1e9 * bg / ((double)n * steps);
    int same = fast.kind == gen.kind;
    printf("%-11s %-11s %12.1f %12.1f %8.2f %12d %12d%s\n", rows[k].family, rows[k].model, nf, ng,
           ng / nf, fast.bytes, gen.bytes, same ? "  (is the general path)" : "");
    if (csv) fprintf(csv, "%s,%s,%.2f,%.2f,%.3f,%d,%d\n", rows[k].family, rows[k].model, nf, ng, ng / nf, fast.bytes, gen.bytes);
    if (!same && !(nf < ng)) worse++;
    rl_integrator_free(fast.in); rl_system_free(fast.sys);
    rl_integrator_free(gen.in); rl_system_free(gen.sys);
  }
  if (csv) { fclose(csv); printf("\nwritten: %s\n", csvname); }
  printf("%s\n", worse ? "SOME FAST PATH IS NOT CHEAPER THAN THE GENERAL PATH" : "every fast path is cheaper than the general path");
  return worse ? 1 : 0;
}
