#!/usr/bin/env python3
"""What does OpenMM 7.7 NonbondedForce.CutoffPeriodic (reaction field) do with excluded
(intramolecular) charge pairs?

Run:  /usr/bin/python3 validate/openmm_rf_intramolecular.py
(OpenMM 7.7 from Debian: apt-get install -y python3-simtk libopenmm-plugins)

Builds three rigid TIP3P waters (sites placed exactly as rotleap places them: r + R d, with R a
rotation about a fixed axis) in a 3 nm cubic box, and a two-site "stretched" molecule whose two
charges are further apart than the cutoff.  For each system OpenMM's energy (Reference platform,
double precision, dispersion correction off) is compared with three formulas:

  inter      sum over intermolecular site pairs with r < rc (minimum image) of
             kc q_a q_b (1/r + krf r^2 - crf)  +  plain LJ 4 eps [(s/r)^12 - (s/r)^6]
  H0         inter only (exclusions contribute nothing)
  H1         inter + sum over excluded pairs of kc q_a q_b (krf r^2 - crf), at ANY distance
  plain      inter + sum over intramolecular pairs of the full RF pair energy (no exclusions)

with krf = (eps - 1)/((2 eps + 1) rc^3), crf = 1/rc + krf rc^2, kc = ONE_4PI_EPS0 (below).
The numbers printed after "rotleap-reference" are what tests/forces/test_ff_openmm.c
checks the C library against.
"""
import math
import sys

try:
    import openmm as mm
    from openmm import unit
except ImportError:  # OpenMM < 7.6 layout
    from simtk import openmm as mm
    from simtk import unit

# OpenMM 7.7's ONE_4PI_EPS0 (SimTKOpenMMRealType.h since 7.6): 1/(4 pi eps0) with CODATA 2018
# eps0 = 8.8541878128e-12 F/m, e = 1.602176634e-19 C, N_A = 6.02214076e23 /mol, in kJ/mol nm e^-2.
# The older 138.935456 (OpenMM <= 7.5, and rotleap's RL_COULOMB_KJMOL_NM before it was updated)
# is 1.18e-8 smaller; the script shows that only the new value reproduces OpenMM 7.7 to 1e-14.
KC_OLD = 138.935456
E_CHARGE, N_A, EPS0 = 1.602176634e-19, 6.02214076e23, 8.8541878128e-12
KC = 1.0 / (4.0 * math.pi * (1e-6 * EPS0 / (E_CHARGE * E_CHARGE * N_A)))

# TIP3P
QO, QH = -0.834, 0.417
SIG_O, EPS_O = 0.315061, 0.6364
ROH, THETA = 0.09572, math.radians(104.52)
MO, MH = 15.9994, 1.008


def water_body_sites():
    """O, H1, H2 in the body frame, centre of mass at the origin, symmetry axis along z."""
    hx, hz = ROH * math.sin(THETA / 2), ROH * math.cos(THETA / 2)
    zc = 2 * MH * hz / (MO + 2 * MH)
    return [(0.0, 0.0, -zc), (hx, 0.0, hz - zc), (-hx, 0.0, hz - zc)]


def rotation(axis, angle):
    """Rodrigues: R = I + sin(a) K + (1 - cos(a)) K^2 (same expression as the C test)."""
    n = math.sqrt(sum(a * a for a in axis))
    x, y, z = (a / n for a in axis)
    K = [[0, -z, y], [z, 0, -x], [-y, x, 0]]
    K2 = [[sum(K[i][m] * K[m][j] for m in range(3)) for j in range(3)] for i in range(3)]
    s, c = math.sin(angle), 1 - math.cos(angle)
    return [[(i == j) + s * K[i][j] + c * K2[i][j] for j in range(3)] for i in range(3)]


# centres, rotation axes and angles of the three waters (mirrored in test_ff_openmm.c)
WATERS = [((1.00, 1.10, 0.90), (0.3, -0.5, 0.8), 0.7),
          ((1.27, 1.05, 1.12), (-0.6, 0.2, 0.4), 2.1),
          ((0.85, 1.33, 1.20), (0.1, 0.9, -0.3), -1.3)]


def place(centre, axis, angle, body):
    R = rotation(axis, angle)
    return [tuple(centre[i] + sum(R[i][m] * d[m] for m in range(3)) for i in range(3))
            for d in body]


def min_image(d, L):
    return [x - L * round(x / L) for x in d]


def formulas(mols, charges, lj, L, rc, eps, kc=None):
    kc = KC if kc is None else kc
    krf = (eps - 1) / ((2 * eps + 1) * rc ** 3)
    crf = 1 / rc + krf * rc * rc
    inter = intra_rf = intra_full = 0.0
    for i, mi in enumerate(mols):
        for j, mj in enumerate(mols):
            for a, ra in enumerate(mi):
                for b, rb in enumerate(mj):
                    if i > j or (i == j and a >= b):
                        continue
                    d = min_image([ra[k] - rb[k] for k in range(3)], L)
                    r = math.sqrt(sum(x * x for x in d))
                    qq = kc * charges[i][a] * charges[j][b]
                    if i == j:
                        intra_rf += qq * (krf * r * r - crf)
                        if r < rc:
                            intra_full += qq * (1 / r + krf * r * r - crf)
                        continue
                    if r >= rc:
                        continue
                    inter += qq * (1 / r + krf * r * r - crf)
                    (sa, ea), (sb, eb) = lj[i][a], lj[j][b]
                    s, e = 0.5 * (sa + sb), math.sqrt(ea * eb)
                    if e > 0:
                        inter += 4 * e * ((s / r) ** 12 - (s / r) ** 6)
    return inter, intra_rf, intra_full


def openmm_energy(mols, charges, lj, L, rc, eps, exclude):
    system = mm.System()
    nb = mm.NonbondedForce()
    nb.setNonbondedMethod(mm.NonbondedForce.CutoffPeriodic)
    nb.setCutoffDistance(rc)
    nb.setReactionFieldDielectric(eps)
    nb.setUseDispersionCorrection(False)
    nb.setUseSwitchingFunction(False)
    system.setDefaultPeriodicBoxVectors(mm.Vec3(L, 0, 0), mm.Vec3(0, L, 0), mm.Vec3(0, 0, L))
    pos, first = [], []
    for m, mol in enumerate(mols):
        first.append(len(pos))
        for a, r in enumerate(mol):
            system.addParticle(1.0)
            nb.addParticle(charges[m][a], lj[m][a][0], lj[m][a][1])
            pos.append(mm.Vec3(*r))
    if exclude:
        for m, mol in enumerate(mols):
            for a in range(len(mol)):
                for b in range(a + 1, len(mol)):
                    nb.addException(first[m] + a, first[m] + b, 0.0, 1.0, 0.0)
    system.addForce(nb)
    ctx = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName("Reference"))
    ctx.setPositions(pos)
    return ctx.getState(getEnergy=True).getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole)


def report(name, mols, charges, lj, L, rc, eps):
    inter, intra_rf, intra_full = formulas(mols, charges, lj, L, rc, eps)
    inter_old, _, _ = formulas(mols, charges, lj, L, rc, eps, KC_OLD)
    e_excl = openmm_energy(mols, charges, lj, L, rc, eps, True)
    e_all = openmm_energy(mols, charges, lj, L, rc, eps, False)
    tol = 1e-11 * max(1.0, abs(e_all))
    h0 = abs(e_excl - inter) <= tol
    h1 = abs(e_excl - (inter + intra_rf)) <= tol
    plain = abs(e_all - (inter + intra_full)) <= tol
    print(f"== {name}: rc = {rc} nm, eps_rf = {eps}, box {L} nm")
    print(f"   OpenMM, intramolecular pairs excluded     : {e_excl:.12f}")
    print(f"   H0 inter only (exclusions add nothing)    : {inter:.12f}   diff {e_excl - inter:+.3e}")
    print(f"   H1 inter + kc qq (krf r^2 - crf) excluded : {inter + intra_rf:.12f}   "
          f"diff {e_excl - (inter + intra_rf):+.3e}")
    print(f"   H0 with kc = {KC_OLD} (old constant)  : {inter_old:.12f}   "
          f"diff {e_excl - inter_old:+.3e}")
    print(f"   OpenMM, no exclusions                     : {e_all:.12f}")
    print(f"   inter + full RF intramolecular if r < rc  : {inter + intra_full:.12f}   "
          f"diff {e_all - (inter + intra_full):+.3e}")
    print(f"   -> H0 {'matches' if h0 else 'fails'}, H1 {'matches' if h1 else 'fails'}, "
          f"unexcluded intramolecular pairs = ordinary cut pairs: {'yes' if plain else 'no'}")
    print(f"   rotleap-reference {name} eps={eps} rc={rc}: excluded {e_excl:.12f} "
          f"unexcluded {e_all:.12f}")
    return h0 and not h1 and plain


def main():
    body = water_body_sites()
    waters = [place(c, ax, an, body) for c, ax, an in WATERS]
    wq = [[QO, QH, QH]] * 3
    wlj = [[(SIG_O, EPS_O), (1.0, 0.0), (1.0, 0.0)]] * 3
    ok = True
    for eps in (78.3, 1.0, 1e30):
        ok &= report("3 TIP3P waters", waters, wq, wlj, 3.0, 1.0, eps)
    # stretched two-site molecule: its charges are 0.7 nm apart, beyond the 0.5 nm cutoff
    stretched = [[(1.0, 1.0, 1.0), (1.0, 1.0, 1.7)], [(1.3, 1.2, 1.1), (1.3, 1.2, 1.5)]]
    sq = [[0.5, -0.5], [0.4, -0.4]]
    slj = [[(1.0, 0.0), (1.0, 0.0)]] * 2
    ok &= report("stretched pair, intramolecular r = 0.7 > rc", stretched, sq, slj, 3.0, 0.5, 78.3)
    print(f"kc used: {KC!r} (OpenMM 7.7 ONE_4PI_EPS0)")
    if ok:
        print("FINDING: OpenMM 7.7 NonbondedForce/CutoffPeriodic adds NOTHING for excluded pairs: "
              "no reaction-field correction kc q q (krf r^2 - crf) (GROMACS adds one), at any "
              "distance.  Pairs that are not excluded are ordinary pairs: full RF energy, cut at rc. "
              "Agreement to 1e-14 kJ/mol needs kc = 138.93545764438198, not 138.935456.")
    else:
        print("FINDING: the expected behaviour was NOT reproduced; see the lines above")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
