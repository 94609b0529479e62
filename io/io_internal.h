/* Shared helpers of the file modules io/io_*.c (not installed). */
#ifndef ROTLEAP_IO_INTERNAL_H
#define ROTLEAP_IO_INTERNAL_H

#include "rotleap/io.h"
#include "../core/system_impl.h"

#include <stdint.h>
#include <stdio.h>

/* Longest line the text readers (extended XYZ, PDB) accept, in characters. */
#define RL_IO_MAX_LINE 65536

/* Open `path` for reading, following symbolic links, and refuse anything but a regular file (a
 * FIFO, a device such as /dev/zero, a directory: "PATH: not a regular file (a character
 * device)").  `what` names the kind of file in messages ("" or e.g. " DCD": "cannot open DCD").
 * *size: the file's size in bytes.  The descriptor is blocking and close-on-exec. */
int rl_io_open_read(const char *path, const char *what, int *fd, long long *size);
/* The same as a stdio stream. */
int rl_io_fopen_read(const char *path, const char *what, FILE **fp, long long *size);

/* Read one line of a text file into *buf (grown as needed; the '\n' and a trailing '\r' removed).
 * *got: 1 for a line, 0 at the end of the file.  A line longer than `max` characters, a NUL byte
 * (a binary file) and a read error are errors naming path:lineno. */
int rl_io_getline(FILE *fp, const char *path, long lineno, size_t max, char **buf, size_t *cap, int *got);

/* Write all n bytes, at offset `off` (pwrite) or, for off < 0, at the current position (write),
 * retrying short writes and EINTR.  0, or the errno of the failing call (EIO for a write of 0). */
int rl_io_write_all(int fd, const void *buf, size_t n, long long off);
/* Read n bytes at offset off.  0, the errno of a failing read, or -1 if the file ends first. */
int rl_io_read_at(int fd, void *buf, size_t n, long long off);
/* rl_error(RL_EINVAL, "PATH: WHAT: strerror(e)"). */
int rl_io_sys_error(int e, const char *path, const char *what);
/* fsync the directory holding path (a rename into it is then durable).  File systems that do not
 * sync directories (EINVAL, ENOTSUP) are not an error. */
int rl_io_sync_dir(const char *path);

/* An atomic file whose stream reported a failed write: report the first failure (its errno) as
 * "PATH: cannot write TMP: reason", remove the temporary file, return the status. */
int rl_atomic_fail(rl_atomic_file *a);

/* Name of site `a` of `species` for files (<= 4 characters + NUL): the molecule's site name,
 * "MW" for a massless "M", "S<a+1>" without a molecule; for a site-less species the species
 * name's first letters. */
void rl_io_site_name(const rl_system *sys, const rl_molecule *const *mols, int species, int a,
                     char out[8]);
/* Residue name: first three characters of the species name, upper case ("MOL" if none). */
void rl_io_res_name(const rl_system *sys, int species, char out[4]);
/* Atom positions (system units) in writer order, [rl_io_natoms][3]; malloc'd, NULL on ENOMEM. */
double (*rl_io_atom_positions(const rl_system *sys))[3];

/* Little-endian encoding. */
static inline void rl_le32(unsigned char *p, uint32_t v)
{
  for (int k = 0; k < 4; k++) p[k] = (unsigned char)(v >> (8 * k));
}
static inline void rl_le64(unsigned char *p, uint64_t v)
{
  for (int k = 0; k < 8; k++) p[k] = (unsigned char)(v >> (8 * k));
}
static inline uint32_t rl_get32(const unsigned char *p)
{
  uint32_t v = 0;
  for (int k = 0; k < 4; k++) v |= (uint32_t)p[k] << (8 * k);
  return v;
}
static inline uint64_t rl_get64(const unsigned char *p)
{
  uint64_t v = 0;
  for (int k = 0; k < 8; k++) v |= (uint64_t)p[k] << (8 * k);
  return v;
}

/* CRC-32, IEEE 802.3 / zlib polynomial (reflected 0xEDB88320), crc = 0 to start. */
uint32_t rl_crc32(uint32_t crc, const void *buf, size_t len);

#endif
