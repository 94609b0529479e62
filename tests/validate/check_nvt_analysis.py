#!/usr/bin/python3
"""CTest: the analysis of validate/nvt_structure.py (part 3) against rotleap's own estimators.

    /usr/bin/python3 tests/validate/check_nvt_analysis.py ROTLEAP SOURCE_DIR WORK_DIR

Part 3 computes the MSD and the dipole-axis P1/P2 of both codes from their trajectories as read by
MDTraj (float32 DCD, Angstrom), with its own numpy code.  Here a short rotleap NVT run (128 TIP4P
from a lattice, 240 steps at 2 fs, a frame and a sample every 4 steps) is analysed both ways:
rotleap's PREFIX.tcf.csv (double-precision centres and molecular dipoles, origins every sample,
lags up to half the samples) against nvt_structure.msd_fft / acf_fft on the DCD + PDB.  They must
agree to float32 round-off (relative 1e-4 on the MSD, 1e-5 absolute on P1 and P2): this checks
the frame-to-sample alignment, that the DCD is unwrapped, that the bisector O -> (H1+H2)/2 is the
dipole axis, and the FFT estimators against rotleap's direct sums.  Also checks msd_fft and acf_fft
against brute force on random data, tau_of on a biexponential, and peak() on a parabola.
Needs numpy and MDTraj (Debian python3-mdtraj); exits 77 (CTest SKIP) without them.  About 2 s of CPU.
"""
import csv
import math
import os
import subprocess
import sys

try:
    import numpy as np
    import mdtraj as md
except ImportError as e:
    print("skip: %s (install python3-numpy python3-mdtraj)" % e)
    sys.exit(77)

failed = 0


def check(name, ok, detail=""):
    global failed
    print("check %-62s %s %s" % (name, detail, "ok" if ok else "FAIL"))
    failed += 0 if ok else 1


def main():
    rotleap, src, work = sys.argv[1:4]
    sys.dont_write_bytecode = True
    sys.path.insert(0, os.path.join(src, "validate"))
    import nvt_structure as ns
    os.makedirs(work, exist_ok=True)
    # the estimators on synthetic data
    rng = np.random.default_rng(5)
    x = np.cumsum(rng.normal(size=(60, 7, 3)), axis=0)
    brute = np.array([np.mean(np.sum((x[m:] - x[:len(x) - m]) ** 2, -1), 0) for m in range(60)])
    check("msd_fft = brute force (random walks)", np.allclose(ns.msd_fft(x), brute, rtol=1e-10, atol=1e-9),
          "%.1e" % np.abs(ns.msd_fft(x) - brute).max())
    y = rng.normal(size=(50, 4))
    brute = np.array([np.mean(y[m:] * y[:len(y) - m], 0) for m in range(50)])
    check("acf_fft = brute force", np.allclose(ns.acf_fft(y), brute, atol=1e-12))
    t = np.arange(200) * 0.04
    tau = ns.tau_of(t, 0.9 * np.exp(-t / 3.0) + 0.1 * np.exp(-t / 0.05), (1.0, 4.0))
    exact = 0.9 * 3.0 + 0.1 * 0.05
    check("tau_of of a biexponential (trapezoid head + fitted tail)", abs(tau - exact) < 2e-3 * exact,
          "%.5f vs %.5f" % (tau, exact))
    r = np.arange(0, 1, 0.005)
    h, pos = ns.peak(r, 3.0 - 400.0 * (r - 0.2771) ** 2, (0.24, 0.34))
    check("peak() of a parabola", abs(h - 3.0) < 1e-9 and abs(pos - 0.2771) < 1e-9, "%.6f %.6f" % (h, pos))
    # rotleap's own estimators against the script's, on one rotleap trajectory
    pre = os.path.join(work, "nvt_analysis")
    with open(pre + ".ini", "w") as f:
        f.write("\n".join(["[system]", "model = tip4p", "count = 128", "density = 1 g/cm3", "seed = 3",
                           "[interactions]", "cutoff = 0.75 nm", "scheme = site",
                           "[run]", "steps = 240", "timestep = 2 fs", "ensemble = nvt-bussi", "temperature = 298 K",
                           "tau = 0.5 ps", "equilibrate = 200", "equilibrate_timestep = 0.5 fs",
                           "[output]", "prefix = %s" % pre, "progress = no", "trajectory_every = 4",
                           "sample_every = 4", "thermo_every = 4", "discard = 0", ""]))
    p = subprocess.run([rotleap, "run", pre + ".ini"], capture_output=True, text=True)
    if p.returncode:
        print(p.stdout + p.stderr)
        sys.exit(1)
    with open(pre + ".tcf.csv") as f:
        rows = list(csv.DictReader(f))
    own = {k: np.array([float(r[k]) for r in rows]) for k in ("lag_time_ps", "dipole_P1", "dipole_P2", "msd_nm2")}
    traj = md.load(pre + ".dcd", top=pre + ".pdb")
    check("frames = samples (60)", traj.n_frames == 60, str(traj.n_frames))
    xyz = traj.xyz.astype(np.float64)
    O, H1, H2 = xyz[:, 0::4], xyz[:, 1::4], xyz[:, 2::4]
    com = (ns.M_O * O + ns.M_H * (H1 + H2)) / (ns.M_O + 2 * ns.M_H)
    u = 0.5 * (H1 + H2) - O
    u /= np.linalg.norm(u, axis=-1, keepdims=True)
    L = len(own["msd_nm2"])
    msd = ns.msd_fft(com).mean(1)[:L]
    p1 = ns.acf_fft(u).sum(-1).mean(1)[:L]
    c2 = sum(wt * ns.acf_fft(u[..., i] * u[..., j]).mean(1)[:L]
             for (i, j, wt) in ((0, 0, 1), (1, 1, 1), (2, 2, 1), (0, 1, 2), (0, 2, 2), (1, 2, 2)))
    p2 = 1.5 * c2 - 0.5
    rel = float(np.max(np.abs(msd[1:] - own["msd_nm2"][1:]) / own["msd_nm2"][1:]))
    check("MSD: script (MDTraj frames) vs rotleap tcf.csv, relative", rel < 1e-4, "%.1e" % rel)
    d1, d2 = float(np.abs(p1 - own["dipole_P1"]).max()), float(np.abs(p2 - own["dipole_P2"]).max())
    check("P1: bisector axis vs rotleap's molecular dipole", d1 < 1e-5, "%.1e" % d1)
    check("P2", d2 < 1e-5, "%.1e" % d2)
    check("MSD grows beyond the ballistic regime (the run moved)", own["msd_nm2"][-1] > 1e-3, "%.2e nm^2" % own["msd_nm2"][-1])
    print("%d checks failed" % failed if failed else "all checks passed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
