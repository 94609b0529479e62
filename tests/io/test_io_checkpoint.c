/* Checkpoints: bit-for-bit round trip of a mixed system (TIP4P water, Stockmayer dipoles, CO2,
 * LJ atoms), a zlib-compatible CRC-32, and clear errors for corruption, truncation, a version
 * mismatch, a species mismatch; a crash while writing leaves the previous checkpoint readable. */
#include "io_testutil.h"

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <sys/types.h>
#include <time.h>

static const char *NAMES[4] = {"tip4p", "stockmayer", "co2", "Ar"};
static const int COUNTS[4] = {20, 12, 6, 10};

static void mixed(io_scene *s, unsigned long seed) { io_scene_build(s, RL_UNITS_REAL, NAMES, COUNTS, 4, 2.5, seed); }

/* CRC-32 bit by bit (the zlib / IEEE 802.3 definition), independent of the library's table. */
static uint32_t crc32_ref(const unsigned char *p, size_t n)
{
  uint32_t c = 0xFFFFFFFFu;
  for (size_t i = 0; i < n; i++) {
    c ^= p[i];
    for (int k = 0; k < 8; k++) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
  }
  return ~c;
}

static unsigned char *slurp(const char *path, size_t *n)
{
  FILE *fp = fopen(path, "rb");
  assert_non_null(fp);
  fseek(fp, 0, SEEK_END);
  *n = (size_t)ftell(fp);
  fseek(fp, 0, SEEK_SET);
  unsigned char *b = malloc(*n + 1);
  assert_non_null(b);
  assert_int_equal(fread(b, 1, *n, fp), *n);
  fclose(fp);
  return b;
}

static void spit(const char *path, const unsigned char *b, size_t n)
{
  FILE *fp = fopen(path, "wb");
  assert_non_null(fp);
  assert_int_equal(fwrite(b, 1, n, fp), n);
  fclose(fp);
}

/* Every stored state quantity, bitwise. */
static int same_state(const rl_system *a, const rl_system *b)
{
  if (rl_system_count(a) != rl_system_count(b) || rl_system_dof(a) != rl_system_dof(b)) return 0;
  for (int i = 0; i < rl_system_count(a); i++) {
    double x[9], y[9];
    rl_system_get_position(a, i, x); rl_system_get_position(b, i, y);
    if (memcmp(x, y, 3 * sizeof(double))) return 0;
    rl_system_get_velocity(a, i, x); rl_system_get_velocity(b, i, y);
    if (memcmp(x, y, 3 * sizeof(double))) return 0;
    if (rl_system_rot_index(a, i) >= 0) {
      rl_system_get_angmom(a, i, x); rl_system_get_angmom(b, i, y);
      if (memcmp(x, y, 3 * sizeof(double))) return 0;
    }
    rl_system_get_orientation(a, i, x); rl_system_get_orientation(b, i, y);
    if (memcmp(x, y, 9 * sizeof(double))) return 0;
    rl_system_get_axis(a, i, x); rl_system_get_axis(b, i, y);
    if (memcmp(x, y, 3 * sizeof(double))) return 0;
  }
  return 1;
}

static void round_trip(void **state)
{
  (void)state;
  io_scene s, t;
  mixed(&s, 11);
  mixed(&t, 99); /* same species, different state */
  rl_system_set_removed_dof(s.sys, 0);
  char path[256];
  io_path(path, sizeof path, "rt.chk");
  const char blob[] = "thermostat state + RNG + accumulators";
  rl_checkpoint_meta m = {1.2345678901234567, 424242, {2.5, 2.6, 2.7}, blob, sizeof blob};
  assert_int_equal(rl_checkpoint_write(path, s.sys, &m), RL_OK);
  CHECK_TRUE("round trip: states differ before reading", !same_state(s.sys, t.sys));
  rl_checkpoint_meta r;
  int st = rl_checkpoint_read(path, t.sys, &r);
  if (st) printf("error: %s\n", rl_last_error());
  assert_int_equal(st, RL_OK);
  CHECK_TRUE("round trip: r, v, l, A, rho and DOF bit for bit (memcmp)", same_state(s.sys, t.sys));
  CHECK_TRUE("round trip: time, step, box bit for bit",
             memcmp(&r.time, &m.time, sizeof m.time) == 0 && r.step == m.step && memcmp(r.box, m.box, sizeof m.box) == 0);
  CHECK_TRUE("round trip: caller blob restored", r.blob_size == sizeof blob && memcmp(r.blob, blob, sizeof blob) == 0);
  free((void *)r.blob);

  rl_checkpoint_meta r2;
  rl_system *u = rl_checkpoint_load(path, &r2);
  assert_non_null(u);
  CHECK_TRUE("load: a new system from the species table equals the original", same_state(s.sys, u) &&
             rl_system_nspecies(u) == 4 && rl_system_species_kind(u, 2) == RL_KIND_LINEAR);
  free((void *)r2.blob);
  rl_system_free(u);

  size_t n;
  unsigned char *b = slurp(path, &n);
  uint32_t stored = (uint32_t)b[n - 4] | (uint32_t)b[n - 3] << 8 | (uint32_t)b[n - 2] << 16 | (uint32_t)b[n - 1] << 24;
  CHECK_TRUE("CRC-32 trailer equals zlib's crc32 of the preceding bytes", stored == crc32_ref(b, n - 4));
  free(b);
  char tmp[300];
  CHECK_TRUE("atomic write leaves no temporary file", !io_find_tmp(path, tmp, sizeof tmp));
  unlink(path);
  io_scene_free(&s);
  io_scene_free(&t);
}

static void errors(void **state)
{
  (void)state;
  io_scene s;
  mixed(&s, 11);
  char path[256], bad[256];
  io_path(path, sizeof path, "err.chk");
  io_path(bad, sizeof bad, "bad.chk");
  rl_checkpoint_meta m = {0.5, 10, {2.5, 2.5, 2.5}, NULL, 0};
  assert_int_equal(rl_checkpoint_write(path, s.sys, &m), RL_OK);
  size_t n;
  unsigned char *b = slurp(path, &n);

  b[n / 2] ^= 0x10; /* one flipped bit in the state */
  spit(bad, b, n);
  CHECK_MSG("corrupted byte: checksum error", rl_checkpoint_read(bad, s.sys, NULL), RL_EINVAL, "checksum mismatch");
  b[n / 2] ^= 0x10;

  spit(bad, b, n - 100);
  CHECK_MSG("truncated file: error with sizes", rl_checkpoint_read(bad, s.sys, NULL), RL_EINVAL, "truncated");
  spit(bad, b, 10);
  CHECK_MSG("file cut inside the header: truncated", rl_checkpoint_read(bad, s.sys, NULL), RL_EINVAL, "truncated");

  b[8] = 2; /* version 2, with a valid CRC so that only the version is wrong */
  uint32_t c = crc32_ref(b, n - 4);
  for (int k = 0; k < 4; k++) b[n - 4 + k] = (unsigned char)(c >> (8 * k));
  spit(bad, b, n);
  CHECK_MSG("version mismatch: error naming both versions", rl_checkpoint_read(bad, s.sys, NULL), RL_EINVAL,
            "version 2; this build of rotleap reads version 1");
  b[0] = 'X';
  spit(bad, b, n);
  CHECK_MSG("not a checkpoint: bad magic", rl_checkpoint_read(bad, s.sys, NULL), RL_EINVAL, "not a rotleap checkpoint");
  free(b);

  /* species mismatches: a different count, a different molecule, different units */
  io_scene t;
  int counts[4] = {20, 13, 6, 10};
  io_scene_build(&t, RL_UNITS_REAL, NAMES, counts, 4, 2.5, 3);
  CHECK_MSG("species mismatch (count): names the species", rl_checkpoint_read(path, t.sys, NULL), RL_EINVAL,
            "species 2 ('stockmayer'): 12 molecules in the checkpoint, 13 in the system");
  io_scene_free(&t);
  const char *names2[4] = {"tip4p-2005", "stockmayer", "co2", "Ar"};
  io_scene_build(&t, RL_UNITS_REAL, names2, COUNTS, 4, 2.5, 3);
  CHECK_MSG("species mismatch (model): names the species and field", rl_checkpoint_read(path, t.sys, NULL),
            RL_EINVAL, "species 1 ('tip4p-2005'): name 'tip4p'");
  io_scene_free(&t);
  io_scene_build(&t, RL_UNITS_LJ, NAMES, COUNTS, 4, 2.5, 3);
  CHECK_MSG("units mismatch", rl_checkpoint_read(path, t.sys, NULL), RL_EINVAL, "units 'real', the system's 'lj'");
  io_scene_free(&t);
  CHECK_MSG("missing file: error names it", rl_checkpoint_read("no/such/file.chk", s.sys, NULL), RL_EINVAL,
            "no/such/file.chk: cannot open");
  unlink(path);
  unlink(bad);
  io_scene_free(&s);
}

static void crash(void **state)
{
  (void)state;
  io_scene s;
  mixed(&s, 5);
  char path[256], tmp[300];
  io_path(path, sizeof path, "crash.chk");
  rl_checkpoint_meta m = {1.0, 100, {2.5, 2.5, 2.5}, NULL, 0};
  assert_int_equal(rl_checkpoint_write(path, s.sys, &m), RL_OK);

  /* (a) a crashed writer left a partial temporary file: the checkpoint is untouched */
  snprintf(tmp, sizeof tmp, "%s.tmp.%d", path, 99999);
  spit(tmp, (const unsigned char *)"RLCHKPT", 7);
  rl_checkpoint_meta r;
  CHECK_TRUE("partial .tmp beside it: previous checkpoint reads",
             rl_checkpoint_read(path, s.sys, &r) == RL_OK && r.step == 100);
  unlink(tmp);

  /* (b) a child writing large checkpoints (64 MB blob) is killed with SIGKILL while its temporary
   *     file exists, i.e. between open and rename: the parent polls for NAME.tmp.XXXXXX */
  size_t big = 64u << 20;
  char *blob = calloc(big, 1);
  assert_non_null(blob);
  for (int attempt = 0; attempt < 2; attempt++) {
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
      rl_checkpoint_meta w = {2.0, 200, {2.5, 2.5, 2.5}, blob, big};
      for (;;) rl_checkpoint_write(path, s.sys, &w);
    }
    struct stat stt;
    int seen = 0;
    tmp[0] = '\0';
    for (int poll = 0; poll < 20000 && !seen; poll++) { /* <= 20 s */
      if (io_find_tmp(path, tmp, sizeof tmp) && stat(tmp, &stt) == 0 && stt.st_size > (off_t)(attempt ? big / 2 : 0)) seen = 1;
      else {
        struct timespec ts = {0, 1000000L};
        nanosleep(&ts, NULL);
      }
    }
    kill(pid, SIGKILL);
    int ws;
    waitpid(pid, &ws, 0);
    int left = tmp[0] && stat(tmp, &stt) == 0;
    printf("info  attempt %d: child %ld killed while writing; temporary file left behind: %s (%ld bytes)\n",
           attempt + 1, (long)pid, left ? "yes" : "no", left ? (long)stt.st_size : 0L);
    CHECK_TRUE("child killed while its temporary file existed (mid-write)", seen);
    unlink(tmp);
    rl_checkpoint_meta k;
    int st = rl_checkpoint_read(path, s.sys, &k);
    if (st) printf("error: %s\n", rl_last_error());
    CHECK_TRUE("killed mid-write: the checkpoint reads (old or new, never partial)",
               st == RL_OK && (k.step == 100 || (k.step == 200 && k.blob_size == big)));
    free((void *)k.blob);
  }
  free(blob);
  unlink(path);
  io_scene_free(&s);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(round_trip),
      cmocka_unit_test(errors),
      cmocka_unit_test(crash),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
