#!/usr/bin/python3
"""Sampling speed at every size and thread count of the TIP4P benchmark (issue 8, benchmark 1).

    /usr/bin/python3 bench/sampling_scale.py [--from bench/sampling_speed.csv | --steps 6,8]
                                             [--sizes 256,2048,16384,65536] [--threads 1,2]
                                             [--rounds 3] [--csv FILE] [--precision double|mixed]

bench/sampling_speed.py finds each code's largest accurate time step for NVT water at 298 K
(rotleap: revised leapfrog + Bussi; OpenMM: LangevinMiddleIntegrator + SETTLE) on 256 molecules,
and times the two chosen runs there, on one thread.  The issue asks for the sampling-speed
comparison in the TIP4P benchmark, which runs N = 256 to 65,536 on one and two threads.  The
largest accurate step is a property of the integrator and the model, not of N (the bias per
molecule does not depend on N; only the statistical error of a run of given length does), so
this script takes the two steps from a sampling_speed CSV (its `chosen` rows) and times each
code at its own step and with its own thermostat at every N and thread count:

  rotleap: `ffbench time tip4p N T STEPS --h H --energy-every STEPS --skin auto` (Bussi, tau = 50 h,
           from a relaxed lattice at 298 K and 1 g/cm3; forces only on the timed steps, energies at
           the ends, as OpenMM's step() computes none; the Verlet skin `rotleap run` takes at H;
           --precision mixed adds --mixed, the TIP4P kernel's terms in single precision);
  OpenMM:  the same sites, box, cutoff 0.9 nm, eps_rf 78.3, plain LJ, rigid waters by SETTLE, a
           CMMotionRemover every 100 steps, LangevinMiddleIntegrator(298 K, friction, H), CPU
           platform with Threads = T, as in sampling_speed.py; 25 fs at 0.5 fs, 1 ps at 2 fs and
           0.4 ps at 4 fs before the warm-up at H, since 8 fs from rotleap's barely relaxed
           lattice blew up in about half the rows.

Rounds alternate the codes and keep each one's best (the machine is shared); one-thread rows pin
both codes to one CPU (openmm_tip4p.py explains why).  ns/day = H / (time per step); the ratio is
rotleap's ns/day over OpenMM's; the target is >= 2.
"""
import argparse
import csv
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "validate"))
import watermodels  # noqa: E402

sys.path.insert(0, HERE)
from rlfiles import cpu_model, pin_row, tokens  # noqa: E402
from openmm_tip4p import timed_start  # noqa: E402

mm = watermodels.mm
T_K = 298.0


def steps_for(n):
    # about 2 s of rotleap per timing run at 256 molecules, at least 30 steps at 65,536 (two
    # periods of either code's list rebuilds, as openmm_tip4p.py)
    return max(30, min(2000, 2000000 // n))


def chosen_steps(path):
    """(rotleap h, OpenMM h) in fs from the chosen rows of a sampling_speed CSV."""
    h = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            if r["chosen"] == "yes":
                h[r["code"]] = float(r["h_fs"])
    if set(h) != {"rotleap", "openmm"}:
        sys.exit("%s: no chosen row for %s" % (path, " and ".join(sorted({"rotleap", "openmm"} - set(h)))))
    return h["rotleap"], h["openmm"]


def rotleap_time(ffbench, n, threads, steps, h_fs, dump=None, precision="double"):
    # 200 relaxation steps of 0.5 fs at every N (ffbench's default of 20 from 16,384 on is enough
    # for 2 fs, but left states with fused waters that blew OpenMM up at 8 fs); the skin that
    # `rotleap run` takes at this step (--skin auto; before 2026-11-26 the library's 0.1 rc)
    cmd = [ffbench, "time", "tip4p", str(n), str(threads), str(steps), "--energy-every", str(steps),
           "--h", repr(h_fs * 1e-3), "--relax", "200", "--skin", "auto"]
    if precision == "mixed":
        cmd.append("--mixed")
    if dump:
        cmd += ["--dump", dump]
    return tokens(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)


def openmm_langevin(n, L, pos, threads, h_fs, friction, seed=1):
    system = watermodels.build_system("tip4p", n, (L, L, L), 0.9, 78.3, rigid=True)
    system.addForce(mm.CMMotionRemover(100))
    integ = mm.LangevinMiddleIntegrator(T_K, friction, h_fs * 1e-3)
    integ.setConstraintTolerance(1e-10)
    ctx = mm.Context(system, integ, mm.Platform.getPlatformByName("CPU"), {"Threads": str(threads)})
    ctx.setPositions(pos)
    ctx.applyConstraints(1e-8)
    integ.setRandomNumberSeed(seed)
    ctx.setVelocitiesToTemperature(T_K, seed)
    # the start is rotleap's lattice after 0.1 ps of relaxation and a few steps at its own h, not
    # yet a liquid (U/N about -39 kJ/mol against -41.6), from which OpenMM at 8 fs blew up in
    # about half the rows: 1 ps at 2 fs and 0.4 ps at 4 fs first (after 25 fs at 0.5 fs), then
    # the warm-up (neighbour list, thread pool) at the production step
    for h, k in ((0.5, 50), (2.0, 500), (4.0, 100), (h_fs, 20)):
        integ.setStepSize(min(h, h_fs) * 1e-3)
        integ.step(k)
    return ctx, integ


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--from", dest="src", default=os.path.join(HERE, "sampling_speed.csv"),
                    help="a sampling_speed.py CSV whose chosen rows give the two time steps")
    ap.add_argument("--steps", help="RL_FS,OPENMM_FS instead of --from")
    ap.add_argument("--sizes", default="256,2048,16384,65536")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--friction", type=float, default=1.0, help="OpenMM Langevin friction (1/ps)")
    ap.add_argument("--ffbench", default=os.path.join(HERE, "..", "build", "bench", "ffbench"))
    ap.add_argument("--csv", default=os.path.join(HERE, "sampling_scale.csv"))
    ap.add_argument("--pin", default="auto", help="CPU for the one-thread rows of both codes: auto, a number, or none")
    ap.add_argument("--precision", choices=("double", "mixed"), default="double",
                    help="rotleap's precision (interactions.precision; ffbench --mixed)")
    a = ap.parse_args()
    if a.steps:
        h_rl, h_omm = (float(x) for x in a.steps.split(","))
        source = "--steps %s" % a.steps
    else:
        h_rl, h_omm = chosen_steps(a.src)
        source = os.path.relpath(a.src, os.path.join(HERE, ".."))
    allowed = os.sched_getaffinity(0)
    t0 = time.time()
    print("Sampling speed, TIP4P-RF (rc 0.9 nm, eps_rf 78.3), 298 K: rotleap Bussi at %g fs (%s precision), "
          "OpenMM LangevinMiddle at %g fs (from %s); best of %d alternating rounds"
          % (h_rl, a.precision, h_omm, source, a.rounds))
    print("%7s %3s %11s %11s %7s %10s %10s %7s %s" % ("N", "T", "rl ms", "omm ms", "t ratio", "rl ns/day",
                                                     "omm ns/day", "ratio", "target >= 2"))
    rows = []
    for n in [int(x) for x in a.sizes.split(",")]:
        for threads in [int(x) for x in a.threads.split(",")]:
            steps = steps_for(n)
            pin = pin_row(threads, a.pin, allowed)
            kv, L, pos = timed_start(lambda dump: rotleap_time(a.ffbench, n, threads, steps, h_rl, dump, a.precision))
            best_rl, rows_rl = float(kv["ms_per_step"]), kv.get("rows", "?")
            # OpenMM at 8 fs is close to its limit (10 fs blows up at once): a run that blows up
            # (in the warm-up or a timed round) starts again from the same positions with new
            # random numbers, and the blow-ups are counted; three end the row
            best_omm, blowups, ctx, r = float("inf"), 0, None, 0
            while r < a.rounds and blowups < 3:
                try:
                    if ctx is None:
                        ctx, integ = openmm_langevin(n, L, pos, threads, h_omm, a.friction, seed=1 + blowups)
                    t = time.perf_counter()
                    integ.step(steps)  # the CPU platform returns when the steps are done
                    best_omm = min(best_omm, 1e3 * (time.perf_counter() - t) / steps)
                except mm.OpenMMException as e:
                    blowups += 1
                    ctx = None
                    print("%7d %3d  OpenMM at %g fs blew up (%s); again with new random numbers"
                          % (n, threads, h_omm, str(e).strip()), flush=True)
                    continue
                r += 1
                if r < a.rounds:
                    best_rl = min(best_rl, float(rotleap_time(a.ffbench, n, threads, steps, h_rl,
                                                              precision=a.precision)["ms_per_step"]))
            ctx = integ = None
            if r < a.rounds:
                print("%7d %3d  OpenMM at %g fs blew up %d times: row not timed" % (n, threads, h_omm, blowups),
                      flush=True)
                continue
            nsday = lambda h, ms: h * 1e-6 * 86400.0 / (ms * 1e-3)
            ns_rl, ns_omm = nsday(h_rl, best_rl), nsday(h_omm, best_omm)
            ratio = ns_rl / ns_omm
            verdict = "met" if ratio >= 2.0 else "missed x%.2f" % (2.0 / ratio)
            print("%7d %3d %11.3f %11.3f %7.3f %10.2f %10.2f %7.3f %s%s%s" % (
                n, threads, best_rl, best_omm, best_rl / best_omm, ns_rl, ns_omm, ratio, verdict,
                "" if pin is None else "  (both on CPU %d)" % pin,
                "  (OpenMM blew up %d time(s))" % blowups if blowups else ""), flush=True)
            rows.append((n, threads, h_rl, h_omm, best_rl, best_omm, best_rl / best_omm, ns_rl, ns_omm, ratio,
                         blowups, "" if pin is None else str(pin), rows_rl, cpu_model()))
    os.sched_setaffinity(0, allowed)
    with open(a.csv + ".part", "w") as f:  # renamed when whole: an earlier CSV is never left half-written
        f.write("N,threads,rotleap_h_fs,openmm_h_fs,rotleap_ms_per_step,openmm_ms_per_step,time_ratio,"
                "rotleap_ns_per_day,openmm_ns_per_day,sampling_ratio,openmm_blowups,pinned_cpu,rotleap_rows,cpu\n")
        for r in rows:
            f.write("%d,%d,%g,%g,%.4f,%.4f,%.4f,%.3f,%.3f,%.4f,%d,%s,%s,\"%s\"\n" % r)
    os.replace(a.csv + ".part", a.csv)
    met = sum(r[9] >= 2.0 for r in rows)
    print("written: %s; target >= 2 met at %d of %d points; rotleap rows %s; CPU %s; %.0f s"
          % (os.path.relpath(a.csv, os.path.join(HERE, "..")), met, len(rows), rows[0][12] if rows else "?",
             cpu_model(), time.time() - t0))


if __name__ == "__main__":
    main()
