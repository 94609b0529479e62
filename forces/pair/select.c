/* Kernel selection for the pair term: which kernel each species takes (from its site pattern),
 * which instruction set its rows use (at load time, from the CPU and the environment), and in
 * which precision. */
#include "fast.h"
#include "kernels/batch.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The row sets of one kernel, per instruction set (NULL: none in this build). */
typedef struct {
  const rl_row_set *portable, *avx512, *avx2, *avx2_mixed;
} row_sets;
#if RL_X512
#define RL_REG(set) (&(set))
#else
#define RL_REG(set) NULL
#endif
static const row_sets sites_lj_rf = {&rl_rows_portable_sites_lj_rf, NULL, NULL, NULL};
static const row_sets tip4p_lj_rf = {&rl_rows_portable_tip4p_lj_rf,
                                     RL_REG(rl_rows_avx512_tip4p_lj_rf),
                                     RL_REG(rl_rows_avx2_tip4p_lj_rf),
                                     RL_REG(rl_rows_avx2_mixed_tip4p_lj_rf)};
/* the Ewald real space: no mixed-precision rows (rl_ff_select turns the mixed precision off) */
static const row_sets sites_lj_ewald = {&rl_rows_portable_sites_lj_ewald, NULL, NULL, NULL};
static const row_sets tip4p_lj_ewald = {&rl_rows_portable_tip4p_lj_ewald,
                                        RL_REG(rl_rows_avx512_tip4p_lj_ewald),
                                        RL_REG(rl_rows_avx2_tip4p_lj_ewald), NULL};
static const row_sets dipole_lj_rf = {&rl_rows_portable_dipole_lj_rf,
                                      RL_REG(rl_rows_avx512_dipole_lj_rf),
                                      RL_REG(rl_rows_avx2_dipole_lj_rf), NULL};
static const row_sets dipole_lj_sf = {&rl_rows_portable_dipole_lj_sf,
                                      RL_REG(rl_rows_avx512_dipole_lj_sf),
                                      RL_REG(rl_rows_avx2_dipole_lj_sf), NULL};
static const row_sets dipole_lj_ewald = {&rl_rows_portable_dipole_lj_ewald,
                                         RL_REG(rl_rows_avx512_dipole_lj_ewald),
                                         RL_REG(rl_rows_avx2_dipole_lj_ewald), NULL};

/* The rows for each separation mode and LJ truncation trunc: the mixed-precision rows where
 * asked for (tmix) and present, else the register rows of vec, else the portable ones; a
 * forces-only row where the set has one, else the full row. */
static void take_rows(row_fn rows[2][3], const row_sets *S, int vec, int tmix, int trunc)
{
  const rl_row_set *r = tmix && S->avx2_mixed ? S->avx2_mixed
                        : vec == VEC_512      ? S->avx512
                        : vec == VEC_256      ? S->avx2
                                              : NULL;
  for (int m = 0; m < 3; m++) {
    const row_fn ev = r ? r->ev[m][trunc] : NULL, fo = r ? r->fo[m][trunc] : NULL;
    rows[0][m] = ev ? ev : S->portable->ev[m][trunc];
    rows[1][m] = fo ? fo : rows[0][m];
  }
}

static void term_set(const rl_forcefield *ff, int ta, int tb, fast_term *T)
{
  const rl_lj_coef *c = &ff->lj[ta * ff->ntypes + tb];
  T->c6 = c->c6;
  T->c12 = c->c12;
  T->eshift = c->eshift;
  T->fshift = c->fshift;
  T->qq = ff->kc * ff->q[ta] * ff->q[tb];
}

/* The kernel of species k from its sites and the current LJ table. */
static void classify(const rl_forcefield *ff, int k, int vec, int tmix, fast_species *K,
                     row_fn rows[2][3])
{
  memset(K, 0, sizeof *K);
  int ns = ff->sp_nsites[k], o = ff->type_off[k];
  if (ns < 1 || ns > RL_FAST_MAXS || ff->sp_count[k] < 2) return;
  int ndip = 0, nq = 0, nquad = 0;
  for (int a = 0; a < ns; a++) {
    ndip += ff->mu[o + a] != 0.0;
    nquad += ff->Q[o + a] != 0.0;
    nq += ff->q[o + a] != 0.0;
  }
  if (nquad) return;
  K->ns = ns;
  K->extent = ff->sp_extent[k];
  for (int a = 0; a < ns; a++) K->perm[a] = a;
  if (ndip) { /* stockmayer: one site at the centre, LJ + dipole, no charge */
    if (ns != 1 || nq || ff->sp_extent[k] != 0.0) { K->ns = 0; return; }
    K->kind = K_DIPOLE;
    K->mu = ff->mu[o];
    K->nterms = 1;
    term_set(ff, o, o, &K->t[0]);
    /* the Ewald real space (the reaction field and shifted force are then not used) */
    take_rows(rows, ff->p.coulomb == RL_COULOMB_EWALD_REAL ? &dipole_lj_ewald
                    : ff->p.dipole_method == RL_DIPOLE_SF ? &dipole_lj_sf
                                                          : &dipole_lj_rf,
              vec, tmix, ff->p.lj_truncation);
    return;
  }
  K->kind = K_SITES;
  int nlj = 0, ncoul = 0, nboth = 0, ljsite = -1;
  for (int a = 0; a < ns; a++)
    for (int b = 0; b < ns; b++) {
      int lj = ff->lj[(o + a) * ff->ntypes + o + b].epsilon != 0.0;
      int qq = ff->q[o + a] != 0.0 && ff->q[o + b] != 0.0;
      if (!lj && !qq) continue;
      fast_term *T = &K->t[K->nterms++];
      T->a = a;
      T->b = b;
      T->what = lj && qq ? T_BOTH : lj ? T_LJ : T_COUL;
      nlj += T->what == T_LJ;
      ncoul += T->what == T_COUL;
      nboth += T->what == T_BOTH;
      if (T->what == T_LJ && a == b) ljsite = a;
      term_set(ff, o + a, o + b, T);
    }
  const int ewald = ff->p.coulomb == RL_COULOMB_EWALD_REAL;
  take_rows(rows, ewald ? &sites_lj_ewald : &sites_lj_rf, vec, tmix, ff->p.lj_truncation);
  /* TIP4P pattern: one LJ site (with itself only, no charge), three charges without LJ */
  if (ns == 4 && nlj == 1 && ljsite >= 0 && ncoul == 9 && nboth == 0) {
    K->kind = K_TIP4P;
    int s = 1;
    K->perm[0] = ljsite;
    for (int a = 0; a < 4; a++)
      if (a != ljsite) K->perm[s++] = a;
    term_set(ff, o + ljsite, o + ljsite, &K->t[0]);
    K->t[0].a = K->t[0].b = 0;
    K->t[0].what = T_LJ;
    for (int p = 0; p < 3; p++)
      for (int q = 0; q < 3; q++) {
        fast_term *T = &K->t[1 + 3 * p + q];
        term_set(ff, o + K->perm[1 + p], o + K->perm[1 + q], T);
        T->a = 1 + p;
        T->b = 1 + q;
        T->what = T_COUL;
      }
    take_rows(rows, ewald ? &tip4p_lj_ewald : &tip4p_lj_rf, vec, tmix, ff->p.lj_truncation);
  }
}

static const char *species_name(const fast_species *K)
{
  return K->kind == K_DIPOLE ? "stockmayer" : K->kind == K_TIP4P ? "tip4p"
                                            : K->kind == K_SITES ? "charge-lj" : NULL;
}

const char *rl_ff_fast_species(const rl_ff_fast *f, int k) { return species_name(&f->sk[k]); }

void rl_ff_kparams(const rl_forcefield *ff, rl_kparams *kp)
{
  const double rc = ff->p.cutoff, md = ff->min_distance;
  const box_consts B = {{ff->box.L[0], ff->box.L[1], ff->box.L[2]},
                        {ff->box.invL[0], ff->box.invL[1], ff->box.invL[2]},
                        rc, rc * rc, ff->p.r_switch, md * md};
  const double alpha = ff->p.coulomb == RL_COULOMB_EWALD_REAL ? ff->p.ewald_alpha : 0.0;
  const rl_kelec E = {ff->kc, ff->rf.krf, ff->rf.crf, rc, alpha, 2.0 * alpha / sqrt(M_PI)};
  kp->B = B;
  kp->E = E;
}

/* Whether the AVX2 TIP4P rows take the image list: some TIP4P species separates its sites by
 * shifting the centres' separation (P_SHIFT) in a box that needs other images (needs_images),
 * the modes rl_ff_fast_compute gives it.  Then the rows of every TIP4P species do. */
int rl_ff_image_rows(const rl_forcefield *ff, unsigned char *images)
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
    if (shift && needs_images(P_SHIFT, &B, prune2(P_SHIFT, &B, K))) {
      for (int q = 0; q < ff->nspecies; q++) images[q] = f->sk[q].kind == K_TIP4P;
      return 1;
    }
  }
  return 0;
}

void rl_ff_select(const rl_forcefield *ff, rl_ff_fast *f)
{
  /* name: the kernels in use, then "+general" if any pair takes the reference routine */
  int general = 0, used = 0;
  char *p = f->namebuf;
  size_t left = sizeof f->namebuf;
  int nonempty = 0;
  for (int k = 0; k < ff->nspecies; k++) nonempty += ff->sp_count[k] > 0 && ff->sp_nsites[k] > 0;
#if RL_X512
  const int avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                   !getenv("ROTLEAP_NO_AVX2");
  if (__builtin_cpu_supports("avx512f") && !getenv("ROTLEAP_NO_AVX512")) f->vec = VEC_512;
  else if (avx2) f->vec = VEC_256;
  /* the AVX2 rows, on AVX-512 too; reaction field only (no single-precision Ewald rows) */
  f->tmix = ff->p.precision == RL_PRECISION_MIXED && avx2 && ff->p.coulomb == RL_COULOMB_RF;
#endif
  for (int k = 0; k < ff->nspecies; k++) {
    classify(ff, k, f->vec, f->tmix, &f->sk[k], f->row[k]);
    if (f->sk[k].kind == K_DIPOLE) f->ndip += ff->sp_count[k];
    if (f->sk[k].kind == K_TIP4P) f->ntip4p += ff->sp_count[k];
    if (ff->sp_count[k] == 0 || ff->sp_nsites[k] == 0) continue;
    const char *nm = species_name(&f->sk[k]);
    if (!nm) { general = 1; continue; }
    if (!strstr(f->namebuf, nm)) {
      int w = snprintf(p, left, "%s%s", used ? "+" : "", nm);
      if (w > 0 && (size_t)w < left) { p += w; left -= (size_t)w; }
      used = 1;
    }
  }
  if (nonempty > 1) general = 1; /* pairs of different species */
  if (general) snprintf(p, left, "%s", used ? "+general" : "general");
  f->name = f->namebuf;
}

const char *rl_ff_fast_name(const rl_ff_fast *f) { return f->name; }
const char *rl_ff_fast_rows(const rl_ff_fast *f)
{
  if (rl_ff_fast_mixed(f)) return f->vec == VEC_512 ? "avx512+avx2-mixed" : "avx2-mixed";
  return f->vec == VEC_512 ? "avx512" : f->vec == VEC_256 ? "avx2" : "portable";
}
int rl_ff_fast_mixed(const rl_ff_fast *f) { return f->tmix && f->ntip4p > 0; }
