#!/usr/bin/python3
"""TIP4P with reaction field: rotleap against OpenMM 7.7's CPU platform, alternately, in one session.

    /usr/bin/python3 bench/openmm_tip4p.py [--sizes 256,2048,16384,65536] [--threads 1,2]
                                           [--rounds 3] [--ffbench build/bench/ffbench] [--pin auto]

For each N and thread count: `ffbench time tip4p N T STEPS --dump FILE` relaxes a lattice
(rotleap, 298 K, 1 g/cm3) and writes its sites; OpenMM gets the same sites, box, cutoff 0.9 nm,
eps_rf 78.3, plain LJ, no dispersion correction (validate/watermodels.build_system, rigid
waters by SETTLE), a VerletIntegrator at 2 fs and CPU platform property Threads = T.  Then
rounds alternate: rotleap (a fresh ffbench run; only its timed steps count) and OpenMM (timed
steps after a warm-up), keeping the best of each.  Prints a table, writes bench/openmm_tip4p.csv.
Both are whole MD steps: forces plus integration (and constraints for OpenMM).  Neither code
computes energies on the timed steps: OpenMM's integrator.step() computes forces only, and
rotleap runs with --energy-every STEPS (output.energy_every), energy and virial at the start and
the end only (before 2026-11-22 rotleap summed both on every step, about 10 % of its step).

With one thread both codes run pinned to one CPU (--pin: auto = the idlest CPU when the row
starts, a CPU number, or none), as in bench/sampling_speed.py: OpenMM's CPU platform hands each
step from the Python thread to a worker thread even with Threads = 1, and on this 2-vCPU KVM guest
the two threads, left unpinned, often sit on different vCPUs and wait for each other (256
molecules: 1.80-2.39 ms per step unpinned against 1.21-1.23 pinned in sampling_speed's runs).
Before 2026-11-21 this benchmark did not pin, which flattered rotleap at small N.  Rows with two
threads run unpinned.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "validate"))
import watermodels  # noqa: E402

sys.path.insert(0, HERE)
from rlfiles import cpu_model, pin_row, tokens  # noqa: E402

mm = watermodels.mm
try:
    from openmm import unit
except ImportError:
    from simtk import unit


def steps_for(n):
    # at least 30 timed steps: two periods of rotleap's list rebuilds (about 15 steps at 2 fs,
    # bench/skin_tip4p.csv) and of OpenMM's, so that a window with no rebuild (6 steps at
    # 65,536 before) does not flatter either code
    return max(30, min(200, 400000 // n))


def rotleap_run(ffbench, n, threads, steps, dump=None):
    cmd = [ffbench, "time", "tip4p", str(n), str(threads), str(steps), "--energy-every", str(steps)]
    if dump:
        cmd += ["--dump", dump]
    return tokens(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)


def read_dump(path):
    with open(path) as f:
        head = f.readline().split()
        n, ns, L = int(head[1]), int(head[2]), float(head[3])
        pos = []
        for _ in range(n):
            x = [float(v) for v in f.readline().split()]
            s = x[12:]
            pos += [mm.Vec3(s[3 * a], s[3 * a + 1], s[3 * a + 2]) for a in range(ns)]
    return n, L, pos


def timed_start(run):
    """run(dump) times rotleap and writes its final state to the file dump; returns ffbench's
    key=value tokens and that state's box edge and site positions, OpenMM's start."""
    with tempfile.TemporaryDirectory() as tmp:
        dump = os.path.join(tmp, "state.txt")
        kv = run(dump)
        _, L, pos = read_dump(dump)
    return kv, L, pos


def openmm_context(n, L, pos, threads):
    system = watermodels.build_system("tip4p", n, (L, L, L), 0.9, 78.3, rigid=True)
    integ = mm.VerletIntegrator(0.002)
    plat = mm.Platform.getPlatformByName("CPU")
    ctx = mm.Context(system, integ, plat, {"Threads": str(threads)})
    ctx.setPositions(pos)
    ctx.applyConstraints(1e-8)
    ctx.setVelocitiesToTemperature(298.0, 1)
    integ.step(5)  # warm-up (neighbour list, thread pool)
    return ctx, integ


def openmm_time(integ, steps):
    t0 = time.perf_counter()
    integ.step(steps)  # the CPU platform returns when the steps are done
    return (time.perf_counter() - t0) / steps


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="256,2048,16384,65536")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--ffbench", default=os.path.join(HERE, "..", "build", "bench", "ffbench"))
    ap.add_argument("--csv", default=os.path.join(HERE, "openmm_tip4p.csv"))
    ap.add_argument("--pin", default="auto", help="CPU for the one-thread rows of both codes: auto (the "
                    "idlest when the row starts), a CPU number, or none")
    a = ap.parse_args()
    allowed = os.sched_getaffinity(0)
    rows = []
    print("TIP4P-RF, rc 0.9 nm, eps_rf 78.3, 2 fs: time per step, best of %d alternating rounds" % a.rounds)
    print("%7s %3s %12s %12s %8s %10s %10s %8s %7s" % ("N", "T", "rotleap ms", "OpenMM ms", "ratio",
                                                       "rl ns/day", "omm ns/day", "target", "ff%"))
    for n in [int(x) for x in a.sizes.split(",")]:
        for threads in [int(x) for x in a.threads.split(",")]:
            steps = steps_for(n)
            # pinned before the context exists: OpenMM's worker threads inherit the affinity,
            # and so do the ffbench processes
            pin = pin_row(threads, a.pin, allowed)
            kv, L, pos = timed_start(lambda dump: rotleap_run(a.ffbench, n, threads, steps, dump))
            best_rl, share, rows_rl = float(kv["ms_per_step"]), float(kv["ff_share"]), kv.get("rows", "?")
            ctx, integ = openmm_context(n, L, pos, threads)
            best_omm = float("inf")
            for r in range(a.rounds):
                best_omm = min(best_omm, 1e3 * openmm_time(integ, steps))
                if r + 1 < a.rounds:
                    kv = rotleap_run(a.ffbench, n, threads, steps)
                    if float(kv["ms_per_step"]) < best_rl:
                        best_rl, share = float(kv["ms_per_step"]), float(kv["ff_share"])
            del ctx, integ
            ratio = best_rl / best_omm
            nsday = lambda ms: 0.002e-3 * 86400.0 / (ms * 1e-3)  # ns per day at 2 fs
            verdict = "met" if ratio <= 0.7 else "missed x%.2f" % (ratio / 0.7)
            print("%7d %3d %12.3f %12.3f %8.3f %10.2f %10.2f %8s %6.1f%% %s" % (
                n, threads, best_rl, best_omm, ratio, nsday(best_rl), nsday(best_omm), verdict,
                100 * share, "" if pin is None else "(both on CPU %d)" % pin), flush=True)
            rows.append((n, threads, best_rl, best_omm, ratio, nsday(best_rl), nsday(best_omm), share,
                         "" if pin is None else str(pin), rows_rl, cpu_model()))
    os.sched_setaffinity(0, allowed)
    with open(a.csv, "w") as f:
        f.write("N,threads,rotleap_ms_per_step,openmm_ms_per_step,ratio,rotleap_ns_per_day,"
                "openmm_ns_per_day,rotleap_ff_share,pinned_cpu,rotleap_rows,cpu\n")
        for r in rows:
            f.write("%d,%d,%.4f,%.4f,%.4f,%.3f,%.3f,%.4f,%s,%s,\"%s\"\n" % r)
    print("written:", a.csv)
    if rows:
        print("rotleap's TIP4P rows: %s (rl_forcefield_rows); CPU: %s" % (rows[0][9], rows[0][10]))
    print("target: rotleap <= 0.7 x OpenMM CPU time per step (rotleap in double precision, OpenMM "
          "CPU mixed/single)")


if __name__ == "__main__":
    main()
