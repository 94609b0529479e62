/* Point-dipole pair kernels (internal): dipole-dipole and charge-dipole, with reaction field
 * (Barker-Watts) or the shifted-force form of Allen & Germano (2006) as in LAMMPS
 * lj/sf/dipole/sf.  Dipoles are moment vectors (charge x length).  r = r_i - r_j.
 *
 * Dipole-dipole, g0 = mu_i.mu_j / r^3 - 3 (mu_i.r)(mu_j.r) / r^5:
 *   RF   U = kc [g0 - 2 krf mu_i.mu_j]          (krf as for charges; eps_rf = 1: plain)
 *   SF   U = kc g0 [1 - 4 (r/rc)^3 + 3 (r/rc)^4]
 * Charge q at i, dipole mu at j:
 *   RF   U = kc q (mu.r) (1/r^3 - 2 krf)
 *   SF   U = kc q (mu.r) / r^3 [1 - 3 (r/rc)^2 + 2 (r/rc)^3]
 * Outputs: f = force on i (on j: -f), gi = dU/dmu_i, gj = dU/dmu_j; the torque on a dipole is
 * mu x (-g) (field times moment). */
#ifndef ROTLEAP_MODELS_DIPOLE_H
#define ROTLEAP_MODELS_DIPOLE_H

/* in kc, krf, r[3], mui[3], muj[3]; out f[3], gi[3], gj[3]; returns U. */
double rl_dipole_dipole_rf(double kc, double krf, const double r[3], const double mui[3],
                           const double muj[3], double f[3], double gi[3], double gj[3]);
/* in kc, rc, r[3], mui[3], muj[3]; out f[3], gi[3], gj[3]; returns U (0 for |r| >= rc). */
double rl_dipole_dipole_sf(double kc, double rc, const double r[3], const double mui[3],
                           const double muj[3], double f[3], double gi[3], double gj[3]);
/* Charge q at i, dipole mu at j, r = r_i - r_j.  out f[3] force on the charge, g[3] = dU/dmu. */
double rl_charge_dipole_rf(double kc, double krf, const double r[3], double q,
                           const double mu[3], double f[3], double g[3]);
double rl_charge_dipole_sf(double kc, double rc, const double r[3], double q,
                           const double mu[3], double f[3], double g[3]);

#endif
