#!/usr/bin/python3
"""Configurational against kinetic temperature over the time step (issue 37): are the configurations
sampled at the thermostat's T0 at large steps?

For each system and step h, `rotleap run` with output.tconf = yes from one start (a lattice relaxed for
--equil-ps at 1 fs by run.equilibrate, the same state for every h: the relaxation's step and seeds do
not depend on h), then --ps of Bussi NVT at h, every average over the whole production
(output.discard = 0), configurations sampled every ~20 fs (output.sample_every = round(20 fs / h)).
The table has U/N, the on-step temperatures of eqs. 9 and 12 (translational, rotational), the mean
mid-step ones of the thermo file (t_trans_mid, t_rot_mid: the velocities the thermostat rescales,
before it does), and the configurational temperatures (docs/observables.md, "Configurational
temperature") with their jackknife errors and z = (T_conf - T0) / error.

Systems: tip4p -- 256 TIP4P at 298 K and 1 g/cm3, site cutoff 0.9 nm, shifted-force LJ, eps_rf = inf
(forces continuous at the cutoff, so T_conf is exact), Bussi tau = 0.1 ps (issue 37's settings);
stockmayer -- examples/stockmayer.ini's 256 dipoles (rho* 0.8, T* 1.35, mu*^2 3, SF LJ and dipoles).

Run (from the repository root, after building rotleap):
    /usr/bin/python3 validate/tconf_vs_h.py [--rotleap build/rotleap] [--systems tip4p,stockmayer]
        [--ps 20] [--equil-ps 4] [--jobs 2] [--md validate/tconf_vs_h.md]
Writes the markdown table (and prints it)."""
import argparse
import concurrent.futures
import csv
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

SYSTEMS = {
    "tip4p": {
        "deck": """[system]
model = tip4p
count = 256
density = 1 g/cm3
orientations = random
seed = 2026
[interactions]
cutoff = 0.9 nm
scheme = site
lj = shifted-force
eps_rf = inf
[run]
ensemble = nvt-bussi
temperature = 298 K
tau = 0.1 ps
equilibrate_timestep = 1 fs
[output]
thermo_every = {thermo}
sample_every = {sample}
tconf = yes
discard = 0
progress = no
""",
        "T0": 298.0, "unit": "fs", "to_time": 1e-3, "hs": [1, 2, 4, 6, 8, 10], "sample_time": 20.0,
        "Tunit": "K", "Eunit": "kJ/mol"},
    "stockmayer": {
        "deck": """[system]
model = stockmayer
count = 256
density = 0.8
orientations = random
[model]
mu = 1.7320508
inertia = 0.025
[interactions]
cutoff = 2.5
lj = shifted-force
dipole = sf
[run]
ensemble = nvt-bussi
temperature = 1.35
tau = 0.2
equilibrate_timestep = 0.001
[output]
thermo_every = {thermo}
sample_every = {sample}
tconf = yes
discard = 0
progress = no
""",
        "T0": 1.35, "unit": "tau", "to_time": 1.0, "hs": [0.001, 0.002, 0.004, 0.006], "sample_time": 0.02,
        "Tunit": "epsilon/k_B", "Eunit": "epsilon"},
}


def value(text, key):
    """(value, error) of 'KEY = V +- E ...' in a results file (error None if there is none)."""
    m = re.search(r"^%s = ([-0-9.eE+]+)(?: \+- ([-0-9.eE+]+))?" % re.escape(key), text, re.M)
    if not m:
        return None, None
    return float(m.group(1)), float(m.group(2)) if m.group(2) else None


def one_run(args, name, h, work):
    sysd = SYSTEMS[name]
    ht = h * sysd["to_time"]  # the step in the deck's time unit (ps or tau)
    sample = max(1, int(round(sysd["sample_time"] / h)))
    steps = int(round(args.ps * 1e3 / h)) if sysd["unit"] == "fs" else int(round(args.tau_time / h))
    thermo = max(1, steps // 200)
    deck = os.path.join(work, "%s_h%g.ini" % (name, h))
    with open(deck, "w") as f:
        f.write(sysd["deck"].format(thermo=thermo, sample=sample))
    eq = int(round(args.equil_ps / 1e-3)) if sysd["unit"] == "fs" else int(round(args.equil_tau / 0.001))
    prefix = os.path.join(work, "%s_h%g" % (name, h))
    cmd = [args.rotleap, "run", deck, "--set", "run.timestep=%g" % ht, "--set", "run.steps=%d" % steps,
           "--set", "run.equilibrate=%d" % eq, "--set", "output.prefix=" + prefix]
    t0 = time.time()
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall = time.time() - t0
    if r.returncode:
        return {"name": name, "h": h, "error": r.stderr.strip()[-300:], "wall": wall}
    text = open(prefix + ".results.txt").read()
    out = {"name": name, "h": h, "wall": wall, "steps": steps, "sample": sample}
    for key in ["U_per_molecule", "temperature_translational", "temperature_rotational", "tconf_translational",
                "tconf_rotational", "tconf"]:
        out[key] = value(text, key)
    mids = {"t_trans_mid": [], "t_rot_mid": []}
    with open(prefix + ".thermo.csv") as f:
        for row in csv.DictReader(f):
            if int(row["step"]) > 0:
                for k in mids:
                    if row.get(k) not in (None, "", "nan"):
                        mids[k].append(float(row[k]))
    for k, v in mids.items():
        out[k] = sum(v) / len(v) if v else float("nan")
    return out


def fmt(ve, digits):
    v, e = ve
    if v is None:
        return "n/a"
    return ("%.*f ± %.*f" % (digits, v, digits, e)) if e is not None else "%.*f" % (digits, v)


def z(ve, T0):
    v, e = ve
    return "%.1f" % ((v - T0) / e) if v is not None and e else ""


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rotleap", default=os.path.join(ROOT, "build", "rotleap"))
    ap.add_argument("--systems", default="tip4p,stockmayer")
    ap.add_argument("--ps", type=float, default=20.0, help="production per TIP4P run, ps")
    ap.add_argument("--equil-ps", type=float, default=4.0, help="relaxation at 1 fs before each TIP4P run, ps")
    ap.add_argument("--tau-time", type=float, default=40.0, help="production per Stockmayer run, tau")
    ap.add_argument("--equil-tau", type=float, default=4.0, help="relaxation at 0.001 tau, tau")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--md", default=os.path.join(ROOT, "validate", "tconf_vs_h.md"))
    ap.add_argument("--work", default=None)
    args = ap.parse_args()
    names = [s for s in args.systems.split(",") if s]
    work = args.work or tempfile.mkdtemp(prefix="tconf_vs_h.")
    os.makedirs(work, exist_ok=True)
    jobs = [(n, h) for n in names for h in SYSTEMS[n]["hs"]]
    t0 = time.time()
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as ex:
        res = list(ex.map(lambda nh: one_run(args, nh[0], nh[1], work), jobs))
    total = time.time() - t0
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    lines = ["# Configurational against kinetic temperature over the time step", "",
             "Generated by `/usr/bin/python3 validate/tconf_vs_h.py %s` on %s at rotleap %s in %.0f s "
             "(%d runs, %d at a time on this 2-core machine shared with other jobs). Do not edit: rerun "
             "the script. Method: its docstring; the estimator: docs/observables.md, \"Configurational "
             "temperature\"." % (" ".join(sys.argv[1:]), time.strftime("%Y-%m-%d %H:%M"), commit, total,
                                  len(jobs), args.jobs), ""]
    for n in names:
        sd = SYSTEMS[n]
        prod = "%g ps" % args.ps if sd["unit"] == "fs" else "%g tau" % args.tau_time
        lines += ["## %s (T0 = %g %s; %s of Bussi NVT per step size)" % (n, sd["T0"], sd["Tunit"], prod), "",
                  "Temperatures in %s; U/N in %s; z = (T_conf - T0) / error. On-step: eqs. 9 and 12; mid-step: "
                  "the mean of the thermo file's t_trans_mid, t_rot_mid." % (sd["Tunit"], sd["Eunit"]), "",
                  "| h (%s) | U/N | T_trans on-step | T_rot on-step | T_trans mid | T_rot mid | T_conf trans | z | "
                  "T_conf rot | z | T_conf | samples | run (s) |" % sd["unit"],
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        dg = 1 if sd["Tunit"] == "K" else 4
        for r in res:
            if r["name"] != n:
                continue
            if "error" in r:
                lines.append("| %g | failed: %s |" % (r["h"], r["error"].replace("\n", " ")))
                continue
            lines.append("| %g | %s | %s | %s | %.*f | %.*f | %s | %s | %s | %s | %s | %d | %.0f |" % (
                r["h"], fmt(r["U_per_molecule"], 3), fmt(r["temperature_translational"], dg),
                fmt(r["temperature_rotational"], dg), dg, r["t_trans_mid"], dg, r["t_rot_mid"],
                fmt(r["tconf_translational"], dg), z(r["tconf_translational"], sd["T0"]),
                fmt(r["tconf_rotational"], dg), z(r["tconf_rotational"], sd["T0"]), fmt(r["tconf"], dg),
                r["steps"] // r["sample"], r["wall"]))
        lines.append("")
    text = "\n".join(lines) + "\n"
    with open(args.md, "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
