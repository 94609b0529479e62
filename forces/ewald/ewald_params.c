/* Ewald parameters (ewald.h): defaults, the choices OpenMM 7.7 makes from its error tolerance,
 * checks that name the parameter, the estimated RMS force errors, and the one-line description. */
#include "ewald_impl.h"
#include "rotleap/error.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

/* The sums over the vectors outside the Ewald set, out to where their terms fall below e^-40
 * of the first one, of |k phi(k)|^2 (S[0]) and, with dip, phi^2 k^6 (S[1]) and phi^2 k^4 (S[2]);
 * phi(k) = 4 pi exp(-k^2 / 4 alpha^2) / k^2. */
static void ewald_omitted(const rl_ewald_info *in, const double L[3], int dip, double S[3])
{
  long nhalf;
  const double k0 = ewald_shortest_omitted(in->kmax, in->kmax_sq, L, &nhalf);
  const double a2 = in->alpha * in->alpha, kcut2 = k0 + 80.0 * a2;
  int nm[3];
  for (int c = 0; c < 3; c++) nm[c] = (int)ceil(L[c] * sqrt(kcut2) / (2 * M_PI));
  S[0] = S[1] = S[2] = 0.0;
  for (int x = 0; x <= nm[0]; x++) /* half space, doubled */
    for (int y = x ? -nm[1] : 0; y <= nm[1]; y++)
      for (int z = (x || y) ? -nm[2] : 1; z <= nm[2]; z++) {
        const int n[3] = {x, y, z};
        if (in_set(n, in->kmax, in->kmax_sq)) continue;
        const double kx = 2 * M_PI * x / L[0], ky = 2 * M_PI * y / L[1], kz = 2 * M_PI * z / L[2];
        const double k2 = kx * kx + ky * ky + kz * kz;
        if (k2 > kcut2) continue;
        const double t = 2.0 * 16.0 * M_PI * M_PI * exp(-k2 / (2.0 * a2)) / k2;
        S[0] += t;
        if (dip) {
          S[1] += t * k2 * k2;
          S[2] += t * k2;
        }
      }
}

/* dF = kc sum q^2 / V sqrt(S / N), S the sum of |k phi(k)|^2 over the omitted vectors. */
double ew_err_ewald(const rl_ewald_info *in, const double L[3])
{
  double S[3];
  ewald_omitted(in, L, 0, S);
  const double V = L[0] * L[1] * L[2];
  return in->coulomb_constant * in->sum_q2 / V * sqrt(S[0] / in->nsites_charged);
}

/* Point dipoles, the omitted vectors: dF = kc sum mu^2 / V sqrt(S_F / 9N), S_F the sum of
 * phi^2 k^6; dT = kc sum mu^2 / V sqrt(2 S_T / 9N), S_T that of phi^2 k^4 (ewald.h). */
static void ew_dip_err_ewald(const rl_ewald_info *in, const double L[3], double *dF, double *dT)
{
  double S[3];
  ewald_omitted(in, L, 1, S);
  const double c = in->coulomb_constant * in->sum_mu2 / (L[0] * L[1] * L[2]), n9 = 9.0 * in->nsites_dipolar;
  *dF = c * sqrt(S[1] / n9);
  *dT = c * sqrt(2.0 * S[2] / n9);
}

/* Point dipoles, the real-space cut: the force by Wang & Holm 2001, eq. (37) (LAMMPS's
 * ewald/dipole uses it too),
 *   dF = kc sum mu^2 / sqrt(V alpha^4 rc^9 N) sqrt(13/6 C^2 + 2/15 D^2 - 13/15 C D) exp(-x^2),
 * the torque from the field of the pairs beyond rc to the same order (B_1 and B_2 of
 * ewald_dipole.h as x -> inf: B_1 = g A / r^4, B_2 = g C / r^6, g = exp(-x^2) / (alpha sqrt pi),
 * the mean over orientations of |m_i x E|^2 = 2/3 mu_i^2 mu_j^2 (B_1^2 - 2/3 B_1 B_2 r^2 +
 * 1/3 B_2^2 r^4), integrated over r > rc to leading order),
 *   dT = kc sum mu^2 / sqrt(V alpha^4 rc^7 N) sqrt(2/3 (A^2 - 2/3 A C + C^2 / 3)) exp(-x^2),
 * x = alpha rc, A = 2 x^2 + 1, C = 4 x^4 + 6 x^2 + 3, D = 8 x^6 + 20 x^4 + 30 x^2 + 15. */
static void ew_dip_err_real(const rl_ewald_info *in, double alpha, double *dF, double *dT)
{
  const double rc = in->cutoff, x2 = alpha * rc * alpha * rc, ex = exp(-x2), a4 = alpha * alpha * alpha * alpha;
  const double A = 2 * x2 + 1, C = (4 * x2 + 6) * x2 + 3, D = ((8 * x2 + 20) * x2 + 30) * x2 + 15;
  const double c = in->coulomb_constant * in->sum_mu2 * ex / sqrt(in->volume * a4 * pow(rc, 7) * in->nsites_dipolar);
  *dF = c / rc * sqrt(13.0 / 6.0 * C * C + 2.0 / 15.0 * D * D - 13.0 / 15.0 * C * D);
  *dT = c * sqrt(2.0 / 3.0 * (A * A - 2.0 / 3.0 * A * C + C * C / 3.0));
}

/* The mesh: Hockney & Eastwood's Q for analytical differentiation and the SPME influence
 * function G = phi(k) / B(m) (B the product of the B-spline moduli):
 *   Q = sum_{m != 0} [ sum_l |k_l|^2 phi_l^2 - 2 G sum_l |k_l|^2 phi_l U_l^2
 *                      + G^2 (sum_l |k_l|^2 U_l^2) (sum_l U_l^2) ],
 * k_l = 2 pi (m + l K) / L the aliases of the mesh vector m, U_l = prod_c sinc(pi (m_c + l_c K_c)
 * / K_c)^p the Fourier transform of the B-spline; dF = kc sum q^2 / V sqrt(Q / N).  The sums
 * over l run over |l_c| <= 4 where they factorise by axis (U^2, k^2 U^2, exp(-k^2/4a^2) U^2) and
 * over |l_c| <= 1 for sum_l |k_l|^2 phi_l^2 (whose aliases fall as exp(-k^2 / 2 alpha^2)). */
/* a[c] = per * K[c] doubles for each axis; -1 (none left allocated) out of memory. */
static int alloc_axes(double *a[3], const int K[3], int per)
{
  int ok = 1;
  for (int c = 0; c < 3; c++) {
    a[c] = malloc(sizeof(double) * (size_t)K[c] * (size_t)per);
    ok &= a[c] != NULL;
  }
  if (ok) return 0;
  for (int c = 0; c < 3; c++) free(a[c]);
  return -1;
}

#define EW_ALIAS 4
#define EW_SKIP 320.0 /* the dipolar sums leave out mesh vectors with k^2 / 4 alpha^2 > 80 */
/* Q of charges (Q[0]) and, with dip, Q_F (Q[1]) and Q_T (Q[2]) of point dipoles (ewald.h): the
 * factorised alias sums per axis are sum_l U^2 k^j (j = 0, 2, 4) and sum_l exp(-k^2/4a^2) U^2 k^j,
 * combined over the axes by (kx^2 + ky^2 + kz^2)^2 = sum_c k_c^4 + 2 sum_{c<d} k_c^2 k_d^2. */
static int pme_functionals(const rl_ewald_info *in, const double L[3], const double *mod[3], int dip, double Q[3])
{
  const double a2 = in->alpha * in->alpha;
  const int p = in->order;
  /* per axis and mesh index: A1 A2 A3, k^2 and exp(-k^2/2a^2) for l = -1, 0, 1, then (dip)
   * A4 = sum U^2 k^4, E2 = sum exp(-k^2/4a^2) U^2 k^2, E4 = sum exp(-k^2/4a^2) U^2 k^4 */
  double *A1[3], *A2[3], *A3[3], *K2[3], *E2[3], *A4[3], *X2[3], *X4[3];
  if (alloc_axes(A1, in->grid, dip ? 12 : 9)) return -1;
  for (int c = 0; c < 3; c++) {
    const int K = in->grid[c];
    A2[c] = A1[c] + K;
    A3[c] = A1[c] + 2 * K;
    K2[c] = A1[c] + 3 * K;
    E2[c] = A1[c] + 6 * K;
    A4[c] = A1[c] + 9 * K;
    X2[c] = A1[c] + 10 * K;
    X4[c] = A1[c] + 11 * K;
    for (int i = 0; i < K; i++) {
      const int m = i < (K + 1) / 2 ? i : i - K;
      double s1 = 0, s2 = 0, s3 = 0, s4 = 0, x2 = 0, x4 = 0;
      for (int l = -EW_ALIAS; l <= EW_ALIAS; l++) {
        const double ml = m + (double)l * K, x = M_PI * ml / K;
        const double u = ml == 0 ? 1.0 : pow(sin(x) / x, p), u2 = u * u;
        const double k = 2 * M_PI * ml / L[c];
        const double e = exp(-k * k / (4 * a2));
        s1 += u2;
        s2 += k * k * u2;
        s3 += e * u2;
        if (dip) {
          s4 += k * k * k * k * u2;
          x2 += e * u2 * k * k;
          x4 += e * u2 * k * k * k * k;
        }
        if (l >= -1 && l <= 1) {
          K2[c][3 * i + l + 1] = k * k;
          E2[c][3 * i + l + 1] = exp(-k * k / (2 * a2));
        }
      }
      A1[c][i] = s1;
      A2[c][i] = s2;
      A3[c][i] = s3;
      if (dip) {
        A4[c][i] = s4;
        X2[c][i] = x2;
        X4[c][i] = x4;
      }
    }
  }
  const int Kx = in->grid[0], Ky = in->grid[1], Kz = in->grid[2];
  Q[0] = Q[1] = Q[2] = 0.0;
  for (int ix = 0; ix < Kx; ix++)
    for (int iy = 0; iy < Ky; iy++)
      for (int iz = 0; iz <= Kz / 2; iz++) { /* m and -m give the same term */
        if (!ix && !iy && !iz) continue;
        const double w = (iz == 0 || (Kz % 2 == 0 && iz == Kz / 2)) ? 1.0 : 2.0;
        const double k2 = K2[0][3 * ix + 1] + K2[1][3 * iy + 1] + K2[2][3 * iz + 1];
        if (dip && k2 > EW_SKIP * a2) continue; /* every term below exp(-80) (the aliases lie further out) */
        const double G = 4 * M_PI * exp(-k2 / (4 * a2)) / k2 / (mod[0][ix] * mod[1][iy] * mod[2][iz]);
        double sum1 = 0.0, sum1F = 0.0, sum1T = 0.0;
        for (int lx = 0; lx < 3; lx++)
          for (int ly = 0; ly < 3; ly++)
            for (int lz = 0; lz < 3; lz++) {
              const double kk = K2[0][3 * ix + lx] + K2[1][3 * iy + ly] + K2[2][3 * iz + lz];
              const double t = 16 * M_PI * M_PI * E2[0][3 * ix + lx] * E2[1][3 * iy + ly] * E2[2][3 * iz + lz];
              sum1 += t / kk;
              if (dip) {
                sum1F += t * kk;
                sum1T += t;
              }
            }
        const double sum2 = 4 * M_PI * A3[0][ix] * A3[1][iy] * A3[2][iz];
        const double sum3 = A1[0][ix] * A1[1][iy] * A1[2][iz];
        const double sum4 = A2[0][ix] * A1[1][iy] * A1[2][iz] + A1[0][ix] * A2[1][iy] * A1[2][iz] +
                            A1[0][ix] * A1[1][iy] * A2[2][iz];
        Q[0] += w * (sum1 - 2 * G * sum2 + G * G * sum3 * sum4);
        if (!dip) continue;
        const double e0[3] = {A3[0][ix], A3[1][iy], A3[2][iz]}, e2[3] = {X2[0][ix], X2[1][iy], X2[2][iz]},
                     e4[3] = {X4[0][ix], X4[1][iy], X4[2][iz]}, u0[3] = {A1[0][ix], A1[1][iy], A1[2][iz]},
                     u2[3] = {A2[0][ix], A2[1][iy], A2[2][iz]}, u4[3] = {A4[0][ix], A4[1][iy], A4[2][iz]};
        double ek2 = 0, ek4 = 0, uk4 = 0; /* sum_l exp U^2 k^2, exp U^2 k^4, U^2 k^4 */
        for (int c = 0; c < 3; c++) {
          const int d = (c + 1) % 3, f = (c + 2) % 3;
          ek2 += e2[c] * e0[d] * e0[f];
          ek4 += e4[c] * e0[d] * e0[f] + 2 * e2[c] * e2[d] * e0[f];
          uk4 += u4[c] * u0[d] * u0[f] + 2 * u2[c] * u2[d] * u0[f];
        }
        Q[1] += w * (sum1F - 2 * G * 4 * M_PI * ek4 + G * G * uk4 * sum4);
        Q[2] += w * (sum1T - 2 * G * 4 * M_PI * ek2 + G * G * sum4 * sum4);
      }
  for (int c = 0; c < 3; c++) free(A1[c]);
  return 0;
}

double ew_err_pme(const rl_ewald_info *in, const double L[3], const double *mod[3])
{
  double Q[3];
  if (pme_functionals(in, L, mod, 0, Q)) return NAN;
  const double V = L[0] * L[1] * L[2];
  return in->coulomb_constant * in->sum_q2 / V * sqrt(fmax(Q[0], 0.0) / in->nsites_charged);
}

/* Point dipoles, the mesh's self-interaction: a dipole alone on the mesh feels a force and a
 * torque that depend on where it sits in its mesh cell (the aliases l != l' of its own density
 * interfere), which the pair functional leaves out and which, unlike a charge's, is as large as
 * the pair error.  With the alias amplitudes W_l = (sin(pi m/K) / (pi (m + l K)/K))^p per axis
 * (the B-spline's transform with its phase), and, for the mesh vectors g_D = 2 pi D K / L (D != 0),
 *   M_D = sum_m G(m) sum_l W_{l+D} W_l k_{l+D} k_l^T,
 * the self energy (kc/2V) sum_m G |sum_l (mu.k_l) W_l exp(-i k_l.r)|^2 gives, averaged over the
 * position in the cell and over orientations (S = (M_D + M_D^T)/2, mean of (u.S u)^2 over unit u:
 * ((tr S)^2 + 2 tr S^2) / 15),
 *   <F^2> = (kc mu^2 / V)^2 sum_{D half} |g_D|^2 ((tr S)^2 + 2 tr S^2) / 30,
 *   <T^2> = (kc mu^2 / V)^2 2 sum_{D half} [tr(M^T M) / 3 - ((tr S)^2 + 2 tr S^2) / 15],
 * mu^2 = sum mu^2 / N; D over |D_c| <= 1, l over |l_c| <= 4.  -1 out of memory. */
#define EW_SELF_D 13 /* the half of {-1, 0, 1}^3 \ {0} */
static int pme_dipole_self(const rl_ewald_info *in, const double L[3], const double *mod[3], double *F2, double *T2)
{
  const double a2 = in->alpha * in->alpha;
  const int p = in->order;
  double *P[3]; /* per axis, index and D_c + 1: sum W W, sum W W k_{l+D}, sum W W k_l, sum W W k_{l+D} k_l; then k^2 */
  if (alloc_axes(P, in->grid, 13)) return -1;
  for (int c = 0; c < 3; c++) {
    const int K = in->grid[c];
    for (int i = 0; i < K; i++) {
      const int m = i < (K + 1) / 2 ? i : i - K;
      const double sm = sin(M_PI * m / K);
      double W[2 * EW_ALIAS + 3], k[2 * EW_ALIAS + 3]; /* l = -EW_ALIAS - 1 .. EW_ALIAS + 1 */
      for (int l = -EW_ALIAS - 1; l <= EW_ALIAS + 1; l++) {
        const double ml = m + (double)l * K, x = M_PI * ml / K;
        W[l + EW_ALIAS + 1] = ml == 0 ? 1.0 : pow(sm / x, p);
        k[l + EW_ALIAS + 1] = 2 * M_PI * ml / L[c];
      }
      double *q = P[c] + 13 * (size_t)i;
      for (int D = -1; D <= 1; D++) {
        double s0 = 0, sa = 0, sb = 0, sab = 0;
        for (int l = -EW_ALIAS; l <= EW_ALIAS; l++) {
          const int a = l + D + EW_ALIAS + 1, b = l + EW_ALIAS + 1;
          const double w = W[a] * W[b];
          s0 += w;
          sa += w * k[a];
          sb += w * k[b];
          sab += w * k[a] * k[b];
        }
        q[4 * (D + 1) + 0] = s0;
        q[4 * (D + 1) + 1] = sa;
        q[4 * (D + 1) + 2] = sb;
        q[4 * (D + 1) + 3] = sab;
      }
      q[12] = k[EW_ALIAS + 1] * k[EW_ALIAS + 1];
    }
  }
  int Ds[EW_SELF_D][3], nD = 0;
  for (int x = -1; x <= 1; x++)
    for (int y = -1; y <= 1; y++)
      for (int z = -1; z <= 1; z++)
        if (x > 0 || (x == 0 && (y > 0 || (y == 0 && z > 0)))) {
          Ds[nD][0] = x;
          Ds[nD][1] = y;
          Ds[nD][2] = z;
          nD++;
        }
  double M[EW_SELF_D][9] = {{0}};
  for (int ix = 0; ix < in->grid[0]; ix++)
    for (int iy = 0; iy < in->grid[1]; iy++)
      for (int iz = 0; iz < in->grid[2]; iz++) {
        if (!ix && !iy && !iz) continue;
        const double *q[3] = {P[0] + 13 * (size_t)ix, P[1] + 13 * (size_t)iy, P[2] + 13 * (size_t)iz};
        const double k2 = q[0][12] + q[1][12] + q[2][12];
        if (k2 > EW_SKIP * a2) continue;
        const double G = 4 * M_PI * exp(-k2 / (4 * a2)) / k2 / (mod[0][ix] * mod[1][iy] * mod[2][iz]);
        for (int d = 0; d < nD; d++) {
          const double *f[3] = {q[0] + 4 * (Ds[d][0] + 1), q[1] + 4 * (Ds[d][1] + 1), q[2] + 4 * (Ds[d][2] + 1)};
          for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) {
              double v = G;
              for (int e = 0; e < 3; e++) v *= f[e][(e == a) + 2 * (e == b)];
              M[d][3 * a + b] += v;
            }
        }
      }
  for (int c = 0; c < 3; c++) free(P[c]);
  double f2 = 0.0, t2 = 0.0;
  for (int d = 0; d < nD; d++) {
    double S[9], tr = 0, trS2 = 0, trMM = 0, g2 = 0;
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) S[3 * a + b] = 0.5 * (M[d][3 * a + b] + M[d][3 * b + a]);
    for (int a = 0; a < 3; a++) {
      tr += S[4 * a];
      const double g = 2 * M_PI * Ds[d][a] * in->grid[a] / L[a];
      g2 += g * g;
      for (int b = 0; b < 3; b++) {
        trS2 += S[3 * a + b] * S[3 * b + a];
        trMM += M[d][3 * a + b] * M[d][3 * a + b];
      }
    }
    const double u4 = (tr * tr + 2 * trS2) / 15.0;
    f2 += g2 * u4 / 2.0;
    t2 += 2.0 * (trMM / 3.0 - u4);
  }
  const double c = in->coulomb_constant * in->sum_mu2 / in->nsites_dipolar / (L[0] * L[1] * L[2]);
  *F2 = c * c * f2;
  *T2 = c * c * fmax(t2, 0.0);
  return 0;
}

/* Point dipoles, the mesh: dF and dT from Q_F and Q_T (ewald.h) and the self-interaction, in
 * quadrature; -1 out of memory. */
static int ew_dip_err_pme(const rl_ewald_info *in, const double L[3], const double *mod[3], double *dF, double *dT)
{
  double Q[3], F2, T2;
  if (pme_functionals(in, L, mod, 1, Q) || pme_dipole_self(in, L, mod, &F2, &T2)) return -1;
  const double c = in->coulomb_constant * in->sum_mu2 / (L[0] * L[1] * L[2]), n9 = 9.0 * in->nsites_dipolar;
  *dF = sqrt(c * c * fmax(Q[1], 0.0) / n9 + F2);
  *dT = sqrt(c * c * 2.0 * fmax(Q[2], 0.0) / n9 + T2);
  return 0;
}

/* The dipolar estimates of the mesh in->grid (ewald.h); -1 out of memory. */
static int dip_pme_at(const rl_ewald_info *in, const double L[3], double *dF, double *dT)
{
  double *mod[3];
  if (alloc_axes(mod, in->grid, 1)) return -1;
  for (int c = 0; c < 3; c++) ew_bspline_moduli(in->order, in->grid[c], mod[c]);
  const int st = ew_dip_err_pme(in, L, (const double **)mod, dF, dT);
  for (int c = 0; c < 3; c++) free(mod[c]);
  return st;
}

/* Point dipoles: alpha where the real-space force estimate falls to in->dip_target (bisection
 * in alpha rc between 1.269, the smallest accepted, and 40). */
static double dip_alpha(const rl_ewald_info *in)
{
  const double rc = in->cutoff;
  double lo = sqrt(-log(0.2)), hi = 40.0, dF, dT;
  ew_dip_err_real(in, lo / rc, &dF, &dT);
  if (dF <= in->dip_target) return lo / rc;
  for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; it++) {
    const double mid = 0.5 * (lo + hi);
    ew_dip_err_real(in, mid / rc, &dF, &dT);
    if (dF > in->dip_target) lo = mid;
    else hi = mid;
  }
  return hi / rc;
}

/* The smallest n' >= n whose prime factors are 2, 3, 5 and 7 (FFTW is fast on these; a prime
 * such as 137 costs it 3.5 times 135). */
static int ew_fft_size(int n)
{
  for (int m = n > 1 ? n : 1;; m++) {
    int r = m;
    for (int f = 2; f <= 7; f++)
      while (r % f == 0) r /= f;
    if (r == 1) return m;
  }
}

/* The mesh of in->order with n FFT-friendly points along the longest edge, the others in
 * proportion (ceil, then FFT-friendly), at least lo per axis. */
static void dip_mesh(int grid[3], const double L[3], int n, int lo)
{
  const double Lmax = fmax(L[0], fmax(L[1], L[2]));
  for (int c = 0; c < 3; c++) {
    const int g = (int)ceil(n * L[c] / Lmax - 1e-9);
    grid[c] = ew_fft_size(g > lo ? g : lo);
  }
}

/* The dipolar reciprocal force estimate of a mesh of spacing h = Lmax / n at in->alpha and
 * in->order, evaluated cheaply on a cube of EW_PROXY^3 points (the same spacing, density and
 * mean mu^2): away from the smallest boxes the estimate depends on alpha, h, p, the density and
 * mu^2 only (a sum over mesh vectors that is an integral times V).  -1 out of memory. */
#define EW_PROXY 24
static int dip_recip_proxy(const rl_ewald_info *in, const double L[3], int n, double *dF)
{
  const double h = fmax(L[0], fmax(L[1], L[2])) / n, Lp[3] = {EW_PROXY * h, EW_PROXY * h, EW_PROXY * h};
  rl_ewald_info t = *in;
  const double np = in->nsites_dipolar * Lp[0] * Lp[1] * Lp[2] / in->volume;
  t.nsites_dipolar = np > 1.0 ? (int)lround(np) : 1;
  t.sum_mu2 = in->sum_mu2 / in->nsites_dipolar * t.nsites_dipolar;
  t.volume = Lp[0] * Lp[1] * Lp[2];
  t.grid[0] = t.grid[1] = t.grid[2] = EW_PROXY;
  double dT;
  return dip_pme_at(&t, Lp, dF, &dT);
}

/* Point dipoles alone, PME, the mesh from the tolerance (and the order too when not given), at
 * the alpha the tolerance gives (dip_alpha: the real-space estimate at in->dip_target; alpha is not
 * traded against the mesh, because a term "ewald-real" resolved on its own must find the same
 * alpha): the order and FFT-friendly mesh of least cost whose reciprocal force estimate is at most
 * in->dip_target.  For each order (p given, else 4..8) the fewest mesh points n along the longest
 * edge whose estimate on the proxy cube is within the target (doubled, then bisected over the
 * FFT-friendly sizes), and of these the cheapest by
 *   cost = M log2 M + EW_COST_POINT N p^3   (M mesh points, N dipoles)
 * (the two FFTs, and the spreading and gathering over p^3 points per dipole).  EW_COST_POINT = 2
 * from timings of the "pme" term of 16,000 Stockmayer dipoles (ewald_point --repeat 3, one
 * thread, a loaded 2-core host): 135^3 p5 0.170 s, 100^3 p6 0.081 s, 81^3 p7 0.061 s, 80^3 p8
 * 0.076 s, 64^3 p8 0.062 s, i.e. about 2.8 ns per M log2 M and 6 ns per N p^3.  The choice is then
 * checked on the true box: n raised while the true estimate exceeds the target, lowered while the
 * next-coarser FFT-friendly mesh still meets it.  -1 out of memory. */
#define EW_COST_POINT 2.0
static int dip_pme_choose(rl_ewald_info *in, const rl_ewald_params *p, const double L[3])
{
  const int p0 = p->order ? p->order : 4, p1 = p->order ? p->order : 8;
  const double target = in->dip_target;
  double best = INFINITY, dF, dT;
  int bn = 0, bp = 0;
  for (int order = p0; order <= p1; order++) {
    const int lo = order > 6 ? order : 6;
    in->order = order;
    int nlo = lo, nhi = lo; /* nlo: too coarse (or the floor), nhi: fine enough */
    for (;;) {
      if (dip_recip_proxy(in, L, nhi, &dF)) return -1;
      if (dF <= target || pow(nhi, 3) > EW_MAX_GRID_POINTS) break;
      nlo = nhi;
      nhi = ew_fft_size(2 * nhi);
    }
    if (dF > target) continue;
    for (;;) {
      const int mid = ew_fft_size((nlo + nhi) / 2 + 1);
      if (mid >= nhi) break;
      if (dip_recip_proxy(in, L, mid, &dF)) return -1;
      if (dF <= target) nhi = mid;
      else nlo = mid;
    }
    int g[3];
    dip_mesh(g, L, nhi, lo);
    const double M = (double)g[0] * g[1] * g[2], cost = M * log2(M) + EW_COST_POINT * in->nsites_dipolar * pow(order, 3);
    if (cost < best) {
      best = cost;
      bn = nhi;
      bp = order;
    }
  }
  if (!bp) bp = p0, bn = 1 << 10; /* none fits: the size check refuses it */
  in->order = bp;
  const int lo = bp > 6 ? bp : 6;
  dip_mesh(in->grid, L, bn, lo); /* on the true box: up while too coarse, down while the next coarser fits */
  if (dip_pme_at(in, L, &dF, &dT)) return -1;
  while (dF > target && (double)in->grid[0] * in->grid[1] * in->grid[2] <= EW_MAX_GRID_POINTS) {
    bn = ew_fft_size(bn + 1);
    dip_mesh(in->grid, L, bn, lo);
    if (dip_pme_at(in, L, &dF, &dT)) return -1;
  }
  while (bn > lo) {
    int down = bn - 1;
    while (down > lo && ew_fft_size(down) != down) down--;
    int g[3];
    memcpy(g, in->grid, sizeof g);
    dip_mesh(in->grid, L, down, lo);
    if (dip_pme_at(in, L, &dF, &dT)) return -1;
    if (dF > target) {
      memcpy(in->grid, g, sizeof g);
      break;
    }
    bn = down;
  }
  return 0;
}

/* The mesh (pme) or k cutoff (ewald) for point dipoles: the axes not given in p get
 * max(base[c], ceil(n L_c / L_max)) for the smallest n whose reciprocal force estimate is at most
 * in->dip_target (k cutoff: n counted up; mesh: doubled, then bisected), or the first beyond the
 * size limit (which the caller then refuses).  -1 out of memory. */
static int dip_kspace(rl_ewald_info *in, const rl_ewald_params *p, rl_ewald_method method, const double L[3], const int base[3])
{
  int *out = method == RL_EWALD_PME ? in->grid : in->kmax;
  const int *given = method == RL_EWALD_PME ? p->grid : p->kmax;
  const double Lmax = fmax(L[0], fmax(L[1], L[2]));
  double dF, dT;
#define DIP_SET(n) \
  for (int c = 0; c < 3; c++) { \
    const double g = ceil((double)(n) * L[c] / Lmax); \
    out[c] = given[c] ? given[c] : g > base[c] ? (int)g : base[c]; \
  }
#define DIP_SIZE() (method == RL_EWALD_PME ? (double)out[0] * out[1] * out[2] \
                                           : (2.0 * out[0] + 1) * (2.0 * out[1] + 1) * (2.0 * out[2] + 1) / 2)
#define DIP_ERR(res) \
  do { \
    if (method == RL_EWALD_PME) { \
      if (dip_pme_at(in, L, &dF, &dT)) return -1; \
    } else { \
      ew_dip_err_ewald(in, L, &dF, &dT); \
    } \
    res = dF <= in->dip_target; \
  } while (0)
  const double limit = method == RL_EWALD_PME ? (double)EW_MAX_GRID_POINTS : (double)EW_MAX_KVECTORS;
  int good;
  DIP_SET(0);
  DIP_ERR(good);
  if (good) return 0;
  if (method == RL_EWALD_SUM) {
    const double nmax = p->kmax_sq > 0 ? ceil(sqrt(p->kmax_sq)) + 1 : 1e9; /* a sphere given: kmax beyond it changes nothing */
    for (int n = 1; n <= nmax; n++) {
      DIP_SET(n);
      if (DIP_SIZE() > limit) return 0;
      DIP_ERR(good);
      if (good) return 0;
    }
    return 0;
  }
  int lo = 1, hi = 8;
  for (;; lo = hi, hi *= 2) {
    DIP_SET(hi);
    if (DIP_SIZE() > limit) return 0;
    DIP_ERR(good);
    if (good) break;
  }
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    DIP_SET(mid);
    DIP_ERR(good);
    if (good) hi = mid;
    else lo = mid;
  }
  DIP_SET(hi);
  return 0;
#undef DIP_SET
#undef DIP_SIZE
#undef DIP_ERR
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
  in->dip_target = tol * in->coulomb_constant * (rl_system_units(sys) == RL_UNITS_LJ ? 1.0 : 100.0); /* 1 A = 0.1 nm */
  if (nd > 0 && !keep && p->alpha == 0.0) { /* point dipoles: their own alpha; with charges the larger */
    const double ad = dip_alpha(in);
    in->alpha = nq > 0 ? fmax(in->alpha, ad) : ad;
  }
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
    if (nd > 0 && !keep && in->kmax_derived) {
      const int base[3] = {nq > 0 ? in->kmax[0] : 1, nq > 0 ? in->kmax[1] : 1, nq > 0 ? in->kmax[2] : 1};
      dip_kspace(in, p, RL_EWALD_SUM, L, base);
    }
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
    if (nd > 0 && nq == 0 && !keep && p->alpha == 0.0 && !p->grid[0] && !p->grid[1] && !p->grid[2]) {
      if (dip_pme_choose(in, p, L)) return rl_error(RL_ENOMEM, "pme: out of memory");
      in->grid_derived = p->order ? 1 : 2; /* 2: the order too */
      total = (double)in->grid[0] * in->grid[1] * in->grid[2];
    } else if (nd > 0 && !keep && in->grid_derived) {
      const int lo = in->order > 6 ? in->order : 6;
      const int base[3] = {nq > 0 ? in->grid[0] : lo, nq > 0 ? in->grid[1] : lo, nq > 0 ? in->grid[2] : lo};
      if (dip_kspace(in, p, RL_EWALD_PME, L, base)) return rl_error(RL_ENOMEM, "pme: out of memory");
      total = (double)in->grid[0] * in->grid[1] * in->grid[2];
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
    double *mod[3];
    if (alloc_axes(mod, in->grid, 1)) return rl_error(RL_ENOMEM, "pme: out of memory");
    for (int c = 0; c < 3; c++) ew_bspline_moduli(in->order, in->grid[c], mod[c]);
    in->err_recip = ew_err_pme(in, L, (const double **)mod);
    for (int c = 0; c < 3; c++) free(mod[c]);
  }
  if (method != RL_EWALD_REAL) in->err_total = sqrt(in->err_real * in->err_real + in->err_recip * in->err_recip);
  in->dip_err_real = in->dip_err_recip = in->dip_err_total = NAN;
  in->dip_terr_real = in->dip_terr_recip = in->dip_terr_total = NAN;
  if (nd > 0) {
    ew_dip_err_real(in, in->alpha, &in->dip_err_real, &in->dip_terr_real);
    in->dip_err_total = in->dip_err_real;
    in->dip_terr_total = in->dip_terr_real;
    if (method == RL_EWALD_SUM) ew_dip_err_ewald(in, L, &in->dip_err_recip, &in->dip_terr_recip);
    else if (method == RL_EWALD_PME && dip_pme_at(in, L, &in->dip_err_recip, &in->dip_terr_recip))
      return rl_error(RL_ENOMEM, "pme: out of memory");
    if (method != RL_EWALD_REAL) {
      in->dip_err_total = hypot(in->dip_err_real, in->dip_err_recip);
      in->dip_terr_total = hypot(in->dip_terr_real, in->dip_terr_recip);
    }
  }
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
    snprintf(k, sizeof k, ", grid %d x %d x %d (%s), order %d%s", in->grid[0], in->grid[1], in->grid[2],
             in->grid_derived ? "from the tolerance" : "given", in->order, in->grid_derived == 2 ? " (from the tolerance)" : "");
  }
  if (isinf(in->eps_surface)) snprintf(b, sizeof b, "tin-foil boundary");
  else snprintf(b, sizeof b, "dielectric boundary eps' = %.6g", in->eps_surface);
  const char *name = in->method == RL_EWALD_PME ? "smooth PME" : in->method == RL_EWALD_SUM ? "Ewald" : "Ewald real space";
  if (in->nsites_dipolar > 0) { /* the dipoles' estimates, and the charges' if there are any */
    const double *d = in->method == RL_EWALD_REAL ? &in->dip_err_real : &in->dip_err_total,
                 *t = in->method == RL_EWALD_REAL ? &in->dip_terr_real : &in->dip_terr_total;
    char dp[64] = "", parts[160] = "";
    if (in->nsites_charged > 0) snprintf(dp, sizeof dp, "; RMS force error on a charge %.3g %s", in->method == RL_EWALD_REAL ? in->err_real : in->err_total, force);
    if (in->method != RL_EWALD_REAL)
      snprintf(parts, sizeof parts, " (real space %.3g, reciprocal %.3g; torque %.3g, %.3g)", in->dip_err_real,
               in->dip_err_recip, in->dip_terr_real, in->dip_terr_recip);
    return snprintf(buf, size, "%s of %s: %s%s%s%s; estimated RMS error on a dipole: force %.3g %s, torque %.3g %s%s "
                    "(the target %.3g %s: tolerance x the force between unit charges 1 %s apart)%s", name,
                    in->nsites_charged > 0 ? "charges and point dipoles" : "point dipoles", a, k,
                    in->method == RL_EWALD_REAL ? "" : ", ", in->method == RL_EWALD_REAL ? "" : b, *d, force, *t,
                    lj ? "epsilon" : "kJ/mol", parts, in->dip_target, force, lj ? "sigma" : "A", dp);
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
