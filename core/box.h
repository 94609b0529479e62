/* Orthorhombic periodic box and the minimum-image convention (internal). */
#ifndef ROTLEAP_BOX_H
#define ROTLEAP_BOX_H

#include <math.h>

typedef struct {
  double L[3];    /* edge lengths (> 0)        */
  double invL[3]; /* 1 / L                     */
} rl_box;

/* Set the edges.  Returns RL_OK or RL_EINVAL (non-positive or non-finite edge, named). */
int rl_box_set(rl_box *box, const double L[3]);

/* Shortest edge. */
double rl_box_min_edge(const rl_box *box);

double rl_box_volume(const rl_box *box);

/* in/out d[3]: a separation vector, replaced by its minimum image (each component in
 * [-L/2, L/2]). */
static inline void rl_box_minimum_image(const rl_box *box, double d[3])
{
  for (int c = 0; c < 3; c++) d[c] -= box->L[c] * nearbyint(d[c] * box->invL[c]);
}

/* in/out r[3]: a position, wrapped into [0, L). */
static inline void rl_box_wrap(const rl_box *box, double r[3])
{
  for (int c = 0; c < 3; c++) {
    r[c] -= box->L[c] * floor(r[c] * box->invL[c]);
    if (r[c] >= box->L[c]) r[c] -= box->L[c]; /* round-off at the upper edge */
    if (r[c] < 0.0) r[c] = 0.0;
  }
}

#endif
