/* The kernel interface of the pair term (internal): what a row of a specialised kernel reads
 * and writes, and the row sets the row files export.
 *
 * A row is one molecule (rank i: the pair list's spatial order) against the ranks nbr[0 .. len)
 * of the same species: row_fn(kp, V, K, i, nbr, len, out) with kp the parameter block of the
 * compute (box, cutoffs, electrostatics), V the bodies' copies in rank order (plain arrays), K
 * the species' terms, and out the thread's buffers and sums.  A row never sees the force field.
 *
 * The tree (docs/interactions.md, "Kernels"):
 *   kernels/<instruction set>/<pattern>_row.h      the row bodies, templates
 *   kernels/<instruction set>/<pattern>_<vdw>_<elec>.c   one row set: the template compiled
 *                                                   with one electrostatics
 *   kernels/elec/<elec>.h                          the electrostatics (rf.h, sf.h, ewald.h;
 *                                                   elec.h)
 *   kernels/vdw_lj.h, batch.h, tip4p.h             what the rows share
 * with the instruction sets portable (omp simd, compiled per CPU with target clones), avx512,
 * avx2 (register rows) and avx2_mixed (AVX2, single precision), the patterns sites
 * ("charge-lj"), tip4p and dipole (Stockmayer), and each row set holding the rows of every
 * separation mode and LJ truncation (rl_row_set), picked per species in select.c. */
#ifndef ROTLEAP_PAIR_KERNEL_H
#define ROTLEAP_PAIR_KERNEL_H

#include "../isa.h"
#include "rotleap/forcefield.h"

#define RL_FAST_MAXS 8  /* sites per molecule in the site kernels                   */
#define RL_FAST_MAXT (RL_FAST_MAXS * RL_FAST_MAXS)


enum { K_NONE = 0, K_SITES = 1, K_DIPOLE = 2, K_TIP4P = 3 };
enum { T_LJ = 0, T_COUL = 1, T_BOTH = 2 };

typedef struct {
  int a, b, what;
  double qq;                     /* kc q_a q_b                                          */
  double c6, c12, eshift, fshift; /* LJ (rl_lj_coef)                                    */
} fast_term;

/* What the kernels read: the bodies in the list's (spatial) order, see rl_ff_fast. */
typedef struct {
  double (*c)[3];                /* [n] centres                                          */
  double (*ax)[3];               /* [n] body Z axes                                      */
  double (*site)[3];             /* [nsites] lab sites                                   */
  double (*dsite)[3];            /* [nsites] site - centre                               */
  int *soff;                     /* [n] first site                                       */
  int *sp;                       /* [n] species                                          */
  double (*pk)[8];               /* [n] dipole ranks, AVX-512 path: centre, 0, mu axis, 0 */
  double (*pk4)[16];             /* [n] TIP4P ranks, AVX-512 path: centre, then site       */
                                 /* perm[s] - centre at 3 + 3 s, 0                      */
  float (*pk4f)[16];             /* [n] TIP4P ranks, mixed precision: site perm[s] -     */
                                 /* centre at 3 s, 0                                    */
  /* The image list of a small box (AVX2 TIP4P rows, see build_images): row m's images are
   * xnbr[xstart[m] .. xstart[m + 1]), the neighbour's rank, and its separation from m is
   * centre_m - centre_j + (xs[0][q], xs[1][q], xs[2][q]).  NULL where not in use. */
  const int *xstart, *xnbr;
  const double *xs[3];
} kview;

typedef struct {
  int kind, ns, nterms;
  fast_term t[RL_FAST_MAXT];     /* tip4p: t[0] the LJ term, t[1 + 3 p + q] charge p, q  */
  int perm[RL_FAST_MAXS];        /* batch slot s holds site perm[s] (tip4p: LJ site first) */
  double extent;                 /* max |site - centre|                                  */
  double mu;                     /* stockmayer: dipole moment                          */
} fast_species;

/* How a kernel forms site separations r = (site a of i) - (site b of j):
 *   P_SITE   site cutoff, each site pair's own minimum image (boxes with an edge <= rp);
 *   P_SHIFT  site cutoff, r = R + d_a - d_b with R an image of the centres' separation, three
 *            fewer roundings per term than P_SITE.  A site pair inside the cutoff has centres
 *            closer than the pruning radius rp = rc + 2 extent.  When every edge L >= 2 rp the
 *            centres' minimum image is the only image that close; in smaller boxes (edges
 *            rp < L < 2 rp, e.g. 256 TIP4P at rc = 0.9 nm) the fills also emit the images
 *            X -+ L of the components with |X| > L - rp (other_images), each a lane of its own.
 *            Every site pair is then counted once: L >= 2 rc puts at most one of its images
 *            inside the cutoff.  Edges L <= rp (2 extent >= rc: molecules as long as the cutoff)
 *            take P_SITE;
 *   P_MOL    molecule cutoff: r = R + d_a - d_b, and the pair interacts iff |R| < rc. */
enum { P_SITE = 0, P_SHIFT = 1, P_MOL = 2 };

/* Batches are padded to a multiple of the widest vector (8 doubles, AVX-512), so the vector
 * loops never run a scalar remainder; padding lanes carry weight 0. */
#define RL_FAST_W 8

/* The box and the cutoffs: edges and their inverses, rc and rc^2, the LJ switch, and the minimum
 * distance squared (a site pair inside the cutoff closer than that is an overlap). */
typedef struct {
  double L[3], iL[3], rc, rc2, rsw, md2;
} box_consts;

/* The parameters of the electrostatics (each header of kernels/elec/ reads its own; a new
 * electrostatics adds its own here, and rl_ff_kparams in select.c sets them). */
typedef struct {
  double kc;        /* Coulomb constant (dipole terms; a charge pair's qq includes it)      */
  double krf, crf;  /* reaction field (elec/rf.h): rl_rf_coef's krf and crf                 */
  double rc;        /* cutoff (elec/sf.h, shifted-force dipoles)                            */
  double alpha, c2a; /* Ewald real space (elec/ewald.h): alpha and 2 alpha / sqrt(pi)       */
} rl_kelec;

/* The parameter block of a compute, what a row reads besides the arrays. */
typedef struct {
  box_consts B;
  rl_kelec E;
} rl_kparams;

/* What a row adds to (one per thread): energies by term, the virial, and whether some site
 * pair inside the cutoff came closer than the minimum distance. */
typedef struct {
  double lj, coul, dip, quad;
  double vir[9];
  int bad;
} rl_ksums;

/* Where a row writes (the thread's buffers, by rank): fs [nsites] site forces, tq [n] torques,
 * ft [n] the dipole records' forces and torques, ft4 [n] the TIP4P records' site forces, and
 * the sums. */
typedef struct {
  double (*fs)[3];
  double (*tq)[3];
  double (*ft)[8];
  double (*ft4)[16];
  rl_ksums *sums;
} rl_kout;

/* A row: rank i against the ranks nbr[0 .. len) of its species, in the list's order. */
typedef void (*row_fn)(const rl_kparams *kp, const kview *V, const fast_species *K, int i,
                       const int *nbr, int len, const rl_kout *out);

/* The rows of one kernel on one instruction set, [separation mode][LJ truncation]: ev computes
 * energies, virial and forces; fo is the same for a forces-only compute (NULL: take ev).  A
 * NULL ev row: this instruction set has no row for that mode (the portable one runs). */
typedef struct {
  row_fn ev[3][4], fo[3][4];
} rl_row_set;

/* The row sets (kernels/<instruction set>/<pattern>_<vdw>_<elec>.c). */
extern const rl_row_set rl_rows_portable_sites_lj_rf, rl_rows_portable_tip4p_lj_rf,
    rl_rows_portable_dipole_lj_rf, rl_rows_portable_dipole_lj_sf, rl_rows_portable_sites_lj_ewald,
    rl_rows_portable_tip4p_lj_ewald, rl_rows_portable_dipole_lj_ewald;
#if RL_X512
extern const rl_row_set rl_rows_avx512_tip4p_lj_rf, rl_rows_avx512_dipole_lj_rf,
    rl_rows_avx512_dipole_lj_sf, rl_rows_avx2_tip4p_lj_rf, rl_rows_avx2_dipole_lj_rf,
    rl_rows_avx2_dipole_lj_sf, rl_rows_avx2_mixed_tip4p_lj_rf, rl_rows_avx512_tip4p_lj_ewald,
    rl_rows_avx2_tip4p_lj_ewald, rl_rows_avx512_dipole_lj_ewald, rl_rows_avx2_dipole_lj_ewald;
#endif

/* A row function with the kernels' arguments (every row file). */
#define ROW_FN_T(ATTR, NAME, BODY)                                                             \
  ATTR static void NAME(const rl_kparams *kp, const kview *V, const fast_species *K, int i,    \
                        const int *nbr, int len, const rl_kout *out)                           \
  {                                                                                            \
    double(*const fs)[3] = out->fs, (*const tq)[3] = out->tq;                                  \
    double(*const ft)[8] = out->ft;                                                            \
    double(*const ft4)[16] = out->ft4;                                                         \
    rl_ksums *const acc = out->sums;                                                           \
    (void)fs;                                                                                  \
    (void)tq;                                                                                  \
    (void)ft;                                                                                  \
    (void)ft4;                                                                                 \
    BODY;                                                                                      \
  }
#define ROW_FN(NAME, BODY) ROW_FN_T(RL_CLONES, NAME, BODY)

/* Row instances for the four LJ truncations, R##0 .. R##3, of a template INST(NAME, ..., TRUNC)
 * (the row templates' RL_*_ROWS use these), and the row-set entries [mode][truncation]. */
#define RL_ROWS_MODE(INST, R, MODE)                                                            \
  INST(R##0, MODE, RL_LJ_PLAIN)                                                                \
  INST(R##1, MODE, RL_LJ_SHIFTED)                                                              \
  INST(R##2, MODE, RL_LJ_SHIFTED_FORCE)                                                        \
  INST(R##3, MODE, RL_LJ_SWITCHED)
#define RL_ROWS_EV(INST, R, EV, MODE)                                                          \
  INST(R##0, EV, MODE, RL_LJ_PLAIN)                                                            \
  INST(R##1, EV, MODE, RL_LJ_SHIFTED)                                                          \
  INST(R##2, EV, MODE, RL_LJ_SHIFTED_FORCE)                                                    \
  INST(R##3, EV, MODE, RL_LJ_SWITCHED)
#define RL_SET_TRUNC(R) {R##0, R##1, R##2, R##3}
/* rows S, H, M for the modes P_SITE, P_SHIFT, P_MOL; NULL: none (the portable row runs) */
#define RL_SET_MODES(S, H, M) {RL_SET_TRUNC(S), RL_SET_TRUNC(H), RL_SET_TRUNC(M)}
#define RL_SET_SHIFT_MOL(H, M) {{NULL, NULL, NULL, NULL}, RL_SET_TRUNC(H), RL_SET_TRUNC(M)}
/* A row set SET of a template INST(NAME, MODE, TRUNC) for every mode: rows S, H, M (P_SITE,
 * P_SHIFT, P_MOL) + truncation. */
#define RL_ROWS_ALL_MODES(SET, INST, S, H, M)                                                  \
  RL_ROWS_MODE(INST, S, P_SITE)                                                                \
  RL_ROWS_MODE(INST, H, P_SHIFT)                                                               \
  RL_ROWS_MODE(INST, M, P_MOL)                                                                 \
  const rl_row_set SET = {RL_SET_MODES(S, H, M), {{0}}};
/* A row set SET of a template INST(NAME, EV, MODE, TRUNC) for the modes with the centres'
 * image, with (XH, XM) and without (OH, OM: forces only) the energy and virial sums. */
#define RL_ROWS_CENTRE_IMAGE(SET, INST, XH, XM, OH, OM)                                        \
  RL_ROWS_EV(INST, XH, 1, P_SHIFT)                                                             \
  RL_ROWS_EV(INST, XM, 1, P_MOL)                                                               \
  RL_ROWS_EV(INST, OH, 0, P_SHIFT)                                                             \
  RL_ROWS_EV(INST, OM, 0, P_MOL)                                                               \
  const rl_row_set SET = {RL_SET_SHIFT_MOL(XH, XM), RL_SET_SHIFT_MOL(OH, OM)};
/* A row set SET of a template INST(NAME, EV, MODE, TRUNC) whose rows do not depend on the mode
 * (point dipoles: r = R), with (X) and without (O) the energy and virial sums. */
#define RL_ROWS_ANY_MODE(SET, INST, X, O)                                                      \
  RL_ROWS_EV(INST, X, 1, P_MOL)                                                                \
  RL_ROWS_EV(INST, O, 0, P_MOL)                                                                \
  const rl_row_set SET = {RL_SET_MODES(X, X, X), RL_SET_MODES(O, O, O)};

#endif
