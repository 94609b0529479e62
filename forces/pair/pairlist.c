/* The pair list (pairlist.h): the rule for a rebuild, and the reference layout (pairs i < j in
 * body order from cells of edge >= rlist). */
#include "pairlist.h"
#include "../../core/threads.h"
#include "rotleap/error.h"

#include <stdlib.h>
#include <string.h>

rl_nlist *rl_nlist_alloc(double skin)
{
  rl_nlist *nl = calloc(1, sizeof *nl);
  if (!nl) { rl_error(RL_ENOMEM, "rl_nlist_alloc: out of memory"); return NULL; }
  nl->n = -1;
  nl->skin = skin > 0.0 ? skin : 0.0;
  return nl;
}

void rl_nlist_free(rl_nlist *nl)
{
  if (!nl) return;
  free(nl->r0);
  free(nl->pairs);
  free(nl->head);
  free(nl->next);
  free(nl);
}

static double disp2(const rl_box *box, const double a[3], const double b[3])
{
  double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  rl_box_minimum_image(box, d);
  return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

int rl_nlist_box_changed(const rl_nlist *nl, const rl_box *box)
{
  return nl->n >= 0 && (box->L[0] != nl->L0[0] || box->L[1] != nl->L0[1] || box->L[2] != nl->L0[2]);
}

int rl_nlist_needs_rebuild(const rl_nlist *nl, const rl_box *box, int n, const double (*r)[3],
                           double *maxdisp, int threads)
{
  if (maxdisp) *maxdisp = INFINITY;
  if (nl->n < 0 || nl->n != n) return 1;
  /* the origins scaled with the box since the build (s = 1 exactly for an unchanged box) */
  const double s[3] = {box->L[0] / nl->L0[0], box->L[1] / nl->L0[1], box->L[2] / nl->L0[2]};
  const double shrink = fmax(0.0, 1.0 - fmin(s[0], fmin(s[1], s[2]))) * nl->rlist;
  double m2 = 0.0;
  (void)threads;
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(static) \
    if (threads > 1 && n >= RL_THREAD_MIN_BODIES) reduction(max : m2)
#endif
  for (int i = 0; i < n; i++) {
    const double o[3] = {s[0] * nl->r0[i][0], s[1] * nl->r0[i][1], s[2] * nl->r0[i][2]};
    m2 = fmax(m2, disp2(box, r[i], o));
  }
  double m = sqrt(m2);
  if (maxdisp) *maxdisp = m;
  return !(2.0 * m + shrink <= nl->skin) || (nl->skin == 0.0 && (m > 0.0 || rl_nlist_box_changed(nl, box)));
}

static int push_pair(rl_nlist *nl, int i, int j)
{
  if (nl->npairs == nl->cap) {
    long cap = nl->cap ? 2 * nl->cap : 1024;
    int (*p)[2] = realloc(nl->pairs, sizeof *p * (size_t)cap);
    if (!p) return rl_error(RL_ENOMEM, "neighbour list: out of memory for %ld pairs", cap);
    nl->pairs = p;
    nl->cap = cap;
  }
  nl->pairs[nl->npairs][0] = i < j ? i : j;
  nl->pairs[nl->npairs][1] = i < j ? j : i;
  nl->npairs++;
  return RL_OK;
}

int rl_nlist_build(rl_nlist *nl, const rl_box *box, double rlist, int n, const double (*r)[3])
{
  if (n != nl->n || !nl->r0) {
    double(*r0)[3] = realloc(nl->r0, sizeof *r0 * (size_t)(n > 0 ? n : 1));
    if (!r0) return rl_error(RL_ENOMEM, "neighbour list: out of memory for %d bodies", n);
    nl->r0 = r0;
  }
  nl->npairs = 0;
  nl->rlist = rlist;
  double rl2 = rlist * rlist;
  int nc[3];
  for (int c = 0; c < 3; c++) {
    double q = floor(box->L[c] / rlist);
    nc[c] = q > 1000.0 ? 1000 : (int)q;
  }
  int use_cells = nc[0] >= 3 && nc[1] >= 3 && nc[2] >= 3;
  nl->used_cells = use_cells;
  if (!use_cells) {
    for (int i = 0; i < n; i++)
      for (int j = i + 1; j < n; j++)
        if (disp2(box, r[i], r[j]) < rl2) {
          int st = push_pair(nl, i, j);
          if (st) return st;
        }
  } else {
    int ncell = nc[0] * nc[1] * nc[2];
    { /* workspace sized for this build */
      int *h = realloc(nl->head, sizeof *h * (size_t)ncell);
      if (h) nl->head = h;
      int *nx = realloc(nl->next, sizeof *nx * (size_t)(n > 0 ? n : 1));
      if (nx) nl->next = nx;
      if (!h || !nx) return rl_error(RL_ENOMEM, "neighbour list: out of memory for %d cells", ncell);
      if (ncell > nl->ncell_cap) nl->ncell_cap = ncell;
    }
    for (int c = 0; c < ncell; c++) nl->head[c] = -1;
    int *cell_of = NULL;
    cell_of = malloc(sizeof *cell_of * (size_t)(n > 0 ? n : 1));
    if (!cell_of) return rl_error(RL_ENOMEM, "neighbour list: out of memory");
    for (int i = 0; i < n; i++) {
      int id = rl_box_cell_index(box, r[i], nc);
      cell_of[i] = id;
      nl->next[i] = nl->head[id];
      nl->head[id] = i;
    }
    for (int i = 0; i < n; i++) {
      int id = cell_of[i];
      int cx = id % nc[0], cy = (id / nc[0]) % nc[1], cz = id / (nc[0] * nc[1]);
      for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
          for (int dx = -1; dx <= 1; dx++) {
            int x = (cx + dx + nc[0]) % nc[0], y = (cy + dy + nc[1]) % nc[1],
                z = (cz + dz + nc[2]) % nc[2];
            for (int j = nl->head[(z * nc[1] + y) * nc[0] + x]; j >= 0; j = nl->next[j])
              if (j > i && disp2(box, r[i], r[j]) < rl2) {
                int st = push_pair(nl, i, j);
                if (st) { free(cell_of); return st; }
              }
          }
    }
    free(cell_of);
  }
  if (n > 0) memcpy(nl->r0, r, sizeof *nl->r0 * (size_t)n);
  memcpy(nl->L0, box->L, sizeof nl->L0);
  nl->n = n;
  nl->builds++;
  return RL_OK;
}
