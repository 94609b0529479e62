/* The kernels' pair list: rows of molecule pairs by rank (the bodies in cell order), split into
 * kernel and reference neighbours, and the image list of a small box. */
#include "fast.h"
#include "kernels/batch.h"
#include "rotleap/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

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

/* The cost of row m (species k) in units of about one pair term: kernel terms per listed
 * pair, 16 per reference pair, and for the row itself (its setup, the last partial vector, the
 * lane sums) 60 for a dipole row and 110 for a site row: the later ranks list fewer neighbours
 * of higher rank, and without that term the thread with the later rows took 8 % longer (8,000
 * dipoles).  For the TIP4P rows on AVX2 a fit of cycles per row against its length gave about
 * 500 + 55 fl cycles, so a row costs as much as 9 of its pairs (12 units each); the all-pairs
 * list of a small box (256 TIP4P) has rows of 0 to 200 pairs, and thread 1 took twice as many.
 * The other site rows take the same 110 unmeasured (about 10 CO2 pairs, 37 charge-LJ pairs). */
static double row_cost(const rl_ff_fast *f, int k, int m)
{
  const fast_species *K = &f->sk[k];
  const int fl = f->fstart[m + 1] - f->fstart[m], gl = f->gstart[m + 1] - f->gstart[m];
  return K->kind == K_DIPOLE ? 4.0 * fl + (fl > 0 ? 60.0 : 0.0) + 16.0 * gl
                             : (double)fl * (K->nterms + 2) + (fl > 0 ? 110.0 : 0.0) + 16.0 * gl;
}

/* Whether the AVX2 TIP4P rows take the image list: some TIP4P species separates its sites by
 * shifting the centres' separation (P_SHIFT) in a box that needs other images (needs_images),
 * the modes rl_ff_fast_compute gives it. */
static int images_wanted(const rl_forcefield *ff)
{
  const rl_ff_fast *f = ff->fast;
  if ((f->vec != VEC_256 && !f->tmix) || ff->p.scheme == RL_CUTOFF_MOLECULE) return 0;
  rl_kparams kp;
  rl_ff_kparams(ff, &kp);
  const box_consts B = kp.B;
  for (int k = 0; k < ff->nspecies; k++) {
    const fast_species *K = &f->sk[k];
    if (K->kind != K_TIP4P || ff->sp_count[k] == 0) continue;
    const double rp = ff->p.cutoff + 2.0 * K->extent;
    int shift = 1;
    for (int c = 0; c < 3; c++) shift &= ff->box.L[c] > rp && ff->box.L[c] >= 2.0 * ff->p.cutoff;
    if (shift && needs_images(P_SHIFT, &B, prune2(P_SHIFT, &B, K))) return 1;
  }
  return 0;
}

/* The image list of a small box, for the TIP4P rows on AVX2 (issue 8).  In a box with an edge
 * shorter than twice the pruning radius a neighbour can be in range through more than one
 * image of its centre, and fill256 looks for those images every step (for 256 TIP4P at
 * rc = 0.9 nm a third of the candidates have a far component), with branches and scalar
 * appends that took a good part of the row (`ffbench time tip4p 256 1 1000 --h 0.006`: the
 * step 0.83-0.87 of the time before, medians of alternating runs, builds included).  Here,
 * once per build, each image of a listed neighbour within rlist (at the build's centres)
 * becomes an entry of its own with its shift s, a multiple of the edges, so that the fill forms
 * c_i - c_j + s, tests it and packs it (fill256x).  That is exact between builds: the centres
 * are continuous (never wrapped), and as each moves less than half the skin, every image within
 * the pruning radius at a step was within rlist at the build.  Each site pair inside the cutoff
 * is still met once (L >= 2 rc).  A row lists its neighbours' minimum images in list order,
 * four at a time, then the other images of those that have any.  Kernel rows of other kinds
 * get empty rows.  Returns 0, or 1 when out of memory. */
#if RL_X512
/* One neighbour whose minimum image has another image within rlist (build_images): its shifts and
 * squared separations per component (0: the minimum image's, 1: the other's), and as bits the
 * components whose switch alone stays inside rlist. */
typedef struct far_image {
  int j, one;
  double s[2][3], x2[2][3];
} far_image;

/* Room in the image list for `more` entries past q (and the 4 slots of slack): grow it, keeping
 * the q entries written.  Returns 0, or 1 when out of memory. */
static int images_room(rl_ff_fast *f, long q, long more)
{
  if (q + more <= f->xcap) return 0;
  const long cap = 2 * (q + more), stride = f->xcap + 4;
  int *xn = realloc(f->xnbr, sizeof(int) * (size_t)(cap + 4));
  if (!xn) return 1;
  f->xnbr = xn;
  double *xs = malloc(sizeof(double) * 3 * (size_t)(cap + 4));
  if (!xs) return 1;
  if (f->xsh)
    for (int c = 0; c < 3; c++) memcpy(xs + c * (cap + 4), f->xsh + c * stride, sizeof(double) * (size_t)q);
  free(f->xsh);
  f->xsh = xs;
  f->xcap = cap;
  return 0;
}

RL_T256 static int build_images(rl_forcefield *ff)
{
  rl_ff_fast *f = ff->fast;
  const int n = ff->n;
  const rl_box *box = &ff->box;
  const double rl = ff->rlist, rl2 = rl * rl;
  const double *bx = f->bx, *by = bx + n, *bz = by + n;
  if (!f->xstart && !(f->xstart = malloc(sizeof(int) * ((size_t)n + 1)))) return 1;
  if (!f->xfar && !(f->xfar = malloc(sizeof *f->xfar * ((size_t)n + 4)))) return 1;
  /* room for every listed neighbour's minimum image and a quarter more (grown per row below
   * when short), with a margin so that the next builds' lists fit as well */
  if (images_room(f, 0, f->fstart[n] + f->fstart[n] / 4 + 8)) return 1;
  const __m256d L[3] = {_mm256_set1_pd(box->L[0]), _mm256_set1_pd(box->L[1]), _mm256_set1_pd(box->L[2])};
  const __m256d iL[3] = {_mm256_set1_pd(box->invL[0]), _mm256_set1_pd(box->invL[1]),
                         _mm256_set1_pd(box->invL[2])};
  const __m256d big = _mm256_set1_pd(6755399441055744.0), vrl2 = _mm256_set1_pd(rl2);
  const __m256d zero = _mm256_setzero_pd();
  const double *P[3] = {bx, by, bz};
  const int *fnbr = f->fnbr;
  far_image *xfar = f->xfar;
  long stride = f->xcap + 4, q = 0;
  int *xn = f->xnbr;
  double *xs = f->xsh;
  for (int m = 0; m < n; m++) {
    f->xstart[m] = (int)q;
    if (f->sk[f->V.sp[m]].kind != K_TIP4P) continue;
    const int lo = f->fstart[m], hi = f->fstart[m + 1];
    int nfar = 0;
    if (images_room(f, q, hi - lo)) return 1; /* the row's minimum images (4 at a time) */
    stride = f->xcap + 4;
    xn = f->xnbr;
    xs = f->xsh;
    /* the minimum images, four neighbours at a time (RL_RND as in the build's scan) */
    for (int p = lo; p < hi; p += 4) {
      const int cnt = hi - p < 4 ? hi - p : 4;
      _Alignas(16) int id[4];
      __m128i vi;
      if (cnt == 4) { /* one load: four int stores read back as one vector would not forward */
        vi = _mm_loadu_si128((const __m128i *)(fnbr + p));
        _mm_store_si128((__m128i *)id, vi);
      } else {
        for (int l = 0; l < 4; l++) id[l] = fnbr[p + (l < cnt ? l : 0)];
        vi = _mm_load_si128((const __m128i *)id);
      }
      __m256d s0[3], s1[3], q0[3], q1[3];
      for (int c = 0; c < 3; c++) {
        const double *Pc = P[c];
        const __m256d d = _mm256_sub_pd(_mm256_set1_pd(Pc[m]),
                                        _mm256_set_pd(Pc[id[3]], Pc[id[2]], Pc[id[1]], Pc[id[0]]));
        const __m256d k = _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(d, iL[c]), big), big);
        s0[c] = _mm256_sub_pd(zero, _mm256_mul_pd(L[c], k));
        const __m256d x0 = _mm256_add_pd(d, s0[c]);
        const __m256d t = _mm256_blendv_pd(L[c], _mm256_sub_pd(zero, L[c]), _mm256_cmp_pd(x0, zero, _CMP_GT_OQ));
        const __m256d x1 = _mm256_add_pd(x0, t);
        s1[c] = _mm256_add_pd(s0[c], t);
        q0[c] = _mm256_mul_pd(x0, x0);
        q1[c] = _mm256_mul_pd(x1, x1);
      }
      _mm_storeu_si128((__m128i *)(xn + q), vi);
      for (int c = 0; c < 3; c++) _mm256_storeu_pd(xs + c * stride + q, s0[c]);
      q += cnt;
      /* an image is inside rlist only if each of its components alone, switched, is (the other
       * image is the farther one): bit c of `one` for lane l; about one neighbour in ten has one
       * for 256 TIP4P at 0.9 nm */
      const __m256d sum = _mm256_add_pd(_mm256_add_pd(q0[0], q0[1]), q0[2]);
      unsigned one[3], any = 0;
      for (int c = 0; c < 3; c++) {
        const __m256d sw = _mm256_add_pd(_mm256_sub_pd(sum, q0[c]), q1[c]);
        one[c] = (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(sw, vrl2, _CMP_LT_OQ)) & ((1u << cnt) - 1u);
        any |= one[c];
      }
      if (!any) continue;
      _Alignas(32) double v[4][3][4]; /* s0, s1, q0, q1 by [component][lane] */
      for (int c = 0; c < 3; c++) {
        _mm256_store_pd(v[0][c], s0[c]);
        _mm256_store_pd(v[1][c], s1[c]);
        _mm256_store_pd(v[2][c], q0[c]);
        _mm256_store_pd(v[3][c], q1[c]);
      }
      for (; any; any &= any - 1) {
        const int l = __builtin_ctz(any);
        far_image *F = &xfar[nfar++];
        F->j = id[l];
        F->one = (int)((one[0] >> l & 1u) | (one[1] >> l & 1u) << 1 | (one[2] >> l & 1u) << 2);
        for (int c = 0; c < 3; c++) {
          F->s[0][c] = v[0][c][l];
          F->s[1][c] = v[1][c][l];
          F->x2[0][c] = v[2][c][l];
          F->x2[1][c] = v[3][c][l];
        }
      }
    }
    /* then the other images of the neighbours that have them: image im takes the other image
     * of component c where bit c is set */
    for (int e = 0; e < nfar; e++) {
      const far_image *F = &xfar[e];
      if (images_room(f, q, 7)) return 1; /* its other images */
      stride = f->xcap + 4;
      xn = f->xnbr;
      xs = f->xsh;
      for (int im = 1; im < 8; im++) {
        const int a = im & 1, g = (im >> 1) & 1, h = im >> 2;
        if ((im & F->one) != im || !(F->x2[a][0] + F->x2[g][1] + F->x2[h][2] < rl2)) continue;
        xn[q] = F->j;
        xs[q] = F->s[a][0];
        xs[stride + q] = F->s[g][1];
        xs[2 * stride + q] = F->s[h][2];
        q++;
      }
    }
  }
  f->xstart[n] = (int)q;
  for (int c = 0; c < 3; c++) /* fill256x's last vector reads up to 3 slots past the last row */
    for (long r = q; r < q + 4; r++) xs[c * stride + r] = 0.0;
  f->V.xstart = f->xstart;
  f->V.xnbr = f->xnbr;
  for (int c = 0; c < 3; c++) f->V.xs[c] = f->xsh + c * stride;
  return 0;
}
#else
static int build_images(rl_forcefield *ff) /* images_wanted is 0 without the AVX2 rows */
{
  (void)ff;
  return 1;
}
#endif

int rl_ff_fast_build(rl_forcefield *ff)
{
  rl_ff_fast *f = ff->fast;
  const int n = ff->n, T = f->nthreads;
  const rl_box *box = &ff->box;
  const double rl = ff->rlist, rl2 = rl * rl;
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
      f->cell_of[i] = rl_box_cell_index(box, ff->centre[i], nc);
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
    f->V.soff[m] = o;
    f->V.sp[m] = ff->body_species[i];
    o += ff->sp_nsites[f->V.sp[m]];
    for (int c = 0; c < 3; c++) /* the scan reads these */
      f->bx[(size_t)c * (size_t)n + (size_t)m] = ff->centre[i][c];
  }
  /* one species with a kernel and sites (a neat liquid): every candidate is a kernel pair */
  int live_species = 0, neat = 1;
  for (int k = 0; k < ff->nspecies; k++)
    if (ff->sp_count[k] > 0) {
      live_species++;
      neat &= f->sk[k].kind != K_NONE && ff->sp_nsites[k] > 0;
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
      chunk_rows *tr = &f->tr[ch];
      tr->fn = tr->gn = 0;
      int m0 = (int)((long)n * ch / C), m1 = (int)((long)n * (ch + 1) / C);
      for (int mi = m0; mi < m1 && !fail; mi++) {
        const int i = f->ord[mi];
        int ki = ff->body_species[i];
        int fast_i = f->sk[ki].kind != K_NONE;
        long f0 = tr->fn, g0 = tr->gn;
        const double ri[3] = {bx[mi], by[mi], bz[mi]};
        if (ff->sp_nsites[ki] > 0) {
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
          if (f->vec == VEC_512)
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
            const int m = cand[q], kj = f->V.sp[m];
            if (ff->sp_nsites[kj] == 0) continue;
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
  /* compute ranges: equal shares of cost (row_cost) */
  double total = 0.0;
  for (int i = 0; i < n; i++) total += row_cost(f, ff->body_species[f->ord[i]], i);
  double run = 0.0;
  int t = 1;
  f->tlo[0] = 0;
  for (int i = 0; i < n && t < T; i++) {
    run += row_cost(f, ff->body_species[f->ord[i]], i);
    while (t < T && run >= total * t / T) f->tlo[t++] = i + 1;
  }
  while (t <= T) f->tlo[t++] = n;
  /* the ranks each thread's rows write: its own, and their neighbours (of higher rank), so that
   * it zeroes and the sums read only those (at 64,000 dipoles on two threads each thread's
   * buffer was 4 MB, of which the other half stayed zero) */
  for (int u = 0; u < T; u++) {
    int hi = f->tlo[u + 1];
    for (int m = f->tlo[u]; m < f->tlo[u + 1]; m++) hi = f->rmax[m] + 1 > hi ? f->rmax[m] + 1 : hi;
    f->thi[u] = hi;
  }
  /* positions at this build, for the rebuild test */
  rl_nlist *chk = f->chk;
  if (chk->n != n || !chk->r0) {
    double(*r0)[3] = realloc(chk->r0, sizeof *r0 * (size_t)(n > 0 ? n : 1));
    if (!r0) return rl_error(RL_ENOMEM, "neighbour list: out of memory for %d bodies", n);
    chk->r0 = r0;
  }
  if (n > 0) memcpy(chk->r0, ff->centre, sizeof *chk->r0 * (size_t)n);
  f->V.xstart = NULL; /* until build_images succeeds */
  if (images_wanted(ff) && build_images(ff))
    return rl_error(RL_ENOMEM, "neighbour list: out of memory for the images of a small box");
  chk->n = n;
  chk->rlist = rl;
  chk->npairs = nf + ng;
  chk->builds++;
  return RL_OK;
}
