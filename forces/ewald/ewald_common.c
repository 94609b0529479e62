/* What the Ewald terms share (ewald_impl.h): the charged sites, U_self and U_intra, the
 * neutralising background and the surface term, and the way from site forces and the site virial
 * to body forces, torques and the molecular virial. */
#include "ewald_impl.h"
#include "ewald_dipole.h"
#include "rotleap/error.h"
#include "../../core/system_impl.h"
#include "../../core/threads.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* erf(alpha r) / r, with its limit 2 alpha / sqrt(pi) at r = 0 */
static double erf_over_r(double alpha, double r)
{
  return r > 0.0 ? erf(alpha * r) / r : 2.0 * alpha / sqrt(M_PI);
}

static int ew_base_init(ew_base *b, const rl_system *sys, const rl_ewald_params *p, rl_ewald_method method)
{
  b->p = *p;
  int st = rl_ewald_resolve(sys, p, method, &b->info);
  if (st) return st;
  b->units = rl_system_units(sys);
  b->threads = rl_threads_resolve(p->threads);
  b->n = rl_system_count(sys);
  b->nsites = rl_system_nsites(sys);
  b->ndip = b->info.nsites_dipolar;
  int npolar = 0; /* with dipoles the list holds every polar site */
  for (int s = 0; s < sys->nspecies; s++)
    for (int a = 0; a < sys->sp[s].nsites; a++)
      npolar += sys->sp[s].count * ((p->species[s].charge && p->species[s].charge[a] != 0.0) ||
                                    (b->ndip && p->species[s].dipole && p->species[s].dipole[a] != 0.0));
  b->nq = npolar;
  rl_system_box(sys, b->L);
  const size_t nq = (size_t)b->nq, ns = (size_t)(b->nsites ? b->nsites : 1), n = (size_t)(b->n ? b->n : 1);
  b->qsite = malloc(sizeof(int) * nq);
  b->qbody = malloc(sizeof(int) * nq);
  b->qmol_first = malloc(sizeof(int) * nq);
  b->qmol_count = malloc(sizeof(int) * nq);
  b->q = malloc(sizeof(double) * nq);
  b->xs = malloc(sizeof(double[3]) * ns);
  b->fs = malloc(sizeof(double[3]) * ns);
  b->xq = malloc(sizeof(double[3]) * nq);
  b->fq = malloc(sizeof(double[3]) * nq);
  b->rc = malloc(sizeof(double[3]) * n);
  b->mu = calloc(nq ? nq : 1, sizeof(double));
  b->md = calloc(nq ? nq : 1, sizeof(double[3]));
  b->eq = calloc(nq ? nq : 1, sizeof(double[3]));
  if (!b->qsite || !b->qbody || !b->qmol_first || !b->qmol_count || !b->q || !b->xs || !b->fs || !b->xq || !b->fq || !b->rc ||
      !b->mu || !b->md || !b->eq) {
    ew_base_free(b);
    return rl_error(RL_ENOMEM, "Ewald: out of memory");
  }
  /* the charged (and, with dipoles, dipolar) sites in site order, and U_self, U_intra */
  const double kc = b->info.coulomb_constant, alpha = b->info.alpha;
  double self = 0.0, intra = 0.0, selfmu = 0.0;
  int k = 0;
  for (int s = 0; s < sys->nspecies; s++) {
    const rl_species *sp = &sys->sp[s];
    const double *q = p->species[s].charge, *dm = b->ndip ? p->species[s].dipole : NULL;
    if (!q && !dm) continue;
#define EW_Q(a) (q ? q[a] : 0.0)
#define EW_MU(a) (dm ? dm[a] : 0.0)
    double mol = 0.0; /* U_intra of one molecule of the species, from its body-frame sites */
    int nqm = 0;
    for (int a = 0; a < sp->nsites; a++) {
      if (EW_Q(a) == 0.0 && EW_MU(a) == 0.0) continue;
      nqm++;
      for (int c = a + 1; c < sp->nsites; c++) {
        if (EW_Q(c) == 0.0 && EW_MU(c) == 0.0) continue;
        const double *da = sp->sites + 3 * a, *dc = sp->sites + 3 * c;
        const double r = sqrt((da[0] - dc[0]) * (da[0] - dc[0]) + (da[1] - dc[1]) * (da[1] - dc[1]) + (da[2] - dc[2]) * (da[2] - dc[2]));
        if (EW_MU(a) == 0.0 && EW_MU(c) == 0.0) {
          mol -= kc * q[a] * q[c] * erf_over_r(alpha, r);
          continue;
        }
        /* a pair with a dipole: the erf parts of the B functions (ewald_dipole.h), in the body
         * frame, where the dipoles lie along Z: r_ac = d_a - d_c */
        double B[3];
        ew_erf_b(alpha, r, B);
        const double rz = da[2] - dc[2], ma = EW_MU(a), mc = EW_MU(c);
        mol -= kc * (EW_Q(a) * EW_Q(c) * B[0] + (EW_Q(a) * mc * rz - EW_Q(c) * ma * rz + ma * mc) * B[1] - ma * rz * mc * rz * B[2]);
      }
    }
    intra += mol * sp->count;
    for (int i = 0; i < sp->count; i++) {
      const int first = k;
      for (int a = 0; a < sp->nsites; a++) {
        if (EW_Q(a) == 0.0 && EW_MU(a) == 0.0) continue;
        b->qsite[k] = sp->site_off + i * sp->nsites + a;
        b->qbody[k] = sp->first + i;
        b->qmol_first[k] = first;
        b->qmol_count[k] = nqm;
        b->q[k] = EW_Q(a);
        b->mu[k] = EW_MU(a);
        self += EW_Q(a) * EW_Q(a);
        selfmu += EW_MU(a) * EW_MU(a);
        k++;
      }
    }
#undef EW_Q
#undef EW_MU
  }
  b->e_self = -kc * alpha / sqrt(M_PI) * self;
  if (b->ndip) b->e_self -= kc * 2.0 * alpha * alpha * alpha / (3.0 * sqrt(M_PI)) * selfmu;
  b->e_intra = intra;
  return RL_OK;
}

void ew_base_free(ew_base *b)
{
  if (!b) return;
  free(b->qsite);
  free(b->qbody);
  free(b->qmol_first);
  free(b->qmol_count);
  free(b->q);
  free(b->xs);
  free(b->fs);
  free(b->xq);
  free(b->fq);
  free(b->rc);
  free(b->mu);
  free(b->md);
  free(b->eq);
}

void *ew_alloc(size_t size, const rl_system *sys, const void *params, rl_ewald_method method)
{
  static const char *const who[3] = {"ewald-real", "ewald", "pme"};
  if (!params) {
    rl_error(RL_EINVAL, "%s: the term needs its parameters (rl_ewald_params)", who[method]);
    return NULL;
  }
  ew_base *b = calloc(1, size);
  if (!b) {
    rl_error(RL_ENOMEM, "%s: out of memory", who[method]);
    return NULL;
  }
  if (ew_base_init(b, sys, params, method)) {
    free(b);
    return NULL;
  }
  return b;
}

void ew_add_virial6(double W[9], const double w[6])
{
  W[0] += w[0];
  W[4] += w[1];
  W[8] += w[2];
  W[1] += w[3];
  W[3] += w[3];
  W[2] += w[4];
  W[6] += w[4];
  W[5] += w[5];
  W[7] += w[5];
}

int ew_base_box(ew_base *b, const rl_system *sys)
{
  /* keep alpha, the k cutoffs and the mesh chosen at alloc: a change of cell must not change the
   * sum's resolution, or the energy would jump under a barostat (OpenMM and GROMACS keep them too) */
  rl_ewald_info in;
  const int st = ew_resolve(sys, &b->p, b->info.method, &b->info, &in);
  if (st) return st;
  b->info = in;
  rl_system_box(sys, b->L);
  return RL_OK;
}

int ew_gather(ew_base *b, const rl_system *sys)
{
  if (rl_system_count(sys) != b->n || rl_system_nsites(sys) != b->nsites)
    return rl_error(RL_ESTATE, "Ewald: the system has changed (%d bodies, %d sites; the term was made for %d, %d)",
                    rl_system_count(sys), rl_system_nsites(sys), b->n, b->nsites);
  const int T = b->threads;
  (void)T; /* a build without OpenMP */
  int bad = -1;
#ifdef _OPENMP
#pragma omp parallel num_threads(T) if (T > 1 && b->n >= RL_THREAD_MIN_BODIES) reduction(max : bad)
#endif
  {
    int i0, i1;
    rl_thread_range(b->n, &i0, &i1);
    rl_system_site_positions_of(sys, i0, i1, b->xs);
    for (int i = i0; i < i1; i++) {
      rl_system_get_position(sys, i, b->rc[i]);
      if (!isfinite(b->rc[i][0] + b->rc[i][1] + b->rc[i][2])) bad = bad > i ? bad : i;
    }
  }
  if (bad >= 0) return rl_error(RL_ENONFINITE, "Ewald: body %d has a non-finite position", bad);
  for (int k = 0; k < b->nq; k++) {
    const double *x = b->xs[b->qsite[k]];
    if (!isfinite(x[0] + x[1] + x[2])) return rl_error(RL_ENONFINITE, "Ewald: a site of body %d has a non-finite position (orientation)", b->qbody[k]);
    memcpy(b->xq[k], x, sizeof(double[3]));
    b->fq[k][0] = b->fq[k][1] = b->fq[k][2] = 0.0;
  }
  if (b->ndip)
    for (int k = 0; k < b->nq; k++) {
      double e[3] = {0, 0, 0};
      if (b->mu[k] != 0.0) rl_system_get_axis(sys, b->qbody[k], e);
      for (int c = 0; c < 3; c++) {
        b->md[k][c] = b->mu[k] * e[c];
        b->eq[k][c] = 0.0;
      }
    }
  return RL_OK;
}

void ew_dipole_virial(const ew_base *b, double W[9])
{
  for (int k = 0; k < b->nq; k++)
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) W[3 * r + c] -= b->md[k][r] * b->eq[k][c];
}

void ew_reciprocal_extras(ew_base *b, double e[5], double W[9])
{
  const double kc = b->info.coulomb_constant, V = b->L[0] * b->L[1] * b->L[2], a = b->info.alpha;
  e[1] = b->e_self;
  e[2] = b->e_intra;
  /* the neutralising background: U = -kc pi Q^2 / (2 V alpha^2); -dU/d(strain_cc) = U */
  const double Q = b->info.net_charge;
  e[3] = 0.0 - kc * M_PI * Q * Q / (2.0 * V * a * a); /* +0 when neutral */
  for (int c = 0; c < 3; c++) W[4 * c] += e[3];
  /* the surface term: U = c |M|^2, c = 2 pi kc / ((2 eps' + 1) V); f_a = -2 c q_a M;
   * site virial sum r (x) f + U 1 (the strain derivative of |M|^2 / V) */
  e[4] = 0.0;
  if (isinf(b->info.eps_surface)) return;
  const double cs = 2.0 * M_PI * kc / ((2.0 * b->info.eps_surface + 1.0) * V);
  if (b->ndip) {
    /* M = sum q r + sum mu: the charges' forces -2 c q M, the dipoles' field -2 c M; the site
     * virial (dipoles fixed under the strain) sum r_r f_c + U delta = -2 c Mq_r M_c + U delta */
    double Mq[3] = {0, 0, 0}, M[3];
    for (int k = 0; k < b->nq; k++)
      for (int c = 0; c < 3; c++) Mq[c] += b->q[k] * b->xq[k][c];
    for (int c = 0; c < 3; c++) M[c] = Mq[c];
    for (int k = 0; k < b->nq; k++)
      for (int c = 0; c < 3; c++) M[c] += b->md[k][c];
    e[4] = cs * (M[0] * M[0] + M[1] * M[1] + M[2] * M[2]);
    for (int k = 0; k < b->nq; k++)
      for (int c = 0; c < 3; c++) {
        b->fq[k][c] -= 2.0 * cs * b->q[k] * M[c];
        b->eq[k][c] -= 2.0 * cs * M[c];
      }
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) W[3 * r + c] += -2.0 * cs * Mq[r] * M[c] + (r == c ? e[4] : 0.0);
    return;
  }
  double M[3] = {0, 0, 0};
  for (int k = 0; k < b->nq; k++)
    for (int c = 0; c < 3; c++) M[c] += b->q[k] * b->xq[k][c];
  e[4] = cs * (M[0] * M[0] + M[1] * M[1] + M[2] * M[2]);
  for (int k = 0; k < b->nq; k++)
    for (int c = 0; c < 3; c++) b->fq[k][c] -= 2.0 * cs * b->q[k] * M[c];
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) W[3 * r + c] += -2.0 * cs * M[r] * M[c] + (r == c ? e[4] : 0.0);
}

void ew_finish(ew_base *b, const rl_system *sys, rl_forces *out, double etotal, const double W[9])
{
  /* site forces, then bodies (each body sums its own sites, in order: any thread count) */
  const int T = b->threads;
  (void)T; /* a build without OpenMP */
  memset(b->fs, 0, sizeof(double[3]) * (size_t)b->nsites);
  for (int k = 0; k < b->nq; k++) memcpy(b->fs[b->qsite[k]], b->fq[k], sizeof(double[3]));
#ifdef _OPENMP
#pragma omp parallel num_threads(T) if (T > 1 && b->n >= RL_THREAD_MIN_BODIES)
#endif
  {
    int i0, i1;
    rl_thread_range(b->n, &i0, &i1);
    rl_system_add_site_forces_of(sys, (const double(*)[3])b->fs, out, i0, i1);
  }
  /* the dipoles' torques md x E (site order: the same sums for any thread count) */
  if (b->ndip)
    for (int k = 0; k < b->nq; k++) {
      const int ri = b->mu[k] != 0.0 ? rl_system_rot_index(sys, b->qbody[k]) : -1;
      if (ri < 0) continue;
      const double *m = b->md[k], *E = b->eq[k];
      out->k[ri][0] += m[1] * E[2] - m[2] * E[1];
      out->k[ri][1] += m[2] * E[0] - m[0] * E[2];
      out->k[ri][2] += m[0] * E[1] - m[1] * E[0];
    }
  if (out->forces_only) return;
  out->energy += etotal;
  /* molecular virial: W_site - sum_a d_a (x) f_a, d_a = r_a - R (virial[3r + c] = sum r_r f_c) */
  double Wm[9];
  memcpy(Wm, W, sizeof Wm);
  for (int k = 0; k < b->nq; k++) {
    const double *x = b->xq[k], *R = b->rc[b->qbody[k]], *f = b->fq[k];
    const double d[3] = {x[0] - R[0], x[1] - R[1], x[2] - R[2]};
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) Wm[3 * r + c] -= d[r] * f[c];
  }
  for (int j = 0; j < 9; j++) out->virial[j] += Wm[j];
}

int ew_compute(ew_base *b, const rl_system *sys, rl_forces *out, double *energies, int ne)
{
  int st = ew_gather(b, sys);
  if (st) return st;
  double e[5] = {0, 0, 0, 0, 0}, W[9] = {0};
  st = b->part(b, &e[0], W);
  if (st) return st;
  if (ne == 5) ew_reciprocal_extras(b, e, W);
  double total = 0.0;
  for (int j = 0; j < ne; j++) total += e[j];
  ew_finish(b, sys, out, total, W);
  for (int j = 0; j < ne; j++) energies[j] = out->forces_only ? NAN : e[j];
  return RL_OK;
}

const rl_ewald_info *rl_ewald_term_info(const void *state) { return state ? &((const ew_base *)state)->info : NULL; }

int rl_ewald_warnings(const void *state, rl_ff_warning *out, int max)
{
  const ew_base *b = state;
  if (!b || b->info.method == RL_EWALD_REAL || fabs(b->info.net_charge) <= 1e-12 * sqrt(b->info.sum_q2)) return 0;
  if (max > 0 && out) {
    const double kc = b->info.coulomb_constant, Q = b->info.net_charge, V = b->L[0] * b->L[1] * b->L[2];
    snprintf(out[0].text, sizeof out[0].text,
             "the system carries a net charge of %.6g e: the Ewald sum adds a uniform neutralising background "
             "(energy %.6g %s, reported as ewald_background), so the result is that of the charges in a jellium",
             Q, -kc * M_PI * Q * Q / (2.0 * V * b->info.alpha * b->info.alpha), b->units == RL_UNITS_LJ ? "epsilon" : "kJ/mol");
  }
  return 1;
}

int rl_ewald_site_forces(void *state, const rl_system *sys, double (*fs)[3], double *energies, double virial_site[9])
{
  ew_base *b = state;
  if (!b || !sys || !fs) return rl_error(RL_EINVAL, "rl_ewald_site_forces: NULL argument");
  int st = ew_gather(b, sys);
  if (st) return st;
  double e[5] = {0, 0, 0, 0, 0}, W[9] = {0};
  st = b->part(b, &e[0], W);
  if (st) return st;
  const int ne = b->info.method == RL_EWALD_REAL ? 1 : 5;
  if (ne == 5) ew_reciprocal_extras(b, e, W);
  memset(fs, 0, sizeof(double[3]) * (size_t)b->nsites);
  for (int k = 0; k < b->nq; k++) memcpy(fs[b->qsite[k]], b->fq[k], sizeof(double[3]));
  if (energies)
    for (int j = 0; j < ne; j++) energies[j] = e[j];
  if (virial_site) memcpy(virial_site, W, sizeof W);
  return RL_OK;
}

double rl_ewald_intra_site_forces(const void *state, const rl_system *sys, double (*fs)[3])
{
  const ew_base *b = state;
  double (*x)[3] = malloc(sizeof(double[3]) * (size_t)(b->nsites ? b->nsites : 1));
  if (!x) return NAN;
  rl_system_site_positions(sys, x);
  memset(fs, 0, sizeof(double[3]) * (size_t)b->nsites);
  const double kc = b->info.coulomb_constant, a = b->info.alpha;
  double U = 0.0;
  for (int k = 0; k < b->nq; k++)
    for (int m = k + 1; m < b->qmol_first[k] + b->qmol_count[k]; m++) {
      const double *xa = x[b->qsite[k]], *xb = x[b->qsite[m]];
      const double d[3] = {xa[0] - xb[0], xa[1] - xb[1], xa[2] - xb[2]};
      const double r = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), qq = kc * b->q[k] * b->q[m];
      U -= qq * erf_over_r(a, r);
      if (r == 0.0) continue;
      /* U_ab = -qq erf(a r)/r: f_a = -dU/dr r/r = qq (d/dr)(erf(a r)/r) d/r */
      const double dfr = (2.0 * a / sqrt(M_PI) * exp(-a * a * r * r) * r - erf(a * r)) / (r * r);
      for (int c = 0; c < 3; c++) {
        fs[b->qsite[k]][c] += qq * dfr * d[c] / r;
        fs[b->qsite[m]][c] -= qq * dfr * d[c] / r;
      }
    }
  free(x);
  return U;
}
