/* The mixed scenes of the finite-difference tests (test_ff_fd.c, test_tconf.c): clusters of
 * every body kind with charges (SCENE_CHARGES), point dipoles with charges (SCENE_DIPOLES) or
 * linear quadrupoles (SCENE_QUADS), and the force-field parameters they share. */
#ifndef ROTLEAP_FF_SCENES_H
#define ROTLEAP_FF_SCENES_H
#include "ff_testutil.h"

enum { SCENE_CHARGES = 0, SCENE_DIPOLES = 1, SCENE_QUADS = 2 };

typedef struct {
  ff_test_species sp[4];
  rl_species_ff sff[4];
  int nsp;
  rl_system *sys;
} scene;

static const double fd_box[3] = {4.0, 4.0, 4.0}; /* every scene's periodic cell, the system's */

static inline void scene_add(scene *s, const ff_test_species *t, int count)
{
  s->sp[s->nsp] = *t;
  s->sp[s->nsp].desc.sites = &s->sp[s->nsp].sites[0][0];
  int st = rl_system_add_species(s->sys, &s->sp[s->nsp].desc, count, NULL);
  if (st) fprintf(stderr, "add_species: %s\n", rl_last_error());
  assert_int_equal(st, RL_OK);
  s->nsp++;
}

static inline void scene_build(scene *s, int which, gsl_rng *rng)
{
  memset(s, 0, sizeof *s);
  s->sys = rl_system_alloc(RL_UNITS_REAL);
  assert_int_equal(rl_system_set_box(s->sys, fd_box), RL_OK);
  ff_test_species t;
  if (which == SCENE_CHARGES) {
    ff_ion(&t, 0.8); scene_add(s, &t, 2);
    ff_water(&t); scene_add(s, &t, 2);
    ff_tetra(&t); scene_add(s, &t, 2);
    ff_co2(&t); scene_add(s, &t, 2);
  } else if (which == SCENE_DIPOLES) {
    ff_ion(&t, -0.5); scene_add(s, &t, 2);
    ff_stockmayer(&t, 0.04); scene_add(s, &t, 3);
    ff_symtop(&t); scene_add(s, &t, 2);
    ff_water(&t); scene_add(s, &t, 1);
  } else {
    ff_2cljq(&t, 0.012); scene_add(s, &t, 3);
    ff_symtop(&t);
    t.has_dipole = 0;
    t.has_quad = 1;
    t.quadrupole[0] = -0.009;
    for (int a = 0; a < 4; a++) t.charge[a] = 0.0;
    scene_add(s, &t, 2);
    ff_water(&t);
    for (int a = 0; a < 4; a++) t.charge[a] = 0.0;
    t.has_quad = 1;
    t.quadrupole[3] = 0.01;
    t.quadrupole[0] = 0.0;
    scene_add(s, &t, 2);
  }
  for (int k = 0; k < s->nsp; k++) s->sff[k] = ff_test_species_ff(&s->sp[k]);
  double c[3] = {2.0, 2.0, 2.0};
  ff_place_cluster(s->sys, rng, c, 0.55, 0.34);
}

static inline void base_params(rl_ff_params *p)
{
  rl_ff_params_default(p);
  p->cutoff = 0.9;
  p->r_switch = 0.7;
}

/* The force-field cases each scene is checked under: case k (from 0) of scene `which` into p and
 * its label; 0 past the last.  SCENE_CHARGES: LJ in each truncation with RF (eps_rf 78.3 and
 * infinity alternating); SCENE_DIPOLES: dipoles RF (eps_rf 78.3 and 1) and SF with shifted-force
 * LJ; SCENE_QUADS: LJ plain and shifted force; each under the site, then the molecule cutoff. */
static inline int ff_scene_case(int which, int k, rl_ff_params *p, char *label, size_t n)
{
  static const char *trunc[] = {"plain", "shifted", "shifted-force", "switched"};
  static const char *scheme[] = {"site", "molecule"};
  static const char *meth[] = {"dipole RF eps 78.3", "dipole RF eps 1", "dipole SF"};
  const int per = which == SCENE_CHARGES ? 4 : which == SCENE_DIPOLES ? 3 : 2, sc = k / per, m = k % per;
  if (sc > 1) return 0;
  base_params(p);
  p->scheme = (rl_cutoff_scheme)sc;
  if (which == SCENE_CHARGES) {
    p->lj_truncation = (rl_lj_truncation)m;
    p->eps_rf = m % 2 ? INFINITY : 78.3;
    snprintf(label, n, "LJ %s + RF(eps %s), %s cutoff", trunc[m], m % 2 ? "inf" : "78.3", scheme[sc]);
  } else if (which == SCENE_DIPOLES) {
    p->lj_truncation = RL_LJ_SHIFTED_FORCE;
    p->eps_rf = m == 1 ? 1.0 : 78.3;
    p->dipole_method = m == 2 ? RL_DIPOLE_SF : RL_DIPOLE_RF;
    snprintf(label, n, "%s + charge-dipole, %s cutoff", meth[m], scheme[sc]);
  } else {
    p->lj_truncation = (rl_lj_truncation)(2 * m);
    snprintf(label, n, "quadrupole + LJ %s, %s cutoff", trunc[2 * m], scheme[sc]);
  }
  return 1;
}

#endif
