#!/usr/bin/python3
"""Today's Langevin thermostat against the Davidchack-Ouldridge-Tretyakov (DOT) scheme over the time
step (issue 37): 256 TIP4P, reaction field (eps_rf = inf, shifted-force LJ, site cutoff 0.9 nm; the
setup of validate/tconf_vs_h.py and validate/REPORT.md part 3), 298 K.

One start (per system.inertia_scale): the lattice relaxed by run.equilibrate (4 ps at 1 fs, Bussi) and 2 ps of nvt-bussi
(tau 0.1 ps) at 1 fs, written as a checkpoint; every run starts from it (a new run from its state,
step 0, as its settings differ).
Runs (--ps of production each, every average over the whole production, configurations sampled
every ~20 fs for the configurational temperature and U):
  reference  nvt-langevin, tau = 1 ps, h = 1 fs (--ref-ps of production)
  langevin   nvt-langevin, tau = 1 ps (OpenMM's LangevinMiddleIntegrator's 1/ps): one friction
  dot        nvt-langevin-dot, tau = 1 ps, tau_rot = --tau-rot (0.05 ps): O in the middle of the drift
  dot-obabo  nvt-langevin-dot-obabo, the same frictions: O in the middle of the kick
  dot@S      dot with system.inertia_scale = S (heavier rotors: the same configurational
             distribution, librations slower by sqrt(S); docs/integrators.md "Heavier rotors")
at h = --hs (2, 6, 8, 10 fs).

The reference and the tolerance were fixed before any run (and are not changed after): a run
samples correctly if |U/N - U/N_ref| <= 2 sqrt(e^2 + e_ref^2) (e: the results file's block error)
and both configurational temperatures are within 2 of their errors of T0 = 298 K.  The table
marks each test and the verdict.

Run (from the repository root, after building rotleap; about 10 minutes of CPU at the defaults):
    /usr/bin/python3 validate/dot_langevin.py [--rotleap build/rotleap] [--ps 30] [--ref-ps 40]
        [--hs 2,6,8,10] [--tau-rot 0.05] [--jobs 2] [--md validate/dot_langevin.md]
Writes the markdown table (and prints it)."""
import argparse
import concurrent.futures
import math
import os
import subprocess
import sys
import tempfile
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tconf_vs_h import SYSTEMS, ROOT, value, fmt  # noqa: E402  (the same TIP4P deck and parsing)
from mdtable import write_md  # noqa: E402

T0 = 298.0
START_LOCK = threading.Lock()
KEYS = ["U_per_molecule", "temperature_translational", "temperature_rotational", "tconf_translational",
        "tconf_rotational"]


def deck(work, sample):
    path = os.path.join(work, "tip4p_s%d.ini" % sample)
    with open(path, "w") as f:
        f.write(SYSTEMS["tip4p"]["deck"].format(thermo=1000, sample=sample))
    return path


def run(args, cmd, prefix):
    t0 = time.time()
    r = subprocess.run([args.rotleap, "run"] + cmd + ["--set", "output.prefix=" + prefix],
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    return r, time.time() - t0


def start_for(args, work, scale=""):
    """The shared start (PREFIX start.chk), or for system.inertia_scale = scale its own, made the same
    way (the lattice relaxed by run.equilibrate and 2 ps of nvt-bussi at 1 fs) with that scale."""
    start = os.path.join(work, "start" + ("@" + scale if scale else ""))
    with START_LOCK:
        if not os.path.exists(start + ".chk"):  # a --work of an earlier call keeps its start
            extra = ["--set", "system.inertia_scale=" + scale] if scale else []
            r, _ = run(args, [deck(work, 20), "--set", "run.ensemble=nvt-bussi", "--set", "run.tau=0.1 ps",
                              "--set", "run.timestep=1 fs", "--set", "run.equilibrate=4000", "--set", "run.steps=2000",
                              "--set", "output.tconf=no"] + extra, start)
            if r.returncode:
                sys.exit("the start failed: " + r.stderr)
    return start + ".chk"


def one(args, work, start, scheme, h):
    sample = max(1, int(round(20.0 / h)))
    ps = args.ref_ps if scheme == "reference" else args.ps
    steps = int(round(ps * 1e3 / h))
    base, _, scale = scheme.partition("@")  # dot@4: with system.inertia_scale = 4
    ens = {"reference": ["nvt-langevin"], "langevin": ["nvt-langevin"],
           "dot": ["nvt-langevin-dot", "run.tau_rot=%g ps" % args.tau_rot],
           "dot-obabo": ["nvt-langevin-dot-obabo", "run.tau_rot=%g ps" % args.tau_rot]}[base]
    if scale:  # its own start: a checkpoint keeps the moments it was written with
        ens = ens + ["system.inertia_scale=%s" % scale]
        start = start_for(args, work, scale)
    cmd = [deck(work, sample), "--set", "system.start=" + start, "--set", "run.ensemble=" + ens[0],
           "--set", "run.tau=1 ps", "--set", "run.timestep=%g fs" % h, "--set", "run.steps=%d" % steps,
           "--set", "run.seed=7"]
    for extra in ens[1:]:
        cmd += ["--set", extra]
    prefix = os.path.join(work, "%s_h%g" % (scheme, h))
    if args.reuse and os.path.exists(prefix + ".results.txt"):  # an earlier call's run, same settings
        r, wall = subprocess.CompletedProcess([], 0), float(value(open(prefix + ".summary.txt").read(), "wall_seconds")[0])
    else:
        r, wall = run(args, cmd, prefix)
    out = {"scheme": scheme, "h": h, "wall": wall, "steps": steps, "samples": steps // sample,
           "reused": bool(args.reuse and not r.args)}
    if r.returncode:
        out["error"] = r.stderr.strip()[-300:]
        return out
    text = open(prefix + ".results.txt").read()
    for key in KEYS:
        out[key] = value(text, key)
    return out


def reused_note(res):
    """--reuse: which runs came from an earlier call (their run time is that call's)."""
    old = [r for r in res if r.get("reused")]
    if not old:
        return ""
    return "; %d of the runs (%s) were an earlier call's in the same --work, with the same settings" % (
        len(old), ", ".join("%s %g fs" % (r["scheme"], r["h"]) for r in old))


def zt(ve):
    v, e = ve
    return (v - T0) / e if v is not None and e else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rotleap", default=os.path.join(ROOT, "build", "rotleap"))
    ap.add_argument("--ps", type=float, default=30.0, help="production per run, ps")
    ap.add_argument("--ref-ps", type=float, default=40.0, help="production of the 1 fs reference, ps")
    ap.add_argument("--hs", default="2,6,8,10", help="time steps, fs")
    ap.add_argument("--schemes", default="langevin,dot,dot-obabo")
    ap.add_argument("--tau-rot", type=float, default=0.05, help="DOT rotational friction time, ps")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--md", default=os.path.join(ROOT, "validate", "dot_langevin.md"))
    ap.add_argument("--work", default=None)
    ap.add_argument("--reuse", action="store_true", help="keep the runs of an earlier call with the same --work "
                    "(their results files), running only the missing ones")
    args = ap.parse_args()
    work = args.work or tempfile.mkdtemp(prefix="dot_langevin.")
    os.makedirs(work, exist_ok=True)
    t0 = time.time()
    start = start_for(args, work)[:-4]
    hs = [float(x) for x in args.hs.split(",") if x]
    jobs = [("reference", 1.0)] + [(s, h) for s in args.schemes.split(",") if s for h in hs]
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as ex:
        res = list(ex.map(lambda sh: one(args, work, start + ".chk", sh[0], sh[1]), jobs))
    total = time.time() - t0
    cpu = sum(r["wall"] for r in res)
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    ref = res[0]
    uref, eref = ref.get("U_per_molecule", (None, None))
    lines = ["# Langevin against Davidchack-Ouldridge-Tretyakov over the time step (256 TIP4P-RF, 298 K)", "",
             "Generated by `/usr/bin/python3 validate/dot_langevin.py %s` on %s at rotleap %s in %.0f s "
             "(%d runs, %d at a time, summed run time %.0f s, on this 2-core machine shared with other jobs%s). "
             "Do not edit: rerun the script. Method, reference and tolerance (fixed before the runs): its "
             "docstring; the schemes: docs/integrators.md, \"The Davidchack-Ouldridge-Tretyakov Langevin "
             "thermostat\"." % (" ".join(sys.argv[1:]), time.strftime("%Y-%m-%d %H:%M"), commit, total, len(jobs),
                                args.jobs, cpu, reused_note(res)), "",
             "%g ps of production per run (reference: %g ps at 1 fs, nvt-langevin tau = 1 ps); DOT: tau = 1 ps, "
             "tau_rot = %g ps. Temperatures in K (on-step: eqs. 9 and 12), U/N in kJ/mol with block errors; "
             "z_U = (U/N - U/N_ref) / sqrt(e^2 + e_ref^2); z = (T_conf - T0) / error. Pass: |z_U| <= 2 and both "
             "|z| <= 2." % (args.ps, args.ref_ps, args.tau_rot), "",
             "| scheme | h (fs) | U/N | z_U | T_trans | T_rot | T_conf trans | z | T_conf rot | z | samples | "
             "run (s) | samples correctly |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in res:
        if "error" in r:
            lines.append("| %s | %g | failed: %s |" % (r["scheme"], r["h"], r["error"].replace("\n", " ")))
            continue
        u, e = r["U_per_molecule"]
        if r is ref:
            zu, verdict = float("nan"), "reference"
        else:
            zu = (u - uref) / math.hypot(e, eref)
            ok = abs(zu) <= 2 and abs(zt(r["tconf_translational"])) <= 2 and abs(zt(r["tconf_rotational"])) <= 2
            verdict = "yes" if ok else "no"
        lines.append("| %s | %g | %s | %s | %s | %s | %s | %.1f | %s | %.1f | %d | %.0f | %s |" % (
            r["scheme"], r["h"], fmt(r["U_per_molecule"], 3), "" if math.isnan(zu) else "%.1f" % zu,
            fmt(r["temperature_translational"], 1), fmt(r["temperature_rotational"], 1),
            fmt(r["tconf_translational"], 1), zt(r["tconf_translational"]), fmt(r["tconf_rotational"], 1),
            zt(r["tconf_rotational"]), r["samples"], r["wall"], verdict))
    text = "\n".join(lines) + "\n"
    write_md(args.md, text)  # the hand-written reading below the table is kept
    print(text)


if __name__ == "__main__":
    main()
