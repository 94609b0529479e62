/* rotleap — unit systems and physical constants.
 *
 * `real` units are OpenMM's and GROMACS's: nm, ps, amu (g/mol), kJ/mol, elementary charge, K.
 * In them kJ/mol = amu nm^2 / ps^2, so F = m a needs no conversion factor.
 * `lj` units are reduced: sigma, epsilon, mass, k_B = 1.
 * Constants: CODATA 2018 (exact SI definitions of k_B, N_A and e since 2019). */
#ifndef ROTLEAP_UNITS_H
#define ROTLEAP_UNITS_H

/* Boltzmann constant in kJ/(mol K) = k_B * N_A / 1000 = 1.380649e-23 * 6.02214076e23 / 1000. */
#define RL_KB_KJMOL 0.00831446261815324
/* Coulomb constant 1/(4 pi eps0) in kJ mol^-1 nm e^-2 from CODATA 2018 (e, N_A exact; eps0 =
 * 8.8541878128e-12 F/m): the value OpenMM 7.7 uses (ONE_4PI_EPS0, 138.93545764438198); the
 * older 138.935456 differs by 1.2e-8 relative (validate/openmm_rf_intramolecular.py). */
#define RL_COULOMB_KJMOL_NM 138.93545764438198
/* 1 debye in e nm (1 D = 3.33564e-30 C m; e = 1.602176634e-19 C). */
#define RL_DEBYE_E_NM 0.020819434
/* 1 fs in ps, 1 Angstrom in nm. */
#define RL_FS 0.001
#define RL_ANGSTROM 0.1

typedef enum { RL_UNITS_REAL = 0, RL_UNITS_LJ = 1 } rl_units;

/* Boltzmann constant in the given unit system. */
static inline double rl_units_kB(rl_units u) { return u == RL_UNITS_LJ ? 1.0 : RL_KB_KJMOL; }

#endif
