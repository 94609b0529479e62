/* Smooth particle-mesh Ewald (Essmann, Perera, Berkowitz, Darden, Lee & Pedersen, J. Chem. Phys.
 * 103, 8577 (1995)): the term "pme" (ewald.h).
 *
 * Each charge is spread on a K_x x K_y x K_z mesh with cardinal B-splines of order p in its
 * fractional coordinates u_c = K_c x_c / L_c; the mesh is Fourier transformed (FFTW3, real to
 * complex), multiplied by the influence function
 *   G(m) = kc exp(-pi^2 m^2 / alpha^2) / (pi V m^2 B(m)),  B = B_x(m_x) B_y(m_y) B_z(m_z),
 * B_c the squared B-spline moduli, m the reciprocal vector (m_c / L_c); the energy is
 * (1/2) sum_m G |F(Q)(m)|^2, and the product transformed back is the mesh potential whose
 * spline-weighted gradient (analytical differentiation of the splines) gives the forces.  The
 * site virial is (1/2) sum_m G |F(Q)|^2 (delta - 2 (1 + pi^2 m^2 / alpha^2) m m^T / m^2) (eq. 2.11).
 *
 * Point dipoles (ewald.h): a site spreads q theta + m . grad theta, grad = (K_c / L_c) d/du_c, whose
 * transform stands in for (q + i m.k) exp(i k.r); the forces then need the splines' second
 * derivatives (from the order p - 2 weights), the field on each dipole their first, and the site
 * virial gains -sum m (x) E (grad = K/L changes under the strain, the dipoles do not).
 *
 * Conventions follow OpenMM 7.7's reference PME (ReferencePME.cpp), so that its numbers are
 * reproduced to round-off: a charge at fractional position t (t - floor t, times K) with integer
 * part i and fraction w spreads onto mesh points i, ..., i + p - 1 (mod K) with the weights
 * M_p(w + p - 1 - j) (a shift of the whole mesh by p - 1 points, which changes nothing), the same
 * B-spline recursions, and moduli below 1e-7 (an odd order's zero at the Nyquist index) replaced
 * by the mean of their neighbours.
 *
 * The interpolation breaks Newton's third law: the mesh forces do not sum to zero (about 1e-5 of
 * sum |F| at tolerance 5e-4), and a run's total momentum would drift away from the zero the
 * leapfrog holds it at (a continuation, whose start removes a momentum above round-off, would
 * then no longer follow the run bit for bit).  With remove_net_force each charged site gives up
 * an equal share of the net force, as Amber's netfrc does; the energy is that of the mesh as
 * before, the forces no longer its exact gradient by that share.
 *
 * Threads (any count gives the same bits): splines and forces site by site; the mesh plane by
 * plane in x, each thread filling its own planes from every charge whose stencil reaches them, in
 * site order; the influence function and the energy and virial plane by plane, summed in plane
 * order.  The FFTs run on one thread (plans made once at alloc with FFTW_ESTIMATE, which does not
 * time anything and so always makes the same plan; FFTW's planner is not thread-safe, so terms
 * must not be allocated concurrently). */
#include "ewald_impl.h"
#include "rotleap/error.h"
#include "../../core/threads.h"

#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define EW_MAX_SPLINE 16 /* above the largest order (12, ewald_params.c) */

typedef struct {
  ew_base b; /* first */
  int K[3], P;
  double *mod[3];       /* [K_c] squared B-spline moduli                                      */
  double *G;            /* [Kx][Ky][Kz/2+1] influence function (0 at m = 0)                     */
  double *mh[3];        /* [K_c] m_c / L_c, the signed frequency of each index                  */
  double *grid;         /* [Kx][Ky][Kz] real mesh (fftw_malloc)                                 */
  fftw_complex *cgrid;  /* [Kx][Ky][Kz/2+1] its transform                                       */
  fftw_plan fwd, bwd;
  int *gi;              /* [nq][3][P] the mesh indices of each charge's stencil, wrapped         */
  double *theta;        /* [nq][3][P] spline weights                                            */
  double *dtheta;       /* [nq][3][P] their derivatives d/du                                    */
  double *d2theta;      /* [nq][3][P] second derivatives (with point dipoles only, else NULL)   */
  double *plane;        /* [Kx][7] energy and virial (xx yy zz xy xz yz) per x plane           */
} pme_state;

static void pme_free(void *state)
{
  pme_state *s = state;
  if (!s) return;
  ew_base_free(&s->b);
  for (int c = 0; c < 3; c++) {
    free(s->mod[c]);
    free(s->mh[c]);
  }
  free(s->G);
  if (s->fwd) fftw_destroy_plan(s->fwd);
  if (s->bwd) fftw_destroy_plan(s->bwd);
  fftw_free(s->grid);
  fftw_free(s->cgrid);
  free(s->gi);
  free(s->theta);
  free(s->dtheta);
  free(s->d2theta);
  free(s->plane);
  free(s);
}

/* M_p at the integer points, as OpenMM's pme_calculate_bsplines_moduli computes them (the
 * weights of a charge at w = 0): data[j] = M_p(p - 1 - j). */
static void bspline_integer(int order, double *data)
{
  data[order - 1] = 0;
  data[1] = 0;
  data[0] = 1;
  for (int k = 3; k < order; k++) {
    const double div = 1.0 / (k - 1.0);
    data[k - 1] = 0;
    for (int l = 1; l < (k - 1); l++) data[k - l - 1] = div * (l * data[k - l - 2] + (k - l) * data[k - l - 1]);
    data[0] = div * data[0];
  }
  const double div = 1.0 / (order - 1);
  data[order - 1] = 0;
  for (int l = 1; l < (order - 1); l++) data[order - l - 1] = div * (l * data[order - l - 2] + (order - l) * data[order - l - 1]);
  data[0] = div * data[0];
}

void ew_bspline_moduli(int order, int K, double *mod)
{
  double data[16], *b = calloc((size_t)K + (size_t)order + 1, sizeof(double));
  if (!b) {
    for (int i = 0; i < K; i++) mod[i] = NAN;
    return;
  }
  bspline_integer(order, data);
  for (int i = 1; i <= order; i++) b[i] = data[i - 1];
  for (int i = 0; i < K; i++) {
    double sc = 0, ss = 0;
    for (int j = 0; j < K; j++) {
      const double arg = (2.0 * M_PI * i * j) / K;
      sc += b[j] * cos(arg);
      ss += b[j] * sin(arg);
    }
    mod[i] = sc * sc + ss * ss;
  }
  for (int i = 0; i < K; i++)
    if (mod[i] < 1.0e-7) mod[i] = (mod[(i - 1 + K) % K] + mod[(i + 1) % K]) / 2;
  free(b);
}

/* The influence function for the current cell. */
static void pme_influence(pme_state *s)
{
  const double *L = s->b.L, a = s->b.info.alpha, kc = s->b.info.coulomb_constant;
  const double factor = M_PI * M_PI / (a * a), boxfactor = M_PI * L[0] * L[1] * L[2];
  for (int c = 0; c < 3; c++)
    for (int k = 0; k < s->K[c]; k++) s->mh[c][k] = (k < (s->K[c] + 1) / 2 ? k : k - s->K[c]) / L[c];
  const int Ky = s->K[1], Kh = s->K[2] / 2 + 1;
  for (int x = 0; x < s->K[0]; x++)
    for (int y = 0; y < Ky; y++)
      for (int z = 0; z < Kh; z++) {
        const double m2 = s->mh[0][x] * s->mh[0][x] + s->mh[1][y] * s->mh[1][y] + s->mh[2][z] * s->mh[2][z];
        s->G[((size_t)x * Ky + y) * Kh + z] =
            (x || y || z) ? kc * exp(-factor * m2) / (m2 * boxfactor * s->mod[0][x] * s->mod[1][y] * s->mod[2][z]) : 0.0;
      }
}

static int pme_box(void *state, const rl_system *sys)
{
  pme_state *s = state;
  const int st = ew_base_box(&s->b, sys);
  if (st) return st;
  pme_influence(s);
  return RL_OK;
}

/* Spline weights of charge k (OpenMM's pme_update_bsplines, and its index and fraction). */
static void pme_splines(pme_state *s, int k)
{
  const int P = s->P;
  for (int c = 0; c < 3; c++) {
    double t = s->b.xq[k][c] / s->b.L[c];
    t = (t - floor(t)) * s->K[c];
    const int ti = (int)t;
    const double dr = t - ti;
    int *g = s->gi + ((size_t)k * 3 + c) * P;
    for (int j = 0, m = ti % s->K[c]; j < P; j++, m = m + 1 < s->K[c] ? m + 1 : 0) g[j] = m;
    double *data = s->theta + ((size_t)k * 3 + c) * P, *ddata = s->dtheta + ((size_t)k * 3 + c) * P;
    double w2[EW_MAX_SPLINE] = {1.0}; /* the weights of order P - 2 (1 for order 1), for d2theta */
    data[P - 1] = 0;
    data[1] = dr;
    data[0] = 1 - dr;
    if (P == 4) memcpy(w2, data, sizeof(double) * 2);
    for (int j = 3; j < P; j++) {
      const double div = 1.0 / (j - 1.0);
      data[j - 1] = div * dr * data[j - 2];
      for (int l = 1; l < (j - 1); l++) data[j - l - 1] = div * ((dr + l) * data[j - l - 2] + (j - l - dr) * data[j - l - 1]);
      data[0] = div * (1 - dr) * data[0];
      if (j == P - 2) memcpy(w2, data, sizeof(double) * (size_t)j);
    }
    ddata[0] = -data[0];
    for (int j = 1; j < P; j++) ddata[j] = data[j - 1] - data[j];
    if (s->d2theta) { /* d/du twice: (D w)[j] = w[j - 1] - w[j], as for ddata */
      double *d2 = s->d2theta + ((size_t)k * 3 + c) * P;
      for (int j = 0; j < P; j++)
        d2[j] = (j < P - 2 ? w2[j] : 0.0) - 2.0 * (j >= 1 && j - 1 < P - 2 ? w2[j - 1] : 0.0) + (j >= 2 ? w2[j - 2] : 0.0);
    }
    const double div = 1.0 / (P - 1);
    data[P - 1] = div * dr * data[P - 2];
    for (int l = 1; l < (P - 1); l++) data[P - l - 1] = div * ((dr + l) * data[P - l - 2] + (P - l - dr) * data[P - l - 1]);
    data[0] = div * (1 - dr) * data[0];
  }
}

/* remove_net_force: fq holds the mesh part alone here; summed in site order */
static int pme_net_force(pme_state *s)
{
  ew_base *b = &s->b;
  const int nq = b->nq;
  if (b->p.remove_net_force && nq > 0) {
    double F[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < nq; k++)
      for (int c = 0; c < 3; c++) F[c] += b->fq[k][c];
    for (int c = 0; c < 3; c++) F[c] /= nq;
    for (int k = 0; k < nq; k++)
      for (int c = 0; c < 3; c++) b->fq[k][c] -= F[c];
  }
  return RL_OK;
}

/* With point dipoles: Q(j) = sum_a [q_a theta_a(j) + m_a . grad theta_a(j)], grad = (s_c d/du_c),
 * s_c = K_c / L_c; this thread's x planes [x0, x1) from every site reaching them, in site order. */
static void pme_spread_dip(pme_state *s, int x0, int x1)
{
  ew_base *b = &s->b;
  const int P = s->P, Kz = s->K[2];
  const size_t yz = (size_t)s->K[1] * Kz;
  const double sc[3] = {s->K[0] / b->L[0], s->K[1] / b->L[1], s->K[2] / b->L[2]};
  for (int k = 0; k < b->nq; k++) {
    const int *gx = s->gi + (size_t)k * 3 * P, *gyi = gx + P, *gzi = gyi + P;
    const double *tx = s->theta + (size_t)k * 3 * P, *ty = tx + P, *tz = ty + P;
    const double *dx = s->dtheta + (size_t)k * 3 * P, *dy = dx + P, *dz = dy + P;
    const double q = b->q[k], mx = b->md[k][0] * sc[0], my = b->md[k][1] * sc[1], mz = b->md[k][2] * sc[2];
    for (int ix = 0; ix < P; ix++) {
      const int xi = gx[ix];
      if (xi < x0 || xi >= x1) continue;
      double *gxp = s->grid + (size_t)xi * yz;
      for (int iy = 0; iy < P; iy++) {
        double *gy = gxp + (size_t)gyi[iy] * Kz;
        const double a0 = (q * tx[ix] + mx * dx[ix]) * ty[iy] + my * tx[ix] * dy[iy], az = mz * tx[ix] * ty[iy];
        for (int iz = 0; iz < P; iz++) gy[gzi[iz]] += a0 * tz[iz] + az * dz[iz];
      }
    }
  }
}

/* With point dipoles, from the mesh potential phi: per site the sums P_c = sum phi d_c theta and
 * P_cd = sum phi d_c d_d theta (d_c = d/du_c); then
 *   dU/dr_d = q s_d P_d + sum_c m_c s_c s_d P_cd,   E_c = -s_c P_c,
 * and the virial's extra term -sum m (x) E (the dipoles fixed under the strain, as in ewald_kspace.c). */
static void pme_gather_dip(pme_state *s, double W[9])
{
  ew_base *b = &s->b;
  const int T = b->threads, nq = b->nq, P = s->P, Kz = s->K[2];
  (void)T; /* a build without OpenMP */
  const size_t yz = (size_t)s->K[1] * Kz;
  const double sc[3] = {s->K[0] / b->L[0], s->K[1] / b->L[1], s->K[2] / b->L[2]};
#ifdef _OPENMP
#pragma omp parallel num_threads(T) if (T > 1)
#endif
  {
    int k0, k1;
    rl_thread_range(nq, &k0, &k1);
    for (int k = k0; k < k1; k++) {
      const int *gx = s->gi + (size_t)k * 3 * P, *gyi = gx + P, *gzi = gyi + P;
      const double *t[3] = {s->theta + (size_t)k * 3 * P, s->theta + (size_t)k * 3 * P + P, s->theta + (size_t)k * 3 * P + 2 * P};
      const double *d[3] = {s->dtheta + (size_t)k * 3 * P, s->dtheta + (size_t)k * 3 * P + P, s->dtheta + (size_t)k * 3 * P + 2 * P};
      const double *h[3] = {s->d2theta + (size_t)k * 3 * P, s->d2theta + (size_t)k * 3 * P + P, s->d2theta + (size_t)k * 3 * P + 2 * P};
      double Pc[3] = {0, 0, 0}, Pcd[6] = {0, 0, 0, 0, 0, 0}; /* xx yy zz xy xz yz */
      for (int ix = 0; ix < P; ix++) {
        const double *gxp = s->grid + (size_t)gx[ix] * yz;
        for (int iy = 0; iy < P; iy++) {
          const double *gy = gxp + (size_t)gyi[iy] * Kz;
          double p0 = 0, p1 = 0, p2 = 0; /* sums over z with theta, dtheta, d2theta */
          for (int iz = 0; iz < P; iz++) {
            const double g = gy[gzi[iz]];
            p0 += t[2][iz] * g;
            p1 += d[2][iz] * g;
            p2 += h[2][iz] * g;
          }
          const double tx = t[0][ix], ty = t[1][iy], dx = d[0][ix], dy = d[1][iy];
          Pc[0] += dx * ty * p0;
          Pc[1] += tx * dy * p0;
          Pc[2] += tx * ty * p1;
          Pcd[0] += h[0][ix] * ty * p0;
          Pcd[1] += tx * h[1][iy] * p0;
          Pcd[2] += tx * ty * p2;
          Pcd[3] += dx * dy * p0;
          Pcd[4] += dx * ty * p1;
          Pcd[5] += tx * dy * p1;
        }
      }
      static const int pair[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
      const double q = b->q[k], *m = b->md[k];
      for (int dd = 0; dd < 3; dd++) {
        double g = q * Pc[dd];
        for (int c = 0; c < 3; c++) g += m[c] * sc[c] * Pcd[pair[c][dd]];
        b->fq[k][dd] -= g * sc[dd];
        b->eq[k][dd] -= sc[dd] * Pc[dd];
      }
    }
  }
  ew_dipole_virial(b, W);
}

static int pme_part(ew_base *b, double *energy, double W[9])
{
  pme_state *s = (pme_state *)b;
  const int T = b->threads, nq = b->nq, P = s->P, Kx = s->K[0], Ky = s->K[1], Kz = s->K[2], Kh = Kz / 2 + 1;
  (void)T; /* a build without OpenMP */
  const size_t yz = (size_t)Ky * Kz;
#ifdef _OPENMP
#pragma omp parallel num_threads(T) if (T > 1)
#endif
  {
    int k0, k1;
    rl_thread_range(nq, &k0, &k1);
    for (int k = k0; k < k1; k++) pme_splines(s, k);
#ifdef _OPENMP
#pragma omp barrier
#endif
    /* spread: this thread's x planes [x0, x1), from every charge reaching them, in site order */
    int x0, x1;
    rl_thread_range(Kx, &x0, &x1);
    memset(s->grid + (size_t)x0 * yz, 0, sizeof(double) * yz * (size_t)(x1 - x0));
    if (b->ndip) {
      pme_spread_dip(s, x0, x1);
    } else
    for (int k = 0; k < nq; k++) {
      const int *gx = s->gi + (size_t)k * 3 * P, *gyi = gx + P, *gzi = gyi + P;
      const double *tx = s->theta + (size_t)k * 3 * P, *ty = tx + P, *tz = ty + P, q = b->q[k];
      for (int ix = 0; ix < P; ix++) {
        const int xi = gx[ix];
        if (xi < x0 || xi >= x1) continue;
        double *gxp = s->grid + (size_t)xi * yz;
        for (int iy = 0; iy < P; iy++) {
          double *gy = gxp + (size_t)gyi[iy] * Kz;
          const double qxy = q * tx[ix] * ty[iy];
          for (int iz = 0; iz < P; iz++) gy[gzi[iz]] += qxy * tz[iz];
        }
      }
    }
  }
  fftw_execute(s->fwd);
  const double a = b->info.alpha, f2 = M_PI * M_PI / (a * a);
#ifdef _OPENMP
#pragma omp parallel for num_threads(T) if (T > 1) schedule(static)
#endif
  for (int x = 0; x < Kx; x++) {
    double e = 0, w[6] = {0, 0, 0, 0, 0, 0};
    const double mx = s->mh[0][x];
    for (int y = 0; y < Ky; y++) {
      const double my = s->mh[1][y];
      for (int z = 0; z < Kh; z++) {
        const size_t i = ((size_t)x * Ky + y) * Kh + z;
        const double G = s->G[i], mz = s->mh[2][z], m2 = mx * mx + my * my + mz * mz;
        if (m2 == 0.0) { /* m = 0: no term (a net charge is the background's) */
          s->cgrid[i][0] = s->cgrid[i][1] = 0.0;
          continue;
        }
        const double wt = (z == 0 || (Kz % 2 == 0 && z == Kz / 2)) ? 0.5 : 1.0; /* half of the full sum */
        const double re = s->cgrid[i][0], im = s->cgrid[i][1];
        const double ek = wt * G * (re * re + im * im), v = 2.0 * (1.0 + f2 * m2) / m2;
        e += ek;
        w[0] += ek * (1.0 - v * mx * mx);
        w[1] += ek * (1.0 - v * my * my);
        w[2] += ek * (1.0 - v * mz * mz);
        w[3] -= ek * v * mx * my;
        w[4] -= ek * v * mx * mz;
        w[5] -= ek * v * my * mz;
        s->cgrid[i][0] = re * G;
        s->cgrid[i][1] = im * G;
      }
    }
    double *pl = s->plane + (size_t)x * 7;
    pl[0] = e;
    for (int j = 0; j < 6; j++) pl[1 + j] = w[j];
  }
  double E = 0, w[6] = {0, 0, 0, 0, 0, 0};
  for (int x = 0; x < Kx; x++) {
    E += s->plane[(size_t)x * 7];
    for (int j = 0; j < 6; j++) w[j] += s->plane[(size_t)x * 7 + 1 + j];
  }
  *energy = E;
  ew_add_virial6(W, w);
  fftw_execute(s->bwd); /* the mesh potential phi = dU/dQ: U = (1/2) sum_j Q(j) phi(j) */
  const double sx = Kx / b->L[0], sy = Ky / b->L[1], sz = Kz / b->L[2];
  if (b->ndip) {
    pme_gather_dip(s, W);
    return pme_net_force(s);
  }
#ifdef _OPENMP
#pragma omp parallel num_threads(T) if (T > 1)
#endif
  {
    int k0, k1;
    rl_thread_range(nq, &k0, &k1);
    for (int k = k0; k < k1; k++) {
      const int *gx = s->gi + (size_t)k * 3 * P, *gyi = gx + P, *gzi = gyi + P;
      const double *tx = s->theta + (size_t)k * 3 * P, *ty = tx + P, *tz = ty + P;
      const double *dx = s->dtheta + (size_t)k * 3 * P, *dy = dx + P, *dz = dy + P;
      double fx = 0, fy = 0, fz = 0;
      for (int ix = 0; ix < P; ix++) {
        const double *gxp = s->grid + (size_t)gx[ix] * yz;
        for (int iy = 0; iy < P; iy++) {
          const double *gy = gxp + (size_t)gyi[iy] * Kz;
          double pz = 0, dpz = 0;
          for (int iz = 0; iz < P; iz++) {
            const double g = gy[gzi[iz]];
            pz += tz[iz] * g;
            dpz += dz[iz] * g;
          }
          fx += dx[ix] * ty[iy] * pz;
          fy += tx[ix] * dy[iy] * pz;
          fz += tx[ix] * ty[iy] * dpz;
        }
      }
      const double q = b->q[k];
      b->fq[k][0] -= q * fx * sx;
      b->fq[k][1] -= q * fy * sy;
      b->fq[k][2] -= q * fz * sz;
    }
  }
  return pme_net_force(s);
}

static void *pme_alloc(const rl_system *sys, const void *params)
{
  pme_state *s = ew_alloc(sizeof *s, sys, params, RL_EWALD_PME);
  if (!s) return NULL;
  s->b.part = pme_part;
  for (int c = 0; c < 3; c++) s->K[c] = s->b.info.grid[c];
  s->P = s->b.info.order;
  const size_t Kx = (size_t)s->K[0], Ky = (size_t)s->K[1], Kz = (size_t)s->K[2], Kh = Kz / 2 + 1;
  int ok = 1;
  for (int c = 0; c < 3; c++) {
    s->mod[c] = malloc(sizeof(double) * (size_t)s->K[c]);
    s->mh[c] = malloc(sizeof(double) * (size_t)s->K[c]);
    ok &= s->mod[c] && s->mh[c];
  }
  s->G = malloc(sizeof(double) * Kx * Ky * Kh);
  s->grid = fftw_malloc(sizeof(double) * Kx * Ky * Kz);
  s->cgrid = fftw_malloc(sizeof(fftw_complex) * Kx * Ky * Kh);
  const size_t nq = (size_t)s->b.nq;
  s->gi = malloc(sizeof(int) * nq * 3 * (size_t)s->P);
  s->theta = malloc(sizeof(double) * nq * 3 * (size_t)s->P);
  s->dtheta = malloc(sizeof(double) * nq * 3 * (size_t)s->P);
  if (s->b.ndip) s->d2theta = malloc(sizeof(double) * nq * 3 * (size_t)s->P);
  s->plane = malloc(sizeof(double) * 7 * Kx);
  ok &= s->G && s->grid && s->cgrid && s->gi && s->theta && s->dtheta && s->plane && (!s->b.ndip || s->d2theta);
  if (ok) {
    s->fwd = fftw_plan_dft_r2c_3d(s->K[0], s->K[1], s->K[2], s->grid, s->cgrid, FFTW_ESTIMATE);
    s->bwd = fftw_plan_dft_c2r_3d(s->K[0], s->K[1], s->K[2], s->cgrid, s->grid, FFTW_ESTIMATE);
    ok = s->fwd && s->bwd;
  }
  if (!ok) {
    pme_free(s);
    rl_error(RL_ENOMEM, "pme: out of memory (a %d x %d x %d mesh)", s->K[0], s->K[1], s->K[2]);
    return NULL;
  }
  for (int c = 0; c < 3; c++) ew_bspline_moduli(s->P, s->K[c], s->mod[c]);
  pme_influence(s);
  return s;
}

static int pme_compute(void *state, const rl_system *sys, rl_forces *out, double *energies)
{
  return ew_compute(state, sys, out, energies, 5);
}

const rl_term_type rl_term_pme = {
    "pme",
    "reciprocal-space Ewald sum of point charges and dipoles by smooth particle-mesh Ewald (B-splines of selectable order, FFTW3), "
    "with the self term, the intramolecular exclusion correction, a neutralising background and the surface term "
    "(rotleap/ewald.h)",
    "U. Essmann, L. Perera, M. L. Berkowitz, T. Darden, H. Lee, L. G. Pedersen, J. Chem. Phys. 103, 8577 (1995)",
    5,
    {"ewald_recip", "ewald_self", "ewald_intra", "ewald_background", "ewald_surface"},
    pme_alloc,
    pme_compute,
    pme_box,
    pme_free};
