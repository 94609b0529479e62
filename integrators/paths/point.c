/* Point particle (ions, LJ atoms): translation only, no rotational state at all. */
#include "path.h"

static int rotate_none(const rl_species *sp, rl_system *s, rl_rotation_work *w)
{
  (void)sp; (void)s; (void)w;
  return RL_OK;
}

static double ke_none(const rl_species *sp, const rl_system *s, int b, const double lt[3])
{
  (void)sp; (void)s; (void)b; (void)lt;
  return 0.0;
}

const rl_family rl_family_point = {RL_KIND_POINT, "point", "none (translation only)", 0,
                                   rotate_none, ke_none};
