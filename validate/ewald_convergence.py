#!/usr/bin/python3
"""Accuracy of the Ewald parameters rotleap derives from a tolerance (issue 33, acceptance 3): the
estimated RMS force error on a charge against the error measured against a tightly converged
Ewald sum, over a range of tolerances.

Run (from the repository root, after building; the driver is built with the tests):
    /usr/bin/python3 validate/ewald_convergence.py [--driver build/tests/forces/ewald/ewald_point]
                                                  [--no-write]
About 10 s on 2 cores for the charges, a few minutes more for the dipoles.  Writes validate/data/ewald_convergence.txt (the table) and
validate/plots/ewald_convergence.png (if matplotlib is there) unless --no-write.

Systems: `ions`, 1,000 random point ions +-1 e in a 3.0 nm cube (centres >= 0.25 nm apart),
cutoff 1.2 nm: the uncorrelated charges the estimates are derived for; `tip4p-ew`, the 216-molecule
TIP4P-Ew liquid of validate/data (sp_tip4p-ew_liquid.chk.gz), cutoff 0.9 nm, whose charges sit in
neutral molecules, which the estimates do not know (they overestimate its error, by 1.2 to 1.6).

For each tolerance delta (1e-3 ... 1e-6) and method (PME, order 5, and Ewald, alpha and the
grid or kmax derived as OpenMM 7.7 derives them) the driver gives the force on every site (real
space + reciprocal part + the intramolecular correction's site forces: the Coulomb forces between
sites of different molecules, whatever alpha); the reference is Ewald with the cutoff at half the box,
alpha cutoff = 6 (erfc(6) = 2e-17) and every vector with exp(-k^2 / 4 alpha^2) > e^-40.  Measured:
sqrt(sum over charged sites of |F - F_ref|^2 / N).  Estimated (rl_ewald_info.err_total): Kolafa &
Perram's real-space estimate and, for the reciprocal part, the omitted vectors (Ewald) or the
Hockney-Eastwood functional of the SPME mesh (PME), in quadrature.  Criterion: estimated within a
factor 2 of measured, every row.  Because at OpenMM's choices the real-space error dominates, a
second set of rows tests the reciprocal estimates alone: the reference's cutoff and alpha (no
real-space error left) with explicit meshes (orders 4 to 8) and k cutoffs; est/meas there is
err_recip over the measured error.

Point dipoles (LJ units, kc = 1; --no-dipoles leaves them out): `dipoles`, 500 random point dipoles
mu*^2 = 3 at rho* = 0.8 (L = 8.55 sigma, centres >= 0.8 sigma apart, random directions), and
`stockmayer`, 256 dipoles of a Stockmayer liquid (rho* 0.8, T* 1.35, mu*^2 3; the last frame of a
short rotleap NVT run, reaction field, made here), both with cutoff 3 sigma.  For each tolerance
delta (the target delta epsilon/sigma, LAMMPS's convention; alpha and the k cutoff or mesh
derived from the dipolar estimates) the estimated RMS force and torque errors on a dipole
(rl_ewald_info.dip_err_total, dip_terr_total) against the measured ones, and again the
reciprocal estimates alone with explicit k cutoffs and meshes.
"""
import argparse
import gzip
import json
import math
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
TOLS = [1e-3, 5e-4, 1e-4, 1e-5, 1e-6]
# mesh points and k cutoffs per 3 nm of edge for the reciprocal-only rows (scaled to the box)
RECIP_PME = [(24, 5), (32, 5), (48, 5), (64, 5), (32, 4), (32, 6), (32, 8)]
RECIP_KMAX = [8, 10, 12, 14]


def run(driver, args, sites=True):
    p = subprocess.run([driver] + args + (["--sites"] if sites else []) + ["--threads", "2"], capture_output=True, text=True)
    if p.returncode:
        sys.exit("failed: %s %s\n%s" % (driver, " ".join(args), p.stderr))
    return json.loads(p.stdout)


def measured(out, ref):
    num, n = 0.0, 0
    for a, b in zip(out["sites"], ref["sites"]):
        if b == [0.0, 0.0, 0.0]:  # an uncharged site (TIP4P's O)
            continue
        num += sum((x - y) ** 2 for x, y in zip(a, b))
        n += 1
    return math.sqrt(num / n)


TOLS_DIP = {"ewald": [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 1e-5], "pme": [3e-2, 1e-2, 3e-3, 1e-3]}
RECIP_DIP_PME = [(32, 5), (48, 5), (64, 5), (32, 7), (48, 7)]  # per 8.55 sigma of edge
RECIP_DIP_KMAX = [8, 10, 12]


def molecular(out, ref, key):
    num = sum(sum((x - y) ** 2 for x, y in zip(a[key], b[key])) for a, b in zip(out["molecules"], ref["molecules"]))
    return math.sqrt(num / len(ref["molecules"]))


def dipole_configs(work, rotleap):
    """The two dipolar configurations as ewald_point --dipoles files: (name, path, L)."""
    import random
    rng = random.Random(3)
    n, L, mu = 500, (500 / 0.8) ** (1.0 / 3.0), math.sqrt(3.0)
    pts = []
    while len(pts) < n:
        r = [rng.random() * L for _ in range(3)]
        if all(sum(((r[c] - q[c]) - L * round((r[c] - q[c]) / L)) ** 2 for c in range(3)) >= 0.64 for q in pts):
            pts.append(r)
    lines = []
    for r in pts:
        e = [rng.gauss(0, 1) for _ in range(3)]
        ne = math.sqrt(sum(x * x for x in e))
        lines.append("%.17g %.17g %.17g %.17g %.17g %.17g" % (*r, *[x / ne for x in e]))
    path = os.path.join(work, "dipoles.txt")
    with open(path, "w") as f:
        f.write("%d %.17g %.17g\n%s\n" % (n, L, mu, "\n".join(lines)))
    out = [("dipoles", path, L)]
    deck = os.path.join(work, "liquid.ini")
    with open(deck, "w") as f:
        f.write("[system]\nmodel = stockmayer\ncount = 256\ndensity = 0.8\ntemperature = 1.35\nseed = 5\n[model]\n"
                "mu = %.17g\n[interactions]\ncutoff = 3.0\nlj = shifted-force\ndipole = sf\n[run]\nsteps = 1500\n"
                "timestep = 0.002\nensemble = nvt-bussi\ntemperature = 1.35\nequilibrate = 500\n[output]\n"
                "prefix = %s\ntrajectory_every = 1500\nthermo_every = 500\nprogress = no\n" % (mu, os.path.join(work, "liquid")))
    p = subprocess.run([rotleap, "run", deck], capture_output=True, text=True)
    if p.returncode:
        sys.exit("failed: rotleap run %s\n%s" % (deck, p.stderr))
    rows = open(os.path.join(work, "liquid.xyz")).read().split("\n")
    L = float(rows[1].split('"')[1].split()[0])
    path = os.path.join(work, "stockmayer.txt")
    with open(path, "w") as f:
        f.write("256 %.17g %.17g\n" % (L, mu))
        for row in rows[2:258]:
            f.write(" ".join(row.split()[1:7]) + "\n")
    out.append(("stockmayer", path, L))
    return out


def dipole_rows(args, work, lines):
    """The dipolar rows; returns whether every ratio lies within a factor 2."""
    ok = True
    lines.append("# point dipoles (LJ units): estimated vs measured RMS force (epsilon/sigma) and torque (epsilon) on a dipole")
    lines.append("system     method tolerance  alpha   grid/kmax      est_F      meas_F     F e/m  est_T      meas_T     T e/m")
    for name, path, L in dipole_configs(work, args.rotleap):
        conf = ["--dipoles", path]
        rcref = 0.5 * L
        aref = 6.0 / rcref
        km = int(math.ceil(L * 2 * aref * math.sqrt(40.0) / (2 * math.pi)))
        ref = run(args.driver, conf + ["--method", "ewald", "--cutoff", repr(rcref), "--alpha", repr(aref),
                                       "--kmax", str(km), str(km), str(km), "--kmax-sq", str(km * km)], sites=False)

        def row(label, out, est_f, est_t):
            nonlocal ok
            p = out["params"]
            mf, mt = molecular(out, ref, "force"), molecular(out, ref, "torque")
            rf, rt = est_f / mf, est_t / mt
            good = 0.5 <= rf <= 2.0 and 0.5 <= rt <= 2.0
            ok &= good
            res = ("x".join(map(str, p["grid"])) + " p%d" % p["order"]) if p["method"] == "pme" else " ".join(map(str, p["kmax"]))
            lines.append("%-10s %-6s %-10s %-7.4f %-13s  %-9.3g  %-9.3g  %-5.2f  %-9.3g  %-9.3g  %.2f%s"
                         % (name, p["method"], label, p["alpha"], res, est_f, mf, rf, est_t, mt, rt, "" if good else "  OUTSIDE 2x"))
            print(lines[-1], flush=True)

        for method in ("ewald", "pme"):
            for tol in TOLS_DIP[method]:
                out = run(args.driver, conf + ["--method", method, "--cutoff", "3.0", "--tolerance", repr(tol)], sites=False)
                p = out["params"]
                row("%.0e" % tol, out, p["dip_err_total"], p["dip_terr_total"])
        lines.append("%-10s reference: Ewald, cutoff %.4f, alpha %.4f, kmax %d, n^2 <= %d" % (name, rcref, aref, km, km * km))
        base = conf + ["--cutoff", repr(rcref), "--alpha", repr(aref), "--tolerance", "0.09"]
        for g, order in RECIP_DIP_PME:
            n = str(int(round(g * L / 8.55)))
            out = run(args.driver, base + ["--method", "pme", "--grid", n, n, n, "--order", str(order)], sites=False)
            row("recip", out, out["params"]["dip_err_recip"], out["params"]["dip_terr_recip"])
        for k in RECIP_DIP_KMAX:
            n = str(int(round(k * L / 8.55)))
            out = run(args.driver, base + ["--method", "ewald", "--kmax", n, n, n], sites=False)
            row("recip", out, out["params"]["dip_err_recip"], out["params"]["dip_terr_recip"])
    return ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--driver", default=os.path.join(ROOT, "build", "tests", "forces", "ewald", "ewald_point"))
    ap.add_argument("--rotleap", default=os.path.join(ROOT, "build", "rotleap"))
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--no-dipoles", action="store_true")
    args = ap.parse_args()
    t0 = time.time()
    work = tempfile.mkdtemp(prefix="rotleap-ewconv-")
    chk = os.path.join(work, "tip4p-ew_liquid.chk")
    with gzip.open(os.path.join(HERE, "data", "sp_tip4p-ew_liquid.chk.gz")) as g, open(chk, "wb") as f:
        f.write(g.read())
    systems = [dict(name="ions", conf=["--ions", "1000", "3.0", "7"], L=3.0, rc=1.2),
               dict(name="tip4p-ew", conf=["--checkpoint", chk, "--model", "tip4p-ew"], L=1.8625827908797699, rc=0.9)]
    lines = ["# validate/ewald_convergence.py (%s): estimated vs measured RMS force error on a charge, kJ/mol/nm"
             % time.strftime("%Y-%m-%d"),
             "system    method tolerance  alpha(/nm)  grid/kmax      est_real   est_recip  est_total  measured   est/meas"]
    rows, ok = [], True
    for s in systems:
        rcref = 0.5 * s["L"]
        aref = 6.0 / rcref
        km = int(math.ceil(s["L"] * 2 * aref * math.sqrt(40.0) / (2 * math.pi)))
        ref = run(args.driver, s["conf"] + ["--method", "ewald", "--cutoff", repr(rcref), "--alpha", repr(aref),
                                            "--kmax", str(km), str(km), str(km), "--kmax-sq", str(km * km)])
        for method in ("pme", "ewald"):
            for tol in TOLS:
                out = run(args.driver, s["conf"] + ["--method", method, "--cutoff", repr(s["rc"]), "--tolerance", repr(tol)])
                p = out["params"]
                meas = measured(out, ref)
                ratio = p["err_total"] / meas
                res = "x".join(map(str, p["grid"])) if method == "pme" else " ".join(map(str, p["kmax"]))
                ok &= 0.5 <= ratio <= 2.0
                rows.append(dict(system=s["name"], method=method, tol=tol, est=p["err_total"], meas=meas,
                                 real=p["err_real"], recip=p["err_recip"]))
                lines.append("%-9s %-6s %-9.0e  %-10.6f  %-13s  %-9.3g  %-9.3g  %-9.3g  %-9.3g  %.2f%s"
                             % (s["name"], method, tol, p["alpha"], res, p["err_real"], p["err_recip"], p["err_total"], meas,
                                ratio, "" if 0.5 <= ratio <= 2.0 else "  OUTSIDE 2x"))
                print(lines[-1], flush=True)
        lines.append("%-9s reference: Ewald, cutoff %.4f nm, alpha %.4f /nm, kmax %d, n^2 <= %d" % (s["name"], rcref, aref, km, km * km))
        # the reciprocal estimates alone: the reference's cutoff and alpha (no real-space error left),
        # explicit meshes and k cutoffs (tolerance 0.09 only lets the coarse ones through the check)
        base = s["conf"] + ["--cutoff", repr(rcref), "--alpha", repr(aref), "--tolerance", "0.09"]
        for method, sets in (("pme", [("--grid", g, o) for g, o in RECIP_PME]), ("ewald", [("--kmax", k, None) for k in RECIP_KMAX])):
            for key, val, order in sets:
                dims = [str(int(round(val * s["L"] / 3.0)))] * 3
                extra = [key] + dims + (["--order", str(order)] if order else [])
                out = run(args.driver, base + ["--method", method] + extra)
                p = out["params"]
                meas = measured(out, ref)
                ratio = p["err_recip"] / meas
                ok &= 0.5 <= ratio <= 2.0
                res = ("x".join(map(str, p["grid"])) + " p%d" % p["order"]) if method == "pme" else " ".join(map(str, p["kmax"]))
                lines.append("%-9s %-6s recip only %-10.6f  %-13s  %-9.3g  %-9.3g  %-9.3g  %-9.3g  %.2f%s"
                             % (s["name"], method, p["alpha"], res, p["err_real"], p["err_recip"], p["err_total"], meas,
                                p["err_recip"] / meas, "" if 0.5 <= ratio <= 2.0 else "  OUTSIDE 2x"))
                print(lines[-1], flush=True)
    lines.append("result (charges: both systems, every tolerance and method): %s; %.0f s"
                 % ("estimate within a factor 2 of the measured error" if ok else "OUTSIDE a factor 2", time.time() - t0))
    if not args.no_dipoles:
        t1 = time.time()
        okd = dipole_rows(args, work, lines)
        lines.append("result (point dipoles: both systems, every row, force and torque): %s; %.0f s"
                     % ("estimate within a factor 2 of the measured error" if okd else "OUTSIDE a factor 2", time.time() - t1))
        ok &= okd
    print(lines[-1])
    if not args.no_write:
        with open(os.path.join(HERE, "data", "ewald_convergence.txt"), "w") as f:
            f.write("\n".join(lines) + "\n")
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            plt = None
        if plt:
            fig, ax = plt.subplots(figsize=(6.4, 4.4))
            for sname, mk in (("ions", "o"), ("tip4p-ew", "s")):
                for method, col in (("pme", "C0"), ("ewald", "C1")):
                    rr = [r for r in rows if r["system"] == sname and r["method"] == method]
                    ax.loglog([r["tol"] for r in rr], [r["meas"] for r in rr], mk + "-", color=col,
                              label="%s %s measured" % (sname, method))
                    ax.loglog([r["tol"] for r in rr], [r["est"] for r in rr], mk + "--", color=col, alpha=0.6,
                              label="%s %s estimated" % (sname, method))
            ax.set_xlabel("tolerance (OpenMM's ewaldErrorTolerance)")
            ax.set_ylabel("RMS force error on a charge (kJ/mol/nm)")
            ax.set_title("Ewald parameters from a tolerance: estimated vs measured")
            ax.legend(fontsize=7)
            fig.tight_layout()
            fig.savefig(os.path.join(HERE, "plots", "ewald_convergence.png"), dpi=110)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
