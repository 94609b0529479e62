/* rotleap — observables: radial distribution functions (periodic orthorhombic box, minimum
 * image, ideal-gas shell normalisation) and a distance between two RDFs. */
#include "rotleap/observables.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rotleap/error.h"

struct rl_rdf {
  double r_max, dr;
  int nbins;
  long frames;
  double *hist;     /* [nbins] ordered pair counts summed over frames        */
  double pair_dens; /* sum over frames of P / V (allowed ordered pairs / volume) */
  double na_sum;    /* sum over frames of na                                    */
  /* the totals before frames 0, S, 2S, ... (rl_rdf_get_from): marks [nmarks] */
  long mark_every;  /* S */
  int nmarks, mark_alloc;
  double *mark_hist; /* [mark_alloc][nbins] */
  double *mark_pd, *mark_na;
};

rl_rdf *rl_rdf_alloc(double r_max, int nbins)
{
  if (!(r_max > 0.0) || !isfinite(r_max) || nbins < 1) {
    rl_error(RL_EINVAL, "rl_rdf_alloc: need r_max > 0 (%g) and nbins >= 1 (%d)", r_max, nbins);
    return NULL;
  }
  rl_rdf *g = calloc(1, sizeof *g);
  if (g) g->hist = calloc((size_t)nbins, sizeof *g->hist);
  if (!g || !g->hist) {
    rl_rdf_free(g);
    rl_error(RL_ENOMEM, "rl_rdf_alloc: out of memory");
    return NULL;
  }
  g->r_max = r_max;
  g->nbins = nbins;
  g->dr = r_max / nbins;
  g->mark_every = 1;
  return g;
}

void rl_rdf_free(rl_rdf *g)
{
  if (!g) return;
  free(g->hist);
  free(g->mark_hist);
  free(g->mark_pd);
  free(g->mark_na);
  free(g);
}

void rl_rdf_reset(rl_rdf *g)
{
  if (!g) return;
  for (int k = 0; k < g->nbins; k++) g->hist[k] = 0.0;
  g->frames = 0;
  g->pair_dens = g->na_sum = 0.0;
  g->nmarks = 0;
  g->mark_every = 1;
}

/* L positive and finite, r_max within half its shortest edge. */
static int check_box(const rl_rdf *g, const double L[3])
{
  double Lmin = fmin(L[0], fmin(L[1], L[2]));
  if (!(Lmin > 0.0) || !isfinite(L[0] * L[1] * L[2]))
    return rl_error(RL_EINVAL, "rl_rdf_add: box edges must be positive and finite");
  if (g->r_max > 0.5 * Lmin * (1.0 + 1e-12))
    return rl_error(RL_EINVAL, "rl_rdf_add: r_max = %g exceeds half the shortest box edge (%g)", g->r_max,
                    0.5 * Lmin);
  return RL_OK;
}

/* The pair counts of one frame (rl_rdf_add's arguments), nothing added.  out hist[nbins]. */
static int count_frame(const rl_rdf *g, const double L[3], const double (*a)[3], int na, const int *mol_a,
                       const double (*b)[3], int nb, const int *mol_b, uint32_t *hist, double *pairs)
{
  if (!g || !L || (na > 0 && !a) || (nb > 0 && !b) || na < 0 || nb < 0)
    return rl_error(RL_EINVAL, "rl_rdf_add: NULL argument or negative count");
  if ((mol_a == NULL) != (mol_b == NULL))
    return rl_error(RL_EINVAL, "rl_rdf_add: give molecule labels for both sets or for neither");
  int st = check_box(g, L);
  if (st) return st;
  double rmax2 = g->r_max * g->r_max, inv_dr = 1.0 / g->dr;
  double excluded = 0.0;
  for (int k = 0; k < g->nbins; k++) hist[k] = 0;
  for (int i = 0; i < na; i++) {
    for (int j = 0; j < nb; j++) {
      if (mol_a && mol_a[i] == mol_b[j]) {
        excluded += 1.0;
        continue;
      }
      double r2 = 0.0;
      for (int d = 0; d < 3; d++) {
        double x = b[j][d] - a[i][d];
        x -= L[d] * round(x / L[d]);
        r2 += x * x;
      }
      if (!(r2 < rmax2)) {
        if (isnan(r2)) return rl_error(RL_ENONFINITE, "rl_rdf_add: non-finite position (a %d, b %d)", i, j);
        continue;
      }
      int k = (int)(sqrt(r2) * inv_dr);
      if (k < g->nbins && hist[k]++ == UINT32_MAX)
        return rl_error(RL_EINVAL, "rl_rdf_add: more than %u pairs in bin %d of one frame", UINT32_MAX, k);
    }
  }
  *pairs = (double)na * (double)nb - excluded;
  return RL_OK;
}

int rl_rdf_add(rl_rdf *g, const double L[3], const double (*a)[3], int na, const int *mol_a,
               const double (*b)[3], int nb, const int *mol_b)
{
  uint32_t *hist = g ? malloc(sizeof *hist * (size_t)g->nbins) : NULL;
  if (g && !hist) return rl_error(RL_ENOMEM, "rl_rdf_add: out of memory");
  double pairs = 0.0;
  int st = count_frame(g, L, a, na, mol_a, b, nb, mol_b, hist, &pairs);
  if (!st) st = rl_rdf_add_counts(g, L, hist, pairs, na);
  free(hist);
  return st;
}

/* Keep the totals before this frame when it is a multiple of S; RL_RDF_MARKS kept at most. */
static int mark(rl_rdf *g)
{
  if (g->frames % g->mark_every) return RL_OK;
  if (g->nmarks == RL_RDF_MARKS) { /* keep every other mark: S doubles */
    for (int k = 0; k < RL_RDF_MARKS / 2; k++) {
      memcpy(g->mark_hist + (size_t)k * (size_t)g->nbins, g->mark_hist + (size_t)(2 * k) * (size_t)g->nbins,
             sizeof(double) * (size_t)g->nbins);
      g->mark_pd[k] = g->mark_pd[2 * k];
      g->mark_na[k] = g->mark_na[2 * k];
    }
    g->nmarks = RL_RDF_MARKS / 2;
    g->mark_every *= 2;
    if (g->frames % g->mark_every) return RL_OK;
  }
  if (g->nmarks == g->mark_alloc) {
    const int alloc = g->mark_alloc ? 2 * g->mark_alloc : 16;
    double *h = realloc(g->mark_hist, sizeof(double) * (size_t)alloc * (size_t)g->nbins);
    if (h) g->mark_hist = h;
    double *pd = h ? realloc(g->mark_pd, sizeof(double) * (size_t)alloc) : NULL;
    if (pd) g->mark_pd = pd;
    double *nm = pd ? realloc(g->mark_na, sizeof(double) * (size_t)alloc) : NULL;
    if (!nm) return rl_error(RL_ENOMEM, "rl_rdf_add: out of memory for the marks of rl_rdf_get_from");
    g->mark_na = nm;
    g->mark_alloc = alloc;
  }
  memcpy(g->mark_hist + (size_t)g->nmarks * (size_t)g->nbins, g->hist, sizeof(double) * (size_t)g->nbins);
  g->mark_pd[g->nmarks] = g->pair_dens;
  g->mark_na[g->nmarks++] = g->na_sum;
  return RL_OK;
}

int rl_rdf_add_counts(rl_rdf *g, const double L[3], const uint32_t *hist, double pairs, int na)
{
  if (!g || !L || !hist) return rl_error(RL_EINVAL, "rl_rdf_add_counts: NULL argument");
  int st = check_box(g, L);
  if (st || (st = mark(g))) return st;
  for (int k = 0; k < g->nbins; k++) g->hist[k] += (double)hist[k];
  g->frames++;
  g->pair_dens += pairs / (L[0] * L[1] * L[2]);
  g->na_sum += na;
  return RL_OK;
}

int rl_rdf_count_sites(const rl_rdf *g, const rl_system *sys, int species_a, int site_a,
                       int species_b, int site_b, uint32_t *hist, double *pairs, int *na_out)
{
  if (!g || !sys || !hist || !pairs || !na_out) return rl_error(RL_EINVAL, "rl_rdf_add_sites: NULL argument");
  double L[3]; /* the system's box */
  rl_system_box(sys, L);
  int ns = rl_system_nspecies(sys);
  if (species_a < 0 || species_a >= ns || species_b < 0 || species_b >= ns)
    return rl_error(RL_EINVAL, "rl_rdf_add_sites: species %d or %d out of range (0..%d)", species_a, species_b,
                    ns - 1);
  if (site_a < 0 || site_a >= rl_system_species_nsites(sys, species_a) || site_b < 0 ||
      site_b >= rl_system_species_nsites(sys, species_b))
    return rl_error(RL_EINVAL, "rl_rdf_add_sites: site %d of species %d or site %d of species %d does not exist",
                    site_a, species_a, site_b, species_b);
  int n = rl_system_count(sys), nsites = rl_system_nsites(sys);
  int na = rl_system_species_count(sys, species_a), nb = rl_system_species_count(sys, species_b);
  double(*s)[3] = malloc(sizeof(double[3]) * (size_t)(nsites > 0 ? nsites : 1));
  double(*a)[3] = malloc(sizeof(double[3]) * (size_t)(na + nb + 1));
  int *mol = malloc(sizeof(int) * (size_t)(na + nb + 1));
  int st;
  if (!s || !a || !mol) {
    st = rl_error(RL_ENOMEM, "rl_rdf_add_sites: out of memory");
    goto done;
  }
  rl_system_site_positions(sys, s);
  int ia = 0, ib = na;
  for (int i = 0; i < n; i++) {
    int sp = rl_system_species_of(sys, i), off = rl_system_site_offset(sys, i);
    if (sp == species_a) {
      for (int d = 0; d < 3; d++) a[ia][d] = s[off + site_a][d];
      mol[ia++] = i;
    }
    if (sp == species_b) {
      for (int d = 0; d < 3; d++) a[ib][d] = s[off + site_b][d];
      mol[ib++] = i;
    }
  }
  st = count_frame(g, L, (const double(*)[3])a, na, mol, (const double(*)[3])(a + na), nb, mol + na, hist, pairs);
  *na_out = na;
done:
  free(s);
  free(a);
  free(mol);
  return st;
}

int rl_rdf_add_sites(rl_rdf *g, const rl_system *sys, int species_a, int site_a,
                     int species_b, int site_b)
{
  uint32_t *hist = g ? malloc(sizeof *hist * (size_t)g->nbins) : NULL;
  if (g && !hist) return rl_error(RL_ENOMEM, "rl_rdf_add_sites: out of memory");
  double pairs = 0.0;
  int na = 0, st = rl_rdf_count_sites(g, sys, species_a, site_a, species_b, site_b, hist, &pairs, &na);
  if (!st) {
    double L[3];
    rl_system_box(sys, L);
    st = rl_rdf_add_counts(g, L, hist, pairs, na);
  }
  free(hist);
  return st;
}

int rl_rdf_nbins(const rl_rdf *g) { return g ? g->nbins : 0; }
double rl_rdf_rmax(const rl_rdf *g) { return g ? g->r_max : NAN; }
long rl_rdf_frames(const rl_rdf *g) { return g ? g->frames : 0; }

/* g(r) from the totals minus those of mark k (k < 0: none). */
static int get_since(const rl_rdf *g, int k, double *r, double *gr)
{
  const double *h0 = k >= 0 ? g->mark_hist + (size_t)k * (size_t)g->nbins : NULL;
  const double pd = g->pair_dens - (k >= 0 ? g->mark_pd[k] : 0.0);
  if (g->frames == 0 || (k >= 0 && (long)k * g->mark_every >= g->frames) || !(pd > 0.0))
    return rl_error(RL_ESTATE, "rl_rdf_get: no frame (or no allowed pair) accumulated yet");
  for (int b = 0; b < g->nbins; b++) {
    if (r) r[b] = (b + 0.5) * g->dr;
    if (gr) {
      double shell = 4.0 / 3.0 * M_PI * (pow(b + 1.0, 3) - pow((double)b, 3)) * g->dr * g->dr * g->dr;
      gr[b] = (g->hist[b] - (h0 ? h0[b] : 0.0)) / (pd * shell);
    }
  }
  return RL_OK;
}

int rl_rdf_get(const rl_rdf *g, double *r, double *gr)
{
  if (!g) return rl_error(RL_EINVAL, "rl_rdf_get: NULL rdf");
  return get_since(g, -1, r, gr);
}

int rl_rdf_get_from(const rl_rdf *g, long first, double *r, double *gr, long *used)
{
  if (!g) return rl_error(RL_EINVAL, "rl_rdf_get_from: NULL rdf");
  if (first <= 0) {
    if (used) *used = 0;
    return get_since(g, -1, r, gr);
  }
  const long k = (first + g->mark_every - 1) / g->mark_every;
  if (used) *used = k < g->nmarks ? k * g->mark_every : g->frames;
  if (k >= g->nmarks)
    return rl_error(RL_ESTATE, "rl_rdf_get_from: no frame from frame %ld on (%ld frames)", first, g->frames);
  return get_since(g, (int)k, r, gr);
}

double rl_rdf_coordination(const rl_rdf *g, double r_lo, double r_hi)
{
  if (!g || !(g->na_sum > 0.0)) return NAN;
  double c = 0.0;
  for (int k = 0; k < g->nbins; k++) {
    double rc = (k + 0.5) * g->dr;
    if (rc >= r_lo && rc < r_hi) c += g->hist[k];
  }
  return c / g->na_sum;
}

double rl_rdf_distance_arrays(const double *g1, const double *g2, int nbins, double dr)
{
  double d = 0.0;
  for (int k = 0; k < nbins; k++) d += fabs(g1[k] - g2[k]);
  return d * dr;
}

int rl_rdf_distance(const rl_rdf *g1, const rl_rdf *g2, double *d)
{
  if (!g1 || !g2 || !d) return rl_error(RL_EINVAL, "rl_rdf_distance: NULL argument");
  if (g1->nbins != g2->nbins || fabs(g1->r_max - g2->r_max) > 1e-12 * g1->r_max)
    return rl_error(RL_EINVAL, "rl_rdf_distance: different binning (%d bins to %g vs %d bins to %g)", g1->nbins,
                    g1->r_max, g2->nbins, g2->r_max);
  double *a = malloc(sizeof(double) * 2 * (size_t)g1->nbins);
  if (!a) return rl_error(RL_ENOMEM, "rl_rdf_distance: out of memory");
  int st = rl_rdf_get(g1, NULL, a);
  if (!st) st = rl_rdf_get(g2, NULL, a + g1->nbins);
  if (!st) *d = rl_rdf_distance_arrays(a, a + g1->nbins, g1->nbins, g1->dr);
  free(a);
  return st;
}
