/* Hostile inputs (issue 30 item 7): counts read from a file are bounded by the file's size before
 * anything is allocated for them, text lines are capped, and each refusal names file:line.  One
 * crafted file per case; under the sanitizer build an allocation of gigabytes or an int overflow
 * would abort the test. */
#include "io_testutil.h"

#include <stdint.h>

static void xyz(void **state)
{
  (void)state;
  const char *names[1] = {"stockmayer"};
  int counts[1] = {2}, n = -1;
  io_scene s;
  io_scene_build(&s, RL_UNITS_LJ, names, counts, 1, 2.0, 1);
  char path[256];
  io_path(path, sizeof path, "h.xyz");
  const char *body = "stockmayer 0 0 0 0 0 1\nstockmayer 1 1 1 0 0 1\n";
  char text[512];

  /* a Properties= count that drove a 5.9 GB allocation, and two that overflow an int */
  snprintf(text, sizeof text, "2\nProperties=species:S:1:pos:R:3:orientation:R:3:junk:R:735000000\n%s", body);
  put_text(path, text);
  CHECK_MSG("XYZ: a Properties= count beyond what a line can hold is refused", rl_xyz_read_state(path, s.sys, NULL),
            RL_EINVAL, ":2: Properties= announces 735000000 columns for 'junk' after 7 others");
  snprintf(text, sizeof text, "2\nProperties=species:S:1:pos:R:3:a:R:2000000000:b:R:2000000000\n%s", body);
  put_text(path, text);
  CHECK_MSG("XYZ: two large Properties= counts (int overflow) are refused", rl_xyz_read_state(path, s.sys, NULL),
            RL_EINVAL, ":2: Properties= announces 2000000000 columns for 'a'");
  snprintf(text, sizeof text, "2\nProperties=species:S:1:pos:R:3:a:R:20000:b:R:20000\n%s", body);
  put_text(path, text);
  CHECK_MSG("XYZ: counts that only together exceed a line are refused", rl_xyz_read_state(path, s.sys, NULL),
            RL_EINVAL, ":2: Properties= announces 20000 columns for 'b' after 20004 others");
  snprintf(text, sizeof text, "2\nProperties=species:S:1:pos:R:99999999999999999999\n%s", body);
  put_text(path, text);
  CHECK_MSG("XYZ: a count beyond long is malformed, not wrapped", rl_xyz_read_state(path, s.sys, NULL), RL_EINVAL,
            ":2: Properties= announces");

  /* the particle count is bounded by the file's size (each body's line has >= 6 bytes) */
  put_text(path, "1000000000\ncomment\nstockmayer 0 0 0 0 0 1\n");
  CHECK_MSG("XYZ: a particle count the file cannot hold is refused by rl_xyz_count", rl_xyz_count(path, &n), RL_EINVAL,
            ":1: 1000000000 particles announced, but a file of 42 bytes holds at most 7");
  put_text(path, "99999999999999999999999\ncomment\n");
  CHECK_MSG("XYZ: a count beyond long long is refused", rl_xyz_count(path, &n), RL_EINVAL,
            ":1: expected the number of particles");

  /* line length cap and NUL bytes */
  FILE *fp = fopen(path, "w");
  fprintf(fp, "2\n");
  for (int k = 0; k < 70000; k++) fputc('x', fp);
  fprintf(fp, "\n%s", body);
  fclose(fp);
  CHECK_MSG("XYZ: a comment line of 70,000 characters is refused, naming the line", rl_xyz_read_state(path, s.sys, NULL),
            RL_EINVAL, ":2: line longer than 65536 characters");
  fp = fopen(path, "w");
  fprintf(fp, "2\ncomment\nstockmayer 0 0 0 0 0 1\nstockmayer 1 1");
  fputc('\0', fp);
  fprintf(fp, " 1 0 0 1\n");
  fclose(fp);
  CHECK_MSG("XYZ: a NUL byte is refused, naming the line", rl_xyz_read_state(path, s.sys, NULL), RL_EINVAL,
            ":4: a NUL byte: not a text file");
  fp = fopen(path, "w");
  fprintf(fp, "2\n");
  for (int k = 0; k < 60000; k++) fputc('x', fp);
  fprintf(fp, "\n%s", body);
  fclose(fp);
  CHECK_TRUE("XYZ: a comment line of 60,000 characters is read", rl_xyz_read_state(path, s.sys, NULL) == RL_OK);
  unlink(path);
  io_scene_free(&s);
}

static void pdb(void **state)
{
  (void)state;
  char path[256];
  io_path(path, sizeof path, "h.pdb");
  int n;
  FILE *fp = fopen(path, "w");
  fprintf(fp, "REMARK   1 test\nREMARK   2 ");
  for (int k = 0; k < 2000; k++) fputc('x', fp);
  fprintf(fp, "\nEND\n");
  fclose(fp);
  CHECK_MSG("PDB: a line of 2,011 characters is refused, naming the line", rl_pdb_count(path, RL_UNITS_REAL, &n, NULL),
            RL_EINVAL, ":2: line longer than 1024 characters");
  fp = fopen(path, "w");
  fprintf(fp, "REMARK   1 test\nATOM      1  OW  SOL A   1       1.000   2.000   3.000  1.00  0.00");
  fputc('\0', fp);
  fprintf(fp, "\nEND\n");
  fclose(fp);
  CHECK_MSG("PDB: a NUL byte is refused, naming the line", rl_pdb_count(path, RL_UNITS_REAL, &n, NULL), RL_EINVAL,
            ":2: a NUL byte: not a text file");
  unlink(path);
}

/* A DCD header (276 bytes, the layout rl_dcd_create writes) with chosen fields. */
static void dcd_header(unsigned char h[276], uint32_t title, uint32_t natoms, uint32_t namnf)
{
  memset(h, 0, 276);
  const uint32_t v[][2] = {{0, 84}, {88, 84}, {92, title}, {260, 164}, {264, 4}, {268, natoms}, {272, 4},
                           {8 + 4 * 8, namnf}, {8 + 4 * 10, 1}, {8 + 4 * 19, 24}, {8 + 4 * 2, 1}};
  for (size_t k = 0; k < sizeof v / sizeof v[0]; k++)
    for (int b = 0; b < 4; b++) h[v[k][0] + (uint32_t)b] = (unsigned char)(v[k][1] >> (8 * b));
  memcpy(h + 4, "CORD", 4);
}

static void put_bytes(const char *path, const unsigned char *b, size_t n)
{
  FILE *fp = fopen(path, "wb");
  assert_non_null(fp);
  assert_int_equal(fwrite(b, 1, n, fp), n);
  fclose(fp);
}

static void dcd(void **state)
{
  (void)state;
  char path[256];
  io_path(path, sizeof path, "h.dcd");
  unsigned char h[276];
  long a = -1, b = -1, c = -1;
  dcd_header(h, 164, 113, 0);
  put_bytes(path, h, sizeof h);
  CHECK_TRUE("DCD: a well-formed header with no frames: 276 + 56 + 3 (8 + 4 x 113) bytes per frame, 0 frames",
             rl_dcd_layout(path, &a, &b) == RL_OK && a == 276 && b == 56 + 3 * (8 + 4 * 113) &&
             rl_dcd_info(path, NULL, NULL, &c) == RL_OK && c == 0);
  dcd_header(h, 0x7FFFFFF0u, 113, 0);
  put_bytes(path, h, sizeof h);
  CHECK_MSG("DCD: a title record longer than the file is refused", rl_dcd_info(path, &a, &b, &c), RL_EINVAL,
            "DCD title record of 2147483632 bytes does not fit in the file (276 bytes)");
  dcd_header(h, 164, 0x7FFFFFFFu, 0);
  put_bytes(path, h, sizeof h);
  CHECK_TRUE("DCD: 2^31 - 1 atoms: frame size computed without overflow, 0 frames",
             rl_dcd_layout(path, &a, &b) == RL_OK && b == 56 + 3 * (8 + 4 * 2147483647L) &&
             rl_dcd_info(path, NULL, NULL, &c) == RL_OK && c == 0);
  dcd_header(h, 164, 0xFFFFFFFFu, 0);
  put_bytes(path, h, sizeof h);
  CHECK_MSG("DCD: a negative atom count is refused", rl_dcd_info(path, &a, &b, &c), RL_EINVAL,
            "DCD atom count 4294967295 is out of range");
  dcd_header(h, 164, 113, 5);
  put_bytes(path, h, sizeof h);
  CHECK_MSG("DCD: fixed atoms (another first-frame layout) are refused", rl_dcd_layout(path, &a, &b), RL_EINVAL,
            "DCD with 5 fixed atoms (NAMNF) is not supported");
  put_bytes(path, h, 50);
  CHECK_MSG("DCD: a truncated header is refused", rl_dcd_layout(path, &a, &b), RL_EINVAL, "DCD header truncated (50 bytes)");
  unlink(path);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(xyz),
      cmocka_unit_test(pdb),
      cmocka_unit_test(dcd),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
