/* Internal layout of rl_system, shared by core/ and integrators/ (not installed). */
#ifndef ROTLEAP_SYSTEM_IMPL_H
#define ROTLEAP_SYSTEM_IMPL_H

#include "rotleap/system.h"

typedef struct {
  char name[64];
  rl_kind kind;
  double mass;
  double J[3];      /* principal moments as given                                          */
  int perm[3];      /* cyclic relabelling (X, Y, Z) used by the symmetric path: J[perm[2]] unique */
  int nsites;
  double *sites;    /* [nsites][3] body frame                                              */
  int first, count; /* bodies [first, first + count)                                       */
  int site_off;     /* first site of the first body                                        */
  int rot_off;      /* offset into l / torque arrays (-1 for points)                       */
  int mat_off;      /* offset into A (-1 unless a matrix kind)                             */
  int axis_off;     /* offset into rho (-1 unless an axis kind)                            */
} rl_species;

struct rl_system {
  rl_units units;
  double kB;
  int n, nrot, nmat, naxis, nsites_total;
  int nspecies, cap_species;
  rl_species *sp;
  int *species_of;  /* [n]                                                                  */
  double (*r)[3], (*v)[3];
  double (*l)[3];   /* [nrot]                                                               */
  double (*A)[9];   /* [nmat]                                                               */
  double (*rho)[3]; /* [naxis]                                                              */
  int removed_dof;
  double cell[9];   /* the periodic cell, row-major rows a, b, c (orthorhombic: diagonal); zeros:
                       no periodic box                                                       */
  unsigned long box_version; /* counts the changes of the cell (rl_system_box_version)       */
};

static inline int rl_kind_is_matrix(rl_kind k)
{
  return k == RL_KIND_SPHERICAL || k == RL_KIND_SYMMETRIC || k == RL_KIND_ASYMMETRIC;
}
static inline int rl_kind_is_axis(rl_kind k) { return k == RL_KIND_DIPOLE || k == RL_KIND_LINEAR; }

/* A right-handed orthonormal frame (row-major A) whose third row is the unit vector rho. */
void rl_frame_from_axis(const double rho[3], double A[9]);

/* Check a rotation matrix: finite, orthonormal to 1e-10, det > 0. */
int rl_check_rotation(const double A[9], const char *who, int body);

#endif
