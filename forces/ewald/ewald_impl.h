/* Internal: the state every Ewald term starts with, and the parts they share (ewald_common.c).
 *
 * A term keeps the charged sites only (q != 0; TIP4P's O drops out): their charges, their
 * global site index and body, and per compute their positions xq and forces fq.  A compute is
 * the same for all three terms: gather positions, the term's own part (`part`: real-space pairs,
 * the k-vector sum or the mesh) adds forces to fq and its site virial to W, the reciprocal terms
 * add the constant and boundary parts, and ew_finish scatters fq to the sites, reduces them to
 * bodies and turns W into the molecular virial. */
#ifndef ROTLEAP_FORCES_EWALD_IMPL_H
#define ROTLEAP_FORCES_EWALD_IMPL_H

#include "rotleap/ewald.h"

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

typedef struct ew_base ew_base;

struct ew_base {
  rl_ewald_info info; /* first: rl_ewald_term_info reads it from any term's state             */
  rl_ewald_params p;  /* as given (its species arrays are read at alloc only)                  */
  rl_units units;
  /* the term's own part: add forces on the charged sites to fq, its site virial to W (r (x) f
   * convention), return its energy in *e */
  int (*part)(ew_base *b, double *e, double W[9]);
  int n, nsites, nq;
  int *qsite, *qbody; /* [nq] global site index, body of each charged site                    */
  double *q;          /* [nq]                                                                 */
  /* point dipoles (ndip > 0): the list then holds every polar site (q != 0 or mu != 0), and the
   * parts take their dipolar paths; with ndip == 0 it holds the charged sites and the charge-only
   * paths run unchanged (the same bits as before dipoles were added) */
  int ndip;
  double *mu;         /* [nq] dipole along the body's Z axis (0: none)                         */
  double (*md)[3];    /* [nq] lab dipoles mu e_z of the current configuration                  */
  double (*eq)[3];    /* [nq] field at each site, E = -dU/d(md) (torque md x E)                */
  double (*xs)[3];    /* [nsites] scratch: site positions                                     */
  double (*fs)[3];    /* [nsites] scratch: site forces                                        */
  double (*xq)[3];    /* [nq] positions of the charged sites                                  */
  double (*fq)[3];    /* [nq] forces on them                                                  */
  double (*rc)[3];    /* [n] body centres                                                     */
  double L[3];        /* the cell the term follows                                            */
  double e_self, e_intra;
  int threads;
  /* for rl_ewald_intra_site_forces: the molecule of each charged site is [mol_first, +count) */
  int *qmol_first, *qmol_count; /* [nq] */
};

/* A term's state of `size` bytes that starts with an ew_base made from params (an
 * rl_ewald_params) for method: resolved, the charges copied, U_self and U_intra computed.  NULL
 * with a message. */
void *ew_alloc(size_t size, const rl_system *sys, const void *params, rl_ewald_method method);
void ew_base_free(ew_base *b);
/* The cell changed: re-resolve, keeping alpha, the k cutoffs and the mesh. */
int ew_base_box(ew_base *b, const rl_system *sys);
/* W (3x3, row-major) += the symmetric tensor w = (xx, yy, zz, xy, xz, yz). */
void ew_add_virial6(double W[9], const double w[6]);

/* Positions of the charged sites (and the centres), and the lab dipoles, for the current
 * configuration; fq and eq zeroed. */
int ew_gather(ew_base *b, const rl_system *sys);
/* The reciprocal parts' extra site virial with point dipoles, W -= sum_a md_a (x) eq_a, eq holding
 * the part's field alone: the dipoles stay fixed under the strain while k (or the mesh's
 * gradient K/L) changes, so m.k changes (ewald_kspace.c). */
void ew_dipole_virial(const ew_base *b, double W[9]);
/* The reciprocal terms' constant and boundary parts: adds U_self, U_intra, U_background,
 * U_surface to e[1..4] (e[0] is U_recip), their forces to fq and their site virial to W. */
void ew_reciprocal_extras(ew_base *b, double e[5], double W[9]);
/* fq -> site forces -> bodies in out, and md x eq to the torques of the dipoles' bodies; W (site
 * virial, dipoles held fixed under the strain) -> molecular virial added to out; energies added
 * unless out->forces_only. */
void ew_finish(ew_base *b, const rl_system *sys, rl_forces *out, double etotal, const double W[9]);

/* The whole compute of a term with its part; ne energy components (1: real, 5: reciprocal). */
int ew_compute(ew_base *b, const rl_system *sys, rl_forces *out, double *energies, int ne);

/* rl_ewald_resolve; with keep, alpha, the k cutoffs, the mesh and the order (and whether they
 * were derived) are kept from it, as a change of cell does (ew_base_box). */
int ew_resolve(const rl_system *sys, const rl_ewald_params *p, rl_ewald_method method, const rl_ewald_info *keep,
               rl_ewald_info *in);
/* rl_ewald_resolve's error estimates (ewald_params.c). */
double ew_err_real(const rl_ewald_info *in, double V);
double ew_err_ewald(const rl_ewald_info *in, const double L[3]);
double ew_err_pme(const rl_ewald_info *in, const double L[3], const double *mod[3]);
/* B-spline moduli |sum_j M_p(j + 1) exp(2 pi i m j / K)|^2 for m = 0..K-1, as OpenMM 7.7's
 * reference PME forms them (values below 1e-7, where an odd order's modulus vanishes at the
 * Nyquist index, replaced by the mean of their neighbours) (pme.c). */
void ew_bspline_moduli(int order, int K, double *mod);

#endif
