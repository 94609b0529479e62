/* File helpers shared by the I/O modules: atomic whole-file writes, atom lists, names, CRC-32. */
#include "io_internal.h"
#include "rotleap/error.h"

#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char *dupstr(const char *s)
{
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

int rl_atomic_open(rl_atomic_file *a, const char *path)
{
  memset(a, 0, sizeof *a);
  if (!path || !*path) return rl_error(RL_EINVAL, "rl_atomic_open: empty file name");
  size_t n = strlen(path) + 32;
  a->path = dupstr(path);
  a->tmp = malloc(n);
  if (!a->path || !a->tmp) {
    free(a->path); free(a->tmp);
    memset(a, 0, sizeof *a);
    return rl_error(RL_ENOMEM, "%s: out of memory", path);
  }
  snprintf(a->tmp, n, "%s.tmp.%ld", path, (long)getpid());
  a->fp = fopen(a->tmp, "wb");
  if (!a->fp) {
    int e = errno;
    rl_error(RL_EINVAL, "%s: cannot create temporary file %s: %s", path, a->tmp, strerror(e));
    free(a->path); free(a->tmp);
    memset(a, 0, sizeof *a);
    return RL_EINVAL;
  }
  return RL_OK;
}

void rl_atomic_abort(rl_atomic_file *a)
{
  if (!a) return;
  if (a->fp) fclose(a->fp);
  if (a->tmp) unlink(a->tmp);
  free(a->path);
  free(a->tmp);
  memset(a, 0, sizeof *a);
}

/* fsync the directory holding path, so that the rename itself is durable. */
static void sync_dir(const char *path)
{
  const char *slash = strrchr(path, '/');
  char dir[4096];
  if (!slash) strcpy(dir, ".");
  else if (slash == path) strcpy(dir, "/");
  else {
    size_t n = (size_t)(slash - path);
    if (n >= sizeof dir) return;
    memcpy(dir, path, n);
    dir[n] = '\0';
  }
  int fd = open(dir, O_RDONLY);
  if (fd < 0) return;
  (void)fsync(fd); /* best effort: some file systems refuse fsync on directories */
  close(fd);
}

int rl_atomic_commit(rl_atomic_file *a)
{
  if (!a || !a->fp) return rl_error(RL_ESTATE, "rl_atomic_commit: file is not open");
  int bad = ferror(a->fp), e = 0;
  if (!bad && fflush(a->fp) != 0) { bad = 1; e = errno; }
  if (!bad && fsync(fileno(a->fp)) != 0) { bad = 1; e = errno; }
  if (fclose(a->fp) != 0 && !bad) { bad = 1; e = errno; }
  a->fp = NULL;
  if (bad) {
    rl_error(RL_EINVAL, "%s: writing %s failed: %s", a->path, a->tmp, e ? strerror(e) : "I/O error");
    rl_atomic_abort(a);
    return RL_EINVAL;
  }
  if (rename(a->tmp, a->path) != 0) {
    e = errno;
    rl_error(RL_EINVAL, "%s: cannot rename %s over it: %s", a->path, a->tmp, strerror(e));
    rl_atomic_abort(a);
    return RL_EINVAL;
  }
  sync_dir(a->path);
  free(a->path);
  free(a->tmp);
  memset(a, 0, sizeof *a);
  return RL_OK;
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
