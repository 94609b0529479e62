/* Cell lists and a Verlet list of molecule pairs (internal).
 *
 * The list holds every pair of bodies (i < j) whose minimum-image centre distance was below
 * `rlist` when it was built.  It stays valid while no centre has moved (minimum image) by more
 * than skin/2 since the build: then no pair can have come closer than rlist - skin, so callers
 * choose rlist = (interaction range of the centres) + skin.  Rotation needs no check: with a
 * site cutoff rc the centres' range is rc + 2 extent (extent = the largest |site - centre|), and
 * a rigid body's sites stay within its extent however it turns.
 * Builds use a cell list (cells >= rlist, O(N)) when every box edge holds at least three cells,
 * and an O(N^2) scan of all pairs otherwise. */
#ifndef ROTLEAP_NEIGHBOR_H
#define ROTLEAP_NEIGHBOR_H

#include "../../core/box.h"

typedef struct {
  int n;                /* size at the last build (-1: never built)                   */
  double rlist, skin;
  double (*r0)[3];      /* [n] centres at the last build                             */
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

/* Mark the list stale (e.g. after a box change). */
void rl_nlist_invalidate(rl_nlist *nl);

/* in  box, n, r[n][3] centres; threads: OpenMP threads for the scan (1: serial; the result
 *     does not depend on it)
 * Returns 1 if the list must be rebuilt: never built, size changed, or some centre has moved
 * by more than skin/2 since the build; 0 otherwise.  Also returns the largest displacement in
 * *maxdisp (may be NULL). */
int rl_nlist_needs_rebuild(const rl_nlist *nl, const rl_box *box, int n, const double (*r)[3],
                           double *maxdisp, int threads);

/* Build the list for list radius rlist (> 0).  Returns RL_OK or RL_ENOMEM. */
int rl_nlist_build(rl_nlist *nl, const rl_box *box, double rlist, int n, const double (*r)[3]);

#endif
