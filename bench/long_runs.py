#!/usr/bin/python3
"""10^6-step NVE runs of a Stockmayer fluid and of water (issue 7, stability at the extremes):
rigidity at the end (|rho| - 1 for dipoles, |A A^T - I| for water; target <= 1e-12) and the
drift of the conserved energy over the whole run beside what `rotleap scan` reports for the same
deck and step over 10^4 steps (target: no drift beyond it).  Prints a table, writes
bench/long_runs.csv.

  Stockmayer: 256 dipoles, rho* = 0.8, T* = 1.35, mu*^2 = 3, shifted-force LJ and dipoles, rc 2.5,
              h = 0.002 (examples/stockmayer.ini, relaxed and equilibrated by Bussi first)
  water:      64 TIP4P (tests/cli/water_scan.ini: rc 0.6 nm, shifted-force LJ, RF 78.3), h = 2 fs,
              after 10 ps of Bussi NVT

water-smooth is the same water with eps_rf = inf, whose reaction-field force vanishes at rc.
All long runs write a checkpoint every 10^5 steps.  The drift is the least-squares slope of the
total energy against time, per molecule, over the thermo rows (every 1000 steps); its standard
error is estimated from 10 blocks.  About 25 minutes on one core of this machine.
usage: /usr/bin/python3 bench/long_runs.py [--rotleap build/rotleap] [--steps 1000000] [--out DIR]"""
import argparse
import csv
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rlfiles import keyvals as summary  # noqa: E402

SCENES = {
    "stockmayer": dict(deck="examples/stockmayer.ini", h="0.002", eq="--set run.steps=20000",
                       unit="reduced (eps per molecule per tau)", per_ns=1.0),
    "water": dict(deck="tests/cli/water_scan.ini", h="2fs",
                  eq="--set run.ensemble=nvt-bussi --set run.temperature=298K --set run.tau=0.1ps --set run.steps=5000",
                  unit="kJ/mol per molecule per ns", per_ns=1e3),
    # the same with eps_rf = inf: the reaction-field force then vanishes at rc (no force jump)
    "water-smooth": dict(deck="tests/cli/water_scan.ini", h="2fs",
                         eq="--set run.ensemble=nvt-bussi --set run.temperature=298K --set run.tau=0.1ps "
                            "--set run.steps=5000 --set interactions.eps_rf=inf",
                         unit="kJ/mol per molecule per ns", per_ns=1e3, extra="--set interactions.eps_rf=inf"),
}


def sh(args, log):
    with open(log, "w") as f:
        p = subprocess.run(args, stdout=f, stderr=subprocess.STDOUT)
    if p.returncode:
        sys.exit("failed: %s (see %s)" % (" ".join(args), log))


def slope(t, e):
    n = len(t)
    mt, me = sum(t) / n, sum(e) / n
    return sum((a - mt) * (b - me) for a, b in zip(t, e)) / sum((a - mt) ** 2 for a in t)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rotleap", default="build/rotleap")
    ap.add_argument("--steps", type=int, default=1000000)
    ap.add_argument("--out", default="bench")
    ap.add_argument("--scenes", default=",".join(SCENES), help="comma-separated subset of " + ",".join(SCENES))
    a = ap.parse_args()
    rl = os.path.abspath(a.rotleap)
    work = os.path.join(a.out, "long_runs_work")
    os.makedirs(work, exist_ok=True)
    rows = []
    for name in a.scenes.split(","):
        sc = SCENES[name]
        t0 = time.time()
        pre = os.path.join(work, name)
        # equilibrate (the deck's own relaxation and ensemble), then NVE from its checkpoint
        sh([rl, "run", sc["deck"], *sc["eq"].split(), "--set", "run.timestep=" + sc["h"],
            "--set", "output.progress=no", "--set", "output.prefix=" + pre + "_eq"], pre + "_eq.log")
        nve = sc.get("extra", "").split() + ["--set", "system.start=" + pre + "_eq.chk", "--set", "run.ensemble=nve", "--set", "run.temperature=",
               "--set", "run.tau=", "--set", "run.equilibrate=0", "--set", "run.timestep=" + sc["h"],
               "--set", "output.progress=no"]
        if name == "stockmayer":
            nve += ["--set", "system.temperature=1.35"]
        sh([rl, "run", sc["deck"], *nve, "--set", "run.steps=%d" % a.steps, "--set", "output.thermo_every=1000",
            "--set", "output.checkpoint_every=100000", "--set", "output.sample_every=0",
            "--set", "output.prefix=" + pre + "_long"], pre + "_long.log")
        s = summary(pre + "_long.summary.txt")
        th = list(csv.DictReader(open(pre + "_long.thermo.csv")))
        n = int(s["molecules"])
        t = [float(r["time"]) for r in th]
        e = [float(r["conserved"]) for r in th]
        d = slope(t, e) / n * sc["per_ns"]
        nb = 10
        m = len(t) // nb
        blocks = [slope(t[k * m:(k + 1) * m], e[k * m:(k + 1) * m]) / n * sc["per_ns"] for k in range(nb)]
        mb = sum(blocks) / nb
        se = (sum((x - mb) ** 2 for x in blocks) / (nb - 1) / nb) ** 0.5
        # the scan's drift for the same deck and step, 10^4 steps from the same start
        sh([rl, "scan", sc["deck"], *nve, "--timesteps", sc["h"], "--steps", "10000", "--no-plot",
            "--set", "output.prefix=" + pre + "_scan"], pre + "_scan.log")
        scan = list(csv.DictReader(open(pre + "_scan.scan.csv")))[0]
        dk = [k for k in scan if k.startswith("drift_per_molecule")][0]
        rows.append(dict(scene=name, steps=s["steps"].split()[0], h=sc["h"], status=s["status"],
                         rigidity_error=s["rigidity_error"].split()[0], calE=s["calE"],
                         drift=d, drift_blocks_se=se, scan_drift=float(scan[dk]), scan_calE=scan["calE"],
                         unit=sc["unit"], wall_s=round(time.time() - t0)))
        print(rows[-1], flush=True)
    path = os.path.join(a.out, "long_runs.csv")
    if os.path.exists(path):  # keep the rows of scenes not rerun
        rows = [r for r in csv.DictReader(open(path)) if r["scene"] not in a.scenes.split(",")] + rows
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print("\n| scene | steps | h | status | rigidity error | calE | drift (long run) | ± (10 blocks) | drift (scan, 1e4 steps) | unit | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print("| %s | %s | %s | %s | %s | %s | %.3g | %.2g | %.3g | %s | %s |" % tuple(r[k] if i < 6 or i > 8 else float(r[k]) for i, k in enumerate(
            ("scene", "steps", "h", "status", "rigidity_error", "calE", "drift", "drift_blocks_se", "scan_drift", "unit", "wall_s"))))


if __name__ == "__main__":
    main()
