/* The threaded driver of the specialised kernels: the workspace, the bodies' copies in rank
 * order, the rows split between threads, each thread's force buffers, and their sums in thread
 * order. */
#include "../../core/threads.h"
#include "fast.h"
#include "rotleap/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#else
static inline int omp_get_thread_num(void) { return 0; }
#endif

void rl_ff_fast_free(rl_ff_fast *f)
{
  if (!f) return;
  free(f->sk);
  free(f->row);
  free(f->kernel);
  free(f->images);
  rl_rowlist_free(f->list);
  free(f->tlo); free(f->thi);
  free(f->fsbuf); free(f->tqbuf);
  free(f->acc);
  free(f->status);
  free(f->mode);
  free(f->V.c); free(f->V.ax); free(f->V.site); free(f->V.dsite);
  free(f->pfs); free(f->ptq);
  free(f->V.pk); free(f->pft); free(f->V.pk4); free(f->pft4); free(f->V.pk4f);
  free(f);
}

/* Zeroed, 64-byte aligned (bytes: a multiple of 64). */
static void *alloc_records(size_t bytes)
{
  void *p = aligned_alloc(64, bytes);
  if (p) memset(p, 0, bytes);
  return p;
}

int rl_ff_fast_setup(rl_forcefield *ff)
{
  long builds = ff->fast ? rl_ff_fast_builds(ff->fast) : 0;
  rl_ff_fast_free(ff->fast);
  ff->fast = NULL;
  if (ff->p.kernel == RL_KERNEL_GENERAL || !ff->p.neighbor_list) return RL_OK;
  rl_ff_fast *f = calloc(1, sizeof *f);
  if (!f) return rl_error(RL_ENOMEM, "forcefield: out of memory");
  const int T = rl_threads_resolve(ff->p.threads);
  f->nthreads = T;
  int n = ff->n;
  const size_t k1 = (size_t)(ff->nspecies > 0 ? ff->nspecies : 1);
  f->sk = calloc(k1, sizeof *f->sk);
  f->row = calloc(k1, sizeof *f->row);
  f->kernel = calloc(k1, 1);
  f->images = calloc(k1, 1);
  f->list = rl_rowlist_alloc(n, T, ff->skin);
  f->tlo = calloc((size_t)T + 1, sizeof(int));
  f->thi = calloc((size_t)T, sizeof(int));
  f->acc = calloc((size_t)T, sizeof *f->acc);
  f->status = calloc((size_t)T, sizeof *f->status);
  f->mode = calloc(k1, sizeof *f->mode);
  const size_t n1 = (size_t)(n > 0 ? n : 1), s1 = (size_t)(ff->nsites > 0 ? ff->nsites : 1);
  f->V.c = malloc(sizeof *f->V.c * n1);
  f->V.ax = malloc(sizeof *f->V.ax * n1);
  f->V.site = malloc(sizeof *f->V.site * s1);
  f->V.dsite = malloc(sizeof *f->V.dsite * s1);
  f->pfs = calloc(s1 * (size_t)T, sizeof *f->pfs); /* zero between computes (see the sums) */
  f->ptq = calloc(n1 * (size_t)T, sizeof *f->ptq);
  if (T > 1) {
    f->fsbuf = malloc(sizeof *f->fsbuf * (size_t)(T - 1) * s1);
    f->tqbuf = malloc(sizeof *f->tqbuf * (size_t)(T - 1) * n1);
  }
  if (!f->sk || !f->row || !f->kernel || !f->images || !f->list || !f->tlo || !f->thi ||
      !f->acc || !f->status || !f->mode || !f->V.c || !f->V.ax || !f->V.site || !f->V.dsite ||
      !f->pfs || !f->ptq || (T > 1 && (!f->fsbuf || !f->tqbuf))) {
    rl_ff_fast_free(f);
    return rl_error(RL_ENOMEM, "forcefield: out of memory for the kernels' workspace");
  }
  f->V.soff = f->list->soff; /* the ranks' first sites and species are the list's */
  f->V.sp = f->list->sp;
  f->list->chk->builds = builds;
  rl_ff_select(ff, f);
  for (int k = 0; k < ff->nspecies; k++) f->kernel[k] = f->sk[k].kind != K_NONE;
  if (f->vec) { /* the register rows' records: 64 bytes (dipoles), 128 (TIP4P) */
    const size_t T1 = (size_t)T;
    if (f->ndip) {
      f->V.pk = alloc_records(sizeof *f->V.pk * n1);
      f->pft = alloc_records(sizeof *f->pft * n1 * T1);
    }
    if (f->ntip4p) {
      if (f->tmix && !(f->V.pk4f = alloc_records(sizeof *f->V.pk4f * n1))) {
        rl_ff_fast_free(f);
        return rl_error(RL_ENOMEM, "forcefield: out of memory for the kernels' workspace");
      }
      f->V.pk4 = alloc_records(sizeof *f->V.pk4 * n1);
      f->pft4 = alloc_records(sizeof *f->pft4 * n1 * T1);
    }
    if ((f->ndip && (!f->V.pk || !f->pft)) || (f->ntip4p && (!f->V.pk4 || !f->pft4))) {
      rl_ff_fast_free(f);
      return rl_error(RL_ENOMEM, "forcefield: out of memory for the kernels' workspace");
    }
  }
  ff->fast = f;
  return RL_OK;
}

int rl_ff_fast_threads(const rl_ff_fast *f) { return f->nthreads; }
long rl_ff_fast_builds(const rl_ff_fast *f) { return f ? f->list->chk->builds : 0; }

const rl_nlist *rl_ff_fast_list(const rl_ff_fast *f) { return f ? f->list->chk : NULL; }

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
  const rl_rowlist *L = f->list;
  const int fl = L->fstart[m + 1] - L->fstart[m], gl = L->gstart[m + 1] - L->gstart[m];
  return K->kind == K_DIPOLE ? 4.0 * fl + (fl > 0 ? 60.0 : 0.0) + 16.0 * gl
                             : (double)fl * (K->nterms + 2) + (fl > 0 ? 110.0 : 0.0) + 16.0 * gl;
}

/* Build the kernels' list from the centres c in box (the current ones, or a restart's origin
 * and the box of its build), and split its rows between the threads. */
static int build(rl_forcefield *ff, const double (*c)[3], const rl_box *box)
{
  rl_ff_fast *f = ff->fast;
  rl_rowlist *L = f->list;
  const int n = ff->n, T = f->nthreads;
  const rl_rowlist_in in = {box, ff->rlist, n, ff->nspecies, c, ff->body_species,
                            ff->sp_count, ff->sp_nsites, f->kernel,
                            rl_ff_image_rows(ff, f->images) ? f->images : NULL, f->vec == VEC_512};
  const int st = rl_rowlist_build(L, &in);
  if (st) return st;
  f->V.xstart = L->ximages ? L->xstart : NULL; /* the image list, if built */
  f->V.xnbr = L->xnbr;
  for (int d = 0; d < 3; d++) f->V.xs[d] = L->xs[d];
  /* compute ranges: equal shares of cost (row_cost) */
  double total = 0.0;
  for (int i = 0; i < n; i++) total += row_cost(f, ff->body_species[L->ord[i]], i);
  double run = 0.0;
  int t = 1;
  f->tlo[0] = 0;
  for (int i = 0; i < n && t < T; i++) {
    run += row_cost(f, ff->body_species[L->ord[i]], i);
    while (t < T && run >= total * t / T) f->tlo[t++] = i + 1;
  }
  while (t <= T) f->tlo[t++] = n;
  /* the ranks each thread's rows write: its own, and their neighbours (of higher rank), so that
   * it zeroes and the sums read only those (at 64,000 dipoles on two threads each thread's
   * buffer was 4 MB, of which the other half stayed zero) */
  for (int u = 0; u < T; u++) {
    int hi = f->tlo[u + 1];
    for (int m = f->tlo[u]; m < f->tlo[u + 1]; m++) hi = L->rmax[m] + 1 > hi ? L->rmax[m] + 1 : hi;
    f->thi[u] = hi;
  }
  return RL_OK;
}

/* ------------------------------------------------------------------------ compute */

int rl_ff_fast_compute(rl_forcefield *ff, rl_acc *out)
{
  rl_ff_fast *f = ff->fast;
  const int n = ff->n, ns = ff->nsites, T = f->nthreads;
  /* the fast minimum image needs |d / L| < 2^51 */
  int far = 0;
#ifdef _OPENMP
#pragma omp parallel for num_threads(T) schedule(static) if (T > 1 && n >= RL_THREAD_MIN_BODIES) \
    reduction(| : far)
#endif
  for (int i = 0; i < n; i++)
    for (int c = 0; c < 3; c++) far |= fabs(ff->centre[i][c]) * ff->box.invL[c] > 1e12;
  if (far) return 1;
  if (ff->origin) { /* a restart: first the list the run had, built from its centres in its box */
    rl_box ob;
    int st = rl_ff_origin_box(ff, &ob);
    if (!st) st = build(ff, (const double(*)[3])ff->origin, &ob);
    free(ff->origin);
    ff->origin = NULL;
    if (st) return st;
  }
  const rl_rowlist *L = f->list;
  /* (an image list's shifts are multiples of the build's edges: any change of the box renews it) */
  if (rl_nlist_needs_rebuild(L->chk, &ff->box, n, (const double(*)[3])ff->centre, NULL, T) ||
      L->chk->rlist != ff->rlist || (L->ximages && rl_nlist_box_changed(L->chk, &ff->box))) {
    int st = build(ff, (const double(*)[3])ff->centre, &ff->box);
    if (st) return st;
  }
  /* each species' separation mode (see P_SHIFT): the molecular shift where the box allows */
  int *mode = f->mode;
  for (int k = 0; k < ff->nspecies; k++) {
    const double rp = ff->p.cutoff + 2.0 * f->sk[k].extent, two_rc = 2.0 * ff->p.cutoff;
    int shift = 1;
    for (int c = 0; c < 3; c++) shift &= ff->box.L[c] > rp && ff->box.L[c] >= two_rc;
    mode[k] = ff->p.scheme == RL_CUTOFF_MOLECULE ? P_MOL : shift ? P_SHIFT : P_SITE;
  }
  kview *V = &f->V;
  const int *ord = L->ord;
  rl_kparams kp; /* what the rows read besides the arrays */
  rl_ff_kparams(ff, &kp);
  /* every body a dipole rank on the AVX-512 rows (a Stockmayer fluid): the kernels read and
   * write only the 64-byte records, so the copies and the sums below take a short path */
  const int dip_only = f->pft && f->ndip == n;
  /* no pairs for the reference routine: the threads' site-force buffers stay empty */
  const int general = L->gstart[n] > 0;
#pragma omp parallel num_threads(T)
  {
    int t = omp_get_thread_num();
    /* the kernels' copies in rank order */
    if (dip_only) {
#pragma omp for schedule(static)
      for (int m = 0; m < n; m++) {
        const int i = ord[m];
        const double mu = f->sk[ff->body_species[i]].mu;
        for (int c = 0; c < 3; c++) {
          V->pk[m][c] = ff->centre[i][c];
          V->pk[m][4 + c] = mu * ff->axis[i][c];
        }
      }
    } else
#pragma omp for schedule(static)
    for (int m = 0; m < n; m++) {
      const int i = ord[m], k = ff->body_species[i], ns_i = ff->sp_nsites[k];
      const int oi = ff->body_site_off[i], om = V->soff[m];
      const fast_species *K = &f->sk[k];
      if (V->pk4 && K->kind == K_TIP4P && mode[k] != P_SITE) {
        /* the AVX-512 TIP4P rows read only the records (and the list only kernel pairs, so no
         * other species' row reads this rank) */
        for (int c = 0; c < 3; c++) {
          V->pk4[m][c] = ff->centre[i][c];
          for (int s = 0; s < 4; s++) V->pk4[m][3 + 3 * s + c] = ff->dsite[oi + K->perm[s]][c];
        }
        if (V->pk4f)
          for (int c = 0; c < 12; c++) V->pk4f[m][c] = (float)V->pk4[m][3 + c];
        continue;
      }
      for (int c = 0; c < 3; c++) {
        V->c[m][c] = ff->centre[i][c];
        V->ax[m][c] = ff->axis[i][c];
      }
      if (V->pk && K->kind == K_DIPOLE) { /* the AVX-512 dipole rows read no sites */
        for (int c = 0; c < 3; c++) {
          V->pk[m][c] = ff->centre[i][c];
          V->pk[m][4 + c] = K->mu * ff->axis[i][c];
        }
        continue;
      }
      for (int a = 0; a < ns_i; a++)
        for (int c = 0; c < 3; c++) {
          V->site[om + a][c] = ff->site[oi + a][c];
          V->dsite[om + a][c] = ff->dsite[oi + a][c];
        }
    } /* implicit barrier */
    double(*fs)[3] = t == 0 ? ff->fs : f->fsbuf + (size_t)(t - 1) * (size_t)ns;
    double(*tq)[3] = t == 0 ? ff->tq : f->tqbuf + (size_t)(t - 1) * (size_t)n;
    double(*pfs)[3] = f->pfs + (size_t)t * (size_t)ns;
    double(*ptq)[3] = f->ptq + (size_t)t * (size_t)n;
    if (t > 0 && general) {
      memset(fs, 0, sizeof *fs * (size_t)ns);
      memset(tq, 0, sizeof *tq * (size_t)n);
    }
    /* the kernel buffers (pfs, ptq, pft, pft4) are zero here: allocated so, and the sums below
     * zero what they read; the thread's rows write ranks [tlo[t], thi[t]) only */
    double(*pft)[8] = f->pft ? f->pft + (size_t)t * (size_t)n : NULL;
    double(*pft4)[16] = f->pft4 ? f->pft4 + (size_t)t * (size_t)n : NULL;
    rl_acc *a = &f->acc[t];
    memset(a, 0, sizeof *a);
    a->fs = fs;
    a->tq = tq;
    a->site_virial = 1;
    a->quiet = 1;
    a->forces_only = out->forces_only;
    int st = RL_OK;
    const rl_kout kout = {pfs, ptq, pft, pft4, &a->s};
    for (int m = f->tlo[t]; m < f->tlo[t + 1] && !st && !a->s.bad; m++) {
      const int i = ord[m], k = ff->body_species[i];
      const fast_species *K = &f->sk[k];
      int fl = L->fstart[m + 1] - L->fstart[m];
      if (fl > 0)
        f->row[k][a->forces_only][mode[k]](&kp, V, K, m, L->fnbr + L->fstart[m], fl, &kout);
      for (int q = L->gstart[m]; q < L->gstart[m + 1] && !st; q++)
        st = rl_ff_body_pair(ff, i, L->gnbr[q], a);
    }
    f->status[t] = st;
#ifdef _OPENMP /* -fopenmp-simd accepts the other directives without OpenMP, not this one */
#pragma omp barrier
#endif
    if (T > 1 && general) { /* add the other threads' buffers, in thread order */
#pragma omp for schedule(static)
      for (int s = 0; s < ns; s++)
        for (int u = 1; u < T; u++) {
          const double *b = f->fsbuf[(size_t)(u - 1) * (size_t)ns + (size_t)s];
          ff->fs[s][0] += b[0]; ff->fs[s][1] += b[1]; ff->fs[s][2] += b[2];
        }
#pragma omp for schedule(static)
      for (int i = 0; i < n; i++)
        for (int u = 1; u < T; u++) {
          const double *b = f->tqbuf[(size_t)(u - 1) * (size_t)n + (size_t)i];
          ff->tq[i][0] += b[0]; ff->tq[i][1] += b[1]; ff->tq[i][2] += b[2];
        }
    }
    /* the kernels' forces and torques back to body order, threads in order, each record zeroed
     * once read (for the next compute: one pass over the buffers instead of a memset and a
     * read, 2 % of a 64,000-dipole step); for the kernels that add the molecular virial
     * (tip4p_row), + sum d (x) F over their site forces, which the correction below subtracts
     * again */
    double cv[9] = {0};
    if (dip_only) {
#pragma omp for schedule(static)
      for (int m = 0; m < n; m++) {
        const int i = ord[m], oi = ff->body_site_off[i];
        for (int u = 0; u < T; u++) {
          if (m < f->tlo[u] || m >= f->thi[u]) continue; /* not written by thread u */
          double *q = f->pft[(size_t)u * (size_t)n + (size_t)m];
          for (int c = 0; c < 3; c++) {
            ff->fs[oi][c] += q[c];
            ff->tq[i][c] += q[4 + c];
          }
          for (int c = 0; c < 8; c++) q[c] = 0.0;
        }
      }
    } else
#pragma omp for schedule(static)
    for (int m = 0; m < n; m++) {
      const int i = ord[m], k = ff->body_species[i], ns_i = ff->sp_nsites[k];
      const int oi = ff->body_site_off[i], om = V->soff[m];
      const int mv = f->sk[k].kind == K_TIP4P && mode[k] != P_SITE; /* 4 sites */
      const int cvir = mv && !out->forces_only; /* their rows summed R (x) F */
      double F[4][3];                           /* cvir: kernel site forces */
      if (cvir) /* a loop, not an initialiser: GCC made that a `rep stos`, 2.5 % of a dipole step */
        for (int a = 0; a < 4; a++) F[a][0] = F[a][1] = F[a][2] = 0.0;
      for (int u = 0; u < T; u++) {
        if (m < f->tlo[u] || m >= f->thi[u]) continue; /* not written by thread u */
        double(*pf)[3] = f->pfs + (size_t)u * (size_t)ns + (size_t)om;
        double *pt = f->ptq[(size_t)u * (size_t)n + (size_t)m];
        for (int a = 0; a < ns_i; a++)
          for (int c = 0; c < 3; c++) {
            ff->fs[oi + a][c] += pf[a][c];
            if (cvir) F[a][c] += pf[a][c];
            pf[a][c] = 0.0;
          }
        for (int c = 0; c < 3; c++) {
          ff->tq[i][c] += pt[c];
          pt[c] = 0.0;
        }
        if (f->pft) { /* every rank's record is zeroed, whatever its kind and mode */
          double *q = f->pft[(size_t)u * (size_t)n + (size_t)m];
          if (f->sk[k].kind == K_DIPOLE) /* ns_i = 1 */
            for (int c = 0; c < 3; c++) {
              ff->fs[oi][c] += q[c];
              ff->tq[i][c] += q[4 + c];
            }
          for (int c = 0; c < 8; c++) q[c] = 0.0;
        }
        if (f->pft4) { /* record slot s: site perm[s] */
          double *q = f->pft4[(size_t)u * (size_t)n + (size_t)m];
          if (mv)
            for (int s = 0; s < 4; s++)
              for (int c = 0; c < 3; c++) {
                const int a = f->sk[k].perm[s];
                ff->fs[oi + a][c] += q[3 + 3 * s + c];
                if (cvir) F[a][c] += q[3 + 3 * s + c];
              }
          for (int c = 0; c < 16; c++) q[c] = 0.0;
        }
      }
      if (cvir)
        for (int a = 0; a < 4; a++)
          for (int x = 0; x < 3; x++)
            for (int y = 0; y < 3; y++) cv[3 * x + y] += ff->dsite[oi + a][x] * F[a][y];
    }
    for (int c = 0; c < 9; c++) f->acc[t].s.vir[c] += cv[c]; /* this thread's: read in order below */
  }
  int bad = 0;
  for (int t = 0; t < T; t++) {
    if (f->status[t] || f->acc[t].s.bad) bad = 1;
    out->s.lj += f->acc[t].s.lj;
    out->s.coul += f->acc[t].s.coul;
    out->s.dip += f->acc[t].s.dip;
    out->s.quad += f->acc[t].s.quad;
    for (int c = 0; c < 9; c++) out->s.vir[c] += f->acc[t].s.vir[c];
  }
  if (bad) return 1; /* the reference loop reruns and reports the overlap */
  if (dip_only || out->forces_only) return RL_OK; /* point dipoles: every d is zero */
  for (int s = 0; s < ns; s++) /* molecular virial: minus sum_sites d (x) F */
    for (int x = 0; x < 3; x++)
      for (int y = 0; y < 3; y++) out->s.vir[3 * x + y] -= ff->dsite[s][x] * ff->fs[s][y];
  return RL_OK;
}
