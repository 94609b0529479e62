/* The force field object shared by the reference pair loop (forcefield.c) and the specialised,
 * threaded kernels (select.c, driver.c).  Internal. */
#ifndef ROTLEAP_PAIR_FORCEFIELD_IMPL_H
#define ROTLEAP_PAIR_FORCEFIELD_IMPL_H

#include "rotleap/forcefield.h"

#include "../../core/box.h"
#include "pairlist.h"
#include "coulomb_rf.h"
#include "lj.h"
#include "kernels/kernel.h"

typedef struct rl_ff_fast rl_ff_fast; /* fast.h */

struct rl_forcefield {
  rl_ff_params p;          /* as given, but p.box 0: the box is the system's               */
  rl_box box;              /* the system's cell at box_version                             */
  unsigned long box_version; /* rl_system_box_version when box was taken                   */
  double kc;               /* Coulomb constant of the unit system                          */
  int n, nspecies, nsites; /* system sizes at alloc                                        */
  int ntypes;              /* one type per (species, site)                                */
  int *type_off;           /* [nspecies] first type of each species                        */
  int *sp_nsites;          /* [nspecies]                                                   */
  int *sp_count;           /* [nspecies] bodies                                            */
  double *sp_extent;       /* [nspecies] max |site - centre| (0 for a species without bodies) */
  double *sig, *eps, *q, *mu, *Q; /* [ntypes]                                             */
  int *type_species, *type_site;  /* [ntypes]                                              */
  rl_lj_coef *lj;          /* [ntypes * ntypes]                                            */
  rl_rf_coef rf;
  int any_dipole, any_quad;
  double extent;           /* max |site - centre| over species (for the site scheme's list) */
  double rlist, skin, min_distance;
  double disp_e, disp_w;   /* sum over type pairs of npairs * tail integrals                */
  /* per-body / per-site workspace */
  int *body_species;       /* [n]                                                          */
  int *body_site_off;      /* [n]                                                          */
  int *body_rot;           /* [n] rot index or -1                                          */
  int *site_type;          /* [nsites]                                                     */
  double (*centre)[3];     /* [n]                                                          */
  double (*axis)[3];       /* [n] body Z in the lab                                        */
  double (*site)[3];       /* [nsites] lab positions                                       */
  double (*dsite)[3];      /* [nsites] site - centre (lab)                                 */
  double (*fs)[3];         /* [nsites] site forces                                         */
  double (*tq)[3];         /* [n] direct (dipole/quadrupole) torques                       */
  rl_nlist *nl;
  double (*origin)[3];     /* [n] set_list_origin: the centres the next list build uses (NULL:
                              the current ones)                                             */
  double origin_L[3];      /* set_list_box: the box that build takes (0: the current one)   */
  rl_ff_fast *fast;        /* NULL: the reference path (kernel = general or no list)       */
  rl_ff_energies e;
  /* for rl_forcefield_warnings and rl_forcefield_discontinuities */
  rl_units units;
  char (*sp_name)[32];     /* [nspecies] species names (truncated)                         */
  double (*tsite)[3];      /* [ntypes] site positions in a frame whose Z is the body axis (the
                              species' first body at alloc; 0 for a species without bodies) */
  int last_pairs;          /* -1 before the first compute; else 1 if some site pair
                              interacted at the last compute, 0 if none did                 */
};

/* Accumulators of one pair loop (one per thread in the threaded driver). */
typedef struct {
  rl_ksums s;              /* energies by term, virial, and `bad` (an overlap, with quiet)   */
  double (*fs)[3];         /* [nsites] site forces to add to                               */
  double (*tq)[3];         /* [n] direct torques to add to                                 */
  int site_virial;         /* 0: vir += R (x) f (molecular, the reference); 1: vir += r (x) f
                              with r the site separation (the driver subtracts sum d (x) F) */
  int quiet;               /* 1: an overlap sets `bad` instead of calling rl_error            */
  int forces_only;         /* 1: energies and virial are not needed (kernels may skip them)  */
} rl_acc;

/* Take the system's current cell (its version too) and check the cutoff against it.  The pair
 * lists stay: their rule (pairlist.h) measures the displacements from the origins scaled with
 * the box, and builds again when the change used up the skin (an image list: at any change).
 * rl_forcefield_compute calls it when the version changed; the pair term (term_pair.c) when the
 * terms are told of a change.  On an error the box stays as it was. */
int rl_ff_take_box(rl_forcefield *ff, const rl_system *sys);

/* The reference all-site-pairs routine for bodies i, j (forcefield.c). */
int rl_ff_body_pair(rl_forcefield *ff, int i, int j, rl_acc *acc);

/* driver.c: choose kernels from the species' site patterns (at alloc and after an LJ
 * override; select.c).  Sets ff->fast (or leaves it NULL).  Returns RL_OK or RL_ENOMEM. */
int rl_ff_fast_setup(rl_forcefield *ff);
void rl_ff_fast_free(rl_ff_fast *fast);
/* The threaded pair loop: fills ff->fs, ff->tq (zeroed by the caller) and acc (molecular
 * virial).  Returns RL_OK, 1 if the reference loop must be rerun to report an overlap (nothing
 * is reported), or an error status. */
int rl_ff_fast_compute(rl_forcefield *ff, rl_acc *acc);
/* Kernel names for the benchmarks and tests (forcefield.h: rl_forcefield_kernel_name). */
const char *rl_ff_fast_name(const rl_ff_fast *fast);
/* The kernel of species k's pairs with itself ("tip4p", "charge-lj", "stockmayer"), or NULL: the
 * reference routine (rl_forcefield_pair_kernel). */
const char *rl_ff_fast_species(const rl_ff_fast *fast, int k);
const char *rl_ff_fast_rows(const rl_ff_fast *fast); /* "avx512", "avx2" or "portable" (+ mixed) */
int rl_ff_fast_mixed(const rl_ff_fast *fast);         /* 1: the tip4p rows in single precision */
int rl_ff_fast_threads(const rl_ff_fast *fast);
long rl_ff_fast_builds(const rl_ff_fast *fast); /* 0 for NULL */
/* The build state of the kernels' list (its centres and box at the last build; NULL for a NULL
 * fast). */
const rl_nlist *rl_ff_fast_list(const rl_ff_fast *fast);
/* The box a build from ff->origin takes: ff->origin_L if set, else the current one. */
int rl_ff_origin_box(const rl_forcefield *ff, rl_box *box);

#endif
