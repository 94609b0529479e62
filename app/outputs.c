/* The files of one run under output.prefix (outputs.h). */
#define _GNU_SOURCE /* copy_file_range */
#include "outputs.h"

#include <rotleap/rotleap.h>

/* Working files are made by the library's safe calls (io.h): rl_file_create creates a new file
 * under an unused name beside its name (O_EXCL|O_NOFOLLOW) and renames it into place, so a link
 * planted there is replaced, never written through; rl_file_open_existing refuses a link,
 * anything but a regular file, and a file with other names (hard links). */

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct {
  char *path, *part;  /* final and working names; NULL: no such stream            */
  int on;             /* this run writes it                                        */
  int fresh;          /* ... into a working file it created                         */
  FILE *fp;           /* the writer's stream, if the outputs own it                */
  int rfd;            /* read-only descriptor of the working file: sync and hash   */
  int64_t skip;       /* leading bytes outside the hash                            */
  int64_t hashed;     /* the hash covers [skip, hashed)                            */
  uint64_t hash;
} out_stream;

struct outputs {
  char *prefix, *lock_path;
  int lock_fd;
  out_stream s[OUT_NSTREAMS];
};

static const char *const stream_ext[OUT_NSTREAMS] = {"thermo.csv", NULL, "pdb", "samples"};

uint64_t outputs_hash(uint64_t h, const void *bytes, size_t n)
{
  const unsigned char *p = bytes;
  for (size_t i = 0; i < n; i++) h = (h ^ p[i]) * 1099511628211ULL;
  return h;
}

static char *join(const char *a, const char *b, const char *c)
{
  const size_t n = strlen(a) + strlen(b) + strlen(c) + 1;
  char *s = malloc(n);
  if (s) snprintf(s, n, "%s%s%s", a, b, c);
  return s;
}

char *outputs_name(const char *prefix, const char *suffix) { return join(prefix, suffix, ""); }

outputs *outputs_alloc(const char *prefix, const char *traj_ext, int samples)
{
  outputs *o = calloc(1, sizeof *o);
  if (!o) return NULL;
  o->lock_fd = -1;
  int ok = (o->prefix = join(prefix, "", "")) && (o->lock_path = join(prefix, ".lock", ""));
  for (int k = 0; k < OUT_NSTREAMS; k++) {
    out_stream *s = &o->s[k];
    s->rfd = -1;
    const char *ext = k == OUT_TRAJ ? traj_ext : stream_ext[k];
    if ((k == OUT_TOPOLOGY && !(traj_ext && !strcmp(traj_ext, "dcd"))) || (k == OUT_SAMPLES && !samples) || !ext)
      continue;
    ok = ok && (s->path = join(prefix, ".", ext)) && (s->part = join(s->path, ".part", ""));
  }
  if (!ok) {
    outputs_free(o);
    rl_error(RL_ENOMEM, "out of memory for the output names of %s", prefix);
    return NULL;
  }
  return o;
}

static int stream_close_fp(out_stream *s)
{
  int st = RL_OK;
  if (s->fp && fclose(s->fp) != 0)
    st = rl_error(RL_EINVAL, "cannot write %s: %s", s->part, strerror(errno));
  s->fp = NULL;
  return st;
}

void outputs_free(outputs *o)
{
  if (!o) return;
  for (int k = 0; k < OUT_NSTREAMS; k++) {
    out_stream *s = &o->s[k];
    if (s->fp) fclose(s->fp);
    if (s->rfd >= 0) close(s->rfd);
    free(s->path);
    free(s->part);
  }
  if (o->lock_fd >= 0) {
    /* removed while still held: a run that opened it before the unlink finds, once it holds
     * the lock, that the name no longer leads to its file, and tries again (outputs_lock) */
    unlink(o->lock_path);
    close(o->lock_fd);
  }
  free(o->lock_path);
  free(o->prefix);
  free(o);
}

/* ----------------------------------------------------------------------------- the lock */

int outputs_lock(outputs *o)
{
  for (int attempt = 0; attempt < 100; attempt++) {
    const int fd = open(o->lock_path, O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0)
      return rl_error(RL_EINVAL, "cannot create the lock %s: %s (output.prefix = %s)", o->lock_path, strerror(errno),
                      o->prefix);
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int e = errno;
      char pid[32] = "";
      const ssize_t n = e == EWOULDBLOCK ? pread(fd, pid, sizeof pid - 1, 0) : -1;
      close(fd);
      if (n > 0) pid[n] = '\0';
      pid[strcspn(pid, "\n")] = '\0';
      if (e == EWOULDBLOCK)
        return rl_error(RL_EINVAL, "output.prefix = %s is in use by another rotleap run (PID %s, which holds %s): "
                        "wait for it to end, or give another output.prefix", o->prefix, pid[0] ? pid : "unknown",
                        o->lock_path);
      return rl_error(RL_EINVAL, "cannot lock %s: %s", o->lock_path, strerror(e));
    }
    /* the name must still lead to the file locked (a run ending removes it while it holds it) */
    struct stat a, b;
    if (fstat(fd, &a) == 0 && stat(o->lock_path, &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino) {
      char pid[32];
      const int n = snprintf(pid, sizeof pid, "%ld\n", (long)getpid());
      if (ftruncate(fd, 0) != 0 || pwrite(fd, pid, (size_t)n, 0) != n) {
        const int e = errno;
        close(fd);
        return rl_error(RL_EINVAL, "cannot write %s: %s", o->lock_path, strerror(e));
      }
      o->lock_fd = fd;
      return RL_OK;
    }
    close(fd);
  }
  return rl_error(RL_EINVAL, "cannot lock %s: it keeps being replaced", o->lock_path);
}

int outputs_check_dir(const char *prefix)
{
  const char *slash = strrchr(prefix, '/');
  char *dir = slash == prefix ? join("/", "", "") : slash ? strndup(prefix, (size_t)(slash - prefix)) : join(".", "", "");
  if (!dir) return rl_error(RL_ENOMEM, "out of memory");
  struct stat st;
  int r = RL_OK;
  if (stat(dir, &st) != 0)
    r = rl_error(RL_EINVAL, "output.prefix = %s: the directory %s: %s", prefix, dir, strerror(errno));
  else if (!S_ISDIR(st.st_mode))
    r = rl_error(RL_EINVAL, "output.prefix = %s: %s is not a directory", prefix, dir);
  else if ((st.st_mode & S_IWOTH) && !(st.st_mode & S_ISVTX))
    r = rl_error(RL_EINVAL, "output.prefix = %s: the directory %s is writable by every user and has no sticky bit, "
                 "so another user could replace rotleap's files there; write the outputs elsewhere", prefix, dir);
  else if (access(dir, W_OK | X_OK) != 0)
    r = rl_error(RL_EINVAL, "output.prefix = %s: cannot create files in %s: %s", prefix, dir, strerror(errno));
  free(dir);
  return r;
}

const char *outputs_path(const outputs *o, int k) { return o->s[k].path; }
const char *outputs_part(const outputs *o, int k) { return o->s[k].part; }

/* -------------------------------------------------------------------- working files */

static FILE *register_fp(out_stream *s, int fd, const char *mode)
{
  FILE *fp = fdopen(fd, mode);
  if (!fp) {
    rl_error(RL_EINVAL, "cannot open %s: %s", s->part, strerror(errno));
    close(fd);
    return NULL;
  }
  s->fp = fp;
  return fp;
}

FILE *outputs_create(outputs *o, int k)
{
  out_stream *s = &o->s[k];
  int fd;
  if (rl_file_create(s->part, &fd)) return NULL;
  s->on = s->fresh = 1;
  s->skip = s->hashed = 0;
  s->hash = OUTPUTS_HASH_INIT;
  return register_fp(s, fd, "w");
}

void outputs_started(outputs *o, int k, int64_t skip)
{
  out_stream *s = &o->s[k];
  s->on = s->fresh = 1;
  s->skip = s->hashed = skip;
  s->hash = OUTPUTS_HASH_INIT;
}

int outputs_started_p(const outputs *o, int k) { return o->s[k].on; }

/* The hash of bytes [skip, len) of an open file; -1 if it is shorter or cannot be read. */
static int hash_range(int fd, int64_t skip, int64_t len, uint64_t *h)
{
  static unsigned char buf[1 << 16];
  uint64_t x = *h;
  for (int64_t at = skip; at < len;) {
    const size_t want = (size_t)(len - at < (int64_t)sizeof buf ? len - at : (int64_t)sizeof buf);
    const ssize_t got = pread(fd, buf, want, at);
    if (got <= 0) {
      if (got < 0 && errno == EINTR) continue;
      return -1;
    }
    x = outputs_hash(x, buf, (size_t)got);
    at += got;
  }
  *h = x;
  return 0;
}

/* What `path` holds against mark m: 1 its first m->len bytes hash to the mark, 0 it does not
 * (why, in `why`), -1 it does not exist. */
static int file_matches(const char *path, const out_mark *m, char *why, size_t n)
{
  const int fd = open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) { snprintf(why, n, "%s does not exist", path); return -1; }
    snprintf(why, n, "%s cannot be read: %s", path, strerror(errno));
    return 0;
  }
  struct stat st;
  int r = 0;
  uint64_t h = OUTPUTS_HASH_INIT;
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) snprintf(why, n, "%s is not a regular file", path);
  else if (st.st_size < m->len) snprintf(why, n, "%s has %lld bytes, fewer than the %lld", path, (long long)st.st_size, (long long)m->len);
  else if (hash_range(fd, m->skip, m->len, &h) != 0) snprintf(why, n, "%s cannot be read: %s", path, strerror(errno));
  else if (h != m->hash) snprintf(why, n, "%s holds other bytes (another run's)", path);
  else r = 1;
  close(fd);
  return r;
}

int outputs_part_matches(const outputs *o, int k, const out_mark *m)
{
  char why[64];
  return o->s[k].part && m->where != MARK_NONE && file_matches(o->s[k].part, m, why, sizeof why) == 1;
}

/* Copy the first len bytes of src into a new file at dst (created as create_new does). */
static int copy_prefix(const char *src, const char *dst, int64_t len)
{
  const int in = open(src, O_RDONLY | O_CLOEXEC);
  if (in < 0) return rl_error(RL_EINVAL, "cannot read %s: %s", src, strerror(errno));
  int out, st = rl_file_create(dst, &out);
  if (st) { close(in); return st; }
  loff_t from = 0;
  while (!st && from < len) {
    ssize_t got = copy_file_range(in, &from, out, NULL, (size_t)(len - from), 0);
    if (got < 0 && (errno == EXDEV || errno == ENOSYS || errno == EINVAL || errno == EOPNOTSUPP)) {
      static char buf[1 << 16]; /* no in-kernel copy between these files: read and write */
      const size_t want = (size_t)(len - from < (loff_t)sizeof buf ? len - from : (loff_t)sizeof buf);
      got = pread(in, buf, want, from);
      if (got > 0) {
        for (ssize_t w = 0; w < got;) {
          const ssize_t put = write(out, buf + w, (size_t)(got - w));
          if (put < 0) {
            if (errno == EINTR) continue;
            st = rl_error(RL_EINVAL, "cannot write %s: %s", dst, strerror(errno));
            break;
          }
          w += put;
        }
        from += got;
        continue;
      }
    }
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) st = rl_error(RL_EINVAL, "cannot copy %s to %s: %s", src, dst, strerror(errno));
    else if (got == 0) st = rl_error(RL_EINVAL, "cannot copy %s to %s: it ended early", src, dst);
  }
  if (!st && fsync(out) != 0) st = rl_error(RL_EINVAL, "cannot write %s: %s", dst, strerror(errno));
  if (close(out) != 0 && !st) st = rl_error(RL_EINVAL, "cannot write %s: %s", dst, strerror(errno));
  close(in);
  if (st) unlink(dst);
  return st;
}

int outputs_resume(outputs *o, int k, const out_mark *m, const char *src_path, const char *src_part)
{
  out_stream *s = &o->s[k];
  if (m->where == MARK_NONE || m->len < m->skip || m->skip < 0)
    return rl_error(RL_EINVAL, "internal error: resuming %s from an empty mark", s->path);
  /* the file the mark names first; the other name second (a run killed between renaming its
   * working files and writing its last checkpoint left them under their final names) */
  const char *cand[2] = {m->where == MARK_FINAL ? src_path : src_part, m->where == MARK_FINAL ? src_part : src_path};
  char why[2][PATH_MAX + 160];
  int found = -1;
  for (int c = 0; c < 2 && found < 0; c++)
    if (file_matches(cand[c], m, why[c], sizeof why[c]) == 1) found = c;
  if (found < 0)
    return rl_error(RL_EINVAL, "neither %s nor %s holds the first %lld bytes that were in it when the checkpoint "
                    "was written (%s; %s)", cand[0], cand[1], (long long)m->len, why[0], why[1]);
  int st = RL_OK;
  if (!strcmp(cand[found], s->part)) { /* this run's own working file: drop what followed the checkpoint */
    int fd;
    if (!(st = rl_file_open_existing(s->part, O_WRONLY, &fd))) {
      if (ftruncate(fd, (off_t)m->len) != 0 || fsync(fd) != 0)
        st = rl_error(RL_EINVAL, "cannot truncate %s after its first %lld bytes: %s", s->part, (long long)m->len,
                      strerror(errno));
      close(fd);
    }
  } else st = copy_prefix(cand[found], s->part, m->len);
  if (st) return st;
  s->on = 1;
  s->fresh = strcmp(cand[found], s->part) != 0; /* a copy: this run's own file */
  s->skip = m->skip;
  s->hashed = m->len;
  s->hash = m->hash;
  return RL_OK;
}

FILE *outputs_append(outputs *o, int k)
{
  out_stream *s = &o->s[k];
  int fd;
  if (rl_file_open_existing(s->part, O_WRONLY | O_APPEND, &fd)) return NULL;
  FILE *fp = register_fp(s, fd, "a");
  if (fp && fseek(fp, 0, SEEK_END) != 0) { /* the stream's position is its end (the journal checks it) */
    rl_error(RL_EINVAL, "cannot open %s: %s", s->part, strerror(errno));
    return NULL;
  }
  return fp;
}

/* Sync the file open at fd (`name` in messages) and hash its bytes [*hashed, len) on into *hash
 * (len < 0: up to its end); *hashed = len. */
static int mark_fd(int fd, const char *name, int64_t len, int64_t *hashed, uint64_t *hash)
{
  struct stat st;
  if (fsync(fd) != 0 || fstat(fd, &st) != 0) return rl_error(RL_EINVAL, "cannot write %s: %s", name, strerror(errno));
  if (st.st_size < *hashed)
    return rl_error(RL_EINVAL, "%s shrank from %lld to %lld bytes while the run wrote it", name, (long long)*hashed,
                    (long long)st.st_size);
  if (len < 0) len = st.st_size;
  if (len < *hashed || len > st.st_size)
    return rl_error(RL_EINVAL, "%s: a mark of its first %lld bytes, but it holds %lld and %lld are marked already", name,
                    (long long)len, (long long)st.st_size, (long long)*hashed);
  if (hash_range(fd, *hashed, len, hash) != 0)
    return rl_error(RL_EINVAL, "cannot read back %s: %s", name, strerror(errno));
  *hashed = len;
  return RL_OK;
}

int outputs_mark(outputs *o, out_mark marks[OUT_NSTREAMS])
{
  for (int k = 0; k < OUT_NSTREAMS; k++) {
    out_stream *s = &o->s[k];
    memset(&marks[k], 0, sizeof marks[k]);
    if (!s->on) continue;
    if (s->fp && fflush(s->fp) != 0) return rl_error(RL_EINVAL, "cannot write %s: %s", s->part, strerror(errno));
    if (s->rfd < 0 && (s->rfd = open(s->part, O_RDONLY | O_NOFOLLOW | O_CLOEXEC)) < 0)
      return rl_error(RL_EINVAL, "cannot read back %s: %s", s->part, strerror(errno));
    const int st = mark_fd(s->rfd, s->part, -1, &s->hashed, &s->hash);
    if (st) return st;
    marks[k] = (out_mark){MARK_PART, s->hashed, s->skip, s->hash};
  }
  return RL_OK;
}

int outputs_mark_file(const char *path, out_tracker *t, int64_t len, out_mark *m)
{
  memset(m, 0, sizeof *m);
  const int fd = open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return rl_error(RL_EINVAL, "cannot read back %s: %s", path, strerror(errno));
  const int st = mark_fd(fd, path, len, &t->hashed, &t->hash);
  close(fd);
  if (!st) *m = (out_mark){MARK_FINAL, t->hashed, t->skip, t->hash};
  return st;
}

int outputs_close(outputs *o)
{
  int st = RL_OK;
  for (int k = 0; k < OUT_NSTREAMS; k++) {
    const int r = stream_close_fp(&o->s[k]);
    if (!st) st = r;
  }
  return st;
}

/* fsync the directory holding path, so that renames in it are durable. */
static int sync_dir_of(const char *path)
{
  const char *slash = strrchr(path, '/');
  char *dir = slash == path ? join("/", "", "") : slash ? strndup(path, (size_t)(slash - path)) : join(".", "", "");
  if (!dir) return rl_error(RL_ENOMEM, "out of memory");
  const int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  int st = RL_OK;
  if (fd >= 0) {
    if (fsync(fd) != 0 && errno != EINVAL && errno != EROFS) /* some file systems refuse it on directories */
      st = rl_error(RL_EINVAL, "cannot sync the directory %s: %s", dir, strerror(errno));
    close(fd);
  }
  free(dir);
  return st;
}

int outputs_commit(outputs *o, out_mark marks[OUT_NSTREAMS])
{
  int st = RL_OK, renamed = 0;
  for (int k = 0; k < OUT_NSTREAMS && !st; k++) {
    out_stream *s = &o->s[k];
    if (!s->on) continue;
    if (rename(s->part, s->path) != 0)
      st = rl_error(RL_EINVAL, "cannot rename %s to %s: %s", s->part, s->path, strerror(errno));
    else {
      renamed = 1;
      if (marks && marks[k].where == MARK_PART) marks[k].where = MARK_FINAL;
    }
  }
  if (renamed) {
    const int r = sync_dir_of(o->prefix);
    if (!st) st = r;
  }
  return st;
}

void outputs_discard(outputs *o)
{
  for (int k = 0; k < OUT_NSTREAMS; k++) {
    out_stream *s = &o->s[k];
    stream_close_fp(s);
    if (s->on && s->fresh) unlink(s->part);
    s->on = 0;
  }
}
