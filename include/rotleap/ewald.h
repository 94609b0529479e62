/* rotleap — Ewald summation of point charges and point dipoles as force terms (terms.h), issue 33.
 *
 * The Coulomb energy of point charges q_a in an orthorhombic periodic cell, split by the
 * screening parameter alpha into
 *
 *   U = U_real + U_recip + U_self + U_intra + U_background + U_surface
 *
 *   U_real       kc sum_{a<b, not in one molecule, r_ab < rc} q_a q_b erfc(alpha r_ab) / r_ab
 *                (minimum image)                                        term "ewald-real"
 *   U_recip      (kc / 2V) sum_{k != 0} (4 pi / k^2) exp(-k^2 / 4 alpha^2) |S(k)|^2,
 *                S(k) = sum_a q_a exp(i k.r_a), every site pair, intramolecular ones included
 *                by the k-vector sum                                     term "ewald"
 *                by smooth particle-mesh Ewald                           term "pme"
 *   U_self       -kc alpha / sqrt(pi) sum_a q_a^2
 *   U_intra      -kc sum_{molecules} sum_{a<b in it} q_a q_b erf(alpha r_ab) / r_ab: removes
 *                the reciprocal-space part of the pairs within a rigid molecule, which are
 *                excluded (as OpenMM and GROMACS exclude them).  For a rigid body every r_ab
 *                is fixed, so U_intra is a constant and its forces, central and equal and
 *                opposite within the molecule, add no net force and no torque to it: it is
 *                computed once, as an energy only (docs/interactions.md, "Ewald").
 *   U_background -kc pi Q^2 / (2 V alpha^2), Q = sum_a q_a: a uniform neutralising background
 *                for a net charge (with a warning naming Q; rl_ewald_warnings)
 *   U_surface    kc 2 pi / ((2 eps' + 1) V) |M|^2, M = sum_a q_a r_a: a sphere of periodic
 *                images in a dielectric eps'; 0 for conducting (tin-foil) surroundings, the
 *                default (eps' = infinity)
 *
 * Point dipoles (all three terms): a site's dipole is the signed
 * scalar rl_species_ff.dipole[a] along its body's Z axis, m_a = mu_a e_z.  With B_0 = erfc(alpha r)/r
 * and B_l = [(2l - 1) B_{l-1} + (2 alpha^2)^l / (alpha sqrt(pi)) exp(-alpha^2 r^2)] / r^2 (B_1, B_2:
 * Allen & Tildesley's B and C; LAMMPS lj/cut/dipole/long), for r = r_a - r_b
 *   U_real       kc sum [q_a q_b B_0 + (q_a m_b.r - q_b m_a.r + m_a.m_b) B_1 - (m_a.r)(m_b.r) B_2]
 *   U_recip      the same sum with S(k) = sum_a (q_a + i m_a.k) exp(i k.r_a); on the mesh each
 *                site spreads q theta + m.grad theta (the B-splines' derivatives)
 *   U_self       adds -kc 2 alpha^3 / (3 sqrt(pi)) sum_a mu_a^2
 *   U_intra      adds, for a molecule with several polar sites, the erf form of the pair terms
 *                above (constant: the dipoles are fixed in the body)
 *   U_surface    with M = sum_a q_a r_a + sum_a m_a
 * and each dipole's torque m_a x E_a, E_a = -dU/dm_a, goes to its body.  The site virial keeps the
 * dipoles fixed under the strain (a barostat keeps the orientations): in k space that adds
 * -sum_a m_a (x) E_a^recip to the charges' formula, and the tensor is no longer symmetric.  The
 * error estimates below are the charges' (none for the dipoles).  docs/interactions.md, "Point
 * dipoles", has the derivations and the comparison with LAMMPS's ewald/dipole.
 *
 * The reciprocal terms ("ewald", "pme") report U_recip, U_self, U_intra, U_background and
 * U_surface as their components (names below); "ewald-real" reports U_real.  The sum of
 * "ewald-real" and one reciprocal term, made from one parameter block, is the Ewald sum; the
 * pair term's reaction-field Coulomb must then be off (no charges in the pair term).
 *
 * Forces on sites become forces and torques on bodies (rl_system_add_site_forces).  The virial
 * is the molecular one (the one a barostat scaling the centres at fixed orientations needs):
 * W = W_site - sum_a d_a (x) f_a, d_a = r_a - R_i the site's offset from its body's centre, with
 * W_site the site virial of the part (for the k-space parts the analytic derivative of U_recip
 * with respect to a strain of the cell and every site, Essmann et al. 1995 eq. 2.11); U_intra
 * and U_self add nothing to it, U_background adds U_background to each diagonal element, U_surface
 * its own derivative (docs/interactions.md).  Storage as rl_forces says: virial[3a + b] =
 * sum r_a f_b.
 *
 * Parameters: one block, rl_ewald_params, for all three types.  alpha, the k-vector cutoffs and
 * the mesh are given explicitly or derived from an error tolerance delta exactly as OpenMM 7.7
 * derives them from NonbondedForce's ewaldErrorTolerance (NonbondedForceImpl::calcEwaldParameters
 * and calcPMEParameters):
 *   alpha = sqrt(-ln(2 delta)) / rc
 *   Ewald: kmax_x is the smallest n with 0.05 sqrt(Lx alpha) n exp(-(pi n / (Lx alpha))^2) < delta
 *          (searched from 10 as OpenMM does), made odd; OpenMM sums |n_x| <= kmax_x - 1, which is
 *          what rotleap's kmax means, so rotleap's kmax[0] = OpenMM's kmaxx - 1
 *   PME:   K_x = max(6, ceil(2 alpha Lx / (3 delta^(1/5)))), B-spline order 5
 * With the choice goes an estimate of the RMS error of the force on a charge (rl_ewald_info):
 * Kolafa & Perram, Mol. Simul. 9, 351 (1992), for the real-space cut; for the k-space part the
 * sum of the omitted terms for Ewald, and Hockney & Eastwood's error functional evaluated for
 * the SPME influence function and analytical differentiation (the form of Ballenegger, Cerda &
 * Holm, J. Chem. Theory Comput. 8, 936 (2012); LAMMPS pppm's "ad" estimate) for PME, both for
 * randomly placed charges: dF = kc sum q^2 / V sqrt(Q / N).
 *
 * Point dipoles have estimates of their own, for randomly placed and oriented dipoles, of the RMS
 * force and torque errors: the real-space cut by Wang & Holm, J. Chem. Phys. 115, 6351 (2001),
 * eq. (37) for the force (as LAMMPS's ewald/dipole) and its counterpart for the torque, derived
 * the same way (the field of the pairs beyond rc, to leading order in exp(-alpha^2 rc^2)); the
 * k-space part from the omitted vectors (Ewald) or Hockney & Eastwood's functional for dipoles
 * (Cerda, Ballenegger, Lenz & Holm, J. Chem. Phys. 129, 234104 (2008)) with the SPME influence
 * function and analytical differentiation (PME):
 *   dF = kc sum mu^2 / V sqrt(Q_F / 9N),  dT = kc sum mu^2 / V sqrt(2 Q_T / 9N),
 *   Q_F = sum_m [sum_l phi_l^2 k_l^6 - 2 G sum_l phi_l U_l^2 k_l^6 + G^2 (sum_l U_l^2 k_l^4)(sum_l U_l^2 k_l^2)],
 *   Q_T = sum_m [sum_l phi_l^2 k_l^4 - 2 G sum_l phi_l U_l^2 k_l^4 + G^2 (sum_l U_l^2 k_l^2)^2]
 * (Ewald: G = 0 over the omitted vectors, U = 1).  When the system has point dipoles, the values
 * not given are derived from them instead: alpha where the real-space force estimate equals
 * dip_target (tolerance times the force between two unit charges 1 A apart; lj: tolerance
 * epsilon/sigma, LAMMPS's kspace accuracy), then the smallest k cutoff (or mesh, in proportion
 * to the edges) whose reciprocal estimate is below it; with charges too, the larger alpha of the
 * two choices and the finer k cutoff or mesh.  Point dipoles alone under PME with the mesh
 * derived: an FFT-friendly mesh (factors 2, 3, 5, 7) and, when order is 0, the spline order
 * (4..8), chosen together at least cost for the target (ewald_params.c, dip_pme_choose).
 *
 * Threads: every loop runs on `threads` OpenMP threads (0: OMP_NUM_THREADS if set, else 1), in
 * shares whose sums never depend on the thread count: structure factors are summed over sites
 * in order, forces site by site, the charge mesh plane by plane (each plane summing its sites in
 * order), energies and virials from per-k-column or per-plane partial sums added in order.  The
 * results are therefore the same to the bit for any number of threads (tests/forces/ewald/
 * test_ewald_sums.c checks 1, 2 and 3).  The FFTs (FFTW3, plans made with FFTW_ESTIMATE, which
 * are deterministic) run on one thread.
 *
 * Units: those of the system; real: nm, kJ/mol, e, kc = RL_COULOMB_KJMOL_NM (OpenMM 7.7's
 * ONE_4PI_EPS0); lj: kc = 1.  alpha in 1/length. */
#ifndef ROTLEAP_EWALD_H
#define ROTLEAP_EWALD_H

#include "rotleap/forcefield.h"
#include "rotleap/terms.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* One parameter block for "ewald-real", "ewald" and "pme" (defaults from rl_ewald_params_default;
 * every derived value follows OpenMM 7.7, see above). */
typedef struct {
  const rl_species_ff *species; /* [nspecies] the sites' charges and point dipoles, per species of
                                   the system (the species' nsites must match; quadrupoles are
                                   refused)                                                    */
  int nspecies;
  double cutoff;           /* rc of the real-space sum (> 0, <= half the shortest edge); sets
                              alpha with the tolerance                                         */
  double tolerance;        /* delta, OpenMM's ewaldErrorTolerance, in (0, 0.1) (default 5e-4,
                              OpenMM's default); the accuracy that derived values aim at and that
                              explicit ones are checked against                                 */
  double alpha;            /* screening parameter (1/length); 0 (default): sqrt(-ln(2 delta))/rc */
  int kmax[3];             /* "ewald": vectors k = 2 pi (n_x/Lx, n_y/Ly, n_z/Lz) with |n_c| <=
                              kmax[c]; 0 (default): derived (OpenMM's kmax - 1)                */
  double kmax_sq;          /* "ewald": and n_x^2 + n_y^2 + n_z^2 <= kmax_sq, a sphere in units of
                              (2 pi / L)^2 in a cubic cell (the NIST SPC/E reference sums use
                              kmax 5 with n^2 < 27, i.e. kmax_sq 26; LAMMPS's ewald likewise);
                              in a non-cubic cell an ellipsoid, so that the set of vectors does
                              not change when the cell is scaled.  0 (default): no such limit
                              (OpenMM sums the whole box of vectors)                          */
  int grid[3];             /* "pme": mesh points per edge; 0 (default): derived (OpenMM's)    */
  int order;               /* "pme": B-spline order p, 3..12; 0 (default): 5 (OpenMM's, fixed
                              there), or for point dipoles alone with the mesh derived, chosen
                              with the mesh                                                    */
  double eps_surface;      /* eps' of the surroundings of the sphere of images: INFINITY
                              (default) conducting, tin foil, no surface term; >= 1 a
                              dielectric (1: vacuum)                                           */
  double coulomb_constant; /* kc; 0 (default): RL_COULOMB_KJMOL_NM (real) or 1 (lj)           */
  int threads;             /* OpenMP threads; 0 (default): OMP_NUM_THREADS if set, else 1     */
  int remove_net_force;    /* "pme": 1 takes the net force of the mesh part off its charged
                              sites, an equal share each (Amber's netfrc), so that the forces
                              sum to zero as the leapfrog's total momentum (held at zero)
                              needs; the energy is unchanged.  0 (default): the forces as
                              OpenMM computes them, whose sum is not zero (the mesh's
                              interpolation breaks Newton's third law; about 1e-5 of the sum of
                              |F| at tolerance 5e-4)                                          */
} rl_ewald_params;

void rl_ewald_params_default(rl_ewald_params *p);

typedef enum {
  RL_EWALD_REAL = 0, /* the real-space part ("ewald-real")             */
  RL_EWALD_SUM = 1,  /* classical Ewald, the k-vector sum ("ewald")    */
  RL_EWALD_PME = 2   /* smooth particle-mesh Ewald ("pme")             */
} rl_ewald_method;

/* What a term uses, resolved from its parameter block and the system (and its cell). */
typedef struct {
  rl_ewald_method method;
  double alpha, cutoff, tolerance;
  int alpha_derived;       /* 1: alpha came from the tolerance                                 */
  int kmax[3];             /* "ewald"                                                          */
  double kmax_sq;          /* "ewald": 0 none                                                  */
  long nkvec;              /* "ewald": vectors summed (half space, k and -k counted once)      */
  int kmax_derived;
  int grid[3], order;      /* "pme"                                                            */
  int grid_derived;
  double eps_surface, coulomb_constant;
  int nsites_charged;      /* N: sites with q != 0 (the error estimates are for these)          */
  double sum_q2, net_charge;
  int nsites_dipolar;      /* sites with a point dipole (mu != 0)                               */
  double sum_mu2;          /* sum over them of mu^2                                             */
  double volume;
  /* estimated RMS error of the force on a charge (energy/length), for randomly placed charges:
   * real-space cut (Kolafa-Perram), reciprocal part (omitted vectors, or the mesh functional),
   * and their root sum of squares; the real-space term fills err_real only, the reciprocal ones
   * err_recip only, err_total both as if the other part were used with the same alpha and rc. */
  double err_real, err_recip, err_total;
  int threads;
  /* with point dipoles (nsites_dipolar > 0; NAN otherwise): the estimated RMS error of the force
   * (dip_err_*) and of the torque (dip_terr_*) on a point dipole, for randomly placed and
   * oriented dipoles, real part, reciprocal part and root sum of squares as above; and dip_target,
   * the force error that values derived for dipoles aim at: tolerance times the force between two
   * unit charges 1 A apart (lj: tolerance epsilon/sigma), LAMMPS's kspace accuracy convention. */
  double dip_err_real, dip_err_recip, dip_err_total;
  double dip_terr_real, dip_terr_recip, dip_terr_total;
  double dip_target;
} rl_ewald_info;

/* Resolve and check a parameter block for a method on a system (its species and cell): derived
 * values filled in, the error estimates computed.  RL_OK, or RL_EINVAL with a message naming the
 * parameter: tolerance outside (0, 0.1); cutoff not positive or beyond half the shortest edge,
 * or so short that alpha would need more than 1024 mesh points (or k vectors) per edge; an
 * explicit alpha with alpha rc below sqrt(-ln 0.2) = 1.27 (where erfc(alpha rc) leaves the
 * real-space cut a relative error beyond 0.1, the largest tolerance); a grid (or kmax) too coarse
 * for the tolerance: exp(-k^2 / 4 alpha^2) > 10 delta at the shortest wave vector it leaves out
 * (the mesh's Nyquist vector pi K / L, or the shortest vector outside the Ewald set); a grid below
 * the spline order; an order outside 3..12; eps' below 1; no box; no charged or dipolar site;
 * quadrupoles on a site; a non-finite charge or dipole; a species table that does not match
 * the system. */
int rl_ewald_resolve(const rl_system *sys, const rl_ewald_params *p, rl_ewald_method method,
                     rl_ewald_info *info);

/* One line (at most `size` - 1 characters, NUL-terminated; returns what snprintf returns) that
 * says what a term uses: method, alpha and where it came from, the k cutoffs or the mesh and
 * order, the boundary, and the estimated RMS force error, e.g.
 * "smooth PME: alpha = 3.4467 /nm (from tolerance 0.0005 and cutoff 0.9 nm), grid 36 x 36 x 36
 * (from the tolerance), order 5, tin-foil boundary; estimated RMS force error on a charge
 * 0.41 kJ/mol/nm (real space 0.23, reciprocal 0.34)". */
int rl_ewald_describe(const rl_ewald_info *info, rl_units units, char *buf, size_t size);

/* The term types (terms.h); their state's first member is the resolved rl_ewald_info, so
 * rl_ewald_term_info works on the state of any of them. */
extern const rl_term_type rl_term_ewald_real; /* "ewald-real": U_real; components: ewald_real  */
extern const rl_term_type rl_term_ewald;      /* "ewald": classical Ewald, components:
                                                 ewald_recip, ewald_self, ewald_intra,
                                                 ewald_background, ewald_surface              */
extern const rl_term_type rl_term_pme;        /* "pme": smooth PME, the same five components   */

const rl_ewald_info *rl_ewald_term_info(const void *state);

/* Setup remarks that are not errors (one sentence each, like rl_forcefield_warnings): a net
 * charge, naming it and the background energy it brings.  Writes the first `max` to out and
 * returns how many there are. */
int rl_ewald_warnings(const void *state, rl_ff_warning *out, int max);

/* Site-level results of a term, for tests and the accuracy scripts: the forces on every site
 * (fs [nsites][3], lab, overwritten), the term's energy components (energies[], as its
 * compute reports them) and the site virial W_site (before the molecular correction).  The
 * term's compute is these plus the reduction to bodies (and, with point dipoles, their torques
 * m x E, which these do not return). */
int rl_ewald_site_forces(void *state, const rl_system *sys, double (*fs)[3], double *energies,
                         double virial_site[9]);

/* The forces on every site (fs [nsites][3], overwritten) of the intramolecular correction
 * U_intra, which the terms never apply (their net force and torque on each rigid molecule is
 * zero; test_ewald_sums.c shows it), and its energy at the current configuration (returned;
 * equal to the constant the terms report).  Charge-charge pairs only: for molecules with point
 * dipoles the pairs with a dipole are left out (of forces and energy). */
double rl_ewald_intra_site_forces(const void *state, const rl_system *sys, double (*fs)[3]);

#ifdef __cplusplus
}
#endif
#endif
