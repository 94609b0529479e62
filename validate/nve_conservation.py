#!/usr/bin/python3
"""Energy conservation over 10,000 NVE steps at h = 1..6 fs (issue 6, part 2; the paper's Fig. 1).

Run (from the repository root, after building rotleap):
    /usr/bin/python3 validate/nve_conservation.py [--rotleap build/rotleap] [--quick] [--no-write]
About 10 minutes on 2 cores (12 rotleap runs of 10,000 steps at ~8 ms/step, two at a time, plus
six OpenMM CPU runs at ~2 ms/step); --quick (1,000 steps, shorter equilibration) about 1.5 min.

System (as the paper's section IV as far as it is specified): 256 TIP4P, 1 g/cm3 (cubic box
1.9711 nm), 298 K, site-based reaction field: each site pair cut at its own minimum-image
distance rc = 0.9 nm (the largest round value below half the box, 0.9856 nm), eps_rf = 78.3
(our choice: the paper's text names "interaction site reaction field geometry [33]" but gives
neither the cutoff nor eps_rf), plain LJ cut at rc, no dispersion correction.  Exactly the
system of validate/single_point.py's liquid (which agrees with OpenMM to 1e-13), with 256
molecules.

One shared start with thermal velocities:
  1. rotleap equilibrates: lattice with random orientations, relaxed 1000 steps at 0.5 fs, then
     Bussi NVT at 298 K, tau 0.1 ps, h_eq = 2 fs, for 5 ps (2500 steps; --quick: 1 ps).  Its
     checkpoint holds r(t), A(t) and the MID-STEP v(t - h_eq/2), l(t - h_eq/2) (l: lab-frame
     angular momentum, docs/files.md).
  2. `rotleap energy --json` gives the molecular forces F(t) and lab torques K(t).  The on-step
     state is v(t) = v(t - h_eq/2) + (h_eq/2) F/M, l(t) = l(t - h_eq/2) + (h_eq/2) K: exactly the
     half kick rotleap itself uses for its on-step kinetic energy (integrators/leapfrog.c).
  3. For a run at step h: v(t - h/2) = v(t) - (h/2) F/M, l(t - h/2) = l(t) - (h/2) K, written
     into the 0-step checkpoint of an NVE run at that h (same species table and box).  rotleap's
     first on-step kinetic energy is then v(t), l(t) again to round-off: every rotleap run starts
     from the same phase point (E(0) equal across h and both variants to ~1e-9 relative).
  4. OpenMM (VerletIntegrator, a leapfrog whose velocities are at t - h/2; O-H, O-H, H-H
     constraints = SETTLE; M a virtual site) gets the site positions r + A^T d and the rigid-body
     velocity field v_a = v(t - h/2) + w x (r_a(t) - R), w = I_lab(t)^-1 l(t - h/2),
     I_lab = A^T diag(J) A.  This field satisfies the constraints exactly.  It is the mid-step
     velocity evaluated with the on-step orientation A(t) instead of a mid-step one, an O(h)
     difference in the direction of each atom's velocity that leaves |v_a| and the kinetic energy
     unchanged to O(h^2) (the extra term is centripetal, along r_a - R, and SETTLE removes it
     from the first position update).  OpenMM's step-0 total energy is printed beside rotleap's
     as the evidence: the two starts agree to a small fraction of the energy fluctuation.
  OpenMM runs on the CPU platform (one thread each; nonbonded forces in single precision,
  integration in double), because the Reference platform needs ~20x longer.

calE = sd(E)/|<E>| and calU = sd(U)/|<U>| are computed from samples every --sample steps (10)
of steps 0 .. steps-1 for all three schemes (the same estimator); rotleap's own every-step calE
(its summary) is recorded beside it as a check.  Drift: least-squares slope of E(t), in kJ/mol
per ns (whole system and per molecule) and relative to |<E>|.  A run that blows up (rotleap
stops with its error; OpenMM: non-finite energy, an exception, or a jump of more than 10 kT per
molecule between samples, rotleap's own criterion) is recorded as such, with the step.

With --coulomb pme (issue 33, acceptance 4) the system is 256 TIP4P-Ew with smooth PME instead:
alpha, grid and order 5 from the error tolerance --ewald-tolerance (5e-4, OpenMM's default) in
both codes (they derive the same ones: validate/ewald_openmm.py), tin-foil boundary, the same
0.9 nm cutoff, plain LJ and no dispersion correction; OpenMM's NonbondedForce PME (CPU platform:
its PME in single precision).  rotleap takes the mesh's net force off (the run does: the
leapfrog keeps the total momentum at zero), OpenMM does not; both are the usual practice.

Writes (unless --no-write) validate/data/nve_conservation.json (everything the report needs) and
validate/data/nve_conservation.csv (E, U and the running calE every 50 steps of every run).
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True
sys.path.insert(0, HERE)
import rlcheckpoint  # noqa: E402

ROOT = os.path.dirname(HERE)
DATA = os.path.join(HERE, "data")
N = 256
CUTOFF, EPS_RF = 0.9, 78.3
LJ = "plain"
MODEL = "tip4p"
DENSITY = 1.0          # g/cm3 (nvt_structure.py --coulomb pme sets 0.995)
COULOMB = "rf"         # or "pme" (--coulomb)
EWALD_TOL = 5e-4       # --ewald-tolerance, with --coulomb pme
T_K = 298.0
KB = 0.00831446261815324  # kJ/mol/K (exact, SI 2019)
H_EQ = 0.002  # ps
PAPER_CALE = {1: 0.0016, 2: 0.0066, 3: 0.017, 4: 0.030, 5: 0.051, 6: 0.11}  # per cent
PAPER_CALU = 0.56  # per cent
SCHEMES = ("rl", "rl-quaternion", "openmm")


def deck(prefix, steps, h, integrator="rl", start=None, box=None, equilibrate=None, seed=2026):
    sysl = ["[system]", "model = %s" % MODEL, "count = %d" % N]
    if box:
        sysl.append("box = %s" % " ".join(repr(b) for b in box))
    else:
        sysl.append("density = %g g/cm3" % DENSITY)
    sysl += ["start = %s" % start] if start else ["orientations = random", "seed = %d" % seed]
    sysl.append("temperature = %g K" % T_K)
    run = ["[run]", "steps = %d" % steps, "timestep = %r ps" % h, "integrator = %s" % integrator]
    if equilibrate:
        run += ["ensemble = nvt-bussi", "temperature = %g K" % T_K, "tau = 0.1 ps",
                "equilibrate = %d" % equilibrate, "equilibrate_timestep = 0.5 fs"]
    else:
        run.append("ensemble = nve")
    if COULOMB == "pme":
        elec = ["coulomb = pme", "ewald_tolerance = %r" % EWALD_TOL]
    else:
        elec = ["scheme = site", "eps_rf = %s" % ("inf" if math.isinf(EPS_RF) else repr(EPS_RF))]
    return "\n".join(sysl + [
        "[interactions]", "cutoff = %r nm" % CUTOFF, "lj = %s" % LJ, "dispersion_correction = no"] + elec + run + [
        "[output]", "prefix = %s" % prefix, "progress = no", "sample_every = 0", ""])


def sh(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode:
        sys.exit("failed: %s\n%s%s" % (" ".join(cmd), p.stdout, p.stderr))
    return p.stdout


def put_state(template, r, v, l, A):
    """Checkpoint bytes `template` with r, v, l (lists of 3-vectors) and A (3x3 nested lists)
    replaced, CRC recomputed (offsets from rlcheckpoint.parse)."""
    t = rlcheckpoint.parse(template)
    out = bytearray(template)
    n, nrot = t["n"], t["nrot"]
    assert t["naxis"] == 0 and len(r) == n and len(l) == nrot
    r_off, v_off, l_off = t["_v_off"] - 24 * n, t["_v_off"], t["_l_off"]
    a_off = l_off + 24 * nrot
    struct.pack_into("<%dd" % (3 * n), out, r_off, *[x for row in r for x in row])
    struct.pack_into("<%dd" % (3 * n), out, v_off, *[x for row in v for x in row])
    struct.pack_into("<%dd" % (3 * nrot), out, l_off, *[x for row in l for x in row])
    struct.pack_into("<%dd" % (9 * n), out, a_off, *[x for m in A for row in m for x in row])
    plen = struct.unpack_from("<Q", out, 16)[0]
    struct.pack_into("<I", out, 24 + plen, zlib.crc32(bytes(out[:24 + plen])) & 0xFFFFFFFF)
    return bytes(out)


def shared_start(rotleap, work, eq_steps):
    """Equilibrate; return (checkpoint dict, on-step v(t), l(t), F(t), K(t), equilibration info)."""
    pre = os.path.join(work, "equil")
    with open(pre + ".ini", "w") as f:
        f.write(deck(pre, eq_steps, H_EQ, equilibrate=1000))
    t0 = time.time()
    sh([rotleap, "run", pre + ".ini"])
    eq_wall = time.time() - t0
    ck = rlcheckpoint.read(pre + ".chk")
    en = os.path.join(work, "energy.ini")
    with open(en, "w") as f:
        f.write(deck(os.path.join(work, "energy"), 0, H_EQ, start=pre + ".chk", box=ck["box"]))
    js = json.loads(sh([rotleap, "energy", en, "--json"]))
    F = [m["force"] for m in js["molecules"]]
    K = [m["torque"] for m in js["molecules"]]
    M = ck["species"][0]["mass"]
    half = H_EQ / 2
    v = [[ck["v"][i][c] + half * F[i][c] / M for c in range(3)] for i in range(N)]
    l = [[ck["l"][i][c] + half * K[i][c] for c in range(3)] for i in range(N)]
    summ = open(pre + ".summary.txt").read()
    info = dict(steps=eq_steps, relax_steps=1000, h_fs=H_EQ * 1e3, wall_s=eq_wall,
                U_start=js["energy"]["total"],
                summary={k.strip(): val.strip() for k, val in
                         (ln.split("=", 1) for ln in summ.splitlines() if "=" in ln and not ln.startswith("#"))})
    return ck, v, l, F, K, info


def rotleap_task(rotleap, work, ck, v, l, F, K, integ, h_ps, steps, every):
    tag = "%s_h%g" % (integ, h_ps * 1e3)
    pre = os.path.join(work, tag)
    with open(pre + "_tmpl.ini", "w") as f:
        f.write(deck(pre + "_tmpl", 0, h_ps, integrator=integ, box=ck["box"]))
    sh([rotleap, "run", pre + "_tmpl.ini"])
    M = ck["species"][0]["mass"]
    vh = [[v[i][c] - 0.5 * h_ps * F[i][c] / M for c in range(3)] for i in range(N)]
    lh = [[l[i][c] - 0.5 * h_ps * K[i][c] for c in range(3)] for i in range(N)]
    start = put_state(open(pre + "_tmpl.chk", "rb").read(), ck["r"], vh, lh, ck["A"])
    with open(pre + "_start.chk", "wb") as f:
        f.write(start)
    with open(pre + ".ini", "w") as f:
        f.write(deck(pre, steps, h_ps, integrator=integ, start=pre + "_start.chk", box=ck["box"]))
    t0 = time.time()
    p = subprocess.run([rotleap, "run", pre + ".ini", "--set", "output.thermo_every=%d" % every],
                       capture_output=True, text=True)
    wall = time.time() - t0
    rows = []
    if os.path.exists(pre + ".thermo.csv"):
        with open(pre + ".thermo.csv") as f:
            rows = [(int(r["step"]), float(r["total"]), float(r["potential"]), float(r["calE"]))
                    for r in csv.DictReader(f)]
    summ = {}
    if os.path.exists(pre + ".summary.txt"):
        summ = {k.strip(): val.strip() for k, val in (ln.split("=", 1) for ln in
                open(pre + ".summary.txt").read().splitlines() if "=" in ln and not ln.startswith("#"))}
    err = (p.stderr.strip().splitlines() or [""])[-1] if p.returncode else ""
    return dict(scheme=integ, h_fs=round(h_ps * 1e3, 6), rows=rows, wall_s=wall, rc=p.returncode,
                error=err, summary=summ, steps_requested=steps)


def openmm_worker(start_json, h_ps, steps, every, platform, out_json):
    """One OpenMM NVE run (called in a subprocess so that two run at once, one thread each)."""
    import numpy as np
    import watermodels
    try:
        import openmm as mm
        from openmm import unit
    except ImportError:
        from simtk import openmm as mm
        from simtk import unit
    st = json.load(open(start_json))
    ck = rlcheckpoint.read(st["chk"])
    d = np.array(ck["species"][0]["sites"])
    J = np.array(ck["species"][0]["moments"])
    M = ck["species"][0]["mass"]
    r = np.array(ck["r"])
    A = np.array(ck["A"])
    vh = np.array(st["v"]) - 0.5 * h_ps * np.array(st["F"]) / M
    lh = np.array(st["l"]) - 0.5 * h_ps * np.array(st["K"])
    pos = np.array(rlcheckpoint.site_positions(ck))
    vel = np.zeros_like(pos)
    for i in range(N):
        Ilab = A[i].T @ np.diag(J) @ A[i]
        w = np.linalg.solve(Ilab, lh[i])
        for a in range(4):
            vel[4 * i + a] = vh[i] + np.cross(w, pos[4 * i + a] - r[i])
    system = watermodels.build_system(st["model"], N, ck["box"], CUTOFF, st["eps_rf"], rigid=True,
                                      pme_tolerance=st["pme_tolerance"])
    integ = mm.VerletIntegrator(h_ps)
    integ.setConstraintTolerance(1e-10)
    props = {"Threads": "1"} if platform == "CPU" else {}
    ctx = mm.Context(system, integ, mm.Platform.getPlatformByName(platform), props)
    ctx.setPositions(pos)
    ctx.computeVirtualSites()
    ctx.setVelocities(vel)
    rows, err, prev = [], "", None
    limit = 10.0 * N * KB * T_K
    t0 = time.time()
    step = 0
    while step < steps:
        if step:
            try:
                integ.step(every)
            except Exception as e:  # OpenMM raises on NaN coordinates
                err = "step %d: OpenMM: %s" % (step, str(e).strip())
                break
        s = ctx.getState(getEnergy=True)
        u = s.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole)
        k = s.getKineticEnergy().value_in_unit(unit.kilojoule_per_mole)
        e = u + k
        if not math.isfinite(e):
            err = "step %d: the total energy is not finite" % step
            break
        if prev is not None and abs(e - prev) > limit:
            err = "step %d: the total energy jumped by %.3g kJ/mol in %d steps (more than 10 kT " \
                  "per molecule)" % (step, abs(e - prev), every)
            break
        rows.append((step, e, u, float("nan")))
        prev = e
        step += every
    json.dump(dict(rows=rows, error=err, wall_s=time.time() - t0, platform=platform,
                   openmm=mm.version.version), open(out_json, "w"))


def openmm_task(work, h_ps, steps, every, platform):
    out = os.path.join(work, "openmm_h%g.json" % (h_ps * 1e3))
    t0 = time.time()
    p = subprocess.run([sys.executable, os.path.abspath(__file__), "--openmm-worker",
                        os.path.join(work, "start.json"), repr(h_ps), str(steps), str(every),
                        platform, out], capture_output=True, text=True)
    wall = time.time() - t0
    if p.returncode:
        return dict(scheme="openmm", h_fs=round(h_ps * 1e3, 6), rows=[], wall_s=wall, rc=p.returncode,
                    error="OpenMM worker failed: " + (p.stderr.strip().splitlines() or [""])[-1],
                    summary={}, steps_requested=steps)
    res = json.load(open(out))
    return dict(scheme="openmm", h_fs=round(h_ps * 1e3, 6), rows=res["rows"], wall_s=wall,
                rc=1 if res["error"] else 0, error=res["error"], summary={}, platform=res["platform"],
                openmm=res["openmm"], steps_requested=steps)


def fluct(x):
    m = sum(x) / len(x)
    return math.sqrt(sum((a - m) ** 2 for a in x) / len(x)) / abs(m), m


def metrics(run, h_fs, steps):
    rows = [r for r in run["rows"] if r[0] < steps]
    if len(rows) < 3:
        return dict(n_samples=len(rows))
    E = [r[1] for r in rows]
    U = [r[2] for r in rows]
    t = [r[0] * h_fs * 1e-6 for r in rows]  # ns
    calE, Em = fluct(E)
    calU, Um = fluct(U)
    tm = sum(t) / len(t)
    slope = sum((a - tm) * (b - Em) for a, b in zip(t, E)) / sum((a - tm) ** 2 for a in t)
    resid = [b - (Em + slope * (a - tm)) for a, b in zip(t, E)]
    running, s1, s2 = [], 0.0, 0.0
    for k, e in enumerate(E):  # running calE over samples 0..k (same estimator as calE)
        s1 += e - E[0]
        s2 += (e - E[0]) ** 2
        n = k + 1
        var = max(s2 / n - (s1 / n) ** 2, 0.0)
        running.append(math.sqrt(var) / abs(s1 / n + E[0]))
    return dict(n_samples=len(rows), last_step=rows[-1][0], E0=E[0], U0=U[0], E_mean=Em, U_mean=Um,
                calE=calE, calU=calU, ratio=calE / calU, drift_kJmol_per_ns=slope,
                drift_per_molecule_per_ns=slope / N, drift_rel_per_ns=slope / abs(Em),
                calE_detrended=math.sqrt(sum(x * x for x in resid) / len(resid)) / abs(Em),
                E_end_minus_start_per_molecule=(E[-1] - E[0]) / N,
                calE_every_step=float(run["summary"]["calE"].split()[0]) if "calE" in run["summary"] else None,
                calU_every_step=float(run["summary"]["calU"].split()[0]) if "calU" in run["summary"] else None,
                running=running)


def write_report(path, table, eq, steps, args, elapsed):
    """The printed table as a Markdown page, with the system, the command and the machine."""
    cpu = "unknown CPU"
    try:
        cpu = next(ln.split(":", 1)[1].strip() for ln in open("/proc/cpuinfo") if ln.startswith("model name"))
    except (OSError, StopIteration):
        pass
    elec = ("smooth PME from error tolerance %g (alpha, grid and order 5 derived as OpenMM does), tin-foil"
            % EWALD_TOL) if COULOMB == "pme" else "site-based reaction field, eps_rf %s" % EPS_RF
    cmd = "/usr/bin/python3 validate/nve_conservation.py " + " ".join(
        os.path.relpath(a, ROOT) if os.path.isabs(a) else a for a in sys.argv[1:])
    lines = ["# Energy conservation: %d %s, %s" % (N, MODEL.upper(), "PME" if COULOMB == "pme" else "reaction field"),
             "", "Regenerate: `%s` (%.0f s on %d jobs; %s, %s)." % (cmd, elapsed, args.jobs, cpu, time.strftime("%Y-%m-%d")),
             "", "System: %d %s at 1 g/cm3, %g K start (Bussi equilibration %d steps at %g fs from a relaxed lattice), "
             "cutoff %g nm, %s, plain LJ, no dispersion correction. NVE %d steps at each h from one shared "
             "phase point (the docstring of validate/nve_conservation.py says how the start is built for each h and for "
             "OpenMM). rl: rotleap's revised angular-momentum leapfrog; rl-quaternion: its quaternion baseline; openmm: "
             "OpenMM %s VerletIntegrator + SETTLE (constraint tolerance 1e-10), CPU platform. calE = sd(E)/|<E>| and "
             "calU = sd(U)/|<U>| from samples every %d steps; drift = least-squares slope of E(t); E(0) the total energy "
             "at step 0 (kJ/mol). 'paper' is Omelyan's calE for TIP4P with reaction field (his Fig. 1), for scale only."
             % (N, MODEL.upper(), T_K, eq["steps"], eq["h_fs"], CUTOFF, elec, steps, _openmm_version(), args.sample),
             "", "```", *table, "```", ""]
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(lines))
    os.replace(path + ".tmp", path)


def _openmm_version():
    try:
        import openmm as mm
    except ImportError:
        from simtk import openmm as mm
    return mm.version.version


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--openmm-worker":
        a = sys.argv[2:]
        openmm_worker(a[0], float(a[1]), int(a[2]), int(a[3]), a[4], a[5])
        return 0
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rotleap", default=os.path.join(ROOT, "build", "rotleap"))
    ap.add_argument("--quick", action="store_true",
                    help="1,000 steps per run and 1 ps of equilibration (about 1.5 min)")
    ap.add_argument("--steps", type=int, help="NVE steps per run (default 10000; --quick 1000)")
    ap.add_argument("--steps-fs", default="1,2,3,4,5,6", help="time steps h in fs")
    ap.add_argument("--sample", type=int, default=10, help="steps between energy samples")
    ap.add_argument("--platform", default="CPU", help="OpenMM platform (CPU or Reference)")
    ap.add_argument("--jobs", type=int, default=2, help="runs at once")
    ap.add_argument("--no-write", action="store_true", help="do not write validate/data/")
    ap.add_argument("--keep", action="store_true", help="keep the work directory")
    ap.add_argument("--schemes", default="rl,rl-quaternion,openmm", help="subset of rl,rl-quaternion,openmm")
    ap.add_argument("--eps-rf", default="78.3", help="reaction-field dielectric (inf: conducting; "
                    "with --lj shifted-force the potential is then continuous with its first derivative)")
    ap.add_argument("--lj", default="plain", help="rotleap LJ truncation (OpenMM runs need plain)")
    ap.add_argument("--tag", default="", help="write data/nve_conservation<TAG>.json/.csv")
    ap.add_argument("--coulomb", default="rf", choices=("rf", "pme"),
                    help="rf: 256 TIP4P with reaction field (default); pme: 256 TIP4P-Ew with smooth PME")
    ap.add_argument("--ewald-tolerance", type=float, default=5e-4, help="with --coulomb pme: the error "
                    "tolerance from which both codes derive alpha and the grid (default 5e-4)")
    ap.add_argument("--report", help="also write the table as a Markdown report to this file")
    args = ap.parse_args()
    global EPS_RF, LJ, MODEL, COULOMB, EWALD_TOL
    EPS_RF, LJ = float(args.eps_rf), args.lj
    COULOMB, EWALD_TOL = args.coulomb, args.ewald_tolerance
    MODEL = "tip4p-ew" if COULOMB == "pme" else "tip4p"
    schemes = args.schemes.split(",")
    if "openmm" in schemes and LJ != "plain":
        sys.exit("OpenMM's NonbondedForce has no %s LJ: drop openmm from --schemes" % LJ)
    rotleap = os.path.abspath(args.rotleap)
    steps = args.steps or (1000 if args.quick else 10000)
    eq_steps = 500 if args.quick else 2500
    hs = [float(x) for x in args.steps_fs.split(",")]
    t0 = time.time()
    work = tempfile.mkdtemp(prefix="rotleap-nvecons-")
    ck, v, l, F, K, eq = shared_start(rotleap, work, eq_steps)
    with open(os.path.join(work, "start.json"), "w") as f:
        json.dump(dict(chk=os.path.join(work, "equil.chk"), v=v, l=l, F=F, K=K, model=MODEL,
                       eps_rf=EPS_RF, pme_tolerance=EWALD_TOL if COULOMB == "pme" else None), f)
    print("equilibrated %d + %d steps in %.0f s: %s; U(t) = %.6f kJ/mol"
          % (eq["relax_steps"], eq_steps, eq["wall_s"], eq["summary"].get("temperature"), eq["U_start"]),
          flush=True)
    jobs = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for h in sorted(hs, reverse=True):  # the long-lived runs first
            for integ in [x for x in ("rl", "rl-quaternion") if x in schemes]:
                jobs.append(pool.submit(rotleap_task, rotleap, work, ck, v, l, F, K, integ, h * 1e-3,
                                        steps, args.sample))
            if "openmm" in schemes:
                jobs.append(pool.submit(openmm_task, work, h * 1e-3, steps, args.sample, args.platform))
        runs = []
        for fut in concurrent.futures.as_completed(jobs):
            r = fut.result()
            runs.append(r)
            print("  %-13s h = %g fs: %s, %.0f s" % (r["scheme"], r["h_fs"], "ok" if not r["rc"] else
                  "STOPPED: " + r["error"], r["wall_s"]), flush=True)
    results = []
    for r in sorted(runs, key=lambda r: (r["h_fs"], SCHEMES.index(r["scheme"]))):
        m = metrics(r, r["h_fs"], steps)
        results.append(dict(scheme=r["scheme"], h_fs=r["h_fs"], ok=not r["rc"], error=r["error"],
                            wall_s=r["wall_s"], steps=steps,
                            steps_done=(r["rows"][-1][0] if r["rows"] else 0),
                            metrics={k: val for k, val in m.items() if k != "running"},
                            curve=[(row[0], row[1], row[2], m["running"][j] if "running" in m else None)
                                   for j, row in enumerate(r["rows"]) if row[0] < steps],
                            fallbacks=r["summary"].get("fallbacks")))
    elapsed = time.time() - t0
    table = ["%-13s %4s %10s %10s %8s %8s %11s %12s %9s %s" % (
        "scheme", "h", "calE %", "paper %", "calU %", "E/U %", "drift/ns", "drift/N/ns", "E(0)", "wall")]
    for res in results:
        m = res["metrics"]
        if "calE" not in m:
            table.append("%-13s %4g  no data: %s" % (res["scheme"], res["h_fs"], res["error"]))
            continue
        table.append("%-13s %4g %10.5f %10s %8.3f %8.2f %+11.3f %+12.5f %9.2f %4.0f s%s" % (
            res["scheme"], res["h_fs"], 100 * m["calE"], PAPER_CALE.get(int(res["h_fs"]), ""),
            100 * m["calU"], 100 * m["ratio"], m["drift_kJmol_per_ns"], m["drift_per_molecule_per_ns"],
            m["E0"], res["wall_s"], "" if res["ok"] else "  STOPPED at step %d: %s" % (
                res["steps_done"], res["error"])))
    print("\n" + "\n".join(table))
    print("total %.0f s" % elapsed)
    if args.report:
        write_report(args.report, table, eq, steps, args, elapsed)
    meta = dict(generated_by="/usr/bin/python3 validate/nve_conservation.py " + " ".join(
                    a for a in sys.argv[1:] if not a.startswith("/")),
                date=time.strftime("%Y-%m-%d %H:%M"), molecules=N, model=MODEL, density_g_cm3=DENSITY,
                box_nm=ck["box"], cutoff_nm=CUTOFF, coulomb=COULOMB,
                ewald_tolerance=EWALD_TOL if COULOMB == "pme" else None,
                scheme="site" if COULOMB == "rf" else None,
                eps_rf=(EPS_RF if math.isfinite(EPS_RF) else "inf") if COULOMB == "rf" else None, lj=LJ,
                dispersion_correction=False, temperature_K=T_K, steps=steps, sample_every=args.sample,
                openmm_platform=args.platform, equilibration=eq, wall_s=elapsed, jobs=args.jobs,
                paper_calE_percent=PAPER_CALE, paper_calU_percent=PAPER_CALU)
    if not args.no_write:
        os.makedirs(DATA, exist_ok=True)
        with open(os.path.join(DATA, "nve_conservation%s.json" % args.tag), "w") as f:
            json.dump(dict(meta=meta, runs=[{k: val for k, val in res.items() if k != "curve"}
                                            for res in results]), f, indent=1)
        with open(os.path.join(DATA, "nve_conservation%s.csv" % args.tag), "w") as f:
            f.write("# validate/nve_conservation.py %s: 256 %s (%s) NVE; every 50th step; calE_running "
                    "= sd(E)/|<E>| over the samples (every %d steps) from step 0 to this step\n"
                    % (meta["date"], MODEL.upper(), "PME" if COULOMB == "pme" else "reaction field", args.sample))
            f.write("scheme,h_fs,step,time_ps,total,potential,calE_running\n")
            for res in results:
                for s, e, u, c in res["curve"]:
                    if s % 50 == 0:
                        f.write("%s,%g,%d,%.4f,%.6f,%.6f,%.4e\n" % (res["scheme"], res["h_fs"], s,
                                s * res["h_fs"] * 1e-3, e, u, c if c is not None else float("nan")))
    if args.keep:
        print("work directory:", work)
    else:
        shutil.rmtree(work)
    return 0


if __name__ == "__main__":
    sys.exit(main())
