/* The Ewald terms' forces, torques and molecular virial are derivatives of their energies
 * (forces/ewald/, issue 33): Richardson-extrapolated central differences (h = 1e-4 nm, rad,
 * strain; limits 1e-8 of the largest value, observed 3e-12 to 7e-10) on a charged mixture of every kind of body (point ions, linear CO2, spherical tops,
 * asymmetric waters with a massless charge) in a non-cubic box, with a dielectric boundary
 * (eps' = 4, the surface term) and a net charge (the background):
 *   forces     dU/dx of each body against -F
 *   torques    dU/dphi of a turn of each body about each lab axis against -K
 *   virial     dU/d strain of the box and the centres along each axis, at fixed orientations,
 *              against -W_cc: the molecular virial, not the site virial (which differs by
 *              sum d_a f_a and is checked to differ)
 * Also: the components add up to the energy, and forces_only gives the same forces to the bit. */
#include "ewald_testutil.h"

typedef struct {
  const char *what;
  const rl_term_type *type;
  double alpha;
} fd_case;

static void fd_one(const fd_case *fc)
{
  ew_scene s;
  const double L[3] = {2.2, 2.3, 2.4};
  ew_scene_mixed(&s, L, 10, 4, 4, 3, 1, 21);
  s.p.cutoff = 1.0;
  s.p.alpha = fc->alpha;
  s.p.eps_surface = 4.0;
  for (int c = 0; c < 3; c++) {
    s.p.kmax[c] = 9;
    s.p.grid[c] = 24 + 2 * c;
  }
  s.p.order = 6;
  rl_terms *t = ew_terms(&s, fc->type, NULL);
  ew_result r;
  assert_int_equal(ew_eval(t, s.sys, &r), RL_OK);
  const int n = r.n;
  double F = 0, K = 0, dF = 0, dK = 0;
  for (int i = 0; i < n; i++) {
    F = fmax(F, norm3d(r.f[i]));
    const int ri = rl_system_rot_index(s.sys, i);
    if (ri >= 0) K = fmax(K, norm3d(r.k[ri]));
    for (int c = 0; c < 3; c++) {
      dF = fmax(dF, fabs(ew_fd(t, s.sys, i, 0, c, 1e-4) + r.f[i][c]));
      if (ri < 0) continue;
      /* (a linear body's torque is perpendicular to its axis: a turn about the axis changes nothing) */
      const double fd = ew_fd(t, s.sys, i, 1, c, 1e-4), kc = r.k[ri][c];
      dK = fmax(dK, fabs(fd + kc));
    }
  }
  double dW = 0, Wn = 0, dsite = 0;
  double Wsite[9], *fs = malloc(sizeof(double[3]) * (size_t)rl_system_nsites(s.sys)), e[5];
  assert_int_equal(rl_ewald_site_forces(rl_terms_state(t, 0), s.sys, (double(*)[3])fs, e, Wsite), RL_OK);
  for (int c = 0; c < 3; c++) {
    const double fd = ew_fd(t, s.sys, 0, 2, c, 1e-4);
    dW = fmax(dW, fabs(fd + r.virial[4 * c]));
    dsite = fmax(dsite, fabs(Wsite[4 * c] - r.virial[4 * c]));
    Wn = fmax(Wn, fabs(r.virial[4 * c]));
  }
  printf("%s: |F| <= %.4g, |K| <= %.4g, W = %.6g %.6g %.6g (site virial %.6g %.6g %.6g)\n", fc->what, F, K, r.virial[0],
         r.virial[4], r.virial[8], Wsite[0], Wsite[4], Wsite[8]);
  char name[160];
  snprintf(name, sizeof name, "%s: forces vs -dU/dx, largest difference relative to the largest force", fc->what);
  EW_CHECK_LE(name, dF / F, 1e-8);
  snprintf(name, sizeof name, "%s: torques vs -dU/dphi, largest difference relative to the largest torque", fc->what);
  EW_CHECK_LE(name, dK / K, 1e-8);
  snprintf(name, sizeof name, "%s: molecular virial W_cc vs -dU/d strain_cc (centres scaled)", fc->what);
  EW_CHECK_LE(name, dW / Wn, 1e-8);
  snprintf(name, sizeof name, "%s: and the site virial is not it (differs by more than 1e-3)", fc->what);
  EW_CHECK_TRUE(name, dsite / Wn > 1e-3);
  /* components and forces_only */
  double sum = 0;
  for (int j = 0; j < r.ne; j++) sum += r.e[j];
  snprintf(name, sizeof name, "%s: its components add up to its energy", fc->what);
  EW_CHECK_LE(name, fabs(sum - r.energy) / fabs(r.energy), 1e-14);
  double (*f2)[3] = calloc((size_t)n, sizeof(double[3])), (*k2)[3] = calloc((size_t)r.nrot + 1, sizeof(double[3]));
  rl_forces fo = {f2, k2, 0.0, {0}, 1};
  assert_int_equal(rl_terms_compute(t, s.sys, &fo), RL_OK);
  snprintf(name, sizeof name, "%s: forces_only: the same forces and torques to the bit, no energy, components NaN", fc->what);
  EW_CHECK_TRUE(name, !memcmp(f2, r.f, sizeof(double[3]) * (size_t)n) && !memcmp(k2, r.k, sizeof(double[3]) * (size_t)r.nrot) &&
                          fo.energy == 0.0 && isnan(rl_terms_energy(t, 0)));
  free(f2);
  free(k2);
  free(fs);
  ew_result_free(&r);
  rl_terms_free(t);
  ew_scene_free(&s);
}

static void real_space(void **state)
{
  (void)state;
  const fd_case c = {"ewald-real (alpha rc 5)", &rl_term_ewald_real, 5.0};
  fd_one(&c);
}

static void ewald(void **state)
{
  (void)state;
  const fd_case c = {"ewald (kmax 9, eps' 4, net charge +1)", &rl_term_ewald, 3.0};
  fd_one(&c);
}

static void pme(void **state)
{
  (void)state;
  const fd_case c = {"pme (24 x 26 x 28, order 6, eps' 4, net charge +1)", &rl_term_pme, 3.0};
  fd_one(&c);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(real_space), cmocka_unit_test(ewald), cmocka_unit_test(pme)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
