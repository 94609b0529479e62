#!/usr/bin/python3
"""Issue 34, acceptance 1 (the Stockmayer part): the two barostats sample the same ensemble.

A Stockmayer liquid (N = --count 256, mu*^2 = 3, T* = 1.35, cutoff 2.5, LJ and dipoles both
shifted-force, moment of inertia 0.1, h = 0.004; Bussi thermostat, tau 0.4) at P0 = --pressure
(2.2: about the pressure of the NVT state rho* = 0.8 of issue 33, examples/stockmayer.ini) under
run.barostat = mc (interval 25) and c-rescale (interval 10, tau_p 2, compressibility 0.05), one
run after the other at nice 10, from an fcc lattice at rho* = 0.8; the first --discard (20 %) of each
run is dropped (output.discard, so rotleap's results.txt averages the same window).

From each run's thermo file (volume every --thermo steps):
  * <V> and <rho> with block errors (--blocks 20 blocks);
  * kappa_T = <dV^2> / (kT <V>) from the WHOLE-window variance (dV about the window's mean), its
    error from the block means of dV^2 (per-block variances are biased low for C-rescale, whose
    volume correlation time is not small against a block: validate/npt_stockmayer.md of b0b3a0c);
  * rotleap's own lines: isothermal_compressibility (jackknife), mc_acceptance,
    crescale_effective_energy_drift.
Then NVT runs (Bussi, same model) at --volumes fractions of V_ref (the mean of the two barostats'
<V>), each from a lattice with 2000 relaxation steps (run.equilibrate) and --nvt-steps steps
(--discard dropped), <P> with block errors; a weighted least-squares line P = a + b V gives
kappa_T(slope) = -1 / (V_ref b) with the error of b.

Pass rule (fixed before running): |z| <= 3 for <V>(MC) - <V>(C-rescale), and for each barostat's
kappa_T from the fluctuations against kappa_T from the slope (z = difference over the combined
error).  A failure is reported, not tuned.

Run (from the repository root, after building rotleap):
    /usr/bin/python3 validate/npt_stockmayer.py [--rotleap build/rotleap] [--count 256] [--steps 200000]
        [--nvt-steps 50000] [--pressure 2.2] [--md validate/npt_stockmayer.md] [--json out.json]
Writes the Markdown table to --md (and the numbers to --json: validate/npt_lammps.py reads the
rotleap <rho> from it).
"""
import argparse
import json
import math
import os
import re
import sys
import tempfile
import time

from stockmayer_common import blocks, finish, run_rotleap, verdict, z

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
T = 1.35
MU = math.sqrt(3.0)

DECK = """[system]
model = stockmayer
count = {count}
density = {rho!r}
lattice = fcc
orientations = random
[model]
mu = {mu!r}
inertia = 0.1
[interactions]
cutoff = 2.5
lj = shifted-force
dipole = sf
[run]
steps = {steps}
timestep = 0.004
ensemble = nvt-bussi
temperature = {T}
tau = 0.4
equilibrate = {equil}
equilibrate_timestep = 0.004
{extra}
[output]
thermo_every = {thermo}
sample_every = 0
discard = {discard}
progress = no
"""

BAROSTATS = [("mc", "barostat = mc\npressure = {p!r}\nbarostat_interval = 25"),
             ("c-rescale", "barostat = c-rescale\npressure = {p!r}\nbarostat_interval = 10\ntau_p = 2\n"
                           "compressibility = 0.05")]


def run(args, work, name, rho, steps, equil, extra):
    discard = int(args.discard * steps) // args.thermo * args.thermo
    deck = DECK.format(count=args.count, rho=rho, mu=MU, steps=steps, T=T, equil=equil, extra=extra,
                       thermo=args.thermo, discard=discard)
    return run_rotleap(args.rotleap, work, name, deck, discard)


def line(res, key):
    m = re.search(r"^%s = (.*)$" % key, res, re.M)
    return m.group(1).split(" [")[0] if m else "n/a"


def analyse_npt(rows, res, args):
    V = [float(r["volume"]) for r in rows]
    m = sum(V) / len(V)
    dv2 = [(v - m) ** 2 for v in V]
    s2, s2e = blocks(dv2, args.blocks)
    Vb = blocks(V, args.blocks)
    k = s2 / (T * m)
    ke = k * math.sqrt((s2e / s2) ** 2 + (Vb[1] / m) ** 2)
    return {"V": Vb, "rho": blocks([args.count / v for v in V], args.blocks), "kappa": (k, ke),
            "P": blocks([float(r["pressure"]) for r in rows], args.blocks), "n": len(V),
            "rl_kappa": line(res, "isothermal_compressibility"), "acc": line(res, "mc_acceptance"),
            "drift": line(res, "crescale_effective_energy_drift")}


def fit(xs, ys, es):
    """Weighted least squares y = a + b x: (b, sigma_b)."""
    w = [1 / e ** 2 for e in es]
    S, Sx, Sy = sum(w), sum(wi * x for wi, x in zip(w, xs)), sum(wi * y for wi, y in zip(w, ys))
    Sxx = sum(wi * x * x for wi, x in zip(w, xs))
    Sxy = sum(wi * x * y for wi, x, y in zip(w, xs, ys))
    D = S * Sxx - Sx * Sx
    b = (S * Sxy - Sx * Sy) / D
    a = (Sy - b * Sx) / S
    chi2 = sum(wi * (y - a - b * x) ** 2 for wi, x, y in zip(w, xs, ys))
    return a, b, math.sqrt(S / D), chi2


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rotleap", default=os.path.join(ROOT, "build", "rotleap"))
    ap.add_argument("--count", type=int, default=256)
    ap.add_argument("--steps", type=int, default=200000)
    ap.add_argument("--nvt-steps", type=int, default=50000)
    ap.add_argument("--volumes", default="0.97,0.99,1.01,1.03")
    ap.add_argument("--thermo", type=int, default=10)
    ap.add_argument("--pressure", type=float, default=2.2)
    ap.add_argument("--discard", type=float, default=0.2)
    ap.add_argument("--blocks", type=int, default=20)
    ap.add_argument("--md", default=os.path.join(HERE, "npt_stockmayer.md"))
    ap.add_argument("--json")
    args = ap.parse_args()
    t0 = time.time()
    res, walls, nvt = {}, {}, []
    with tempfile.TemporaryDirectory() as work:
        for b, extra in BAROSTATS:
            rows, text, walls[b] = run(args, work, b, 0.8, args.steps, 0, extra.format(p=args.pressure))
            res[b] = analyse_npt(rows, text, args)
            print(b, res[b], walls[b], flush=True)
        Vref = 0.5 * (res["mc"]["V"][0] + res["c-rescale"]["V"][0])
        for f in [float(x) for x in args.volumes.split(",")]:
            V = f * Vref
            rows, _, w = run(args, work, "nvt%g" % f, args.count / V, args.nvt_steps, 2000, "")
            P = blocks([float(r["pressure"]) for r in rows], args.blocks)
            nvt.append((V, P, w))
            print("NVT", V, P, w, flush=True)
    a, slope, se, chi2 = fit([v for v, _, _ in nvt], [p[0] for _, p, _ in nvt], [p[1] for _, p, _ in nvt])
    ks = (-1 / (Vref * slope), se / abs(slope) / (Vref * abs(slope)))
    zv = z(res["mc"]["V"], res["c-rescale"]["V"])
    zk = {b: z(res[b]["kappa"], ks) for b, _ in BAROSTATS}
    ok = abs(zv) <= 3 and all(abs(v) <= 3 for v in zk.values())
    cmd = "/usr/bin/python3 validate/npt_stockmayer.py --count %d --steps %d --nvt-steps %d --pressure %g" % (
        args.count, args.steps, args.nvt_steps, args.pressure)
    L = ["# NPT Stockmayer: Monte Carlo against stochastic cell rescaling, and kappa_T against NVT", "",
         "Generated by `%s` (%.0f s wall on the shared 2-core machine, one run at a time at nice 10)." % (
             cmd, time.time() - t0), "",
         "%d Stockmayer molecules, mu*^2 = 3, T* = 1.35, P0 = %g, cutoff 2.5 (LJ and dipoles shifted-force), I = 0.1, "
         "h = 0.004, Bussi tau 0.4; %d steps per barostat from an fcc lattice at rho* = 0.8, the first %d %% dropped; "
         "%d blocks. Pass rule (fixed before the run): |z| <= 3 for <V> (MC against C-rescale) and for each "
         "barostat's kappa_T against the NVT slope." % (args.count, args.pressure, args.steps,
                                                        round(100 * args.discard), args.blocks), "",
         "| barostat | <V> | <rho> | <P> | kappa_T = <dV^2>/(kT<V>) (whole window) | rotleap's isothermal_compressibility "
         "| MC acceptance / C-rescale effective energy drift | wall s |",
         "|---|---|---|---|---|---|---|---|"]
    for b, _ in BAROSTATS:
        r = res[b]
        L.append("| %s | %.3f ± %.3f | %.5f ± %.5f | %.4f ± %.4f | %.4f ± %.4f | %s | %s | %.0f |" % (
            b, *r["V"], *r["rho"], *r["P"], *r["kappa"], r["rl_kappa"], r["acc"] if b == "mc" else r["drift"],
            walls[b]))
    L += ["", "NVT runs (%d steps each after 2000 relaxation steps, the first %d %% dropped):" % (
        args.nvt_steps, round(100 * args.discard)), "", "| V | rho | <P> | wall s |", "|---|---|---|---|"]
    for V, P, w in nvt:
        L.append("| %.3f | %.5f | %.4f ± %.4f | %.0f |" % (V, args.count / V, *P, w))
    L += ["", "Slope dP/dV = %.5f ± %.5f (weighted fit, chi^2 = %.2f for %d degrees of freedom); "
              "kappa_T = -1/(V_ref dP/dV) = %.4f ± %.4f at V_ref = %.3f." % (slope, se, chi2, len(nvt) - 2, *ks, Vref),
          "", "| test | z | pass |", "|---|---|---|",
          "| <V>: MC − C-rescale | %.2f | %s |" % (zv, verdict(zv))]
    for b, _ in BAROSTATS:
        L.append("| kappa_T (%s fluctuations) − kappa_T (NVT slope) | %.2f | %s |" % (
            b, zk[b], verdict(zk[b])))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"args": vars(args), "npt": res, "nvt": nvt, "kappa_slope": ks, "walls": walls}, f, indent=1)
    return finish(args.md, L, ok)


if __name__ == "__main__":
    sys.exit(main())
