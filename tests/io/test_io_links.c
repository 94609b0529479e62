/* Links and special files (issue 30 items 6 and 7): nothing is written through a symbolic or hard
 * link planted at an output's name, temporaries are created O_EXCL | O_NOFOLLOW with mode 0666
 * minus the umask, and every reader refuses what is not a regular file (a link to /dev/zero, a
 * FIFO, a directory) instead of reading it forever.  An alarm turns a hang into a failure. */
#include "io_testutil.h"

#include <fcntl.h>
#include <sys/stat.h>

static const char *NAMES[2] = {"tip4p", "stockmayer"};
static const int COUNTS[2] = {4, 4};

static int has_text(const char *path, const char *text)
{
  char buf[256] = "";
  FILE *fp = fopen(path, "r");
  if (!fp) return 0;
  size_t n = fread(buf, 1, sizeof buf - 1, fp);
  fclose(fp);
  buf[n] = '\0';
  return strcmp(buf, text) == 0;
}

static int is_link(const char *path)
{
  struct stat st;
  return lstat(path, &st) == 0 && S_ISLNK(st.st_mode);
}

static void create(void **state)
{
  (void)state;
  char victim[256], out[256], hard[256];
  io_path(victim, sizeof victim, "victim.txt");
  io_path(out, sizeof out, "out.dat");
  io_path(hard, sizeof hard, "hard.dat");
  put_text(victim, "precious");
  unlink(out);
  assert_int_equal(symlink(victim, out), 0);
  int fd = -1;
  assert_int_equal(rl_file_create(out, &fd), RL_OK);
  assert_int_equal(write(fd, "new", 3), 3);
  close(fd);
  CHECK_TRUE("rl_file_create over a symbolic link: the link's target is untouched", has_text(victim, "precious"));
  CHECK_TRUE("rl_file_create over a symbolic link: the name is now a new regular file", !is_link(out) && has_text(out, "new"));
  unlink(hard);
  assert_int_equal(link(victim, hard), 0);
  assert_int_equal(rl_file_create(hard, &fd), RL_OK);
  assert_int_equal(write(fd, "other", 5), 5);
  close(fd);
  CHECK_TRUE("rl_file_create over a hard link: the other name keeps its content", has_text(victim, "precious") && has_text(hard, "other"));
  mode_t old = umask(022);
  unlink(out);
  assert_int_equal(rl_file_create(out, &fd), RL_OK);
  close(fd);
  struct stat st;
  assert_int_equal(stat(out, &st), 0);
  CHECK_TRUE("rl_file_create: mode 0666 minus the umask (0644 under umask 022), not mkstemp's 0600",
             (st.st_mode & 0777) == 0644);
  rl_atomic_file af;
  assert_int_equal(rl_atomic_open(&af, out), RL_OK);
  char tmp[300];
  CHECK_TRUE("rl_atomic_open: its temporary is NAME.tmp.XXXXXX, mode 0644 under umask 022",
             strlen(af.tmp) == strlen(out) + 11 && stat(af.tmp, &st) == 0 && (st.st_mode & 0777) == 0644 &&
             io_find_tmp(out, tmp, sizeof tmp));
  rl_atomic_abort(&af);
  umask(old);
  CHECK_TRUE("rl_atomic_abort removes the temporary", !io_find_tmp(out, tmp, sizeof tmp));
  unlink(out);
  unlink(hard);
  unlink(victim);
}

static void open_existing(void **state)
{
  (void)state;
  char victim[256], lnk[256], hard[256], fifo[256], dir[256];
  io_path(victim, sizeof victim, "victim2.txt");
  io_path(lnk, sizeof lnk, "link2.txt");
  io_path(hard, sizeof hard, "hard2.txt");
  io_path(fifo, sizeof fifo, "fifo2");
  io_path(dir, sizeof dir, "dir2");
  put_text(victim, "precious");
  unlink(lnk); unlink(hard); unlink(fifo); rmdir(dir);
  assert_int_equal(symlink(victim, lnk), 0);
  assert_int_equal(link(victim, hard), 0);
  assert_int_equal(mkfifo(fifo, 0600), 0);
  assert_int_equal(mkdir(dir, 0700), 0);
  int fd = -1;
  CHECK_MSG("rl_file_open_existing: a symbolic link is refused", rl_file_open_existing(lnk, O_RDWR, &fd), RL_EINVAL,
            "is a symbolic link: refusing to follow it");
  CHECK_MSG("rl_file_open_existing: a symbolic link is refused for reading too", rl_file_open_existing(lnk, O_RDONLY, &fd),
            RL_EINVAL, "is a symbolic link");
  CHECK_MSG("rl_file_open_existing: a file with two hard links is refused for writing",
            rl_file_open_existing(hard, O_WRONLY | O_TRUNC, &fd), RL_EINVAL, "has 2 hard links: refusing to write through a link");
  CHECK_TRUE("rl_file_open_existing: ... and O_TRUNC did not truncate it", has_text(victim, "precious"));
  CHECK_MSG("rl_file_open_existing: a FIFO is not a regular file (and does not block)",
            rl_file_open_existing(fifo, O_RDWR, &fd), RL_EINVAL, "not a regular file (a FIFO)");
  CHECK_MSG("rl_file_open_existing: a directory is not a regular file", rl_file_open_existing(dir, O_RDONLY, &fd),
            RL_EINVAL, "not a regular file (a directory)");
  CHECK_MSG("rl_file_open_existing: O_CREAT is refused", rl_file_open_existing(victim, O_RDWR | O_CREAT, &fd), RL_EINVAL,
            "existing files only");
  int st = rl_file_open_existing(hard, O_RDONLY, &fd);
  CHECK_TRUE("rl_file_open_existing: a hard-linked file may be read", st == RL_OK && fd >= 0);
  if (fd >= 0) close(fd);
  unlink(hard);
  st = rl_file_open_existing(victim, O_RDWR | O_APPEND, &fd);
  CHECK_TRUE("rl_file_open_existing: a plain file opens for appending", st == RL_OK && write(fd, "!", 1) == 1);
  close(fd);
  CHECK_TRUE("rl_file_open_existing: ... and is written", has_text(victim, "precious!"));
  unlink(lnk); unlink(fifo); rmdir(dir); unlink(victim);
}

/* Outputs of the library never write through links planted at their names. */
static void writers(void **state)
{
  (void)state;
  io_scene s;
  io_scene_build(&s, RL_UNITS_REAL, NAMES, COUNTS, 1, 1.2, 3);
  char victim[256], out[256], old_tmp[300];
  io_path(victim, sizeof victim, "victim3.txt");
  io_path(out, sizeof out, "w.chk");
  put_text(victim, "precious");
  /* the temporary name of earlier versions, NAME.tmp.<pid>: a link planted there is not followed */
  snprintf(old_tmp, sizeof old_tmp, "%s.tmp.%ld", out, (long)getpid());
  unlink(old_tmp);
  assert_int_equal(symlink(victim, old_tmp), 0);
  rl_checkpoint_meta m = {0.0, 0, {1.2, 1.2, 1.2}, NULL, 0};
  assert_int_equal(rl_checkpoint_write(out, s.sys, &m), RL_OK);
  CHECK_TRUE("checkpoint: a link at NAME.tmp.<pid> is not followed", has_text(victim, "precious") && is_link(old_tmp));
  unlink(old_tmp);
  /* a link at the output's own name is replaced */
  unlink(out);
  assert_int_equal(symlink(victim, out), 0);
  assert_int_equal(rl_checkpoint_write(out, s.sys, &m), RL_OK);
  CHECK_TRUE("checkpoint: a link at NAME is replaced, its target untouched", has_text(victim, "precious") && !is_link(out));
  unlink(out);

  io_path(out, sizeof out, "w.dcd");
  unlink(out);
  assert_int_equal(symlink(victim, out), 0);
  rl_dcd *d = rl_dcd_create(out, s.sys, 0, 1, 0.002, NULL);
  assert_non_null(d);
  assert_int_equal(rl_dcd_write_frame(d, s.sys), RL_OK);
  assert_int_equal(rl_dcd_close(d), RL_OK);
  CHECK_TRUE("DCD create: a link at NAME is replaced, its target untouched", has_text(victim, "precious") && !is_link(out));
  char lnk[256];
  io_path(lnk, sizeof lnk, "w-link.dcd");
  unlink(lnk);
  assert_int_equal(symlink(out, lnk), 0);
  CHECK_MSG("DCD append: a symbolic link is refused", rl_dcd_append(lnk, s.sys, 1) == NULL, 1, "is a symbolic link");
  unlink(lnk);
  assert_int_equal(link(out, lnk), 0);
  CHECK_MSG("DCD append: a file with another hard link is refused", rl_dcd_append(lnk, s.sys, 1) == NULL, 1,
            "has 2 hard links");
  unlink(lnk);
  d = rl_dcd_append(out, s.sys, 1);
  CHECK_TRUE("DCD append: the plain file is accepted", d != NULL);
  assert_int_equal(rl_dcd_close(d), RL_OK);
  unlink(out);
  unlink(victim);
  io_scene_free(&s);
}

/* Readers: a start file linked to /dev/zero, a FIFO, a directory. */
static void readers(void **state)
{
  (void)state;
  io_scene s;
  io_scene_build(&s, RL_UNITS_REAL, NAMES, COUNTS, 2, 1.2, 3);
  char zero[256], fifo[256], dir[256];
  io_path(zero, sizeof zero, "zero.pdb");
  io_path(fifo, sizeof fifo, "fifo.xyz");
  io_path(dir, sizeof dir, "dir.chk");
  unlink(zero); unlink(fifo); rmdir(dir);
  assert_int_equal(symlink("/dev/zero", zero), 0);
  assert_int_equal(mkfifo(fifo, 0600), 0);
  assert_int_equal(mkdir(dir, 0700), 0);
  alarm(20); /* a reader that reads /dev/zero forever or blocks on the FIFO fails here */
  const char *paths[3] = {zero, fifo, dir}, *kinds[3] = {"a character device", "a FIFO", "a directory"};
  for (int k = 0; k < 3; k++) {
    const char *p = paths[k];
    char want[128], name[128];
    snprintf(want, sizeof want, "not a regular file (%s)", kinds[k]);
    int n;
    double box[3];
    long a, b, c;
    rl_checkpoint_meta m;
    snprintf(name, sizeof name, "rl_pdb_count: %s refused", kinds[k]);
    CHECK_MSG(name, rl_pdb_count(p, RL_UNITS_REAL, &n, box), RL_EINVAL, want);
    snprintf(name, sizeof name, "rl_pdb_read_state: %s refused", kinds[k]);
    CHECK_MSG(name, rl_pdb_read_state(p, s.sys, s.mols, 0.0, NULL, NULL), RL_EINVAL, want);
    snprintf(name, sizeof name, "rl_xyz_count: %s refused", kinds[k]);
    CHECK_MSG(name, rl_xyz_count(p, &n), RL_EINVAL, want);
    snprintf(name, sizeof name, "rl_xyz_read_state: %s refused", kinds[k]);
    CHECK_MSG(name, rl_xyz_read_state(p, s.sys, box), RL_EINVAL, want);
    snprintf(name, sizeof name, "rl_checkpoint_read: %s refused", kinds[k]);
    CHECK_MSG(name, rl_checkpoint_read(p, s.sys, &m), RL_EINVAL, want);
    snprintf(name, sizeof name, "rl_checkpoint_load: %s refused", kinds[k]);
    CHECK_MSG(name, rl_checkpoint_load(p, &m) != NULL, 0, want);
    snprintf(name, sizeof name, "rl_dcd_info: %s refused", kinds[k]);
    CHECK_MSG(name, rl_dcd_info(p, &a, &b, &c), RL_EINVAL, want);
    snprintf(name, sizeof name, "rl_dcd_layout: %s refused", kinds[k]);
    CHECK_MSG(name, rl_dcd_layout(p, &a, &b), RL_EINVAL, want);
  }
  alarm(0);
  unlink(zero); unlink(fifo); rmdir(dir);
  io_scene_free(&s);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(create),
      cmocka_unit_test(open_existing),
      cmocka_unit_test(writers),
      cmocka_unit_test(readers),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
