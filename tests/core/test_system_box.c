/* The system owns its periodic cell (issue 32 item 1): one call changes it, every change is
 * counted (the version by which caches learn of it), clones and checkpoints carry it, the
 * writers take it from the system (the RDF too: tests/observables/test_obs_rdf.c), and what is not supported yet is refused. */
#include "../testutil.h"

#define CHECK_TRUE(name, cond) CHECK_LE(name, (cond) ? 0.0 : 1.0, 0.0)

#include <rotleap/io.h>

static rl_system *two_points(void)
{
  rl_system *s = rl_system_alloc(RL_UNITS_LJ);
  rl_species_desc d = {"ar", RL_KIND_POINT, 1.0, {0, 0, 0}, 0, NULL};
  assert_int_equal(rl_system_add_species(s, &d, 2, NULL), RL_OK);
  return s;
}

static void box_api(void **state)
{
  (void)state;
  rl_system *s = two_points();
  double L[3], h[9];
  rl_system_box(s, L);
  CHECK_TRUE("a new system has no box (zeros, not periodic, volume 0)",
             L[0] == 0 && L[1] == 0 && L[2] == 0 && !rl_system_periodic(s) && rl_system_volume(s) == 0.0);
  const unsigned long v0 = rl_system_box_version(s);
  const double B[3] = {3.0, 4.0, 5.0};
  assert_int_equal(rl_system_set_box(s, B), RL_OK);
  rl_system_box(s, L);
  rl_system_cell(s, h);
  CHECK_TRUE("set_box: edges, the diagonal cell matrix, volume, periodic",
             L[0] == 3 && L[1] == 4 && L[2] == 5 && h[0] == 3 && h[4] == 4 && h[8] == 5 && h[1] == 0 && h[3] == 0 &&
                 rl_system_volume(s) == 60.0 && rl_system_periodic(s));
  CHECK_TRUE("a change increments the box version", rl_system_box_version(s) == v0 + 1);
  assert_int_equal(rl_system_set_box(s, B), RL_OK);
  CHECK_TRUE("setting the same box again changes nothing (version kept)", rl_system_box_version(s) == v0 + 1);
  const double tri[9] = {3, 0, 0, 1, 4, 0, 0, 0, 5}, neg[3] = {3, -1, 5}, nan3[3] = {3, NAN, 5};
  CHECK_TRUE("a triclinic cell is refused (not supported yet), the box unchanged",
             rl_system_set_cell(s, tri) == RL_EINVAL && rl_system_volume(s) == 60.0);
  printf("info  message: %s\n", rl_last_error());
  CHECK_TRUE("a negative edge is refused", rl_system_set_box(s, neg) == RL_EINVAL);
  CHECK_TRUE("a NaN edge is refused", rl_system_set_box(s, nan3) == RL_ENONFINITE);
  CHECK_TRUE("the refusals changed nothing", rl_system_box_version(s) == v0 + 1 && rl_system_volume(s) == 60.0);
  rl_system *c = rl_system_clone(s);
  rl_system_box(c, L);
  CHECK_TRUE("a clone carries the box", L[0] == 3 && L[1] == 4 && L[2] == 5);
  const double zero[3] = {0, 0, 0};
  assert_int_equal(rl_system_set_box(c, zero), RL_OK);
  CHECK_TRUE("all zeros: no box again", !rl_system_periodic(c));
  rl_system_free(c);
  rl_system_free(s);
}

static void writers_and_checkpoints_take_it(void **state)
{
  (void)state;
  rl_system *s = two_points();
  const double B[3] = {3.0, 4.0, 5.0}, r1[3] = {0.5, 0.5, 0.5}, r2[3] = {2.5, 3.5, 4.5};
  rl_system_set_position(s, 0, r1);
  rl_system_set_position(s, 1, r2);
  assert_int_equal(rl_system_set_box(s, B), RL_OK);
  assert_int_equal(rl_xyz_write("test_system_box.xyz", s, 0.0, 0), RL_OK);
  double read[3] = {0, 0, 0};
  rl_system *t = two_points();
  assert_int_equal(rl_xyz_read_state("test_system_box.xyz", t, read), RL_OK);
  CHECK_TRUE("the XYZ writer writes the system's box", read[0] == 3 && read[1] == 4 && read[2] == 5);
  rl_checkpoint_meta m = {0.0, 0, {9, 9, 9}, NULL, 0}, r;
  assert_int_equal(rl_checkpoint_write("test_system_box.chk", s, &m), RL_OK);
  assert_int_equal(rl_checkpoint_read("test_system_box.chk", t, &r), RL_OK);
  double L[3];
  rl_system_box(t, L);
  CHECK_TRUE("a checkpoint holds the system's box (not meta's) and restores it", L[0] == 3 && L[1] == 4 && L[2] == 5 &&
             r.box[0] == 3);
  remove("test_system_box.xyz");
  remove("test_system_box.chk");
  rl_system_free(t);
  rl_system_free(s);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(box_api), cmocka_unit_test(writers_and_checkpoints_take_it)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
