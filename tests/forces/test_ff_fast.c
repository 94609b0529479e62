/* The specialised, threaded kernels (p.kernel = RL_KERNEL_AUTO) against the reference path
 * (RL_KERNEL_GENERAL) on random periodic liquids: TIP4P-like water ("tip4p"), point dipoles
 * ("stockmayer", reaction field, plain truncation and shifted force), linear CO2 and ions
 * ("charge-lj"), and a mixture of all of them with general cross pairs.  Both cutoff schemes,
 * all four LJ truncations, a box whose half edge equals the cutoff (site images differ from the
 * centre image) and larger boxes (the kernels shift sites by the centres' image), a TIP4P whose
 * LJ site is listed last, 1 against 2 and 3 threads (a mixture and neat liquids),
 * reproducibility for a fixed thread count and for repeated computes, the kernel choice from
 * site patterns, and the overlap error message. */
#include "ff_testutil.h"

typedef struct {
  ff_test_species sp[7];
  rl_species_ff sff[7];
  int nsp;
  rl_system *sys;
  double L;
} scene;

/* Random liquid: counts[k] bodies of sp[k], centres at least dmin apart, number density rho. */
static void scene_build(scene *s, gsl_rng *rng, rl_units units, const int *counts, double rho,
                        double dmin, double Lfix)
{
  s->sys = rl_system_alloc(units);
  int n = 0;
  for (int k = 0; k < s->nsp; k++) {
    s->sp[k].desc.sites = &s->sp[k].sites[0][0];
    assert_int_equal(rl_system_add_species(s->sys, &s->sp[k].desc, counts[k], NULL), RL_OK);
    s->sff[k] = ff_test_species_ff(&s->sp[k]);
    n += counts[k];
  }
  s->L = Lfix > 0.0 ? Lfix : cbrt(n / rho);
  double(*r)[3] = malloc(sizeof *r * (size_t)n);
  for (int i = 0; i < n; i++) {
    for (int tries = 0;; tries++) {
      assert_true(tries < 1000000);
      double x[3];
      for (int c = 0; c < 3; c++) x[c] = gsl_ran_flat(rng, -0.5 * s->L, 1.5 * s->L); /* unwrapped */
      int ok = 1;
      for (int j = 0; j < i && ok; j++) {
        double d2 = 0.0;
        for (int c = 0; c < 3; c++) {
          double d = x[c] - r[j][c];
          d -= s->L * nearbyint(d / s->L);
          d2 += d * d;
        }
        ok = d2 >= dmin * dmin;
      }
      if (ok) { memcpy(r[i], x, sizeof x); break; }
    }
    assert_int_equal(rl_system_set_position(s->sys, i, r[i]), RL_OK);
    ff_random_orientation(s->sys, i, rng);
  }
  free(r);
  const double box[3] = {s->L, s->L, s->L};
  assert_int_equal(rl_system_set_box(s->sys, box), RL_OK); /* the force fields take it */
}

/* Largest relative difference of everything a compute returns (0 when bit-identical). */
static double compare(rl_forcefield *fa, rl_forcefield *fb, rl_system *sys, const char *what,
                      double tol)
{
  ff_result a, b;
  ff_result_compute(&a, fa, sys);
  ff_result_compute(&b, fb, sys);
  rl_ff_energies ea, eb;
  rl_forcefield_energies(fa, &ea);
  rl_forcefield_energies(fb, &eb);
  double scale = fabs(eb.lj) + fabs(eb.coulomb) + fabs(eb.dipolar) + fabs(eb.quadrupolar);
  double de = fabs(ea.total - eb.total);
  de = fmax(de, fabs(ea.lj - eb.lj));
  de = fmax(de, fabs(ea.coulomb - eb.coulomb));
  de = fmax(de, fabs(ea.dipolar - eb.dipolar));
  de = fmax(de, fabs(ea.quadrupolar - eb.quadrupolar));
  double worst = 0.0;
  char name[240];
  snprintf(name, sizeof name, "%s: energies by term, max |dE| / sum |E_term|", what);
  FF_CHECK_LE(name, de / scale, tol);
  worst = fmax(worst, de / scale);
  double df = ff_maxdiff((const double(*)[3])a.f, (const double(*)[3])b.f, a.n) /
              ff_maxnorm((const double(*)[3])b.f, b.n);
  snprintf(name, sizeof name, "%s: max |df| / max |f|", what);
  FF_CHECK_LE(name, df, tol);
  worst = fmax(worst, df);
  if (b.nrot > 0) {
    double dk = ff_maxdiff((const double(*)[3])a.k, (const double(*)[3])b.k, a.nrot) /
                ff_maxnorm((const double(*)[3])b.k, b.nrot);
    snprintf(name, sizeof name, "%s: max |dk| / max |k|", what);
    FF_CHECK_LE(name, dk, tol);
    worst = fmax(worst, dk);
  }
  double vd = 0.0, vs = 0.0;
  for (int c = 0; c < 9; c++) {
    vd = fmax(vd, fabs(a.out.virial[c] - b.out.virial[c]));
    vs = fmax(vs, fabs(b.out.virial[c]));
  }
  snprintf(name, sizeof name, "%s: max |dW| / max |W|", what);
  FF_CHECK_LE(name, vd / vs, tol);
  worst = fmax(worst, vd / vs);
  ff_result_free(&a);
  ff_result_free(&b);
  return worst;
}

static rl_forcefield *make(scene *s, const rl_ff_params *p0, rl_kernel_choice kernel, int threads)
{
  rl_ff_params p = *p0;
  p.kernel = kernel;
  p.threads = threads;
  rl_forcefield *ff = rl_forcefield_alloc(s->sys, &p, s->sff, s->nsp);
  if (!ff) fprintf(stderr, "alloc: %s\n", rl_last_error());
  assert_non_null(ff);
  return ff;
}

static const char *trunc_name[4] = {"plain", "shifted", "shifted-force", "switched"};

/* The pair-row paths the dipole and TIP4P species can take: the best the CPU has, the AVX2
 * register rows on an AVX-512 CPU, the portable rows.  On a CPU without AVX-512 the first two
 * are the same, and without AVX2 all three. */
#define NPATH 3
static const char *path_label[NPATH] = {"", ", ROTLEAP_NO_AVX512", ", portable rows"};
/* The rows path k must take on this CPU (rl_forcefield_rows). */
static const char *expected_rows(int k)
{
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(ROTLEAP_NO_CLONES)
  if (k == 0 && __builtin_cpu_supports("avx512f")) return "avx512";
  if (k <= 1 && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return "avx2";
#endif
  (void)k;
  return "portable";
}
static int cur_path;
static void set_path(int k)
{
  cur_path = k;
  if (k >= 1) setenv("ROTLEAP_NO_AVX512", "1", 1);
  else unsetenv("ROTLEAP_NO_AVX512");
  if (k >= 2) setenv("ROTLEAP_NO_AVX2", "1", 1);
  else unsetenv("ROTLEAP_NO_AVX2");
}

/* Auto vs general for both schemes and every truncation; the auto kernel's name is checked. */
static void sweep(scene *s, rl_ff_params *p, const char *label, const char *kernel_name)
{
  for (int scheme = 0; scheme < 2; scheme++)
    for (int tr = 0; tr < 4; tr++) {
      if (scheme == RL_CUTOFF_MOLECULE && p->coulomb == RL_COULOMB_EWALD_REAL) continue; /* refused */
      p->scheme = (rl_cutoff_scheme)scheme;
      p->lj_truncation = (rl_lj_truncation)tr;
      p->r_switch = 0.8 * p->cutoff;
      rl_forcefield *fa = make(s, p, RL_KERNEL_AUTO, 2), *fg = make(s, p, RL_KERNEL_GENERAL, 0);
      char what[200];
      snprintf(what, sizeof what, "%s, %s cutoff, LJ %s", label, scheme ? "molecule" : "site",
               trunc_name[tr]);
      if (scheme == 0 && tr == 0) {
        char nm[240];
        snprintf(nm, sizeof nm, "%s: kernel '%s' chosen (expected '%s')", label,
                 rl_forcefield_kernel(fa), kernel_name);
        FF_CHECK_TRUE(nm, strcmp(rl_forcefield_kernel(fa), kernel_name) == 0);
        if (!strcmp(kernel_name, "tip4p") || !strcmp(kernel_name, "stockmayer")) {
          snprintf(nm, sizeof nm, "%s: rows '%s' (expected '%s')", label, rl_forcefield_rows(fa),
                   expected_rows(cur_path));
          FF_CHECK_TRUE(nm, strcmp(rl_forcefield_rows(fa), expected_rows(cur_path)) == 0);
        }
        FF_CHECK_TRUE("reference path is named 'general'",
                      strcmp(rl_forcefield_kernel(fg), "general") == 0);
      }
      compare(fa, fg, s->sys, what, 1e-12);
      rl_forcefield_free(fa);
      rl_forcefield_free(fg);
    }
}

/* 400 TIP4P-like waters at 33.4 / nm^3 (cutoff 0.7 nm), or 500 point dipoles at 25 / nm^3
 * (cutoff 0.75 nm), and default parameters for the box. */
static void neat_scene(scene *s, gsl_rng *rng, int water, rl_ff_params *p)
{
  *s = (scene){.nsp = 1};
  if (water) ff_water(&s->sp[0]);
  else ff_stockmayer(&s->sp[0], 0.05);
  int cnt[1] = {water ? 400 : 500};
  scene_build(s, rng, RL_UNITS_REAL, cnt, water ? 33.4 : 25.0, water ? 0.25 : 0.27, 0.0);
  rl_ff_params_default(p);
  p->cutoff = water ? 0.7 : 0.75;
}

static void test_tip4p(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 11);
  scene s;
  rl_ff_params p;
  neat_scene(&s, rng, 1, &p);
  for (int k = 0; k < NPATH; k++) {
    char what[120];
    snprintf(what, sizeof what, "tip4p liquid (400)%s", path_label[k]);
    set_path(k);
    sweep(&s, &p, what, "tip4p");
  }
  set_path(0);
  p.eps_rf = INFINITY;
  p.scheme = RL_CUTOFF_SITE;
  p.lj_truncation = RL_LJ_PLAIN;
  rl_forcefield *fa = make(&s, &p, RL_KERNEL_AUTO, 1), *fg = make(&s, &p, RL_KERNEL_GENERAL, 0);
  compare(fa, fg, s.sys, "tip4p liquid, eps_rf = inf, 1 thread", 1e-12);
  rl_forcefield_free(fa);
  rl_forcefield_free(fg);
  rl_system_free(s.sys);
  gsl_rng_free(rng);
}

/* Half the box edge equals the cutoff: site pairs whose minimum image is not the centres'
 * (the fills add the centres' other images, P_SHIFT in ff_fast.c). */
static void test_periodic_edge(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 12);
  scene s = {.nsp = 1};
  ff_water(&s.sp[0]);
  int cnt[1] = {216};
  scene_build(&s, rng, RL_UNITS_REAL, cnt, 0.0, 0.25, 1.8);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = 0.9;
  for (int k = 0; k < NPATH; k++) { /* the other images in every path's fill */
    char what[120];
    snprintf(what, sizeof what, "tip4p, L = 2 rc%s", path_label[k]);
    set_path(k);
    sweep(&s, &p, what, "tip4p");
  }
  set_path(0);
  /* a non-cubic box, shortest edge 2 rc */
  rl_system_free(s.sys);
  s = (scene){.nsp = 1};
  ff_water(&s.sp[0]);
  scene_build(&s, rng, RL_UNITS_REAL, cnt, 0.0, 0.25, 1.8);
  const double L189[3] = {1.8, 2.3, 1.9};
  assert_int_equal(rl_system_set_box(s.sys, L189), RL_OK);
  p.scheme = RL_CUTOFF_SITE;
  rl_forcefield *fa = make(&s, &p, RL_KERNEL_AUTO, 2), *fg = make(&s, &p, RL_KERNEL_GENERAL, 0);
  compare(fa, fg, s.sys, "tip4p, box 1.8 x 2.3 x 1.9, rc 0.9", 1e-12);
  rl_forcefield_free(fa);
  rl_forcefield_free(fg);
  rl_system_free(s.sys);
  /* a cutoff short against the molecule, rc = 0.22 nm, in a column 0.44 x 0.44 x 3.6 nm: the
   * pruning radius rp = rc + 2 extent (0.40 nm) exceeds L / sqrt 2, so images that shift two
   * components (a corner's) lie within it too.  Layers 0.3 nm apart hold two molecules each,
   * (x, y) and about (x + L/2, y + L/2), whose four images in x and y are all within rp */
  s = (scene){.nsp = 1};
  ff_water(&s.sp[0]);
  int few[1] = {24};
  scene_build(&s, rng, RL_UNITS_REAL, few, 0.0, 0.25, 3.6);
  for (int b = 0; b < few[0]; b += 2) {
    const double x = gsl_ran_flat(rng, 0.0, 0.44), y = gsl_ran_flat(rng, 0.0, 0.44);
    const double r0[3] = {x, y, 0.15 * b};
    const double r1[3] = {x + gsl_ran_flat(rng, 0.2, 0.24), y + gsl_ran_flat(rng, 0.2, 0.24),
                          0.15 * b};
    assert_int_equal(rl_system_set_position(s.sys, b, r0), RL_OK);
    assert_int_equal(rl_system_set_position(s.sys, b + 1, r1), RL_OK);
  }
  const double Lcol[3] = {0.44, 0.44, 3.6};
  assert_int_equal(rl_system_set_box(s.sys, Lcol), RL_OK);
  p.cutoff = 0.22;
  p.scheme = RL_CUTOFF_SITE; /* the molecule cutoff has no other images */
  p.lj_truncation = RL_LJ_SHIFTED;
  p.r_switch = 0.0;
  for (int k = 0; k < NPATH; k++) {
    char what[120];
    snprintf(what, sizeof what, "tip4p, column 0.44 x 0.44 x 3.6 nm, rc 0.22%s", path_label[k]);
    set_path(k);
    fa = make(&s, &p, RL_KERNEL_AUTO, 2);
    fg = make(&s, &p, RL_KERNEL_GENERAL, 0);
    compare(fa, fg, s.sys, what, 1e-12);
    rl_forcefield_free(fa);
    rl_forcefield_free(fg);
  }
  set_path(0);
  rl_system_free(s.sys);
  gsl_rng_free(rng);
}

/* The TIP4P kernel gathers the LJ site into slot 0 whatever its place in the species: here
 * the sites are listed M, H, H, O.  And the site kernel ("charge-lj") in a box whose half edge
 * equals the cutoff: CO2, whose neighbours' centres have up to two images within the pruning
 * radius, and a rod longer than the cutoff, where each site pair takes its own image. */
static void test_site_order_and_small_box(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 15);
  scene s = {.nsp = 1};
  ff_species_init(&s.sp[0], "water-mhho", RL_KIND_ASYMMETRIC, 18.0, 0.6, 1.2, 1.5, 4);
  ff_site(&s.sp[0], 0, 0, 0, 0.0084, 0, 0, -1.04);
  ff_site(&s.sp[0], 1, 0.0757, 0, 0.0520, 0, 0, 0.52);
  ff_site(&s.sp[0], 2, -0.0757, 0, 0.0520, 0, 0, 0.52);
  ff_site(&s.sp[0], 3, 0, 0, -0.0066, 0.3154, 0.6485, 0.0);
  int cnt[1] = {400};
  scene_build(&s, rng, RL_UNITS_REAL, cnt, 33.4, 0.25, 0.0);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = 0.7;
  sweep(&s, &p, "tip4p listed M, H, H, O (400)", "tip4p");
  rl_system_free(s.sys);

  s = (scene){.nsp = 1};
  ff_co2(&s.sp[0]);
  int cc[1] = {60};
  scene_build(&s, rng, RL_UNITS_REAL, cc, 0.0, 0.33, 1.6);
  p.cutoff = 0.8;
  sweep(&s, &p, "linear co2, L = 2 rc", "charge-lj");
  rl_system_free(s.sys);

  /* a rod longer than the cutoff (2 extent = 1.4 nm, rc = 0.8 nm): with L = 2 rc < rc + 2
   * extent the images X and X + L of a neighbour's centre can both be within the pruning
   * radius on one side, so each site pair takes its own minimum image (P_SITE; taking the
   * centres' images instead fails here at 2e-10) */
  s = (scene){.nsp = 1};
  ff_species_init(&s.sp[0], "rod", RL_KIND_LINEAR, 60.0, 12.0, 12.0, 0.0, 3);
  ff_site(&s.sp[0], 0, 0, 0, 0, 0.28, 0.23, 0.6);
  ff_site(&s.sp[0], 1, 0, 0, 0.7, 0.30, 0.66, -0.3);
  ff_site(&s.sp[0], 2, 0, 0, -0.7, 0.30, 0.66, -0.3);
  int cr[1] = {24};
  scene_build(&s, rng, RL_UNITS_REAL, cr, 0.0, 0.33, 1.6);
  sweep(&s, &p, "rod of length 1.4 nm, L = 2 rc = 1.6 nm", "charge-lj");
  rl_system_free(s.sys);
  gsl_rng_free(rng);
}

static void test_stockmayer(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 13);
  scene s;
  rl_ff_params p;
  neat_scene(&s, rng, 0, &p);
  p.eps_rf = 1.0; /* plain truncation (LAMMPS lj/cut/dipole/cut) */
  sweep(&s, &p, "stockmayer, RF eps_rf = 1", "stockmayer");
  p.eps_rf = 78.3;
  sweep(&s, &p, "stockmayer, RF eps_rf = 78.3", "stockmayer");
  p.dipole_method = RL_DIPOLE_SF;
  sweep(&s, &p, "stockmayer, shifted force", "stockmayer");
  /* rows of several batches (about 110 pairs within rc per row on average, 220 in the first
   * rows; a batch holds 64), so that a batch fills in the middle of a group of candidates */
  p.cutoff = 1.3;
  sweep(&s, &p, "stockmayer, shifted force, rc = 1.3", "stockmayer");
  /* the sweeps above took the best rows the CPU has; the other paths (set_path) again */
  for (int k = 1; k < NPATH; k++) {
    char what[120];
    set_path(k);
    p.cutoff = 1.3;
    p.dipole_method = RL_DIPOLE_SF;
    snprintf(what, sizeof what, "stockmayer, shifted force, rc = 1.3%s", path_label[k]);
    sweep(&s, &p, what, "stockmayer");
    p.cutoff = 0.75;
    p.dipole_method = RL_DIPOLE_RF;
    snprintf(what, sizeof what, "stockmayer, RF eps_rf = 78.3%s", path_label[k]);
    sweep(&s, &p, what, "stockmayer");
    p.dipole_method = RL_DIPOLE_SF;
    snprintf(what, sizeof what, "stockmayer, shifted force%s", path_label[k]);
    sweep(&s, &p, what, "stockmayer");
  }
  set_path(0);
  rl_system_free(s.sys);
  gsl_rng_free(rng);
}

static void test_charge_lj(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 14);
  scene s = {.nsp = 1};
  ff_co2(&s.sp[0]);
  int cnt[1] = {300};
  scene_build(&s, rng, RL_UNITS_REAL, cnt, 12.0, 0.33, 0.0);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = 0.8;
  sweep(&s, &p, "linear co2 (300)", "charge-lj");
  rl_system_free(s.sys);
  gsl_rng_free(rng);
}

/* Water + dipoles + ions + CO2: kernel rows for like pairs, the reference routine for the rest. */
static void test_mixture(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 15);
  scene s = {.nsp = 4};
  ff_water(&s.sp[0]);
  ff_stockmayer(&s.sp[1], 0.04);
  ff_ion(&s.sp[2], 0.7);
  ff_co2(&s.sp[3]);
  int cnt[4] = {350, 60, 20, 40};
  scene_build(&s, rng, RL_UNITS_REAL, cnt, 30.0, 0.26, 0.0);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = 0.7;
  p.dispersion_correction = 1;
  sweep(&s, &p, "mixture water/dipole/ion/co2", "tip4p+stockmayer+charge-lj+general");

  /* threads: 1 vs 2 to round-off; a fixed count reproduces itself bit for bit */
  p.scheme = RL_CUTOFF_SITE;
  p.lj_truncation = RL_LJ_SHIFTED;
  rl_forcefield *f1 = make(&s, &p, RL_KERNEL_AUTO, 1), *f2 = make(&s, &p, RL_KERNEL_AUTO, 2),
                *f2b = make(&s, &p, RL_KERNEL_AUTO, 2), *f3 = make(&s, &p, RL_KERNEL_AUTO, 3);
#ifdef _OPENMP /* rotleap links OpenMP publicly: this test is built the same way */
  FF_CHECK_TRUE("threads = 2 is used", rl_forcefield_threads(f2) == 2);
#else
  FF_CHECK_TRUE("threads = 2 runs on one thread without OpenMP", rl_forcefield_threads(f2) == 1);
#endif
  compare(f1, f2, s.sys, "mixture, 1 thread vs 2 threads", 1e-13);
  compare(f2, f3, s.sys, "mixture, 2 threads vs 3 threads", 1e-13);
  double w = compare(f2, f2b, s.sys, "mixture, 2 threads twice (reproducible)", 0.0);
  FF_CHECK_TRUE("mixture, 2 threads twice: bit-identical", w == 0.0);
  rl_forcefield_free(f1);
  rl_forcefield_free(f2);
  rl_forcefield_free(f2b);
  rl_forcefield_free(f3);

  /* the list is reused and rebuilt as the reference's is */
  rl_forcefield *fa = make(&s, &p, RL_KERNEL_AUTO, 2), *fg = make(&s, &p, RL_KERNEL_GENERAL, 0);
  compare(fa, fg, s.sys, "mixture, before moves", 1e-12);
  int n = rl_system_count(s.sys);
  for (int step = 0; step < 6; step++) {
    for (int i = 0; i < n; i++) {
      double r[3];
      rl_system_get_position(s.sys, i, r);
      for (int c = 0; c < 3; c++) r[c] += gsl_ran_flat(rng, -0.012, 0.012);
      rl_system_set_position(s.sys, i, r);
    }
    char what[80];
    snprintf(what, sizeof what, "mixture, random walk step %d", step + 1);
    compare(fa, fg, s.sys, what, 1e-12);
  }
  FF_CHECK_TRUE("mixture: the kernels' list was rebuilt during the walk",
                rl_forcefield_rebuilds(fa) > 1);
  rl_forcefield_free(fa);
  rl_forcefield_free(fg);
  rl_system_free(s.sys);
  gsl_rng_free(rng);
}

/* Kernel choice follows the site pattern; an LJ override that breaks it falls back. */
/* A neat liquid on 1, 2 and 3 threads: each thread zeroes and the sums read only the ranks its
 * rows write (tlo..thi in ff_fast.c), so 2 and 3 threads must agree with 1 to round-off, and a
 * second compute with the same force field must repeat the first bit for bit (a rank left
 * unzeroed would add the last compute's forces again). */
static void threads_neat(scene *s, const rl_ff_params *p, const char *label)
{
  rl_forcefield *f1 = make(s, p, RL_KERNEL_AUTO, 1), *f2 = make(s, p, RL_KERNEL_AUTO, 2),
                *f3 = make(s, p, RL_KERNEL_AUTO, 3);
  char what[200];
  snprintf(what, sizeof what, "%s, 1 thread vs 2 threads", label);
  compare(f1, f2, s->sys, what, 1e-13);
  snprintf(what, sizeof what, "%s, 1 thread vs 3 threads", label);
  compare(f1, f3, s->sys, what, 1e-13);
  for (int t = 2; t <= 3; t++) {
    rl_forcefield *f = t == 2 ? f2 : f3;
    snprintf(what, sizeof what, "%s, %d threads, the same force field twice", label, t);
    double w = compare(f, f, s->sys, what, 0.0);
    snprintf(what, sizeof what, "%s, %d threads twice: bit-identical", label, t);
    FF_CHECK_TRUE(what, w == 0.0);
  }
  rl_forcefield_free(f1);
  rl_forcefield_free(f2);
  rl_forcefield_free(f3);
}

static void test_threads_neat(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 16);
  for (int water = 0; water < 2; water++) {
    scene s;
    rl_ff_params p;
    neat_scene(&s, rng, water, &p);
    const char *label[2][2] = {{"stockmayer (500)", "stockmayer (500), ROTLEAP_NO_AVX512"},
                               {"tip4p (400)", "tip4p (400), ROTLEAP_NO_AVX512"}};
    threads_neat(&s, &p, label[water][0]);
    setenv("ROTLEAP_NO_AVX512", "1", 1); /* the portable rows */
    threads_neat(&s, &p, label[water][1]);
    unsetenv("ROTLEAP_NO_AVX512");
    rl_system_free(s.sys);
  }
  gsl_rng_free(rng);
}

/* out->forces_only: the forces and torques of a full compute to the bit, no energy or virial
 * (energy and virial stay 0, the energies read NaN), and a full compute after it repeats the
 * one before bit for bit (the forces-only rows leave the buffers as the full rows do). */
static void forces_only(scene *s, const rl_ff_params *p, int threads, const char *label)
{
  rl_forcefield *ff = make(s, p, RL_KERNEL_AUTO, threads);
  ff_result a, b, c;
  ff_result_compute(&a, ff, s->sys);
  b.n = a.n;
  b.nrot = a.nrot;
  b.f = calloc((size_t)b.n + 1, sizeof *b.f);
  b.k = calloc((size_t)b.nrot + 1, sizeof *b.k);
  rl_forces o = {b.f, b.k, 0.0, {0}, 1};
  assert_int_equal(rl_forcefield_compute(ff, s->sys, &o), RL_OK);
  rl_ff_energies e;
  rl_forcefield_energies(ff, &e);
  ff_result_compute(&c, ff, s->sys);
  char what[200];
  int same_f = !memcmp(a.f, b.f, sizeof *a.f * (size_t)a.n) && !memcmp(a.k, b.k, sizeof *a.k * (size_t)a.nrot);
  snprintf(what, sizeof what, "%s, %d thread(s): forces-only forces and torques bit-identical", label, threads);
  FF_CHECK_TRUE(what, same_f);
  int none = o.energy == 0.0 && isnan(e.total) && isnan(e.lj);
  for (int q = 0; q < 9; q++) none &= o.virial[q] == 0.0;
  snprintf(what, sizeof what, "%s, %d thread(s): forces only: no energy or virial", label, threads);
  FF_CHECK_TRUE(what, none);
  int again = !memcmp(a.f, c.f, sizeof *a.f * (size_t)a.n) && !memcmp(a.k, c.k, sizeof *a.k * (size_t)a.nrot) &&
              a.out.energy == c.out.energy && !memcmp(a.out.virial, c.out.virial, sizeof a.out.virial) &&
              a.out.energy != 0.0;
  snprintf(what, sizeof what, "%s, %d thread(s): a full compute after a forces-only one repeats the first", label, threads);
  FF_CHECK_TRUE(what, again);
  ff_result_free(&a);
  ff_result_free(&b);
  ff_result_free(&c);
  rl_forcefield_free(ff);
}

static void test_forces_only(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 17);
  for (int water = 0; water < 2; water++) {
    scene s;
    rl_ff_params p;
    neat_scene(&s, rng, water, &p);
    for (int k = 0; k < NPATH; k++) { /* each path's forces-only rows (set_path) */
      char label[100];
      snprintf(label, sizeof label, "%s%s", water ? "tip4p (400)" : "stockmayer (500)", path_label[k]);
      set_path(k);
      for (int t = 1; t <= 2; t++) forces_only(&s, &p, t, label);
    }
    set_path(0);
    rl_system_free(s.sys);
  }
  gsl_rng_free(rng);
}

static void test_choice(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 16);
  scene s = {.nsp = 1};
  ff_water(&s.sp[0]);
  int cnt[1] = {200};
  scene_build(&s, rng, RL_UNITS_REAL, cnt, 33.4, 0.25, 0.0);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = 0.65;
  rl_forcefield *fa = make(&s, &p, RL_KERNEL_AUTO, 2), *fg = make(&s, &p, RL_KERNEL_GENERAL, 0);
  FF_CHECK_TRUE("water: tip4p kernel", strcmp(rl_forcefield_kernel(fa), "tip4p") == 0);
  /* LJ between H sites: no longer the tip4p pattern, but still LJ + charges */
  assert_int_equal(rl_forcefield_set_lj_pair(fa, 0, 1, 0, 2, 0.1, 0.05), RL_OK);
  assert_int_equal(rl_forcefield_set_lj_pair(fg, 0, 1, 0, 2, 0.1, 0.05), RL_OK);
  FF_CHECK_TRUE("water with H1-H2 LJ override: charge-lj kernel",
                strcmp(rl_forcefield_kernel(fa), "charge-lj") == 0);
  compare(fa, fg, s.sys, "water with an H1-H2 LJ override", 1e-12);
  rl_forcefield_free(fa);
  rl_forcefield_free(fg);
  p.neighbor_list = 0;
  fa = make(&s, &p, RL_KERNEL_AUTO, 2);
  FF_CHECK_TRUE("no neighbour list: the reference path",
                strcmp(rl_forcefield_kernel(fa), "general") == 0);
  rl_forcefield_free(fa);
  p.neighbor_list = 1;
  p.kernel = (rl_kernel_choice)7;
  FF_CHECK_TRUE("unknown kernel choice is an error", rl_forcefield_alloc(s.sys, &p, s.sff, 1) == NULL);
  FF_CHECK_TRUE("... named", strstr(rl_last_error(), "unknown kernel choice 7") != NULL);
  p.kernel = RL_KERNEL_AUTO;
  p.threads = -1;
  FF_CHECK_TRUE("negative thread count is an error", rl_forcefield_alloc(s.sys, &p, s.sff, 1) == NULL);
  rl_system_free(s.sys);
  gsl_rng_free(rng);
}

/* Overlapping sites: the same status and message as the reference path. */
static void test_overlap(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 17);
  for (int kind = 0; kind < 2; kind++) {
    scene s = {.nsp = 1};
    if (kind == 0) ff_water(&s.sp[0]);
    else ff_stockmayer(&s.sp[0], 0.05);
    int cnt[1] = {150};
    scene_build(&s, rng, RL_UNITS_REAL, cnt, 25.0, 0.27, 0.0);
    rl_ff_params p;
    rl_ff_params_default(&p);
    p.cutoff = 0.6;
    /* place 0: body 7 exactly on body 3; place 1 (water): body 7 with body 3's orientation,
     * moved by H1 - H2, so that its H2 sits on body 3's H1 and only charge sites overlap
     * (the oxygens are 0.15 nm apart) */
    for (int place = 0; place < (kind == 0 ? 2 : 1); place++) {
      double r[3];
      rl_system_get_position(s.sys, 3, r);
      if (kind == 0) {
        double A[9];
        rl_system_get_orientation(s.sys, 3, A);
        rl_system_set_orientation(s.sys, 7, A);
        if (place == 1) { /* body 3's sites O, H1, H2, M (ff_water) */
          double(*x)[3] = malloc(sizeof *x * (size_t)rl_system_nsites(s.sys));
          const int o3 = rl_system_site_offset(s.sys, 3);
          rl_system_site_positions(s.sys, x);
          for (int c = 0; c < 3; c++) r[c] += x[o3 + 1][c] - x[o3 + 2][c];
          free(x);
        }
      }
      rl_system_set_position(s.sys, 7, r);
      for (int scheme = 0; scheme < 2; scheme++) {
        p.scheme = (rl_cutoff_scheme)scheme;
        char msg_a[512], msg_g[512];
        int n = rl_system_count(s.sys), nr = rl_system_nrot(s.sys);
        double(*f)[3] = calloc((size_t)n, sizeof *f), (*k)[3] = calloc((size_t)nr + 1, sizeof *k);
        rl_forces out = {f, k, 0.0, {0}, 0};
        rl_forcefield *fa = make(&s, &p, RL_KERNEL_AUTO, 2);
        rl_forcefield *fg = make(&s, &p, RL_KERNEL_GENERAL, 0);
        int sa = rl_forcefield_compute(fa, s.sys, &out);
        snprintf(msg_a, sizeof msg_a, "%s", rl_last_error());
        int sg = rl_forcefield_compute(fg, s.sys, &out);
        snprintf(msg_g, sizeof msg_g, "%s", rl_last_error());
        char name[200];
        snprintf(name, sizeof name, "overlap (%s, %s cutoff): same status and message as general",
                 kind ? "dipoles" : place ? "water, H on H" : "water",
                 scheme ? "molecule" : "site");
        printf("  auto:    %s\n  general: %s\n", msg_a, msg_g);
        FF_CHECK_TRUE(name, sa == RL_EINVAL && sg == RL_EINVAL && strcmp(msg_a, msg_g) == 0 &&
                                strstr(msg_a, "overlapping sites") != NULL);
        rl_forcefield_free(fa);
        rl_forcefield_free(fg);
        free(f);
        free(k);
      }
    }
    rl_system_free(s.sys);
  }
  gsl_rng_free(rng);
}

/* A mixture in a box too small for the kernels' cell grid (L = 1.5 nm, r_list / 2 >= 0.33 nm:
 * 4 cells per edge, so build() scans all ranks above each row): kernel species (water,
 * dipoles, ions, CO2), species without a kernel (a symmetric top with a dipole off the centre,
 * and a species of one body), and a species without sites.  Kernel and reference pairs
 * from the one all-pairs scan, on 1, 2 and 3 threads against the reference path, and again
 * after moves that rebuild the list. */
static void test_small_box_mixture(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 18);
  scene s = {.nsp = 7};
  ff_water(&s.sp[0]);
  ff_stockmayer(&s.sp[1], 0.04);
  ff_ion(&s.sp[2], 0.7);
  ff_co2(&s.sp[3]);
  ff_symtop(&s.sp[4]);
  ff_ion(&s.sp[5], -0.7);
  ff_species_init(&s.sp[6], "ghost", RL_KIND_POINT, 10.0, 0, 0, 0, 0);
  const int cnt[7] = {40, 15, 8, 10, 5, 1, 7};
  const double L = 1.5;
  scene_build(&s, rng, RL_UNITS_REAL, cnt, 0.0, 0.26, L);
  rl_system *sys = s.sys;
  int n = 0;
  for (int k = 0; k < 7; k++) n += cnt[k];
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = 0.6;
  for (int scheme = 0; scheme < 2; scheme++) {
    p.scheme = (rl_cutoff_scheme)scheme;
    p.kernel = RL_KERNEL_GENERAL;
    p.threads = 0;
    rl_forcefield *fg = rl_forcefield_alloc(sys, &p, s.sff, 7), *fa[3];
    assert_non_null(fg);
    p.kernel = RL_KERNEL_AUTO;
    for (int t = 0; t < 3; t++) {
      p.threads = t + 1;
      fa[t] = rl_forcefield_alloc(sys, &p, s.sff, 7);
      assert_non_null(fa[t]);
    }
    FF_CHECK_TRUE("small-box mixture: kernels and the reference path",
                  strcmp(rl_forcefield_kernel(fa[0]), "tip4p+stockmayer+charge-lj+general") == 0);
    for (int step = 0; step < 4; step++) {
      char what[200];
      for (int t = 0; t < 3; t++) {
        snprintf(what, sizeof what, "small-box mixture, %s cutoff, %d thread(s), step %d",
                 scheme ? "molecule" : "site", t + 1, step);
        compare(fa[t], fg, sys, what, 1e-12);
        if (t) {
          snprintf(what, sizeof what, "small-box mixture, %s cutoff, 1 vs %d threads, step %d",
                   scheme ? "molecule" : "site", t + 1, step);
          compare(fa[0], fa[t], sys, what, 1e-13);
        }
      }
      for (int i = 0; i < n; i++) { /* beyond half the skin: the next compute rebuilds */
        double q[3];
        rl_system_get_position(sys, i, q);
        for (int c = 0; c < 3; c++) q[c] += gsl_ran_flat(rng, -0.03, 0.03);
        rl_system_set_position(sys, i, q);
      }
    }
    FF_CHECK_TRUE("small-box mixture: the kernels' list was rebuilt", rl_forcefield_rebuilds(fa[1]) > 1);
    for (int t = 0; t < 3; t++) rl_forcefield_free(fa[t]);
    rl_forcefield_free(fg);
  }
  rl_system_free(sys);
  gsl_rng_free(rng);
}

/* 256 TIP4P-like waters in a box of 1.97 nm at rc = 0.9 nm, where a neighbour can be within
 * the pruning radius through two images of its centre (the AVX2 rows' image list, build_images
 * in ff_fast.c, and the other fills' images).  The bodies move by less than half the skin between
 * computes, so the list is not rebuilt, while pairs near half the box edge change which image
 * is the nearest: each compute against the reference path. */
static void water_box(scene *s, gsl_rng *rng, rl_ff_params *p, int count, double rc)
{
  *s = (scene){.nsp = 1};
  ff_water(&s->sp[0]);
  int cnt[1] = {count};
  scene_build(s, rng, RL_UNITS_REAL, cnt, 33.4, 0.25, 0.0);
  rl_ff_params_default(p);
  p->cutoff = rc;
}

static void nudge(rl_system *sys, gsl_rng *rng, double a)
{
  for (int i = 0; i < rl_system_count(sys); i++) {
    double q[3];
    rl_system_get_position(sys, i, q);
    for (int c = 0; c < 3; c++) q[c] += gsl_ran_flat(rng, -a, a);
    rl_system_set_position(sys, i, q);
    ff_random_orientation(sys, i, rng);
  }
}

static void test_image_list(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 19);
  scene s;
  rl_ff_params p;
  water_box(&s, rng, &p, 256, 0.9);
  p.skin = 0.2;
  for (int k = 0; k < NPATH; k++) {
    set_path(k);
    for (int t = 1; t <= 2; t++) {
      rl_forcefield *fa = make(&s, &p, RL_KERNEL_AUTO, t), *fg = make(&s, &p, RL_KERNEL_GENERAL, 0);
      for (int step = 0; step < 4; step++) {
        char what[200];
        snprintf(what, sizeof what, "256 waters, L = %.3f nm, rc 0.9, %d thread(s)%s, move %d",
                 s.L, t, path_label[k], step);
        compare(fa, fg, s.sys, what, 1e-12);
        nudge(s.sys, rng, 0.012); /* three moves: < 0.063 from the list's origin < skin / 2 */
      }
      char what[200];
      snprintf(what, sizeof what, "256 waters%s, %d thread(s): one list build for the moves", path_label[k], t);
      FF_CHECK_TRUE(what, rl_forcefield_rebuilds(fa) == 1);
      rl_forcefield_free(fa);
      rl_forcefield_free(fg);
    }
  }
  set_path(0);
  /* 64 waters at rc = 0.6 nm (L = 1.24 nm) with a skin of 0.3 nm (rlist 1.08 nm): the image
   * list holds 2.8 entries per listed pair (2,016 pairs, 5,668 images), more than its first
   * allocation, so it grows while it is built */
  {
    scene w;
    rl_ff_params q;
    water_box(&w, rng, &q, 64, 0.6);
    q.skin = 0.3;
    for (int t = 1; t <= 2; t++) {
      rl_forcefield *fa = make(&w, &q, RL_KERNEL_AUTO, t), *fg = make(&w, &q, RL_KERNEL_GENERAL, 0);
      char what[120];
      snprintf(what, sizeof what, "64 waters, L = %.3f nm, rc 0.6, %d thread(s)", w.L, t);
      compare(fa, fg, w.sys, what, 1e-12);
      rl_forcefield_free(fa);
      rl_forcefield_free(fg);
    }
    rl_system_free(w.sys);
  }
  /* a smaller box for the same bodies (rl_system_set_box), no body moved: new neighbours
   * come within range through the new images, so the kernels' list must be rebuilt */
  rl_forcefield *fa = make(&s, &p, RL_KERNEL_AUTO, 1), *fg = make(&s, &p, RL_KERNEL_GENERAL, 0);
  compare(fa, fg, s.sys, "256 waters before the box shrinks", 1e-12);
  const double L2[3] = {0.93 * s.L, 0.93 * s.L, 0.93 * s.L};
  assert_int_equal(rl_system_set_box(s.sys, L2), RL_OK); /* both force fields follow it */
  compare(fa, fg, s.sys, "256 waters after rl_system_set_box to 0.93 L", 1e-12);
  /* following the system's box (p.box left 0) is being made for it: bit for bit a force field
   * built in the new box, on each path */
  double Lf[3];
  rl_forcefield_get_box(fa, Lf);
  FF_CHECK_TRUE("the force field reports the system's new box",
                Lf[0] == L2[0] && Lf[1] == L2[1] && Lf[2] == L2[2]);
  rl_forcefield *na = make(&s, &p, RL_KERNEL_AUTO, 1), *ng = make(&s, &p, RL_KERNEL_GENERAL, 0);
  compare(fa, na, s.sys, "kernels: after rl_system_set_box vs a force field made in the new box", 0.0);
  compare(fg, ng, s.sys, "reference: after rl_system_set_box vs a force field made in the new box", 0.0);
  rl_forcefield_free(na);
  rl_forcefield_free(ng);
  rl_forcefield_free(fa);
  rl_forcefield_free(fg);
  rl_system_free(s.sys);
  gsl_rng_free(rng);
}

/* Mixed precision (p.precision = RL_PRECISION_MIXED): the "tip4p" AVX2 rows in single
 * precision against the double reference path, both cutoff schemes and every LJ truncation,
 * in a box with and without other images.  Each term's separation and 1/r carry a relative
 * error of about 1e-7 (float's unit round-off 6e-8; vrsqrtps and one Newton step), sums are
 * double: measured here up to 2e-6 (forces, relative to the largest force), below 1e-6 for the
 * energies and the virial, so the bound is 2e-5.  A "mixed" that computed in double would
 * differ by 1e-14: it must differ by more than 1e-9.  Without AVX2 the precision in use is
 * double, and so are the results. */
/* The two water scenes of the mixed-precision and Ewald tests: 400 waters (box 0), 256 in a box
 * with L < 2 rp (box 1). */
static void two_waters(scene *s, gsl_rng *rng, rl_ff_params *p, int box)
{
  if (box) water_box(s, rng, p, 256, 0.9);
  else neat_scene(s, rng, 1, p);
}

static void test_mixed_precision(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 20);
  for (int box = 0; box < 2; box++) {
    scene s;
    rl_ff_params p;
    two_waters(&s, rng, &p, box);
    for (int scheme = 0; scheme < 2; scheme++)
      for (int tr = 0; tr < 4; tr++) {
        p.scheme = (rl_cutoff_scheme)scheme;
        p.lj_truncation = (rl_lj_truncation)tr;
        p.r_switch = 0.8 * p.cutoff;
        p.precision = RL_PRECISION_MIXED;
        rl_forcefield *fm = make(&s, &p, RL_KERNEL_AUTO, 2), *fm2 = make(&s, &p, RL_KERNEL_AUTO, 2);
        p.precision = RL_PRECISION_DOUBLE;
        rl_forcefield *fd = make(&s, &p, RL_KERNEL_AUTO, 2), *fg = make(&s, &p, RL_KERNEL_GENERAL, 0);
        char what[200];
        snprintf(what, sizeof what, "mixed, %s, %s cutoff, LJ %s", box ? "256 waters, L < 2 rp" : "400 waters",
                 scheme ? "molecule" : "site", trunc_name[tr]);
        const int avx2 = strcmp(expected_rows(1), "avx2") == 0;
        char nm[320];
        snprintf(nm, sizeof nm, "%s: precision '%s' (expected '%s')", what, rl_forcefield_precision(fm),
                 avx2 ? "mixed" : "double");
        FF_CHECK_TRUE(nm, strcmp(rl_forcefield_precision(fm), avx2 ? "mixed" : "double") == 0);
        FF_CHECK_TRUE("the double kernels say 'double'", strcmp(rl_forcefield_precision(fd), "double") == 0);
        compare(fm, fg, s.sys, what, 2e-5);
        const double dd = compare(fm, fd, s.sys, "mixed against the double kernels", 2e-5);
        snprintf(nm, sizeof nm, "%s: differs from double (%.1e) as %s", what, dd,
                 avx2 ? "single precision must" : "double must not");
        FF_CHECK_TRUE(nm, avx2 ? dd > 1e-9 : dd == 0.0);
        compare(fm, fm2, s.sys, "mixed, 2 threads, twice: bit for bit", 0.0);
        rl_forcefield_free(fm);
        rl_forcefield_free(fm2);
        rl_forcefield_free(fd);
        rl_forcefield_free(fg);
      }
    rl_system_free(s.sys);
  }
  gsl_rng_free(rng);
}

/* The Ewald real space (coulomb = RL_COULOMB_EWALD_REAL, kernels/elec/ewald.h): every row path of
 * the TIP4P and charge-lj kernels against the reference routine, whose erfc and exp are the C
 * library's, at alpha rc = 2.6 (tolerance 5e-4) and 4.9 (both pieces of the erfc polynomial), in
 * a large box and one with L < 2 rp (the image list); 1 against 2 and 3 threads; the mixed
 * precision falls back to double; the Stockmayer kernel's dipolar rows likewise; what the Ewald
 * real space refuses. */
static void test_ewald(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 21);
  for (int box = 0; box < 2; box++) {
    scene s;
    rl_ff_params p;
    two_waters(&s, rng, &p, box);
    p.coulomb = RL_COULOMB_EWALD_REAL;
    for (int a = 0; a < 2; a++) {
      p.ewald_alpha = (a ? 4.9 : 2.6) / p.cutoff;
      for (int k = 0; k < NPATH; k++) {
        char what[160];
        snprintf(what, sizeof what, "ewald, alpha rc %.1f, tip4p (%s)%s", p.ewald_alpha * p.cutoff,
                 box ? "256, L < 2 rp" : "400", path_label[k]);
        set_path(k);
        sweep(&s, &p, what, "tip4p");
      }
      set_path(0);
    }
    p.lj_truncation = RL_LJ_PLAIN;
    threads_neat(&s, &p, box ? "ewald, tip4p (256)" : "ewald, tip4p (400)");
    setenv("ROTLEAP_NO_AVX512", "1", 1);
    threads_neat(&s, &p, box ? "ewald, tip4p (256), ROTLEAP_NO_AVX512" : "ewald, tip4p (400), ROTLEAP_NO_AVX512");
    unsetenv("ROTLEAP_NO_AVX512");
    p.precision = RL_PRECISION_MIXED;
    rl_forcefield *fm = make(&s, &p, RL_KERNEL_AUTO, 1);
    FF_CHECK_TRUE("ewald, precision mixed: the pair terms run in double",
                  strcmp(rl_forcefield_precision(fm), "double") == 0);
    rl_tconf_sums ts;
    FF_CHECK_TRUE("ewald: rl_config_temperature (reaction field only) refuses",
                  rl_config_temperature(fm, s.sys, &ts) == RL_EINVAL);
    rl_forcefield_free(fm);
    p.precision = RL_PRECISION_DOUBLE;
    /* refused: the molecule cutoff, alpha <= 0, intramolecular_rf */
    rl_ff_params q = p;
    q.scheme = RL_CUTOFF_MOLECULE;
    FF_CHECK_TRUE("ewald with the molecule cutoff is refused", !rl_forcefield_alloc(s.sys, &q, s.sff, s.nsp));
    q = p;
    q.ewald_alpha = 0.0;
    FF_CHECK_TRUE("ewald with alpha 0 is refused", !rl_forcefield_alloc(s.sys, &q, s.sff, s.nsp));
    q = p;
    q.intramolecular_rf = 1;
    FF_CHECK_TRUE("ewald with intramolecular_rf is refused", !rl_forcefield_alloc(s.sys, &q, s.sff, s.nsp));
    rl_system_free(s.sys);
  }
  { /* charge-lj: CO2 */
    scene s = {.nsp = 1};
    ff_co2(&s.sp[0]);
    int cnt[1] = {300};
    scene_build(&s, rng, RL_UNITS_REAL, cnt, 12.0, 0.33, 0.0);
    rl_ff_params p;
    rl_ff_params_default(&p);
    p.cutoff = 0.8;
    p.coulomb = RL_COULOMB_EWALD_REAL;
    for (int a = 0; a < 2; a++) {
      p.ewald_alpha = (a ? 4.9 : 2.6) / p.cutoff;
      sweep(&s, &p, a ? "ewald, alpha rc 4.9, linear co2 (300)" : "ewald, alpha rc 2.6, linear co2 (300)", "charge-lj");
    }
    rl_system_free(s.sys);
  }
  { /* Stockmayer point dipoles: the dipole_lj_ewald rows, every path, against the reference
     * routine's rl_dipole_dipole_ewald (the C library's erfc and exp) */
    scene s;
    rl_ff_params p;
    neat_scene(&s, rng, 0, &p);
    p.coulomb = RL_COULOMB_EWALD_REAL;
    p.ewald_alpha = 2.6 / p.cutoff; /* alpha r from 0.94 to 2.6: both pieces of the erfc polynomial */
    for (int k = 0; k < NPATH; k++) {
      char what[160];
      snprintf(what, sizeof what, "ewald, alpha rc 2.6, stockmayer (500)%s", path_label[k]);
      set_path(k);
      sweep(&s, &p, what, "stockmayer");
    }
    set_path(0);
    rl_system_free(s.sys);
  }
  { /* refused: dipoles off the centre of a molecule, and dipoles beside charges */
    for (int c = 0; c < 2; c++) {
      scene s = {.nsp = c ? 2 : 1};
      if (c) {
        ff_stockmayer(&s.sp[0], 0.05);
        ff_ion(&s.sp[1], 1.0);
      } else {
        ff_symtop(&s.sp[0]);
        s.sp[0].charge[1] = s.sp[0].charge[2] = s.sp[0].charge[3] = 0.0; /* no charges: only the off-centre dipole */
      }
      int cnt[2] = {60, 10};
      scene_build(&s, rng, RL_UNITS_REAL, cnt, 20.0, 0.3, 0.0);
      rl_ff_params p;
      rl_ff_params_default(&p);
      p.cutoff = 0.6;
      p.coulomb = RL_COULOMB_EWALD_REAL;
      p.ewald_alpha = 3.0 / p.cutoff;
      FF_CHECK_TRUE(c ? "ewald with point dipoles beside charges is refused"
                      : "ewald with a dipole on a many-site molecule is refused",
                    !rl_forcefield_alloc(s.sys, &p, s.sff, s.nsp));
      FF_CHECK_TRUE("  naming the dipole", strstr(rl_last_error(), "point dipole") != NULL);
      rl_system_free(s.sys);
    }
  }
  gsl_rng_free(rng);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_tip4p),   cmocka_unit_test(test_periodic_edge),
      cmocka_unit_test(test_stockmayer), cmocka_unit_test(test_charge_lj),
      cmocka_unit_test(test_mixture), cmocka_unit_test(test_threads_neat),
      cmocka_unit_test(test_forces_only), cmocka_unit_test(test_choice),
      cmocka_unit_test(test_overlap), cmocka_unit_test(test_site_order_and_small_box),
      cmocka_unit_test(test_small_box_mixture), cmocka_unit_test(test_image_list),
      cmocka_unit_test(test_mixed_precision), cmocka_unit_test(test_ewald),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
