/* Internal to the kernels' pair list (pairlist_rows.c, pairlist_images.c). */
#ifndef ROTLEAP_PAIR_PAIRLIST_ROWS_H
#define ROTLEAP_PAIR_PAIRLIST_ROWS_H

#include "isa.h"
#include "pairlist.h"

/* The image list of the rows of the species in->images (pairlist_images.c).  Returns 0, or 1
 * when out of memory (or without the AVX2 rows, where no one asks for it). */
int rl_rowlist_images(rl_rowlist *L, const rl_rowlist_in *in);

#endif
