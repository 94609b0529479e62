/* rotleap — a system of rigid bodies: species (kind, mass, principal moments, body-frame
 * sites) and the state arrays.
 *
 * Storage follows "model only what the scene requires":
 *   point            r, v
 *   point dipole     r, v, rho (unit axis), l         (5 degrees of freedom)
 *   linear           r, v, rho, l                     (5)
 *   spherical top    r, v, A (3x3), l                 (6)
 *   symmetric top    r, v, A, l                       (6)
 *   asymmetric       r, v, A, l                       (6)
 * One contiguous array per quantity for the whole system; a species is a view (offset, count).
 * Frames follow the paper: A maps lab to body (E = A e), row-major; a site's lab position is
 * r + A^T Delta; for axis kinds rho is the body Z axis in the lab (the third row of A) and a
 * site at body (0, 0, d) sits at r + d rho.  l is the lab angular momentum. */
#ifndef ROTLEAP_SYSTEM_H
#define ROTLEAP_SYSTEM_H

#include "rotleap/units.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  RL_KIND_AUTO = -1,     /* classify from the principal moments (rl_classify_inertia)        */
  RL_KIND_POINT = 0,     /* no rotation                                                      */
  RL_KIND_DIPOLE = 1,    /* point dipole: rho only, spherical inertia I, omega = l / I       */
  RL_KIND_LINEAR = 2,    /* linear molecule: rho only, J_XX = J_YY, J_ZZ = 0                 */
  RL_KIND_SPHERICAL = 3, /* J_XX = J_YY = J_ZZ: A exp[phi W(omega)/omega], omega = l/J, with
                            the Cayley angle phi = 2 atan(h omega/2) (section III.D), not the
                            exact rotation by h omega (phi is (h omega)^2/12 short, relatively);
                            no solve                                                        */
  RL_KIND_SYMMETRIC = 4, /* two equal moments: Omega_Z = theta_Z, eq. 29 in closed form      */
  RL_KIND_ASYMMETRIC = 5 /* general: guarded quasi-analytic cubic (or exact / quaternion)    */
} rl_kind;

/* Relative tolerance for calling two principal moments equal when classifying:
 * |J_a - J_b| <= RL_INERTIA_RTOL * max(J).  Chosen well above the round-off of an eigen-
 * decomposition of a tensor built from sites (~1e-15) and well below any real anisotropy
 * (the most nearly symmetric catalogue molecules differ at 1e-3). */
#define RL_INERTIA_RTOL 1e-10

typedef struct {
  const char *name;       /* species name (copied); may be NULL                            */
  rl_kind kind;           /* RL_KIND_AUTO to classify from `inertia`                        */
  double mass;            /* > 0                                                             */
  double inertia[3];      /* principal moments J_XX, J_YY, J_ZZ of the body frame.  Point: ignored.
                             Dipole: I, I, I (or I, I, 0).  Linear: J, J, 0.  Symmetric: the
                             unique moment may sit on any axis (the integrator relabels).   */
  int nsites;             /* >= 0 interaction sites                                          */
  const double *sites;    /* [nsites][3] body-frame positions relative to the centre of mass
                             (copied; may be NULL if nsites = 0).  Axis kinds: x = y = 0.    */
} rl_species_desc;

typedef struct rl_system rl_system;

rl_system *rl_system_alloc(rl_units units);
void rl_system_free(rl_system *sys); /* accepts NULL */

/* Append `count` bodies of a new species.  Validates the descriptor (positive finite mass and
 * moments, kind consistent with the moments, sites on the axis for axis kinds).  New bodies sit
 * at the origin at rest with A = I (rho = e_z).  *species (may be NULL) receives the index. */
int rl_system_add_species(rl_system *sys, const rl_species_desc *desc, int count, int *species);

/* Classify principal moments to the cheapest exact kind (RL_KIND_LINEAR if one moment is
 * zero, SPHERICAL, SYMMETRIC, or ASYMMETRIC), with RL_INERTIA_RTOL. */
rl_kind rl_classify_inertia(const double J[3]);
const char *rl_kind_name(rl_kind kind);
/* The rotation path that integrates a kind (its fast path), for listings. */
const char *rl_kind_rotation_path(rl_kind kind);
int rl_kind_rotational_dof(rl_kind kind); /* 0, 2 or 3 */

int rl_system_count(const rl_system *sys);          /* bodies                             */
int rl_system_nspecies(const rl_system *sys);
int rl_system_species_of(const rl_system *sys, int body);
rl_kind rl_system_species_kind(const rl_system *sys, int species);
const char *rl_system_species_name(const rl_system *sys, int species);
int rl_system_species_nsites(const rl_system *sys, int species);
int rl_system_species_count(const rl_system *sys, int species); /* bodies of that species */
int rl_system_nsites(const rl_system *sys);         /* all sites, all bodies              */
double rl_system_mass(const rl_system *sys, int body);
void rl_system_inertia(const rl_system *sys, int body, double J[3]);
rl_units rl_system_units(const rl_system *sys);
double rl_system_kB(const rl_system *sys);

/* Degrees of freedom: sum over bodies of 3 + rotational, minus `removed` constraints (default 3
 * for the conserved total momentum; set 0 for a single body in free space if wanted).  With 3 or
 * more removed, rl_integrator_init and rl_integrator_resume hold the total momentum at zero
 * under every thermostat but Langevin, which counts all 3N translational dof instead and leaves
 * this setting alone (rl_integrator_dof gives the integrator's count). */
void rl_system_set_removed_dof(rl_system *sys, int removed);
int rl_system_dof(const rl_system *sys);
int rl_system_dof_translational(const rl_system *sys);
int rl_system_dof_rotational(const rl_system *sys);

/* Per-body state.  Orientation setters reject non-finite input and an A that is not
 * orthonormal to 1e-10 (or det < 0), or a rho whose norm is not 1 to 1e-10.  Velocity and angular
 * momentum given here are on-step values at the current time; the integrator staggers them. */
int rl_system_set_position(rl_system *sys, int body, const double r[3]);
int rl_system_set_velocity(rl_system *sys, int body, const double v[3]);
int rl_system_set_angmom(rl_system *sys, int body, const double l[3]); /* lab frame */
int rl_system_set_orientation(rl_system *sys, int body, const double A[9]);
int rl_system_set_axis(rl_system *sys, int body, const double rho[3]);
void rl_system_get_position(const rl_system *sys, int body, double r[3]);
void rl_system_get_velocity(const rl_system *sys, int body, double v[3]);
void rl_system_get_angmom(const rl_system *sys, int body, double l[3]);
/* A (3x3 row-major).  For axis kinds: a matrix whose third row is rho (the first two rows
 * complete it to a right-handed orthonormal frame). */
void rl_system_get_orientation(const rl_system *sys, int body, double A[9]);
/* Body Z axis in the lab (rho for axis kinds, the third row of A otherwise). */
void rl_system_get_axis(const rl_system *sys, int body, double rho[3]);

/* The periodic cell the system owns.  Its matrix has the cell vectors a, b, c as rows (row-major
 * h[9], GROMACS's convention); today every cell is orthorhombic (h diagonal: the box edges Lx,
 * Ly, Lz), and the representation is the one a triclinic cell will extend.  A system starts
 * without a box (zeros: free space).  rl_system_set_box is the one call that changes it (a start,
 * a checkpoint, a barostat); every change increments rl_system_box_version, by which whatever
 * caches data that depends on the box (pair lists, image lists, kernel tables, meshes) learns
 * that it must update (the force terms check it before each computation, terms.h). */
int rl_system_set_box(rl_system *sys, const double L[3]); /* edges > 0 and finite, or all 0: none */
void rl_system_box(const rl_system *sys, double L[3]);    /* edges (zeros: no box)            */
/* The cell matrix (rows a, b, c); RL_EINVAL from rl_system_set_cell for a cell that is not
 * orthorhombic (not supported yet) or not positive. */
int rl_system_set_cell(rl_system *sys, const double h[9]);
void rl_system_cell(const rl_system *sys, double h[9]);
double rl_system_volume(const rl_system *sys);            /* 0 without a box                  */
int rl_system_periodic(const rl_system *sys);             /* 1 with a box                     */
unsigned long rl_system_box_version(const rl_system *sys);

/* A deep copy (species, state and cell), or NULL with a message. */
rl_system *rl_system_clone(const rl_system *sys);

/* Starting states.  Centres on a simple-cubic (sc) or face-centred-cubic (fcc) lattice filling
 * the orthorhombic box L, which becomes the system's box (rl_system_set_box) (cells as close to cubic as the body count allows; bodies in order),
 * orientations uniformly random (random = 1, from a GSL mt19937 seeded with `seed`) or all equal
 * to the identity. */
typedef enum { RL_LATTICE_SC = 0, RL_LATTICE_FCC = 1 } rl_lattice;
int rl_system_lattice(rl_system *sys, const double L[3], rl_lattice lattice, int random, unsigned long seed);
/* Velocities and angular momenta from Maxwell-Boltzmann at T (on-step values), total momentum
 * removed; for dipoles and linear molecules only the two components perpendicular to the axis. */
int rl_system_maxwell_boltzmann(rl_system *sys, double T, unsigned long seed);

/* Bytes of dynamical state one body of `species` carries (r, v and, by kind, l, A or rho). */
int rl_system_state_bytes(const rl_system *sys, int species);

/* Lab positions of every site, [nsites][3], bodies in order, sites in species order. */
void rl_system_site_positions(const rl_system *sys, double (*out)[3]);
/* The same for bodies [i0, i1) only (out still indexed by site; for threaded callers). */
void rl_system_site_positions_of(const rl_system *sys, int i0, int i1, double (*out)[3]);
/* First site of `body` in the site arrays. */
int rl_system_site_offset(const rl_system *sys, int body);

/* Raw state arrays (for force providers and kernels).  Index of body i in the rotational arrays
 * (l, torque) is rl_system_rot_index(sys, i), -1 for point bodies. */
double (*rl_system_r(rl_system *sys))[3];
double (*rl_system_v(rl_system *sys))[3];
int rl_system_rot_index(const rl_system *sys, int body);
int rl_system_nrot(const rl_system *sys);

#ifdef __cplusplus
}
#endif
#endif
