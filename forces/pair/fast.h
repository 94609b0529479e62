/* The specialised kernels' path of the pair term (internal): the state that kernel selection
 * (select.c) and the threaded driver (driver.c) share; the kernels' pair list is pairlist.h's,
 * the rows are in kernels/ (kernels/kernel.h).
 *
 * At alloc (rl_ff_fast_setup) each species gets a kernel from its site pattern (select.c):
 *   sites      LJ and charges only, <= RL_FAST_MAXS sites: a fixed list of (site a, site b,
 *              LJ | charge | both) terms made once, so the inner loop never tests which terms
 *              apply.  One LJ site without charge + three charges without LJ is "tip4p"
 *              (1 LJ + 9 charge terms); anything else is "charge-lj" (all terms).
 *   stockmayer one site at the centre with LJ and a dipole, no charge: LJ + dipole-dipole.
 * Pairs of two bodies of one such species go through its kernel; every other pair (another
 * species, quadrupoles, charge-dipole, LJ overrides that break a pattern) through the reference
 * routine rl_ff_body_pair.
 *
 * Layout: at each list build the bodies are ranked in cell order (x fastest); the kernels read
 * copies of centres, axes and sites in that order, refreshed every step, so a row's neighbours
 * lie in a few contiguous runs of memory and consecutive rows share them (`ffbench scaling`
 * shows the cost per molecule against N).  The molecule-pair list is in CSR form (row m: the
 * ranks above m within rlist), split at build time into kernel and reference neighbours
 * (rl_rowlist).  A portable row walks its neighbours in batches of RL_FAST_B: it keeps those
 * within the centres' interaction range (the list holds about twice as many), copies their
 * sites into structure-of-arrays buffers padded to 8 lanes, runs branch-free `omp simd` loops
 * (the cutoff as a 0/1 factor), then scatters the forces.  Where the CPU has AVX-512 (and
 * ROTLEAP_NO_AVX512 is unset) the TIP4P rows with the centres' image keep only the
 * neighbours' indices and centre separations in their batches (tip4p_fill512) and form all
 * terms in registers from transposes of 128-byte records (tip4p_row512), and the dipole rows
 * keep no batch at all: they pack each eight neighbours within the cutoff into registers and
 * form their terms there (dipole_row512).  Where the CPU has AVX2 but not AVX-512 (and
 * ROTLEAP_NO_AVX2 is unset) both do the same four lanes wide (tip4p_row256, dipole_row256).
 * The portable TIP4P rows run their 10 terms in one loop; "charge-lj" one loop per term.  Each
 * term is the reference formula; 1/sqrt is rl_rsqrt (a few ulp, no divider; vrsqrt14pd and two
 * Newton steps in the AVX-512 rows), a * b + c may be one FMA, and separations and sums are
 * formed in another order, so results agree with the reference to round-off.
 *
 * Threads (driver.c): rows are split into contiguous ranges of nearly equal cost, one per
 * thread; each thread adds into its own site-force and torque buffers; the buffers and the
 * per-thread energy and virial sums are added in thread order.  Fixed thread count:
 * reproducible bit for bit.
 *
 * Virial: kernels add r (x) f with r the site separation; afterwards W = sum r (x) f -
 * sum_sites d_a (x) F_a (d_a = site - centre, F_a = total site force), which equals the
 * reference sum of R (x) f with R = r - d_a + d_b.  The TIP4P kernel with the centres' image
 * adds R (x) F per pair directly, and the compute step adds back its share of the correction
 * (see tip4p_row). */
#ifndef ROTLEAP_PAIR_FAST_H
#define ROTLEAP_PAIR_FAST_H

#include "forcefield_impl.h"
#include "kernels/kernel.h"
#include "pairlist.h"

struct rl_ff_fast {
  int nthreads;
  fast_species *sk;              /* [nspecies] what the rows read of each species        */
  row_fn (*row)[2][3];           /* [nspecies][forces only][separation mode]: the rows   */
  unsigned char *kernel;         /* [nspecies] 1: the species has a kernel (sk kind)     */
  unsigned char *images;         /* [nspecies] the image list's species (rl_ff_image_rows) */
  const char *name;
  char namebuf[96];
  /* The kernels' pair list: at each build the bodies are ranked by cell (x fastest), and the
   * kernels work on copies in that order (V, refreshed every step), so a row's neighbours sit
   * in a few contiguous runs of memory and consecutive rows share them.  Kernel rows and their
   * neighbours are ranks; reference rows are ranks with body neighbours. */
  rl_rowlist *list;
  int *tlo;                      /* [nthreads + 1] row ranges                           */
  int *thi;                      /* [nthreads] thread t's rows write the kernel buffers   */
                                 /* (pfs, ptq, pft, pft4) of ranks [tlo[t], thi[t])    */
  double (*fsbuf)[3];            /* [(nthreads - 1) nsites]                             */
  double (*tqbuf)[3];            /* [(nthreads - 1) n]                                  */
  rl_acc *acc;                   /* [nthreads]                                          */
  int *status;                   /* [nthreads]                                          */
  int *mode;                     /* [nspecies] separation mode of this compute          */
  kview V;                       /* soff, sp and the image list point into list          */
  double (*pfs)[3];              /* [nthreads nsites] kernel site forces, rank order    */
  double (*ptq)[3];              /* [nthreads n] kernel torques, rank order             */
  int vec;                       /* the dipole and TIP4P rows: VEC_PORTABLE, or the      */
                                 /* register rows on VEC_512 (AVX-512) or VEC_256 (AVX2) */
  int tmix;                      /* the TIP4P rows in mixed precision (AVX2, pk4f)        */
  int ndip;                      /* bodies of K_DIPOLE species                           */
  double (*pft)[8];              /* vec:  [nthreads n] force 0..2, torque 4..6 on dipole  */
                                 /* ranks from the batches (rows add their own to pfs) */
  int ntip4p;                    /* bodies of K_TIP4P species                            */
  double (*pft4)[16];            /* vec:  [nthreads n] forces on TIP4P ranks' sites from */
                                 /* the batches, as in pk4                              */
};

/* The register rows in use (rl_ff_fast.vec). */
enum { VEC_PORTABLE = 0, VEC_512 = 1, VEC_256 = 2 };

/* select.c: the kernel of each species, the instruction set of the register rows and the
 * precision; f->sk, vec, tmix, ndip, ntip4p and the name. */
void rl_ff_select(const rl_forcefield *ff, rl_ff_fast *f);

/* select.c: the parameter block of a compute (box, cutoffs, electrostatics). */
void rl_ff_kparams(const rl_forcefield *ff, rl_kparams *kp);

/* select.c: whether the AVX2 TIP4P rows take the image list of a small box (the box, the
 * modes and the rows in use); if so, 1 with images[k] = 1 for the species whose rows do. */
int rl_ff_image_rows(const rl_forcefield *ff, unsigned char *images);

#endif
