#!/usr/bin/python3
"""CTest: point dipoles in the Ewald terms (ewald-real + ewald, through tests/forces/ewald/ewald_point
--dipoles) on the checked-in Stockmayer configurations against the checked-in LAMMPS ewald/dipole
numbers (no LAMMPS needed).

    /usr/bin/python3 tests/forces/ewald/check_ewald_lammps.py EWALD_POINT SOURCE_DIR WORK_DIR

The data (tests/forces/ewald/data/ewald_dipole_lammps.json.gz) are written by
    /usr/bin/python3 validate/ewald_dipole_lammps.py
whose compare() this uses: as they are, energy, forces and torques within 1e-6; with the real-space
difference of LAMMPS's erfc approximation (stored with the data) added, within 1e-11.
"""
import gzip
import json
import os
import subprocess
import sys
import tempfile


def main():
    driver, src, work = sys.argv[1:4]
    sys.path.insert(0, os.path.join(src, "validate"))
    from ewald_dipole_lammps import compare, write_config
    os.makedirs(work, exist_ok=True)
    with gzip.open(os.path.join(src, "tests", "forces", "ewald", "data", "ewald_dipole_lammps.json.gz"), "rt") as f:
        ref = json.load(f)
    failures = 0
    for c in ref["cases"]:
        with tempfile.TemporaryDirectory(dir=work) as w:
            cfg = os.path.join(w, "config.txt")
            write_config(cfg, c["box"], c["mu"], c["positions"], c["axes"])
            p = subprocess.run([driver, "--dipoles", cfg] + c["args"], capture_output=True, text=True)
        if p.returncode:
            print("check %-36s FAIL: %s" % (c["case"], p.stderr.strip()))
            failures += 1
            continue
        ok, row = compare(json.loads(p.stdout), c)
        print("check " + row)
        failures += not ok
    n = len(ref["cases"])
    print("%d of %d cases agree with %s" % (n - failures, n, ref["lammps"]))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
