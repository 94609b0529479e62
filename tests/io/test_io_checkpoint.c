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
  assert_int_equal(rl_system_set_box(s.sys, m.box), RL_OK); /* the system's box is written */
  assert_int_equal(rl_checkpoint_write(path, s.sys, &m), RL_OK);
  CHECK_TRUE("round trip: states differ before reading", !same_state(s.sys, t.sys));
  rl_checkpoint_meta r;
  int st = rl_checkpoint_read(path, t.sys, &r);
  if (st) printf("error: %s\n", rl_last_error());
  assert_int_equal(st, RL_OK);
  CHECK_TRUE("round trip: r, v, l, A, rho and DOF bit for bit (memcmp)", same_state(s.sys, t.sys));
  double tb[3];
  rl_system_box(t.sys, tb);
  CHECK_TRUE("round trip: time, step, box bit for bit (in meta and in the system read into)",
             memcmp(&r.time, &m.time, sizeof m.time) == 0 && r.step == m.step && memcmp(r.box, m.box, sizeof m.box) == 0 &&
                 memcmp(tb, m.box, sizeof tb) == 0);
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

/* ------------------------------------------------------------------ crafted checkpoints */

/* Offsets of the fields of a version-1 checkpoint (file offsets), found by walking its layout. */
typedef struct {
  size_t units, dof, time, step, box, nspecies, n, nrot, nmat, naxis, r, v, l, A, rho, blob;
  size_t name[4], kind[4], mass[4], J[4], nsites[4], sites[4], count[4];
} ck_offsets;

static uint32_t le32(const unsigned char *p) { return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24; }

static void ck_walk(const unsigned char *b, ck_offsets *o)
{
  o->units = 24; o->dof = 28; o->time = 32; o->step = 40; o->box = 48; o->nspecies = 72;
  size_t at = 76;
  uint32_t ns = le32(b + o->nspecies);
  assert_true(ns <= 4);
  for (uint32_t k = 0; k < ns; k++) {
    o->name[k] = at; at += 4 + le32(b + at);
    o->kind[k] = at; at += 4;
    o->mass[k] = at; at += 8;
    o->J[k] = at; at += 24;
    o->nsites[k] = at; at += 4;
    o->sites[k] = at; at += 24 * le32(b + o->nsites[k]);
    o->count[k] = at; at += 4;
  }
  o->n = at; o->nrot = at + 4; o->nmat = at + 8; o->naxis = at + 12;
  at += 16;
  o->r = at; at += 24 * le32(b + o->n);
  o->v = at; at += 24 * le32(b + o->n);
  o->l = at; at += 24 * le32(b + o->nrot);
  o->A = at; at += 72 * le32(b + o->nmat);
  o->rho = at; at += 24 * le32(b + o->naxis);
  o->blob = at;
}

static void set_f64(unsigned char *p, double x) { uint64_t u; memcpy(&u, &x, 8); for (int k = 0; k < 8; k++) p[k] = (unsigned char)(u >> (8 * k)); }
static double get_f64(const unsigned char *p) { uint64_t u = 0; for (int k = 0; k < 8; k++) u |= (uint64_t)p[k] << (8 * k); double x; memcpy(&x, &u, 8); return x; }
static void set_u32(unsigned char *p, uint32_t v) { for (int k = 0; k < 4; k++) p[k] = (unsigned char)(v >> (8 * k)); }
static void set_u64(unsigned char *p, uint64_t v) { for (int k = 0; k < 8; k++) p[k] = (unsigned char)(v >> (8 * k)); }

/* Write b (n bytes) to path with its CRC-32 trailer recomputed: a crafted but intact file. */
static void spit_crc(const char *path, unsigned char *b, size_t n)
{
  uint32_t c = crc32_ref(b, n - 4);
  set_u32(b + n - 4, c);
  spit(path, b, n);
}

typedef void (*craft_fn)(unsigned char *b, const ck_offsets *o);
static void c_time_nan(unsigned char *b, const ck_offsets *o) { set_f64(b + o->time, NAN); }
static void c_time_inf(unsigned char *b, const ck_offsets *o) { set_f64(b + o->time, -INFINITY); }
static void c_step_neg(unsigned char *b, const ck_offsets *o) { set_u64(b + o->step, (uint64_t)-5); }
static void c_box_zero(unsigned char *b, const ck_offsets *o) { set_f64(b + o->box, 0.0); }
static void c_box_nan(unsigned char *b, const ck_offsets *o) { set_f64(b + o->box + 16, NAN); }
static void c_box_neg(unsigned char *b, const ck_offsets *o) { set_f64(b + o->box + 8, -2.5); }
static void c_units(unsigned char *b, const ck_offsets *o) { set_u32(b + o->units, 7); }
static void c_dof(unsigned char *b, const ck_offsets *o) { set_u32(b + o->dof, 9); }
static void c_dof_neg(unsigned char *b, const ck_offsets *o) { set_u32(b + o->dof, (uint32_t)-1); }
static void c_kind(unsigned char *b, const ck_offsets *o) { set_u32(b + o->kind[1], 9); }
static void c_mass(unsigned char *b, const ck_offsets *o) { set_f64(b + o->mass[0], 0.0); }
static void c_mass_nan(unsigned char *b, const ck_offsets *o) { set_f64(b + o->mass[3], NAN); }
static void c_J_nan(unsigned char *b, const ck_offsets *o) { set_f64(b + o->J[0] + 8, NAN); }
static void c_J_zero(unsigned char *b, const ck_offsets *o) { set_f64(b + o->J[0] + 16, 0.0); }
static void c_J_lin(unsigned char *b, const ck_offsets *o) { set_f64(b + o->J[2], 0.0); }
static void c_site(unsigned char *b, const ck_offsets *o) { set_f64(b + o->sites[0] + 24 + 8, INFINITY); }
static void c_count(unsigned char *b, const ck_offsets *o) { set_u32(b + o->count[3], (uint32_t)-1); }
static void c_n(unsigned char *b, const ck_offsets *o) { set_u32(b + o->count[3], 9); }
static void c_r(unsigned char *b, const ck_offsets *o) { set_f64(b + o->r + 24 * 4 + 8, NAN); }
static void c_v(unsigned char *b, const ck_offsets *o) { set_f64(b + o->v + 24 * 47, INFINITY); }
static void c_l(unsigned char *b, const ck_offsets *o) { set_f64(b + o->l + 24 * 30 + 16, NAN); }
static void c_A_ortho(unsigned char *b, const ck_offsets *o) { set_f64(b + o->A + 72 * 2, get_f64(b + o->A + 72 * 2) * (1 + 1e-7)); }
static void c_A_refl(unsigned char *b, const ck_offsets *o)
{
  for (int k = 0; k < 3; k++) set_f64(b + o->A + 72 * 6 + 8 * k, -get_f64(b + o->A + 72 * 6 + 8 * k));
}
static void c_A_nan(unsigned char *b, const ck_offsets *o) { set_f64(b + o->A + 72 * 19 + 64, NAN); }
static void c_rho(unsigned char *b, const ck_offsets *o) { set_f64(b + o->rho + 24 * 13, get_f64(b + o->rho + 24 * 13) + 1e-6); }
static void c_nspecies(unsigned char *b, const ck_offsets *o) { set_u32(b + o->nspecies, 999999); }
static void c_nsites(unsigned char *b, const ck_offsets *o) { set_u32(b + o->nsites[0], 3000000); }
static void c_name(unsigned char *b, const ck_offsets *o) { set_u32(b + o->name[0], 200); }
static void c_blob(unsigned char *b, const ck_offsets *o) { set_u64(b + o->blob, (uint64_t)1 << 40); }

/* Every field is validated: each crafted file has a correct CRC, and each refusal names the
 * file and the field (and the body, counted from 1: tip4p 1-20, stockmayer 21-32, co2 33-38,
 * Ar 39-48). */
static void crafted(void **state)
{
  (void)state;
  io_scene s;
  mixed(&s, 11);
  char path[256], bad[256];
  io_path(path, sizeof path, "ok.chk");
  io_path(bad, sizeof bad, "crafted.chk");
  rl_checkpoint_meta m = {0.5, 10, {2.5, 2.5, 2.5}, "blob", 4};
  assert_int_equal(rl_checkpoint_write(path, s.sys, &m), RL_OK);
  size_t n;
  unsigned char *orig = slurp(path, &n), *b = malloc(n);
  assert_non_null(b);
  ck_offsets o;
  ck_walk(orig, &o);
  assert_int_equal(o.blob + 8 + 4 + 4, n); /* the walk ends at the blob size, blob, CRC */
  static const struct {
    craft_fn f;
    const char *what, *msg;
  } cases[] = {
      {c_time_nan, "time NaN", "checkpoint field 'time' is nan: not finite"},
      {c_time_inf, "time -inf", "checkpoint field 'time' is -inf: not finite"},
      {c_step_neg, "step -5", "checkpoint field 'step' is -5: negative"},
      {c_box_zero, "box edge 0", "checkpoint field 'box' edge 1 is 0: must be finite and > 0"},
      {c_box_nan, "box edge NaN", "checkpoint field 'box' edge 3 is nan"},
      {c_box_neg, "box edge -2.5", "checkpoint field 'box' edge 2 is -2.5"},
      {c_units, "units 7", "checkpoint field 'units' is 7: 0 (real) or 1 (lj) expected"},
      {c_dof, "removed DOF 9", "checkpoint field 'removed_dof' is 9: 0 to 3 expected"},
      {c_dof_neg, "removed DOF -1", "checkpoint field 'removed_dof' is -1"},
      {c_kind, "kind 9", "species 2 ('stockmayer'): checkpoint field 'kind' is 9: not a known kind"},
      {c_mass, "mass 0", "species 1 ('tip4p'): checkpoint field 'mass' is 0: must be finite and > 0"},
      {c_mass_nan, "mass NaN", "species 4 ('Ar'): checkpoint field 'mass' is nan"},
      {c_J_nan, "moment NaN", "species 1 ('tip4p'): checkpoint field 'J[1]' is nan"},
      {c_J_zero, "moment 0 of an asymmetric top", "species 1 ('tip4p'): checkpoint field 'J[2]' is 0: must be finite and > 0 for this kind"},
      {c_J_lin, "moment 0 of a linear molecule's J[0]", "species 3 ('co2'): checkpoint field 'J[0]' is 0"},
      {c_site, "site coordinate inf", "species 1 ('tip4p'): checkpoint field 'sites': site 2 is not finite"},
      {c_count, "count -1", "species 4 ('Ar'): checkpoint field 'count' is -1: negative"},
      {c_n, "species count 9 for 10 bodies", "checkpoint fields 'n', 'nrot', 'nmat', 'naxis' (48, 38, 20, 18) do not match its species table (47, 38, 20, 18)"},
      {c_r, "r NaN", "checkpoint field 'r' of body 5 is not finite"},
      {c_v, "v inf", "checkpoint field 'v' of body 48 is not finite"},
      {c_l, "l NaN", "checkpoint field 'l' of body 31 is not finite"},
      {c_A_ortho, "A off by 1e-7", "checkpoint field 'A': body 3: orientation matrix is not orthonormal"},
      {c_A_refl, "A a reflection", "checkpoint field 'A': body 7: orientation matrix is a reflection"},
      {c_A_nan, "A NaN", "checkpoint field 'A': body 20: orientation has a non-finite element"},
      {c_rho, "rho not unit", "checkpoint field 'rho' of body 34 is not a unit vector"},
      {c_nspecies, "species count 999999", "checkpoint species count 999999 does not fit in the"},
      {c_nsites, "site count 3000000", "species 1: checkpoint site count 3000000 does not fit in the"},
      {c_name, "name length 200", "species 1: checkpoint field 'name' is 200 bytes long (at most 63)"},
      {c_blob, "blob size 2^40", "checkpoint payload ends inside blob"},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    memcpy(b, orig, n);
    cases[k].f(b, &o);
    spit_crc(bad, b, n);
    char name[128];
    rl_checkpoint_meta r = {0};
    snprintf(name, sizeof name, "crafted (valid CRC), read: %s", cases[k].what);
    CHECK_MSG(name, rl_checkpoint_read(bad, s.sys, &r), RL_EINVAL, cases[k].msg);
    snprintf(name, sizeof name, "crafted (valid CRC), load: %s", cases[k].what);
    rl_system *u = rl_checkpoint_load(bad, &r);
    CHECK_MSG(name, u != NULL, 0, cases[k].msg);
    rl_system_free(u);
  }
  memcpy(b, orig, n);
  spit_crc(bad, b, n);
  rl_checkpoint_meta r = {0};
  CHECK_TRUE("the crafting helper itself: the unmodified bytes with their CRC read", rl_checkpoint_read(bad, s.sys, &r) == RL_OK);
  free((void *)r.blob);
  free(orig);
  free(b);
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
      cmocka_unit_test(crafted),
      cmocka_unit_test(crash),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
