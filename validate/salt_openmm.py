#!/usr/bin/python3
"""Issue 35, acceptance 2 (reaction field): SPC/E water with Na+ and Cl- (Joung & Cheatham 2008),
512 waters and 10 ion pairs (`system.species = spc-e:512 na-spce:10 cl-spce:10`), a single point of
rotleap against OpenMM 7.7's Reference platform.

rotleap makes the configuration (fcc lattice, species at random, random orientations, 20 NVT steps
of 1 fs at 298 K) and evaluates its checkpoint with `rotleap energy --json` (scheme = site,
lj = plain, no dispersion correction, eps_rf = 78.3, rc = 0.9 nm).  OpenMM gets the sites r + A^T d
of the checkpoint (validate/rlcheckpoint.py) in a NonbondedForce (CutoffPeriodic, the same eps_rf,
no switch, no dispersion correction, Lorentz-Berthelot as OpenMM always mixes, every pair within a
water excluded) with the water parameters of validate/watermodels.py and the ions' from the paper
written down here (Table 5, SPC/E: Na+ R_min/2 1.212 A, epsilon 0.3526418 kcal/mol; Cl- 2.711 A,
0.0127850 kcal/mol; sigma = 2 R_min/2 / 2^(1/6)).  Molecular forces are sums of atom forces,
torques sum (r_a - R) x f_a about rotleap's centres.

Tolerances as validate/single_point.py: |dE|/|E| <= 1e-10, RMS relative force and torque error
<= 1e-8.

Smooth PME (the same configuration; `coulomb = pme` with the explicit parameters ewald_alpha =
PME_ALPHA, pme_grid = PME_GRID, pme_order = 5, tin-foil, against OpenMM's NonbondedForce PME with
setPMEParameters(alpha, nx, ny, nz), whose B-splines are of order 5; every pair within a water
excluded, which both codes correct for in reciprocal space): the tolerances of issue 33's OpenMM
comparison (validate/ewald_openmm.py), |dE|/|E| <= 1e-9 and RMS relative forces and torques <= 1e-8.
The mesh's forces do not sum to zero (its interpolation breaks Newton's third law); `rotleap run`
and `energy` take an equal share of their sum from every charged site (Amber's netfrc;
docs/interactions.md, "remove_net_force"), OpenMM leaves it: the same share is taken from OpenMM's
atom forces here (it is 2e-6 of the RMS force, uniform, and would otherwise dominate the
comparison: every ion's force differs by the same 5e-4 kJ/mol/nm).

    /usr/bin/python3 validate/salt_openmm.py [--rotleap build/rotleap] [--write]
        --write stores the checkpoint (validate/data/salt_openmm.chk.gz, v and l zeroed) and OpenMM's
        numbers (validate/data/salt_openmm.json.gz)
    /usr/bin/python3 validate/salt_openmm.py --check [--rotleap build/rotleap]
        CTest (cli_species_openmm): rotleap on the checked-in checkpoint against the checked-in
        OpenMM numbers, without OpenMM (standard library only)
"""
import argparse
import gzip
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True
import rlcheckpoint  # noqa: E402

DATA = os.path.join(HERE, "data")
KCAL = 4.184
# (mass, charge, sigma nm, epsilon kJ/mol): Joung & Cheatham 2008, Table 5 (SPC/E)
IONS = {"na-spce": (22.99, 1.0, 2 * 0.1212 / 2 ** (1 / 6), 0.3526418 * KCAL),
        "cl-spce": (35.45, -1.0, 2 * 0.2711 / 2 ** (1 / 6), 0.0127850 * KCAL)}
DECK = """[system]
species = spc-e:512 na-spce:10 cl-spce:10
density = 1 g/cm3
lattice = fcc
seed = 35
temperature = 298 K
%s
[interactions]
cutoff = 0.9 nm
scheme = site
lj = plain
dispersion_correction = no
eps_rf = 78.3
[run]
ensemble = nvt-bussi
temperature = 298 K
steps = %d
timestep = 1 fs
[output]
thermo_every = 10
checkpoint_every = 0
progress = no
"""
TOL_E, TOL_F = 1e-10, 1e-8
TOL_E_PME = 1e-9
PME_ALPHA, PME_GRID = 3.3, (32, 32, 32)  # /nm; about OpenMM's choice at tolerance 1e-4 for this 2.54 nm box
PME_SETS = ["interactions.coulomb=pme", "interactions.ewald_alpha=%r /nm" % PME_ALPHA,
            "interactions.pme_grid=%d %d %d" % PME_GRID, "interactions.pme_order=5"]


def sh(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode:
        sys.exit("failed (%d): %s\n%s%s" % (p.returncode, " ".join(cmd), p.stdout, p.stderr))
    return p.stdout


def rotleap_energy(rl, chk, tmp, pme=False):
    path = os.path.join(tmp, "point.ini")
    text = DECK % ("start = " + chk, 0)
    if pme:  # the reaction field's dielectric is not a key of the Ewald sum
        text = text.replace("eps_rf = 78.3\n", "")
    open(path, "w").write(text)
    sets = sum((["--set", x] for x in PME_SETS), []) if pme else []
    E = json.loads(sh([rl, "energy", path, "--json", "--set", "output.prefix=" + os.path.join(tmp, "point")] + sets))
    return {"energy": E["energy"]["total"], "F": [m["force"] for m in E["molecules"]],
            "K": [m["torque"] for m in E["molecules"]]}


def openmm_eval(ck, pme=False):
    import numpy as np
    import openmm as mm
    from openmm import unit
    import watermodels
    box = ck["box"]
    system = mm.System()
    system.setDefaultPeriodicBoxVectors(mm.Vec3(box[0], 0, 0), mm.Vec3(0, box[1], 0), mm.Vec3(0, 0, box[2]))
    nb = mm.NonbondedForce()
    nb.setCutoffDistance(0.9)
    if pme:
        nb.setNonbondedMethod(mm.NonbondedForce.PME)
        nb.setPMEParameters(PME_ALPHA, *PME_GRID)
    else:
        nb.setNonbondedMethod(mm.NonbondedForce.CutoffPeriodic)
        nb.setReactionFieldDielectric(78.3)
    nb.setUseDispersionCorrection(False)
    nb.setUseSwitchingFunction(False)
    masses, owner = [], []
    body = 0
    for sp in ck["species"]:
        sites = watermodels.site_params("spc-e") if sp["name"] == "spc-e" else [("I",) + IONS[sp["name"]]]
        for _ in range(sp["count"]):
            base = system.getNumParticles()
            for _, mass, q, sig, eps in sites:
                system.addParticle(mass)
                nb.addParticle(q, sig, eps)
                masses.append(mass)
                owner.append(body)
            for a in range(len(sites)):
                for b in range(a + 1, len(sites)):
                    nb.addException(base + a, base + b, 0.0, 1.0, 0.0)
            body += 1
    system.addForce(nb)
    pos = np.array(rlcheckpoint.site_positions(ck))
    ctx = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName("Reference"))
    ctx.setPositions(pos)
    st = ctx.getState(getEnergy=True, getForces=True)
    e = st.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole)
    f = np.array(st.getForces(asNumpy=True).value_in_unit(unit.kilojoule_per_mole / unit.nanometer))
    if pme:  # rotleap's remove_net_force: each charged site gives up an equal share of the net force
        charged = np.array([nb.getParticleParameters(a)[0].value_in_unit(unit.elementary_charge) != 0.0
                            for a in range(system.getNumParticles())])
        f[charged] -= f.sum(0) / charged.sum()
    n = ck["n"]
    F, K = np.zeros((n, 3)), np.zeros((n, 3))
    owner = np.array(owner)
    for i in range(n):
        idx = np.where(owner == i)[0]
        F[i] = f[idx].sum(0)
        K[i] = np.cross(pos[idx] - np.array(ck["r"][i]), f[idx]).sum(0)
    return {"energy": e, "F": F.tolist(), "K": K.tolist(), "openmm": mm.__version__}


def rel_rms(a, b):
    num = sum((x - y) ** 2 for u, v in zip(a, b) for x, y in zip(u, v))
    den = sum(y ** 2 for v in b for y in v)
    return math.sqrt(num / den)


def compare(rl, om, tol_e=TOL_E, what="reaction field"):
    dE = abs(rl["energy"] - om["energy"]) / abs(om["energy"])
    dF, dK = rel_rms(rl["F"], om["F"]), rel_rms(rl["K"], om["K"])
    ok = len(rl["F"]) == len(om["F"]) and dE <= tol_e and dF <= TOL_F and dK <= TOL_F
    print("%s:" % what)
    print("energy  rotleap %.12g, OpenMM Reference %.12g kJ/mol: %.3e relative (tolerance %g)" % (
        rl["energy"], om["energy"], dE, tol_e))
    print("forces  RMS relative %.3e, torques %.3e (tolerance %g)" % (dF, dK, TOL_F))
    print("ok" if ok else "FAIL")
    return ok


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rotleap", default=os.path.join(os.path.dirname(HERE), "build", "rotleap"))
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--write", action="store_true")
    a = ap.parse_args()
    rl = os.path.abspath(a.rotleap)
    chk_gz, ref = os.path.join(DATA, "salt_openmm.chk.gz"), os.path.join(DATA, "salt_openmm.json.gz")
    ref_pme = os.path.join(DATA, "salt_openmm_pme.json.gz")
    pme_what = "PME (alpha %g /nm, grid %dx%dx%d, order 5)" % ((PME_ALPHA,) + PME_GRID)
    with tempfile.TemporaryDirectory() as tmp:
        chk = os.path.join(tmp, "salt.chk")
        if a.check:
            open(chk, "wb").write(gzip.decompress(open(chk_gz, "rb").read()))
            om = json.loads(gzip.decompress(open(ref, "rb").read()))
            om_pme = json.loads(gzip.decompress(open(ref_pme, "rb").read()))
            print("checked-in OpenMM %s Reference numbers" % om.get("openmm", "?"))
            ok = compare(rotleap_energy(rl, chk, tmp), om)
            ok = compare(rotleap_energy(rl, chk, tmp, pme=True), om_pme, TOL_E_PME, pme_what) and ok
            sys.exit(0 if ok else 1)
        path = os.path.join(tmp, "make.ini")
        open(path, "w").write(DECK % ("", 20))
        sh([rl, "run", path, "--set", "output.prefix=" + os.path.join(tmp, "salt")])
        ck = rlcheckpoint.read(chk)
        om, om_pme = openmm_eval(ck), openmm_eval(ck, pme=True)
        ok = compare(rotleap_energy(rl, chk, tmp), om)
        ok = compare(rotleap_energy(rl, chk, tmp, pme=True), om_pme, TOL_E_PME, pme_what) and ok
        if a.write:
            buf = rlcheckpoint.zero_velocities(open(chk, "rb").read())
            open(chk_gz, "wb").write(gzip.compress(buf, 9, mtime=0))
            open(ref, "wb").write(gzip.compress(json.dumps(om).encode(), 9, mtime=0))
            open(ref_pme, "wb").write(gzip.compress(json.dumps(om_pme).encode(), 9, mtime=0))
            print("wrote", chk_gz, ref, ref_pme)
        sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
