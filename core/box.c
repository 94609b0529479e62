/* Orthorhombic periodic box. */
#include "box.h"
#include "rotleap/error.h"

int rl_box_set(rl_box *box, const double L[3])
{
  static const char axis[3] = {'x', 'y', 'z'};
  for (int c = 0; c < 3; c++)
    if (!(L[c] > 0.0) || !isfinite(L[c]))
      return rl_error(RL_EINVAL, "box edge L%c = %g must be positive and finite", axis[c], L[c]);
  for (int c = 0; c < 3; c++) {
    box->L[c] = L[c];
    box->invL[c] = 1.0 / L[c];
  }
  return RL_OK;
}

double rl_box_min_edge(const rl_box *box)
{
  return fmin(box->L[0], fmin(box->L[1], box->L[2]));
}

double rl_box_volume(const rl_box *box) { return box->L[0] * box->L[1] * box->L[2]; }
