/* rotleap — observables: averages with error bars, fluctuation formulas, radial distribution
 * functions, time correlation functions, diffusion and the static dielectric constant.
 *
 * The module computes; it never prints and never exits.  Accumulators are caller-owned objects
 * (`_alloc` / `_free`, free accepts NULL); kernels take plain arrays plus counts and never see the
 * integrator.  Functions that can fail return RL_OK or an error code with rl_last_error() set.
 * Definitions, formulas, units and references: docs/observables.md.
 *
 * Units are those of the caller's data (for an rl_system: its unit system, system.h / units.h). */
#ifndef ROTLEAP_OBSERVABLES_H
#define ROTLEAP_OBSERVABLES_H

#include <stddef.h>
#include <stdint.h>

#include "rotleap/forcefield.h"
#include "rotleap/system.h"
#include "rotleap/units.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ====================================================================== scalar series
 * An on-line accumulator for one scalar time series (U per molecule, T, P, E, ...): mean,
 * population standard deviation sd = <(x - <x>)^2>^(1/2) (the paper's convention, 1/n), and
 * Flyvbjerg-Petersen blocking (J. Chem. Phys. 91, 461 (1989)) done on the fly in O(log n)
 * memory: level k holds the series averaged over blocks of 2^k consecutive samples (a trailing
 * odd sample of a level waits for its partner and is not counted).  The series itself is not
 * stored.  All moments use Welford updates (no cancellation for E ~ 1e4 with sd ~ 1e-2). */

#define RL_BLOCK_MAX_LEVELS 48

typedef struct rl_series rl_series;

typedef struct {
  int level;          /* blocking level k (block length 2^k samples)                       */
  long nblocks;       /* blocks at this level                                               */
  double sem;         /* standard error of the mean estimated at this level:
                         sqrt(var_k / (nblocks - 1)), var_k the 1/n variance of block means  */
  double sem_err;     /* its own uncertainty, sem / sqrt(2 (nblocks - 1))                   */
} rl_block_level;

typedef struct {
  long n;             /* samples                                                            */
  double mean;        /* sample mean                                                        */
  double sd;          /* population standard deviation (1/n)                                */
  double sem;         /* block-averaged standard error of the mean at the chosen level      */
  double sem_err;     /* uncertainty of `sem`                                               */
  double sem_naive;   /* sd / sqrt(n - 1): the error bar if samples were independent        */
  double tau;         /* integrated autocorrelation time in samples, from
                         sem^2 = 2 tau sd^2 / n: tau = (sem / sem_naive)^2 / 2
                         (1/2 for independent samples)                                       */
  int level;          /* chosen blocking level (block length 2^level samples)               */
  int converged;      /* 1 if the Lee-Needs-Towler criterion was met at some level with at
                         least 4 blocks; 0: the series is too short for its correlation time
                         and `sem` is the largest-level value (a lower bound)                */
} rl_block_result;

/* Returns NULL (rl_last_error set) on allocation failure. */
rl_series *rl_series_alloc(void);
void rl_series_free(rl_series *s); /* accepts NULL */
void rl_series_reset(rl_series *s);
/* in x: a finite sample.  RL_ENONFINITE for NaN/Inf (the sample is not added). */
int rl_series_add(rl_series *s, double x);
long rl_series_count(const rl_series *s);
double rl_series_mean(const rl_series *s);  /* NaN if empty */
double rl_series_sd(const rl_series *s);    /* population sd (1/n); NaN if empty */
/* The paper's relative fluctuation sd / |mean| (calE for E, calU for U) of the samples so far.
 * Called after every rl_series_add it is the *running* calE as a function of run length. NaN if
 * empty or mean = 0. */
double rl_series_rel_fluct(const rl_series *s);
/* Number of blocking levels with at least 2 blocks, and the table of them.
 * out levels[nmax]: filled up to min(nmax, that number). */
int rl_series_block_levels(const rl_series *s, rl_block_level *levels, int nmax);
/* Mean and block-averaged error.  The level is the smallest k satisfying the criterion of
 * Lee, Needs & Towler, Phys. Rev. E 83, 066706 (2011) (as in pyblock):
 *     (2^k)^3 > 2 n (sem_k / sem_0)^4,
 * i.e. block length B beyond ~ (2 n tau^2)^(1/3).  RL_EINVAL if n < 4. */
int rl_series_block_average(const rl_series *s, rl_block_result *r);

/* Fixed number of blocks on a stored series: x[n] split into `nblocks` equal blocks of
 * floor(n / nblocks) samples (the remainder at the end is dropped); sem = sd of block means /
 * sqrt(nblocks - 1).  in x[n], n, nblocks >= 2 with n / nblocks >= 1.  out mean, sem. */
int rl_block_fixed(const double *x, size_t n, int nblocks, double *mean, double *sem);

/* Running relative fluctuation of a stored series: out[k] = sd(x[0..k]) / |mean(x[0..k])|
 * (the paper's calE as a function of run length, Fig. 1).  in x[n]; out out[n] (may alias x). */
int rl_running_rel_fluct(const double *x, size_t n, double *out);

/* ====================================================================== stored series
 * rl_trace keeps a scalar series in bounded memory, so that averages can start anywhere (after
 * an equilibration detected at the end of a run): consecutive blocks of B samples, each with its
 * count, mean and sum of squared deviations.  B = 1 (every sample kept) until `cap` blocks are
 * stored; then neighbouring blocks merge pairwise and B doubles, so at most cap blocks are kept
 * and a start is resolved to B samples (B < 2 n / cap).  The samples after the last full block
 * wait in a partial block, counted in the moments but not in the blocking.  Deterministic: the
 * same samples give the same bits. */

/* Count, mean and m2 = sum (x - mean)^2 of a set of samples (n = 0: empty). */
typedef struct {
  long n;
  double mean, m2;
} rl_moments;

/* The moments of the union of two sets (Chan, Golub & LeVeque's pairwise update). */
rl_moments rl_moments_merge(rl_moments a, rl_moments b);
/* Leave-one-out moments: out[i] = the union of every group but i (merged from both sides, no
 * subtraction).  in g[m], m >= 2; out out[m]. */
int rl_moments_leave_one_out(const rl_moments *g, long m, rl_moments *out);
/* Jackknife standard error of an estimator from its m leave-one-out values theta[m]:
 * sqrt((m - 1)/m sum (theta_i - mean)^2).  NaN if m < 2 or a value is not finite. */
double rl_jackknife_error(const double *theta, long m);

#define RL_TRACE_CAP 65536 /* blocks kept by default: 1 MB */

typedef struct rl_trace rl_trace;

/* in cap: blocks kept, a power of two >= 4 (0: RL_TRACE_CAP).  NULL with a message on bad
 * input or no memory. */
rl_trace *rl_trace_alloc(long cap);
void rl_trace_free(rl_trace *t); /* accepts NULL */
/* in x finite (RL_ENONFINITE otherwise, not added); RL_ENOMEM if the store cannot grow. */
int rl_trace_add(rl_trace *t, double x);
long rl_trace_count(const rl_trace *t);
long rl_trace_block(const rl_trace *t); /* B, samples per stored block */
/* The first sample index >= i where the stored data can start: i rounded up to a multiple of B
 * (the count if that is beyond the last full block). */
long rl_trace_align(const rl_trace *t, long i);
/* Moments of the samples from rl_trace_align(t, from) to the end (partial block included). */
rl_moments rl_trace_moments(const rl_trace *t, long from);
/* Moments of consecutive groups of `len` samples from rl_trace_align(t, from) (len rounded up
 * to a multiple of B; a trailing incomplete group is left out, as in blocking).  out out[nmax]
 * (may be NULL).  Returns the number of complete groups. */
long rl_trace_groups(const rl_trace *t, long from, long len, rl_moments *out, long nmax);
/* rl_series_block_average of the samples from rl_trace_align(t, from): Flyvbjerg-Petersen
 * levels from log2 B up (the Lee-Needs-Towler level chosen among them; sem_naive from the exact
 * moments).  With B = 1 it is the rl_series result for the same samples (to rounding: block
 * means are merged pairwise).  RL_EINVAL if fewer
 * than 4 samples. */
int rl_trace_block_average(const rl_trace *t, long from, rl_block_result *r);

/* ====================================================================== equilibration
 * Statistical inefficiency g = 1 + 2 sum_{t=1}^{n-2} (1 - t/n) C(t) of x[n], with the normalised
 * autocorrelation C(t) = sum_{i<n-t} dx_i dx_{i+t} / ((n - t) sigma^2), dx = x - mean, sigma^2
 * the 1/n variance, summed until C(t) <= 0 at some t > 3; g < 1 is set to 1.  This is
 * pymbar's timeseries.statisticalInefficiency (fast = False, mintime = 3).  n/g is the number of
 * uncorrelated samples.  RL_EINVAL if n < 2 or the variance is 0. */
int rl_statistical_inefficiency(const double *x, long n, double *g);
/* Automated equilibration detection (J. D. Chodera, J. Chem. Theory Comput. 12, 1799 (2016);
 * pymbar's timeseries.detectEquilibration): the start t0 that maximises the number of
 * uncorrelated samples N_eff(t0) = (n - t0) / g(x[t0..n)), trying t0 = 0, stride, 2 stride, ...
 * up to t0_max (t0_max < 0: n - 2, every start as pymbar); a constant tail counts as N_eff = 1,
 * and the first maximum wins.  (pymbar counts n - t0 + 1 samples; here n - t0, the samples
 * actually left.)  in x[n], n >= 2, stride >= 1; out t0, g = g at t0, neff = N_eff(t0) (any may
 * be NULL).  Cost O(n^2 / stride) times the correlation length: give it at most a few thousand
 * points (rl_trace_equilibration does). */
int rl_detect_equilibration(const double *x, long n, long stride, long t0_max, long *t0, double *g,
                            double *neff);
/* rl_detect_equilibration on the means of consecutive groups of B k samples of a trace, k the
 * smallest giving at most `points` groups (points >= 8), with starts up to the fraction
 * max_start of the groups (1: every start; rotleap run uses 1/2, docs/observables.md): the start,
 * in samples, is a multiple of the group length; g and N_eff are in groups (N_eff counts
 * uncorrelated samples of the raw series as well, while the groups are shorter than its
 * correlation time).  out t0 (samples), len (samples per group), g, neff, at_limit (1 if t0 lies
 * in the last tenth of the starts tried: the relaxation may be longer) (any may be NULL). */
int rl_trace_equilibration(const rl_trace *t, long points, double max_start, long *t0, long *len, double *g,
                           double *neff, int *at_limit);

/* ====================================================================== heat capacity
 * All return C_V of the whole system (extensive) in energy/temperature (real: kJ mol^-1 K^-1;
 * lj: k_B); divide by N for per molecule.  kB = rl_units_kB(units).
 *
 * NVT (canonical, e.g. Bussi stochastic rescaling): C_V = <dE^2> / (kB T^2), E = K + U.
 *   in var_E (population variance of the total energy), T (thermostat temperature).          */
int rl_heat_capacity_nvt(double var_E, double T, double kB, double *cv);
/* Isokinetic NVT (the paper's eqs. 17-18: K fixed, configurations canonical): the kinetic part
 * is the ideal dof kB / 2 and the configurational part comes from the potential energy,
 * C_V = dof kB / 2 + <dU^2> / (kB T^2).   in var_U, T, dof (kinetic degrees of freedom).
 * The same formula holds for canonical sampling (K and U independent, <dK^2> = dof (kB T)^2 / 2):
 * it is rl_heat_capacity_nvt with the kinetic part known instead of sampled, and `rotleap run`
 * uses it, with T the thermostat's target, for every NVT run (docs/observables.md).            */
int rl_heat_capacity_isokinetic(double var_U, double T, int dof, double kB, double *cv);
/* NVE, Lebowitz-Percus-Verlet (Phys. Rev. 153, 250 (1967)) from kinetic-energy fluctuations:
 *   <dK^2> = (2 <K>^2 / f) (1 - f kB / (2 C_V))   =>   C_V = (f kB / 2) / (1 - f <dK^2> / (2 <K>^2))
 * with f = dof the kinetic degrees of freedom (rl_system_dof), T = 2<K>/(f kB).
 * in mean_K, var_K, dof.  RL_EINVAL if f <dK^2> / (2 <K>^2) >= 1 (fluctuations at or above the
 * canonical value: the run is not microcanonical or too short). */
int rl_heat_capacity_nve(double mean_K, double var_K, int dof, double kB, double *cv);

/* ====================================================================== radial distribution
 * g_ab(r) between two sets of points a[na], b[nb] in a periodic orthorhombic box L, minimum
 * image, histogram of nbins bins of width dr = r_max / nbins on [0, r_max], r_max <= min(L)/2.
 * Optional molecule labels exclude pairs within one molecule (and self pairs when a and b are
 * the same set: pass the same labels).  Normalisation by ideal-gas shell counts:
 *   g(r_k) = H_k / (F * P / V * (4 pi / 3) ((k+1)^3 - k^3) dr^3)
 * with H_k the ordered (a, b) pair count in bin k summed over F frames and P the number of
 * ordered pairs allowed (na nb minus excluded), V = Lx Ly Lz (averaged over frames). */

typedef struct rl_rdf rl_rdf;

/* in r_max > 0, nbins >= 1.  NULL with a message on bad input or no memory. */
rl_rdf *rl_rdf_alloc(double r_max, int nbins);
void rl_rdf_free(rl_rdf *g); /* accepts NULL */
void rl_rdf_reset(rl_rdf *g);
/* Add one frame.
 * in L[3] box edges (r_max <= min(L)/2 else RL_EINVAL); a[na][3], b[nb][3] positions (any image);
 *    mol_a[na], mol_b[nb]: molecule labels (a pair with mol_a[i] == mol_b[j] is excluded), or both
 *    NULL for no exclusion (then a pair at distance 0 counts in bin 0: pass labels for a = b). */
int rl_rdf_add(rl_rdf *g, const double L[3], const double (*a)[3], int na, const int *mol_a,
               const double (*b)[3], int nb, const int *mol_b);
/* Add one frame for the site pair (species_a, site_a) - (species_b, site_b) of a system (site
 * indices within species; e.g. water O-O is (0, 0, 0, 0), H-H (0, 1, 0, 1) and (0, 1, 0, 2)
 * together -- call once per pair or use rl_rdf_add with a merged set).  Intramolecular pairs
 * are excluded. */
int rl_rdf_add_sites(rl_rdf *g, const rl_system *sys, int species_a, int site_a,
                     int species_b, int site_b);
/* One frame's contribution, counted without adding it, and added from its counts: for a
 * journal that replays frames (rl_rdf_add = count, then add the counts; the same bits).
 * out hist[nbins]: ordered pair counts per bin (RL_EINVAL if one exceeds UINT32_MAX), *pairs the
 * frame's allowed ordered pairs P, *na its a points.  in L[3] as in rl_rdf_add. */
int rl_rdf_count_sites(const rl_rdf *g, const rl_system *sys, int species_a, int site_a,
                       int species_b, int site_b, uint32_t *hist, double *pairs, int *na);
int rl_rdf_add_counts(rl_rdf *g, const double L[3], const uint32_t *hist, double pairs, int na);
int rl_rdf_nbins(const rl_rdf *g);
double rl_rdf_rmax(const rl_rdf *g);
long rl_rdf_frames(const rl_rdf *g);
/* out r[nbins] bin centres (may be NULL), gr[nbins] g(r).  RL_ESTATE if no frame was added. */
int rl_rdf_get(const rl_rdf *g, double *r, double *gr);
/* g(r) of the frames from `first` on (the equilibrated part of a run).  The accumulator keeps
 * its totals at RL_RDF_MARKS evenly spaced frames (0, S, 2S, ...; S = 1 until that many
 * frames, then S doubles), so the frames used start at the first mark >= first: S - 1 frames
 * later at most (S < 2 frames / RL_RDF_MARKS).  out r, gr as rl_rdf_get, *used (may be NULL)
 * the first frame used.  RL_ESTATE if no frame is left. */
#define RL_RDF_MARKS 256
int rl_rdf_get_from(const rl_rdf *g, long first, double *r, double *gr, long *used);
/* Mean number of b points around an a point with r_lo <= r < r_hi (bins whose centres lie in
 * the range): sum of H_k / (F na).  For the first shell integrate up to the first minimum. */
double rl_rdf_coordination(const rl_rdf *g, double r_lo, double r_hi);
/* Integrated absolute difference D = int_0^rmax |g1(r) - g2(r)| dr (length units; divide by
 * r_max for a dimensionless mean difference).  The two must have the same r_max and nbins. */
int rl_rdf_distance(const rl_rdf *g1, const rl_rdf *g2, double *d);
/* The same on plain arrays g1[nbins], g2[nbins] of bin width dr. */
double rl_rdf_distance_arrays(const double *g1, const double *g2, int nbins, double dr);

/* ====================================================================== time correlations
 * Stored samples of one 3-vector per body (axis, velocity, angular velocity, unwrapped centre),
 * taken every `dt` of time; correlation functions averaged over bodies and over every time
 * origin (origin stride 1 by default) up to a maximum lag. */

typedef struct rl_vec_series rl_vec_series;

typedef enum {
  RL_TCF_DOT = 0, /* C(t) = <a(0) . a(t)> (unnormalised; VACF, angular-velocity ACF)         */
  RL_TCF_P1 = 1,  /* <P1(u(0) . u(t))>, u = a/|a| (dipole-axis ACF, first Legendre)          */
  RL_TCF_P2 = 2,  /* <P2(u(0) . u(t))>, P2(x) = (3x^2 - 1)/2                                 */
  RL_TCF_MSD = 3  /* <|a(t) - a(0)|^2> (a: unwrapped centres)                                 */
} rl_tcf_kind;

/* in n bodies per frame (>= 1).  NULL on bad input / no memory. */
rl_vec_series *rl_vec_series_alloc(int n);
void rl_vec_series_free(rl_vec_series *s); /* accepts NULL */
/* Append a frame: in x[n][3] (copied).  RL_ENONFINITE for NaN/Inf. */
int rl_vec_series_add(rl_vec_series *s, const double (*x)[3]);
int rl_vec_series_count(const rl_vec_series *s);  /* bodies */
long rl_vec_series_frames(const rl_vec_series *s);
/* Frame f (0-based) as [n][3], or NULL if out of range. */
const double (*rl_vec_series_frame(const rl_vec_series *s, long f))[3];
/* Correlation function over lags 0..max_lag (in frames).
 * in kind, max_lag (0 <= max_lag < frames), origin_stride >= 1 (time origins every stride frames).
 * out c[max_lag + 1].  For P1/P2 a zero vector is RL_EINVAL. */
int rl_tcf_compute(const rl_vec_series *s, rl_tcf_kind kind, long max_lag, long origin_stride,
                   double *c);
/* The same over the `count` frames from `first` (a part of a run: its equilibrated part, or one
 * of its blocks); max_lag < count. */
int rl_tcf_compute_range(const rl_vec_series *s, long first, long count, rl_tcf_kind kind,
                         long max_lag, long origin_stride, double *c);
/* The same over the bodies body0 .. body0 + nbodies - 1 only (a species of a mixture: its bodies
 * are consecutive); over all of them it is rl_tcf_compute_range, bit for bit. */
int rl_tcf_compute_bodies(const rl_vec_series *s, long first, long count, int body0, int nbodies,
                          rl_tcf_kind kind, long max_lag, long origin_stride, double *c);

/* Self-diffusion, Einstein: least-squares line msd(t) = a + 6 D t over lags lag_lo..lag_hi
 * (inclusive; t = lag dt).  `rotleap run` computes lags up to L = min(frames / 2, 1000) and fits
 * L/5..L: 20 % to 100 % of the lags computed, i.e. 10 % to 50 % of the stored samples while the
 * 1,000-lag bound does not apply (the ballistic start excluded; no lag beyond half the samples,
 * where fewer origins average it).  out D, D_err (standard error of
 * the slope / 6 from the fit residuals; it ignores the correlation between lags, so it is a
 * lower bound), either may be NULL.  in msd[nlag], 0 <= lag_lo < lag_hi < nlag. */
int rl_diffusion_einstein(const double *msd, long nlag, double dt, long lag_lo, long lag_hi,
                          double *D, double *D_err);
/* Self-diffusion, Green-Kubo: D = (1/3) int_0^{t_max} <v(0) . v(t)> dt (trapezoid over vacf[nlag],
 * t_max = (nlag - 1) dt).  vacf from RL_TCF_DOT on centre-of-mass velocities. */
int rl_diffusion_green_kubo(const double *vacf, long nlag, double dt, double *D);

/* Minimum-image unwrapping: out[i] = x[i] + L round((prev[i] - x[i]) / L) per component, the
 * image of x[i] nearest the previous unwrapped position (valid while a body moves less than L/2
 * between samples).  in L[3], prev[n][3] (previous unwrapped), x[n][3] (any image);
 * out out[n][3] (may alias x or prev: each component is read before it is written). */
void rl_unwrap(const double L[3], const double (*prev)[3], const double (*x)[3], int n,
               double (*out)[3]);

/* ---- per-body vectors of a system, to feed rl_vec_series ----
 * out [n][3] with n = rl_system_count(sys).  Velocities and angular momenta are whatever the
 * system holds (on-step values before rl_integrator_init / after rl_integrator_finish;
 * half-step values in between). */
void rl_system_positions(const rl_system *sys, double (*r)[3]);
void rl_system_velocities(const rl_system *sys, double (*v)[3]);
/* Body Z in the lab.  This is the dipole axis for point dipoles and linear molecules (and
 * symmetric tops with the dipole on the unique axis) but NOT for water: TIP4P's dipole lies
 * along its C2 axis, perpendicular to body Z.  For a dipole-axis ACF of any model feed the
 * molecular dipoles mu_i of rl_system_dipoles (P1/P2 normalise them). */
void rl_system_axes(const rl_system *sys, double (*u)[3]);
/* Lab angular velocity: matrix bodies omega = A^T J^-1 A l; axis bodies (dipole, linear) the
 * part of l / J_perp perpendicular to rho (J_perp = J_XX); point bodies 0. */
void rl_system_angular_velocities(const rl_system *sys, double (*w)[3]);

/* ====================================================================== dipoles, dielectric */

/* Molecular dipoles: mu_i = sum_a q_a (s_a - r_i) + sum_a p_a rho_i, with s_a the lab site
 * positions, r_i the centre of mass and p_a the point dipole along body Z (rl_species_ff).
 * Relative to the centre of mass: equal to sum q s for neutral molecules; a net molecular charge
 * contributes nothing (M of ionic systems is not defined this way).
 * in sys, species[nspecies] (nspecies = rl_system_nspecies, nsites must match).
 * out mu[n][3] (may be NULL), M[3] = sum_i mu_i (may be NULL).  Units: charge x length
 * (real: e nm; 1 D = RL_DEBYE_E_NM e nm; lj: reduced mu*). */
int rl_system_dipoles(const rl_system *sys, const rl_species_ff *species, int nspecies,
                      double (*mu)[3], double M[3]);

/* Total-dipole fluctuation accumulator: <M>, <M^2>, <dM^2> = <M.M> - <M>.<M> (Welford). */
typedef struct rl_dipole_acc rl_dipole_acc;
rl_dipole_acc *rl_dipole_acc_alloc(void);
void rl_dipole_acc_free(rl_dipole_acc *d); /* accepts NULL */
int rl_dipole_acc_add(rl_dipole_acc *d, const double M[3]);
long rl_dipole_acc_count(const rl_dipole_acc *d);
/* out mean[3] (may be NULL); returns <dM^2> (NaN if empty). */
double rl_dipole_acc_fluct(const rl_dipole_acc *d, double mean[3]);

/* Static dielectric constant with a reaction-field boundary (Neumann, Mol. Phys. 50, 841 (1983)):
 *   (eps - 1)(2 eps_rf + 1) / (2 eps_rf + eps) = y,   y = 4 pi kc <dM^2> / (3 V kB T)
 * (SI: y = <dM^2> / (3 eps0 V kB T), since kc = 1/(4 pi eps0)), solved as
 *   eps = (2 eps_rf (1 + y) + 1) / (2 eps_rf + 1 - y);   eps_rf = INFINITY (tin foil): eps = 1 + y.
 * in dM2 = <dM^2> (charge^2 length^2), V volume, T temperature, eps_rf >= 1 or INFINITY,
 *    units, coulomb_constant kc (0: RL_COULOMB_KJMOL_NM in real, 1 in lj).
 * RL_EINVAL for bad input or y >= 2 eps_rf + 1 (no positive solution). */
int rl_dielectric_constant(double dM2, double V, double T, double eps_rf, rl_units units,
                           double coulomb_constant, double *eps);
/* The inverse: <dM^2> expected for a fluid of dielectric constant eps under boundary eps_rf. */
double rl_dielectric_fluct(double eps, double V, double T, double eps_rf, rl_units units,
                           double coulomb_constant);

#ifdef __cplusplus
}
#endif
#endif
