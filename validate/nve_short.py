#!/usr/bin/python3
"""Short NVE comparison: rotleap's revised leapfrog vs OpenMM 7.7's VerletIntegrator + SETTLE.

Run (from the repository root, after validate/single_point.py has written
validate/data/sp_tip4p_liquid.chk.gz):
    /usr/bin/python3 validate/nve_short.py [--rotleap build/rotleap] [--no-write]
About 25 s (OpenMM Reference, 500 steps of 216 TIP4P, is most of it).

System: 216 TIP4P, the equilibrated liquid of the single-point set (1 g/cm3, site cutoff 0.9 nm,
reaction field eps_rf 78.3, plain LJ, no dispersion correction), started AT REST: both codes take
the same positions (r + A^T d from the checkpoint) and zero mid-step velocities v(-h/2) = 0,
l(-h/2) = 0 (OpenMM's Verlet is a leapfrog too; its setVelocities(0) is the same start).  A
start at rest needs no conversion of angular momenta to atom velocities, which for mid-step
quantities of a rotating body is not unique and would put an O(h) difference into the start.
The molecules then fall into the potential: T rises to ~175 K in 0.5 ps.

rotleap: `rotleap run` NVE, h = 1 fs, 500 steps, and the same start at h = 0.5 fs, 200 steps
(from the checkpoint validate/data/nve_tip4p_start.chk.gz: the configuration spliced into the
0-step checkpoint of an NVE run, see rlcheckpoint.splice_state).
OpenMM: VerletIntegrator(1 fs), O-H, O-H, H-H constraints (SETTLE), M a virtual site, Reference
platform, 500 steps; its step-by-step energies go to validate/data/nve_openmm_tip4p.csv, which
tests/validate/check_nve.py compares rotleap against without OpenMM.

Criteria: see validate/nve_metrics.py and validate/README.md.
"""
import argparse
import gzip
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

ROOT = os.path.dirname(HERE)
DATA = os.path.join(HERE, "data")
from nve_metrics import STEPS, H, WINDOW, metrics, report, rotleap_deck, rotleap_series  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rotleap", default=os.path.join(ROOT, "build", "rotleap"))
    ap.add_argument("--platform", default="Reference")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    rotleap = os.path.abspath(args.rotleap)
    t0 = time.time()
    work = tempfile.mkdtemp(prefix="rotleap-nve-")
    liquid = gzip.open(os.path.join(DATA, "sp_tip4p_liquid.chk.gz")).read()
    ck = rlcheckpoint.parse(liquid)
    box, n = ck["box"], ck["n"]
    # template: the 0-step checkpoint of an NVE run of the same system
    tmpl = os.path.join(work, "template")
    with open(tmpl + ".ini", "w") as f:
        f.write(rotleap_deck("", box, 0, H, tmpl).replace("start = \n", ""))
    subprocess.run([rotleap, "run", tmpl + ".ini"], check=True, capture_output=True)
    start = rlcheckpoint.splice_state(open(tmpl + ".chk", "rb").read(), liquid)
    start_path = os.path.join(work, "nve_tip4p_start.chk")
    with open(start_path, "wb") as f:
        f.write(start)

    rl = rotleap_series(rotleap, work, start_path, box, STEPS, H, "rl_h1")
    rl_half = rotleap_series(rotleap, work, start_path, box, 2 * WINDOW + 2, H / 2, "rl_h05")

    system = watermodels.build_system("tip4p", n, box, 0.9, 78.3, rigid=True)
    integ = mm.VerletIntegrator(H)
    integ.setConstraintTolerance(1e-10)
    ctx = mm.Context(system, integ, mm.Platform.getPlatformByName(args.platform))
    ctx.setPositions(np.array(rlcheckpoint.site_positions(ck)))
    ctx.computeVirtualSites()
    ctx.setVelocities(np.zeros((4 * n, 3)))
    omm = []
    for step in range(STEPS + 1):
        if step:
            integ.step(1)
        st = ctx.getState(getEnergy=True)
        u = st.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole)
        k = st.getKineticEnergy().value_in_unit(unit.kilojoule_per_mole)
        omm.append((step, u + k, u))
    m = metrics(rl, rl_half, omm, n)
    lines = report(m)
    print("\n".join(lines))
    print("rotleap step 0 U %.10f, OpenMM step 0 U %.10f; %.0f s" % (rl[0][2], omm[0][2], time.time() - t0))
    if not args.no_write:
        with gzip.GzipFile(os.path.join(DATA, "nve_tip4p_start.chk.gz"), "wb", mtime=0) as g:
            g.write(start)
        with open(os.path.join(DATA, "nve_openmm_tip4p.csv"), "w") as f:
            f.write("# OpenMM %s %s, VerletIntegrator 1 fs + SETTLE, 216 TIP4P from "
                    "nve_tip4p_start.chk.gz at rest; written by\n"
                    "#   /usr/bin/python3 validate/nve_short.py --rotleap BUILD/rotleap\n"
                    "# kinetic energy: OpenMM's (leapfrog: mean of the half-step values)\n"
                    % (mm.version.version, args.platform))
            f.write("step,total,potential\n")
            for s, e, u in omm:
                f.write("%d,%.10f,%.10f\n" % (s, e, u))
        with open(os.path.join(DATA, "nve_summary.txt"), "w") as f:
            f.write("# validate/nve_short.py (%s)\n" % time.strftime("%Y-%m-%d") + "\n".join(lines) + "\n")
    return 0 if m["ok1"] and m["ok2"] else 1


if __name__ == "__main__":
    sys.exit(main())
