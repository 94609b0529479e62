/* Verlet list + cell list against the brute-force O(N^2) sum on random liquid-like
 * configurations (water-like asymmetric bodies, point dipoles, ions), both cutoff schemes:
 * energies and forces/torques agree to 1e-12 relative; small moves reuse the list; pure
 * rotations, however large, reuse it and stay exact (the list radius holds twice the extent);
 * large translations trigger a rebuild.  Also: cell-list builds give the same
 * pair set as the all-pairs scan, and the kernels' layout (rl_rowlist: rows by rank, from its
 * cells or its all-pairs scan, scalar or AVX-512, on 1 and 2 threads) lists the same pairs as
 * the reference layout, split by species into kernel and reference neighbours, with an image
 * list that holds every image of a neighbour within the list radius once. */
#include "ff_testutil.h"

#include "../../forces/pair/pairlist.h"

typedef struct {
  ff_test_species sp[3];
  rl_species_ff sff[3];
  rl_system *sys;
  double L;
} liquid;

static void liquid_build(liquid *lq, gsl_rng *rng, int nw, int nd, int ni)
{
  memset(lq, 0, sizeof *lq);
  lq->sys = rl_system_alloc(RL_UNITS_REAL);
  ff_water(&lq->sp[0]);
  ff_stockmayer(&lq->sp[1], 0.04);
  ff_ion(&lq->sp[2], 0.7);
  int cnt[3] = {nw, nd, ni};
  for (int k = 0; k < 3; k++) {
    lq->sp[k].desc.sites = &lq->sp[k].sites[0][0];
    assert_int_equal(rl_system_add_species(lq->sys, &lq->sp[k].desc, cnt[k], NULL), RL_OK);
    lq->sff[k] = ff_test_species_ff(&lq->sp[k]);
  }
  int n = nw + nd + ni;
  lq->L = cbrt(n / 33.4);
  double(*r)[3] = malloc(sizeof *r * (size_t)n);
  for (int i = 0; i < n; i++) {
    for (int tries = 0;; tries++) {
      assert_true(tries < 1000000);
      double x[3];
      for (int c = 0; c < 3; c++) x[c] = gsl_ran_flat(rng, 0.0, lq->L);
      int ok = 1;
      for (int j = 0; j < i && ok; j++) {
        double d2 = 0.0;
        for (int c = 0; c < 3; c++) {
          double d = x[c] - r[j][c];
          d -= lq->L * nearbyint(d / lq->L);
          d2 += d * d;
        }
        ok = d2 >= 0.24 * 0.24;
      }
      if (ok) {
        memcpy(r[i], x, sizeof x);
        break;
      }
    }
    rl_system_set_position(lq->sys, i, r[i]);
    ff_random_orientation(lq->sys, i, rng);
  }
  free(r);
}

static void compare(rl_forcefield *list, rl_forcefield *brute, rl_system *sys, const char *what)
{
  ff_result a, b;
  ff_result_compute(&a, list, sys);
  ff_result_compute(&b, brute, sys);
  char name[200];
  snprintf(name, sizeof name, "nlist %s: |E_list - E_brute| / |E_brute|", what);
  FF_CHECK_LE(name, fabs(a.out.energy - b.out.energy) / fabs(b.out.energy), 1e-12);
  snprintf(name, sizeof name, "nlist %s: max |f_list - f_brute| / max |f|", what);
  FF_CHECK_LE(name, ff_maxdiff((const double(*)[3])a.f, (const double(*)[3])b.f, a.n) /
                        ff_maxnorm((const double(*)[3])b.f, b.n), 1e-12);
  snprintf(name, sizeof name, "nlist %s: max |k_list - k_brute| / max |k|", what);
  FF_CHECK_LE(name, ff_maxdiff((const double(*)[3])a.k, (const double(*)[3])b.k, a.nrot) /
                        ff_maxnorm((const double(*)[3])b.k, b.nrot), 1e-12);
  double vd = 0.0, vs = 0.0;
  for (int c = 0; c < 9; c++) {
    vd = fmax(vd, fabs(a.out.virial[c] - b.out.virial[c]));
    vs = fmax(vs, fabs(b.out.virial[c]));
  }
  snprintf(name, sizeof name, "nlist %s: max |W_list - W_brute| / max |W|", what);
  FF_CHECK_LE(name, vd / vs, 1e-12);
  ff_result_free(&a);
  ff_result_free(&b);
}

static void run_scheme(rl_cutoff_scheme scheme, unsigned long seed)
{
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, seed);
  liquid lq;
  liquid_build(&lq, rng, 700, 80, 20);
  rl_system *sys = lq.sys;
  int n = rl_system_count(sys);
  const double box[3] = {lq.L, lq.L, lq.L};
  assert_int_equal(rl_system_set_box(sys, box), RL_OK);
  rl_ff_params p;
  rl_ff_params_default(&p);
  p.cutoff = 0.7;
  p.skin = 0.06;
  p.scheme = scheme;
  p.lj_truncation = RL_LJ_SHIFTED;
  p.dispersion_correction = 1;
  rl_forcefield *list = rl_forcefield_alloc(sys, &p, lq.sff, 3);
  assert_non_null(list);
  p.neighbor_list = 0;
  rl_forcefield *brute = rl_forcefield_alloc(sys, &p, lq.sff, 3);
  assert_non_null(brute);
  const char *sn = scheme == RL_CUTOFF_SITE ? "site" : "molecule";
  char what[120];

  snprintf(what, sizeof what, "%s cutoff, %d bodies, initial", sn, n);
  compare(list, brute, sys, what);
  FF_CHECK_TRUE("nlist: first compute builds the list once", rl_forcefield_rebuilds(list) == 1);

  /* small moves: every site moves < skin/4, the list must be reused */
  for (int i = 0; i < n; i++) {
    double r[3];
    rl_system_get_position(sys, i, r);
    for (int c = 0; c < 3; c++) r[c] += gsl_ran_flat(rng, -0.004, 0.004);
    rl_system_set_position(sys, i, r);
    double ax[3] = {gsl_ran_gaussian(rng, 1), gsl_ran_gaussian(rng, 1), gsl_ran_gaussian(rng, 1)};
    double nn = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]), R[9];
    for (int c = 0; c < 3; c++) ax[c] /= nn;
    ff_rotation(ax, 0.04, R);
    ff_rotate_body(sys, i, R);
  }
  snprintf(what, sizeof what, "%s cutoff, small moves (list reused)", sn);
  compare(list, brute, sys, what);
  FF_CHECK_TRUE("nlist: small moves (< skin/2) do not rebuild", rl_forcefield_rebuilds(list) == 1);

  /* pure rotations, every body turned at random: H sites move ~0.1 nm > skin/2, yet the list
   * stays valid (its radius includes twice the extent) and the sums must stay exact */
  for (int i = 0; i < n; i++) ff_random_orientation(sys, i, rng);
  snprintf(what, sizeof what, "%s cutoff, every body turned at random (list reused)", sn);
  compare(list, brute, sys, what);
  FF_CHECK_TRUE("nlist: pure rotations reuse the list", rl_forcefield_rebuilds(list) == 1);

  /* large displacements: everything moves by up to 0.3 nm and turns at random */
  for (int i = 0; i < n; i++) {
    double r[3];
    rl_system_get_position(sys, i, r);
    for (int c = 0; c < 3; c++) r[c] += gsl_ran_flat(rng, -0.3, 0.3);
    rl_system_set_position(sys, i, r);
    ff_random_orientation(sys, i, rng);
  }
  snprintf(what, sizeof what, "%s cutoff, large displacements", sn);
  compare(list, brute, sys, what);
  FF_CHECK_TRUE("nlist: large displacements trigger a rebuild", rl_forcefield_rebuilds(list) == 2);

  /* a random walk of small steps: the list is rebuilt when (and only when) needed */
  long before = rl_forcefield_rebuilds(list);
  for (int step = 0; step < 12; step++) {
    for (int i = 0; i < n; i++) {
      double r[3];
      rl_system_get_position(sys, i, r);
      for (int c = 0; c < 3; c++) r[c] += gsl_ran_flat(rng, -0.01, 0.01);
      rl_system_set_position(sys, i, r);
    }
    ff_result a, b;
    ff_result_compute(&a, list, sys);
    ff_result_compute(&b, brute, sys);
    double ee = fabs(a.out.energy - b.out.energy) / fabs(b.out.energy);
    double fe = ff_maxdiff((const double(*)[3])a.f, (const double(*)[3])b.f, a.n) /
                ff_maxnorm((const double(*)[3])b.f, b.n);
    ff_result_free(&a);
    ff_result_free(&b);
    snprintf(what, sizeof what, "nlist %s cutoff, walk step %2d: max(rel dE, rel df)", sn, step);
    FF_CHECK_LE(what, fmax(ee, fe), 1e-12);
  }
  long walks = rl_forcefield_rebuilds(list) - before;
  snprintf(what, sizeof what, "nlist %s cutoff: walk rebuilt the list (%ld times in 12 steps)",
           sn, walks);
  FF_CHECK_TRUE(what, walks >= 1 && walks < 12);

  rl_forcefield_free(list);
  rl_forcefield_free(brute);
  rl_system_free(sys);
  gsl_rng_free(rng);
}

static void test_site_scheme(void **state)
{
  (void)state;
  run_scheme(RL_CUTOFF_SITE, 101);
}

static void test_molecule_scheme(void **state)
{
  (void)state;
  run_scheme(RL_CUTOFF_MOLECULE, 102);
}

/* The cell-list build and the all-pairs scan find the same pairs. */
static void test_cells_vs_all_pairs(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 7);
  int n = 3000;
  double(*r)[3] = malloc(sizeof *r * (size_t)n);
  rl_box box;
  double L[3] = {4.0, 5.0, 4.5};
  assert_int_equal(rl_box_set(&box, L), RL_OK);
  for (int i = 0; i < n; i++)
    for (int c = 0; c < 3; c++) r[i][c] = gsl_ran_flat(rng, -2.0 * L[c], 3.0 * L[c]); /* unwrapped */
  rl_nlist *a = rl_nlist_alloc(0.1), *b = rl_nlist_alloc(0.1);
  assert_int_equal(rl_nlist_build(a, &box, 1.2, n, (const double(*)[3])r), RL_OK);
  assert_int_equal(rl_nlist_build(b, &box, 1.9, n, (const double(*)[3])r), RL_OK);
  FF_CHECK_TRUE("cells: rlist 1.2 in a 4 x 5 x 4.5 box uses cells", a->used_cells == 1);
  FF_CHECK_TRUE("cells: rlist 1.9 (< 3 cells along x) uses the all-pairs scan", b->used_cells == 0);
  /* pairs of a within 1.2 must equal the pairs of b within 1.2 */
  char *inA = calloc((size_t)n * (size_t)n, 1);
  long cntA = 0, cntB = 0, missing = 0;
  for (long k = 0; k < a->npairs; k++) {
    inA[(size_t)a->pairs[k][0] * (size_t)n + (size_t)a->pairs[k][1]] = 1;
    cntA++;
  }
  for (long k = 0; k < b->npairs; k++) {
    int i = b->pairs[k][0], j = b->pairs[k][1];
    double d[3] = {r[i][0] - r[j][0], r[i][1] - r[j][1], r[i][2] - r[j][2]};
    rl_box_minimum_image(&box, d);
    if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < 1.2 * 1.2) {
      cntB++;
      if (!inA[(size_t)i * (size_t)n + (size_t)j]) missing++;
    }
  }
  char name[160];
  snprintf(name, sizeof name, "cells: same pair set as all-pairs scan (%ld pairs, %ld missing)",
           cntA, missing);
  FF_CHECK_TRUE(name, cntA == cntB && missing == 0);
  free(inA);
  rl_nlist_free(a);
  rl_nlist_free(b);
  free(r);
  gsl_rng_free(rng);
}

/* Random unwrapped centres in box: n of them, the first n0 of species 0 (a kernel species),
 * the rest of species 1 (none). */
static double (*random_centres(gsl_rng *rng, const rl_box *box, int n))[3]
{
  double(*r)[3] = malloc(sizeof *r * (size_t)n);
  for (int i = 0; i < n; i++)
    for (int c = 0; c < 3; c++) r[i][c] = gsl_ran_flat(rng, -2.0 * box->L[c], 3.0 * box->L[c]);
  return r;
}

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(ROTLEAP_NO_CLONES)
#define HAVE_REGISTER_ROWS 1 /* the AVX-512 scan and the (AVX2) image list are compiled */
#else
#define HAVE_REGISTER_ROWS 0
#endif

/* The pairs of a rows list as a matrix in[i n + j] (i < j, bodies); 0 if a pair is listed twice
 * or a kernel pair joins another species (or a reference pair two bodies of the kernel
 * species). */
static int rows_pairs(const rl_rowlist *L, int n, int n0, char *in, long *count)
{
  int ok = 1;
  *count = 0;
  for (int m = 0; m < n; m++) {
    const int i = L->ord[m];
    for (int q = L->fstart[m]; q < L->fstart[m + 1]; q++) {
      const int j = L->ord[L->fnbr[q]];
      ok &= L->fnbr[q] > m && i < n0 && j < n0;
      const int a = i < j ? i : j, b = i < j ? j : i;
      ok &= !in[(size_t)a * (size_t)n + (size_t)b];
      in[(size_t)a * (size_t)n + (size_t)b] = 1;
      (*count)++;
    }
    for (int q = L->gstart[m]; q < L->gstart[m + 1]; q++) {
      const int j = L->gnbr[q];
      ok &= !(i < n0 && j < n0);
      const int a = i < j ? i : j, b = i < j ? j : i;
      ok &= !in[(size_t)a * (size_t)n + (size_t)b];
      in[(size_t)a * (size_t)n + (size_t)b] = 1;
      (*count)++;
    }
  }
  return ok;
}

/* The kernels' layout lists the reference layout's pairs (one rule, two layouts: pairlist.h),
 * with cells (rlist 1.2: 6 x 8 x 7 cells of rlist / 2) and without (rlist 1.9: 4 per edge). */
static void test_rows_vs_pairs(void **state)
{
  (void)state;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 11);
  const int n = 1500, n0 = 1000;
  rl_box box;
  const double L[3] = {4.0, 5.0, 4.5};
  assert_int_equal(rl_box_set(&box, L), RL_OK);
  double(*r)[3] = random_centres(rng, &box, n);
  int *species = malloc(sizeof(int) * (size_t)n);
  for (int i = 0; i < n; i++) species[i] = i < n0 ? 0 : 1;
  const int count[2] = {n0, n - n0}, nsites[2] = {3, 1};
  const unsigned char kernel[2] = {1, 0};
  char *ref = calloc((size_t)n * (size_t)n, 1), *got = calloc((size_t)n * (size_t)n, 1);
  const double rlists[2] = {1.2, 1.9};
  for (int k = 0; k < 2; k++) {
    rl_nlist *nl = rl_nlist_alloc(0.1);
    assert_int_equal(rl_nlist_build(nl, &box, rlists[k], n, (const double(*)[3])r), RL_OK);
    memset(ref, 0, (size_t)n * (size_t)n);
    for (long q = 0; q < nl->npairs; q++)
      ref[(size_t)nl->pairs[q][0] * (size_t)n + (size_t)nl->pairs[q][1]] = 1;
    for (int scan512 = 0; scan512 <= HAVE_REGISTER_ROWS; scan512++)
      for (int threads = 1; threads <= 2; threads++) {
        if (scan512 && !__builtin_cpu_supports("avx512f")) continue;
        rl_rowlist *rows = rl_rowlist_alloc(n, threads, 0.1);
        assert_non_null(rows);
        const rl_rowlist_in in = {&box, rlists[k], n, 2, (const double(*)[3])r, species,
                                  count, nsites, kernel, NULL, scan512};
        assert_int_equal(rl_rowlist_build(rows, &in), RL_OK);
        memset(got, 0, (size_t)n * (size_t)n);
        long cnt;
        const int split = rows_pairs(rows, n, n0, got, &cnt);
        char name[200];
        snprintf(name, sizeof name, "rows rlist %.1f, %s scan, %d thread%s: %ld pairs, each once, "
                 "split by species", rlists[k], scan512 ? "AVX-512" : "scalar", threads,
                 threads > 1 ? "s" : "", cnt);
        FF_CHECK_TRUE(name, split && cnt > 0);
        snprintf(name, sizeof name, "rows rlist %.1f: the reference layout's %ld pairs",
                 rlists[k], nl->npairs);
        FF_CHECK_TRUE(name, cnt == nl->npairs && !memcmp(ref, got, (size_t)n * (size_t)n));
        rl_rowlist_free(rows);
      }
    rl_nlist_free(nl);
  }
  free(ref);
  free(got);
  free(species);
  free(r);
  gsl_rng_free(rng);
}

/* The image list of a small box (edges 2.0-2.4 < 2 rlist): for every row, exactly the images
 * c_i - c_j + s of its kernel neighbours j (s a multiple of the edges) within rlist, each once.
 * Only where the build has the AVX2 rows and the CPU runs them. */
static void test_image_rows(void **state)
{
  (void)state;
  if (!HAVE_REGISTER_ROWS || !__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) {
    printf("check image list: no AVX2 rows in this build or CPU, skipped\n");
    return;
  }
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 12);
  const int n = 300;
  rl_box box;
  const double L[3] = {2.0, 2.4, 2.2}, rlist = 1.05;
  assert_int_equal(rl_box_set(&box, L), RL_OK);
  double(*r)[3] = random_centres(rng, &box, n);
  int *species = calloc((size_t)n, sizeof(int));
  const int count[1] = {n}, nsites[1] = {4};
  const unsigned char kernel[1] = {1}, images[1] = {1};
  rl_rowlist *rows = rl_rowlist_alloc(n, 1, 0.1);
  const rl_rowlist_in in = {&box, rlist, n, 1, (const double(*)[3])r, species, count, nsites,
                            kernel, images, 0};
  assert_int_equal(rl_rowlist_build(rows, &in), RL_OK);
  FF_CHECK_TRUE("image list: built", rows->ximages == 1);
  long listed = 0, expected = 0, wrong = 0, more = 0;
  for (int m = 0; m < n; m++) {
    const int i = rows->ord[m];
    /* expected: every image of every kernel neighbour within rlist */
    for (int q = rows->fstart[m]; q < rows->fstart[m + 1]; q++) {
      const int j = rows->ord[rows->fnbr[q]];
      for (int a = -2; a <= 2; a++)
        for (int b = -2; b <= 2; b++)
          for (int c = -2; c <= 2; c++) {
            const double s[3] = {a * L[0], b * L[1], c * L[2]};
            double d[3], d2 = 0.0;
            for (int x = 0; x < 3; x++) {
              d[x] = r[i][x] - r[j][x];
              d[x] -= L[x] * nearbyint(d[x] / L[x]);
              d[x] += s[x];
              d2 += d[x] * d[x];
            }
            if (d2 >= rlist * rlist) continue;
            expected++;
            more += a || b || c;
            /* listed once with its shift (up to round-off of the shift) */
            int found = 0;
            for (int e = rows->xstart[m]; e < rows->xstart[m + 1]; e++) {
              if (rows->ord[rows->xnbr[e]] != j) continue;
              double y2 = 0.0;
              for (int x = 0; x < 3; x++) {
                const double y = r[i][x] - r[j][x] + rows->xs[x][e] - d[x];
                y2 += y * y;
              }
              found += y2 < 1e-18;
            }
            wrong += found != 1;
          }
    }
    listed += rows->xstart[m + 1] - rows->xstart[m];
  }
  char name[200];
  snprintf(name, sizeof name, "image list: %ld entries, %ld images within rlist (%ld not the "
           "minimum one), each once", listed, expected, more);
  FF_CHECK_TRUE(name, wrong == 0 && listed == expected && more > 0);
  rl_rowlist_free(rows);
  free(species);
  free(r);
  gsl_rng_free(rng);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_cells_vs_all_pairs),
      cmocka_unit_test(test_rows_vs_pairs),
      cmocka_unit_test(test_image_rows),
      cmocka_unit_test(test_site_scheme),
      cmocka_unit_test(test_molecule_scheme),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
