/* The kernels' pair list (pairlist.h): rows of molecule pairs by rank (the bodies in cell
 * order), split into kernel and reference neighbours. */
#include "pairlist_rows.h"
#include "rotleap/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#else
static inline int omp_get_thread_num(void) { return 0; }
#endif

void rl_rowlist_free(rl_rowlist *f)
{
  if (!f) return;
  rl_nlist_free(f->chk);
  free(f->ord); free(f->soff); free(f->sp);
  free(f->fstart); free(f->gstart); free(f->fnbr); free(f->gnbr); free(f->rmax);
  free(f->xstart); free(f->xnbr); free(f->xsh); free(f->xfar);
  if (f->tr)
    for (int c = 0; c < f->nchunk; c++) { free(f->tr[c].f); free(f->tr[c].g); }
  free(f->tr);
  if (f->cand)
    for (int t = 0; t < f->nthreads; t++) free(f->cand[t]);
  free(f->cand);
  free(f->cell_of); free(f->cell_start); free(f->cell_body); free(f->bx);
  free(f);
}

rl_rowlist *rl_rowlist_alloc(int n, int threads, double skin)
{
  rl_rowlist *f = calloc(1, sizeof *f);
  if (!f) { rl_error(RL_ENOMEM, "neighbour list: out of memory"); return NULL; }
  const int T = threads > 0 ? threads : 1;
  const size_t n1 = (size_t)(n > 0 ? n : 1);
  f->nthreads = T;
  f->chk = rl_nlist_alloc(skin);
  f->fstart = calloc(n1 + 1, sizeof(int));
  f->gstart = calloc(n1 + 1, sizeof(int));
  f->rmax = malloc(sizeof(int) * n1);
  f->nchunk = T > 1 ? 16 * T : 1;
  f->tr = calloc((size_t)f->nchunk, sizeof *f->tr);
  f->cand = calloc((size_t)T, sizeof *f->cand);
  f->cell_of = malloc(sizeof(int) * n1);
  f->cell_body = malloc(sizeof(int) * n1);
  f->ord = malloc(sizeof(int) * n1);
  f->soff = malloc(sizeof(int) * n1);
  f->sp = malloc(sizeof(int) * n1);
  f->bx = malloc(sizeof *f->bx * 3 * n1);
  int bad = !f->chk || !f->fstart || !f->gstart || !f->rmax || !f->tr || !f->cand ||
            !f->cell_of || !f->cell_body || !f->ord || !f->soff || !f->sp || !f->bx;
  for (int t = 0; t < T && !bad; t++) /* scan512 stores 16 at a time */
    bad = !(f->cand[t] = malloc(sizeof(int) * (n1 + 16)));
  if (bad) {
    rl_rowlist_free(f);
    rl_error(RL_ENOMEM, "neighbour list: out of memory for the kernels' list");
    return NULL;
  }
  return f;
}

static int push(int **a, long *cap, long *len, int v)
{
  if (*len == *cap) {
    long nc = *cap ? 2 * *cap : 4096;
    int *p = realloc(*a, sizeof *p * (size_t)nc);
    if (!p) return 1;
    *a = p;
    *cap = nc;
  }
  (*a)[(*len)++] = v;
  return 0;
}

#if RL_X512
/* The list build's candidates on AVX-512: of the ranks in the runs [lo[r], hi[r]), those whose
 * centre (X, Y, Z by rank) lies within rlist of ri, in rank order, eight at a time, packed
 * with vpcompressd (the scalar loop was 11 % of a 64,000-dipole step in perf, issue 8).  The
 * separation, its image and r^2 take the scalar loop's operations in its order, each rounded
 * once (the _round_ forms are not fused into FMAs under -ffp-contract=fast), so both keep the
 * same pairs to the last bit.  Stores 16 indices at a time: cand needs 16 slots of slack. */
RL_T512 static int scan512(const double *X, const double *Y, const double *Z, const double ri[3],
                           const rl_box *box, double rl2, const int *lo, const int *hi, int nr,
                           int *cand)
{
#define RL_CUR _MM_FROUND_CUR_DIRECTION
  const __m512d c[3] = {_mm512_set1_pd(ri[0]), _mm512_set1_pd(ri[1]), _mm512_set1_pd(ri[2])};
  const __m512d L[3] = {_mm512_set1_pd(box->L[0]), _mm512_set1_pd(box->L[1]),
                        _mm512_set1_pd(box->L[2])};
  const __m512d iL[3] = {_mm512_set1_pd(box->invL[0]), _mm512_set1_pd(box->invL[1]),
                         _mm512_set1_pd(box->invL[2])};
  const __m512d big = _mm512_set1_pd(6755399441055744.0), R2 = _mm512_set1_pd(rl2);
  const __m512i iota = _mm512_set_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0);
  const double *P[3] = {X, Y, Z};
  int nin = 0;
  for (int r = 0; r < nr; r++)
    for (int m = lo[r]; m < hi[r]; m += 8) {
      const int left = hi[r] - m;
      const __mmask8 live = left >= 8 ? (__mmask8)0xFF : (__mmask8)((1u << left) - 1u);
      __m512d d2 = _mm512_setzero_pd();
      for (int k = 0; k < 3; k++) { /* d -= L RL_RND(d / L); d2 = (dx^2 + dy^2) + dz^2 */
        __m512d d = _mm512_sub_round_pd(c[k], _mm512_maskz_loadu_pd(live, P[k] + m), RL_CUR);
        __m512d q = _mm512_add_round_pd(_mm512_mul_round_pd(d, iL[k], RL_CUR), big, RL_CUR);
        q = _mm512_sub_round_pd(q, big, RL_CUR);
        d = _mm512_sub_round_pd(d, _mm512_mul_round_pd(L[k], q, RL_CUR), RL_CUR);
        const __m512d dd = _mm512_mul_round_pd(d, d, RL_CUR);
        d2 = k ? _mm512_add_round_pd(d2, dd, RL_CUR) : dd;
      }
      const __mmask8 keep = _mm512_mask_cmp_pd_mask(live, d2, R2, _CMP_LT_OQ);
      const __m512i id = _mm512_add_epi32(_mm512_set1_epi32(m), iota);
      _mm512_storeu_si512(cand + nin, _mm512_maskz_compress_epi32((__mmask16)keep, id));
      nin += __builtin_popcount(keep);
    }
#undef RL_CUR
  return nin;
}
#endif

int rl_rowlist_build(rl_rowlist *f, const rl_rowlist_in *in)
{
  const int n = in->n, T = f->nthreads;
  (void)T; /* a build without OpenMP */
  const rl_box *box = in->box;
  const double rl = in->rlist, rl2 = rl * rl;
  /* Cells of edge >= rlist / 2, searched +-2 cells (the 5^3 stencil spans 15.6 rlist^3 of
   * candidates, against 27 rlist^3 for cells >= rlist searched +-1), when every edge holds at
   * least 5; else all pairs, through the same branch-free scan (a branch per pair made the
   * builds 5 % of a 256-TIP4P step at 6 fs, rebuilt every 6 steps).  With cells >= rlist a
   * box of a few list radii had 3 per edge and every body was a candidate of every other:
   * builds took ~3 steps' time for 2,048 TIP4P. */
  enum { reach = 2 }; /* a constant: sizes the runs arrays below */
  int nc[3];
  for (int c = 0; c < 3; c++) nc[c] = (int)fmin(256.0, floor(box->L[c] / (0.5 * rl)));
  const int cells = nc[0] >= 2 * reach + 1 && nc[1] >= 2 * reach + 1 && nc[2] >= 2 * reach + 1;
  const int ncell = cells ? nc[0] * nc[1] * nc[2] : 1;
  if (cells) {
    if (ncell + 1 > f->ncell_cap) {
      int *cs = realloc(f->cell_start, sizeof *cs * (size_t)(ncell + 1));
      if (!cs) return rl_error(RL_ENOMEM, "neighbour list: out of memory for %d cells", ncell);
      f->cell_start = cs;
      f->ncell_cap = ncell + 1;
    }
    memset(f->cell_start, 0, sizeof(int) * (size_t)(ncell + 1));
    for (int i = 0; i < n; i++) {
      f->cell_of[i] = rl_box_cell_index(box, in->centre[i], nc);
      f->cell_start[f->cell_of[i] + 1]++;
    }
    for (int c = 0; c < ncell; c++) f->cell_start[c + 1] += f->cell_start[c];
    for (int i = 0; i < n; i++) f->cell_body[f->cell_start[f->cell_of[i]]++] = i; /* ascending */
    for (int c = ncell; c > 0; c--) f->cell_start[c] = f->cell_start[c - 1];
    f->cell_start[0] = 0;
  }
  /* the spatial order (cell_body lists the bodies cell by cell), and each rank's species,
   * first site in the kernels' copies and centre */
  for (int m = 0; m < n; m++) f->ord[m] = cells ? f->cell_body[m] : m;
  for (int m = 0, o = 0; m < n; m++) {
    const int i = f->ord[m];
    f->soff[m] = o;
    f->sp[m] = in->body_species[i];
    o += in->sp_nsites[f->sp[m]];
    for (int c = 0; c < 3; c++) /* the scan reads these */
      f->bx[(size_t)c * (size_t)n + (size_t)m] = in->centre[i][c];
  }
  /* one species with a kernel and sites (a neat liquid): every candidate is a kernel pair */
  int live_species = 0, neat = 1;
  for (int k = 0; k < in->nspecies; k++)
    if (in->sp_count[k] > 0) {
      live_species++;
      neat &= in->kernel[k] && in->sp_nsites[k] > 0;
    }
  neat &= live_species == 1;
  const double *bx = f->bx, *by = bx + n, *bz = bx + 2 * (size_t)n;
  /* rows: chunk c holds ranks m in [n c / C, n (c+1) / C); body i = ord[m] lists the j of
   * higher rank, kernel pairs by rank, reference pairs by body; lengths go to f/gstart[m+1].
   * A chunk's rows do not depend on the thread that takes it. */
  int fail = 0;
  const int C = f->nchunk;
#pragma omp parallel num_threads(T) reduction(| : fail)
  {
    int *cand = f->cand[omp_get_thread_num()];
#pragma omp for schedule(dynamic, 1)
    for (int ch = 0; ch < C; ch++) {
      rl_rowchunk *tr = &f->tr[ch];
      tr->fn = tr->gn = 0;
      int m0 = (int)((long)n * ch / C), m1 = (int)((long)n * (ch + 1) / C);
      for (int mi = m0; mi < m1 && !fail; mi++) {
        const int i = f->ord[mi];
        int ki = in->body_species[i];
        int fast_i = in->kernel[ki];
        long f0 = tr->fn, g0 = tr->gn;
        const double ri[3] = {bx[mi], by[mi], bz[mi]};
        if (in->sp_nsites[ki] > 0) {
          /* the runs of ranks to scan: the cell stencil's, or (all pairs) the ranks above mi */
          int lo[(2 * reach + 1) * (2 * reach + 1) * (2 * reach + 1)], hi[sizeof lo / sizeof *lo];
          int nr = 0, nin = 0;
          if (!cells) {
            lo[0] = mi + 1;
            hi[0] = n;
            nr = hi[0] > lo[0];
          } else {
            int id = f->cell_of[i];
            int cx = id % nc[0], cy = (id / nc[0]) % nc[1], cz = id / (nc[0] * nc[1]);
            int wx[2 * reach + 1], wy[2 * reach + 1], wz[2 * reach + 1]; /* wrapped, no `%` */
            for (int d = -reach; d <= reach; d++) {
              const int x = cx + d, y = cy + d, z = cz + d;
              wx[d + reach] = x < 0 ? x + nc[0] : x >= nc[0] ? x - nc[0] : x;
              wy[d + reach] = y < 0 ? y + nc[1] : y >= nc[1] ? y - nc[1] : y;
              wz[d + reach] = z < 0 ? z + nc[2] : z >= nc[2] ? z - nc[2] : z;
            }
            /* the candidates of higher rank within rlist, branch-free (about a quarter of the
             * stencil's bodies are inside, a branch was mispredicted often); runs of cells
             * along x are contiguous in rank unless the stencil wraps */
            const int runs = cx - reach >= 0 && cx + reach < nc[0] ? 1 : 2 * reach + 1;
            for (int dz = 0; dz <= 2 * reach; dz++)
              for (int dy = 0; dy <= 2 * reach; dy++)
                for (int r = 0; r < runs; r++) {
                  const int row = (wz[dz] * nc[1] + wy[dy]) * nc[0];
                  const int c0 = row + (runs == 1 ? wx[0] : wx[r]);
                  const int c1 = row + (runs == 1 ? wx[2 * reach] : wx[r]);
                  lo[nr] = f->cell_start[c0] > mi + 1 ? f->cell_start[c0] : mi + 1;
                  hi[nr] = f->cell_start[c1 + 1];
                  nr += hi[nr] > lo[nr];
                }
          }
#if RL_X512
          if (in->scan512)
            nin = scan512(bx, by, bz, ri, box, rl2, lo, hi, nr, cand);
          else
#endif
            for (int r = 0; r < nr; r++)
              for (int m = lo[r]; m < hi[r]; m++) {
                double d[3] = {ri[0] - bx[m], ri[1] - by[m], ri[2] - bz[m]};
                for (int c = 0; c < 3; c++) d[c] -= box->L[c] * RL_RND(d[c] * box->invL[c]);
                cand[nin] = m;
                nin += d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < rl2;
              }
          if (neat) { /* all kernel pairs: one copy */
            if (tr->fn + nin > tr->fcap) {
              long nc2 = tr->fcap ? 2 * tr->fcap : 4096;
              while (nc2 < tr->fn + nin) nc2 *= 2;
              int *p = realloc(tr->f, sizeof *p * (size_t)nc2);
              if (!p) { fail = 1; break; }
              tr->f = p;
              tr->fcap = nc2;
            }
            if (nin) /* tr->f is still NULL while no row has had a pair (a dilute gas) */
              memcpy(tr->f + tr->fn, cand, sizeof(int) * (size_t)nin);
            tr->fn += nin;
            nin = 0;
          }
          for (int q = 0; q < nin && !fail; q++) {
            const int m = cand[q], kj = f->sp[m];
            if (in->sp_nsites[kj] == 0) continue;
            if (fast_i && kj == ki)
              fail |= push(&tr->f, &tr->fcap, &tr->fn, m);
            else
              fail |= push(&tr->g, &tr->gcap, &tr->gn, f->ord[m]);
          }
        }
        f->fstart[mi + 1] = (int)(tr->fn - f0);
        f->gstart[mi + 1] = (int)(tr->gn - g0);
        int top = mi;
        for (long q = f0; q < tr->fn; q++) top = tr->f[q] > top ? tr->f[q] : top;
        f->rmax[mi] = top;
      }
    }
  }
  if (fail) return rl_error(RL_ENOMEM, "neighbour list: out of memory");
  f->fstart[0] = f->gstart[0] = 0;
  for (int i = 0; i < n; i++) {
    f->fstart[i + 1] += f->fstart[i];
    f->gstart[i + 1] += f->gstart[i];
  }
  long nf = f->fstart[n], ng = f->gstart[n];
  if (nf > f->fcap) {
    int *p = realloc(f->fnbr, sizeof *p * (size_t)nf);
    if (!p) return rl_error(RL_ENOMEM, "neighbour list: out of memory for %ld pairs", nf);
    f->fnbr = p;
    f->fcap = nf;
  }
  if (ng > f->gcap) {
    int *p = realloc(f->gnbr, sizeof *p * (size_t)ng);
    if (!p) return rl_error(RL_ENOMEM, "neighbour list: out of memory for %ld pairs", ng);
    f->gnbr = p;
    f->gcap = ng;
  }
  for (int c = 0; c < C; c++) {
    int i0 = (int)((long)n * c / C);
    if (f->tr[c].fn) memcpy(f->fnbr + f->fstart[i0], f->tr[c].f, sizeof(int) * (size_t)f->tr[c].fn);
    if (f->tr[c].gn) memcpy(f->gnbr + f->gstart[i0], f->tr[c].g, sizeof(int) * (size_t)f->tr[c].gn);
  }
  /* positions at this build, for the rebuild test */
  rl_nlist *chk = f->chk;
  if (chk->n != n || !chk->r0) {
    double(*r0)[3] = realloc(chk->r0, sizeof *r0 * (size_t)(n > 0 ? n : 1));
    if (!r0) return rl_error(RL_ENOMEM, "neighbour list: out of memory for %d bodies", n);
    chk->r0 = r0;
  }
  if (n > 0) memcpy(chk->r0, in->centre, sizeof *chk->r0 * (size_t)n);
  memcpy(chk->L0, box->L, sizeof chk->L0);
  f->ximages = 0; /* until build_images succeeds */
  if (in->images && rl_rowlist_images(f, in))
    return rl_error(RL_ENOMEM, "neighbour list: out of memory for the images of a small box");
  chk->n = n;
  chk->rlist = rl;
  chk->npairs = nf + ng;
  chk->builds++;
  return RL_OK;
}
