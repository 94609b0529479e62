#!/usr/bin/python3
"""CTest: the Ewald terms (ewald-real + ewald or pme, through tests/forces/ewald/ewald_point) on the
checked-in configurations against the checked-in OpenMM 7.7 Reference numbers (no OpenMM needed).

    /usr/bin/python3 tests/forces/ewald/check_ewald_openmm.py EWALD_POINT SOURCE_DIR WORK_DIR

The data (validate/data/sp_*.chk.gz, ewald_openmm_reference.json.gz) are written by
    /usr/bin/python3 validate/ewald_openmm.py
Criteria (issue 33): energy within 1e-9 relative; molecular forces and torques within 1e-8 RMS
relative; where rotleap derives alpha and the grid from the tolerance, OpenMM's values exactly.
Standard library only; one line per check.
"""
import gzip
import json
import math
import os
import subprocess
import sys


def rms_rel(a, b):
    num = sum((x - y) ** 2 for ra, rb in zip(a, b) for x, y in zip(ra, rb))
    return math.sqrt(num / sum(y * y for rb in b for y in rb))


def main():
    driver, src, work = sys.argv[1:4]
    data = os.path.join(src, "validate", "data")
    os.makedirs(work, exist_ok=True)
    with gzip.open(os.path.join(data, "ewald_openmm_reference.json.gz"), "rt") as f:
        ref = json.load(f)
    tol = ref["tolerance"]
    failures = 0
    for c in ref["cases"]:
        chk = os.path.join(work, c["chk"][:-3])
        if not os.path.exists(chk):
            with gzip.open(os.path.join(data, c["chk"]), "rb") as g, open(chk, "wb") as f:
                f.write(g.read())
        args = [chk if a == "CHECKPOINT" else a for a in c["args"]]
        p = subprocess.run([driver] + args, capture_output=True, text=True)
        name = "%s %s %s" % (c["model"], c["config"], c["case"])
        if p.returncode:
            print("check %-40s FAIL: %s" % (name, p.stderr.strip()))
            failures += 1
            continue
        out = json.loads(p.stdout)
        F = [m["force"] for m in out["molecules"]]
        K = [m["torque"] for m in out["molecules"]]
        dE = abs(out["energy"]["total"] - c["energy"]) / abs(c["energy"])
        dF, dK = rms_rel(F, c["forces"]), rms_rel(K, c["torques"])
        ok = len(F) == len(c["forces"]) and dE <= tol["energy_rel"] and dF <= tol["force_rms_rel"] and dK <= tol["torque_rms_rel"]
        same = ""
        if "--tolerance" in args:
            ok &= out["params"]["alpha"] == c["alpha"]
            same = ", alpha %s" % ("= OpenMM's" if out["params"]["alpha"] == c["alpha"] else "!= OpenMM's %r" % c["alpha"])
            if c["grid"] is not None:
                ok &= out["params"]["grid"] == c["grid"]
                same += ", grid %s" % ("= OpenMM's" if out["params"]["grid"] == c["grid"] else "!= OpenMM's %s" % c["grid"])
        print("check %-40s dE %.1e  dF %.1e  dK %.1e%s  %s" % (name, dE, dF, dK, same, "ok" if ok else "FAIL"))
        failures += not ok
    n = len(ref["cases"])
    print("%d of %d cases agree with OpenMM %s (%s)" % (n - failures, n, ref["openmm"], ref["platform"]))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
