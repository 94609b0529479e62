/* Shared helpers of the file modules core/io_*.c (not installed). */
#ifndef ROTLEAP_IO_INTERNAL_H
#define ROTLEAP_IO_INTERNAL_H

#include "rotleap/io.h"
#include "system_impl.h"

#include <stdint.h>

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
