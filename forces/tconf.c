/* The configurational temperature of rigid bodies (forcefield.h, rl_config_temperature).
 *
 * Every pair term is written as a function U(s, a, b, c) of s = r.r, a = e_i.r, b = e_j.r and
 * c = e_i.e_j, with r = r_site(i) - r_site(j) and e_i, e_j the bodies' Z axes (the direction of
 * their point dipoles and quadrupoles).  From U's first and second partial derivatives in those
 * four variables one routine (pair_blocks) forms the gradient and the Hessian blocks in r, e_i
 * and e_j, and from those the forces, torques and both Laplacians of each body (accumulate).
 * The potentials are re-derived from the force field's tables (the LJ coefficients with their
 * truncation and any pair override, the charges, dipoles, quadrupoles, krf): the reference pair
 * routine returns no second derivatives.  test_tconf checks the forces and torques against
 * rl_forcefield_compute and the Laplacians against finite differences of its energy. */
#include "rotleap/forcefield.h"
#include "rotleap/error.h"

#include "pair/forcefield_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { VS, VA, VB, VC, NVAR }; /* the variables s, a, b, c */

/* First and second partial derivatives of one pair term in (s, a, b, c). */
typedef struct {
  double d[NVAR];
  double dd[NVAR][NVAR]; /* symmetric */
} pd;

static void pd_sym(pd *p, int v, int w, double x)
{
  p->dd[v][w] += x;
  if (v != w) p->dd[w][v] += x;
}

/* A radial function f(rho) as f_s = df/ds and f_ss = d2f/ds2 (s = rho^2), from f' and f''. */
static void radial_s(double rho, double f1, double f2, double *fs, double *fss)
{
  *fs = f1 / (2.0 * rho);
  *fss = (f2 - f1 / rho) / (4.0 * rho * rho);
}

/* k w(x) rho^-n with x = rho / rc and w one of: 0 none (w = 1), 1 the SF dipole-dipole
 * 1 - 4x^3 + 3x^4, 2 the SF charge-dipole 1 - 3x^2 + 2x^3.  Value, and f_s, f_ss. */
static double radial(double k, int n, int w, double rho, double rc, double *fs, double *fss)
{
  double W = 1.0, W1 = 0.0, W2 = 0.0;
  if (w) {
    const double x = rho / rc;
    if (w == 1) {
      W = 1.0 + x * x * x * (-4.0 + 3.0 * x);
      W1 = x * x * (-12.0 + 12.0 * x) / rc;
      W2 = x * (-24.0 + 36.0 * x) / (rc * rc);
    } else {
      W = 1.0 + x * x * (-3.0 + 2.0 * x);
      W1 = x * (-6.0 + 6.0 * x) / rc;
      W2 = (-6.0 + 12.0 * x) / (rc * rc);
    }
  }
  double p = 1.0;
  for (int k = 0; k < n; k++) p /= rho;
  const double dn = (double)n;
  const double f = k * W * p;
  const double f1 = k * (W1 * p - dn * W * p / rho);
  const double f2 = k * (W2 * p - 2.0 * dn * W1 * p / rho + dn * (dn + 1.0) * W * p / (rho * rho));
  radial_s(rho, f1, f2, fs, fss);
  return f;
}

/* Lennard-Jones in its truncation: U, U', U'' at rho. */
static double lj_radial(const rl_lj_coef *c, double rho, double *u1, double *u2)
{
  const double ir = 1.0 / rho, ir2 = ir * ir, ir6 = ir2 * ir2 * ir2;
  double u = (c->c12 * ir6 - c->c6) * ir6;
  double d1 = (-12.0 * c->c12 * ir6 + 6.0 * c->c6) * ir6 * ir;
  double d2 = (156.0 * c->c12 * ir6 - 42.0 * c->c6) * ir6 * ir2;
  switch (c->trunc) {
  case RL_LJ_PLAIN: break;
  case RL_LJ_SHIFTED: u -= c->eshift; break;
  case RL_LJ_SHIFTED_FORCE:
    u -= c->eshift + (rho - c->rc) * c->fshift;
    d1 -= c->fshift;
    break;
  case RL_LJ_SWITCHED:
    if (rho >= c->rc) { *u1 = *u2 = 0.0; return 0.0; }
    if (rho > c->rsw) {
      const double w = c->rc - c->rsw, x = (rho - c->rsw) / w;
      const double S = 1.0 + x * x * x * (-10.0 + x * (15.0 - 6.0 * x));
      const double S1 = x * x * (-30.0 + x * (60.0 - 30.0 * x)) / w;
      const double S2 = x * (-60.0 + x * (180.0 - 120.0 * x)) / (w * w);
      d2 = d2 * S + 2.0 * d1 * S1 + u * S2;
      d1 = d1 * S + u * S1;
      u *= S;
    }
    break;
  }
  *u1 = d1;
  *u2 = d2;
  return u;
}

/* The partial derivatives of every interaction of site type ta (body i) with type tb (body j)
 * at separation r (s = r.r, a = e_i.r, b = e_j.r, c = e_i.e_j) added to p; returns the energy. */
static double site_pd(const rl_forcefield *ff, int ta, int tb, double s, double a, double b, double c, pd *p)
{
  const double rho = sqrt(s), rc = ff->p.cutoff;
  double e = 0.0, fs, fss;
  const rl_lj_coef *lj = &ff->lj[ta * ff->ntypes + tb];
  if (lj->epsilon != 0.0) {
    double u1, u2;
    e += lj_radial(lj, rho, &u1, &u2);
    radial_s(rho, u1, u2, &fs, &fss);
    p->d[VS] += fs;
    p->dd[VS][VS] += fss;
  }
  const double qa = ff->q[ta], qb = ff->q[tb];
  if (qa != 0.0 && qb != 0.0) { /* qq (1/rho + krf rho^2 - crf) */
    const double qq = ff->kc * qa * qb, krf = ff->rf.krf;
    e += qq * (1.0 / rho + krf * s - ff->rf.crf);
    radial_s(rho, qq * (-1.0 / s + 2.0 * krf * rho), qq * (2.0 / (s * rho) + 2.0 * krf), &fs, &fss);
    p->d[VS] += fs;
    p->dd[VS][VS] += fss;
  }
  const double ma = ff->mu[ta], mb = ff->mu[tb];
  const int sf = ff->p.dipole_method == RL_DIPOLE_SF;
  if (ma != 0.0 && mb != 0.0 && !(sf && rho >= rc)) {
    /* U = ma mb [A c + B a b]; RF: A = kc (rho^-3 - 2 krf), B = -3 kc rho^-5; SF: both times w1 */
    double As, Ass, Bs, Bss;
    double A = radial(ff->kc, 3, sf, rho, rc, &As, &Ass);
    const double B = radial(-3.0 * ff->kc, 5, sf, rho, rc, &Bs, &Bss);
    if (!sf) A -= 2.0 * ff->kc * ff->rf.krf;
    const double m = ma * mb;
    e += m * (A * c + B * a * b);
    p->d[VS] += m * (As * c + Bs * a * b);
    p->d[VC] += m * A;
    p->d[VA] += m * B * b;
    p->d[VB] += m * B * a;
    pd_sym(p, VS, VS, m * (Ass * c + Bss * a * b));
    pd_sym(p, VS, VC, m * As);
    pd_sym(p, VS, VA, m * Bs * b);
    pd_sym(p, VS, VB, m * Bs * a);
    pd_sym(p, VA, VB, m * B);
  }
  for (int side = 0; side < 2; side++) { /* charge at a, dipole at b; then dipole at a, charge at b */
    const double q = side ? qb : qa, mu = side ? ma : mb;
    if (q == 0.0 || mu == 0.0 || (sf && rho >= rc)) continue;
    /* U = P(rho) mu (e.(r_charge - r_dipole)); RF: P = kc q (rho^-3 - 2 krf); SF: kc q w2 rho^-3 */
    double Ps, Pss;
    double P = radial(ff->kc * q, 3, sf ? 2 : 0, rho, rc, &Ps, &Pss);
    if (!sf) P -= 2.0 * ff->kc * q * ff->rf.krf;
    const double m = side ? -mu : mu; /* r_charge - r_dipole = -r for a dipole at a */
    const int v = side ? VA : VB;
    const double x = side ? a : b;
    e += m * P * x;
    p->d[VS] += m * Ps * x;
    p->d[v] += m * P;
    pd_sym(p, VS, VS, m * Pss * x);
    pd_sym(p, VS, v, m * Ps);
  }
  const double Qa = ff->Q[ta], Qb = ff->Q[tb];
  if (Qa != 0.0 && Qb != 0.0) {
    /* U = K [(1 + 2c^2) s^-5/2 - 5 (a^2 + b^2) s^-7/2 - 20 c a b s^-7/2 + 35 a^2 b^2 s^-9/2] */
    const double K = 0.75 * ff->kc * Qa * Qb;
    double T[3], T1[3], T2[3]; /* s^-n/2 for n = 5, 7, 9 and their s-derivatives */
    for (int k = 0; k < 3; k++) {
      const double h = 2.5 + k;
      T[k] = pow(s, -h);
      T1[k] = -h * T[k] / s;
      T2[k] = h * (h + 1.0) * T[k] / (s * s);
    }
    const double a2 = a * a, b2 = b * b;
    const double F5 = 1.0 + 2.0 * c * c, F7 = -5.0 * (a2 + b2) - 20.0 * c * a * b, F9 = 35.0 * a2 * b2;
    e += K * (F5 * T[0] + F7 * T[1] + F9 * T[2]);
    const double Fa[3] = {0.0, -10.0 * a - 20.0 * c * b, 70.0 * a * b2};
    const double Fb[3] = {0.0, -10.0 * b - 20.0 * c * a, 70.0 * a2 * b};
    const double Fc[3] = {4.0 * c, -20.0 * a * b, 0.0};
    double ds = 0.0, dss = 0.0, da = 0.0, db = 0.0, dc = 0.0, dsa = 0.0, dsb = 0.0, dsc = 0.0;
    const double F[3] = {F5, F7, F9};
    for (int k = 0; k < 3; k++) {
      ds += F[k] * T1[k];
      dss += F[k] * T2[k];
      da += Fa[k] * T[k];
      db += Fb[k] * T[k];
      dc += Fc[k] * T[k];
      dsa += Fa[k] * T1[k];
      dsb += Fb[k] * T1[k];
      dsc += Fc[k] * T1[k];
    }
    p->d[VS] += K * ds;
    p->d[VA] += K * da;
    p->d[VB] += K * db;
    p->d[VC] += K * dc;
    pd_sym(p, VS, VS, K * dss);
    pd_sym(p, VS, VA, K * dsa);
    pd_sym(p, VS, VB, K * dsb);
    pd_sym(p, VS, VC, K * dsc);
    pd_sym(p, VA, VA, K * (-10.0 * T[1] + 70.0 * b2 * T[2]));
    pd_sym(p, VB, VB, K * (-10.0 * T[1] + 70.0 * a2 * T[2]));
    pd_sym(p, VC, VC, K * 4.0 * T[0]);
    pd_sym(p, VA, VB, K * (-20.0 * c * T[1] + 140.0 * a * b * T[2]));
    pd_sym(p, VA, VC, K * (-20.0 * b * T[1]));
    pd_sym(p, VB, VC, K * (-20.0 * a * T[1]));
  }
  return e;
}

typedef double mat3[3][3];

static double dot3(const double x[3], const double y[3]) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; }

/* (x . y) tr H - y^T H x for H[k][l] = d2U / dx_k dy_l: the rotational Laplacian's term of the
 * coordinate pair (x, y) summed over the three lab axes. */
static double rot_term(const double x[3], mat3 H, const double y[3])
{
  double yHx = 0.0;
  for (int k = 0; k < 3; k++)
    for (int l = 0; l < 3; l++) yHx += y[k] * H[k][l] * x[l];
  return dot3(x, y) * (H[0][0] + H[1][1] + H[2][2]) - yHx;
}

/* H = alpha I + sum_vw dd[v][w] p_v q_w^T, with p_v = d(var v)/dX, q_w = d(var w)/dY. */
static void block(mat3 H, double alpha, const pd *p, const double *const P[NVAR], const double *const Q[NVAR])
{
  for (int k = 0; k < 3; k++)
    for (int l = 0; l < 3; l++) H[k][l] = k == l ? alpha : 0.0;
  for (int v = 0; v < NVAR; v++)
    for (int w = 0; w < NVAR; w++) {
      if (!P[v] || !Q[w] || p->dd[v][w] == 0.0) continue;
      for (int k = 0; k < 3; k++)
        for (int l = 0; l < 3; l++) H[k][l] += p->dd[v][w] * P[v][k] * Q[w][l];
    }
}

/* Per-body accumulators. */
typedef struct {
  double (*f)[3], (*k)[3];
  double *lap_r, *lap_rot;
} sums;

/* One site pair's derivatives p (r = r_a - r_b, a's offset da in body i, b's db in body j, axes
 * ei, ej) into bodies i and j: forces, torques, Laplacians. */
static void accumulate(const pd *p, const double r[3], const double da[3], const double db[3], const double ei[3],
                       const double ej[3], int i, int j, sums *S)
{
  const double r2[3] = {2.0 * r[0], 2.0 * r[1], 2.0 * r[2]};
  /* gradients of the variables: in r {2r, ei, ej, -}; in ei {-, r, -, ej}; in ej {-, -, r, ei} */
  const double *const Gr[NVAR] = {r2, ei, ej, NULL};
  const double *const Gi[NVAR] = {NULL, r, NULL, ej};
  const double *const Gj[NVAR] = {NULL, NULL, r, ei};
  double gr[3], gi[3], gj[3];
  for (int k = 0; k < 3; k++) {
    gr[k] = p->d[VS] * r2[k] + p->d[VA] * ei[k] + p->d[VB] * ej[k];
    gi[k] = p->d[VA] * r[k] + p->d[VC] * ej[k];
    gj[k] = p->d[VB] * r[k] + p->d[VC] * ei[k];
  }
  mat3 Hrr, Hri, Hrj, Hii, Hjj;
  block(Hrr, 2.0 * p->d[VS], p, Gr, Gr);
  block(Hri, p->d[VA], p, Gr, Gi);
  block(Hrj, p->d[VB], p, Gr, Gj);
  block(Hii, 0.0, p, Gi, Gi);
  block(Hjj, 0.0, p, Gj, Gj);
  const double lap = Hrr[0][0] + Hrr[1][1] + Hrr[2][2];
  S->lap_r[i] += lap;
  S->lap_r[j] += lap;
  /* site a moves with r (dr/dr_a = I), site b against it (dr/dr_b = -I) */
  for (int k = 0; k < 3; k++) {
    S->f[i][k] -= gr[k];
    S->f[j][k] += gr[k];
  }
  /* torque -sum_p x_p x g_p: (d_a, g_r) and (e_i, g_i) on i; (d_b, -g_r) and (e_j, g_j) on j */
  S->k[i][0] -= da[1] * gr[2] - da[2] * gr[1] + ei[1] * gi[2] - ei[2] * gi[1];
  S->k[i][1] -= da[2] * gr[0] - da[0] * gr[2] + ei[2] * gi[0] - ei[0] * gi[2];
  S->k[i][2] -= da[0] * gr[1] - da[1] * gr[0] + ei[0] * gi[1] - ei[1] * gi[0];
  S->k[j][0] -= -(db[1] * gr[2] - db[2] * gr[1]) + ej[1] * gj[2] - ej[2] * gj[1];
  S->k[j][1] -= -(db[2] * gr[0] - db[0] * gr[2]) + ej[2] * gj[0] - ej[0] * gj[2];
  S->k[j][2] -= -(db[0] * gr[1] - db[1] * gr[0]) + ej[0] * gj[1] - ej[1] * gj[0];
  /* sum_pq [(x_p.x_q) tr H_pq - x_q^T H_pq x_p] - 2 sum_p g_p.x_p over the body's coordinates */
  S->lap_rot[i] += rot_term(da, Hrr, da) + 2.0 * rot_term(da, Hri, ei) + rot_term(ei, Hii, ei) -
                   2.0 * (dot3(gr, da) + dot3(gi, ei));
  S->lap_rot[j] += rot_term(db, Hrr, db) - 2.0 * rot_term(db, Hrj, ej) + rot_term(ej, Hjj, ej) -
                   2.0 * (-dot3(gr, db) + dot3(gj, ej));
}

/* accumulate for a pair whose terms are all central (U = U(s): LJ and charges), in closed form:
 * g_r = 2 U_s r, H_rr = 2 U_s I + 4 U_ss r r^T, so tr H_rr = 6 U_s + 4 U_ss s and
 * (d.d) tr H_rr - d^T H_rr d = 4 U_s |d|^2 + 4 U_ss (|d|^2 s - (d.r)^2). */
static void accumulate_central(double Us, double Uss, const double r[3], const double da[3], const double db[3],
                               int i, int j, sums *S)
{
  const double s = dot3(r, r), lap = 6.0 * Us + 4.0 * Uss * s;
  const double gr[3] = {2.0 * Us * r[0], 2.0 * Us * r[1], 2.0 * Us * r[2]};
  S->lap_r[i] += lap;
  S->lap_r[j] += lap;
  for (int k = 0; k < 3; k++) {
    S->f[i][k] -= gr[k];
    S->f[j][k] += gr[k];
  }
  S->k[i][0] -= da[1] * gr[2] - da[2] * gr[1];
  S->k[i][1] -= da[2] * gr[0] - da[0] * gr[2];
  S->k[i][2] -= da[0] * gr[1] - da[1] * gr[0];
  S->k[j][0] += db[1] * gr[2] - db[2] * gr[1];
  S->k[j][1] += db[2] * gr[0] - db[0] * gr[2];
  S->k[j][2] += db[0] * gr[1] - db[1] * gr[0];
  const double a2 = dot3(da, da), ar = dot3(da, r), b2 = dot3(db, db), br = dot3(db, r);
  S->lap_rot[i] += 4.0 * Us * a2 + 4.0 * Uss * (a2 * s - ar * ar) - 2.0 * dot3(gr, da);
  S->lap_rot[j] += 4.0 * Us * b2 + 4.0 * Uss * (b2 * s - br * br) + 2.0 * dot3(gr, db);
}

int rl_tconf_exact(const rl_forcefield *ff)
{
  rl_ff_discontinuity dis[8];
  const int nd = rl_forcefield_discontinuities(ff, dis, 8);
  for (int t = 0; t < nd && t < 8; t++)
    if (dis[t].energy_jumps || dis[t].force_jumps) return 0;
  return 1;
}

int rl_config_temperature(const rl_forcefield *ff, const rl_system *sys, rl_tconf_sums *out)
{
  if (!ff || !sys || !out) return rl_error(RL_EINVAL, "rl_config_temperature: NULL argument");
  const int n = rl_system_count(sys), nsites = rl_system_nsites(sys);
  if (n != ff->n || nsites != ff->nsites || rl_system_nspecies(sys) != ff->nspecies)
    return rl_error(RL_ESTATE, "rl_config_temperature: the system changed since the force field was made");
  if (ff->p.coulomb != RL_COULOMB_RF)
    return rl_error(RL_EINVAL, "rl_config_temperature: the pair term's Coulomb is the Ewald real space, whose "
                               "Laplacian is not written here (reaction field only)");
  memset(out, 0, sizeof *out);
  double(*site)[3] = malloc(sizeof *site * (size_t)(nsites > 0 ? nsites : 1));
  double(*ctr)[3] = malloc(sizeof *ctr * (size_t)(n > 0 ? n : 1));
  double(*axis)[3] = malloc(sizeof *axis * (size_t)(n > 0 ? n : 1));
  double(*acc)[3] = calloc((size_t)(2 * n + 1), sizeof *acc);
  double *lap = calloc((size_t)(2 * n + 1), sizeof *lap);
  int *off = malloc(sizeof *off * (size_t)(n + 1)), *type0 = malloc(sizeof *type0 * (size_t)(n + 1));
  char *oriented = malloc((size_t)ff->ntypes + 1); /* a type with a dipole or quadrupole */
  char *pairs = malloc((size_t)ff->ntypes * (size_t)ff->ntypes + 1); /* type pairs with some term */
  if (!site || !ctr || !axis || !acc || !lap || !off || !type0 || !oriented || !pairs) {
    free(site); free(ctr); free(axis); free(acc); free(lap); free(off); free(type0); free(oriented); free(pairs);
    return rl_error(RL_ENOMEM, "rl_config_temperature: out of memory for %d bodies", n);
  }
  for (int t = 0; t < ff->ntypes; t++) oriented[t] = ff->mu[t] != 0.0 || ff->Q[t] != 0.0;
  for (int ta = 0; ta < ff->ntypes; ta++)
    for (int tb = 0; tb < ff->ntypes; tb++) {
      const int qa = ff->q[ta] != 0.0, qb = ff->q[tb] != 0.0, ma = ff->mu[ta] != 0.0, mb = ff->mu[tb] != 0.0;
      pairs[ta * ff->ntypes + tb] = ff->lj[ta * ff->ntypes + tb].epsilon != 0.0 || (qa && qb) || (ma && mb) ||
                                    (qa && mb) || (ma && qb) || (ff->Q[ta] != 0.0 && ff->Q[tb] != 0.0);
    }
  const double half[3] = {0.5 * ff->box.L[0], 0.5 * ff->box.L[1], 0.5 * ff->box.L[2]};
  rl_system_site_positions(sys, site);
  double ext = 0.0; /* the largest site offset: the site scheme's bodies interact within rc + 2 ext */
  for (int i = 0; i < n; i++) {
    rl_system_get_position(sys, i, ctr[i]);
    rl_system_get_axis(sys, i, axis[i]);
    off[i] = rl_system_site_offset(sys, i);
    type0[i] = ff->type_off[rl_system_species_of(sys, i)];
  }
  off[n] = nsites;
  for (int i = 0; i < n; i++)
    for (int a = off[i]; a < off[i + 1]; a++) {
      double d[3] = {site[a][0] - ctr[i][0], site[a][1] - ctr[i][1], site[a][2] - ctr[i][2]};
      ext = fmax(ext, sqrt(dot3(d, d)));
    }
  sums S = {acc, acc + n, lap, lap + n};
  const double rc = ff->p.cutoff, rc2 = rc * rc, rb = rc + 2.0 * ext, md2 = ff->min_distance * ff->min_distance;
  const int mol = ff->p.scheme == RL_CUTOFF_MOLECULE;
  int st = RL_OK;
  for (int i = 0; i < n && !st; i++)
    for (int j = i + 1; j < n && !st; j++) {
      double R[3] = {ctr[i][0] - ctr[j][0], ctr[i][1] - ctr[j][1], ctr[i][2] - ctr[j][2]};
      rl_box_minimum_image(&ff->box, R);
      const double R2 = dot3(R, R);
      if (mol ? R2 >= rc2 : R2 >= rb * rb) continue;
      for (int a = off[i]; a < off[i + 1] && !st; a++)
        for (int b = off[j]; b < off[j + 1]; b++) {
          const int ta = type0[i] + a - off[i], tb = type0[j] + b - off[j];
          if (!pairs[ta * ff->ntypes + tb]) continue; /* no interaction between these sites */
          const double da[3] = {site[a][0] - ctr[i][0], site[a][1] - ctr[i][1], site[a][2] - ctr[i][2]};
          const double db[3] = {site[b][0] - ctr[j][0], site[b][1] - ctr[j][1], site[b][2] - ctr[j][2]};
          double r[3] = {R[0] + da[0] - db[0], R[1] + da[1] - db[1], R[2] + da[2] - db[2]};
          /* the site scheme takes each site pair's own minimum image, as the reference routine: the
           * centres' image unless a component is beyond half the box */
          if (!mol && (fabs(r[0]) > half[0] || fabs(r[1]) > half[1] || fabs(r[2]) > half[2]))
            rl_box_minimum_image(&ff->box, r);
          const double s = dot3(r, r);
          if (!mol && s >= rc2) continue;
          if (s < md2) {
            st = rl_error(RL_EINVAL, "rl_config_temperature: overlapping sites: site %d of body %d and site %d of "
                          "body %d are %g apart", a - off[i], i, b - off[j], j, sqrt(s));
            break;
          }
          if (!oriented[ta] && !oriented[tb]) { /* LJ and charges only */
            pd p = {{0.0}, {{0.0}}};
            site_pd(ff, ta, tb, s, 0.0, 0.0, 0.0, &p);
            if (p.d[VS] != 0.0 || p.dd[VS][VS] != 0.0) accumulate_central(p.d[VS], p.dd[VS][VS], r, da, db, i, j, &S);
            continue;
          }
          pd p;
          memset(&p, 0, sizeof p);
          site_pd(ff, ta, tb, s, dot3(axis[i], r), dot3(axis[j], r), dot3(axis[i], axis[j]), &p);
          accumulate(&p, r, da, db, axis[i], axis[j], i, j, &S);
        }
    }
  if (!st) {
    for (int i = 0; i < n; i++) {
      out->f2 += dot3(S.f[i], S.f[i]);
      out->lap_r += S.lap_r[i];
      if (rl_system_rot_index(sys, i) < 0) continue;
      out->k2 += dot3(S.k[i], S.k[i]);
      out->lap_rot += S.lap_rot[i];
    }
  }
  free(site); free(ctr); free(axis); free(acc); free(lap); free(off); free(type0); free(oriented); free(pairs);
  return st;
}
