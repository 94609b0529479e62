/* The pair list of the pair term (internal): the molecule pairs whose minimum-image centre
 * distance was below the list radius rlist when the list was built.
 *
 * One rule decides when to build again, for every list: it stays valid while no centre has
 * moved (minimum image) by more than skin/2 since the build (rl_nlist_needs_rebuild).  Then no
 * pair can have come closer than rlist - skin, so callers choose rlist = (interaction range of
 * the centres) + skin.  The list also outlives a change of the box (a barostat's scaling): with
 * s_k = L_k / L0_k the edges now over those at the build, a centre's displacement is measured
 * from its origin scaled with the box, d_i = r_i - s r0_i (minimum image), and a pair left out
 * of the list (every image at least rlist apart at the build) is now at least
 * s_min rlist - 2 max|d| apart, since scaling by s changes a distance r by at most
 * (1 - s_min) r.  So the list stays valid while 2 max|d| + max(0, 1 - s_min) rlist <= skin: the
 * box's shrinking uses up skin in proportion to rlist.  A box that did not change gives s = 1
 * exactly, and the rule is the one without a box change, to the bit.  Rotation needs no check: with a site cutoff rc the centres' range is
 * rc + 2 extent (extent = the largest |site - centre|), and a rigid body's sites stay within
 * its extent however it turns.  The centres at a build also restart a run on the list it had
 * (rl_forcefield_list_origin).
 *
 * Two layouts, because their users differ:
 *   rl_nlist   the reference path's (pairlist.c): pairs i < j in body order, built from cells
 *              of edge >= rlist (O(N)) when every box edge holds at least three, else by an
 *              O(N^2) scan of all pairs.  The reference routine walks it serially; its order
 *              fixes the reference sums and which overlapping pair an error names first, and
 *              it is built independently of the kernels' list, so that the tests comparing the
 *              two paths (test_ff_fast) check the kernels' list too.
 *   rl_rowlist the kernels' (pairlist_rows.c, pairlist_images.c): the bodies ranked in cell
 *              order (cells of rlist/2, a 5^3 stencil), row m listing the ranks above m,
 *              split into kernel neighbours (ranks of the same kernel species) and reference
 *              neighbours (bodies), built in parallel chunks; and, for the AVX2 TIP4P rows of
 *              a small box, every image of a neighbour within rlist with its shift.
 * Serving the reference path from the rows would change its sums at round-off and the overlap
 * it names first; serving the kernels from the pairs would lose the spatial order, the split
 * and the parallel build.  test_ff_nlist checks that both list the same pairs. */
#ifndef ROTLEAP_PAIR_PAIRLIST_H
#define ROTLEAP_PAIR_PAIRLIST_H

#include "../../core/box.h"

/* The reference layout, and every list's build state (the kernels' list keeps one, without
 * pairs, for the rule). */
typedef struct {
  int n;                /* size at the last build (-1: never built)                   */
  double rlist, skin;
  double (*r0)[3];      /* [n] centres at the last build                             */
  double L0[3];         /* the box's edges at the last build                         */
  int (*pairs)[2];      /* [npairs] i < j                                            */
  long npairs, cap;
  long builds;          /* number of builds so far                                   */
  int used_cells;       /* 1 if the last build used cells, 0 for the all-pairs scan   */
  int *head, *next;     /* cell list workspace                                       */
  int ncell_cap;
} rl_nlist;

/* in skin >= 0.  Returns NULL (with rl_error set) when out of memory. */
rl_nlist *rl_nlist_alloc(double skin);
void rl_nlist_free(rl_nlist *nl); /* accepts NULL */

/* in  box (the current one), n, r[n][3] centres; threads: OpenMP threads for the scan (1:
 *     serial; the result does not depend on it)
 * Returns 1 if the list must be rebuilt: never built, size changed, or
 * 2 max|d| + max(0, 1 - s_min) rlist > skin (the rule above; with skin 0, any displacement or
 * change of the box); 0 otherwise.  Also returns the largest displacement max|d| in *maxdisp
 * (may be NULL). */
int rl_nlist_needs_rebuild(const rl_nlist *nl, const rl_box *box, int n, const double (*r)[3],
                           double *maxdisp, int threads);

/* 1 if box differs from the box of the last build (0 before any build). */
int rl_nlist_box_changed(const rl_nlist *nl, const rl_box *box);

/* Build the list for list radius rlist (> 0) in box (recorded as L0).  Returns RL_OK or RL_ENOMEM. */
int rl_nlist_build(rl_nlist *nl, const rl_box *box, double rlist, int n, const double (*r)[3]);

/* ---------------------------------------------------------------- the kernels' layout */

typedef struct {
  int *f, *g;                    /* kernel / reference neighbours of this chunk's rows  */
  long fcap, gcap, fn, gn;
} rl_rowchunk;

typedef struct far_image far_image; /* pairlist_images.c */

typedef struct {
  rl_nlist *chk;                 /* the build's centres, size, radius and count          */
  int nthreads;
  /* the rows, by rank (the bodies in cell order at the build): */
  int *ord;                      /* [n] body of each rank                                */
  int *soff, *sp;                /* [n] each rank's first site and species               */
  int *fstart, *gstart;          /* [n + 1] CSR row starts: kernel, reference neighbours */
  int *fnbr, *gnbr;              /* kernel neighbours (ranks), reference ones (bodies)   */
  long fcap, gcap;
  int *rmax;                     /* [n] highest rank of row m and its kernel neighbours   */
  /* The image list of a small box (when asked for, else ximages = 0): row m's entries are
   * xnbr[xstart[m] .. xstart[m + 1]), the neighbour's rank, and its separation from m is
   * centre_m - centre_j + (xs[0][q], xs[1][q], xs[2][q]), a multiple of the edges added. */
  int ximages;
  int *xstart, *xnbr;            /* [n + 1] and [xcap + 4]                               */
  const double *xs[3];           /* into xsh                                             */
  double *xsh;                   /* [3 (xcap + 4)] the shifts, x then y then z           */
  long xcap;
  far_image *xfar;               /* [n + 4] workspace                                    */
  /* the build's workspace */
  int nchunk;                    /* rows in chunks that the threads take in turn         */
  rl_rowchunk *tr;               /* [nchunk] (dynamic: the first ranks have the most     */
                                 /* candidates of higher rank)                           */
  int **cand;                    /* [nthreads][n + 16] one row's candidates within rlist */
  int *cell_of, *cell_start, *cell_body;
  int ncell_cap;
  double *bx;                    /* [3 n] centres by rank, x then y then z               */
} rl_rowlist;

/* What a build of the kernels' list reads (plain arrays). */
typedef struct {
  const rl_box *box;
  double rlist;                  /* > 0                                                  */
  int n, nspecies;
  const double (*centre)[3];     /* [n]                                                  */
  const int *body_species;       /* [n]                                                  */
  const int *sp_count;           /* [nspecies] bodies                                    */
  const int *sp_nsites;          /* [nspecies] sites (0: the species interacts with none) */
  const unsigned char *kernel;   /* [nspecies] 1: its pairs of two bodies go to kernel rows */
  const unsigned char *images;   /* [nspecies] 1: the image list for its rows; NULL: none */
  int scan512;                   /* 1: the AVX-512 candidate scan (the CPU has it)        */
} rl_rowlist_in;

/* For n bodies, built by `threads` OpenMP threads (the rows do not depend on the count), skin
 * >= 0 for the rule.  NULL (with rl_error set) when out of memory. */
rl_rowlist *rl_rowlist_alloc(int n, int threads, double skin);
void rl_rowlist_free(rl_rowlist *L); /* accepts NULL */

/* Build the rows (and the image list when in->images) from in->centre.  Returns RL_OK or
 * RL_ENOMEM (with rl_error). */
int rl_rowlist_build(rl_rowlist *L, const rl_rowlist_in *in);

#endif
