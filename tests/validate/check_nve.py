#!/usr/bin/python3
"""CTest: a short NVE run of rotleap (216 TIP4P from rest, h = 1 fs, 500 steps; and h = 0.5 fs,
202 steps) against OpenMM 7.7's VerletIntegrator + SETTLE trajectory checked in as
validate/data/nve_openmm_tip4p.csv (no OpenMM needed at test time).

    /usr/bin/python3 tests/validate/check_nve.py ROTLEAP SOURCE_DIR WORK_DIR

Data written by: /usr/bin/python3 validate/nve_short.py --rotleap build/rotleap
Criteria: validate/nve_metrics.py (trajectory over the first 100 steps; calE and drift).
About 6 s.
"""
import csv
import gzip
import os
import sys


def main():
    rotleap, src, work = sys.argv[1:4]
    sys.dont_write_bytecode = True  # no __pycache__ in the source tree
    sys.path.insert(0, os.path.join(src, "validate"))
    import nve_metrics as nm
    data = os.path.join(src, "validate", "data")
    os.makedirs(work, exist_ok=True)
    start = os.path.join(work, "nve_tip4p_start.chk")
    with gzip.open(os.path.join(data, "nve_tip4p_start.chk.gz")) as g, open(start, "wb") as f:
        f.write(g.read())
    with open(os.path.join(data, "nve_openmm_tip4p.csv")) as f:
        rows = csv.DictReader(line for line in f if not line.startswith("#"))
        omm = [(int(r["step"]), float(r["total"]), float(r["potential"])) for r in rows]
    import rlcheckpoint
    ck = rlcheckpoint.read(start)
    rl = nm.rotleap_series(rotleap, work, start, ck["box"], nm.STEPS, nm.H, "rl_h1")
    half = nm.rotleap_series(rotleap, work, start, ck["box"], 2 * nm.WINDOW + 2, nm.H / 2, "rl_h05")
    m = nm.metrics(rl, half, omm, ck["n"])
    for line in nm.report(m):
        print(line)
    print("step 0: U rotleap %.6f, OpenMM %.6f" % (rl[0][2], omm[0][2]))
    return 0 if m["ok1"] and m["ok2"] else 1


if __name__ == "__main__":
    sys.exit(main())
