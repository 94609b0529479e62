/* rotleap — forces: what a force provider computes (forces, torques, energy, virial) and the
 * provider interface the integrator calls.  Below the integrator: force terms, the pair force
 * field and user providers include this header, not integrator.h. */
#ifndef ROTLEAP_FORCES_H
#define ROTLEAP_FORCES_H

#include "rotleap/system.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  double (*f)[3];    /* out [n][3]    force on each body's centre of mass (lab)              */
  double (*k)[3];    /* out [nrot][3] torque about the centre of mass (lab), rot-indexed      */
  double energy;     /* out           potential energy                                        */
  double virial[9];  /* out           sum r_ij (x) f_ij (molecular virial tensor), optional   */
  int forces_only;   /* in            nonzero: the caller needs f and k only; the provider may
                                      leave energy and virial at 0 (rotleap's force field then
                                      skips their sums: ~10 % of a TIP4P step)                */
} rl_forces;

/* Compute forces and torques for the current positions/orientations of sys.  `out` arrays are
 * zeroed before the call, and so are energy and virial.  A provider may ignore forces_only and
 * compute everything.  Return RL_OK, or a status set with rl_error(). */
typedef int (*rl_force_fn)(void *ctx, const rl_system *sys, rl_forces *out);

typedef struct {
  rl_force_fn compute;
  void *ctx;
} rl_force_provider;

/* Molecular pressure P = (2 ke_trans + tr virial) / (3 V) of a computation f (its virial, which
 * includes any long-range correction) with the centre-of-mass kinetic energy ke_trans and V the
 * system's volume.  Units: energy / volume (real: kJ mol^-1 nm^-3 = 16.6054 bar); NaN without a
 * box. */
double rl_forces_pressure(const rl_system *sys, const rl_forces *f, double ke_trans);
/* The same in a box of edges L (the box the virial was computed in, when the system's has changed
 * since: a barostat). */
double rl_forces_pressure_in(const double L[3], const rl_forces *f, double ke_trans);

/* Accumulate site forces fs[nsites][3] (lab) into body forces and torques
 * k += (r_a - r) x f_a.  For providers that work site by site. */
void rl_system_add_site_forces(const rl_system *sys, const double (*fs)[3], rl_forces *out);
/* The same for bodies [i0, i1) only (for threaded callers). */
void rl_system_add_site_forces_of(const rl_system *sys, const double (*fs)[3], rl_forces *out,
                                  int i0, int i1);

#ifdef __cplusplus
}
#endif
#endif
