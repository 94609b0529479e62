/* The force field object: parameter tables, cutoff schemes, pair loops (neighbour list or
 * brute force), site forces -> molecular forces and torques, energies and virial. */
#include "rotleap/forcefield.h"
#include "rotleap/error.h"

#include "dipole.h"
#include "quadrupole.h"
#include "forcefield_impl.h"
#include "coulomb_ewald.h"
#include "../../core/threads.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void rl_ff_params_default(rl_ff_params *p)
{
  memset(p, 0, sizeof *p);
  p->cutoff = 0.0;
  p->scheme = RL_CUTOFF_SITE;
  p->lj_truncation = RL_LJ_PLAIN;
  p->r_switch = 0.0;
  p->dispersion_correction = 0;
  p->eps_rf = 78.3;
  p->dipole_method = RL_DIPOLE_RF;
  p->intramolecular_rf = 0;
  p->coulomb_constant = 0.0;
  p->neighbor_list = 1;
  p->skin = -1.0;
  p->min_distance = -1.0;
  p->kernel = RL_KERNEL_AUTO;
  p->threads = 0;
  p->precision = RL_PRECISION_DOUBLE;
}

double rl_ff_skin_for_step(double cutoff, double kT, double mass, double h)
{
  if (!(kT > 0) || !(mass > 0) || !(h > 0)) return 0.1 * cutoff;
  const double x = sqrt(3.0 * kT / mass) * h / (0.0015 * cutoff);
  return fmin(0.25, 0.1 * sqrt(fmax(1.0, x))) * cutoff;
}

void rl_forcefield_free(rl_forcefield *ff)
{
  if (!ff) return;
  free(ff->type_off);
  free(ff->sp_nsites);
  free(ff->sp_count);
  free(ff->sp_extent);
  free(ff->sig);
  free(ff->eps);
  free(ff->q);
  free(ff->mu);
  free(ff->Q);
  free(ff->type_species);
  free(ff->type_site);
  free(ff->lj);
  free(ff->body_species);
  free(ff->body_site_off);
  free(ff->body_rot);
  free(ff->site_type);
  free(ff->centre);
  free(ff->axis);
  free(ff->site);
  free(ff->dsite);
  free(ff->fs);
  free(ff->tq);
  rl_nlist_free(ff->nl);
  rl_ff_fast_free(ff->fast);
  free(ff->origin);
  free(ff->tsite);
  free(ff->sp_name);
  free(ff);
}

static void *xcalloc(size_t n, size_t size) { return calloc(n > 0 ? n : 1, size); }

static int check_cutoff(const rl_box *box, double rc)
{
  static const char ax[3] = {'x', 'y', 'z'};
  int m = 0;
  for (int c = 1; c < 3; c++)
    if (box->L[c] < box->L[m]) m = c;
  if (rc > 0.5 * box->L[m])
    return rl_error(RL_EINVAL, "forcefield: cutoff %g is larger than half the shortest box edge "
                    "(L%c = %g, half = %g)", rc, ax[m], box->L[m], 0.5 * box->L[m]);
  return RL_OK;
}

static void lj_mix(rl_forcefield *ff, int ta, int tb, double sigma, double epsilon)
{
  rl_lj_coef *c = &ff->lj[ta * ff->ntypes + tb];
  rl_lj_coef_init(c, sigma, epsilon, ff->p.lj_truncation, ff->p.cutoff, ff->p.r_switch);
  ff->lj[tb * ff->ntypes + ta] = *c;
}

static void update_dispersion(rl_forcefield *ff)
{
  ff->disp_e = ff->disp_w = 0.0;
  if (!ff->p.dispersion_correction) return;
  for (int a = 0; a < ff->ntypes; a++)
    for (int b = 0; b < ff->ntypes; b++) {
      const rl_lj_coef *c = &ff->lj[a * ff->ntypes + b];
      if (c->epsilon == 0.0) continue;
      int ka = ff->type_species[a], kb = ff->type_species[b];
      double np = ka == kb ? (double)ff->sp_count[ka] * (ff->sp_count[ka] - 1)
                           : (double)ff->sp_count[ka] * ff->sp_count[kb];
      double e, w;
      rl_lj_tail(c, &e, &w);
      ff->disp_e += np * e;
      ff->disp_w += np * w;
    }
}

/* Largest |site - centre| of one body, and (if t) its sites' offsets from the centre in a frame
 * whose Z is the body's axis (orientation independent).  -1 if out of memory. */
static double species_extent(const rl_system *sys, int body, int nsites, double (*t)[3])
{
  double ext = 0.0, r[3], e[3], u[3], v[3];
  rl_system_get_position(sys, body, r);
  rl_system_get_axis(sys, body, e);
  /* u: the unit vector along the lab axis least aligned with e, made perpendicular; v = e x u */
  int m = fabs(e[0]) <= fabs(e[1]) && fabs(e[0]) <= fabs(e[2]) ? 0 : fabs(e[1]) <= fabs(e[2]) ? 1 : 2;
  for (int c = 0; c < 3; c++) u[c] = (c == m) - e[m] * e[c];
  const double un = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (int c = 0; c < 3; c++) u[c] /= un;
  v[0] = e[1] * u[2] - e[2] * u[1];
  v[1] = e[2] * u[0] - e[0] * u[2];
  v[2] = e[0] * u[1] - e[1] * u[0];
  int off = rl_system_site_offset(sys, body), ns = rl_system_nsites(sys);
  double(*s)[3] = malloc(sizeof *s * (size_t)(ns > 0 ? ns : 1));
  if (!s) return -1.0;
  rl_system_site_positions(sys, s);
  for (int a = 0; a < nsites; a++) {
    double d[3] = {s[off + a][0] - r[0], s[off + a][1] - r[1], s[off + a][2] - r[2]};
    ext = fmax(ext, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    if (t) {
      t[a][0] = u[0] * d[0] + u[1] * d[1] + u[2] * d[2];
      t[a][1] = v[0] * d[0] + v[1] * d[1] + v[2] * d[2];
      t[a][2] = e[0] * d[0] + e[1] * d[1] + e[2] * d[2];
    }
  }
  free(s);
  return ext;
}

static int check_array(const double *x, int k, int ns, const char *name, int nonneg)
{
  for (int a = 0; a < ns; a++) {
    if (!isfinite(x[a]))
      return rl_error(RL_EINVAL, "forcefield: species %d: %s[%d] = %g is not finite", k, name, a,
                      x[a]);
    if (nonneg && x[a] < 0.0)
      return rl_error(RL_EINVAL, "forcefield: species %d: %s[%d] = %g is negative", k, name, a,
                      x[a]);
  }
  return RL_OK;
}

/* The box the force field takes: the system's cell; for a system without one, the deprecated
 * p.box of callers written before the system owned its cell (forcefield.h). */
/* The periodic cell is the system's (rl_system_set_box); the force field keeps a copy that
 * rl_forcefield_compute refreshes when the system's box version changes. */
static int system_box(const rl_system *sys, rl_box *box)
{
  double L[3];
  rl_system_box(sys, L);
  if (!rl_system_periodic(sys))
    return rl_error(RL_EINVAL, "forcefield: the system has no periodic box (rl_system_set_box)");
  return rl_box_set(box, L);
}

rl_forcefield *rl_forcefield_alloc(const rl_system *sys, const rl_ff_params *p,
                                   const rl_species_ff *species, int nspecies)
{
  if (!sys || !p || (!species && nspecies > 0)) {
    rl_error(RL_EINVAL, "rl_forcefield_alloc: NULL argument");
    return NULL;
  }
  int n = rl_system_count(sys), nsp = rl_system_nspecies(sys), nsites = rl_system_nsites(sys);
  if (nspecies != nsp) {
    rl_error(RL_EINVAL, "forcefield: %d species parameter sets given, the system has %d species",
             nspecies, nsp);
    return NULL;
  }
  /* ---- scalar parameters */
  if (!(p->cutoff > 0.0) || !isfinite(p->cutoff)) {
    rl_error(RL_EINVAL, "forcefield: cutoff %g must be positive and finite", p->cutoff);
    return NULL;
  }
  rl_box box;
  if (system_box(sys, &box)) return NULL;
  if (check_cutoff(&box, p->cutoff)) return NULL;
  if (p->scheme != RL_CUTOFF_SITE && p->scheme != RL_CUTOFF_MOLECULE) {
    rl_error(RL_EINVAL, "forcefield: unknown cutoff scheme %d", (int)p->scheme);
    return NULL;
  }
  if ((int)p->lj_truncation < 0 || (int)p->lj_truncation > RL_LJ_SWITCHED) {
    rl_error(RL_EINVAL, "forcefield: unknown LJ truncation %d", (int)p->lj_truncation);
    return NULL;
  }
  if (p->lj_truncation == RL_LJ_SWITCHED && !(p->r_switch >= 0.0 && p->r_switch < p->cutoff)) {
    rl_error(RL_EINVAL, "forcefield: r_switch %g must satisfy 0 <= r_switch < cutoff %g",
             p->r_switch, p->cutoff);
    return NULL;
  }
  if (!(p->eps_rf >= 1.0)) {
    rl_error(RL_EINVAL, "forcefield: eps_rf %g must be >= 1 (INFINITY allowed)", p->eps_rf);
    return NULL;
  }
  if (p->coulomb != RL_COULOMB_RF && p->coulomb != RL_COULOMB_EWALD_REAL) {
    rl_error(RL_EINVAL, "forcefield: unknown coulomb method %d (reaction field %d, Ewald real space %d)",
             (int)p->coulomb, (int)RL_COULOMB_RF, (int)RL_COULOMB_EWALD_REAL);
    return NULL;
  }
  if (p->coulomb == RL_COULOMB_EWALD_REAL &&
      (!(p->ewald_alpha > 0.0) || !isfinite(p->ewald_alpha) || p->scheme != RL_CUTOFF_SITE || p->intramolecular_rf)) {
    rl_error(RL_EINVAL, "forcefield: the Ewald real space (coulomb = ewald) needs ewald_alpha > 0 and finite (%g), "
             "the site cutoff (scheme %s) and intramolecular_rf = 0 (%d)", p->ewald_alpha,
             p->scheme == RL_CUTOFF_SITE ? "site" : "molecule", p->intramolecular_rf);
    return NULL;
  }
  if (p->dipole_method != RL_DIPOLE_RF && p->dipole_method != RL_DIPOLE_SF) {
    rl_error(RL_EINVAL, "forcefield: unknown dipole method %d", (int)p->dipole_method);
    return NULL;
  }
  if (!isfinite(p->coulomb_constant) || p->coulomb_constant < 0.0) {
    rl_error(RL_EINVAL, "forcefield: coulomb_constant %g must be finite and >= 0 (0: default)",
             p->coulomb_constant);
    return NULL;
  }
  if (p->precision != RL_PRECISION_DOUBLE && p->precision != RL_PRECISION_MIXED) {
    rl_error(RL_EINVAL, "forcefield: unknown precision %d (double %d, mixed %d)",
             (int)p->precision, (int)RL_PRECISION_DOUBLE, (int)RL_PRECISION_MIXED);
    return NULL;
  }
  if (p->kernel != RL_KERNEL_AUTO && p->kernel != RL_KERNEL_GENERAL) {
    rl_error(RL_EINVAL, "forcefield: unknown kernel choice %d (auto %d, general %d)",
             (int)p->kernel, (int)RL_KERNEL_AUTO, (int)RL_KERNEL_GENERAL);
    return NULL;
  }
  if (p->threads < 0) {
    rl_error(RL_EINVAL, "forcefield: threads %d must be >= 0 (0: OpenMP's default)", p->threads);
    return NULL;
  }
  if (isnan(p->skin) || isinf(p->skin) || isnan(p->min_distance) || isinf(p->min_distance)) {
    rl_error(RL_EINVAL, "forcefield: skin %g and min_distance %g must be finite", p->skin,
             p->min_distance);
    return NULL;
  }

  /* ---- species tables */
  int *first_body = xcalloc((size_t)nsp, sizeof *first_body);
  int *count = xcalloc((size_t)nsp, sizeof *count);
  if (!first_body || !count) {
    free(first_body); free(count);
    rl_error(RL_ENOMEM, "forcefield: out of memory");
    return NULL;
  }
  for (int k = 0; k < nsp; k++) first_body[k] = -1;
  for (int i = n - 1; i >= 0; i--) {
    int k = rl_system_species_of(sys, i);
    first_body[k] = i;
    count[k]++;
  }
  int ntypes = 0;
  for (int k = 0; k < nsp; k++) {
    const rl_species_ff *s = &species[k];
    int st = RL_OK;
    if (first_body[k] >= 0) {
      int b = first_body[k];
      int ns_sys = (b + 1 < n ? rl_system_site_offset(sys, b + 1) : nsites) -
                   rl_system_site_offset(sys, b);
      if (s->nsites != ns_sys)
        st = rl_error(RL_EINVAL, "forcefield: species %d: nsites = %d but the system's species "
                      "has %d sites", k, s->nsites, ns_sys);
    }
    if (!st && s->nsites < 0)
      st = rl_error(RL_EINVAL, "forcefield: species %d: nsites = %d is negative", k, s->nsites);
    if (!st && s->nsites > 0) {
      const char *missing = !s->sigma ? "sigma" : !s->epsilon ? "epsilon"
                            : !s->charge ? "charge" : NULL;
      if (missing)
        st = rl_error(RL_EINVAL, "forcefield: species %d: missing array %s (nsites = %d)", k,
                      missing, s->nsites);
    }
    if (!st && s->nsites > 0) st = check_array(s->sigma, k, s->nsites, "sigma", 1);
    if (!st && s->nsites > 0) st = check_array(s->epsilon, k, s->nsites, "epsilon", 1);
    if (!st && s->nsites > 0) st = check_array(s->charge, k, s->nsites, "charge", 0);
    if (!st && s->dipole) st = check_array(s->dipole, k, s->nsites, "dipole", 0);
    if (!st && s->quadrupole) st = check_array(s->quadrupole, k, s->nsites, "quadrupole", 0);
    if (!st && rl_system_species_kind(sys, k) == RL_KIND_POINT) {
      for (int a = 0; a < s->nsites && !st; a++)
        if ((s->dipole && s->dipole[a] != 0.0) || (s->quadrupole && s->quadrupole[a] != 0.0))
          st = rl_error(RL_EINVAL, "forcefield: species %d is a point species but site %d "
                        "carries a %s: a point body has no orientation", k, a,
                        s->dipole && s->dipole[a] != 0.0 ? "dipole" : "quadrupole");
    }
    if (st) { free(first_body); free(count); return NULL; }
    ntypes += s->nsites;
  }
  /* quadrupoles interact only with quadrupoles (and LJ): reject scenes that mix them */
  {
    int kq = -1, aq = -1, kp = -1, ap = -1;
    for (int k = 0; k < nsp; k++)
      for (int a = 0; a < species[k].nsites; a++) {
        if (species[k].quadrupole && species[k].quadrupole[a] != 0.0 && kq < 0) { kq = k; aq = a; }
        if ((species[k].charge[a] != 0.0 || (species[k].dipole && species[k].dipole[a] != 0.0)) &&
            kp < 0) { kp = k; ap = a; }
      }
    if (kq >= 0 && kp >= 0) {
      free(first_body); free(count);
      rl_error(RL_EINVAL, "forcefield: species %d site %d carries a quadrupole and species %d "
               "site %d a charge or dipole: charge-quadrupole and dipole-quadrupole "
               "interactions are not supported (quadrupoles interact with quadrupoles only)", kq, aq, kp, ap);
      return NULL;
    }
  }

  rl_forcefield *ff = calloc(1, sizeof *ff);
  if (!ff) { free(first_body); free(count); rl_error(RL_ENOMEM, "forcefield: out of memory"); return NULL; }
  ff->p = *p;
  ff->box = box;
  ff->box_version = rl_system_box_version(sys);
  ff->kc = p->coulomb_constant != 0.0 ? p->coulomb_constant
           : rl_system_units(sys) == RL_UNITS_LJ ? 1.0 : RL_COULOMB_KJMOL_NM;
  ff->n = n; ff->nspecies = nsp; ff->nsites = nsites; ff->ntypes = ntypes;
  ff->sp_count = count;
  size_t nt = (size_t)ntypes;
  ff->type_off = xcalloc((size_t)nsp, sizeof(int));
  ff->sp_nsites = xcalloc((size_t)nsp, sizeof(int));
  ff->sp_extent = xcalloc((size_t)nsp, sizeof(double));
  ff->sig = xcalloc(nt, sizeof(double)); ff->eps = xcalloc(nt, sizeof(double));
  ff->q = xcalloc(nt, sizeof(double)); ff->mu = xcalloc(nt, sizeof(double));
  ff->Q = xcalloc(nt, sizeof(double));
  ff->type_species = xcalloc(nt, sizeof(int)); ff->type_site = xcalloc(nt, sizeof(int));
  ff->lj = xcalloc(nt * nt, sizeof(rl_lj_coef));
  ff->body_species = xcalloc((size_t)n, sizeof(int));
  ff->body_site_off = xcalloc((size_t)n, sizeof(int));
  ff->body_rot = xcalloc((size_t)n, sizeof(int));
  ff->site_type = xcalloc((size_t)nsites, sizeof(int));
  ff->centre = xcalloc((size_t)n, sizeof *ff->centre);
  ff->axis = xcalloc((size_t)n, sizeof *ff->axis);
  ff->tq = xcalloc((size_t)n, sizeof *ff->tq);
  ff->site = xcalloc((size_t)nsites, sizeof *ff->site);
  ff->dsite = xcalloc((size_t)nsites, sizeof *ff->dsite);
  ff->fs = xcalloc((size_t)nsites, sizeof *ff->fs);
  ff->tsite = xcalloc(nt, sizeof *ff->tsite);
  ff->sp_name = xcalloc((size_t)nsp, sizeof *ff->sp_name);
  ff->units = rl_system_units(sys);
  ff->last_pairs = -1;
  if (!ff->tsite || !ff->sp_name ||
      !ff->type_off || !ff->sp_nsites || !ff->sp_extent || !ff->sig || !ff->eps || !ff->q || !ff->mu || !ff->Q ||
      !ff->type_species || !ff->type_site || !ff->lj || !ff->body_species ||
      !ff->body_site_off || !ff->body_rot || !ff->site_type || !ff->centre || !ff->axis ||
      !ff->tq || !ff->site || !ff->dsite || !ff->fs) {
    free(first_body);
    rl_forcefield_free(ff);
    rl_error(RL_ENOMEM, "forcefield: out of memory for %d types, %d bodies", ntypes, n);
    return NULL;
  }
  int t = 0;
  for (int k = 0; k < nsp; k++) {
    const rl_species_ff *s = &species[k];
    ff->type_off[k] = t;
    ff->sp_nsites[k] = s->nsites;
    const char *name = rl_system_species_name(sys, k);
    snprintf(ff->sp_name[k], sizeof ff->sp_name[k], "%s", name ? name : "");
    for (int a = 0; a < s->nsites; a++, t++) {
      ff->sig[t] = s->sigma[a];
      ff->eps[t] = s->epsilon[a];
      ff->q[t] = s->charge[a];
      ff->mu[t] = s->dipole ? s->dipole[a] : 0.0;
      ff->Q[t] = s->quadrupole ? s->quadrupole[a] : 0.0;
      ff->type_species[t] = k;
      ff->type_site[t] = a;
      if (ff->mu[t] != 0.0) ff->any_dipole = 1;
      if (ff->Q[t] != 0.0) ff->any_quad = 1;
    }
    if (first_body[k] >= 0) {
      double ext = species_extent(sys, first_body[k], s->nsites, ff->tsite + ff->type_off[k]);
      if (ext < 0.0) {
        free(first_body);
        rl_forcefield_free(ff);
        rl_error(RL_ENOMEM, "forcefield: out of memory");
        return NULL;
      }
      ff->extent = fmax(ff->extent, ext);
      ff->sp_extent[k] = ext;
    }
  }
  free(first_body);
  for (int a = 0; a < ntypes; a++)
    for (int b = a; b < ntypes; b++)
      lj_mix(ff, a, b, 0.5 * (ff->sig[a] + ff->sig[b]), sqrt(ff->eps[a] * ff->eps[b]));
  rl_rf_coef_init(&ff->rf, p->eps_rf, p->cutoff);
  /* Ewald: point dipoles only as Stockmayer particles (one uncharged site, at the centre) in a
   * scene without charges: the pair routines have dipole-dipole Ewald pairs, not charge-dipole
   * ones nor off-centre dipoles (the term "ewald-real" has them) */
  int charged = 0;
  for (int a = 0; a < ntypes; a++) charged |= ff->q[a] != 0.0;
  for (int a = 0; a < ntypes && p->coulomb == RL_COULOMB_EWALD_REAL; a++) {
    if (ff->mu[a] != 0.0 && (ff->sp_nsites[ff->type_species[a]] != 1 || charged)) {
      const int ka = ff->type_species[a], sa = ff->type_site[a];
      rl_forcefield_free(ff);
      rl_error(RL_EINVAL, "forcefield: species %d site %d carries a point dipole: the Ewald real space "
               "(coulomb = ewald) takes point dipoles only on one-site species in a scene without charges "
               "(the term ewald-real takes the others)", ka, sa);
      return NULL;
    }
  }
  for (int i = 0; i < n; i++) {
    int k = rl_system_species_of(sys, i);
    ff->body_species[i] = k;
    ff->body_site_off[i] = rl_system_site_offset(sys, i);
    ff->body_rot[i] = rl_system_rot_index(sys, i);
    for (int a = 0; a < ff->sp_nsites[k]; a++)
      ff->site_type[ff->body_site_off[i] + a] = ff->type_off[k] + a;
  }
  ff->skin = p->skin < 0.0 ? 0.1 * p->cutoff : p->skin;
  ff->min_distance = p->min_distance < 0.0 ? 1e-3 * p->cutoff : p->min_distance;
  ff->rlist = p->cutoff + ff->skin + (p->scheme == RL_CUTOFF_SITE ? 2.0 * ff->extent : 0.0);
  if (p->neighbor_list) {
    ff->nl = rl_nlist_alloc(ff->skin);
    if (!ff->nl) { rl_forcefield_free(ff); return NULL; }
  }
  update_dispersion(ff);
  if (rl_ff_fast_setup(ff)) { rl_forcefield_free(ff); return NULL; }
  return ff;
}

int rl_forcefield_set_lj_pair(rl_forcefield *ff, int ka, int a, int kb, int b, double sigma,
                              double epsilon)
{
  if (!ff) return rl_error(RL_EINVAL, "rl_forcefield_set_lj_pair: NULL force field");
  if (ka < 0 || ka >= ff->nspecies || kb < 0 || kb >= ff->nspecies)
    return rl_error(RL_EINVAL, "forcefield: LJ pair override for species %d - %d: no such "
                    "species (%d species)", ka, kb, ff->nspecies);
  if (a < 0 || a >= ff->sp_nsites[ka] || b < 0 || b >= ff->sp_nsites[kb])
    return rl_error(RL_EINVAL, "forcefield: LJ pair override species %d site %d - species %d "
                    "site %d: no such site", ka, a, kb, b);
  if (!(sigma >= 0.0) || !(epsilon >= 0.0) || !isfinite(sigma) || !isfinite(epsilon))
    return rl_error(RL_EINVAL, "forcefield: LJ pair override species %d site %d - species %d "
                    "site %d: sigma %g and epsilon %g must be finite and >= 0", ka, a, kb, b,
                    sigma, epsilon);
  lj_mix(ff, ff->type_off[ka] + a, ff->type_off[kb] + b, sigma, epsilon);
  update_dispersion(ff);
  return rl_ff_fast_setup(ff); /* an override may break a kernel's site pattern */
}

int rl_ff_take_box(rl_forcefield *ff, const rl_system *sys)
{
  double L[3];
  rl_system_box(sys, L);
  rl_box box;
  int st = rl_system_periodic(sys) ? rl_box_set(&box, L)
           : rl_error(RL_EINVAL, "forcefield: the system no longer has a periodic box");
  if (st) return st;
  st = check_cutoff(&box, ff->p.cutoff);
  if (st) return st;
  ff->box = box;
  ff->box_version = rl_system_box_version(sys);
  return RL_OK; /* the lists stay (their rule follows the box: pairlist.h) */
}

void rl_forcefield_get_box(const rl_forcefield *ff, double L[3])
{
  memcpy(L, ff->box.L, sizeof ff->box.L);
}

long rl_forcefield_rebuilds(const rl_forcefield *ff)
{
  return (ff->nl ? ff->nl->builds : 0) + rl_ff_fast_builds(ff->fast);
}
const char *rl_forcefield_kernel(const rl_forcefield *ff)
{
  return ff->fast ? rl_ff_fast_name(ff->fast) : "general";
}
const char *rl_forcefield_pair_kernel(const rl_forcefield *ff, int a, int b)
{
  if (a < 0 || b < 0 || a >= ff->nspecies || b >= ff->nspecies) return NULL;
  const char *k = ff->fast && a == b ? rl_ff_fast_species(ff->fast, a) : NULL; /* the lists: same species only */
  return k ? k : "general";
}
const char *rl_forcefield_rows(const rl_forcefield *ff)
{
  return ff->fast ? rl_ff_fast_rows(ff->fast) : "portable";
}
const char *rl_forcefield_precision(const rl_forcefield *ff)
{
  return ff->fast && rl_ff_fast_mixed(ff->fast) ? "mixed" : "double";
}
int rl_forcefield_threads(const rl_forcefield *ff) { return ff->fast ? rl_ff_fast_threads(ff->fast) : 1; }
double rl_forcefield_list_radius(const rl_forcefield *ff) { return ff->rlist; }

/* The build state of the list a checkpoint stores (the kernels', else the reference one), or
 * NULL while it has none. */
static const rl_nlist *list_state(const rl_forcefield *ff)
{
  const rl_nlist *nl = ff->fast ? rl_ff_fast_list(ff->fast) : ff->nl;
  return nl && nl->n == ff->n && nl->r0 && ff->n > 0 ? nl : NULL;
}

int rl_forcefield_list_origin(const rl_forcefield *ff, double (*r0)[3])
{
  const rl_nlist *nl = list_state(ff);
  if (!nl) return 0;
  memcpy(r0, nl->r0, sizeof *r0 * (size_t)ff->n);
  return 1;
}

int rl_forcefield_list_box(const rl_forcefield *ff, double L0[3])
{
  const rl_nlist *nl = list_state(ff);
  if (!nl) return 0;
  memcpy(L0, nl->L0, sizeof nl->L0);
  return 1;
}

int rl_forcefield_set_list_box(rl_forcefield *ff, const double L0[3])
{
  rl_box b;
  if (rl_box_set(&b, L0) || check_cutoff(&b, ff->p.cutoff))
    return rl_error_wrap(RL_EINVAL, "forcefield: the list's box %g %g %g", L0[0], L0[1], L0[2]);
  memcpy(ff->origin_L, L0, sizeof ff->origin_L);
  return RL_OK;
}

int rl_ff_origin_box(const rl_forcefield *ff, rl_box *box)
{
  if (!(ff->origin_L[0] > 0.0)) {
    *box = ff->box;
    return RL_OK;
  }
  return rl_box_set(box, ff->origin_L);
}

int rl_forcefield_set_list_origin(rl_forcefield *ff, const double (*r0)[3])
{
  for (int i = 0; i < ff->n; i++)
    if (!isfinite(r0[i][0]) || !isfinite(r0[i][1]) || !isfinite(r0[i][2]))
      return rl_error(RL_EINVAL, "forcefield: list origin of body %d is not finite", i);
  if (!ff->origin && !(ff->origin = malloc(sizeof *ff->origin * (size_t)(ff->n > 0 ? ff->n : 1))))
    return rl_error(RL_ENOMEM, "forcefield: out of memory");
  memcpy(ff->origin, r0, sizeof *r0 * (size_t)ff->n);
  memset(ff->origin_L, 0, sizeof ff->origin_L); /* the current box, unless set_list_box follows */
  return RL_OK;
}

void rl_forcefield_energies(const rl_forcefield *ff, rl_ff_energies *e) { *e = ff->e; }

double rl_forcefield_pressure(const rl_forcefield *ff, const rl_forces *f, double ke_trans)
{
  double V = rl_box_volume(&ff->box);
  return (2.0 * ke_trans + f->virial[0] + f->virial[4] + f->virial[8]) / (3.0 * V);
}

static int ff_compute_cb(void *ctx, const rl_system *sys, rl_forces *out)
{
  return rl_forcefield_compute((rl_forcefield *)ctx, sys, out);
}

rl_force_provider rl_forcefield_provider(rl_forcefield *ff)
{
  rl_force_provider pr = {ff_compute_cb, ff};
  return pr;
}

/* ------------------------------------------------------------------------- pair loop */

static inline void cross_add(double t[3], const double a[3], const double b[3], double s)
{
  t[0] += s * (a[1] * b[2] - a[2] * b[1]);
  t[1] += s * (a[2] * b[0] - a[0] * b[2]);
  t[2] += s * (a[0] * b[1] - a[1] * b[0]);
}

/* The pair terms, in the order their forces are summed. */
enum { TERM_LJ, TERM_COUL, TERM_DD, TERM_QD, TERM_QQ, NTERMS };
#define ALL_TERMS ((1u << NTERMS) - 1u)

/* The interactions in `mask` (bits 1 << TERM_*) of a site of type ta (its body's axis ea) with
 * one of type tb (axis eb) at separation r = r_a - r_b (r2 = |r|^2): each term's energy is added
 * to *e[term], its force on a to f, and the direct (dipole, quadrupole) torques to ka, kb. */
static inline void site_terms(const rl_forcefield *ff, int ta, int tb, const double r[3],
                              double r2, const double ea[3], const double eb[3], unsigned mask,
                              double *const e[NTERMS], double f[3], double ka[3], double kb[3])
{
  const rl_lj_coef *lj = &ff->lj[ta * ff->ntypes + tb];
  if ((mask & 1u << TERM_LJ) && lj->epsilon != 0.0) {
    double fs;
    *e[TERM_LJ] += rl_lj_pair(lj, r2, &fs);
    for (int c = 0; c < 3; c++) f[c] += fs * r[c];
  }
  double qa = ff->q[ta], qb = ff->q[tb];
  if ((mask & 1u << TERM_COUL) && qa != 0.0 && qb != 0.0) {
    double fs;
    *e[TERM_COUL] += ff->p.coulomb == RL_COULOMB_EWALD_REAL
                         ? rl_coulomb_ewald_pair(ff->p.ewald_alpha, ff->kc * qa * qb, r2, &fs)
                         : rl_coulomb_rf_pair(&ff->rf, ff->kc * qa * qb, r2, &fs);
    for (int c = 0; c < 3; c++) f[c] += fs * r[c];
  }
  double ma = ff->mu[ta], mb = ff->mu[tb];
  if ((mask & (1u << TERM_DD | 1u << TERM_QD)) && (ma != 0.0 || mb != 0.0)) {
    double mua[3], mub[3], fp[3], ga[3], gb[3];
    for (int c = 0; c < 3; c++) { mua[c] = ma * ea[c]; mub[c] = mb * eb[c]; }
    int sf = ff->p.dipole_method == RL_DIPOLE_SF;
    if ((mask & 1u << TERM_DD) && ma != 0.0 && mb != 0.0) {
      *e[TERM_DD] += ff->p.coulomb == RL_COULOMB_EWALD_REAL
                         ? rl_dipole_dipole_ewald(ff->kc, ff->p.ewald_alpha, r, mua, mub, fp, ga, gb)
                     : sf ? rl_dipole_dipole_sf(ff->kc, ff->p.cutoff, r, mua, mub, fp, ga, gb)
                          : rl_dipole_dipole_rf(ff->kc, ff->rf.krf, r, mua, mub, fp, ga, gb);
      for (int c = 0; c < 3; c++) f[c] += fp[c];
      cross_add(ka, mua, ga, -1.0);
      cross_add(kb, mub, gb, -1.0);
    }
    if ((mask & 1u << TERM_QD) && qa != 0.0 && mb != 0.0) { /* charge at a, dipole at b */
      *e[TERM_QD] += sf ? rl_charge_dipole_sf(ff->kc, ff->p.cutoff, r, qa, mub, fp, gb)
                        : rl_charge_dipole_rf(ff->kc, ff->rf.krf, r, qa, mub, fp, gb);
      for (int c = 0; c < 3; c++) f[c] += fp[c];
      cross_add(kb, mub, gb, -1.0);
    }
    if ((mask & 1u << TERM_QD) && ma != 0.0 && qb != 0.0) { /* dipole at a, charge at b */
      double rm[3] = {-r[0], -r[1], -r[2]}; /* r_charge - r_dipole */
      *e[TERM_QD] += sf ? rl_charge_dipole_sf(ff->kc, ff->p.cutoff, rm, qb, mua, fp, ga)
                        : rl_charge_dipole_rf(ff->kc, ff->rf.krf, rm, qb, mua, fp, ga);
      for (int c = 0; c < 3; c++) f[c] -= fp[c]; /* fp is the force on the charge (b) */
      cross_add(ka, mua, ga, -1.0);
    }
  }
  double Qa = ff->Q[ta], Qb = ff->Q[tb];
  if ((mask & 1u << TERM_QQ) && Qa != 0.0 && Qb != 0.0) {
    double fp[3], ga[3], gb[3];
    *e[TERM_QQ] += rl_quadrupole_quadrupole(ff->kc, r, Qa, ea, Qb, eb, fp, ga, gb);
    for (int c = 0; c < 3; c++) f[c] += fp[c];
    cross_add(ka, ea, ga, -1.0);
    cross_add(kb, eb, gb, -1.0);
  }
}

/* All interactions of site sa (body i) with site sb (body j), separation r = r_sa - r_sb,
 * centre vector R = r_i - r_j consistent with it. */
static int site_pair(rl_forcefield *ff, int i, int j, int sa, int sb, const double r[3],
                     const double R[3], rl_acc *acc)
{
  double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
  if (r2 < ff->min_distance * ff->min_distance) {
    if (acc->quiet) { acc->s.bad = 1; return RL_EINVAL; }
    return rl_error(RL_EINVAL, "forcefield: overlapping sites: site %d of body %d and site %d of "
                    "body %d are %g apart (minimum %g)", sa - ff->body_site_off[i], i,
                    sb - ff->body_site_off[j], j, sqrt(r2), ff->min_distance);
  }
  double *const e[NTERMS] = {&acc->s.lj, &acc->s.coul, &acc->s.dip, &acc->s.dip, &acc->s.quad};
  double f[3] = {0.0, 0.0, 0.0};
  site_terms(ff, ff->site_type[sa], ff->site_type[sb], r, r2, ff->axis[i], ff->axis[j], ALL_TERMS,
             e, f, acc->tq[i], acc->tq[j]);
  for (int c = 0; c < 3; c++) {
    acc->fs[sa][c] += f[c];
    acc->fs[sb][c] -= f[c];
  }
  const double *Rv = acc->site_virial ? r : R;
  for (int x = 0; x < 3; x++)
    for (int y = 0; y < 3; y++) acc->s.vir[3 * x + y] += Rv[x] * f[y];
  return RL_OK;
}

int rl_ff_body_pair(rl_forcefield *ff, int i, int j, rl_acc *acc)
{
  int ki = ff->body_species[i], kj = ff->body_species[j];
  int ni = ff->sp_nsites[ki], nj = ff->sp_nsites[kj];
  if (ni == 0 || nj == 0) return RL_OK;
  int oi = ff->body_site_off[i], oj = ff->body_site_off[j];
  double rc2 = ff->p.cutoff * ff->p.cutoff;
  double R[3] = {ff->centre[i][0] - ff->centre[j][0], ff->centre[i][1] - ff->centre[j][1],
                 ff->centre[i][2] - ff->centre[j][2]};
  rl_box_minimum_image(&ff->box, R);
  if (ff->p.scheme == RL_CUTOFF_MOLECULE) {
    if (R[0] * R[0] + R[1] * R[1] + R[2] * R[2] >= rc2) return RL_OK;
    for (int a = 0; a < ni; a++)
      for (int b = 0; b < nj; b++) {
        const double *da = ff->dsite[oi + a], *db = ff->dsite[oj + b];
        double r[3] = {R[0] + da[0] - db[0], R[1] + da[1] - db[1], R[2] + da[2] - db[2]};
        int st = site_pair(ff, i, j, oi + a, oj + b, r, R, acc);
        if (st) return st;
      }
  } else {
    for (int a = 0; a < ni; a++)
      for (int b = 0; b < nj; b++) {
        const double *sa = ff->site[oi + a], *sb = ff->site[oj + b];
        double r[3] = {sa[0] - sb[0], sa[1] - sb[1], sa[2] - sb[2]};
        rl_box_minimum_image(&ff->box, r);
        if (r[0] * r[0] + r[1] * r[1] + r[2] * r[2] >= rc2) continue;
        const double *da = ff->dsite[oi + a], *db = ff->dsite[oj + b];
        double Rs[3] = {r[0] - da[0] + db[0], r[1] - da[1] + db[1], r[2] - da[2] + db[2]};
        int st = site_pair(ff, i, j, oi + a, oj + b, r, Rs, acc);
        if (st) return st;
      }
  }
  return RL_OK;
}

/* Optional (intramolecular_rf = 1, GROMACS's convention; OpenMM 7.7 adds nothing): kc q_a q_b
 * (krf r^2 - crf) for every charge pair within one molecule, whatever its distance.  Central forces: no net force or torque on a
 * rigid body, but they are added to the site forces all the same. */
static double intramolecular_rf(rl_forcefield *ff)
{
  double e = 0.0;
  for (int i = 0; i < ff->n; i++) {
    int ns = ff->sp_nsites[ff->body_species[i]], o = ff->body_site_off[i];
    for (int a = 0; a < ns; a++)
      for (int b = a + 1; b < ns; b++) {
        double qa = ff->q[ff->site_type[o + a]], qb = ff->q[ff->site_type[o + b]];
        if (qa == 0.0 || qb == 0.0) continue;
        double r[3], fs;
        for (int c = 0; c < 3; c++) r[c] = ff->site[o + a][c] - ff->site[o + b][c];
        e += rl_coulomb_rf_excluded(&ff->rf, ff->kc * qa * qb,
                                    r[0] * r[0] + r[1] * r[1] + r[2] * r[2], &fs);
        for (int c = 0; c < 3; c++) {
          ff->fs[o + a][c] += fs * r[c];
          ff->fs[o + b][c] -= fs * r[c];
        }
      }
  }
  return e;
}

/* The reference pair loop: every listed (or, without a list, every) body pair through
 * rl_ff_body_pair, serially, in list order.  `rebuild` forces a fresh list (the fast path keeps
 * its own list, so after it the reference list may be stale). */
static int reference_pairs(rl_forcefield *ff, rl_acc *acc, int rebuild)
{
  int n = ff->n, st = RL_OK;
  if (ff->nl) {
    if (ff->origin && !rebuild) { /* a restart: the list the run had (list_origin, list_box) */
      rl_box ob;
      st = rl_ff_origin_box(ff, &ob);
      if (!st) st = rl_nlist_build(ff->nl, &ob, ff->rlist, n, (const double(*)[3])ff->origin);
      free(ff->origin);
      ff->origin = NULL;
      if (st) return st;
    }
    if (rebuild ||
        rl_nlist_needs_rebuild(ff->nl, &ff->box, n, (const double(*)[3])ff->centre, NULL, 1)) {
      st = rl_nlist_build(ff->nl, &ff->box, ff->rlist, n, (const double(*)[3])ff->centre);
      if (st) return st;
    }
    for (long p = 0; p < ff->nl->npairs && !st; p++)
      st = rl_ff_body_pair(ff, ff->nl->pairs[p][0], ff->nl->pairs[p][1], acc);
  } else {
    for (int i = 0; i < n && !st; i++)
      for (int j = i + 1; j < n && !st; j++) st = rl_ff_body_pair(ff, i, j, acc);
  }
  return st;
}

/* Body i's centre, axis and sites (relative to the centre) from sys.  A non-finite one:
 * RL_ENONFINITE, with a message unless quiet. */
static int take_body(rl_forcefield *ff, const rl_system *sys, int i, int quiet)
{
  rl_system_get_position(sys, i, ff->centre[i]);
  rl_system_get_axis(sys, i, ff->axis[i]);
  const double *r = ff->centre[i], *u = ff->axis[i];
  if (!isfinite(r[0]) || !isfinite(r[1]) || !isfinite(r[2]))
    return quiet ? RL_ENONFINITE
                 : rl_error(RL_ENONFINITE, "forcefield: body %d (species %d) has a non-finite "
                            "position (%g, %g, %g)", i, ff->body_species[i], r[0], r[1], r[2]);
  if (!isfinite(u[0]) || !isfinite(u[1]) || !isfinite(u[2]))
    return quiet ? RL_ENONFINITE
                 : rl_error(RL_ENONFINITE, "forcefield: body %d (species %d) has a non-finite "
                            "orientation", i, ff->body_species[i]);
  int ns = ff->sp_nsites[ff->body_species[i]], o = ff->body_site_off[i];
  for (int a = 0; a < ns; a++) {
    const double *s = ff->site[o + a];
    if (!isfinite(s[0]) || !isfinite(s[1]) || !isfinite(s[2]))
      return quiet ? RL_ENONFINITE
                   : rl_error(RL_ENONFINITE, "forcefield: body %d (species %d) site %d has a "
                              "non-finite position (%g, %g, %g)", i, ff->body_species[i], a,
                              s[0], s[1], s[2]);
    for (int c = 0; c < 3; c++) ff->dsite[o + a][c] = s[c] - r[c];
  }
  return RL_OK;
}

int rl_forcefield_compute(rl_forcefield *ff, const rl_system *sys, rl_forces *out)
{
  if (!ff || !sys || !out) return rl_error(RL_EINVAL, "rl_forcefield_compute: NULL argument");
  if (rl_system_count(sys) != ff->n || rl_system_nsites(sys) != ff->nsites ||
      rl_system_nspecies(sys) != ff->nspecies)
    return rl_error(RL_ESTATE, "forcefield: the system changed since the force field was made "
                    "(%d bodies, %d sites, %d species; now %d, %d, %d)", ff->n, ff->nsites,
                    ff->nspecies, rl_system_count(sys), rl_system_nsites(sys),
                    rl_system_nspecies(sys));
  if (rl_system_box_version(sys) != ff->box_version) { /* the system's cell changed */
    const int st = rl_ff_take_box(ff, sys);
    if (st) return st;
  }
  int n = ff->n;
  /* the bodies on the pair loop's threads, each a contiguous share: its sites, the checks, and
   * its rows of the site forces and torques zeroed; the first bad body is taken again for its
   * message (rl_error's buffer is the calling thread's) */
  const int T = rl_forcefield_threads(ff);
  (void)T; /* a build without OpenMP */
  int first = n;
#ifdef _OPENMP
#pragma omp parallel num_threads(T) if (T > 1 && n >= RL_THREAD_MIN_BODIES) reduction(min : first)
#endif
  {
    int i0, i1;
    rl_thread_range(n, &i0, &i1);
    rl_system_site_positions_of(sys, i0, i1, ff->site);
    for (int i = i0; i < i1; i++)
      if (take_body(ff, sys, i, 1) && i < first) first = i;
    const int s0 = i0 < n ? ff->body_site_off[i0] : ff->nsites;
    const int s1 = i1 < n ? ff->body_site_off[i1] : ff->nsites;
    if (s1 > s0) memset(ff->fs + s0, 0, sizeof *ff->fs * (size_t)(s1 - s0));
    if (i1 > i0) memset(ff->tq + i0, 0, sizeof *ff->tq * (size_t)(i1 - i0));
  }
  if (first < n) return take_body(ff, sys, first, 0);
  rl_acc acc;
  memset(&acc, 0, sizeof acc);
  acc.fs = ff->fs;
  acc.tq = ff->tq;
  acc.forces_only = out->forces_only != 0;
  int st = ff->fast ? rl_ff_fast_compute(ff, &acc) : 1;
  if (st > 0) { /* the reference path, or a rerun of it that reports an overlap */
    memset(ff->fs, 0, sizeof *ff->fs * (size_t)ff->nsites);
    memset(ff->tq, 0, sizeof *ff->tq * (size_t)n);
    memset(&acc, 0, sizeof acc);
    acc.fs = ff->fs;
    acc.tq = ff->tq;
    st = reference_pairs(ff, &acc, ff->fast != NULL);
  }
  if (st) return st;
  /* did any site pair interact?  (the first site force or torque that is not 0 says so) */
  ff->last_pairs = 0;
  for (int a = 0; a < ff->nsites && !ff->last_pairs; a++)
    ff->last_pairs = ff->fs[a][0] != 0.0 || ff->fs[a][1] != 0.0 || ff->fs[a][2] != 0.0;
  for (int i = 0; i < n && !ff->last_pairs; i++)
    ff->last_pairs = ff->tq[i][0] != 0.0 || ff->tq[i][1] != 0.0 || ff->tq[i][2] != 0.0;
  double e_intra = ff->p.intramolecular_rf ? intramolecular_rf(ff) : 0.0;
  double V = rl_box_volume(&ff->box);
  double e_disp = 2.0 * M_PI / V * ff->disp_e;
  double p_disp = -2.0 * M_PI / (3.0 * V * V) * ff->disp_w;

#ifdef _OPENMP
#pragma omp parallel num_threads(T) if (T > 1 && n >= RL_THREAD_MIN_BODIES)
#endif
  {
    int i0, i1;
    rl_thread_range(n, &i0, &i1);
    rl_system_add_site_forces_of(sys, (const double(*)[3])ff->fs, out, i0, i1);
    for (int i = i0; i < i1; i++) {
      int ri = ff->body_rot[i];
      if (ri < 0) continue;
      for (int c = 0; c < 3; c++) out->k[ri][c] += ff->tq[i][c];
    }
  }
  if (out->forces_only) { /* the energies were not summed (not all: the reference path's were) */
    const double nan = NAN;
    ff->e = (rl_ff_energies){nan, nan, nan, nan, nan, nan, nan, nan};
    return RL_OK;
  }
  ff->e.lj = acc.s.lj;
  ff->e.coulomb = acc.s.coul + e_intra;
  ff->e.coulomb_intra = e_intra;
  ff->e.dipolar = acc.s.dip;
  ff->e.quadrupolar = acc.s.quad;
  ff->e.dispersion = e_disp;
  ff->e.pressure_dispersion = p_disp;
  ff->e.total = acc.s.lj + acc.s.coul + e_intra + acc.s.dip + acc.s.quad + e_disp;
  out->energy += ff->e.total;
  for (int c = 0; c < 9; c++) out->virial[c] += acc.s.vir[c];
  for (int c = 0; c < 3; c++) out->virial[4 * c] += p_disp * V; /* tr = 3 V P_disp */
  return RL_OK;
}

/* ----------------------------------------------- setup warnings and the cutoff's discontinuities */

/* Two bodies of species ka and kb can meet: both exist, and a species meets itself only with
 * two bodies or more. */
static int can_meet(const rl_forcefield *ff, int ka, int kb)
{
  return ff->sp_count[ka] > 0 && ff->sp_count[kb] > 0 && (ka != kb || ff->sp_count[ka] > 1);
}

static const char *unit_energy(const rl_forcefield *ff) { return ff->units == RL_UNITS_LJ ? "epsilon" : "kJ/mol"; }
static const char *unit_length(const rl_forcefield *ff) { return ff->units == RL_UNITS_LJ ? "sigma" : "nm"; }
static const char *unit_force(const rl_forcefield *ff) { return ff->units == RL_UNITS_LJ ? "epsilon/sigma" : "kJ/mol/nm"; }

/* One line of text into buf (truncated to size - 1 characters). */
static void line(char *buf, size_t size, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, size, fmt, ap);
  va_end(ap);
}

/* "water site 0" (or "species 2 site 0" for a species without a name) */
static void site_label(const rl_forcefield *ff, int t, char *buf, size_t size)
{
  const int k = ff->type_species[t];
  if (ff->sp_name[k][0]) snprintf(buf, size, "%s site %d", ff->sp_name[k], ff->type_site[t]);
  else snprintf(buf, size, "species %d site %d", k, ff->type_site[t]);
}

/* The terms types ta and tb have between them (bits 1 << TERM_*), if their bodies can meet. */
static unsigned pair_terms(const rl_forcefield *ff, int ta, int tb)
{
  if (!can_meet(ff, ff->type_species[ta], ff->type_species[tb])) return 0;
  unsigned m = 0;
  if (ff->lj[ta * ff->ntypes + tb].epsilon != 0.0) m |= 1u << TERM_LJ;
  if (ff->q[ta] != 0.0 && ff->q[tb] != 0.0) m |= 1u << TERM_COUL;
  if (ff->mu[ta] != 0.0 && ff->mu[tb] != 0.0) m |= 1u << TERM_DD;
  if ((ff->q[ta] != 0.0 && ff->mu[tb] != 0.0) || (ff->mu[ta] != 0.0 && ff->q[tb] != 0.0)) m |= 1u << TERM_QD;
  if (ff->Q[ta] != 0.0 && ff->Q[tb] != 0.0) m |= 1u << TERM_QQ;
  return m;
}

int rl_forcefield_warnings(const rl_forcefield *ff, rl_ff_warning *out, int max)
{
  if (!ff) return 0;
  int n = 0;
  const double rc = ff->p.cutoff, well = pow(2.0, 1.0 / 6.0);
  int wa = -1, wb = -1, count = 0;
  unsigned any = 0;
  for (int ta = 0; ta < ff->ntypes; ta++)
    for (int tb = ta; tb < ff->ntypes; tb++) {
      const unsigned m = pair_terms(ff, ta, tb);
      any |= m;
      const rl_lj_coef *c = &ff->lj[ta * ff->ntypes + tb];
      if (!(m & 1u << TERM_LJ) || !(rc < well * c->sigma)) continue;
      count++;
      if (wa < 0 || c->sigma > ff->lj[wa * ff->ntypes + wb].sigma) { wa = ta; wb = tb; }
    }
  if (count) {
    const rl_lj_coef *c = &ff->lj[wa * ff->ntypes + wb];
    char la[48], lb[48], more[48] = "";
    site_label(ff, wa, la, sizeof la);
    site_label(ff, wb, lb, sizeof lb);
    if (count > 1) snprintf(more, sizeof more, " (and %d more site pairs)", count - 1);
    if (n < max)
      line(out[n].text, sizeof out[n].text, "the cutoff %g %s is shorter than %s of the "
               "Lennard-Jones pair %s - %s (sigma %g %s, epsilon %g %s)%s: %s", rc, unit_length(ff),
               rc < c->sigma ? "the sigma" : "the minimum at 2^(1/6) sigma", la, lb, c->sigma,
               unit_length(ff), c->epsilon, unit_energy(ff), more,
               rc < c->sigma ? "the attractive well and most of the repulsion are cut"
                             : "the attractive well is cut");
    n++;
  }
  if (ff->last_pairs == 0 && any) {
    if (n < max)
      line(out[n].text, sizeof out[n].text, "no pair of sites was within the cutoff %g %s at "
               "the last force computation: every intermolecular energy, force and torque is "
               "zero (the cutoff is shorter than the distances between the molecules' sites)",
               rc, unit_length(ff));
    n++;
  }
  return n;
}

/* A rotation for sample k: the 24 rotations of the cube (k < 24), which turn a body's axis onto
 * each lab axis (where the dipole and quadrupole extremes lie), then pseudo-random ones. */
static void rotation_sample(int k, double R[9])
{
  static const int perm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
  if (k < 24) { /* signed permutation matrices with determinant +1 */
    for (int idx = 0, found = 0; idx < 48; idx++) {
      const int p = idx / 8, sg = idx % 8, odd = p >= 3;
      const int neg = (sg & 1) + (sg >> 1 & 1) + (sg >> 2 & 1);
      if ((odd + neg) % 2) continue; /* det = (-1)^(odd + neg) */
      if (found++ < k) continue;
      memset(R, 0, 9 * sizeof *R);
      for (int r = 0; r < 3; r++) R[3 * r + perm[p][r]] = (sg >> r & 1) ? -1.0 : 1.0;
      return;
    }
  }
  uint64_t s = 0x243F6A8885A308D3ull * (uint64_t)(k + 1), z;
  double q[4], n2;
  do { /* uniform in the 4-ball, then onto the sphere: a uniform rotation */
    n2 = 0.0;
    for (int c = 0; c < 4; c++) {
      s += 0x9E3779B97F4A7C15ull; /* splitmix64 */
      z = (s ^ (s >> 30)) * 0xBF58476D1CE4E5B9ull;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
      q[c] = 2.0 * ((double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53) - 1.0;
      n2 += q[c] * q[c];
    }
  } while (n2 > 1.0 || n2 < 1e-6);
  const double w = q[0], x = q[1], y = q[2], zz = q[3], sc = 2.0 / n2;
  R[0] = 1 - sc * (y * y + zz * zz); R[1] = sc * (x * y - w * zz);     R[2] = sc * (x * zz + w * y);
  R[3] = sc * (x * y + w * zz);     R[4] = 1 - sc * (x * x + zz * zz); R[5] = sc * (y * zz - w * x);
  R[6] = sc * (x * zz - w * y);     R[7] = sc * (y * zz + w * x);     R[8] = 1 - sc * (x * x + y * y);
}

enum { JUMP_SAMPLES = 64 }; /* rotations per body: 24 of the cube, 40 random */

/* The largest |energy| and |force| of term `t` where a pair crosses the cutoff, over pairs of
 * orientations: for the site cutoff, each site pair at r = rc (orientations move only the axes);
 * for the molecule cutoff, each molecule pair at centre distance rc, summed over its site pairs
 * (a sample with sites closer than min_distance is skipped). */
static void jump_size(const rl_forcefield *ff, int t, double *emax, double *fmax_)
{
  const double rc = ff->p.cutoff;
  const int mol = ff->p.scheme == RL_CUTOFF_MOLECULE;
  const int isotropic = !mol && (t == TERM_LJ || t == TERM_COUL); /* one sample is enough */
  double Ri[9], Rj[9], k1[3], k2[3];
  *emax = *fmax_ = 0.0;
  for (int ka = 0; ka < ff->nspecies; ka++)
    for (int kb = ka; kb < ff->nspecies; kb++) {
      const int oa = ff->type_off[ka], ob = ff->type_off[kb];
      unsigned has = 0;
      for (int a = 0; a < ff->sp_nsites[ka]; a++)
        for (int b = 0; b < ff->sp_nsites[kb]; b++) has |= pair_terms(ff, oa + a, ob + b);
      if (!(has & 1u << t)) continue;
      const int ns = isotropic ? 1 : JUMP_SAMPLES;
      for (int si = 0; si < ns; si++)
        for (int sj = 0; sj < ns; sj++) {
          rotation_sample(si, Ri);
          rotation_sample(sj, Rj);
          const double ea[3] = {Ri[2], Ri[5], Ri[8]}, eb[3] = {Rj[2], Rj[5], Rj[8]}; /* R z */
          double e = 0.0, f[3] = {0.0, 0.0, 0.0};
          double *const ep[NTERMS] = {&e, &e, &e, &e, &e};
          int skip = 0;
          for (int a = 0; a < ff->sp_nsites[ka] && !skip; a++)
            for (int b = 0; b < ff->sp_nsites[kb] && !skip; b++) {
              if (!(pair_terms(ff, oa + a, ob + b) & 1u << t)) continue;
              double r[3] = {0.0, 0.0, rc};
              if (mol) {
                const double *da = ff->tsite[oa + a], *db = ff->tsite[ob + b];
                for (int c = 0; c < 3; c++)
                  r[c] += Ri[3 * c] * da[0] + Ri[3 * c + 1] * da[1] + Ri[3 * c + 2] * da[2] -
                          (Rj[3 * c] * db[0] + Rj[3 * c + 1] * db[1] + Rj[3 * c + 2] * db[2]);
              }
              const double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
              if (r2 < ff->min_distance * ff->min_distance) { skip = 1; break; }
              if (!mol) { /* each site pair on its own */
                e = 0.0;
                f[0] = f[1] = f[2] = 0.0;
              }
              site_terms(ff, oa + a, ob + b, r, r2, ea, eb, 1u << t, ep, f, k1, k2);
              if (!mol) {
                *emax = fmax(*emax, fabs(e));
                *fmax_ = fmax(*fmax_, sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
              }
            }
          if (mol && !skip) {
            *emax = fmax(*emax, fabs(e));
            *fmax_ = fmax(*fmax_, sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
          }
        }
    }
}

int rl_forcefield_discontinuities(const rl_forcefield *ff, rl_ff_discontinuity *out, int max)
{
  if (!ff) return 0;
  static const char *const names[NTERMS] = {"lj", "coulomb", "dipole-dipole", "charge-dipole", "quadrupole"};
  const rl_ff_params *p = &ff->p;
  const int mol = p->scheme == RL_CUTOFF_MOLECULE, sf = p->dipole_method == RL_DIPOLE_SF;
  const int inf = isinf(p->eps_rf);
  const double tol = 1e-9 * p->cutoff;
  unsigned present = 0, offcentre = 0;
  for (int ta = 0; ta < ff->ntypes; ta++)
    for (int tb = ta; tb < ff->ntypes; tb++) {
      const unsigned m = pair_terms(ff, ta, tb);
      present |= m;
      const double *da = ff->tsite[ta], *db = ff->tsite[tb];
      if (sqrt(da[0] * da[0] + da[1] * da[1] + da[2] * da[2]) > tol ||
          sqrt(db[0] * db[0] + db[1] * db[1] + db[2] * db[2]) > tol)
        offcentre |= m;
    }
  static const char *const trunc[4] = {"plain", "shifted", "shifted-force", "switched"};
  const char *cut = mol ? ", molecule cutoff" : "", *pair = mol ? "molecule" : "site";
  int n = 0;
  for (int t = 0; t < NTERMS; t++) {
    if (!(present & 1u << t)) continue;
    /* the site pair's own form at r = rc (docs/interactions.md derives each) */
    int ej = 0, fj = 0, aniso = t == TERM_DD || t == TERM_QD || t == TERM_QQ;
    char label[96];
    const char *fix = "";
    switch (t) {
    case TERM_LJ:
      ej = p->lj_truncation == RL_LJ_PLAIN;
      fj = ej || p->lj_truncation == RL_LJ_SHIFTED;
      snprintf(label, sizeof label, "Lennard-Jones (%s%s)", trunc[p->lj_truncation], cut);
      fix = "lj = shifted-force or switched";
      break;
    case TERM_COUL:
      if (p->coulomb == RL_COULOMB_EWALD_REAL) { /* kc q q erfc(alpha rc) / rc: as small as the tolerance asks */
        ej = fj = 1;
        snprintf(label, sizeof label, "Coulomb Ewald real space (alpha = %g, plain cutoff)", p->ewald_alpha);
        fix = NULL;
        break;
      }
      fj = !inf;
      snprintf(label, sizeof label, "Coulomb reaction field (eps_rf = %g%s)", p->eps_rf, cut);
      fix = inf ? "" : "eps_rf = inf";
      break;
    case TERM_DD:
    case TERM_QD:
      if (p->coulomb == RL_COULOMB_EWALD_REAL) { /* the screened B_1, B_2 at rc: as small as the tolerance asks */
        ej = fj = 1;
        snprintf(label, sizeof label, "%s Ewald real space (alpha = %g, plain cutoff)", names[t], p->ewald_alpha);
        fix = NULL;
        break;
      }
      ej = !sf && (t == TERM_DD || !inf);
      fj = !sf;
      if (sf) snprintf(label, sizeof label, "%s shifted force%s", names[t], cut);
      else snprintf(label, sizeof label, "%s reaction field (eps_rf = %g%s)", names[t], p->eps_rf, cut);
      fix = sf ? "" : "dipole = sf";
      break;
    default:
      ej = fj = 1;
      snprintf(label, sizeof label, "quadrupole-quadrupole (plain truncation%s)", cut);
      fix = NULL; /* none */
      break;
    }
    char remedy[96];
    if (!fix && (t == TERM_COUL || p->coulomb == RL_COULOMB_EWALD_REAL))
      line(remedy, sizeof remedy, "a smaller interactions.ewald_tolerance makes it smaller");
    else if (!fix)
      line(remedy, sizeof remedy, "no continuous form is offered (the jump falls as cutoff^-5)");
    else if (mol && (offcentre & 1u << t)) /* whole molecules enter: sites at r != rc */
      line(remedy, sizeof remedy, "interactions.scheme = site%s%s is continuous", *fix ? " with " : "", fix);
    else
      line(remedy, sizeof remedy, "interactions.%s is continuous", fix);
    if (mol && (offcentre & 1u << t)) ej = fj = aniso = 1;
    rl_ff_discontinuity d = {names[t], ej, ej && aniso, fj, 0.0, 0.0, ""};
    if (ej || fj) {
      double e, f;
      jump_size(ff, t, &e, &f);
      d.energy_jump = ej ? e : 0.0;
      d.force_jump = fj ? f : 0.0;
    }
    if (d.heats)
      line(d.text, sizeof d.text, "%s: the energy of a %s pair jumps at the cutoff by up to "
               "%.3g %s, by orientation, so an NVE run heats at any time step; %s", label, pair,
               d.energy_jump, unit_energy(ff), remedy);
    else if (ej)
      line(d.text, sizeof d.text, "%s: the energy of a %s pair jumps at the cutoff by %.3g %s at "
               "every crossing: the run conserves the shifted energy and calE reads high; %s",
               label, pair, d.energy_jump, unit_energy(ff), remedy);
    else if (fj)
      line(d.text, sizeof d.text, "%s: the force of a %s pair jumps at the cutoff by up to "
               "%.3g %s (the energy is continuous): an energy error that falls with the time "
               "step; %s", label, pair, d.force_jump, unit_force(ff), remedy);
    else
      line(d.text, sizeof d.text, "%s: energy and force are continuous at the cutoff", label);
    if (n < max) out[n] = d;
    n++;
  }
  int intra = 0;
  for (int k = 0; k < ff->nspecies && p->intramolecular_rf; k++) {
    int charged = 0;
    for (int a = 0; a < ff->sp_nsites[k]; a++) charged += ff->q[ff->type_off[k] + a] != 0.0;
    intra |= ff->sp_count[k] > 0 && charged > 1;
  }
  if (intra) {
    rl_ff_discontinuity d = {"coulomb-intramolecular", 0, 0, 0, 0.0, 0.0, ""};
    line(d.text, sizeof d.text, "intramolecular reaction field: a constant for rigid "
             "molecules, with no cutoff: continuous");
    if (n < max) out[n] = d;
    n++;
  }
  return n;
}

rl_species_ff rl_molecule_ff(const rl_molecule *m)
{
  rl_species_ff f = {m->nsites, m->sigma, m->epsilon, m->charge, m->has_dipole ? m->dipole : NULL,
                     m->has_quadrupole ? m->quadrupole : NULL};
  return f;
}
