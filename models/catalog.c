/* The catalogue of named rigid models.  Every number carries its source; conversions use
 * 1 kcal = 4.184 kJ, k_B = 0.00831446261815324 kJ/(mol K) (exact, SI 2019), 1 A = 0.1 nm, 1 D A = 0.0020819434 e nm^2.
 * The literature check behind these values is docs/catalog-sources.md. */
#include "rotleap/catalog.h"
#include "rotleap/error.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define KCAL 4.184
#define KB_KJ RL_KB_KJMOL /* eps/k_B in K to kJ/mol */
#define DEG (M_PI / 180.0)

/* Masses (amu), IUPAC standard atomic weights as used by OpenMM's force fields. */
#define M_H 1.008
#define M_C 12.011
#define M_N 14.007
#define M_O 15.9994

/* Site table a define() fills before rl_molecule_build turns it into a body frame. */
typedef struct {
  int n;
  const char *names[RL_MOLECULE_MAX_SITES];
  double pos[RL_MOLECULE_MAX_SITES][3], mass[RL_MOLECULE_MAX_SITES];
  double sigma[RL_MOLECULE_MAX_SITES], eps[RL_MOLECULE_MAX_SITES], q[RL_MOLECULE_MAX_SITES];
  double dip[RL_MOLECULE_MAX_SITES][3], quad[RL_MOLECULE_MAX_SITES];
  double inertia[3];
} site_table;

static int site(site_table *t, const char *name, double x, double y, double z, double mass,
                double sigma, double eps, double q)
{
  int a = t->n++;
  t->names[a] = name;
  t->pos[a][0] = x; t->pos[a][1] = y; t->pos[a][2] = z;
  t->mass[a] = mass; t->sigma[a] = sigma; t->eps[a] = eps; t->q[a] = q;
  return a;
}

static int finish(const rl_model *self, site_table *t, int force_general, rl_molecule *m)
{
  rl_molecule_def d = {self->name, t->n, t->names, &t->pos[0][0], t->mass, t->sigma, t->eps,
                       t->q, &t->dip[0][0], t->quad, {t->inertia[0], t->inertia[1], t->inertia[2]}, 0.0};
  return rl_molecule_build(&d, force_general, m);
}

/* ---- water: O at the origin, H in the xz plane, M on the bisector (nm, e, kJ/mol) ---- */
static void water(site_table *t, double roh, double angle_deg, double rom, double qh,
                  double sigma_nm, double eps_kj, int four_site)
{
  double half = 0.5 * angle_deg * DEG;
  double qo = four_site ? 0.0 : -2.0 * qh;
  site(t, "O", 0, 0, 0, M_O, sigma_nm, eps_kj, qo);
  site(t, "H1", roh * sin(half), 0, roh * cos(half), M_H, 0, 0, qh);
  site(t, "H2", -roh * sin(half), 0, roh * cos(half), M_H, 0, 0, qh);
  if (four_site) site(t, "M", 0, 0, rom, 0.0, 0, 0, -2.0 * qh);
}

static int def_tip4p(const rl_model *s, const double *p, int fg, rl_molecule *m)
{ /* Jorgensen et al. 1983: sigma 3.15365 A, eps 0.1550 kcal/mol, O-M 0.15 A, q_H 0.52 */
  (void)p;
  site_table t = {0};
  water(&t, 0.09572, 104.52, 0.015, 0.52, 0.315365, 0.1550 * KCAL, 1);
  return finish(s, &t, fg, m);
}
static int def_tip4p_ew(const rl_model *s, const double *p, int fg, rl_molecule *m)
{ /* Horn et al. 2004: sigma 3.16435 A, eps 0.16275 kcal/mol, O-M 0.125 A, q_H 0.52422 */
  (void)p;
  site_table t = {0};
  water(&t, 0.09572, 104.52, 0.0125, 0.52422, 0.316435, 0.16275 * KCAL, 1);
  return finish(s, &t, fg, m);
}
static int def_tip4p_2005(const rl_model *s, const double *p, int fg, rl_molecule *m)
{ /* Abascal & Vega 2005: sigma 3.1589 A, eps/k 93.2 K, O-M 0.1546 A, q_H 0.5564 */
  (void)p;
  site_table t = {0};
  water(&t, 0.09572, 104.52, 0.01546, 0.5564, 0.31589, 93.2 * KB_KJ, 1);
  return finish(s, &t, fg, m);
}
static int def_spce(const rl_model *s, const double *p, int fg, rl_molecule *m)
{ /* Berendsen et al. 1987: O-H 1 A, H-O-H 109.47 deg, q_H 0.4238; LJ from the SPC A, C
     coefficients: sigma 0.316557 nm, eps 0.650194 kJ/mol (GROMACS spce.itp) */
  (void)p;
  site_table t = {0};
  water(&t, 0.1, 109.47, 0.0, 0.4238, 0.316557, 0.650194, 0);
  return finish(s, &t, fg, m);
}
static int def_tip3p(const rl_model *s, const double *p, int fg, rl_molecule *m)
{ /* Jorgensen et al. 1983: q_H 0.417, sigma 3.15061 A, eps 0.1521 kcal/mol */
  (void)p;
  site_table t = {0};
  water(&t, 0.09572, 104.52, 0.0, 0.417, 0.315061, 0.1521 * KCAL, 0);
  return finish(s, &t, fg, m);
}

/* ---- linear molecules ---- */
static int def_co2(const rl_model *s, const double *p, int fg, rl_molecule *m)
{ /* EPM2, Harris & Yung 1995: C-O 1.149 A; C: sigma 2.757 A, eps/k 28.129 K, q +0.6512;
     O: sigma 3.033 A, eps/k 80.507 K, q -0.3256 */
  (void)p;
  site_table t = {0};
  site(&t, "O1", 0, 0, -0.1149, M_O, 0.3033, 80.507 * KB_KJ, -0.3256);
  site(&t, "C", 0, 0, 0, M_C, 0.2757, 28.129 * KB_KJ, 0.6512);
  site(&t, "O2", 0, 0, 0.1149, M_O, 0.3033, 80.507 * KB_KJ, -0.3256);
  return finish(s, &t, fg, m);
}
static int def_n2(const rl_model *s, const double *p, int fg, rl_molecule *m)
{ /* 2CLJQ, Vrabec, Stoll & Hasse 2001: sigma 3.3211 A, eps/k 34.897 K, L 1.0464 A,
     Q 1.4397 D A (point quadrupole at the centre, along the axis) */
  (void)p;
  site_table t = {0};
  double L = 0.10464, sg = 0.33211, ep = 34.897 * KB_KJ;
  site(&t, "N1", 0, 0, -0.5 * L, M_N, sg, ep, 0);
  site(&t, "N2", 0, 0, 0.5 * L, M_N, sg, ep, 0);
  int c = site(&t, "Q", 0, 0, 0, 0.0, 0, 0, 0);
  t.quad[c] = 1.4397 * 0.0020819434;
  return finish(s, &t, fg, m);
}
/* A parameter without which the model has no meaning: the message names the parameter (the deck
 * reports it at its line) and what 0 would mean. */
static int positive_ok(const char *param, double x, const char *why)
{
  if (x > 0.0 && isfinite(x)) return 1;
  rl_error(RL_EINVAL, "%s %g must be positive (%s)", param, x, why);
  return 0;
}
/* The two-centre models need two distinct centres: at L* = 0 they would be one LJ site of depth
 * 4 eps with no rotation at all. */
#define ELONGATION_WHY "L* = 0 would put both LJ centres on one site"

static int def_2clj(const rl_model *s, const double *p, int fg, rl_molecule *m)
{ /* two LJ centres sigma = eps = 1, total mass 1, elongation L* = L/sigma */
  if (!positive_ok("elongation", p[0], ELONGATION_WHY)) return RL_EINVAL;
  site_table t = {0};
  site(&t, "A1", 0, 0, -0.5 * p[0], 0.5, 1.0, 1.0, 0);
  site(&t, "A2", 0, 0, 0.5 * p[0], 0.5, 1.0, 1.0, 0);
  return finish(s, &t, fg, m);
}
static int def_2cljq(const rl_model *s, const double *p, int fg, rl_molecule *m)
{ /* 2CLJ plus a point quadrupole Q* = Q/sqrt(eps sigma^5) at the centre along the axis */
  if (!positive_ok("elongation", p[0], ELONGATION_WHY)) return RL_EINVAL;
  site_table t = {0};
  site(&t, "A1", 0, 0, -0.5 * p[0], 0.5, 1.0, 1.0, 0);
  site(&t, "A2", 0, 0, 0.5 * p[0], 0.5, 1.0, 1.0, 0);
  int c = site(&t, "Q", 0, 0, 0, 0.0, 0, 0, 0);
  t.quad[c] = p[1];
  return finish(s, &t, fg, m);
}

/* ---- point dipole ---- */
static int def_stockmayer(const rl_model *s, const double *p, int fg, rl_molecule *m)
{ /* LJ sigma = eps = m = 1 plus a point dipole mu* = mu/sqrt(eps sigma^3); inertia I* (mu = 0:
     an LJ atom, whose inertia does not matter) */
  if (p[0] != 0.0 && !positive_ok("inertia", p[1], "a dipole with I* = 0 would have no rotational inertia; "
                                  "mu = 0 makes an LJ atom")) return RL_EINVAL;
  site_table t = {0};
  int a = site(&t, "S", 0, 0, 0, 1.0, 1.0, 1.0, 0);
  t.dip[a][2] = p[0];
  t.inertia[0] = t.inertia[1] = t.inertia[2] = p[1];
  return finish(s, &t, fg, m);
}

/* ---- tops ---- */
static int def_ch4(const rl_model *s, const double *p, int fg, rl_molecule *m)
{ /* OPLS-AA methane, Jorgensen, Maxwell & Tirado-Rives 1996: C-H 1.09 A, tetrahedral;
     C: sigma 3.50 A, eps 0.066 kcal/mol, q -0.24; H: sigma 2.50 A, eps 0.030 kcal/mol, q +0.06 */
  (void)p;
  site_table t = {0};
  double b = 0.109 / sqrt(3.0);
  site(&t, "C", 0, 0, 0, M_C, 0.350, 0.066 * KCAL, -0.24);
  site(&t, "H1", b, b, b, M_H, 0.250, 0.030 * KCAL, 0.06);
  site(&t, "H2", b, -b, -b, M_H, 0.250, 0.030 * KCAL, 0.06);
  site(&t, "H3", -b, b, -b, M_H, 0.250, 0.030 * KCAL, 0.06);
  site(&t, "H4", -b, -b, b, M_H, 0.250, 0.030 * KCAL, 0.06);
  return finish(s, &t, fg, m);
}
static int def_nh3(const rl_model *s, const double *p, int fg, rl_molecule *m)
{ /* Eckl, Vrabec & Hasse 2008: one LJ centre on N (sigma 3.376 A, eps/k 182.9 K) and point
     charges N -0.9993, H +0.3331; N-H 1.0136 A, H-N-H 105.99 deg (C3v) */
  (void)p;
  site_table t = {0};
  double r = 0.10136, ang = 105.99 * DEG;
  /* H atoms on a cone about z: |H_i - H_j| = 2 r sin(ang/2) = sqrt(3) rho */
  double rho = 2.0 * r * sin(0.5 * ang) / sqrt(3.0), z = sqrt(r * r - rho * rho);
  site(&t, "N", 0, 0, 0, M_N, 0.3376, 182.9 * KB_KJ, -0.9993);
  for (int k = 0; k < 3; k++) {
    static const char *hn[3] = {"H1", "H2", "H3"};
    double phi = 2.0 * M_PI * k / 3.0;
    site(&t, hn[k], rho * cos(phi), rho * sin(phi), -z, M_H, 0, 0, 0.3331);
  }
  return finish(s, &t, fg, m);
}

/* ---- atoms and ions: one LJ site (+ a charge) ---- */
static int def_argon(const rl_model *s, const double *p, int fg, rl_molecule *m)
{ /* Rahman 1964: sigma 3.405 A, eps/k 119.8 K; mass 39.948 (IUPAC) */
  (void)p;
  site_table t = {0};
  site(&t, "Ar", 0, 0, 0, 39.948, 0.3405, 119.8 * KB_KJ, 0);
  return finish(s, &t, fg, m);
}
/* Joung & Cheatham 2008, Table 5 (as AMBER's frcmod.ionsjc_{spce,tip3p,tip4pew}): Rmin/2 in A and
 * eps in kcal/mol; sigma = 2^(5/6) Rmin/2; masses 22.99 and 35.45 (AMBER's, OpenMM's) */
#define RMIN2_TO_SIGMA_NM(r) ((r) * pow(2.0, 5.0 / 6.0) * 0.1)
static int ion(const rl_model *s, const char *name, double mass, double q, double rmin2_A, double eps_kcal,
               int fg, rl_molecule *m)
{
  site_table t = {0};
  site(&t, name, 0, 0, 0, mass, RMIN2_TO_SIGMA_NM(rmin2_A), eps_kcal * KCAL, q);
  return finish(s, &t, fg, m);
}
#define ION(fn, site_name, mass, q, rmin2, eps)                                                          \
  static int fn(const rl_model *s, const double *p, int fg, rl_molecule *m)                            \
  {                                                                                                    \
    (void)p;                                                                                           \
    return ion(s, site_name, mass, q, rmin2, eps, fg, m);                                              \
  }
ION(def_na_spce, "Na", 22.99, 1.0, 1.212, 0.3526418)
ION(def_cl_spce, "Cl", 35.45, -1.0, 2.711, 0.0127850)
ION(def_na_tip3p, "Na", 22.99, 1.0, 1.369, 0.0874393)
ION(def_cl_tip3p, "Cl", 35.45, -1.0, 2.513, 0.0355910)
ION(def_na_tip4pew, "Na", 22.99, 1.0, 1.226, 0.1684375)
ION(def_cl_tip4pew, "Cl", 35.45, -1.0, 2.760, 0.0116615)

#define JC08 "I. S. Joung, T. E. Cheatham III, J. Phys. Chem. B 112, 9020 (2008), Table 5"
static const rl_model catalog[] = {
    {"stockmayer", "Stockmayer fluid: LJ + point dipole (reduced units)",
     "W. H. Stockmayer, J. Chem. Phys. 9, 398 (1941); I* = 0.025 is a conventional choice, adjustable",
     RL_UNITS_LJ, RL_KIND_DIPOLE, 0, 2, {"mu", "inertia"}, {"sqrt(eps sigma^3)", "m sigma^2"},
     {1.7320508075688772, 0.025}, def_stockmayer},
    {"2clj", "two-centre Lennard-Jones (reduced units)",
     "e.g. J. Vrabec, J. Stoll, H. Hasse, J. Phys. Chem. B 105, 12126 (2001) for the 2CLJ family",
     RL_UNITS_LJ, RL_KIND_LINEAR, 0, 1, {"elongation"}, {"sigma"}, {0.5}, def_2clj},
    {"2cljq", "two-centre Lennard-Jones + point quadrupole (reduced units)",
     "J. Stoll, J. Vrabec, H. Hasse, J. Fischer, Fluid Phase Equilib. 179, 339 (2001)",
     RL_UNITS_LJ, RL_KIND_LINEAR, 0, 2, {"elongation", "quadrupole"}, {"sigma", "sqrt(eps sigma^5)"},
     {0.5, 1.0}, def_2cljq},
    {"n2", "nitrogen, 2CLJQ", "J. Vrabec, J. Stoll, H. Hasse, J. Phys. Chem. B 105, 12126 (2001)",
     RL_UNITS_REAL, RL_KIND_LINEAR, 0, 0, {NULL}, {NULL}, {0}, def_n2},
    {"co2", "carbon dioxide, EPM2 (rigid)", "J. G. Harris, K. H. Yung, J. Phys. Chem. 99, 12021 (1995)",
     RL_UNITS_REAL, RL_KIND_LINEAR, 1, 0, {NULL}, {NULL}, {0}, def_co2},
    {"ch4", "methane, OPLS-AA 5-site", "W. L. Jorgensen, D. S. Maxwell, J. Tirado-Rives, J. Am. Chem. Soc. 118, 11225 (1996)",
     RL_UNITS_REAL, RL_KIND_SPHERICAL, 1, 0, {NULL}, {NULL}, {0}, def_ch4},
    {"nh3", "ammonia, 4-site (LJ on N, point charges)", "B. Eckl, J. Vrabec, H. Hasse, Mol. Phys. 106, 1039 (2008)",
     RL_UNITS_REAL, RL_KIND_SYMMETRIC, 0, 0, {NULL}, {NULL}, {0}, def_nh3},
    {"tip4p", "water, TIP4P", "W. L. Jorgensen et al., J. Chem. Phys. 79, 926 (1983)",
     RL_UNITS_REAL, RL_KIND_ASYMMETRIC, 0, 0, {NULL}, {NULL}, {0}, def_tip4p},
    {"tip4p-ew", "water, TIP4P-Ew", "H. W. Horn et al., J. Chem. Phys. 120, 9665 (2004)",
     RL_UNITS_REAL, RL_KIND_ASYMMETRIC, 0, 0, {NULL}, {NULL}, {0}, def_tip4p_ew},
    {"tip4p-2005", "water, TIP4P/2005", "J. L. F. Abascal, C. Vega, J. Chem. Phys. 123, 234505 (2005)",
     RL_UNITS_REAL, RL_KIND_ASYMMETRIC, 0, 0, {NULL}, {NULL}, {0}, def_tip4p_2005},
    {"spc-e", "water, SPC/E", "H. J. C. Berendsen, J. R. Grigera, T. P. Straatsma, J. Phys. Chem. 91, 6269 (1987)",
     RL_UNITS_REAL, RL_KIND_ASYMMETRIC, 0, 0, {NULL}, {NULL}, {0}, def_spce},
    {"tip3p", "water, TIP3P", "W. L. Jorgensen et al., J. Chem. Phys. 79, 926 (1983)",
     RL_UNITS_REAL, RL_KIND_ASYMMETRIC, 0, 0, {NULL}, {NULL}, {0}, def_tip3p},
    {"argon", "argon, Lennard-Jones atom", "A. Rahman, Phys. Rev. 136, A405 (1964)",
     RL_UNITS_REAL, RL_KIND_POINT, 0, 0, {NULL}, {NULL}, {0}, def_argon},
    {"na-spce", "Na+ for SPC/E water (Joung-Cheatham)", JC08, RL_UNITS_REAL, RL_KIND_POINT, 0, 0, {NULL}, {NULL}, {0}, def_na_spce},
    {"cl-spce", "Cl- for SPC/E water (Joung-Cheatham)", JC08, RL_UNITS_REAL, RL_KIND_POINT, 0, 0, {NULL}, {NULL}, {0}, def_cl_spce},
    {"na-tip3p", "Na+ for TIP3P water (Joung-Cheatham)", JC08, RL_UNITS_REAL, RL_KIND_POINT, 0, 0, {NULL}, {NULL}, {0}, def_na_tip3p},
    {"cl-tip3p", "Cl- for TIP3P water (Joung-Cheatham)", JC08, RL_UNITS_REAL, RL_KIND_POINT, 0, 0, {NULL}, {NULL}, {0}, def_cl_tip3p},
    {"na-tip4pew", "Na+ for TIP4P-Ew water (Joung-Cheatham)", JC08, RL_UNITS_REAL, RL_KIND_POINT, 0, 0, {NULL}, {NULL}, {0}, def_na_tip4pew},
    {"cl-tip4pew", "Cl- for TIP4P-Ew water (Joung-Cheatham)", JC08, RL_UNITS_REAL, RL_KIND_POINT, 0, 0, {NULL}, {NULL}, {0}, def_cl_tip4pew},
};

int rl_catalog_count(void) { return (int)(sizeof catalog / sizeof catalog[0]); }
const rl_model *rl_catalog_get(int i) { return i >= 0 && i < rl_catalog_count() ? &catalog[i] : NULL; }

const rl_model *rl_catalog_find(const char *name)
{
  char known[512] = "";
  for (int i = 0; i < rl_catalog_count(); i++) {
    if (name && !strcmp(catalog[i].name, name)) return &catalog[i];
    strncat(known, i ? ", " : "", sizeof known - strlen(known) - 1);
    strncat(known, catalog[i].name, sizeof known - strlen(known) - 1);
  }
  rl_error(RL_EINVAL, "unknown model '%s' (known: %s)", name ? name : "(null)", known);
  return NULL;
}

int rl_model_param_index(const rl_model *model, const char *param)
{
  for (int k = 0; k < model->nparams; k++)
    if (!strcmp(model->param_names[k], param)) return k;
  return -1;
}

int rl_model_build(const rl_model *model, const double *params, int force_general, rl_molecule *m)
{
  double p[RL_MODEL_MAX_PARAMS];
  for (int k = 0; k < model->nparams; k++) {
    p[k] = params ? params[k] : model->param_defaults[k];
    if (!isfinite(p[k]))
      return rl_error(RL_EINVAL, "model %s: parameter %s is not finite", model->name, model->param_names[k]);
  }
  for (int k = 0; k < model->nparams; k++)
    if (!(p[k] >= 0.0))
      return rl_error(RL_EINVAL, "model %s: parameter %s = %g must be >= 0", model->name,
                      model->param_names[k], p[k]);
  return model->define(model, p, force_general, m);
}
