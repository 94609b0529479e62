#!/usr/bin/env python3
"""Bit-for-bit regression between two builds of rotleap (issue 32: a restructuring that changes
no behaviour).  Runs the same matrix with both binaries and compares every output byte for byte:
each example deck, 200 steps after a short relaxation, under NVE, Bussi, Langevin and the
isokinetic thermostat, in double and mixed precision, on 1 and 2 threads, with a trajectory;
checkpoint, thermo file, trajectory (+ PDB), analysis journal, results, RDF and correlation
functions.  The summary differs by its wall time and is compared without it.

  scripts/bitwise_regress.py OLD_ROTLEAP NEW_ROTLEAP WORKDIR [--decks a,b] [--quick]

To compare a commit with the working tree:
  git worktree add /tmp/base COMMIT && cmake -S /tmp/base -B /tmp/base/build -DROTLEAP_TESTS=OFF &&
  cmake --build /tmp/base/build -j && scripts/bitwise_regress.py /tmp/base/build/rotleap build/rotleap /tmp/bits
Prints one line per case and a count; exit status 0 if every case is identical.  About 4 minutes
on 2 cores."""
import argparse
import filecmp
import os
import re
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ENSEMBLES = ["nve", "nvt-bussi", "nvt-langevin", "nvt-isokinetic"]
EXTS = ["chk", "thermo.csv", "dcd", "pdb", "xyz", "samples", "results.txt", "rdf.csv", "tcf.csv"]


def deck_temperature(deck):
    text = open(deck).read()
    m = re.search(r"^\s*temperature\s*=\s*([^;#\n]+)", text, re.M)
    return m.group(1).strip()


def cases(decks, quick):
    for deck in decks:
        T = deck_temperature(deck)
        name = os.path.basename(deck)[:-4]
        for ens in ENSEMBLES if not quick else ENSEMBLES[:2]:
            for prec in ["double", "mixed"]:
                for threads in [1, 2]:
                    args = ["--set", "run.steps=200", "--set", "run.equilibrate=100", "--set", "output.thermo_every=10",
                            "--set", "output.trajectory_every=20", "--set", "output.progress=no",
                            "--set", "interactions.precision=" + prec, "--set", "run.threads=%d" % threads,
                            "--set", "run.ensemble=" + ens, "--set", "system.temperature=" + T]
                    if ens == "nve":
                        args += ["--set", "run.temperature=", "--set", "run.tau="]
                    else:
                        args += ["--set", "run.temperature=" + T]
                        if ens == "nvt-isokinetic":
                            args += ["--set", "run.tau="]
                    yield "%s-%s-%s-t%d" % (name, ens, prec, threads), deck, args


def run(binary, work, case):
    name, deck, args = case
    prefix = os.path.join(work, name)
    r = subprocess.run([binary, "run", deck] + args + ["--set", "output.prefix=" + prefix],
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    return r.returncode, r.stderr


def compare(a, b, name):
    bad = []
    for ext in EXTS:
        fa, fb = os.path.join(a, name + "." + ext), os.path.join(b, name + "." + ext)
        if os.path.exists(fa) != os.path.exists(fb):
            bad.append(ext + " (missing)")
        elif os.path.exists(fa) and not filecmp.cmp(fa, fb, shallow=False):
            bad.append(ext)
    sa, sb = (os.path.join(d, name + ".summary.txt") for d in (a, b))
    strip = lambda p: [l for l in open(p) if not l.startswith(("wall_seconds", "# rotleap"))] if os.path.exists(p) else None
    if strip(sa) != strip(sb):
        bad.append("summary.txt")
    return bad


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("work")
    ap.add_argument("--decks", default="")
    ap.add_argument("--quick", action="store_true", help="NVE and Bussi only")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    decks = sorted(os.path.join(SRC, "examples", f) for f in os.listdir(os.path.join(SRC, "examples")) if f.endswith(".ini"))
    if a.decks:
        decks = [d for d in decks if os.path.basename(d)[:-4] in a.decks.split(",")]
    shutil.rmtree(a.work, ignore_errors=True)
    dirs = {k: os.path.join(a.work, k) for k in ("old", "new")}
    for d in dirs.values():
        os.makedirs(d)
    selected = list(cases(decks, a.quick))
    with ThreadPoolExecutor(a.jobs) as pool:  # one binary after the other, so that the two never share the CPUs unevenly
        for which, binary in (("old", a.old), ("new", a.new)):
            results = list(pool.map(lambda c: run(binary, dirs[which], c), selected))
            for c, (code, err) in zip(selected, results):
                if code:
                    print("%s: %s run failed (%d): %s" % (c[0], which, code, err.strip()[:300]))
    same = 0
    for name, _, _ in selected:
        bad = compare(dirs["old"], dirs["new"], name)
        print("%s: %s" % (name, "identical" if not bad else "DIFFERS in " + ", ".join(bad)))
        same += not bad
    print("%d of %d cases byte for byte identical" % (same, len(selected)))
    return 0 if same == len(selected) else 1


if __name__ == "__main__":
    sys.exit(main())
