#!/usr/bin/python3
"""TIP4P-Ew with smooth PME: rotleap against OpenMM 7.7's CPU platform, alternately, in one session
(issue 33, acceptance 6, first part).

    /usr/bin/python3 bench/pme_vs_openmm.py [--sizes 2048,16384] [--threads 1,2] [--rounds 3]
                                            [--tolerance 5e-4] [--old] [--ffbench build/bench/ffbench]

As bench/openmm_tip4p.py does for the reaction field (its start, timing and pinning are reused):
`ffbench time tip4p-ew N T STEPS --pme TOL --dump FILE` relaxes a lattice (298 K, 1 g/cm3) and
times rotleap's whole MD steps: the pair term with LJ and the Ewald real space in one pass (its
TIP4P rows), the term "pme" for the mesh (alpha and grid from the tolerance as OpenMM chooses
them, order 5), the integrator.  OpenMM gets the same sites and box: TIP4P-Ew
(validate/watermodels.build_system, rigid by SETTLE, intramolecular pairs excluded), its
NonbondedForce switched to PME with cutoff 0.9 nm and ewaldErrorTolerance TOL, plain LJ, no
dispersion correction, a VerletIntegrator at 2 fs, CPU platform property Threads = T.  Rounds
alternate rotleap (a fresh ffbench run) and OpenMM, the best of each kept.  recip% is the share of
rotleap's step spent in the PME term (mesh, FFTs, forces from the mesh).  --old adds one run of
rotleap with the real space as the separate term "ewald-real" (the path before the rows had it).
Prints a table and writes bench/pme_vs_openmm.csv.
"""
import argparse
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import openmm_tip4p as rf  # noqa: E402  (start, dump reader, OpenMM timing, steps per size)
from rlfiles import cpu_model, pin_row, tokens  # noqa: E402

mm = rf.mm


def rotleap_run(ffbench, n, threads, steps, tol, dump=None, old=False):
    cmd = [ffbench, "time", "tip4p-ew", str(n), str(threads), str(steps), "--energy-every", str(steps),
           "--pme", repr(tol)]
    if n >= 16384:
        cmd += ["--relax", "20"]
    if dump:
        cmd += ["--dump", dump]
    if old:
        cmd += ["--real-term"]
    return tokens(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)


def openmm_context(n, L, pos, threads, tol):
    system = rf.watermodels.build_system("tip4p-ew", n, (L, L, L), 0.9, 78.3, rigid=True, pme_tolerance=tol)
    nb = [f for f in system.getForces() if isinstance(f, mm.NonbondedForce)][0]
    integ = mm.VerletIntegrator(0.002)
    ctx = mm.Context(system, integ, mm.Platform.getPlatformByName("CPU"), {"Threads": str(threads)})
    ctx.setPositions(pos)
    ctx.applyConstraints(1e-8)
    ctx.setVelocitiesToTemperature(298.0, 1)
    integ.step(5)  # warm-up (neighbour list, thread pool, FFT plans)
    alpha, nx, ny, nz = nb.getPMEParametersInContext(ctx)
    return ctx, integ, (alpha, nx, ny, nz)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="2048,16384")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--tolerance", type=float, default=5e-4)
    ap.add_argument("--old", action="store_true", help="also time the real space as the separate term")
    ap.add_argument("--ffbench", default=os.path.join(HERE, "..", "build", "bench", "ffbench"))
    ap.add_argument("--csv", default=os.path.join(HERE, "pme_vs_openmm.csv"))
    ap.add_argument("--pin", default="auto")
    a = ap.parse_args()
    allowed = os.sched_getaffinity(0)
    rows = []
    print("TIP4P-Ew, PME, rc 0.9 nm, ewaldErrorTolerance %g, 2 fs: time per step, best of %d alternating rounds"
          % (a.tolerance, a.rounds))
    print("%6s %2s %11s %11s %7s %7s %8s %11s %s" % ("N", "T", "rotleap ms", "OpenMM ms", "ratio", "recip%", "target",
                                                   "rl old ms", "mesh (rotleap / OpenMM)"))
    for n in [int(x) for x in a.sizes.split(",")]:
        for threads in [int(x) for x in a.threads.split(",")]:
            steps = rf.steps_for(n)
            pin = pin_row(threads, a.pin, allowed)
            kv, L, pos = rf.timed_start(lambda dump: rotleap_run(a.ffbench, n, threads, steps, a.tolerance, dump))
            best_rl, share = float(kv["ms_per_step"]), float(kv["recip_share"])
            ctx, integ, pme = openmm_context(n, L, pos, threads, a.tolerance)
            best_omm = float("inf")
            for r in range(a.rounds):
                best_omm = min(best_omm, 1e3 * rf.openmm_time(integ, steps))
                if r + 1 < a.rounds:
                    k2 = rotleap_run(a.ffbench, n, threads, steps, a.tolerance)
                    if float(k2["ms_per_step"]) < best_rl:
                        best_rl, share = float(k2["ms_per_step"]), float(k2["recip_share"])
            del ctx, integ
            old = float(rotleap_run(a.ffbench, n, threads, steps, a.tolerance, old=True)["ms_per_step"]) if a.old else float("nan")
            ratio = best_rl / best_omm
            verdict = "met" if ratio <= 0.7 else "missed x%.2f" % (ratio / 0.7)
            mesh = "%s %.4f / %d^3 %.4f" % (kv["grid"], float(kv["alpha"]), pme[1], pme[0])
            print("%6d %2d %11.3f %11.3f %7.3f %6.1f%% %8s %11.3f %s %s" % (
                n, threads, best_rl, best_omm, ratio, 100 * share, verdict, old, mesh,
                "" if pin is None else "(both on CPU %d)" % pin), flush=True)
            rows.append((n, threads, best_rl, best_omm, ratio, share, old, kv["grid"], float(kv["alpha"]),
                         pme[1], pme[0], "" if pin is None else str(pin), kv.get("rows", "?"), cpu_model()))
    os.sched_setaffinity(0, allowed)
    with open(a.csv, "w") as f:
        f.write("N,threads,rotleap_ms_per_step,openmm_ms_per_step,ratio,rotleap_recip_share,rotleap_old_ms_per_step,"
                "rotleap_grid,rotleap_alpha,openmm_grid,openmm_alpha,pinned_cpu,rotleap_rows,cpu\n")
        for r in rows:
            f.write("%d,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%s,%.6f,%d,%.6f,%s,%s,\"%s\"\n" % r)
    print("written:", a.csv)
    if rows:
        print("rotleap's TIP4P rows: %s; CPU: %s" % (rows[0][12], rows[0][13]))
    print("target: rotleap <= 0.7 x OpenMM CPU time per step (rotleap in double precision, OpenMM CPU "
          "mixed/single)")


if __name__ == "__main__":
    main()
