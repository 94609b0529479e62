/* rotleap — molecule types from their sites.
 *
 * A molecule type is given by its sites in any frame: positions, masses (massless sites allowed,
 * like TIP4P's M), LJ parameters, charges, point dipoles and linear point quadrupoles.
 * rl_molecule_build computes the centre of mass, the inertia tensor and its principal axes (GSL
 * eigen-decomposition), classifies the type to the cheapest exact family and expresses every site
 * in the principal (body) frame:
 *
 *   point      all mass at one point and nothing orientational           translation only
 *   dipole     one centre with a point dipole, spherical inertia given   rho only
 *   linear     all sites on a line (smallest moment 0)                   rho only, J = (J, J, 0)
 *   spherical  three equal moments                                       exp map, no solve
 *   symmetric  two equal moments; unique axis put on body Z              closed form (eq. 29)
 *   asymmetric J_X < J_Y < J_Z                                           guarded cubic
 *
 * Two moments count as equal when |J_a - J_b| <= RL_INERTIA_RTOL max J (1e-10, system.h); a
 * moment is zero when J <= RL_INERTIA_RTOL max J.  Moments classified equal are replaced by their
 * mean; the change is below 1e-10 relative by construction (below def->inertia_rtol where a
 * caller symmetrises a near miss with a larger tolerance).  The sites of a linear molecule (and
 * any dipole) must lie on the axis within RL_AXIS_RTOL = 1e-5 of the molecule's size -- the
 * distance at which a site's contribution to the zero moment reaches the 1e-10 tolerance -- and
 * are projected onto it; a site farther off (e.g. a massless charge) is an error, because it
 * would exert a torque about an axis with no moment of inertia.
 *
 * force_general = 1 sends any rotating type through the general asymmetric path instead (for
 * checking the fast paths and for the trade study).  A linear molecule or point dipole then
 * carries a full rotation matrix with surrogate moments (J, J, J): with no spin about the axis
 * (l . rho = 0, which the torques keep) the general equations give exactly the fast path's
 * motion of rho.  Its kinetic energy and temperature then count 3 rotational degrees of freedom. */
#ifndef ROTLEAP_MOLECULE_H
#define ROTLEAP_MOLECULE_H

#include "rotleap/system.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RL_MOLECULE_MAX_SITES 16
#define RL_AXIS_RTOL 1e-5

typedef struct {
  const char *name;
  int nsites;                     /* 1 .. RL_MOLECULE_MAX_SITES                                */
  const char *const *site_names;  /* [nsites] or NULL                                          */
  const double *pos;              /* [nsites][3] positions in any frame                        */
  const double *mass;             /* [nsites] >= 0; total > 0                                  */
  const double *sigma;            /* [nsites] or NULL                                          */
  const double *epsilon;          /* [nsites] or NULL                                          */
  const double *charge;           /* [nsites] or NULL                                          */
  const double *dipole;           /* [nsites][3] dipole vectors (same frame as pos) or NULL   */
  const double *quadrupole;       /* [nsites] linear quadrupole along the molecular axis, or NULL */
  double inertia[3];              /* single-centre molecules only: principal moments (I, I, I) */
  double inertia_rtol;            /* 0: RL_INERTIA_RTOL.  Larger (at most 1e-4): moments closer than
                                     inertia_rtol max J count as equal and are replaced by their mean,
                                     symmetrising a near miss whose coordinates were rounded      */
} rl_molecule_def;

typedef struct {
  char name[64];
  rl_kind kind;                   /* the family it is integrated by                            */
  rl_kind natural_kind;           /* what classification found (= kind unless forced)           */
  double mass;
  double inertia[3];              /* principal moments, body X, Y, Z                            */
  double com[3];                  /* centre of mass in the input frame                          */
  double axes[9];                 /* rows: body X, Y, Z in the input frame (right-handed);
                                     body = axes (x - com)                                      */
  int nsites;
  char site_names[RL_MOLECULE_MAX_SITES][8];
  double sites[RL_MOLECULE_MAX_SITES][3];   /* body frame                                       */
  double site_mass[RL_MOLECULE_MAX_SITES];
  double sigma[RL_MOLECULE_MAX_SITES], epsilon[RL_MOLECULE_MAX_SITES], charge[RL_MOLECULE_MAX_SITES];
  double dipole[RL_MOLECULE_MAX_SITES];     /* along body Z (signed)                            */
  double quadrupole[RL_MOLECULE_MAX_SITES]; /* along body Z                                      */
  int has_dipole, has_quadrupole;
} rl_molecule;

/* Build and classify.  Errors (with the site and the reason): no mass, non-finite input,
 * too many sites, a dipole that is not along the molecular axis of a linear molecule (or along
 * body Z of a top), a single-centre dipole without a spherical inertia, a linear molecule with a
 * site off its axis. */
int rl_molecule_build(const rl_molecule_def *def, int force_general, rl_molecule *m);

/* A species descriptor viewing m (pointers into m: keep m alive while adding the species). */
void rl_molecule_species(const rl_molecule *m, rl_species_desc *d);

#ifdef __cplusplus
}
#endif
#endif
