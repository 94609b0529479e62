#!/usr/bin/python3
"""Issue 34, acceptance 1 (the water part): for 216 TIP4P both barostats sample the same ensemble.

System: the quick start's (examples/tip4p.ini): 216 TIP4P, site cutoff 0.9 nm, reaction field
eps_rf = 78.3, plain LJ, with the LJ dispersion correction (its pressure follows the volume),
298 K, Bussi thermostat tau = 0.1 ps, h = 2 fs.

Runs, each from its own lattice relaxed by run.equilibrate (2 ps at 1 fs) and --eq-ps at 2 fs
(discarded):
  * NPT at 1 bar, run.barostat = mc (trials every 25 steps, OpenMM's default) and c-rescale
    (tau_p 1 ps, compressibility 4.5e-5 /bar), --npt-ps of production each: <V> with block errors
    from the thermo file's volume column, and kappa_T = <dV^2> / (k_B T <V>) from the whole
    production (the results file's isothermal_compressibility; the error: the variance of block
    variances, blocks of --block-ps);
  * NVT at --volumes (relative to 6.4617 nm^3, the volume at 1 g/cm^3), --nvt-ps of production each:
    <P> with block errors; a weighted straight line P(V) gives dP/dV and kappa_T = -1/(V dP/dV) at
    the Monte Carlo run's <V>.
Criteria, fixed before the runs: the two barostats' <V> agree within 2 combined errors; each
barostat's kappa_T from its fluctuations agrees with the slope's kappa_T within 2 combined errors.
The Monte Carlo acceptance ratio and the C-rescale conserved-energy drift are reported (the
results file's mc_acceptance, the summary's conserved_drift).

    /usr/bin/python3 validate/npt_tip4p.py [--rotleap build/rotleap] [--npt-ps 1000] [--nvt-ps 200]
        [--volumes 0.97,0.99,1.01,1.03] [--jobs 2] [--md validate/npt_tip4p.md]
Run time: about 1.7 ms per step of one core for this system: the defaults are 2 x 500,000 + 4 x
100,000 steps, about 40 minutes of CPU (20 minutes with --jobs 2 on an idle 2-core machine).
"""
import argparse
import concurrent.futures
import csv
import math
import os
import re
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True
from mdtable import blocks, write_md  # noqa: E402
KB = 0.0083144626  # kJ/mol/K
BAR = 16.6054  # kJ/mol/nm^3 per bar is 1/16.6054: 1 kJ/mol/nm^3 = 16.6054 bar
T0 = 298.0
V1 = 6.46169951  # nm^3: 216 TIP4P at 1 g/cm^3 (the thermo file's volume of that deck)

DECK = """[system]
model = tip4p
count = 216
box = {L!r} nm
orientations = random
seed = {seed}
[interactions]
cutoff = 0.9 nm
scheme = site
lj = plain
eps_rf = 78.3
dispersion_correction = yes
[run]
ensemble = nvt-bussi
temperature = 298 K
tau = 0.1 ps
timestep = 2 fs
equilibrate = 2000
equilibrate_timestep = 1 fs
steps = {steps}
{extra}
[output]
thermo_every = 10
sample_every = 0
discard = {discard}
progress = no
"""


def run(args, work, name, L, ps, extra):
    steps = int(round((args.eq_ps + ps) * 500))
    discard = int(round(args.eq_ps * 500))
    pre = os.path.join(work, name)
    with open(pre + ".ini", "w") as f:
        f.write(DECK.format(L=L, seed=11 + len(name), steps=steps, extra=extra, discard=discard))
    t0 = time.time()
    p = subprocess.run([args.rotleap, "run", pre + ".ini", "--set", "output.prefix=" + pre], capture_output=True,
                       text=True)
    if p.returncode:
        return dict(name=name, error=(p.stderr.strip().splitlines() or ["?"])[-1])
    rows = list(csv.DictReader(open(pre + ".thermo.csv")))
    rows = [r for r in rows if int(r["step"]) >= discard]
    summ = open(pre + ".summary.txt").read()
    res = open(pre + ".results.txt").read()
    return dict(name=name, V=[float(r.get("volume") or L ** 3) for r in rows], P=[float(r["pressure"]) for r in rows],
                summary=summ, results=res, wall=time.time() - t0)


def kappa_fluct(V, nb):
    """kappa_T = var(V) / (kT <V>) (1/bar) from the whole series, its error from block variances."""
    m = sum(V) / len(V)
    var = sum((v - m) ** 2 for v in V) / (len(V) - 1)
    n = len(V) // nb
    bv = []
    for i in range(nb):
        b = V[i * n:(i + 1) * n]
        bm = sum(b) / n
        bv.append(sum((v - bm) ** 2 for v in b) / (n - 1))
    mb = sum(bv) / nb
    err = math.sqrt(sum((x - mb) ** 2 for x in bv) / (nb * (nb - 1)))
    k = var / (KB * T0 * m) / BAR  # nm^3 / (kJ/mol) -> 1/bar
    return k, k * err / var


def key(text, name):
    m = re.search(r"^%s = ([-0-9.eE+]+)" % re.escape(name), text, re.M)
    return float(m.group(1)) if m else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rotleap", default=os.path.join(ROOT, "build", "rotleap"))
    ap.add_argument("--npt-ps", type=float, default=1000.0)
    ap.add_argument("--nvt-ps", type=float, default=200.0)
    ap.add_argument("--eq-ps", type=float, default=20.0, help="discarded start of every run at 2 fs")
    ap.add_argument("--volumes", default="0.97,0.99,1.01,1.03", help="NVT volumes relative to 1 g/cm^3's")
    ap.add_argument("--blocks", type=int, default=10)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--md", default=os.path.join(HERE, "npt_tip4p.md"))
    ap.add_argument("--work", default=None)
    args = ap.parse_args()
    work = args.work or tempfile.mkdtemp(prefix="npt_tip4p.")
    os.makedirs(work, exist_ok=True)
    t0 = time.time()
    L1 = V1 ** (1 / 3)
    jobs = [("mc", L1, args.npt_ps, "barostat = mc\npressure = 1 bar"),
            ("c-rescale", L1, args.npt_ps, "barostat = c-rescale\npressure = 1 bar\ntau_p = 1 ps\n"
                                             "compressibility = 4.5e-5 1/bar")]
    rel = [float(x) for x in args.volumes.split(",") if x]
    jobs += [("nvt_%g" % s, (s * V1) ** (1 / 3), args.nvt_ps, "") for s in rel]
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as ex:
        res = list(ex.map(lambda j: run(args, work, *j), jobs))
    bad = [r for r in res if "error" in r]
    if bad:
        sys.exit("; ".join("%s: %s" % (r["name"], r["error"]) for r in bad))
    npt, nvt = res[:2], res[2:]
    for r in npt:
        r["Vm"] = blocks(r["V"], args.blocks)
        r["kappa"] = kappa_fluct(r["V"], args.blocks)
    pts = []
    for r, s in zip(nvt, rel):
        p, e = blocks(r["P"], args.blocks)
        pts.append((s * V1, p, e))
    # weighted straight line P = a + b V
    w = [1 / e ** 2 for _, _, e in pts]
    S, Sx, Sy = sum(w), sum(wi * v for wi, (v, _, _) in zip(w, pts)), sum(wi * p for wi, (_, p, _) in zip(w, pts))
    Sxx = sum(wi * v * v for wi, (v, _, _) in zip(w, pts))
    Sxy = sum(wi * v * p for wi, (v, p, _) in zip(w, pts))
    D = S * Sxx - Sx * Sx
    b, eb = (S * Sxy - Sx * Sy) / D, math.sqrt(S / D)
    a = (Sy - b * Sx) / S
    chi2 = sum(wi * (p - a - b * v) ** 2 for wi, (v, p, _) in zip(w, pts))
    Vref = npt[0]["Vm"][0]
    ks, eks = -1.0 / (Vref * b), eb / (Vref * b * b)  # 1/bar (P in bar)
    zV = (npt[0]["Vm"][0] - npt[1]["Vm"][0]) / math.hypot(npt[0]["Vm"][1], npt[1]["Vm"][1])
    L = ["# NPT TIP4P: Monte Carlo against stochastic cell rescaling, and kappa_T two ways", "",
         "Generated by `/usr/bin/python3 validate/npt_tip4p.py %s` on %s in %.0f s (%d runs, %d at a time, on this "
         "2-core machine shared with other jobs). Do not edit: rerun the script. System, runs and criteria (fixed "
         "before the runs): its docstring." % (" ".join(sys.argv[1:]), time.strftime("%Y-%m-%d %H:%M"),
                                              time.time() - t0, len(jobs), args.jobs), "",
         "216 TIP4P, RF eps_rf 78.3, rc 0.9 nm, dispersion correction, 298 K, 1 bar, h = 2 fs; %g ps NPT and %g ps "
         "NVT production per run after %g ps; errors from %d blocks." % (args.npt_ps, args.nvt_ps, args.eq_ps,
                                                                         args.blocks), "",
         "| barostat | <V> (nm³) | <ρ> (g/cm³) | κ_T fluct. (1e-5/bar) | z vs slope | MC acceptance | conserved drift |",
         "|---|---|---|---|---|---|---|"]
    ok = abs(zV) <= 2
    for r in npt:
        (v, ev), (k, ek) = r["Vm"], r["kappa"]
        z = (k - ks) / math.hypot(ek, eks)
        ok = ok and abs(z) <= 2
        L.append("| %s | %.4f ± %.4f | %.4f ± %.4f | %.2f ± %.2f | %.1f | %s | %s |" % (
            r["name"], v, ev, V1 / v, V1 * ev / v ** 2, 1e5 * k, 1e5 * ek, z,
            "%.3f" % key(r["results"], "mc_acceptance") if r["name"] == "mc" else "",
            "%.3g" % key(r["summary"], "conserved_drift") if r["name"] != "mc" else ""))
    L += ["", "<V>: z = %.2f (MC − C-rescale over the combined error)." % zV, "",
          "| NVT V (nm³) | <P> (bar) |", "|---|---|"]
    L += ["| %.4f | %.1f ± %.1f |" % p for p in pts]
    L += ["", "Slope dP/dV = %.1f ± %.1f bar/nm³ (χ² = %.2f for %d points); κ_T = −1/(<V>_MC dP/dV) = "
          "(%.2f ± %.2f)e-5 /bar." % (b, eb, chi2, len(pts), 1e5 * ks, 1e5 * eks), "",
          "Both barostats sample the same ensemble by the fixed criteria: **%s**." % ("yes" if ok else "no")]
    text = "\n".join(L) + "\n"
    write_md(args.md, text)
    print(text)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
