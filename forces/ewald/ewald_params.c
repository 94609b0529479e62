/* Ewald parameters (ewald.h): defaults, the choices OpenMM 7.7 makes from its error tolerance,
 * checks that name the parameter, the estimated RMS force errors, and the one-line description. */
#include "ewald_impl.h"
#include "rotleap/error.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* Largest mesh (points) and Ewald set (vectors) accepted: a cutoff that needs more leaves the
 * whole sum to reciprocal space. */
#define EW_MAX_GRID_POINTS (1L << 27)
#define EW_MAX_KVECTORS (1L << 24)
#define EW_MAX_ORDER 12

void rl_ewald_params_default(rl_ewald_params *p)
{
  *p = (rl_ewald_params){0};
  p->tolerance = 5e-4;
  p->eps_surface = INFINITY;
}

/* OpenMM 7.7 NonbondedForceImpl::EwaldErrorFunction and findZero (initial guess 10). */
static double omm_ewald_error(double width, double alpha, double target, int arg)
{
  double temp = arg * M_PI / (width * alpha);
  return target - 0.05 * sqrt(width * alpha) * arg * exp(-temp * temp);
}

static int omm_kmax(double width, double alpha, double tol)
{
  int arg = 10;
  double value = omm_ewald_error(width, alpha, tol, arg);
  if (value > 0.0) {
    while (value > 0.0 && arg > 0) value = omm_ewald_error(width, alpha, tol, --arg);
    arg = arg + 1;
  } else {
    while (value < 0.0) value = omm_ewald_error(width, alpha, tol, ++arg);
  }
  if (arg % 2 == 0) arg++;
  return arg;
}

/* Whether the integer vector n is in the Ewald set (either half). */
static int in_set(const int n[3], const int kmax[3], double kmax_sq)
{
  for (int c = 0; c < 3; c++)
    if (abs(n[c]) > kmax[c]) return 0;
  return !(kmax_sq > 0 && (double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2] > kmax_sq);
}

/* |k|^2 of the shortest nonzero vector outside the Ewald set; the number of vectors in the
 * half space. */
static double ewald_shortest_omitted(const int kmax[3], double kmax_sq, const double L[3], long *nhalf)
{
  double best = INFINITY;
  long count = 0;
  for (int x = -kmax[0] - 1; x <= kmax[0] + 1; x++)
    for (int y = -kmax[1] - 1; y <= kmax[1] + 1; y++)
      for (int z = -kmax[2] - 1; z <= kmax[2] + 1; z++) {
        const int n[3] = {x, y, z};
        if (!x && !y && !z) continue;
        const double kx = 2 * M_PI * x / L[0], ky = 2 * M_PI * y / L[1], kz = 2 * M_PI * z / L[2];
        const double k2 = kx * kx + ky * ky + kz * kz;
        if (in_set(n, kmax, kmax_sq)) {
          count += x > 0 || (x == 0 && (y > 0 || (y == 0 && z > 0)));
        } else if (k2 < best) {
          best = k2;
        }
      }
  *nhalf = count;
  return best;
}

double ew_err_real(const rl_ewald_info *in, double V)
{
  const double a = in->alpha, rc = in->cutoff;
  return 2.0 * in->coulomb_constant * in->sum_q2 * exp(-a * a * rc * rc) / sqrt(in->nsites_charged * rc * V);
}

/* dF = kc sum q^2 / V sqrt(S / N), S = sum over the omitted vectors of |k phi(k)|^2,
 * phi(k) = 4 pi exp(-k^2 / 4 alpha^2) / k^2; the omitted vectors out to where their terms fall
 * below e^-40 of the first one. */
double ew_err_ewald(const rl_ewald_info *in, const double L[3])
{
  long nhalf;
  const double k0 = ewald_shortest_omitted(in->kmax, in->kmax_sq, L, &nhalf);
  const double a2 = in->alpha * in->alpha, kcut2 = k0 + 80.0 * a2;
  int nm[3];
  for (int c = 0; c < 3; c++) nm[c] = (int)ceil(L[c] * sqrt(kcut2) / (2 * M_PI));
  double S = 0.0;
  for (int x = 0; x <= nm[0]; x++) /* half space, doubled */
    for (int y = x ? -nm[1] : 0; y <= nm[1]; y++)
      for (int z = (x || y) ? -nm[2] : 1; z <= nm[2]; z++) {
        const int n[3] = {x, y, z};
        if (in_set(n, in->kmax, in->kmax_sq)) continue;
        const double kx = 2 * M_PI * x / L[0], ky = 2 * M_PI * y / L[1], kz = 2 * M_PI * z / L[2];
        const double k2 = kx * kx + ky * ky + kz * kz;
        if (k2 > kcut2) continue;
        S += 2.0 * 16.0 * M_PI * M_PI * exp(-k2 / (2.0 * a2)) / k2;
      }
  const double V = L[0] * L[1] * L[2];
  return in->coulomb_constant * in->sum_q2 / V * sqrt(S / in->nsites_charged);
}

/* The mesh: Hockney & Eastwood's Q for analytical differentiation and the SPME influence
 * function G = phi(k) / B(m) (B the product of the B-spline moduli):
 *   Q = sum_{m != 0} [ sum_l |k_l|^2 phi_l^2 - 2 G sum_l |k_l|^2 phi_l U_l^2
 *                      + G^2 (sum_l |k_l|^2 U_l^2) (sum_l U_l^2) ],
 * k_l = 2 pi (m + l K) / L the aliases of the mesh vector m, U_l = prod_c sinc(pi (m_c + l_c K_c)
 * / K_c)^p the Fourier transform of the B-spline; dF = kc sum q^2 / V sqrt(Q / N).  The sums
 * over l run over |l_c| <= 4 where they factorise by axis (U^2, k^2 U^2, exp(-k^2/4a^2) U^2) and
 * over |l_c| <= 1 for sum_l |k_l|^2 phi_l^2 (whose aliases fall as exp(-k^2 / 2 alpha^2)). */
#define EW_ALIAS 4
double ew_err_pme(const rl_ewald_info *in, const double L[3], const double *mod[3])
{
  const double a2 = in->alpha * in->alpha;
  const int p = in->order;
  double *A1[3], *A2[3], *A3[3], *K2[3], *E2[3]; /* per axis and mesh index */
  int ok = 1;
  for (int c = 0; c < 3; c++) {
    const int K = in->grid[c];
    A1[c] = malloc(sizeof(double) * (size_t)K * 9); /* A1 A2 A3, then k^2 and exp(-k^2/2a^2) for l = -1, 0, 1 */
    ok &= A1[c] != NULL;
  }
  if (!ok) {
    for (int c = 0; c < 3; c++) free(A1[c]);
    return NAN;
  }
  for (int c = 0; c < 3; c++) {
    const int K = in->grid[c];
    A2[c] = A1[c] + K;
    A3[c] = A1[c] + 2 * K;
    K2[c] = A1[c] + 3 * K;
    E2[c] = A1[c] + 6 * K;
    for (int i = 0; i < K; i++) {
      const int m = i < (K + 1) / 2 ? i : i - K;
      double s1 = 0, s2 = 0, s3 = 0;
      for (int l = -EW_ALIAS; l <= EW_ALIAS; l++) {
        const double ml = m + (double)l * K, x = M_PI * ml / K;
        const double u = ml == 0 ? 1.0 : pow(sin(x) / x, p), u2 = u * u;
        const double k = 2 * M_PI * ml / L[c];
        s1 += u2;
        s2 += k * k * u2;
        s3 += exp(-k * k / (4 * a2)) * u2;
        if (l >= -1 && l <= 1) {
          K2[c][3 * i + l + 1] = k * k;
          E2[c][3 * i + l + 1] = exp(-k * k / (2 * a2));
        }
      }
      A1[c][i] = s1;
      A2[c][i] = s2;
      A3[c][i] = s3;
    }
  }
  const int Kx = in->grid[0], Ky = in->grid[1], Kz = in->grid[2];
  double Q = 0.0;
  for (int ix = 0; ix < Kx; ix++)
    for (int iy = 0; iy < Ky; iy++)
      for (int iz = 0; iz <= Kz / 2; iz++) { /* m and -m give the same term */
        if (!ix && !iy && !iz) continue;
        const double w = (iz == 0 || (Kz % 2 == 0 && iz == Kz / 2)) ? 1.0 : 2.0;
        const double k2 = K2[0][3 * ix + 1] + K2[1][3 * iy + 1] + K2[2][3 * iz + 1];
        const double G = 4 * M_PI * exp(-k2 / (4 * a2)) / k2 / (mod[0][ix] * mod[1][iy] * mod[2][iz]);
        double sum1 = 0.0;
        for (int lx = 0; lx < 3; lx++)
          for (int ly = 0; ly < 3; ly++)
            for (int lz = 0; lz < 3; lz++) {
              const double kk = K2[0][3 * ix + lx] + K2[1][3 * iy + ly] + K2[2][3 * iz + lz];
              sum1 += 16 * M_PI * M_PI * E2[0][3 * ix + lx] * E2[1][3 * iy + ly] * E2[2][3 * iz + lz] / kk;
            }
        const double sum2 = 4 * M_PI * A3[0][ix] * A3[1][iy] * A3[2][iz];
        const double sum3 = A1[0][ix] * A1[1][iy] * A1[2][iz];
        const double sum4 = A2[0][ix] * A1[1][iy] * A1[2][iz] + A1[0][ix] * A2[1][iy] * A1[2][iz] +
                            A1[0][ix] * A1[1][iy] * A2[2][iz];
        Q += w * (sum1 - 2 * G * sum2 + G * G * sum3 * sum4);
      }
  for (int c = 0; c < 3; c++) free(A1[c]);
  const double V = L[0] * L[1] * L[2];
  return in->coulomb_constant * in->sum_q2 / V * sqrt(fmax(Q, 0.0) / in->nsites_charged);
}

static const char *method_key(rl_ewald_method m) { return m == RL_EWALD_PME ? "pme" : m == RL_EWALD_SUM ? "ewald" : "ewald-real"; }

int ew_resolve(const rl_system *sys, const rl_ewald_params *p, rl_ewald_method method, const rl_ewald_info *keep,
               rl_ewald_info *in)
{
  if (!sys || !p || !in) return rl_error(RL_EINVAL, "rl_ewald_resolve: NULL argument");
  if (method != RL_EWALD_REAL && method != RL_EWALD_SUM && method != RL_EWALD_PME)
    return rl_error(RL_EINVAL, "rl_ewald_resolve: unknown method %d", (int)method);
  const char *who = method_key(method);
  *in = (rl_ewald_info){0};
  in->method = method;
  if (!rl_system_periodic(sys)) return rl_error(RL_EINVAL, "%s: the system has no periodic box (Ewald sums need one)", who);
  double L[3];
  rl_system_box(sys, L);
  /* species and charges (at alloc; a change of cell keeps what alloc found: the caller's arrays
   * need not outlive the alloc) */
  double q2 = 0.0, Q = 0.0, mu2 = 0.0;
  long nq = 0, nd = 0;
  if (keep) {
    nq = keep->nsites_charged;
    q2 = keep->sum_q2;
    Q = keep->net_charge;
    nd = keep->nsites_dipolar;
    mu2 = keep->sum_mu2;
  } else {
    const int ns = rl_system_nspecies(sys);
    if (p->nspecies != ns || (ns && !p->species))
      return rl_error(RL_EINVAL, "%s: species: %d given, the system has %d", who, p->nspecies, ns);
    for (int s = 0; s < ns; s++) {
      const rl_species_ff *f = &p->species[s];
      const int m = rl_system_species_nsites(sys, s), count = rl_system_species_count(sys, s);
      const char *name = rl_system_species_name(sys, s);
      if (f->nsites != m)
        return rl_error(RL_EINVAL, "%s: species %d (%s): %d sites given, the system has %d", who, s, name ? name : "", f->nsites, m);
      for (int a = 0; a < m; a++) {
        if (f->quadrupole && f->quadrupole[a] != 0.0)
          return rl_error(RL_EINVAL, "%s: species %d (%s), site %d carries a quadrupole: the Ewald terms sum point charges "
                          "and point dipoles only (quadrupoles are not supported)", who, s, name ? name : "", a);
        const double mu = f->dipole ? f->dipole[a] : 0.0;
        if (!isfinite(mu)) return rl_error(RL_EINVAL, "%s: species %d (%s), site %d: dipole %g is not finite", who, s, name ? name : "", a, mu);
        if (mu != 0.0) {
          nd += count;
          mu2 += (double)count * mu * mu;
        }
        const double q = f->charge ? f->charge[a] : 0.0;
        if (!isfinite(q)) return rl_error(RL_EINVAL, "%s: species %d (%s), site %d: charge %g is not finite", who, s, name ? name : "", a, q);
        if (q == 0.0) continue;
        nq += count;
        q2 += (double)count * q * q;
        Q += (double)count * q;
      }
    }
    if (nq == 0 && nd == 0)
      return rl_error(RL_EINVAL, "%s: no site carries a charge or a point dipole: there is nothing for an Ewald sum to sum", who);
  }
  in->nsites_charged = (int)nq;
  in->nsites_dipolar = (int)nd;
  in->sum_mu2 = mu2;
  in->sum_q2 = q2;
  in->net_charge = Q;
  in->volume = L[0] * L[1] * L[2];
  /* tolerance, cutoff, alpha */
  const double tol = p->tolerance;
  if (!(tol > 0.0 && tol < 0.1))
    return rl_error(RL_EINVAL, "%s: tolerance = %g must lie in (0, 0.1) (the relative force error aimed at, OpenMM's "
                    "ewaldErrorTolerance; 5e-4 is OpenMM's default)", who, tol);
  in->tolerance = tol;
  const double rc = p->cutoff;
  if (!(rc > 0.0) || !isfinite(rc)) return rl_error(RL_EINVAL, "%s: cutoff = %g must be positive and finite", who, rc);
  for (int c = 0; c < 3; c++)
    if (rc > 0.5 * L[c])
      return rl_error(RL_EINVAL, "%s: cutoff = %g exceeds half the box edge %c = %g (the minimum image would miss pairs)",
                      who, rc, "xyz"[c], L[c]);
  in->cutoff = rc;
  if (!(p->alpha >= 0.0) || !isfinite(p->alpha))
    return rl_error(RL_EINVAL, "%s: alpha = %g must be positive (or 0: from the tolerance)", who, p->alpha);
  if (keep) {
    in->alpha = keep->alpha;
    in->alpha_derived = keep->alpha_derived;
  } else if (p->alpha == 0.0) {
    in->alpha = (1.0 / rc) * sqrt(-log(2.0 * tol)); /* OpenMM's expression, operation for operation */
    in->alpha_derived = 1;
  } else {
    in->alpha = p->alpha;
    const double ar = in->alpha * rc;
    if (ar < sqrt(-log(0.2)))
      return rl_error(RL_EINVAL, "%s: alpha = %g with cutoff = %g: alpha cutoff = %.4g is below sqrt(-ln 0.2) = 1.269, "
                      "so the real-space sum would be cut where erfc(alpha r) = %.3g of the Coulomb pair terms remains "
                      "(more than the largest tolerance, 0.1, allows); raise alpha or the cutoff",
                      who, in->alpha, rc, ar, erfc(ar));
  }
  if (isnan(p->eps_surface) || p->eps_surface < 1.0)
    return rl_error(RL_EINVAL, "%s: eps_surface = %g must be >= 1 (1: vacuum) or infinite (conducting, tin foil)", who, p->eps_surface);
  in->eps_surface = p->eps_surface;
  if (p->coulomb_constant < 0.0 || !isfinite(p->coulomb_constant))
    return rl_error(RL_EINVAL, "%s: coulomb_constant = %g must be positive (or 0: that of the units)", who, p->coulomb_constant);
  in->coulomb_constant = p->coulomb_constant > 0.0 ? p->coulomb_constant
                         : rl_system_units(sys) == RL_UNITS_LJ ? 1.0 : RL_COULOMB_KJMOL_NM;
  if (p->threads < 0) return rl_error(RL_EINVAL, "%s: threads = %d must be >= 0", who, p->threads);
  in->threads = p->threads;
  const double a2 = in->alpha * in->alpha;
  in->err_real = ew_err_real(in, in->volume);
  in->err_recip = NAN;
  in->err_total = in->err_real;
  if (method == RL_EWALD_SUM) {
    for (int c = 0; c < 3; c++) {
      if (p->kmax[c] < 0) return rl_error(RL_EINVAL, "ewald: kmax[%d] = %d must be >= 0 (0: from the tolerance)", c, p->kmax[c]);
      in->kmax[c] = keep ? keep->kmax[c] : p->kmax[c] ? p->kmax[c] : omm_kmax(L[c], in->alpha, tol) - 1;
      in->kmax_derived |= p->kmax[c] == 0;
    }
    if (keep) in->kmax_derived = keep->kmax_derived;
    if (!(p->kmax_sq >= 0.0) || !isfinite(p->kmax_sq))
      return rl_error(RL_EINVAL, "ewald: kmax_sq = %g must be >= 0 (0: no spherical limit)", p->kmax_sq);
    in->kmax_sq = p->kmax_sq;
    const double vol = (2.0 * in->kmax[0] + 1) * (2.0 * in->kmax[1] + 1) * (2.0 * in->kmax[2] + 1);
    if (vol / 2 > EW_MAX_KVECTORS)
      return rl_error(RL_EINVAL, "ewald: kmax = %d %d %d gives %.3g vectors (at most %ld): %s", in->kmax[0], in->kmax[1],
                      in->kmax[2], vol / 2, EW_MAX_KVECTORS,
                      in->kmax_derived ? "the cutoff is too short for the tolerance (alpha = sqrt(-ln 2 tolerance) / cutoff "
                                         "puts the sum in reciprocal space); use PME or a longer cutoff"
                                       : "reduce kmax");
    long nhalf;
    const double k0 = ewald_shortest_omitted(in->kmax, in->kmax_sq, L, &nhalf);
    in->nkvec = nhalf;
    if (nhalf == 0) return rl_error(RL_EINVAL, "ewald: kmax = %d %d %d with kmax_sq = %g leaves no k vector", in->kmax[0], in->kmax[1], in->kmax[2], in->kmax_sq);
    if (!in->kmax_derived || p->kmax_sq > 0) {
      const double left = exp(-k0 / (4 * a2));
      if (left > 10 * tol)
        return rl_error(RL_EINVAL, "ewald: kmax = %d %d %d, kmax_sq = %g is too coarse for tolerance %g: the shortest vector "
                        "left out, |k| = %.4g, still carries exp(-k^2/4 alpha^2) = %.3g of its weight (more than 10 tolerance); "
                        "raise kmax (or kmax_sq), or the tolerance", in->kmax[0], in->kmax[1], in->kmax[2], in->kmax_sq, tol,
                        sqrt(k0), left);
    }
    in->err_recip = ew_err_ewald(in, L);
  } else if (method == RL_EWALD_PME) {
    in->order = keep ? keep->order : p->order ? p->order : 5;
    if (in->order < 3 || in->order > EW_MAX_ORDER)
      return rl_error(RL_EINVAL, "pme: order = %d must lie in 3..%d (0: 5, OpenMM's)", p->order, EW_MAX_ORDER);
    double total = 1.0;
    for (int c = 0; c < 3; c++) {
      if (p->grid[c] < 0) return rl_error(RL_EINVAL, "pme: grid[%d] = %d must be >= 0 (0: from the tolerance)", c, p->grid[c]);
      if (keep) {
        in->grid[c] = keep->grid[c];
        in->grid_derived = keep->grid_derived;
      } else if (p->grid[c]) {
        in->grid[c] = p->grid[c];
      } else {
        const double g = ceil(2 * in->alpha * L[c] / (3 * pow(tol, 0.2))); /* OpenMM's expression */
        in->grid[c] = g > 6 ? (g < 1e9 ? (int)g : 1000000000) : 6;
        in->grid_derived = 1;
      }
      total *= in->grid[c];
      if (in->grid[c] < in->order)
        return rl_error(RL_EINVAL, "pme: grid[%d] = %d is below the spline order %d", c, in->grid[c], in->order);
    }
    if (total > EW_MAX_GRID_POINTS)
      return rl_error(RL_EINVAL, "pme: a grid of %d x %d x %d points (%.3g; at most %ld) %s", in->grid[0], in->grid[1], in->grid[2],
                      total, EW_MAX_GRID_POINTS,
                      in->grid_derived ? "follows from the cutoff and tolerance: the cutoff is too short (alpha = sqrt(-ln 2 "
                                         "tolerance) / cutoff puts the sum in reciprocal space); lengthen the cutoff"
                                       : "is too large");
    for (int c = 0; c < 3; c++) {
      if (!p->grid[c] || (keep && keep->grid_derived)) continue; /* derived counts are OpenMM's: not checked */
      const double kn = M_PI * in->grid[c] / L[c], left = exp(-kn * kn / (4 * a2));
      if (left > 10 * tol)
        return rl_error(RL_EINVAL, "pme: grid[%d] = %d is too coarse for tolerance %g: at its Nyquist wave vector pi K/L = "
                        "%.4g the screening exp(-k^2/4 alpha^2) = %.3g is more than 10 tolerance; refine the grid (or raise "
                        "the tolerance)", c, in->grid[c], tol, kn, left);
    }
    double *mod[3] = {NULL, NULL, NULL};
    int ok = 1;
    for (int c = 0; c < 3; c++) {
      mod[c] = malloc(sizeof(double) * (size_t)in->grid[c]);
      ok &= mod[c] != NULL;
      if (mod[c]) ew_bspline_moduli(in->order, in->grid[c], mod[c]);
    }
    in->err_recip = ok ? ew_err_pme(in, L, (const double **)mod) : NAN;
    for (int c = 0; c < 3; c++) free(mod[c]);
    if (!ok) return rl_error(RL_ENOMEM, "pme: out of memory");
  }
  if (method != RL_EWALD_REAL) in->err_total = sqrt(in->err_real * in->err_real + in->err_recip * in->err_recip);
  return RL_OK;
}

int rl_ewald_describe(const rl_ewald_info *in, rl_units units, char *buf, size_t size)
{
  const int lj = units == RL_UNITS_LJ;
  const char *len = lj ? "sigma" : "nm", *force = lj ? "epsilon/sigma" : "kJ/mol/nm";
  char a[200], k[200] = "", b[96];
  snprintf(a, sizeof a, "alpha = %.6g /%s (%s%.3g and cutoff %.6g %s)", in->alpha, len,
           in->alpha_derived ? "from tolerance " : "given; tolerance ", in->tolerance, in->cutoff, len);
  if (in->method == RL_EWALD_SUM) {
    char sq[48] = "";
    if (in->kmax_sq > 0) snprintf(sq, sizeof sq, ", n^2 <= %.6g", in->kmax_sq);
    snprintf(k, sizeof k, ", |n| <= %d %d %d%s (%s; %ld vectors)", in->kmax[0], in->kmax[1], in->kmax[2], sq,
             in->kmax_derived ? "from the tolerance" : "given", in->nkvec);
  } else if (in->method == RL_EWALD_PME) {
    snprintf(k, sizeof k, ", grid %d x %d x %d (%s), order %d", in->grid[0], in->grid[1], in->grid[2],
             in->grid_derived ? "from the tolerance" : "given", in->order);
  }
  if (isinf(in->eps_surface)) snprintf(b, sizeof b, "tin-foil boundary");
  else snprintf(b, sizeof b, "dielectric boundary eps' = %.6g", in->eps_surface);
  const char *name = in->method == RL_EWALD_PME ? "smooth PME" : in->method == RL_EWALD_SUM ? "Ewald" : "Ewald real space";
  if (in->nsites_dipolar > 0) { /* the estimates are those for charges (none for the dipoles) */
    char dp[64] = "";
    if (in->nsites_charged > 0) snprintf(dp, sizeof dp, "; RMS force error on a charge %.3g %s", in->method == RL_EWALD_REAL ? in->err_real : in->err_total, force);
    return snprintf(buf, size, "%s of %s: %s%s%s%s; no error estimate for the dipoles%s", name,
                    in->nsites_charged > 0 ? "charges and point dipoles" : "point dipoles", a, k,
                    in->method == RL_EWALD_REAL ? "" : ", ", in->method == RL_EWALD_REAL ? "" : b, dp);
  }
  if (in->method == RL_EWALD_REAL)
    return snprintf(buf, size, "%s: %s; estimated RMS force error of the real-space cut on a charge %.3g %s", name, a,
                    in->err_real, force);
  return snprintf(buf, size, "%s: %s%s, %s; estimated RMS force error on a charge %.3g %s (real space %.3g, reciprocal %.3g)",
                  name, a, k, b, in->err_total, force, in->err_real, in->err_recip);
}

int rl_ewald_resolve(const rl_system *sys, const rl_ewald_params *p, rl_ewald_method method, rl_ewald_info *in)
{
  return ew_resolve(sys, p, method, NULL, in);
}
