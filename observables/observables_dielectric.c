/* rotleap — observables: molecular and total dipoles of a system, the total-dipole fluctuation
 * accumulator and the static dielectric constant with a reaction-field boundary. */
#include "rotleap/observables.h"

#include <math.h>
#include <stdlib.h>

#include "rotleap/error.h"

int rl_system_dipoles(const rl_system *sys, const rl_species_ff *species, int nspecies, double (*mu)[3],
                      double M[3])
{
  if (!sys || (!species && nspecies > 0)) return rl_error(RL_EINVAL, "rl_system_dipoles: NULL argument");
  int ns = rl_system_nspecies(sys);
  if (nspecies != ns)
    return rl_error(RL_EINVAL, "rl_system_dipoles: %d species data for a system of %d species", nspecies, ns);
  for (int s = 0; s < ns; s++) {
    int k = rl_system_species_nsites(sys, s);
    if (species[s].nsites != k)
      return rl_error(RL_EINVAL, "rl_system_dipoles: species %d has %d sites in the system, %d in its data", s, k,
                      species[s].nsites);
    if (species[s].dipole && rl_system_species_kind(sys, s) == RL_KIND_POINT)
      for (int a = 0; a < k; a++)
        if (species[s].dipole[a] != 0.0)
          return rl_error(RL_EINVAL, "rl_system_dipoles: species %d is a point body with a point dipole", s);
  }
  int n = rl_system_count(sys), nsites = rl_system_nsites(sys);
  double(*site)[3] = malloc(sizeof(double[3]) * (size_t)(nsites > 0 ? nsites : 1));
  if (!site) return rl_error(RL_ENOMEM, "rl_system_dipoles: out of memory");
  rl_system_site_positions(sys, site);
  double tot[3] = {0, 0, 0};
  for (int i = 0; i < n; i++) {
    int s = rl_system_species_of(sys, i), off = rl_system_site_offset(sys, i);
    const rl_species_ff *sp = &species[s];
    double r[3], rho[3] = {0, 0, 0}, m[3] = {0, 0, 0};
    rl_system_get_position(sys, i, r);
    if (rl_system_species_kind(sys, s) != RL_KIND_POINT) rl_system_get_axis(sys, i, rho);
    for (int a = 0; a < sp->nsites; a++) {
      double q = sp->charge ? sp->charge[a] : 0.0, p = sp->dipole ? sp->dipole[a] : 0.0;
      for (int d = 0; d < 3; d++) m[d] += q * (site[off + a][d] - r[d]) + p * rho[d];
    }
    for (int d = 0; d < 3; d++) {
      if (mu) mu[i][d] = m[d];
      tot[d] += m[d];
    }
  }
  free(site);
  if (M)
    for (int d = 0; d < 3; d++) M[d] = tot[d];
  return RL_OK;
}

struct rl_dipole_acc {
  long n;
  double mean[3], m2; /* m2 = sum |M - mean|^2 (Welford, summed over components) */
};

rl_dipole_acc *rl_dipole_acc_alloc(void)
{
  rl_dipole_acc *d = calloc(1, sizeof *d);
  if (!d) rl_error(RL_ENOMEM, "rl_dipole_acc_alloc: out of memory");
  return d;
}

void rl_dipole_acc_free(rl_dipole_acc *d) { free(d); }

int rl_dipole_acc_add(rl_dipole_acc *d, const double M[3])
{
  if (!d || !M) return rl_error(RL_EINVAL, "rl_dipole_acc_add: NULL argument");
  if (!isfinite(M[0] + M[1] + M[2])) return rl_error(RL_ENONFINITE, "rl_dipole_acc_add: non-finite M");
  d->n++;
  for (int k = 0; k < 3; k++) {
    double delta = M[k] - d->mean[k];
    d->mean[k] += delta / (double)d->n;
    d->m2 += delta * (M[k] - d->mean[k]);
  }
  return RL_OK;
}

long rl_dipole_acc_count(const rl_dipole_acc *d) { return d ? d->n : 0; }

double rl_dipole_acc_fluct(const rl_dipole_acc *d, double mean[3])
{
  if (!d || d->n == 0) return NAN;
  if (mean)
    for (int k = 0; k < 3; k++) mean[k] = d->mean[k];
  return d->m2 / (double)d->n;
}

static int y_factor(double V, double T, rl_units units, double kc, double *f)
{
  if (!(V > 0.0) || !(T > 0.0) || !isfinite(V) || !isfinite(T) || !(kc >= 0.0) || !isfinite(kc))
    return rl_error(RL_EINVAL, "rl_dielectric: need V > 0 (%g), T > 0 (%g), coulomb_constant >= 0 (%g)", V, T, kc);
  if (kc == 0.0) kc = units == RL_UNITS_LJ ? 1.0 : RL_COULOMB_KJMOL_NM;
  *f = 4.0 * M_PI * kc / (3.0 * V * rl_units_kB(units) * T);
  return RL_OK;
}

int rl_dielectric_constant(double dM2, double V, double T, double eps_rf, rl_units units, double coulomb_constant,
                           double *eps)
{
  double f = 0.0;
  if (!eps) return rl_error(RL_EINVAL, "rl_dielectric_constant: NULL eps");
  int st = y_factor(V, T, units, coulomb_constant, &f);
  if (st) return st;
  if (!(dM2 >= 0.0) || !isfinite(dM2)) return rl_error(RL_EINVAL, "rl_dielectric_constant: <dM^2> = %g", dM2);
  if (!(eps_rf >= 1.0)) return rl_error(RL_EINVAL, "rl_dielectric_constant: eps_rf = %g (need >= 1 or INFINITY)", eps_rf);
  /* formed in x = 1 / eps_rf, so that eps_rf = 1e308 is the conducting limit (x = 0), as the
   * reaction field's own constant is (forces/pair/coulomb_rf.c), rather than an overflow of 2 eps_rf */
  const double y = f * dM2, x = 1.0 / eps_rf, den = 2.0 + x - x * y;
  if (!(den > 0.0))
    return rl_error(RL_EINVAL,
                    "rl_dielectric_constant: y = 4 pi kc <dM^2>/(3 V kT) = %g >= 2 eps_rf + 1 = %g: no finite eps", y,
                    2.0 * eps_rf + 1.0);
  *eps = (2.0 * (1.0 + y) + x) / den;
  return RL_OK;
}

double rl_dielectric_fluct(double eps, double V, double T, double eps_rf, rl_units units, double coulomb_constant)
{
  double f = 0.0;
  if (y_factor(V, T, units, coulomb_constant, &f) || !(eps >= 1.0) || !(eps_rf >= 1.0)) return NAN;
  const double x = 1.0 / eps_rf, y = (eps - 1.0) * (2.0 + x) / (2.0 + eps * x);
  return y / f;
}
