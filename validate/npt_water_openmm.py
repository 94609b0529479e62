#!/usr/bin/python3
"""Issue 34, acceptance 2: the density of rigid water at 298 K and 1 bar, rotleap against OpenMM 7.7.

Models: TIP4P/2005 and TIP4P-Ew (--models), --count molecules (512).  Both codes: smooth PME at
ewaldErrorTolerance --tolerance (5e-4; rotleap's coulomb = pme with ewald_tolerance derives
OpenMM's alpha and mesh, validate/ewald_openmm.py), cutoff --cutoff (0.9 nm), plain LJ with the
long-range dispersion correction (energy and pressure), every intramolecular pair excluded, 298 K,
Langevin friction 1/ps (rotleap run.ensemble = nvt-langevin, tau 1 ps; OpenMM
LangevinMiddleIntegrator), Monte Carlo barostat at 1 bar with a trial every 25 steps (rotleap
run.barostat = mc, barostat_interval 25; OpenMM MonteCarloBarostat(1 bar, 298 K, 25)).  OpenMM
holds the water rigid with SETTLE (M a virtual site); rotleap integrates rigid bodies.

One start per model: rotleap's lattice at 0.997 g/cm^3 relaxed by run.equilibrate (2 ps at 1 fs)
and 10 ps of Bussi NVT at 2 fs.  From it: rotleap NPT at h = --rotleap-fs (2 and 5 fs: the time
step's effect on the density), OpenMM NPT at 2 fs (positions r + A^T d from the checkpoint,
velocities drawn at 298 K), each --eq-ps discarded + --ns of production, the density every
--every-ps.

Statistics: <rho> with the error of --blocks block means.  Criterion (fixed before the runs):
rotleap's <rho> at 2 fs within 2 combined errors of OpenMM's, per model.  The 5 fs runs are
reported with z against rotleap's 2 fs (the time step's effect), not judged.  Published
densities at 298 K and 1 bar, for comparison (not a criterion: other cutoffs and run lengths):
TIP4P/2005 0.9979 g/cm^3 (Abascal & Vega, J. Chem. Phys. 123, 234505 (2005)); TIP4P-Ew 0.995 g/cm^3
(Horn et al., J. Chem. Phys. 120, 9665 (2004)); experiment 0.997 g/cm^3.

    /usr/bin/python3 validate/npt_water_openmm.py [--rotleap build/rotleap] [--models tip4p-2005,tip4p-ew]
        [--ns 1] [--eq-ps 100] [--rotleap-fs 2,5] [--jobs 2] [--md validate/npt_water_openmm.md] [--work DIR]
A finished run's densities are kept in DIR (--work), and an unfinished run keeps a checkpoint there every 10 ps
(rotleap's PREFIX.chk, OpenMM's createCheckpoint), so that the same command with the same --work after an
interruption repeats no finished run and continues an unfinished one from its last checkpoint (its "run (s)"
is then the continuation's wall time only).
Run time at the defaults: about 3.5 CPU hours (512 TIP4P with PME: about 3 ms per step for rotleap and 7 ms
for OpenMM's CPU platform on one core of this AMD EPYC, 500,000 steps per nanosecond at 2 fs), under two hours
with --jobs 2 on two otherwise idle cores:
start it on an otherwise idle machine and leave it.  --ns 0.01 --eq-ps 2 is a smoke test
(minutes; its errors mean nothing).
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True
import rlcheckpoint  # noqa: E402
from mdtable import blocks, write_md  # noqa: E402

T_K, P_BAR, INTERVAL = 298.0, 1.0, 25
M_WATER = 15.9994 + 2 * 1.008  # amu
AMU_NM3_TO_G_CM3 = 1.66053907e-3  # 1 amu = 1.66053907e-24 g, 1 nm^3 = 1e-21 cm^3
PUBLISHED = {"tip4p-2005": (0.9979, "Abascal & Vega 2005"), "tip4p-ew": (0.995, "Horn et al. 2004")}

DECK = """[system]
model = {model}
count = {count}
{where}
temperature = 298 K
[interactions]
cutoff = {cutoff!r} nm
lj = plain
dispersion_correction = yes
coulomb = pme
ewald_tolerance = {tol!r}
[run]
temperature = 298 K
{run}
[output]
thermo_every = {every}
sample_every = 0
progress = no
checkpoint_every = {chk}
"""


def density(n, V):
    """g/cm^3 of n waters in V nm^3."""
    return n * M_WATER * AMU_NM3_TO_G_CM3 / V


def tau_int(x, dt):
    """The integrated autocorrelation time of the series x sampled every dt (the sum of its
    normalised autocorrelation up to where it first falls below 0.05): the blocks of 1 ns / --blocks
    must be much longer for their means to be independent."""
    x = [v - sum(x) / len(x) for v in x]
    n, var = len(x), sum(v * v for v in x) / len(x)
    tau = 0.5
    for k in range(1, n // 2):
        c = sum(x[i] * x[i + k] for i in range(n - k)) / ((n - k) * var)
        if c < 0.05:
            break
        tau += c
    return tau * dt


def sh(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode:
        raise RuntimeError((p.stderr.strip().splitlines() or ["exit %d" % p.returncode])[-1])
    return p.stdout


def make_start(args, work, model):
    pre = os.path.join(work, "start_" + model)
    if not os.path.exists(pre + ".chk"):
        with open(pre + ".ini", "w") as f:
            f.write(DECK.format(model=model, count=args.count, where="density = 0.997 g/cm3\norientations = random\nseed = 34",
                                cutoff=args.cutoff, tol=args.tolerance, every=100, chk=0,
                                run="ensemble = nvt-bussi\ntau = 0.1 ps\ntimestep = 2 fs\nsteps = 5000\n"
                                    "equilibrate = 2000\nequilibrate_timestep = 1 fs"))
        sh([args.rotleap, "run", pre + ".ini", "--set", "output.prefix=" + pre])
    return pre + ".chk"


def rotleap_npt(args, work, model, start, h):
    pre = os.path.join(work, "rl_%s_h%g" % (model, h))
    every = max(1, int(round(args.every_ps * 1e3 / h)))
    eq = int(round(args.eq_ps * 1e3 / h))
    steps = eq + int(round(args.ns * 1e6 / h))
    box = " ".join(repr(x) for x in rlcheckpoint.read(start)["box"])  # the deck needs it beside the start
    deck = DECK.format(model=model, count=args.count, where="start = %s\nbox = %s nm" % (start, box),
                       cutoff=args.cutoff, tol=args.tolerance, every=every,
                       chk=max(1, int(round(args.checkpoint_ps * 1e3 / h))),
                       run="ensemble = nvt-langevin\ntau = 1 ps\ntimestep = %g fs\nsteps = %d\nbarostat = mc\n"
                           "pressure = 1 bar\nbarostat_interval = %d\nseed = 5" % (h, steps, INTERVAL))
    cmd = [args.rotleap, "run", pre + ".ini", "--set", "output.prefix=" + pre]
    try:  # the same deck and a checkpoint of it: a run interrupted (killed, rebooted) continues from there
        same = open(pre + ".ini").read() == deck and os.path.exists(pre + ".chk")
    except OSError:
        same = False
    if same:
        cmd += ["--set", "system.start=" + pre + ".chk"]
    else:
        with open(pre + ".ini", "w") as f:
            f.write(deck)
    t0 = time.time()
    sh(cmd)
    rows = [r for r in csv.DictReader(open(pre + ".thermo.csv")) if int(r["step"]) >= eq]
    return dict(code="rotleap", model=model, h=h, rho=[float(r["density"]) for r in rows], wall=time.time() - t0)


def openmm_worker(argv):
    """A subprocess (its own thread pool): OpenMM NPT from the start; prints JSON.  Every
    checkpoint_ps it keeps an OpenMM checkpoint and the densities so far in RESUME, from
    which the same settings continue after an interruption."""
    model, start, count, cutoff, tol, h, eq_ps, ns, every_ps, checkpoint_ps, resume = argv
    count, cutoff, tol, h, eq_ps, ns, every_ps = int(count), float(cutoff), float(tol), float(h), float(eq_ps), \
        float(ns), float(every_ps)
    import base64
    import watermodels
    mm = watermodels.mm
    try:
        from openmm import unit
    except ImportError:  # OpenMM < 7.6 layout
        from simtk import unit
    ck = rlcheckpoint.read(start)
    system = watermodels.build_system(model, count, ck["box"], cutoff, None, rigid=True, pme_tolerance=tol,
                                      dispersion_correction=True)
    system.addForce(mm.MonteCarloBarostat(P_BAR, T_K, INTERVAL))
    integ = mm.LangevinMiddleIntegrator(T_K, 1.0, h * 1e-3)
    integ.setRandomNumberSeed(5)
    ctx = mm.Context(system, integ, mm.Platform.getPlatformByName("CPU"), {"Threads": "1"})
    every = max(1, int(round(every_ps * 1e3 / h)))
    rho = None
    try:
        with open(resume) as f:
            kept = json.load(f)
        if kept["argv"] == argv[:-1]:
            ctx.loadCheckpoint(base64.b64decode(kept["checkpoint"]))
            rho = kept["rho"]
    except (OSError, ValueError, KeyError):
        pass
    if rho is None:
        ctx.setPositions([mm.Vec3(*x) for x in rlcheckpoint.site_positions(ck)])
        ctx.computeVirtualSites()
        ctx.setVelocitiesToTemperature(T_K, 5)
        integ.step(int(round(eq_ps * 1e3 / h)))
        rho = []
    keep = max(1, int(round(float(checkpoint_ps) / every_ps)))
    while len(rho) < int(round(ns * 1e6 / h)) // every:
        integ.step(every)
        V = ctx.getState().getPeriodicBoxVolume().value_in_unit(unit.nanometer ** 3)
        rho.append(density(count, V))
        if len(rho) % keep == 0:
            with open(resume + ".tmp", "w") as f:
                json.dump(dict(argv=argv[:-1], rho=rho,
                               checkpoint=base64.b64encode(ctx.createCheckpoint()).decode()), f)
            os.replace(resume + ".tmp", resume)
    print(json.dumps(rho))


def openmm_npt(args, work, model, start, h):
    t0 = time.time()
    out = sh(["/usr/bin/python3", os.path.abspath(__file__), "--openmm-worker", model, start, str(args.count),
              repr(args.cutoff), repr(args.tolerance), repr(h), repr(args.eq_ps), repr(args.ns), repr(args.every_ps),
              repr(args.checkpoint_ps), os.path.join(work, "openmm_%s_h%g.resume.json" % (model, h))])
    return dict(code="openmm", model=model, h=h, rho=json.loads(out), wall=time.time() - t0)


def cached(fn, args, work, model, start, h):
    """fn's result, kept in work/<code>_<model>_h<h>.json once a run has finished, so that a run of
    hours interrupted (a reboot, a kill) and started again with the same --work and settings repeats only
    the runs that had not finished. The settings are part of the file: other settings run again."""
    key = dict(count=args.count, cutoff=args.cutoff, tolerance=args.tolerance, ns=args.ns, eq_ps=args.eq_ps,
               every_ps=args.every_ps)
    path = os.path.join(work, "%s_%s_h%g.json" % (fn.__name__, model, h))
    try:
        with open(path) as f:
            old = json.load(f)
        if old.get("settings") == key:
            return old["result"]
    except (OSError, ValueError):
        pass
    res = fn(args, work, model, start, h)
    with open(path + ".tmp", "w") as f:
        json.dump(dict(settings=key, result=res), f)
    os.replace(path + ".tmp", path)
    return res


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--openmm-worker":
        return openmm_worker(sys.argv[2:])
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rotleap", default=os.path.join(ROOT, "build", "rotleap"))
    ap.add_argument("--models", default="tip4p-2005,tip4p-ew")
    ap.add_argument("--count", type=int, default=512)
    ap.add_argument("--cutoff", type=float, default=0.9)
    ap.add_argument("--tolerance", type=float, default=5e-4)
    ap.add_argument("--ns", type=float, default=1.0, help="production per run, ns")
    ap.add_argument("--eq-ps", type=float, default=100.0)
    ap.add_argument("--every-ps", type=float, default=1.0, help="density sampled every this many ps")
    ap.add_argument("--rotleap-fs", default="2,5")
    ap.add_argument("--checkpoint-ps", type=float, default=10.0, help="an unfinished run's checkpoints, every this many ps")
    ap.add_argument("--blocks", type=int, default=10)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--codes", default="openmm,rotleap",
                    help="run only these codes' runs (e.g. two invocations side by side with the same --work)")
    ap.add_argument("--md", default=os.path.join(HERE, "npt_water_openmm.md"))
    ap.add_argument("--work", default=None)
    args = ap.parse_args()
    args.rotleap = os.path.abspath(args.rotleap)
    work = args.work or tempfile.mkdtemp(prefix="npt_water.")
    os.makedirs(work, exist_ok=True)
    models = [m for m in args.models.split(",") if m]
    codes = args.codes.split(",")
    starts = {m: make_start(args, work, m) for m in models}
    tasks = []  # model by model, so that an interrupted run has finished whole models first
    for m in models:
        tasks += [(openmm_npt, m, 2.0)] * ("openmm" in codes) + \
            [(rotleap_npt, m, float(h)) for h in args.rotleap_fs.split(",") if h and "rotleap" in codes]
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as ex:
        futs = [ex.submit(cached, fn, args, work, m, starts[m], h) for fn, m, h in tasks]
        res = []
        for f, (fn, m, h) in zip(futs, tasks):
            try:
                res.append(f.result())
            except RuntimeError as e:
                res.append(dict(code=fn.__name__.split("_")[0], model=m, h=h, error=str(e)))
    for r in res:
        if "rho" in r:
            r["mean"] = blocks(r["rho"], args.blocks)
    L = ["# Water density at 298 K and 1 bar: rotleap against OpenMM 7.7 (Monte Carlo barostat, PME)", "",
         "Generated by `/usr/bin/python3 validate/npt_water_openmm.py %s` on %s (%d runs; run (s) is each run's own "
         "wall time, up to --jobs at a time on a 2-core AMD EPYC shared with other jobs; runs finished earlier in "
         "--work are reused, an interrupted one continued from its checkpoint). Do not edit: rerun the script. Setup "
         "and criterion (fixed before the runs): its docstring." % (" ".join(sys.argv[1:]),
                                                                      time.strftime("%Y-%m-%d %H:%M"), len(tasks)), "",
         "%d molecules, PME at tolerance %g, rc %g nm, LJ dispersion correction, Langevin 1/ps, MC barostat every "
         "%d steps; %g ps discarded + %g ns production; errors from %d block means." % (
             args.count, args.tolerance, args.cutoff, INTERVAL, args.eq_ps, args.ns, args.blocks), "",
         "| model | code | h (fs) | <ρ> (g/cm³) | z | τ_ρ (ps) | published | run (s) |",
         "|---|---|---|---|---|---|---|---|"]
    ok, judged = True, True
    for m in models:
        om = next((r for r in res if r["model"] == m and r["code"] == "openmm"), {})
        rl2 = next((r for r in res if r["model"] == m and r["code"] == "rotleap" and r["h"] == 2.0), {})
        if not ("mean" in om and "mean" in rl2):
            judged = False
        for r in [x for x in res if x["model"] == m]:
            if "error" in r:
                L.append("| %s | %s | %g | failed: %s | | | | |" % (m, r["code"], r["h"], r["error"]))
                ok = False
                continue
            ref = om if r["code"] == "rotleap" and r["h"] == 2.0 else rl2 if r["code"] == "rotleap" else None
            z = ""
            if ref and "mean" in ref:
                z = "%.2f" % ((r["mean"][0] - ref["mean"][0]) / math.hypot(r["mean"][1], ref["mean"][1]))
                if ref is om:
                    ok = ok and abs(float(z)) <= 2
            pub = PUBLISHED.get(m)
            L.append("| %s | %s | %g | %.4f ± %.4f | %s | %.1f | %s | %.0f |" % (
                m, r["code"], r["h"], r["mean"][0], r["mean"][1], z, tau_int(r["rho"], args.every_ps),
                "%g (%s)" % pub if pub else "", r["wall"]))
    L += ["", "τ_ρ: the density's integrated autocorrelation time (the blocks must be much longer). "
          "z: rotleap 2 fs against OpenMM; rotleap at other steps against rotleap 2 fs. rotleap's density at 2 fs "
          "within 2 combined errors of OpenMM's for every model: **%s**." % (
              ("yes" if ok else "no") if judged else "not judged (a model without both runs)")]
    text = "\n".join(L) + "\n"
    write_md(args.md, text)
    print(text)
    return 0 if ok and judged else 1


if __name__ == "__main__":
    sys.exit(main())
