/* CHARMM/NAMD DCD trajectories (the format MDTraj, VMD, MDAnalysis read).
 *
 * Layout (little-endian, each record framed by 32-bit Fortran length markers):
 *   header  84 bytes: "CORD", ICNTRL[20]: NSET, ISTART, NSAVC, NSTEP, 0 x 4, NAMNF = 0, DELTA
 *           (float32), 1 (unit cell present), 0 (no 4th dimension), 0 x 7, 24 (CHARMM version)
 *   title   4 + 80 k bytes: NTITLE, NTITLE lines of 80 characters
 *   natom   4 bytes
 *   frame   unit cell 6 doubles (a, gamma, b, beta, alpha, c; angles in degrees, as NAMD),
 *           then X, Y, Z records of NATOM float32 each.
 *
 * Written with pwrite(2) on a descriptor (no stdio buffer): a frame is one write at the end of
 * the file, then the 16 bytes NSET, ISTART, NSAVC, NSTEP of the header are rewritten in place.
 * The errno of the first failing call is the message; later calls return that status. */
#include "io_internal.h"
#include "rotleap/error.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define DCD_TITLE_BYTES 164L /* NTITLE = 2 lines of 80 characters */
#define DCD_COUNTS_OFFSET 8L /* NSET, ISTART, NSAVC, NSTEP */

struct rl_dcd {
  int fd;
  char *path;
  int natoms;
  long nset, istart, nsavc;
  long long header, frame, end; /* bytes before frame 1, bytes per frame, end of the last frame */
  int status;                   /* first error, sticky */
  unsigned char *buf;           /* one frame */
};

/* What a DCD's header says, checked against the file's size. */
typedef struct {
  long long header, frame, size;
  long nset, istart, nsavc;
  int natoms, cell, title;
} dcd_hdr;

static long long frame_bytes(long long natoms, int cell) { return (cell ? 56LL : 0LL) + 3LL * (8LL + 4LL * natoms); }

/* Read and check the header of the DCD open on fd (size bytes).  Every length it holds is
 * bounded by the file's size before it is used. */
static int parse_header(int fd, long long size, const char *path, dcd_hdr *h)
{
  unsigned char b[100], t[12];
  memset(h, 0, sizeof *h);
  h->size = size;
  int e = size < (long long)sizeof b ? -1 : rl_io_read_at(fd, b, sizeof b, 0);
  if (e > 0) return rl_io_sys_error(e, path, "cannot read the DCD header");
  if (e < 0) return rl_error(RL_EINVAL, "%s: DCD header truncated (%lld bytes)", path, size);
  if (rl_get32(b) != 84 || memcmp(b + 4, "CORD", 4) != 0 || rl_get32(b + 88) != 84)
    return rl_error(RL_EINVAL, "%s: not a little-endian CORD DCD", path);
  const uint32_t title = rl_get32(b + 92);
  if (title < 4 || (long long)title > size - 112)
    return rl_error(RL_EINVAL, "%s: DCD title record of %u bytes does not fit in the file (%lld bytes)", path,
                    title, size);
  if ((e = rl_io_read_at(fd, t, sizeof t, 96 + (long long)title)))
    return e > 0 ? rl_io_sys_error(e, path, "cannot read the DCD header")
                 : rl_error(RL_EINVAL, "%s: DCD header truncated (%lld bytes)", path, size);
  const uint32_t natoms = rl_get32(t + 8);
  if (rl_get32(t) != title || rl_get32(t + 4) != 4)
    return rl_error(RL_EINVAL, "%s: not a little-endian CORD DCD (record markers)", path);
  unsigned char m[4];
  if ((e = rl_io_read_at(fd, m, 4, 108 + (long long)title)) || rl_get32(m) != 4)
    return e > 0 ? rl_io_sys_error(e, path, "cannot read the DCD header")
                 : rl_error(RL_EINVAL, "%s: not a little-endian CORD DCD (atom count record)", path);
  if (natoms < 1 || natoms > 0x7FFFFFFFu)
    return rl_error(RL_EINVAL, "%s: DCD atom count %u is out of range", path, natoms);
  const uint32_t charmm = rl_get32(b + 84), namnf = rl_get32(b + 40);
  if (namnf != 0) return rl_error(RL_EINVAL, "%s: DCD with %u fixed atoms (NAMNF) is not supported", path, namnf);
  if (charmm != 0 && rl_get32(b + 52) != 0)
    return rl_error(RL_EINVAL, "%s: DCD with a fourth dimension is not supported", path);
  h->header = 112 + (long long)title;
  h->title = (int)title;
  h->natoms = (int)natoms;
  h->cell = charmm != 0 && rl_get32(b + 48) != 0;
  h->frame = frame_bytes(natoms, h->cell);
  h->nset = (long)(int32_t)rl_get32(b + 8);
  h->istart = (long)(int32_t)rl_get32(b + 12);
  h->nsavc = (long)(int32_t)rl_get32(b + 16);
  return RL_OK;
}

/* Open path for reading (a regular file; links followed) and parse its header. */
static int read_header(const char *path, dcd_hdr *h)
{
  if (!path) return rl_error(RL_EINVAL, "DCD: NULL path");
  int fd;
  long long size;
  int st = rl_io_open_read(path, " DCD", &fd, &size);
  if (st) return st;
  st = parse_header(fd, size, path, h);
  close(fd);
  return st;
}

static int fail(rl_dcd *d, int e, const char *what)
{
  return d->status = rl_io_sys_error(e, d->path, what);
}

static void dcd_free(rl_dcd *d)
{
  if (!d) return;
  if (d->fd >= 0) close(d->fd);
  free(d->path);
  free(d->buf);
  free(d);
}

static rl_dcd *dcd_new(const char *path, const rl_system *sys)
{
  rl_dcd *d = calloc(1, sizeof *d);
  if (!d) { rl_error(RL_ENOMEM, "%s: out of memory", path); return NULL; }
  d->fd = -1;
  d->natoms = rl_io_natoms(sys);
  d->frame = frame_bytes(d->natoms, 1);
  d->path = malloc(strlen(path) + 1);
  d->buf = malloc((size_t)d->frame);
  if (!d->path || !d->buf) {
    dcd_free(d);
    rl_error(RL_ENOMEM, "%s: out of memory for %d atoms", path, rl_io_natoms(sys));
    return NULL;
  }
  strcpy(d->path, path);
  return d;
}

/* Rewrite NSET, ISTART, NSAVC and NSTEP (one write of 16 bytes). */
static int update_counts(rl_dcd *d)
{
  unsigned char b[16];
  rl_le32(b, (uint32_t)d->nset);
  rl_le32(b + 4, (uint32_t)d->istart);
  rl_le32(b + 8, (uint32_t)d->nsavc);
  rl_le32(b + 12, (uint32_t)(d->nset * d->nsavc));
  int e = rl_io_write_all(d->fd, b, sizeof b, DCD_COUNTS_OFFSET);
  return e ? fail(d, e, "cannot update the DCD's frame count") : RL_OK;
}

static void put_marker(unsigned char **p, uint32_t n)
{
  rl_le32(*p, n);
  *p += 4;
}

rl_dcd *rl_dcd_create(const char *path, const rl_system *sys, long first_step, long interval,
                      double dt, const char *title)
{
  if (!path || !sys) { rl_error(RL_EINVAL, "rl_dcd_create: NULL argument"); return NULL; }
  if (interval < 1) { rl_error(RL_EINVAL, "%s: DCD frame interval %ld must be >= 1", path, interval); return NULL; }
  rl_dcd *d = dcd_new(path, sys);
  if (!d) return NULL;
  d->nsavc = interval;
  d->istart = first_step;
  if (rl_file_create(path, &d->fd)) { dcd_free(d); return NULL; }
  unsigned char h[112 + DCD_TITLE_BYTES] = {0}, *p = h;
  put_marker(&p, 84);
  memcpy(p, "CORD", 4);
  unsigned char *ic = p + 4; /* ICNTRL[20] */
  rl_le32(ic + 4 * 1, (uint32_t)first_step); /* ISTART (NSET, NSTEP: update_counts) */
  rl_le32(ic + 4 * 2, (uint32_t)interval);   /* NSAVC */
  /* DELTA: CHARMM and NAMD store the time step in AKMA units (1 AKMA = 4.888821e-14 s =
   * 0.04888821 ps), and MDAnalysis converts it so (MDAnalysis/units.py: timeUnit_factor['AKMA'] =
   * 1 / 4.888821e-2 per ps; DCDReader: dt = DELTA x NSAVC in AKMA -> ps), as does OpenMM's
   * DCDFile (dt in ps / 0.04888821).  MDTraj's load_dcd ignores DELTA (its time is the frame
   * index).  Reduced (lj) time has no AKMA equivalent: it is stored as it is. */
  float delta = (float)(sys->units == RL_UNITS_REAL ? dt / RL_DCD_AKMA_PS : dt);
  uint32_t du;
  memcpy(&du, &delta, 4);
  rl_le32(ic + 4 * 9, du);
  rl_le32(ic + 4 * 10, 1);  /* unit cell in every frame */
  rl_le32(ic + 4 * 19, 24); /* CHARMM version */
  p += 84;
  put_marker(&p, 84);
  put_marker(&p, DCD_TITLE_BYTES);
  unsigned char *t = p;
  memset(t, ' ', DCD_TITLE_BYTES);
  rl_le32(t, 2);
  char line[81];
  snprintf(line, sizeof line, "REMARKS %s", title ? title : "rotleap trajectory");
  memcpy(t + 4, line, strlen(line));
  snprintf(line, sizeof line, "REMARKS units: %s", sys->units == RL_UNITS_REAL ? "Angstrom" : "sigma (reduced)");
  memcpy(t + 84, line, strlen(line));
  p += DCD_TITLE_BYTES;
  put_marker(&p, DCD_TITLE_BYTES);
  put_marker(&p, 4);
  put_marker(&p, (uint32_t)d->natoms);
  put_marker(&p, 4);
  d->header = d->end = (long long)(p - h);
  int e = rl_io_write_all(d->fd, h, (size_t)d->header, 0);
  if (e || update_counts(d)) {
    if (e) fail(d, e, "cannot write the DCD header");
    dcd_free(d);
    return NULL;
  }
  return d;
}

int rl_dcd_info(const char *path, long *first_step, long *interval, long *frames)
{
  dcd_hdr h;
  int st = read_header(path, &h);
  if (st) return st;
  if (first_step) *first_step = h.istart;
  if (interval) *interval = h.nsavc;
  if (frames) *frames = (long)((h.size - h.header) / h.frame);
  return RL_OK;
}

int rl_dcd_layout(const char *path, long *header_bytes, long *frame_bytes)
{
  dcd_hdr h;
  int st = read_header(path, &h);
  if (st) return st;
  if (header_bytes) *header_bytes = (long)h.header;
  if (frame_bytes) *frame_bytes = (long)h.frame;
  return RL_OK;
}

rl_dcd *rl_dcd_append(const char *path, const rl_system *sys, long keep_frames)
{
  if (!path || !sys) { rl_error(RL_EINVAL, "rl_dcd_append: NULL argument"); return NULL; }
  rl_dcd *d = dcd_new(path, sys);
  if (!d) return NULL;
  if (rl_file_open_existing(path, O_RDWR, &d->fd)) { dcd_free(d); return NULL; }
  struct stat sb;
  if (fstat(d->fd, &sb) != 0) { fail(d, errno, "cannot stat the DCD"); dcd_free(d); return NULL; }
  dcd_hdr h;
  if (parse_header(d->fd, (long long)sb.st_size, path, &h)) { dcd_free(d); return NULL; }
  if (!h.cell) {
    rl_error(RL_EINVAL, "%s: not a DCD written by rotleap (CHARMM DCD with a unit cell per frame expected)", path);
    dcd_free(d);
    return NULL;
  }
  if (h.natoms != d->natoms) {
    rl_error(RL_EINVAL, "%s: DCD has %d atoms, the system writes %d", path, h.natoms, d->natoms);
    dcd_free(d);
    return NULL;
  }
  const long have = (long)((h.size - h.header) / h.frame);
  if (keep_frames < 0 || keep_frames > have) {
    rl_error(RL_EINVAL, "%s: DCD holds %ld complete frames, cannot keep %ld", path, have, keep_frames);
    dcd_free(d);
    return NULL;
  }
  d->header = h.header;
  d->istart = h.istart;
  d->nsavc = h.nsavc;
  d->nset = keep_frames;
  d->end = h.header + keep_frames * h.frame;
  if (ftruncate(d->fd, (off_t)d->end) != 0) {
    fail(d, errno, "cannot truncate the DCD");
    dcd_free(d);
    return NULL;
  }
  if (update_counts(d)) { dcd_free(d); return NULL; }
  return d;
}

int rl_dcd_write_frame(rl_dcd *d, const rl_system *sys)
{
  double Lb[3] = {0, 0, 0};
  if (sys) rl_system_box(sys, Lb);
  const double *box = sys && rl_system_periodic(sys) ? Lb : NULL;
  if (!d || !sys) return rl_error(RL_EINVAL, "rl_dcd_write_frame: NULL argument");
  if (d->status) return d->status; /* reported when it happened */
  if (rl_io_natoms(sys) != d->natoms)
    return rl_error(RL_EINVAL, "%s: system has %d atoms, DCD %d", d->path, rl_io_natoms(sys), d->natoms);
  double s = rl_io_length_scale(sys);
  double(*x)[3] = rl_io_atom_positions(sys);
  if (!x) return rl_error_wrap(RL_ENOMEM, "%s", d->path);
  unsigned char *p = d->buf;
  double c6[6] = {box ? box[0] * s : 0.0, 90.0, box ? box[1] * s : 0.0, 90.0, 90.0, box ? box[2] * s : 0.0};
  put_marker(&p, 48);
  for (int k = 0; k < 6; k++, p += 8) {
    uint64_t u;
    memcpy(&u, &c6[k], 8);
    rl_le64(p, u);
  }
  put_marker(&p, 48);
  const uint32_t rec = (uint32_t)(4 * d->natoms);
  for (int c = 0; c < 3; c++) {
    put_marker(&p, rec);
    for (int a = 0; a < d->natoms; a++, p += 4) {
      float f = (float)(x[a][c] * s);
      uint32_t u;
      memcpy(&u, &f, 4);
      rl_le32(p, u);
    }
    put_marker(&p, rec);
  }
  free(x);
  int e = rl_io_write_all(d->fd, d->buf, (size_t)d->frame, d->end);
  if (e) return fail(d, e, "cannot write a DCD frame");
  d->end += d->frame;
  d->nset++;
  return update_counts(d);
}

long rl_dcd_frames(const rl_dcd *d) { return d ? d->nset : 0; }

int rl_dcd_sync(rl_dcd *d)
{
  if (!d) return rl_error(RL_EINVAL, "rl_dcd_sync: NULL argument");
  if (d->status) return d->status;
  int st = update_counts(d);
  if (!st && fsync(d->fd) != 0) st = fail(d, errno, "cannot sync the DCD to disk");
  return st;
}

int rl_dcd_close(rl_dcd *d)
{
  if (!d) return RL_OK;
  int st = d->status;
  if (d->fd >= 0 && close(d->fd) != 0 && !st) st = fail(d, errno, "cannot close the DCD");
  d->fd = -1;
  dcd_free(d);
  return st;
}
