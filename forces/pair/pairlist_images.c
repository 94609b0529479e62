/* The kernels' pair list (pairlist.h): the image list of a small box, for the AVX2 TIP4P rows. */
#include "pairlist_rows.h"
#include "rotleap/error.h"

#include <stdlib.h>
#include <string.h>

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
static int images_room(rl_rowlist *f, long q, long more)
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

RL_T256 int rl_rowlist_images(rl_rowlist *f, const rl_rowlist_in *in)
{
  const int n = in->n;
  const rl_box *box = in->box;
  const double rl = in->rlist, rl2 = rl * rl;
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
    if (!in->images[f->sp[m]]) continue;
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
  for (int c = 0; c < 3; c++) f->xs[c] = f->xsh + c * stride;
  f->ximages = 1;
  return 0;
}
#else
int rl_rowlist_images(rl_rowlist *f, const rl_rowlist_in *in) /* no image list without the AVX2 rows */
{
  (void)f;
  (void)in;
  return 1;
}
#endif

