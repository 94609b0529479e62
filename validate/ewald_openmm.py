#!/usr/bin/python3
"""Ewald and smooth PME of rotleap (forces/ewald/, issue 33) against OpenMM 7.7's Reference platform.

Run (from the repository root, after building; the driver is built with the tests):
    /usr/bin/python3 validate/ewald_openmm.py [--driver build/tests/forces/ewald/ewald_point] [--no-write]
OpenMM 7.7 from Debian: apt-get install -y python3-simtk libopenmm-plugins python3-numpy.
About 5 s on 2 cores.

Configurations: the checked-in single-point checkpoints (validate/single_point.py) of TIP4P-Ew,
SPC/E and TIP3P: `liquid` (216 molecules, 1.8626 nm cube, cutoff 0.9 nm) and `random-noncubic`
(130 molecules, 1.55 x 1.60 x 1.70 nm, cutoff 0.75 nm); and liquid CO2 (EPM2, three charges on
the molecular axis): `liquid` (256 molecules, 2.6036 nm cube at 1.06 g/cm3, cutoff 1.0 nm, grid
32^3 for the explicit case), validate/data/sp_co2_liquid.chk.gz, the checkpoint of
examples/co2.ini shortened to 1000 + 500 steps with seed 11 (velocities zeroed).  On each, electrostatics only (every LJ
epsilon 0 in OpenMM; rotleap's "ewald-real" + reciprocal terms), every intramolecular pair excluded
(OpenMM: exceptions with zero charge product; rotleap: pairs within a body are excluded and their
reciprocal-space part subtracted), no dispersion correction, tin-foil boundary:

  pme-explicit   OpenMM PME with setPMEParameters(alpha, nx, ny, nz) (alpha 3.3 /nm; grid 24^3, or
                 20 x 21 x 22 in the non-cubic box; OpenMM's spline order, 5) against rotleap "pme"
                 with the same alpha, grid and order 5
  pme-tolerance  OpenMM PME from ewaldErrorTolerance 5e-4 and rotleap "pme" from tolerance 5e-4:
                 alpha and the grid must come out the same (OpenMM's getPMEParametersInContext), and
                 the results agree
  ewald-tolerance  OpenMM's Ewald method from tolerance 5e-4 against rotleap "ewald" from the same
                 tolerance (OpenMM's alpha and kmax: rotleap's kmax = OpenMM's kmax - 1)
  ewald-1e-5     the same at tolerance 1e-5

Molecular forces and torques from OpenMM's atom forces as in single_point.py (the force OpenMM 7.7
still reports on TIP4P's virtual site after distributing it is left out).  Criteria (issue 33):
|dE| / |E| <= 1e-9, RMS relative force and torque error <= 1e-8.

Writes (unless --no-write) validate/data/ewald_openmm_reference.json.gz (every case's OpenMM numbers:
what tests/forces/ewald/check_ewald_openmm.py compares rotleap with, without OpenMM) and
validate/data/ewald_openmm_summary.txt (the table printed at the end).  Exit status 1 on a failure.
"""
import argparse
import gzip
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True
sys.path.insert(0, HERE)
import rlcheckpoint  # noqa: E402
import watermodels  # noqa: E402

try:
    import openmm as mm
    from openmm import unit
except ImportError:
    from simtk import openmm as mm
    from simtk import unit

TOL_E, TOL_F, TOL_K = 1e-9, 1e-8, 1e-8
ROOT = os.path.dirname(HERE)
DATA = os.path.join(HERE, "data")
MODELS = ["tip4p-ew", "spc-e", "tip3p", "co2"]
WATER_CONFIGS = [dict(name="liquid", cutoff=0.9, grid=(24, 24, 24)),
                 dict(name="random-noncubic", cutoff=0.75, grid=(20, 21, 22))]
CONFIGS = {"co2": [dict(name="liquid", cutoff=1.0, grid=(32, 32, 32))]}
# EPM2 CO2 (Harris & Yung, J. Phys. Chem. 99, 12021 (1995)): C-O 1.149 A, q_C +0.6512 e, q_O -0.3256 e;
# written down here from the paper, not read from rotleap (as watermodels.py does for water).  The LJ
# parameters are irrelevant (electrostatics only).  Sites in rotleap's order O1, C, O2.
M_C, M_O = 12.011, 15.9994
CO2_SITES = [("O1", M_O, -0.3256, 0.3033, 0.0), ("C", M_C, 0.6512, 0.2757, 0.0), ("O2", M_O, -0.3256, 0.3033, 0.0)]
CO2_BOND = 0.1149


def model_sites(model):
    """[(name, mass, charge, sigma, eps)] in rotleap's site order."""
    return CO2_SITES if model == "co2" else watermodels.site_params(model)


def check_co2_geometry(ck):
    """The checkpoint's CO2 is EPM2's geometry (to the 1e-12 nm that a rotleap body frame holds)."""
    d = [s[2] for s in ck["species"][0]["sites"]]
    if max(abs(d[0] + CO2_BOND), abs(d[1]), abs(d[2] - CO2_BOND)) > 1e-12:
        sys.exit("CO2 checkpoint geometry %s is not EPM2's (C-O %g nm)" % (d, CO2_BOND))
CASES = [dict(name="pme-explicit", method="pme", alpha=3.3),
         dict(name="pme-tolerance", method="pme", tolerance=5e-4),
         dict(name="ewald-tolerance", method="ewald", tolerance=5e-4),
         dict(name="ewald-1e-5", method="ewald", tolerance=1e-5)]


def openmm_system(model, nmol, box, cutoff, case, grid):
    """Charges only, every intramolecular pair excluded, M a ThreeParticleAverageSite."""
    sites = model_sites(model)
    ns = len(sites)
    system = mm.System()
    system.setDefaultPeriodicBoxVectors(mm.Vec3(box[0], 0, 0), mm.Vec3(0, box[1], 0), mm.Vec3(0, 0, box[2]))
    nb = mm.NonbondedForce()
    nb.setNonbondedMethod(mm.NonbondedForce.PME if case["method"] == "pme" else mm.NonbondedForce.Ewald)
    nb.setCutoffDistance(cutoff)
    nb.setUseDispersionCorrection(False)
    nb.setUseSwitchingFunction(False)
    if "tolerance" in case:
        nb.setEwaldErrorTolerance(case["tolerance"])
    else:
        nb.setPMEParameters(case["alpha"], *grid)
    w = watermodels.vsite_weights(model) if model != "co2" and watermodels.four_site(model) else None
    for m in range(nmol):
        base = m * ns
        for name, mass, q, sig, eps in sites:
            system.addParticle(mass)
            nb.addParticle(q, 0.3, 0.0)
        if w:
            system.setVirtualSite(base + 3, mm.ThreeParticleAverageSite(base, base + 1, base + 2, *w))
        for a in range(ns):
            for b in range(a + 1, ns):
                nb.addException(base + a, base + b, 0.0, 1.0, 0.0)
    system.addForce(nb)
    return system, nb


def openmm_eval(model, ck, cutoff, case, grid):
    nmol = ck["n"]
    system, nb = openmm_system(model, nmol, ck["box"], cutoff, case, grid)
    ctx = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName("Reference"))
    ctx.setPositions(np.array(rlcheckpoint.site_positions(ck)))
    ctx.computeVirtualSites()
    st = ctx.getState(getEnergy=True, getForces=True, getPositions=True)
    e = st.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole)
    f = np.array(st.getForces(asNumpy=True).value_in_unit(unit.kilojoule_per_mole / unit.nanometer))
    x = np.array(st.getPositions(asNumpy=True).value_in_unit(unit.nanometer))
    ns = len(ck["species"][0]["sites"])
    masses = np.array([s[1] for s in model_sites(model)])
    F = np.zeros((nmol, 3))
    K = np.zeros((nmol, 3))
    for i in range(nmol):
        xa, fa = x[i * ns:(i + 1) * ns], f[i * ns:(i + 1) * ns]
        R = (masses[:, None] * xa).sum(0) / masses.sum()
        if ns == 4:  # OpenMM 7.7 still reports the distributed force on M: use O, H1, H2 only
            xa, fa = xa[:3], fa[:3]
        F[i] = fa.sum(0)
        K[i] = np.cross(xa - R, fa).sum(0)
    out = dict(energy=e, F=F, K=K)
    if case["method"] == "pme":
        a, nx, ny, nz = nb.getPMEParametersInContext(ctx)
        out.update(alpha=a, grid=[nx, ny, nz])
    else:  # OpenMM has no getter for the Ewald set: its formula (NonbondedForceImpl::calcEwaldParameters)
        out.update(alpha=(1.0 / cutoff) * math.sqrt(-math.log(2.0 * case["tolerance"])))
    return out


def driver_args(case, cfg, model, chk):
    a = ["--checkpoint", chk, "--model", model, "--method", case["method"], "--cutoff", repr(cfg["cutoff"])]
    if "tolerance" in case:
        a += ["--tolerance", repr(case["tolerance"])]
    else:
        a += ["--alpha", repr(case["alpha"]), "--grid"] + [str(g) for g in cfg["grid"]] + ["--order", "5"]
    return a


def rel_rms(a, b):
    return float(np.sqrt(np.sum((a - b) ** 2) / np.sum(b ** 2)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--driver", default=os.path.join(ROOT, "build", "tests", "forces", "ewald", "ewald_point"))
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    t0 = time.time()
    work = tempfile.mkdtemp(prefix="rotleap-ewald-")
    rows, refs, ok = [], [], True
    print("OpenMM %s Reference; tolerances: energy %.0e relative, forces and torques %.0e RMS relative"
          % (mm.version.version, TOL_E, TOL_F))
    for model in MODELS:
        for cfg in CONFIGS.get(model, WATER_CONFIGS):
            chkgz = "sp_%s_%s.chk.gz" % (model, cfg["name"])
            chk = os.path.join(work, chkgz[:-3])
            with gzip.open(os.path.join(DATA, chkgz)) as g, open(chk, "wb") as f:
                f.write(g.read())
            ck = rlcheckpoint.read(chk)
            if model == "co2":
                check_co2_geometry(ck)
            for case in CASES:
                ref = openmm_eval(model, ck, cfg["cutoff"], case, cfg["grid"])
                cmd = [args.driver] + driver_args(case, cfg, model, chk)
                p = subprocess.run(cmd, capture_output=True, text=True)
                if p.returncode:
                    sys.exit("failed: %s\n%s" % (" ".join(cmd), p.stderr))
                rl = json.loads(p.stdout)
                Frl = np.array([m["force"] for m in rl["molecules"]])
                Krl = np.array([m["torque"] for m in rl["molecules"]])
                Erl = rl["energy"]["total"]
                r = dict(model=model, config=cfg["name"], case=case["name"], n=ck["n"], E_omm=ref["energy"], E_rl=Erl,
                         dE=abs(Erl - ref["energy"]) / abs(ref["energy"]), dF=rel_rms(Frl, ref["F"]),
                         dK=rel_rms(Krl, ref["K"]), alpha_omm=ref["alpha"], alpha_rl=rl["params"]["alpha"],
                         grid_omm=ref.get("grid"), grid_rl=rl["params"]["grid"], kmax_rl=rl["params"]["kmax"],
                         describe=rl["describe"])
                r["ok"] = r["dE"] <= TOL_E and r["dF"] <= TOL_F and r["dK"] <= TOL_K
                if "tolerance" in case:  # the derived parameters must be OpenMM's
                    r["ok"] &= r["alpha_rl"] == r["alpha_omm"]
                    if case["method"] == "pme":
                        r["ok"] &= r["grid_rl"] == r["grid_omm"]
                ok &= r["ok"]
                rows.append(r)
                par = ("grid %s" % "x".join(map(str, r["grid_rl"]))) if case["method"] == "pme" else \
                      ("kmax %s" % " ".join(map(str, r["kmax_rl"])))
                print("  %-8s %-16s %-16s N=%3d alpha %.6f %-17s E_omm %+.10f  dE %.1e  dF %.1e  dK %.1e  %s"
                      % (model, cfg["name"], case["name"], ck["n"], r["alpha_rl"], par, ref["energy"], r["dE"], r["dF"],
                         r["dK"], "ok" if r["ok"] else "FAIL"), flush=True)
                refs.append(dict(model=model, config=cfg["name"], case=case["name"], chk=chkgz,
                                 args=driver_args(case, cfg, model, "CHECKPOINT"),
                                 alpha=ref["alpha"], grid=ref.get("grid"), energy=ref["energy"],  # forces, torques: 11 digits
                                 forces=[[float("%.11g" % v) for v in row] for row in ref["F"]],
                                 torques=[[float("%.11g" % v) for v in row] for row in ref["K"]]))
    elapsed = time.time() - t0
    summary = ["# validate/ewald_openmm.py: rotleap ewald-real + ewald/pme vs OpenMM %s Reference (%s), %.0f s"
               % (mm.version.version, time.strftime("%Y-%m-%d"), elapsed),
               "# tolerances: energy %.0e relative; force, torque %.0e RMS relative; derived alpha and grid identical"
               % (TOL_E, TOL_F),
               "model    config           case              N   alpha        grid/kmax      E_OpenMM(kJ/mol)      "
               "E_rotleap(kJ/mol)     rel_dE   rms_dF   rms_dK"]
    for r in rows:
        par = "x".join(map(str, r["grid_rl"])) if r["grid_omm"] is not None or r["case"].startswith("pme") else \
              " ".join(map(str, r["kmax_rl"]))
        summary.append("%-8s %-16s %-16s %4d  %.9f  %-13s %+.12f  %+.12f  %.1e  %.1e  %.1e%s"
                       % (r["model"], r["config"], r["case"], r["n"], r["alpha_rl"], par, r["E_omm"], r["E_rl"], r["dE"],
                          r["dF"], r["dK"], "" if r["ok"] else "  FAIL"))
    mx = lambda k: max(r[k] for r in rows)
    summary.append("max: rel_dE %.1e  rms_dF %.1e  rms_dK %.1e" % (mx("dE"), mx("dF"), mx("dK")))
    summary.append("result: %s" % ("all within tolerance" if ok else "DISAGREEMENT (see FAIL rows)"))
    print("\n".join(summary))
    if not args.no_write:
        with open(os.path.join(DATA, "ewald_openmm_summary.txt"), "w") as f:
            f.write("\n".join(summary) + "\n")
        with gzip.GzipFile(os.path.join(DATA, "ewald_openmm_reference.json.gz"), "wb", mtime=0) as g:
            g.write(json.dumps({"generated_by": "/usr/bin/python3 validate/ewald_openmm.py", "openmm": mm.version.version,
                                "platform": "Reference",
                                "tolerance": {"energy_rel": TOL_E, "force_rms_rel": TOL_F, "torque_rms_rel": TOL_K},
                                "cases": refs}, separators=(",", ":")).encode())
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
