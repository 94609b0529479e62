/* rotleap — observables: scalar series (Welford moments, on-line Flyvbjerg-Petersen blocking),
 * fixed-block averages, running relative fluctuations and heat capacities from fluctuations.
 * Formulas and references: docs/observables.md. */
#include "rotleap/observables.h"

#include <math.h>
#include <stdlib.h>

#include "rotleap/error.h"

typedef struct {
  long n;
  double mean, m2; /* Welford: m2 = sum (x - mean)^2 */
  int pending;
  double held;     /* first half of the next block of the level above */
} level_acc;

struct rl_series {
  level_acc lv[RL_BLOCK_MAX_LEVELS];
};

static void welford(long *n, double *mean, double *m2, double x)
{
  (*n)++;
  double d = x - *mean;
  *mean += d / (double)*n;
  *m2 += d * (x - *mean);
}

rl_series *rl_series_alloc(void)
{
  rl_series *s = calloc(1, sizeof *s);
  if (!s) rl_error(RL_ENOMEM, "rl_series_alloc: out of memory");
  return s;
}

void rl_series_free(rl_series *s) { free(s); }

void rl_series_reset(rl_series *s)
{
  if (s) *s = (rl_series){0};
}

int rl_series_add(rl_series *s, double x)
{
  if (!s) return rl_error(RL_EINVAL, "rl_series_add: NULL series");
  if (!isfinite(x)) return rl_error(RL_ENONFINITE, "rl_series_add: non-finite sample %g", x);
  for (int k = 0; k < RL_BLOCK_MAX_LEVELS; k++) {
    level_acc *l = &s->lv[k];
    welford(&l->n, &l->mean, &l->m2, x);
    if (!l->pending) {
      l->pending = 1;
      l->held = x;
      break;
    }
    l->pending = 0;
    x = 0.5 * (l->held + x);
  }
  return RL_OK;
}

long rl_series_count(const rl_series *s) { return s ? s->lv[0].n : 0; }

double rl_series_mean(const rl_series *s)
{
  return (s && s->lv[0].n > 0) ? s->lv[0].mean : NAN;
}

double rl_series_sd(const rl_series *s)
{
  return (s && s->lv[0].n > 0) ? sqrt(s->lv[0].m2 / (double)s->lv[0].n) : NAN;
}

double rl_series_rel_fluct(const rl_series *s)
{
  double m = rl_series_mean(s);
  if (!(m != 0.0) || isnan(m)) return NAN;
  return rl_series_sd(s) / fabs(m);
}

static void level_sem(const level_acc *l, int k, rl_block_level *out)
{
  double nb = (double)l->n;
  double var = l->m2 / nb; /* 1/n variance of the block means */
  out->level = k;
  out->nblocks = l->n;
  out->sem = sqrt(var / (nb - 1.0));
  out->sem_err = out->sem / sqrt(2.0 * (nb - 1.0));
}

int rl_series_block_levels(const rl_series *s, rl_block_level *levels, int nmax)
{
  if (!s) return 0;
  int m = 0;
  for (int k = 0; k < RL_BLOCK_MAX_LEVELS && s->lv[k].n >= 2; k++) {
    if (levels && m < nmax) level_sem(&s->lv[k], k, &levels[m]);
    m++;
  }
  return m;
}

/* The Lee-Needs-Towler level among lv[m] (levels with >= 4 blocks), with `naive` the error of
 * independent samples (level 0): sets r's level, sem, sem_err, sem_naive, tau and converged.
 * No level with 4 blocks: the naive error, a lower bound (converged = 0). */
static void choose_level(const rl_block_level *lv, int m, long n, double naive, rl_block_result *r)
{
  r->sem_naive = naive;
  r->converged = 0;
  int chosen = -1, last4 = -1;
  for (int j = 0; j < m; j++) {
    if (lv[j].nblocks < 4) break;
    last4 = j;
    const double ratio = naive > 0.0 ? lv[j].sem / naive : 1.0, B = ldexp(1.0, lv[j].level);
    if (B * B * B > 2.0 * (double)n * ratio * ratio * ratio * ratio) {
      chosen = j;
      r->converged = 1;
      break;
    }
  }
  if (chosen < 0) chosen = last4;
  r->level = chosen < 0 ? 0 : lv[chosen].level;
  r->sem = chosen < 0 ? naive : lv[chosen].sem;
  r->sem_err = chosen < 0 ? NAN : lv[chosen].sem_err;
  r->tau = naive > 0.0 ? 0.5 * (r->sem / naive) * (r->sem / naive) : 0.5;
}

int rl_series_block_average(const rl_series *s, rl_block_result *r)
{
  if (!s || !r) return rl_error(RL_EINVAL, "rl_series_block_average: NULL argument");
  long n = s->lv[0].n;
  if (n < 4) return rl_error(RL_EINVAL, "rl_series_block_average: %ld samples (need >= 4)", n);
  rl_block_level lv[RL_BLOCK_MAX_LEVELS];
  int m = rl_series_block_levels(s, lv, RL_BLOCK_MAX_LEVELS);
  r->n = n;
  r->mean = s->lv[0].mean;
  r->sd = sqrt(s->lv[0].m2 / (double)n);
  choose_level(lv, m, n, lv[0].sem, r);
  return RL_OK;
}

int rl_block_fixed(const double *x, size_t n, int nblocks, double *mean, double *sem)
{
  if (!x || nblocks < 2 || n < (size_t)nblocks)
    return rl_error(RL_EINVAL, "rl_block_fixed: need x != NULL and n (%zu) >= nblocks (%d) >= 2", n, nblocks);
  size_t b = n / (size_t)nblocks;
  long cnt = 0;
  double mu = 0.0, m2 = 0.0;
  for (int k = 0; k < nblocks; k++) {
    double sum = 0.0;
    for (size_t i = 0; i < b; i++) sum += x[(size_t)k * b + i];
    if (!isfinite(sum)) return rl_error(RL_ENONFINITE, "rl_block_fixed: non-finite data in block %d", k);
    welford(&cnt, &mu, &m2, sum / (double)b);
  }
  if (mean) *mean = mu;
  if (sem) *sem = sqrt(m2 / (double)nblocks / (double)(nblocks - 1));
  return RL_OK;
}

int rl_running_rel_fluct(const double *x, size_t n, double *out)
{
  if ((!x || !out) && n > 0) return rl_error(RL_EINVAL, "rl_running_rel_fluct: NULL array");
  long cnt = 0;
  double mu = 0.0, m2 = 0.0;
  for (size_t i = 0; i < n; i++) {
    if (!isfinite(x[i])) return rl_error(RL_ENONFINITE, "rl_running_rel_fluct: x[%zu] = %g", i, x[i]);
    welford(&cnt, &mu, &m2, x[i]);
    out[i] = mu != 0.0 ? sqrt(m2 / (double)cnt) / fabs(mu) : NAN;
  }
  return RL_OK;
}

/* ------------------------------------------------------------------ heat capacity */

int rl_heat_capacity_nvt(double var_E, double T, double kB, double *cv)
{
  if (!cv || !(var_E >= 0.0) || !(T > 0.0) || !(kB > 0.0) || !isfinite(var_E) || !isfinite(T))
    return rl_error(RL_EINVAL, "rl_heat_capacity_nvt: need var_E >= 0 (%g), T > 0 (%g), kB > 0 (%g)",
                    var_E, T, kB);
  *cv = var_E / (kB * T * T);
  return RL_OK;
}

int rl_heat_capacity_isokinetic(double var_U, double T, int dof, double kB, double *cv)
{
  if (!cv || !(var_U >= 0.0) || !(T > 0.0) || !(kB > 0.0) || dof < 1 || !isfinite(var_U) || !isfinite(T))
    return rl_error(RL_EINVAL,
                    "rl_heat_capacity_isokinetic: need var_U >= 0 (%g), T > 0 (%g), dof >= 1 (%d), kB > 0",
                    var_U, T, dof);
  *cv = 0.5 * dof * kB + var_U / (kB * T * T);
  return RL_OK;
}

int rl_heat_capacity_nve(double mean_K, double var_K, int dof, double kB, double *cv)
{
  if (!cv || !(mean_K > 0.0) || !(var_K >= 0.0) || dof < 1 || !(kB > 0.0) || !isfinite(mean_K) ||
      !isfinite(var_K))
    return rl_error(RL_EINVAL, "rl_heat_capacity_nve: need <K> > 0 (%g), var_K >= 0 (%g), dof >= 1 (%d), kB > 0",
                    mean_K, var_K, dof);
  double x = 0.5 * dof * var_K / (mean_K * mean_K);
  if (x >= 1.0)
    return rl_error(RL_EINVAL,
                    "rl_heat_capacity_nve: f <dK^2> / (2 <K>^2) = %g >= 1: kinetic-energy fluctuations at "
                    "or above the canonical value (not a microcanonical run, or too short)", x);
  *cv = 0.5 * dof * kB / (1.0 - x);
  return RL_OK;
}

/* ------------------------------------------------------------------ stored series */

rl_moments rl_moments_merge(rl_moments a, rl_moments b)
{
  if (a.n == 0) return b;
  if (b.n == 0) return a;
  const long n = a.n + b.n;
  const double d = b.mean - a.mean;
  rl_moments m = {n, a.mean + d * ((double)b.n / (double)n), a.m2 + b.m2 + d * d * ((double)a.n * (double)b.n / (double)n)};
  return m;
}

int rl_moments_leave_one_out(const rl_moments *g, long m, rl_moments *out)
{
  if (!g || !out || m < 2) return rl_error(RL_EINVAL, "rl_moments_leave_one_out: need g, out and m >= 2 (%ld)", m);
  /* out[i] first holds the union of g[0..i) (prefix), then the suffix g(i..m) is merged in */
  rl_moments acc = {0, 0.0, 0.0};
  for (long i = 0; i < m; i++) {
    out[i] = acc;
    acc = rl_moments_merge(acc, g[i]);
  }
  acc = (rl_moments){0, 0.0, 0.0};
  for (long i = m - 1; i >= 0; i--) {
    out[i] = rl_moments_merge(out[i], acc);
    acc = rl_moments_merge(g[i], acc);
  }
  return RL_OK;
}

double rl_jackknife_error(const double *theta, long m)
{
  if (!theta || m < 2) return NAN;
  double mean = 0.0, s = 0.0;
  for (long i = 0; i < m; i++) mean += theta[i];
  mean /= (double)m;
  for (long i = 0; i < m; i++) s += (theta[i] - mean) * (theta[i] - mean);
  const double e = sqrt((double)(m - 1) / (double)m * s);
  return isfinite(e) ? e : NAN;
}

struct rl_trace {
  long cap, B, nb, alloc; /* blocks kept at most, samples per block, full blocks, allocated */
  rl_moments *blk;        /* [nb] full blocks                                                */
  rl_moments part;        /* the block being filled (part.n < B)                             */
};

rl_trace *rl_trace_alloc(long cap)
{
  if (cap == 0) cap = RL_TRACE_CAP;
  if (cap < 4 || (cap & (cap - 1))) {
    rl_error(RL_EINVAL, "rl_trace_alloc: cap = %ld must be a power of two >= 4", cap);
    return NULL;
  }
  rl_trace *t = calloc(1, sizeof *t);
  if (!t) {
    rl_error(RL_ENOMEM, "rl_trace_alloc: out of memory");
    return NULL;
  }
  t->cap = cap;
  t->B = 1;
  return t;
}

void rl_trace_free(rl_trace *t)
{
  if (!t) return;
  free(t->blk);
  free(t);
}

int rl_trace_add(rl_trace *t, double x)
{
  if (!t) return rl_error(RL_EINVAL, "rl_trace_add: NULL trace");
  if (!isfinite(x)) return rl_error(RL_ENONFINITE, "rl_trace_add: non-finite sample %g", x);
  if (t->part.n + 1 == t->B && t->nb == t->alloc) { /* room for the block this sample completes */
    const long alloc = t->alloc ? 2 * t->alloc : 256;
    rl_moments *p = realloc(t->blk, sizeof *p * (size_t)alloc);
    if (!p) return rl_error(RL_ENOMEM, "rl_trace_add: out of memory at %ld blocks", t->nb);
    t->blk = p;
    t->alloc = alloc;
  }
  welford(&t->part.n, &t->part.mean, &t->part.m2, x);
  if (t->part.n < t->B) return RL_OK;
  t->blk[t->nb++] = t->part;
  t->part = (rl_moments){0, 0.0, 0.0};
  if (t->nb == t->cap) { /* full: merge neighbours, B doubles */
    for (long k = 0; k < t->cap / 2; k++) t->blk[k] = rl_moments_merge(t->blk[2 * k], t->blk[2 * k + 1]);
    t->nb = t->cap / 2;
    t->B *= 2;
  }
  return RL_OK;
}

long rl_trace_count(const rl_trace *t) { return t ? t->nb * t->B + t->part.n : 0; }
long rl_trace_block(const rl_trace *t) { return t ? t->B : 1; }

long rl_trace_align(const rl_trace *t, long i)
{
  if (!t || i <= 0) return 0;
  const long a = (i + t->B - 1) / t->B * t->B;
  return a <= t->nb * t->B ? a : rl_trace_count(t);
}

rl_moments rl_trace_moments(const rl_trace *t, long from)
{
  rl_moments m = {0, 0.0, 0.0};
  if (!t) return m;
  const long a = rl_trace_align(t, from);
  if (a == rl_trace_count(t)) return m;
  for (long k = a / t->B; k < t->nb; k++) m = rl_moments_merge(m, t->blk[k]);
  return rl_moments_merge(m, t->part);
}

long rl_trace_groups(const rl_trace *t, long from, long len, rl_moments *out, long nmax)
{
  if (!t || len < 1) return 0;
  const long per = (len + t->B - 1) / t->B, first = rl_trace_align(t, from) / t->B;
  const long m = first < t->nb ? (t->nb - first) / per : 0;
  for (long g = 0; out && g < m && g < nmax; g++) {
    rl_moments acc = {0, 0.0, 0.0};
    for (long k = 0; k < per; k++) acc = rl_moments_merge(acc, t->blk[first + g * per + k]);
    out[g] = acc;
  }
  return m;
}

int rl_trace_block_average(const rl_trace *t, long from, rl_block_result *r)
{
  if (!t || !r) return rl_error(RL_EINVAL, "rl_trace_block_average: NULL argument");
  const rl_moments all = rl_trace_moments(t, from);
  const long n = all.n;
  if (n < 4) return rl_error(RL_EINVAL, "rl_trace_block_average: %ld samples (need >= 4)", n);
  /* level k >= log2 B: means of 2^k samples, each a merge of 2^k / B stored blocks */
  int kB = 0;
  while ((1L << kB) < t->B) kB++;
  const long first = rl_trace_align(t, from) / t->B, avail = t->nb - first;
  rl_block_level lv[RL_BLOCK_MAX_LEVELS];
  int m = 0;
  for (int k = kB; k < RL_BLOCK_MAX_LEVELS; k++) {
    const long per = 1L << (k - kB), ng = avail / per;
    if (ng < 2) break;
    long cnt = 0;
    double mu = 0.0, m2 = 0.0;
    for (long g = 0; g < ng; g++) {
      rl_moments acc = {0, 0.0, 0.0};
      for (long q = 0; q < per; q++) acc = rl_moments_merge(acc, t->blk[first + g * per + q]);
      welford(&cnt, &mu, &m2, acc.mean);
    }
    level_acc la = {cnt, mu, m2, 0, 0.0};
    level_sem(&la, k, &lv[m++]);
  }
  const double sd = sqrt(all.m2 / (double)n);
  r->n = n;
  r->mean = all.mean;
  r->sd = sd;
  choose_level(lv, m, n, sd / sqrt((double)n - 1.0), r);
  return RL_OK;
}

/* ------------------------------------------------------------------ equilibration */

int rl_statistical_inefficiency(const double *x, long n, double *g)
{
  if (!x || !g || n < 2) return rl_error(RL_EINVAL, "rl_statistical_inefficiency: need x, g and n >= 2 (%ld)", n);
  double mu = 0.0, s2 = 0.0;
  for (long i = 0; i < n; i++) mu += x[i];
  mu /= (double)n;
  for (long i = 0; i < n; i++) s2 += (x[i] - mu) * (x[i] - mu);
  s2 /= (double)n;
  if (!(s2 > 0.0)) return rl_error(RL_EINVAL, "rl_statistical_inefficiency: the series is constant (variance %g)", s2);
  double ineff = 1.0;
  for (long t = 1; t < n - 1; t++) {
    double c = 0.0;
    for (long i = 0; i < n - t; i++) c += (x[i] - mu) * (x[i + t] - mu);
    c /= (double)(n - t) * s2;
    if (c <= 0.0 && t > 3) break;
    ineff += 2.0 * c * (1.0 - (double)t / (double)n);
  }
  *g = ineff < 1.0 ? 1.0 : ineff;
  return RL_OK;
}

int rl_detect_equilibration(const double *x, long n, long stride, long t0_max, long *t0, double *g, double *neff)
{
  if (!x || n < 2 || stride < 1)
    return rl_error(RL_EINVAL, "rl_detect_equilibration: need x, n >= 2 (%ld) and stride >= 1 (%ld)", n, stride);
  for (long i = 0; i < n; i++)
    if (!isfinite(x[i])) return rl_error(RL_ENONFINITE, "rl_detect_equilibration: x[%ld] = %g", i, x[i]);
  long best = 0;
  double best_g = (double)n, best_neff = -1.0;
  if (t0_max < 0 || t0_max > n - 2) t0_max = n - 2;
  for (long t = 0; t <= t0_max; t += stride) {
    double gt;
    if (rl_statistical_inefficiency(x + t, n - t, &gt)) gt = (double)(n - t); /* constant: one sample */
    const double ne = (double)(n - t) / gt;
    if (ne > best_neff) {
      best = t;
      best_g = gt;
      best_neff = ne;
    }
  }
  if (t0) *t0 = best;
  if (g) *g = best_g;
  if (neff) *neff = best_neff;
  return RL_OK;
}

int rl_trace_equilibration(const rl_trace *t, long points, double max_start, long *t0, long *len, double *g,
                           double *neff, int *at_limit)
{
  if (!t || points < 8 || !(max_start > 0.0 && max_start <= 1.0))
    return rl_error(RL_EINVAL, "rl_trace_equilibration: need a trace, points >= 8 (%ld) and 0 < max_start <= 1 (%g)",
                    points, max_start);
  const long per = (t->nb + points - 1) / points > 0 ? (t->nb + points - 1) / points : 1, L = per * t->B;
  const long m = rl_trace_groups(t, 0, L, NULL, 0);
  if (len) *len = L;
  if (t0) *t0 = 0;
  if (at_limit) *at_limit = 0;
  if (g) *g = NAN;
  if (neff) *neff = NAN;
  if (m < 2) return RL_OK; /* too short to tell: nothing discarded */
  rl_moments *gm = malloc(sizeof *gm * (size_t)m);
  double *x = malloc(sizeof *x * (size_t)m);
  if (!gm || !x) {
    free(gm);
    free(x);
    return rl_error(RL_ENOMEM, "rl_trace_equilibration: out of memory");
  }
  rl_trace_groups(t, 0, L, gm, m);
  for (long k = 0; k < m; k++) x[k] = gm[k].mean;
  long k0 = 0, kmax = (long)(max_start * (double)(m - 2));
  const int st = rl_detect_equilibration(x, m, 1, kmax, &k0, g, neff);
  if (!st && t0) *t0 = k0 * L;
  if (!st && at_limit) *at_limit = k0 > 0 && 10 * k0 >= 9 * kmax; /* in the last tenth of the search */
  free(gm);
  free(x);
  return st;
}
