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

/* The cell (x fastest) of position r in a grid of nc[0] x nc[1] x nc[2] cells over the box. */
static inline int rl_box_cell_index(const rl_box *box, const double r[3], const int nc[3])
{
  double w[3] = {r[0], r[1], r[2]};
  rl_box_wrap(box, w);
  int ci[3];
  for (int c = 0; c < 3; c++) {
    ci[c] = (int)(w[c] * box->invL[c] * nc[c]);
    if (ci[c] >= nc[c]) ci[c] = nc[c] - 1;
    if (ci[c] < 0) ci[c] = 0;
  }
  return (ci[2] * nc[1] + ci[1]) * nc[0] + ci[0];
}

#endif
