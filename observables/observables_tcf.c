/* rotleap — observables: stored per-body vector samples, time correlation functions with
 * multiple time origins, diffusion (Einstein and Green-Kubo), unwrapping and per-body samplers. */
#include "rotleap/observables.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rotleap/error.h"

struct rl_vec_series {
  int n;
  long frames, cap;
  double *x; /* [cap][n][3] */
};

rl_vec_series *rl_vec_series_alloc(int n)
{
  if (n < 1) {
    rl_error(RL_EINVAL, "rl_vec_series_alloc: n = %d bodies (need >= 1)", n);
    return NULL;
  }
  rl_vec_series *s = calloc(1, sizeof *s);
  if (!s) {
    rl_error(RL_ENOMEM, "rl_vec_series_alloc: out of memory");
    return NULL;
  }
  s->n = n;
  return s;
}

void rl_vec_series_free(rl_vec_series *s)
{
  if (!s) return;
  free(s->x);
  free(s);
}

int rl_vec_series_add(rl_vec_series *s, const double (*x)[3])
{
  if (!s || !x) return rl_error(RL_EINVAL, "rl_vec_series_add: NULL argument");
  size_t fsz = (size_t)s->n * 3;
  for (size_t i = 0; i < fsz; i++)
    if (!isfinite(x[i / 3][i % 3]))
      return rl_error(RL_ENONFINITE, "rl_vec_series_add: non-finite component (body %zu)", i / 3);
  if (s->frames == s->cap) {
    long cap = s->cap ? 2 * s->cap : 64;
    double *p = realloc(s->x, sizeof(double) * fsz * (size_t)cap);
    if (!p) return rl_error(RL_ENOMEM, "rl_vec_series_add: out of memory at %ld frames", s->frames);
    s->x = p;
    s->cap = cap;
  }
  memcpy(s->x + fsz * (size_t)s->frames, x, sizeof(double) * fsz);
  s->frames++;
  return RL_OK;
}

int rl_vec_series_count(const rl_vec_series *s) { return s ? s->n : 0; }
long rl_vec_series_frames(const rl_vec_series *s) { return s ? s->frames : 0; }

const double (*rl_vec_series_frame(const rl_vec_series *s, long f))[3]
{
  if (!s || f < 0 || f >= s->frames) return NULL;
  return (const double(*)[3])(s->x + (size_t)s->n * 3 * (size_t)f);
}

int rl_tcf_compute(const rl_vec_series *s, rl_tcf_kind kind, long max_lag, long origin_stride, double *c)
{
  return rl_tcf_compute_range(s, 0, s ? s->frames : 0, kind, max_lag, origin_stride, c);
}

int rl_tcf_compute_range(const rl_vec_series *all, long first, long count, rl_tcf_kind kind, long max_lag,
                         long origin_stride, double *c)
{
  return rl_tcf_compute_bodies(all, first, count, 0, all ? all->n : 0, kind, max_lag, origin_stride, c);
}

int rl_tcf_compute_bodies(const rl_vec_series *all, long first, long count, int body0, int nbodies, rl_tcf_kind kind,
                          long max_lag, long origin_stride, double *c)
{
  if (!all || !c) return rl_error(RL_EINVAL, "rl_tcf_compute: NULL argument");
  if (body0 < 0 || nbodies < 1 || nbodies > all->n - body0)
    return rl_error(RL_EINVAL, "rl_tcf_compute: bodies %d to %d are not within the %d bodies", body0, body0 + nbodies - 1,
                    all->n);
  if (first < 0 || count < 1 || count > all->frames - first)
    return rl_error(RL_EINVAL, "rl_tcf_compute: frames %ld to %ld are not within the %ld frames", first,
                    first + count - 1, all->frames);
  /* those frames, as a series of their own */
  const rl_vec_series view = {all->n, count, count, all->x + (size_t)all->n * 3 * (size_t)first};
  const rl_vec_series *s = &view;
  if (max_lag < 0 || max_lag >= s->frames)
    return rl_error(RL_EINVAL, "rl_tcf_compute: max_lag = %ld must be in [0, frames = %ld)", max_lag, s->frames);
  if (origin_stride < 1) return rl_error(RL_EINVAL, "rl_tcf_compute: origin_stride = %ld (need >= 1)", origin_stride);
  if (kind < RL_TCF_DOT || kind > RL_TCF_MSD) return rl_error(RL_EINVAL, "rl_tcf_compute: unknown kind %d", (int)kind);
  int n = s->n;
  double *norm = NULL;
  if (kind == RL_TCF_P1 || kind == RL_TCF_P2) {
    norm = malloc(sizeof(double) * (size_t)n * (size_t)s->frames);
    if (!norm) return rl_error(RL_ENOMEM, "rl_tcf_compute: out of memory");
    for (long f = 0; f < s->frames; f++)
      for (int i = body0; i < body0 + nbodies; i++) {
        const double *a = s->x + 3 * ((size_t)f * n + i);
        double q = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        if (!(q > 0.0)) {
          free(norm);
          return rl_error(RL_EINVAL, "rl_tcf_compute: zero vector (frame %ld, body %d) for a Legendre ACF", f, i);
        }
        norm[(size_t)f * n + i] = 1.0 / q;
      }
  }
  for (long lag = 0; lag <= max_lag; lag++) {
    double sum = 0.0;
    long origins = 0;
    for (long t0 = 0; t0 + lag < s->frames; t0 += origin_stride) {
      const double *a = s->x + 3 * (size_t)t0 * n, *b = s->x + 3 * (size_t)(t0 + lag) * n;
      for (int i = body0; i < body0 + nbodies; i++) {
        const double *u = a + 3 * i, *w = b + 3 * i;
        double v;
        if (kind == RL_TCF_MSD) {
          double dx = w[0] - u[0], dy = w[1] - u[1], dz = w[2] - u[2];
          v = dx * dx + dy * dy + dz * dz;
        } else {
          v = u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
          if (kind != RL_TCF_DOT) {
            v *= norm[(size_t)t0 * n + i] * norm[(size_t)(t0 + lag) * n + i];
            if (kind == RL_TCF_P2) v = 1.5 * v * v - 0.5;
          }
        }
        sum += v;
      }
      origins++;
    }
    c[lag] = sum / ((double)origins * nbodies);
  }
  free(norm);
  return RL_OK;
}

int rl_diffusion_einstein(const double *msd, long nlag, double dt, long lag_lo, long lag_hi, double *D,
                          double *D_err)
{
  if (!msd || !(dt > 0.0) || lag_lo < 0 || lag_hi <= lag_lo || lag_hi >= nlag)
    return rl_error(RL_EINVAL, "rl_diffusion_einstein: need msd, dt > 0 and 0 <= lag_lo (%ld) < lag_hi (%ld) < nlag (%ld)",
                    lag_lo, lag_hi, nlag);
  double m = (double)(lag_hi - lag_lo + 1), st = 0.0, sy = 0.0;
  for (long k = lag_lo; k <= lag_hi; k++) {
    st += k * dt;
    sy += msd[k];
  }
  double tm = st / m, ym = sy / m, stt = 0.0, sty = 0.0;
  for (long k = lag_lo; k <= lag_hi; k++) {
    double t = k * dt - tm;
    stt += t * t;
    sty += t * (msd[k] - ym);
  }
  double slope = sty / stt, icpt = ym - slope * tm;
  if (D) *D = slope / 6.0;
  if (D_err) {
    double rss = 0.0;
    for (long k = lag_lo; k <= lag_hi; k++) {
      double e = msd[k] - (icpt + slope * k * dt);
      rss += e * e;
    }
    *D_err = m > 2.0 ? sqrt(rss / (m - 2.0) / stt) / 6.0 : NAN;
  }
  return isfinite(slope) ? RL_OK : rl_error(RL_ENONFINITE, "rl_diffusion_einstein: non-finite slope");
}

int rl_diffusion_green_kubo(const double *vacf, long nlag, double dt, double *D)
{
  if (!vacf || !D || nlag < 2 || !(dt > 0.0))
    return rl_error(RL_EINVAL, "rl_diffusion_green_kubo: need vacf, D, nlag >= 2 (%ld), dt > 0", nlag);
  double s = 0.5 * (vacf[0] + vacf[nlag - 1]);
  for (long k = 1; k < nlag - 1; k++) s += vacf[k];
  *D = s * dt / 3.0;
  return isfinite(*D) ? RL_OK : rl_error(RL_ENONFINITE, "rl_diffusion_green_kubo: non-finite integral");
}

void rl_unwrap(const double L[3], const double (*prev)[3], const double (*x)[3], int n, double (*out)[3])
{
  for (int i = 0; i < n; i++)
    for (int d = 0; d < 3; d++) {
      double xi = x[i][d];
      out[i][d] = xi + L[d] * round((prev[i][d] - xi) / L[d]);
    }
}

void rl_system_positions(const rl_system *sys, double (*r)[3])
{
  int n = rl_system_count(sys);
  for (int i = 0; i < n; i++) rl_system_get_position(sys, i, r[i]);
}

void rl_system_velocities(const rl_system *sys, double (*v)[3])
{
  int n = rl_system_count(sys);
  for (int i = 0; i < n; i++) rl_system_get_velocity(sys, i, v[i]);
}

void rl_system_axes(const rl_system *sys, double (*u)[3])
{
  int n = rl_system_count(sys);
  for (int i = 0; i < n; i++) rl_system_get_axis(sys, i, u[i]);
}

void rl_system_angular_velocities(const rl_system *sys, double (*w)[3])
{
  int n = rl_system_count(sys);
  for (int i = 0; i < n; i++) {
    rl_kind kind = rl_system_species_kind(sys, rl_system_species_of(sys, i));
    double l[3], J[3];
    w[i][0] = w[i][1] = w[i][2] = 0.0;
    if (kind == RL_KIND_POINT) continue;
    rl_system_get_angmom(sys, i, l);
    rl_system_inertia(sys, i, J);
    if (kind == RL_KIND_DIPOLE || kind == RL_KIND_LINEAR) {
      double rho[3];
      rl_system_get_axis(sys, i, rho);
      double lr = l[0] * rho[0] + l[1] * rho[1] + l[2] * rho[2];
      for (int d = 0; d < 3; d++) w[i][d] = (l[d] - lr * rho[d]) / J[0];
    } else {
      double A[9], Om[3];
      rl_system_get_orientation(sys, i, A);
      for (int a = 0; a < 3; a++) Om[a] = (A[3 * a] * l[0] + A[3 * a + 1] * l[1] + A[3 * a + 2] * l[2]) / J[a];
      for (int d = 0; d < 3; d++) w[i][d] = A[d] * Om[0] + A[3 + d] * Om[1] + A[6 + d] * Om[2];
    }
  }
}
