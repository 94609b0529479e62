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
  r->sem_naive = lv[0].sem;
  r->converged = 0;
  int chosen = -1, last4 = 0;
  for (int k = 0; k < m; k++) {
    if (lv[k].nblocks < 4) break;
    last4 = k;
    double ratio = lv[0].sem > 0.0 ? lv[k].sem / lv[0].sem : 1.0;
    double B = ldexp(1.0, k);
    if (B * B * B > 2.0 * (double)n * ratio * ratio * ratio * ratio) {
      chosen = k;
      r->converged = 1;
      break;
    }
  }
  if (chosen < 0) chosen = last4;
  r->level = chosen;
  r->sem = lv[chosen].sem;
  r->sem_err = lv[chosen].sem_err;
  r->tau = r->sem_naive > 0.0 ? 0.5 * (r->sem / r->sem_naive) * (r->sem / r->sem_naive) : 0.5;
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
