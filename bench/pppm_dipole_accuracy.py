#!/usr/bin/python3
"""Measured (not estimated) RMS force and torque errors of rotleap's dipolar PME and LAMMPS's
pppm/dipole on relaxed Stockmayer configurations (issue 33, acceptance 6: "equal accuracy").

    /usr/bin/python3 bench/pppm_dipole_accuracy.py [--sizes 1000,4000,16000] [--tolerance 1e-2]
        [--lammps-acc 1e-2,5e-3]  (--tolerance: a list too) [--ffbench build/bench/ffbench]
        [--driver build/tests/forces/ewald/ewald_point] [--check-ewald]

Per size: bench/ffbench relaxes a Stockmayer fluid (rho* 0.8, T* 1.35, mu*^2 3, as
bench/pppm_dipole_lammps.py) and dumps it; on that configuration the electrostatic forces and
torques of
  ref   rotleap PME at tight settings (cutoff 5 sigma, order 8, tolerance 1e-5: estimated error
        ~1e-5, a thousandth of the 1e-2 target); --check-ewald compares it with rotleap's
        classical dipolar Ewald (alpha rc = 4.5, kmax from the tolerance 1e-6) and LAMMPS
        ewald/dipole at accuracy 1e-7 (smallest size only, it is slow);
  rl    rotleap PME at --tolerance (cutoff 2.5, alpha and mesh from the tolerance, as ffbench);
  lmp   LAMMPS lj/cut/dipole/long 2.5 (LJ epsilon 0: electrostatics alone) + pppm/dipole ACC,
        `run 0`, forces and torques from a dump, for each ACC of --lammps-acc;
and the RMS over dipoles of |F - F_ref| and |T - T_ref| (epsilon/sigma, epsilon) beside each
code's own estimate (rotleap dip_err_total / dip_terr_total; LAMMPS's "estimated absolute RMS
force accuracy").  Both codes aim their accuracy at tolerance x the force between two unit
charges 1 sigma apart.  Prints a table; --csv FILE writes it too.  Runs: 1000 a few seconds,
16000 about a minute, 32000 a few minutes (the reference mesh).
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import lammps_stockmayer as ls  # noqa: E402  (the LAMMPS data file from a rotleap dump)

RC = 2.5
REF = ["--cutoff", "5.0", "--order", "8", "--tolerance", "1e-5"]


def relaxed(ffbench, n, tol, dump):
    subprocess.run([ffbench, "time", "stockmayer", str(n), "1", "20", "--energy-every", "20", "--pme", repr(tol),
                    "--dump", dump], check=True, capture_output=True, text=True)


def point_config(dump, path):
    """ffbench's dump -> ewald_point's --dipoles file ("N L MU", then x y z ex ey ez)."""
    with open(dump) as f:
        head = f.readline().split()
        n, L = int(head[1]), float(head[3])
        rows = [[float(v) for v in f.readline().split()] for _ in range(n)]
    with open(path, "w") as g:
        g.write("%d %.17g %.17g\n" % (n, L, ls.MU))
        for x in rows:
            p = [c - L * math.floor(c / L) for c in x[0:3]]
            g.write("%.17g %.17g %.17g %.17g %.17g %.17g\n" % tuple(p + x[9:12]))
    return n, L


def rotleap(driver, cfg, args):
    p = subprocess.run([driver, "--dipoles", cfg] + args, capture_output=True, text=True)
    if p.returncode:
        sys.exit("ewald_point failed: %s" % p.stderr)
    out = json.loads(p.stdout)
    return out["params"], [m["force"] for m in out["molecules"]], [m["torque"] for m in out["molecules"]]


def lammps(data, n, kspace, rc, tmp):
    """Electrostatic forces and torques of LAMMPS (`run 0`), its estimate, grid and g_ewald."""
    inp = os.path.join(tmp, "in.acc")
    with open(inp, "w") as f:
        f.write("""units lj
atom_style hybrid sphere dipole
boundary p p p
read_data %s
pair_style lj/cut/dipole/long %g
pair_coeff * * 0.0 1.0
kspace_style %s
compute tq all property/atom tqx tqy tqz
dump d all custom 1 %s/dump.acc id fx fy fz c_tq[1] c_tq[2] c_tq[3]
dump_modify d format float %%.17g sort id
run 0
""" % (data, rc, kspace, tmp))
    screen = os.path.join(tmp, "screen.acc")
    subprocess.run(["lmp", "-in", inp, "-log", "none", "-screen", screen], check=True, capture_output=True, text=True,
                   cwd=tmp)
    out = open(screen).read()
    acc = re.search(r"estimated absolute RMS force accuracy = ([0-9.eE+-]+)", out)
    grid = re.search(r"grid = (\d+) (\d+) (\d+)", out)
    gew = re.search(r"G vector \(1/distance\) = ([0-9.eE+-]+)", out)
    lines = open(os.path.join(tmp, "dump.acc")).read().splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
    F, T = [], []
    for l in lines[start:start + n]:
        w = [float(x) for x in l.split()]
        F.append(w[1:4])
        T.append(w[4:7])
    return {"acc": float(acc.group(1)) if acc else float("nan"), "grid": "x".join(grid.groups()) if grid else "?",
            "g_ewald": float(gew.group(1)) if gew else float("nan")}, F, T


def rms(a, b):
    return math.sqrt(sum((x - y) ** 2 for ra, rb in zip(a, b) for x, y in zip(ra, rb)) / len(b))


def measure(ffbench, driver, n, tol, accs, check, tmp):
    """Rows (code, setting, alpha, mesh, est F, meas F, est T, meas T) for one size."""
    dump, cfg, data = (os.path.join(tmp, x) for x in ("state.txt", "config.txt", "data.stockmayer"))
    relaxed(ffbench, n, tol[0], dump)
    point_config(dump, cfg)
    ls.write_data(dump, data)
    pr, Fr, Tr = rotleap(driver, cfg, ["--method", "pme"] + REF)
    rows = [("ref", "tight", pr["alpha"], "%dx%dx%d p%d" % (tuple(pr["grid"]) + (pr["order"],)), pr["dip_err_total"],
             float("nan"), pr["dip_terr_total"], float("nan"))]
    if check:
        pe, Fe, Te = rotleap(driver, cfg, ["--method", "ewald", "--cutoff", "5.0", "--alpha", "0.9", "--tolerance", "1e-6"])
        rows.append(("rl-ewald", "1e-6", pe["alpha"], "kmax %d" % pe["kmax"][0], pe["dip_err_total"], rms(Fe, Fr),
                     pe["dip_terr_total"], rms(Te, Tr)))
        le, Fl, Tl = lammps(data, n, "ewald/dipole 1e-7", 5.0, tmp)
        rows.append(("lmp-ewald", "1e-7", le["g_ewald"], "-", le["acc"], rms(Fl, Fr), float("nan"), rms(Tl, Tr)))
    for t in tol:
        p, F, T = rotleap(driver, cfg, ["--method", "pme", "--cutoff", repr(RC), "--tolerance", repr(t)])
        rows.append(("rotleap", repr(t), p["alpha"], "%dx%dx%d p%d" % (tuple(p["grid"]) + (p["order"],)), p["dip_err_total"],
                     rms(F, Fr), p["dip_terr_total"], rms(T, Tr)))
    for acc in accs:
        le, Fl, Tl = lammps(data, n, "pppm/dipole %r" % acc, RC, tmp)
        rows.append(("lammps", repr(acc), le["g_ewald"], le["grid"] + " p5", le["acc"], rms(Fl, Fr), float("nan"),
                     rms(Tl, Tr)))
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="1000,4000,16000")
    ap.add_argument("--tolerance", default="1e-2", help="rotleap's tolerances, comma-separated")
    ap.add_argument("--lammps-acc", default="1e-2")
    ap.add_argument("--ffbench", default=os.path.join(HERE, "..", "build", "bench", "ffbench"))
    ap.add_argument("--driver", default=os.path.join(HERE, "..", "build", "tests", "forces", "ewald", "ewald_point"))
    ap.add_argument("--check-ewald", action="store_true")
    ap.add_argument("--csv")
    a = ap.parse_args()
    accs = [float(x) for x in a.lammps_acc.split(",")]
    head = "%6s %-9s %-7s %8s %-14s %9s %9s %6s %9s %9s" % ("N", "code", "setting", "alpha", "mesh", "est F", "meas F",
                                                            "e/m", "est T", "meas T")
    print("Stockmayer rho*=0.8 mu*^2=3, relaxed; RMS errors on a dipole against the tight reference (epsilon/sigma, epsilon)")
    print(head)
    out = []
    for i, n in enumerate(int(x) for x in a.sizes.split(",")):
        with tempfile.TemporaryDirectory() as tmp:
            rows = measure(a.ffbench, a.driver, n, [float(x) for x in a.tolerance.split(",")], accs, a.check_ewald and i == 0, tmp)
        for r in rows:
            print("%6d %-9s %-7s %8.4f %-14s %9.3g %9.3g %6.2f %9.3g %9.3g" % ((n,) + r[:6] + (r[4] / r[5],) + r[6:]),
                  flush=True)
            out.append((n,) + r)
    if a.csv:
        with open(a.csv, "w") as f:
            f.write("N,code,setting,alpha,mesh,est_rms_force,meas_rms_force,est_rms_torque,meas_rms_torque\n")
            for r in out:
                f.write("%d,%s,%s,%.6f,%s,%.4g,%.4g,%.4g,%.4g\n" % r)


if __name__ == "__main__":
    main()
