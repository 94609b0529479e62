#!/usr/bin/python3
"""Issue 37: at which time step does each scheme stop sampling 256 TIP4P at 298 K correctly, what
limits it, and how do the paper's claim and OpenMM's LangevinMiddleIntegrator + SETTLE compare.

One command runs the two studies it reads (each resumable in --work: started again with the same
--work, a study runs only what had not finished) and writes validate/large_steps.md:

1. bench/sampling_speed.py: structure and energy.  256 TIP4P, reaction field eps_rf = 78.3, plain LJ,
   rc 0.9 nm, one shared start, 4 + 200 ps per run; the reference rotleap Bussi (tau 1 ps) at 1 fs;
   rotleap Bussi 2-10 fs, DOT Langevin (nvt-langevin-dot, tau 1 ps, tau_rot 0.05 ps) 6-10 fs, DOT
   with heavier rotors (system.inertia_scale 4) 6-12 fs, OpenMM 7.7 LangevinMiddleIntegrator
   (friction 1/ps) + SETTLE 1-10 fs, GROMACS 2022 sd + SETTLE 1-8 fs.  A run is accurate if
   |z_U| <= 3 and z_rdf <= 3 (O-O RDF, permutation null) against the reference: the rule of
   sampling_speed.py, fixed in issue 8, before these runs.  Then the timing: ns/day of each code at
   its largest accurate step, alternating, in one run.
2. validate/dot_langevin.py: the configurational temperature (translational and rotational, from
   forces and torques), which tells whether configurations are sampled at T0 independently of the
   kinetic energy.  256 TIP4P, eps_rf = inf, shifted-force LJ (validate/tconf_vs_h.py's system),
   30 ps per run, Langevin 1 fs reference; pass: |z_U| <= 2 and both |T_conf - T0| <= 2 errors:
   its rule, fixed in 57865fa before its first run.

The tables give each scheme's largest passing step and every failing step beside it.  Nothing is tuned to pass: the references and tolerances above are the studies' own.

    /usr/bin/python3 validate/large_steps.py [--rotleap build/rotleap] [--work DIR] [--quick]
        [--md validate/large_steps.md]
Run time: the sampling study about 50 min of CPU on one core of this machine (29 runs of 204 ps,
then 3 + 10 timing rounds), the configurational-temperature study about 20 min of CPU (16 runs of
30 ps, 2 at a time); --quick (10 ps per run, errors meaningless) is a smoke test of a few minutes.
The hand-written reading below the generated part of the report is kept when it is regenerated.
"""
import argparse
import csv
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True
from mdtable import write_md  # noqa: E402

VARIANTS = "dot:6,8,10;dot@4:6,8,10,12"
GROMACS_FS = "1,2,3,4,5,6,8"
TCONF_SCHEMES, TCONF_HS = "langevin,dot,dot@4", "2,4,6,8,10"
NAMES = {("rotleap", "bussi"): "rotleap Bussi (tau 1 ps)", ("rotleap", "langevin-dot"): "rotleap DOT Langevin",
         ("rotleap", "langevin-dot@4"): "rotleap DOT Langevin, rotors x4",
         ("openmm", "langevin"): "OpenMM LangevinMiddle + SETTLE", ("gromacs", "sd"): "GROMACS sd + SETTLE"}


def sh(cmd, log):
    with open(log, "a") as f:
        f.write("$ %s\n" % " ".join(cmd))
        f.flush()
        p = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
    if p.returncode not in (0, 1):  # sampling_speed exits 1 when a code has no accurate step
        sys.exit("%s failed (exit %d): see %s" % (cmd[1], p.returncode, log))


def num(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return float("nan")


def sampling_schemes(rows):
    """(code, thermostat) -> runs by h, the reference's row apart."""
    out = {}
    for r in rows:
        if r["code"] not in ("rotleap", "openmm", "gromacs") or r["thermostat"] == "isokinetic":
            continue
        if r["code"] == "rotleap" and r["thermostat"] == "bussi" and num(r["h_fs"]) == 1.0:
            continue  # the reference
        out.setdefault((r["code"], r["thermostat"]), []).append(r)
    for v in out.values():
        v.sort(key=lambda r: num(r["h_fs"]))
    return out


def why(r):
    """What failed in a sampling run."""
    if r["status"] != "ok":
        return "unstable" + (" (%s)" % r["error"] if r.get("error") else "")
    parts = []
    if abs(num(r["z_U"])) > 3:
        parts.append("U/N (z %+.1f)" % num(r["z_U"]))
    if num(r["z_rdf"]) > 3:
        parts.append("O-O RDF (z %+.1f)" % num(r["z_rdf"]))
    return ", ".join(parts) or "?"


def largest(runs, ok):
    """The largest passing step (as sampling_speed.py chooses) and the failing runs."""
    good = [r for r in runs if ok(r)]
    return (good[-1] if good else None), [r for r in runs if not ok(r)]


def tconf_rows(md):
    """The rows of dot_langevin's table: scheme, h, z_U, z_trans, z_rot, T_conf values, verdict."""
    out = []
    for line in open(md):
        c = [x.strip() for x in line.strip().strip("|").split("|")]
        if len(c) >= 13 and re.match(r"^[0-9.]+$", c[1]) and c[0] != "reference":
            out.append(dict(scheme=c[0], h=float(c[1]), z_U=num(c[3]), tt=c[6], z_t=num(c[7]), tr=c[8], z_r=num(c[9]),
                            ok=c[12] == "yes"))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rotleap", default=os.path.join(ROOT, "build", "rotleap"))
    ap.add_argument("--work", help="work directory (kept; a second call with it continues the studies)")
    ap.add_argument("--quick", action="store_true", help="smoke test: 10 ps runs, meaningless errors")
    ap.add_argument("--md", default=os.path.join(HERE, "large_steps.md"))
    args = ap.parse_args()
    rotleap = os.path.abspath(args.rotleap)
    work = os.path.abspath(args.work) if args.work else tempfile.mkdtemp(prefix="large_steps.")
    os.makedirs(work, exist_ok=True)
    log = os.path.join(work, "large_steps.log")
    t0 = time.time()
    # 1. structure and energy, and the timing
    smd, scsv = os.path.join(work, "sampling.md"), os.path.join(work, "sampling.csv")
    if not os.path.exists(smd):
        shutil.copy(os.path.join(ROOT, "bench", "sampling_speed.md"), smd)  # its results block is replaced
    cmd = ["/usr/bin/python3", os.path.join(ROOT, "bench", "sampling_speed.py"), "--rotleap", rotleap,
           "--variants", VARIANTS, "--gromacs-fs", GROMACS_FS, "--work", os.path.join(work, "sampling"),
           "--csv", scsv, "--md", smd]
    sh(cmd + (["--quick", "--write"] if args.quick else []), log)
    # 2. the configurational temperature
    tmd = os.path.join(work, "tconf.md")
    sh(["/usr/bin/python3", os.path.join(HERE, "dot_langevin.py"), "--rotleap", rotleap, "--work",
        os.path.join(work, "tconf"), "--reuse", "--schemes", TCONF_SCHEMES, "--hs", TCONF_HS, "--md", tmd]
       + (["--ps", "5", "--ref-ps", "5"] if args.quick else []), log)
    wall = time.time() - t0

    rows = list(csv.DictReader(open(scsv)))
    ratio = {r["thermostat"] or "openmm": num(r["ns_per_day"]) for r in rows if r["code"] == "ratio"}  # '' = OpenMM's
    schemes = sampling_schemes(rows)
    tc = tconf_rows(tmd)
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    L = ["# Large time steps for rigid water: where each scheme stops sampling correctly (issue 37)", "",
         "Generated by `/usr/bin/python3 validate/large_steps.py %s` on %s at rotleap %s in %.0f s of wall time "
         "(this call; runs an earlier call with the same --work had finished are reused) on %s, 2 cores shared with "
         "other jobs. Do not edit: rerun the script. The studies, their references and tolerances (fixed "
         "before the runs): its docstring. Their full tables follow the summary."
         % (" ".join(sys.argv[1:]), time.strftime("%Y-%m-%d %H:%M"), commit, wall, cpu), ""]
    if args.quick:
        L += ["**A --quick smoke run: 10 ps per run, the errors and verdicts mean nothing.**", ""]
    L += ["## 1. Structure and energy against a 1 fs reference (256 TIP4P, RF)", "",
          "| scheme | steps tested (fs) | largest accurate step | ns/day there | failing steps |",
          "|---|---|---|---|---|"]
    best = {}
    for key, runs in sorted(schemes.items(), key=lambda kv: list(NAMES).index(kv[0]) if kv[0] in NAMES else 99):
        ok = lambda r: r["accurate"] == "yes" and r["status"] == "ok"
        b, f = largest(runs, ok)
        best[key] = b
        L.append("| %s | %s | %s | %s | %s |" % (
            NAMES.get(key, "%s %s" % key), ", ".join("%g" % num(r["h_fs"]) for r in runs),
            "**%g fs**" % num(b["h_fs"]) if b else "none",
            "%.0f" % num(b["ns_per_day"]) if b and math.isfinite(num(b["ns_per_day"])) else "—",
            "; ".join("%g fs: %s" % (num(r["h_fs"]), why(r)) for r in f) or "none"))
    L += ["", "Accurate: stable, |z_U| <= 3 and z_rdf <= 3 against rotleap Bussi at 1 fs; the largest accurate step "
          "is the largest step that passes (sampling_speed.py's choice), a smaller failing step is listed beside it "
          "(with about 30 comparisons at 3 sigma, one failure by chance is not unlikely). ns/day: one thread, the "
          "best of the alternating timing rounds (bench/sampling_speed.py). rotleap/OpenMM ns/day at the steps "
          "sampling_speed.py chose: %s; rotleap/GROMACS: %s. With heavier rotors the configurations are the "
          "model's but the rotational dynamics is slower, so that row's ns/day is a sampling speed of "
          "configurations, not of the real dynamics." % (
              "%.2f" % ratio["openmm"] if math.isfinite(ratio.get("openmm", float("nan"))) else "—",
              "%.2f" % ratio["gromacs"] if math.isfinite(ratio.get("gromacs", float("nan"))) else "—"), ""]
    L += ["## 2. Configurational temperature (256 TIP4P, RF eps_rf = inf)", "",
          "| scheme | steps tested (fs) | largest step passing | failing steps |", "|---|---|---|---|"]
    for s in dict.fromkeys(r["scheme"] for r in tc):
        runs = sorted((r for r in tc if r["scheme"] == s), key=lambda r: r["h"])
        b, fails = largest(runs, lambda r: r["ok"])
        fail = []
        for f in fails:
            what = []
            if abs(f["z_U"]) > 2:
                what.append("U/N (z %+.1f)" % f["z_U"])
            if abs(f["z_t"]) > 2:
                what.append("T_conf trans %s K (z %+.1f)" % (f["tt"], f["z_t"]))
            if abs(f["z_r"]) > 2:
                what.append("T_conf rot %s K (z %+.1f)" % (f["tr"], f["z_r"]))
            fail.append("%g fs: %s" % (f["h"], ", ".join(what) or "?"))
        L.append("| %s | %s | %s | %s |" % (s, ", ".join("%g" % r["h"] for r in runs), "%g fs" % b["h"] if b else "none",
                                         "; ".join(fail) or "none"))
    ten = [NAMES.get(k, "%s %s" % k) for k, b in best.items() if b and num(b["h_fs"]) >= 10]
    L += ["", "## 3. The goal: structure and U/N within error at 10 fs", "",
          ("Met by: %s (section 1's rule)." % ", ".join(ten)) if ten else
          "Not met by any scheme under section 1's rule; the best steps are in its table.", ""]
    L += ["## The studies' full tables", "", "### bench/sampling_speed.py", ""]
    text = open(smd).read()
    i, j = text.find("<!-- results -->"), text.find("<!-- /results -->")
    L += [text[i + len("<!-- results -->"):j].strip() if i >= 0 and j > i else "(no results block: %s)" % smd, ""]
    ttext = open(tmd).read()
    k = ttext.find("| scheme |")
    L += ["### validate/dot_langevin.py", "", ttext[k:ttext.find("\n\n", k)].strip() if k >= 0 else "(no table)", ""]
    out = "\n".join(L) + "\n"
    write_md(args.md, out)
    print(out)
    print("work directory:", work)
    return 0


if __name__ == "__main__":
    sys.exit(main())
