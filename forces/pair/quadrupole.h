/* Linear point quadrupole-quadrupole kernel (internal), for 2CLJQ models.  A linear quadrupole
 * of strength Q (= sum q z^2 of a linear charge distribution along its unit axis e) at each
 * site; with r = r_i - r_j, c_i = e_i.r/r, c_j = e_j.r/r, c_ij = e_i.e_j (Gray & Gubbins,
 * Theory of Molecular Fluids, vol. 1, 1984):
 *   U = kc 3 Q_i Q_j / (4 r^5) [1 - 5 c_i^2 - 5 c_j^2 - 15 c_i^2 c_j^2 + 2 (c_ij - 5 c_i c_j)^2]
 * Plain truncation (the usual 2CLJQ treatment; no reaction field for quadrupoles). */
#ifndef ROTLEAP_MODELS_QUADRUPOLE_H
#define ROTLEAP_MODELS_QUADRUPOLE_H

/* in  kc, r[3], Qi, ei[3] (unit), Qj, ej[3] (unit)
 * out f[3] force on i, gi[3] = dU/de_i, gj[3] = dU/de_j (torque on i: -e_i x gi)
 * returns U. */
double rl_quadrupole_quadrupole(double kc, const double r[3], double Qi, const double ei[3],
                                double Qj, const double ej[3], double f[3], double gi[3],
                                double gj[3]);

#endif
