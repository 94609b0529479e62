/* File helpers shared by the I/O modules: opening files safely, checked writes, atomic whole-file
 * writes, atom lists, names, CRC-32. */
#define _GNU_SOURCE /* fopencookie: an atomic file's stream keeps the errno of its first failure */
#include "io_internal.h"
#include "rotleap/error.h"

#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static char *dupstr(const char *s)
{
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

int rl_io_sys_error(int e, const char *path, const char *what)
{
  return rl_error(RL_EINVAL, "%s: %s: %s", path, what, strerror(e ? e : EIO));
}

int rl_io_write_all(int fd, const void *buf, size_t n, long long off)
{
  const char *p = buf;
  while (n > 0) {
    ssize_t w = off < 0 ? write(fd, p, n) : pwrite(fd, p, n, (off_t)off);
    if (w < 0 && errno == EINTR) continue;
    if (w < 0) return errno ? errno : EIO;
    if (w == 0) return EIO;
    p += w;
    n -= (size_t)w;
    if (off >= 0) off += w;
  }
  return 0;
}

int rl_io_read_at(int fd, void *buf, size_t n, long long off)
{
  char *p = buf;
  while (n > 0) {
    ssize_t r = pread(fd, p, n, (off_t)off);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) return errno ? errno : EIO;
    if (r == 0) return -1;
    p += r;
    n -= (size_t)r;
    off += r;
  }
  return 0;
}

static const char *file_type(mode_t m)
{
  return S_ISDIR(m) ? "a directory" : S_ISCHR(m) ? "a character device" : S_ISBLK(m) ? "a block device"
         : S_ISFIFO(m) ? "a FIFO" : S_ISSOCK(m) ? "a socket" : S_ISLNK(m) ? "a symbolic link" : "not a file";
}

/* Clear O_NONBLOCK (set at open so that a FIFO cannot block the open itself). */
static int set_blocking(int fd)
{
  int fl = fcntl(fd, F_GETFL);
  return fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) < 0 ? errno : 0;
}

int rl_io_open_read(const char *path, const char *what, int *fd, long long *size)
{
  *fd = -1;
  if (!path || !*path) return rl_error(RL_EINVAL, "empty file name");
  int f = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (f < 0) {
    int e = errno;
    return rl_error(RL_EINVAL, "%s: cannot open%s: %s", path, what, strerror(e));
  }
  struct stat st;
  if (fstat(f, &st) != 0) {
    int e = errno;
    close(f);
    return rl_io_sys_error(e, path, "cannot stat");
  }
  if (!S_ISREG(st.st_mode)) {
    close(f);
    return rl_error(RL_EINVAL, "%s: not a regular file (%s): refusing to read it", path, file_type(st.st_mode));
  }
  int e = set_blocking(f);
  if (e) { close(f); return rl_io_sys_error(e, path, "cannot open"); }
  *fd = f;
  *size = (long long)st.st_size;
  return RL_OK;
}

int rl_io_fopen_read(const char *path, const char *what, FILE **fp, long long *size)
{
  int fd, st = rl_io_open_read(path, what, &fd, size);
  if (st) return st;
  *fp = fdopen(fd, "r");
  if (!*fp) {
    int e = errno;
    close(fd);
    return rl_io_sys_error(e, path, "cannot open");
  }
  return RL_OK;
}

int rl_io_getline(FILE *fp, const char *path, long lineno, size_t max, char **buf, size_t *cap, int *got)
{
  size_t n = 0;
  int c = EOF;
  *got = 0;
  while ((c = getc_unlocked(fp)) != EOF && c != '\n') {
    if (c == '\0') return rl_error(RL_EINVAL, "%s:%ld: a NUL byte: not a text file", path, lineno);
    if (n >= max) return rl_error(RL_EINVAL, "%s:%ld: line longer than %zu characters", path, lineno, max);
    if (n + 2 > *cap) {
      size_t nc = *cap ? 2 * *cap : 256;
      if (nc > max + 2) nc = max + 2;
      char *b = realloc(*buf, nc);
      if (!b) return rl_error(RL_ENOMEM, "%s:%ld: out of memory", path, lineno);
      *buf = b;
      *cap = nc;
    }
    (*buf)[n++] = (char)c;
  }
  if (c == EOF && ferror(fp)) return rl_io_sys_error(errno, path, "read error");
  if (c == EOF && n == 0) return RL_OK;
  if (!*buf) { /* an empty line first */
    if (!(*buf = malloc(*cap = 256))) return rl_error(RL_ENOMEM, "%s:%ld: out of memory", path, lineno);
  }
  if (n && (*buf)[n - 1] == '\r') n--;
  (*buf)[n] = '\0';
  *got = 1;
  return RL_OK;
}

/* --------------------------------------------------------------------- names beside a file */

/* NAME.tmp.XXXXXX, six characters from the kernel's random source (the clock and a counter as
 * a fallback), as mkstemp's, but created here so that the mode is 0666 minus the umask. */
static void temp_name(char *tmp, size_t n, const char *path)
{
  static const char al[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
  static _Atomic unsigned long counter;
  unsigned char r[6];
  if (getrandom(r, sizeof r, GRND_NONBLOCK) != (ssize_t)sizeof r) {
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    unsigned long x = (unsigned long)ts.tv_nsec ^ ((unsigned long)ts.tv_sec << 20) ^
                      ((unsigned long)getpid() << 40) ^ (++counter * 0x9E3779B97F4A7C15ul);
    for (int k = 0; k < 6; k++, x = x * 6364136223846793005ul + 1442695040888963407ul) r[k] = (unsigned char)(x >> 56);
  }
  snprintf(tmp, n, "%s.tmp.", path);
  size_t o = strlen(tmp);
  for (int k = 0; k < 6; k++) tmp[o + (size_t)k] = al[r[k] % 62];
  tmp[o + 6] = '\0';
}

/* Create a new temporary file beside path: O_CREAT | O_EXCL | O_NOFOLLOW (a name planted there,
 * link or file, is never opened: another name is drawn), mode 0666 minus the umask. */
static int create_temp(const char *path, char **tmp, int *fd)
{
  size_t n = strlen(path) + 16;
  *tmp = malloc(n);
  if (!*tmp) return rl_error(RL_ENOMEM, "%s: out of memory", path);
  for (int attempt = 0; attempt < 100; attempt++) {
    temp_name(*tmp, n, path);
    *fd = open(*tmp, O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (*fd >= 0) return RL_OK;
    if (errno != EEXIST) break;
  }
  int e = errno;
  rl_error(RL_EINVAL, "%s: cannot create a temporary file beside it (%s): %s", path, *tmp, strerror(e));
  free(*tmp);
  *tmp = NULL;
  return RL_EINVAL;
}

int rl_io_sync_dir(const char *path)
{
  const char *slash = strrchr(path, '/');
  char *dir = slash == path ? dupstr("/") : slash ? strndup(path, (size_t)(slash - path)) : dupstr(".");
  if (!dir) return rl_error(RL_ENOMEM, "%s: out of memory", path);
  int st = RL_OK, fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0 || (fsync(fd) != 0 && errno != EINVAL && errno != ENOTSUP && errno != EROFS)) {
    int e = errno;
    st = rl_error(RL_EINVAL, "%s: cannot sync its directory %s: %s", path, dir, strerror(e));
  }
  if (fd >= 0) close(fd);
  free(dir);
  return st;
}

int rl_file_create(const char *path, int *fd)
{
  if (fd) *fd = -1;
  if (!path || !*path || !fd) return rl_error(RL_EINVAL, "rl_file_create: empty file name or NULL fd");
  char *tmp;
  int f, st = create_temp(path, &tmp, &f);
  if (st) return st;
  /* rename replaces the name itself: a link there is replaced, never followed or written */
  if (rename(tmp, path) != 0) {
    int e = errno;
    close(f);
    unlink(tmp);
    st = rl_error(RL_EINVAL, "%s: cannot create it (renaming %s over it): %s", path, tmp, strerror(e));
    free(tmp);
    return st;
  }
  free(tmp);
  if ((st = rl_io_sync_dir(path))) { close(f); return st; }
  *fd = f;
  return RL_OK;
}

int rl_file_open_existing(const char *path, int flags, int *fd)
{
  if (fd) *fd = -1;
  if (!path || !*path || !fd) return rl_error(RL_EINVAL, "rl_file_open_existing: empty file name or NULL fd");
  if (flags & (O_CREAT | O_EXCL))
    return rl_error(RL_EINVAL, "%s: rl_file_open_existing opens existing files only (no O_CREAT)", path);
  const int writing = (flags & O_ACCMODE) != O_RDONLY, trunc = (flags & O_TRUNC) != 0;
  /* O_TRUNC after the checks: truncating a file with another name would write through it */
  int f = open(path, (flags & ~O_TRUNC) | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (f < 0) {
    int e = errno;
    struct stat ls;
    if (e == ELOOP && lstat(path, &ls) == 0 && S_ISLNK(ls.st_mode))
      return rl_error(RL_EINVAL, "%s: is a symbolic link: refusing to follow it", path);
    return rl_error(RL_EINVAL, "%s: cannot open: %s", path, strerror(e));
  }
  struct stat st;
  int e = fstat(f, &st) != 0 ? errno : 0;
  if (e) { close(f); return rl_io_sys_error(e, path, "cannot stat"); }
  if (!S_ISREG(st.st_mode)) {
    close(f);
    return rl_error(RL_EINVAL, "%s: not a regular file (%s): refusing to open it", path, file_type(st.st_mode));
  }
  if (writing && st.st_nlink > 1) {
    close(f);
    return rl_error(RL_EINVAL, "%s: has %lu hard links: refusing to write through a link (another name "
                    "shares this file)", path, (unsigned long)st.st_nlink);
  }
  if ((e = set_blocking(f)) || (trunc && ftruncate(f, 0) != 0 && (e = errno))) {
    close(f);
    return rl_io_sys_error(e, path, "cannot open");
  }
  *fd = f;
  return RL_OK;
}

/* --------------------------------------------------------------------- atomic whole files */

/* The stream of an atomic file writes through these, so that the errno of its first failed
 * write, flush or close is kept for the message (stdio forgets it). */
typedef struct {
  int fd;
  int err; /* errno of the first failure, 0 if none */
} atomic_io;

static ssize_t aio_write(void *c, const char *buf, size_t n)
{
  atomic_io *io = c;
  if (io->err) { errno = io->err; return 0; }
  int e = rl_io_write_all(io->fd, buf, n, -1);
  if (e) { io->err = e; errno = e; return 0; }
  return (ssize_t)n;
}

static int aio_seek(void *c, off64_t *off, int whence)
{
  atomic_io *io = c;
  off_t r = lseek(io->fd, (off_t)*off, whence);
  if (r < 0) { if (!io->err) io->err = errno; return -1; }
  *off = r;
  return 0;
}

static int aio_close(void *c)
{
  atomic_io *io = c;
  int r = close(io->fd);
  if (r != 0 && !io->err) io->err = errno;
  io->fd = -1;
  return r;
}

int rl_atomic_open(rl_atomic_file *a, const char *path)
{
  memset(a, 0, sizeof *a);
  if (!path || !*path) return rl_error(RL_EINVAL, "rl_atomic_open: empty file name");
  atomic_io *io = calloc(1, sizeof *io);
  a->path = dupstr(path);
  if (!io || !a->path) {
    free(io); free(a->path);
    memset(a, 0, sizeof *a);
    return rl_error(RL_ENOMEM, "%s: out of memory", path);
  }
  int st = create_temp(path, &a->tmp, &io->fd);
  if (st) { free(io); free(a->path); memset(a, 0, sizeof *a); return st; }
  cookie_io_functions_t fns = {NULL, aio_write, aio_seek, aio_close};
  a->fp = fopencookie(io, "w", fns);
  if (!a->fp) {
    int e = errno;
    close(io->fd);
    unlink(a->tmp);
    free(io); free(a->path); free(a->tmp);
    memset(a, 0, sizeof *a);
    return rl_io_sys_error(e, path, "cannot open a stream");
  }
  a->io = io;
  return RL_OK;
}

void rl_atomic_abort(rl_atomic_file *a)
{
  if (!a) return;
  if (a->fp) fclose(a->fp);
  if (a->tmp) unlink(a->tmp);
  free(a->io);
  free(a->path);
  free(a->tmp);
  memset(a, 0, sizeof *a);
}

int rl_atomic_fail(rl_atomic_file *a)
{
  const atomic_io *io = a->io;
  int st = rl_error(RL_EINVAL, "%s: cannot write %s: %s", a->path, a->tmp, strerror(io && io->err ? io->err : EIO));
  rl_atomic_abort(a);
  return st;
}

int rl_atomic_commit(rl_atomic_file *a)
{
  if (!a || !a->fp) return rl_error(RL_ESTATE, "rl_atomic_commit: file is not open");
  atomic_io *io = a->io;
  if (fflush(a->fp) != 0 || ferror(a->fp) || io->err) return rl_atomic_fail(a);
  if (fsync(io->fd) != 0) {
    int e = errno;
    rl_error(RL_EINVAL, "%s: cannot sync %s to disk: %s", a->path, a->tmp, strerror(e));
    rl_atomic_abort(a);
    return RL_EINVAL;
  }
  int closed = fclose(a->fp);
  a->fp = NULL;
  if (closed != 0 || io->err) return rl_atomic_fail(a);
  if (rename(a->tmp, a->path) != 0) {
    int e = errno;
    rl_error(RL_EINVAL, "%s: cannot rename %s over it: %s", a->path, a->tmp, strerror(e));
    rl_atomic_abort(a);
    return RL_EINVAL;
  }
  int st = rl_io_sync_dir(a->path);
  free(a->io);
  free(a->path);
  free(a->tmp);
  memset(a, 0, sizeof *a);
  return st;
}

int rl_io_natoms(const rl_system *sys)
{
  int n = 0;
  for (int k = 0; k < sys->nspecies; k++)
    n += sys->sp[k].count * (sys->sp[k].nsites > 0 ? sys->sp[k].nsites : 1);
  return n;
}

double rl_io_length_scale(const rl_system *sys) { return sys->units == RL_UNITS_REAL ? 10.0 : 1.0; }

double (*rl_io_atom_positions(const rl_system *sys))[3]
{
  int na = rl_io_natoms(sys), ns = sys->nsites_total;
  double(*x)[3] = malloc(sizeof *x * (size_t)(na > 0 ? na : 1));
  double(*s)[3] = malloc(sizeof *s * (size_t)(ns > 0 ? ns : 1));
  if (!x || !s) {
    free(x); free(s);
    rl_error(RL_ENOMEM, "out of memory for %d atom positions", na);
    return NULL;
  }
  if (ns > 0) rl_system_site_positions(sys, s);
  int o = 0;
  for (int k = 0; k < sys->nspecies; k++) {
    const rl_species *sp = &sys->sp[k];
    for (int b = 0; b < sp->count; b++) {
      int i = sp->first + b;
      if (sp->nsites == 0) { memcpy(x[o++], sys->r[i], sizeof x[0]); continue; }
      int so = sp->site_off + b * sp->nsites;
      for (int a = 0; a < sp->nsites; a++) memcpy(x[o++], s[so + a], sizeof x[0]);
    }
  }
  free(s);
  return x;
}

void rl_io_site_name(const rl_system *sys, const rl_molecule *const *mols, int species, int a,
                     char out[8])
{
  const rl_molecule *m = mols ? mols[species] : NULL;
  if (sys->sp[species].nsites == 0) {
    const char *nm = sys->sp[species].name;
    snprintf(out, 8, "%.3s", nm[0] ? nm : "X");
    for (char *c = out; *c; c++) *c = (char)toupper((unsigned char)*c);
    return;
  }
  if (m && a < m->nsites && m->site_names[a][0]) {
    if (strcmp(m->site_names[a], "M") == 0 && m->site_mass[a] == 0.0) strcpy(out, "MW");
    else snprintf(out, 8, "%.4s", m->site_names[a]);
  } else {
    snprintf(out, 8, "S%d", (a + 1) % 1000);
  }
}

void rl_io_res_name(const rl_system *sys, int species, char out[4])
{
  const char *nm = sys->sp[species].name;
  int n = 0;
  for (const char *c = nm; *c && n < 3; c++)
    if (isalnum((unsigned char)*c)) out[n++] = (char)toupper((unsigned char)*c);
  if (n == 0) { strcpy(out, "MOL"); return; }
  out[n] = '\0';
}

uint32_t rl_crc32(uint32_t crc, const void *buf, size_t len)
{ /* nibble-at-a-time: a 16-entry constant table (thread-safe, no initialisation) */
  static const uint32_t t[16] = {
      0x00000000u, 0x1DB71064u, 0x3B6E20C8u, 0x26D930ACu, 0x76DC4190u, 0x6B6B51F4u,
      0x4DB26158u, 0x5005713Cu, 0xEDB88320u, 0xF00F9344u, 0xD6D6A3E8u, 0xCB61B38Cu,
      0x9B64C2B0u, 0x86D3D2D4u, 0xA00AE278u, 0xBDBDF21Cu};
  const unsigned char *p = buf;
  crc = ~crc;
  for (size_t i = 0; i < len; i++) {
    crc ^= p[i];
    crc = t[crc & 15] ^ (crc >> 4);
    crc = t[crc & 15] ^ (crc >> 4);
  }
  return ~crc;
}
