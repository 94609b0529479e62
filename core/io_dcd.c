/* CHARMM/NAMD DCD trajectories (the format MDTraj, VMD, MDAnalysis read).
 *
 * Layout (little-endian, each record framed by 32-bit Fortran length markers):
 *   header  84 bytes: "CORD", ICNTRL[20]: NSET, ISTART, NSAVC, NSTEP, 0 x 5, DELTA (float32),
 *           1 (unit cell present), 0 x 8, 24 (CHARMM version)
 *   title   4 + 80 k bytes: NTITLE, NTITLE lines of 80 characters
 *   natom   4 bytes
 *   frame   unit cell 6 doubles (a, gamma, b, beta, alpha, c; angles in degrees, as NAMD),
 *           then X, Y, Z records of NATOM float32 each. */
#include "io_internal.h"
#include "rotleap/error.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define DCD_HEADER_BYTES 276L /* 92 + (4 + 164 + 4) + (4 + 4 + 4) */
#define DCD_NSET_OFFSET 8L

struct rl_dcd {
  FILE *fp;
  char *path;
  int natoms;
  long nset, nsavc;
  int status;           /* first error, sticky */
  unsigned char *bytes; /* [4 natoms + 8] */
};

static long frame_bytes(int natoms) { return 56L + 3L * (8L + 4L * natoms); }

static int io_fail(rl_dcd *d, const char *what)
{
  int e = errno;
  d->status = rl_error(RL_EINVAL, "%s: DCD %s failed: %s", d->path, what, e ? strerror(e) : "I/O error");
  return d->status;
}

static int put_record(rl_dcd *d, const unsigned char *data, uint32_t n)
{
  unsigned char m[4];
  rl_le32(m, n);
  if (fwrite(m, 1, 4, d->fp) != 4 || (n && fwrite(data, 1, n, d->fp) != n) || fwrite(m, 1, 4, d->fp) != 4)
    return io_fail(d, "write");
  return RL_OK;
}

static void dcd_free(rl_dcd *d)
{
  if (!d) return;
  if (d->fp) fclose(d->fp);
  free(d->path);
  free(d->bytes);
  free(d);
}

static rl_dcd *dcd_new(const char *path, const rl_system *sys)
{
  rl_dcd *d = calloc(1, sizeof *d);
  if (!d) { rl_error(RL_ENOMEM, "%s: out of memory", path); return NULL; }
  d->natoms = rl_io_natoms(sys);
  d->path = malloc(strlen(path) + 1);
  d->bytes = malloc(4 * (size_t)d->natoms + 8);
  if (!d->path || !d->bytes) {
    dcd_free(d);
    rl_error(RL_ENOMEM, "%s: out of memory for %d atoms", path, rl_io_natoms(sys));
    return NULL;
  }
  strcpy(d->path, path);
  return d;
}

/* Rewrite NSET and NSTEP in the header and return to the end. */
static int update_count(rl_dcd *d)
{
  unsigned char b[4];
  if (fflush(d->fp) != 0 || fseek(d->fp, DCD_NSET_OFFSET, SEEK_SET) != 0) return io_fail(d, "header seek");
  rl_le32(b, (uint32_t)d->nset);
  if (fwrite(b, 1, 4, d->fp) != 4) return io_fail(d, "header update");
  if (fseek(d->fp, DCD_NSET_OFFSET + 12, SEEK_SET) != 0) return io_fail(d, "header seek");
  rl_le32(b, (uint32_t)(d->nset * d->nsavc));
  if (fwrite(b, 1, 4, d->fp) != 4) return io_fail(d, "header update");
  if (fflush(d->fp) != 0 || fseek(d->fp, 0, SEEK_END) != 0) return io_fail(d, "seek to end");
  return RL_OK;
}

rl_dcd *rl_dcd_create(const char *path, const rl_system *sys, long first_step, long interval,
                      double dt, const char *title)
{
  if (!path || !sys) { rl_error(RL_EINVAL, "rl_dcd_create: NULL argument"); return NULL; }
  if (interval < 1) { rl_error(RL_EINVAL, "%s: DCD frame interval %ld must be >= 1", path, interval); return NULL; }
  rl_dcd *d = dcd_new(path, sys);
  if (!d) return NULL;
  d->nsavc = interval;
  d->fp = fopen(path, "w+b");
  if (!d->fp) {
    int e = errno;
    rl_error(RL_EINVAL, "%s: cannot create DCD: %s", path, strerror(e));
    dcd_free(d);
    return NULL;
  }
  unsigned char h[84] = {0};
  memcpy(h, "CORD", 4);
  rl_le32(h + 4, 0);                          /* NSET, updated per frame */
  rl_le32(h + 8, (uint32_t)first_step);       /* ISTART */
  rl_le32(h + 12, (uint32_t)interval);        /* NSAVC */
  rl_le32(h + 16, 0);                         /* NSTEP */
  float delta = (float)dt;
  uint32_t du;
  memcpy(&du, &delta, 4);
  rl_le32(h + 4 + 4 * 9, du);                 /* DELTA */
  rl_le32(h + 4 + 4 * 10, 1);                 /* unit cell in every frame */
  rl_le32(h + 4 + 4 * 19, 24);                /* CHARMM version */
  unsigned char t[164];
  memset(t, ' ', sizeof t);
  rl_le32(t, 2);
  char line[81];
  snprintf(line, sizeof line, "REMARKS %s", title ? title : "rotleap trajectory");
  memcpy(t + 4, line, strlen(line));
  snprintf(line, sizeof line, "REMARKS units: %s", sys->units == RL_UNITS_REAL ? "Angstrom" : "sigma (reduced)");
  memcpy(t + 84, line, strlen(line));
  unsigned char na[4];
  rl_le32(na, (uint32_t)d->natoms);
  if (put_record(d, h, 84) || put_record(d, t, 164) || put_record(d, na, 4) || fflush(d->fp) != 0) {
    if (!d->status) io_fail(d, "header write");
    dcd_free(d);
    return NULL;
  }
  return d;
}

int rl_dcd_info(const char *path, long *first_step, long *interval, long *frames)
{
  if (!path) return rl_error(RL_EINVAL, "rl_dcd_info: NULL path");
  FILE *fp = fopen(path, "rb");
  if (!fp) return rl_error(RL_EINVAL, "%s: cannot open DCD: %s", path, strerror(errno));
  unsigned char h[DCD_HEADER_BYTES];
  struct stat st;
  const int ok = fread(h, 1, sizeof h, fp) == sizeof h && fstat(fileno(fp), &st) == 0;
  fclose(fp);
  if (!ok) return rl_error(RL_EINVAL, "%s: DCD header truncated (< %ld bytes)", path, DCD_HEADER_BYTES);
  if (rl_get32(h) != 84 || memcmp(h + 4, "CORD", 4) != 0 || rl_get32(h + 264) != 4)
    return rl_error(RL_EINVAL, "%s: not a little-endian CORD DCD", path);
  if (first_step) *first_step = (long)rl_get32(h + 12);
  if (interval) *interval = (long)rl_get32(h + 16);
  if (frames) *frames = ((long)st.st_size - DCD_HEADER_BYTES) / frame_bytes((int)rl_get32(h + 268));
  return RL_OK;
}

rl_dcd *rl_dcd_append(const char *path, const rl_system *sys, long keep_frames)
{
  if (!path || !sys) { rl_error(RL_EINVAL, "rl_dcd_append: NULL argument"); return NULL; }
  rl_dcd *d = dcd_new(path, sys);
  if (!d) return NULL;
  d->fp = fopen(path, "r+b");
  if (!d->fp) {
    int e = errno;
    rl_error(RL_EINVAL, "%s: cannot open DCD for appending: %s", path, strerror(e));
    dcd_free(d);
    return NULL;
  }
  unsigned char h[DCD_HEADER_BYTES];
  if (fread(h, 1, sizeof h, d->fp) != sizeof h) {
    rl_error(RL_EINVAL, "%s: DCD header truncated (< %ld bytes)", path, DCD_HEADER_BYTES);
    dcd_free(d);
    return NULL;
  }
  if (rl_get32(h) != 84 || memcmp(h + 4, "CORD", 4) != 0 || rl_get32(h + 88) != 84 ||
      rl_get32(h + 92) != 164 || rl_get32(h + 264) != 4 || rl_get32(h + 4 + 4 + 40) != 1) {
    rl_error(RL_EINVAL, "%s: not a DCD written by rotleap (little-endian CORD header with a unit "
             "cell and a 2-line title expected)", path);
    dcd_free(d);
    return NULL;
  }
  int natoms = (int)rl_get32(h + 268);
  if (natoms != d->natoms) {
    rl_error(RL_EINVAL, "%s: DCD has %d atoms, the system writes %d", path, natoms, d->natoms);
    dcd_free(d);
    return NULL;
  }
  d->nsavc = (long)rl_get32(h + 16);
  struct stat st;
  if (fstat(fileno(d->fp), &st) != 0) { io_fail(d, "stat"); dcd_free(d); return NULL; }
  long have = ((long)st.st_size - DCD_HEADER_BYTES) / frame_bytes(natoms);
  if (keep_frames < 0 || keep_frames > have) {
    rl_error(RL_EINVAL, "%s: DCD holds %ld complete frames, cannot keep %ld", path, have, keep_frames);
    dcd_free(d);
    return NULL;
  }
  fflush(d->fp);
  if (ftruncate(fileno(d->fp), DCD_HEADER_BYTES + keep_frames * frame_bytes(natoms)) != 0) {
    io_fail(d, "truncate");
    dcd_free(d);
    return NULL;
  }
  d->nset = keep_frames;
  if (update_count(d)) { dcd_free(d); return NULL; }
  return d;
}

int rl_dcd_write_frame(rl_dcd *d, const rl_system *sys, const double box[3])
{
  if (!d || !sys) return rl_error(RL_EINVAL, "rl_dcd_write_frame: NULL argument");
  if (d->status) return rl_error(d->status, "%s: DCD is in an error state", d->path);
  if (rl_io_natoms(sys) != d->natoms)
    return rl_error(RL_EINVAL, "%s: system has %d atoms, DCD %d", d->path, rl_io_natoms(sys), d->natoms);
  double s = rl_io_length_scale(sys);
  unsigned char cell[48];
  double c6[6] = {box ? box[0] * s : 0.0, 90.0, box ? box[1] * s : 0.0, 90.0, 90.0, box ? box[2] * s : 0.0};
  for (int k = 0; k < 6; k++) {
    uint64_t u;
    memcpy(&u, &c6[k], 8);
    rl_le64(cell + 8 * k, u);
  }
  int st = put_record(d, cell, 48);
  if (st) return st;
  double(*x)[3] = rl_io_atom_positions(sys);
  if (!x) return d->status = RL_ENOMEM;
  for (int c = 0; c < 3 && !st; c++) {
    for (int a = 0; a < d->natoms; a++) {
      float f = (float)(x[a][c] * s);
      uint32_t u;
      memcpy(&u, &f, 4);
      rl_le32(d->bytes + 4 * a, u);
    }
    st = put_record(d, d->bytes, (uint32_t)(4 * d->natoms));
  }
  free(x);
  if (st) return st;
  d->nset++;
  return update_count(d);
}

long rl_dcd_frames(const rl_dcd *d) { return d ? d->nset : 0; }

int rl_dcd_close(rl_dcd *d)
{
  if (!d) return RL_OK;
  int st = d->status;
  if (fflush(d->fp) != 0 && !st) st = io_fail(d, "flush");
  if (fclose(d->fp) != 0 && !st) st = io_fail(d, "close");
  d->fp = NULL;
  dcd_free(d);
  return st;
}
