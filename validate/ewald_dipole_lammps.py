#!/usr/bin/python3
"""Dipolar Ewald of rotleap (forces/ewald/, issue 33, acceptance 2) against LAMMPS's ewald/dipole.

Run (from the repository root, after building; the driver is built with the tests):
    /usr/bin/python3 validate/ewald_dipole_lammps.py [--driver build/tests/forces/ewald/ewald_point]
                                                     [--lmp /usr/bin/lmp] [--no-write]
LAMMPS from Debian (apt-get install lammps: `lmp`, 29 Sep 2021 update 2, with the DIPOLE and
KSPACE packages).  A few seconds.

Configurations: Stockmayer fluids in reduced units (LAMMPS `units lj`, rotleap's LJ units: kc = 1,
lengths in sigma, energies in epsilon), rho* = 0.8, mu*^2 = 3, on an fcc lattice with random
displacements (0.1 sigma) and random dipole directions: 108 dipoles (L = 5.13) and 256 (L = 6.84).
LAMMPS: `atom_style hybrid sphere dipole`, `pair_style lj/cut/dipole/long` with LJ epsilon 0 (the
electrostatic part alone), `kspace_style ewald/dipole` with `kspace_modify gewald ALPHA kmax/ewald
K K K`, `run 0`, energies from thermo (ecoul: real space, elong: the reciprocal sum with the self
term; tin foil: ewald/dipole has no surface term), forces and torques from a dump (fx fy fz, and
compute property/atom tqx tqy tqz).  rotleap: "ewald-real" + "ewald" (tests/forces/ewald/
ewald_point --dipoles), the same alpha and real-space cutoff, and the same vectors: LAMMPS keeps
k = 2 pi n / L with |n_c| <= K and |k|^2 <= max_c (2 pi K / L_c)^2, i.e. rotleap's kmax = K K K and
kmax_sq = K^2 in a cube.

Cases per configuration: `tight` (alpha rc = 4.5, K = 14: both sums converged to ~1e-10) and `loose`
(alpha rc = 3, K = 6: truncated sums, the same truncation in both codes).  Criteria (issue 33):
|dE| / |E| <= 1e-6 for the total and for each part, RMS relative force and torque errors <= 1e-6.

Writes (unless --no-write) tests/forces/ewald/data/ewald_dipole_lammps.json.gz: the configurations,
parameters and LAMMPS's numbers, which tests/forces/ewald/check_ewald_lammps.py compares rotleap with
(CTest, no LAMMPS needed), and tests/forces/ewald/data/ewald_dipole_lammps_summary.txt (the table).
Exit status 1 on a failure.
"""
import argparse
import gzip
import json
import math
import os
import random
import subprocess
import sys
import tempfile

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(SRC, "tests", "forces", "ewald", "data")
# plain: rotleap against LAMMPS as they are (energy relative to |ecoul| + |elong|, forces and torques
# RMS relative); same_erfc: with the real-space difference that LAMMPS's erfc approximation makes
# added to rotleap's (every energy relative to |U| or |ecoul| + |elong|, forces, torques)
TOL = {"plain": 1e-6, "same_erfc": 1e-11}
MU2 = 3.0
RHO = 0.8
RC = 2.5


def fcc(ncell, rho, seed):
    """4 ncell^3 sites of an fcc lattice at density rho, displaced at random by up to 0.1 sigma per
    axis, with random unit dipole axes."""
    rng = random.Random(seed)
    n = 4 * ncell ** 3
    L = (n / rho) ** (1.0 / 3.0)
    a = L / ncell
    base = [(0, 0, 0), (0.5, 0.5, 0), (0.5, 0, 0.5), (0, 0.5, 0.5)]
    pos, axes = [], []
    for i in range(ncell):
        for j in range(ncell):
            for k in range(ncell):
                for b in base:
                    x = [((i, j, k)[c] + b[c]) * a + rng.uniform(-0.1, 0.1) for c in range(3)]
                    pos.append([xc % L for xc in x])
                    while True:
                        e = [rng.gauss(0, 1) for _ in range(3)]
                        r = math.sqrt(sum(v * v for v in e))
                        if r > 1e-3:
                            break
                    axes.append([v / r for v in e])
    return L, pos, axes


def write_config(path, L, mu, pos, axes):
    with open(path, "w") as f:
        f.write("%d %.17g %.17g\n" % (len(pos), L, mu))
        for r, e in zip(pos, axes):
            f.write("%.17g %.17g %.17g %.17g %.17g %.17g\n" % tuple(r + e))


# LAMMPS 2021's lj/cut/dipole/long computes erfc(x) with the approximation of Abramowitz & Stegun
# 7.1.26 (|error| <= 1.5e-7), t = 1 / (1 + p x): erfc = t (a1 + t (a2 + t (a3 + t (a4 + t a5)))) e^{-x^2};
# its constants (pair_lj_cut_dipole_long.cpp, EWALD_P, A1..A5):
AS_P, AS_A = 0.3275911, (0.254829592, -0.284496736, 1.421413741, -1.453152027, 1.061405429)


def erfc_lammps(x, ex):
    t = 1.0 / (1.0 + AS_P * x)
    return t * (AS_A[0] + t * (AS_A[1] + t * (AS_A[2] + t * (AS_A[3] + t * AS_A[4])))) * ex


def real_space(L, mu, pos, axes, alpha, rc, approx):
    """The real-space dipolar Ewald sum (docs/interactions.md) in numpy: energy, forces, torques,
    with the exact erfc or (approx) LAMMPS's.  Used to show how much of the difference between the
    codes is LAMMPS's erfc."""
    import numpy as np
    x = np.array(pos)
    m = mu * np.array(axes)
    n = len(pos)
    i, j = np.triu_indices(n, 1)
    r = x[i] - x[j]
    r -= L * np.round(r / L)
    r2 = (r * r).sum(1)
    keep = r2 < rc * rc
    i, j, r, r2 = i[keep], j[keep], r[keep], r2[keep]
    rr = np.sqrt(r2)
    ex = np.exp(-alpha * alpha * r2)
    ec = erfc_lammps(alpha * rr, ex) if approx else np.array([math.erfc(v) for v in alpha * rr])
    sp = math.sqrt(math.pi)
    B0 = ec / rr
    B1 = (B0 + 2 * alpha / sp * ex) / r2
    B2 = (3 * B1 + 4 * alpha ** 3 / sp * ex) / r2
    B3 = (5 * B2 + 8 * alpha ** 5 / sp * ex) / r2
    mi, mj = m[i], m[j]
    mir, mjr, mm = (mi * r).sum(1), (mj * r).sum(1), (mi * mj).sum(1)
    U = (mm * B1 - mir * mjr * B2).sum()
    fi = ((mm * B2 - mir * mjr * B3)[:, None] * r + B2[:, None] * (mjr[:, None] * mi + mir[:, None] * mj))
    Ei = B2[:, None] * mjr[:, None] * r - B1[:, None] * mj
    Ej = B2[:, None] * mir[:, None] * r - B1[:, None] * mi
    F = np.zeros((n, 3))
    T = np.zeros((n, 3))
    np.add.at(F, i, fi)
    np.add.at(F, j, -fi)
    np.add.at(T, i, np.cross(mi, Ei))
    np.add.at(T, j, np.cross(mj, Ej))
    return U, F.tolist(), T.tolist()


def run_lammps(lmp, work, L, mu, pos, axes, alpha, K):
    data = os.path.join(work, "data.lmp")
    with open(data, "w") as f:
        f.write("rotleap Stockmayer configuration\n\n%d atoms\n1 atom types\n\n" % len(pos))
        for c in "xyz":
            f.write("0 %.17g %slo %shi\n" % (L, c, c))
        f.write("\nMasses\n\n1 1.0\n\nAtoms # hybrid\n\n")
        for i, (r, e) in enumerate(zip(pos, axes)):
            # id type x y z | sphere: diameter density | dipole: q mux muy muz
            f.write("%d 1 %.17g %.17g %.17g 1.0 1.9098593171027440 0.0 %.17g %.17g %.17g\n"
                    % (i + 1, r[0], r[1], r[2], mu * e[0], mu * e[1], mu * e[2]))
    inp = os.path.join(work, "in.lmp")
    with open(inp, "w") as f:
        f.write("""units lj
atom_style hybrid sphere dipole
boundary p p p
read_data %s
pair_style lj/cut/dipole/long %.17g %.17g
pair_coeff 1 1 0.0 1.0
kspace_style ewald/dipole 1e-6
kspace_modify gewald %.17g kmax/ewald %d %d %d
compute tq all property/atom tqx tqy tqz
thermo_style custom step pe evdwl ecoul elong
thermo_modify norm no format float %%.17g
dump d all custom 1 %s/dump.txt id fx fy fz c_tq[1] c_tq[2] c_tq[3]
dump_modify d format float %%.17g sort id
run 0
""" % (data, RC, RC, alpha, K, K, K, work))
    p = subprocess.run([lmp, "-in", inp, "-log", os.path.join(work, "log.lammps"), "-screen", "none", "-nocite"],
                       capture_output=True, text=True)
    log = open(os.path.join(work, "log.lammps")).read()
    if p.returncode:
        raise RuntimeError("lmp failed: %s\n%s" % (p.stderr, log[-2000:]))
    lines = log.splitlines()
    head = next(i for i, l in enumerate(lines) if l.split()[:5] == ["Step", "PotEng", "E_vdwl", "E_coul", "E_long"])
    v = [float(x) for x in lines[head + 1].split()]
    energy = {"pe": v[1], "evdwl": v[2], "ecoul": v[3], "elong": v[4]}
    dump = open(os.path.join(work, "dump.txt")).read().splitlines()
    start = next(i for i, l in enumerate(dump) if l.startswith("ITEM: ATOMS")) + 1
    F, T = [], []
    for l in dump[start:start + len(pos)]:
        w = [float(x) for x in l.split()]
        F.append(w[1:4])
        T.append(w[4:7])
    gl = [l for l in lines if "G vector" in l or "KSpace vectors" in l]
    return energy, F, T, gl


def run_rotleap(driver, work, L, mu, pos, axes, alpha, K):
    cfg = os.path.join(work, "config.txt")
    write_config(cfg, L, mu, pos, axes)
    args = ["--dipoles", cfg, "--method", "ewald", "--cutoff", repr(RC), "--alpha", repr(alpha),
            "--kmax", str(K), str(K), str(K), "--kmax-sq", str(K * K), "--tolerance", "0.05"]
    p = subprocess.run([driver] + args, capture_output=True, text=True)
    if p.returncode:
        raise RuntimeError("ewald_point failed: %s" % p.stderr)
    return json.loads(p.stdout), args


def rms_rel(a, b):
    num = sum((x - y) ** 2 for ra, rb in zip(a, b) for x, y in zip(ra, rb))
    return math.sqrt(num / sum(y * y for rb in b for y in rb))


def compare(out, c):
    """rotleap's output (ewald_point's JSON) against a case's LAMMPS numbers: as they are, and with
    the real-space difference between LAMMPS's erfc and the exact one (c["erfc_correction"]) added to
    rotleap's.  Returns (ok, row) -- the same function is in tests/forces/ewald/check_ewald_lammps.py."""
    e, ref, cor = out["energy"], c["energy"], c["erfc_correction"]
    scale = abs(ref["ecoul"]) + abs(ref["elong"])
    recip = e["ewald_recip"] + e["ewald_self"] + e["ewald_intra"] + e["ewald_background"] + e["ewald_surface"]
    F = [m["force"] for m in out["molecules"]]
    T = [m["torque"] for m in out["molecules"]]
    Fc = [[a + b for a, b in zip(x, y)] for x, y in zip(F, cor["forces"])]
    Tc = [[a + b for a, b in zip(x, y)] for x, y in zip(T, cor["torques"])]
    d = {"dU": abs(e["total"] - ref["pe"]) / abs(ref["pe"]), "dU_scale": abs(e["total"] - ref["pe"]) / scale,
         "dF": rms_rel(F, c["forces"]), "dT": rms_rel(T, c["torques"]),
         "dU_c": abs(e["total"] + cor["energy"] - ref["pe"]) / abs(ref["pe"]),
         "dreal_c": abs(e["ewald_real"] + cor["energy"] - ref["ecoul"]) / scale,
         "drecip": abs(recip - ref["elong"]) / scale,
         "dF_c": rms_rel(Fc, c["forces"]), "dT_c": rms_rel(Tc, c["torques"])}
    ok = (len(F) == len(c["forces"]) and d["dU_scale"] <= TOL["plain"] and d["dF"] <= TOL["plain"] and d["dT"] <= TOL["plain"]
          and all(d[k] <= TOL["same_erfc"] for k in ("dU_c", "dreal_c", "drecip", "dF_c", "dT_c")))
    row = ("%-36s U %.10g (LAMMPS %.10g): dU %.1e (%.1e of |real|+|recip|), dF %.1e, dT %.1e; with LAMMPS's erfc: "
           "dU %.1e, d(real) %.1e, d(recip+self) %.1e, dF %.1e, dT %.1e  %s"
           % (c["case"], e["total"], ref["pe"], d["dU"], d["dU_scale"], d["dF"], d["dT"], d["dU_c"], d["dreal_c"],
              d["drecip"], d["dF_c"], d["dT_c"], "ok" if ok else "FAIL"))
    return ok, row


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--driver", default=os.path.join(SRC, "build", "tests", "forces", "ewald", "ewald_point"))
    ap.add_argument("--lmp", default="/usr/bin/lmp")
    ap.add_argument("--no-write", action="store_true")
    a = ap.parse_args()
    mu = math.sqrt(MU2)
    cases, rows, failures = [], [], 0
    for ncell, seed in [(3, 108), (4, 256)]:
        L, pos, axes = fcc(ncell, RHO, seed)
        for name, arc, K in [("tight", 4.5, 14), ("loose", 3.0, 6)]:
            alpha = arc / RC
            with tempfile.TemporaryDirectory() as work:
                energy, F, T, gl = run_lammps(a.lmp, work, L, mu, pos, axes, alpha, K)
                out, args = run_rotleap(a.driver, work, L, mu, pos, axes, alpha, K)
            Ue, Fe, Te = real_space(L, mu, pos, axes, alpha, RC, False)
            Ua, Fa, Ta = real_space(L, mu, pos, axes, alpha, RC, True)
            label = "N=%d %s (alpha %.4g, rc %.4g, K %d)" % (len(pos), name, alpha, RC, K)
            c = {"case": label, "count": len(pos), "box": L, "mu": mu, "alpha": alpha, "cutoff": RC, "kmax": K,
                 "args": args[2:], "positions": pos, "axes": axes, "energy": energy, "forces": F, "torques": T,
                 "erfc_correction": {"energy": Ua - Ue,
                                     "forces": [[a - b for a, b in zip(x, y)] for x, y in zip(Fa, Fe)],
                                     "torques": [[a - b for a, b in zip(x, y)] for x, y in zip(Ta, Te)]}}
            ok, row = compare(out, c)
            failures += not ok
            rows.append(row)
            print(row, flush=True)
            cases.append(c)
    ver = subprocess.run([a.lmp, "-h"], capture_output=True, text=True).stdout.splitlines()
    version = next(("LAMMPS (%s)" % l.split(" - ", 1)[1].strip() for l in ver if "Simulator - " in l), "LAMMPS")
    summary = ("rotleap ewald-real + ewald against %s ewald/dipole + lj/cut/dipole/long (LJ epsilon 0), run 0;\n"
               "Stockmayer, rho* %.2g, mu*^2 %.3g, tin foil.  Criteria: as they are, energy (relative to |ecoul| + |elong|),\n"
               "forces and torques (RMS relative) <= %.0e; with LAMMPS's erfc approximation (Abramowitz-Stegun 7.1.26)\n"
               "in rotleap's real space too (the difference computed in numpy), every number <= %.0e\n"
               % (version, RHO, MU2, TOL["plain"], TOL["same_erfc"])
               + "\n".join(rows) + "\n%d of %d cases agree\n" % (len(rows) - failures, len(rows)))
    print(summary.splitlines()[-1])
    if not a.no_write:
        os.makedirs(DATA, exist_ok=True)
        with gzip.open(os.path.join(DATA, "ewald_dipole_lammps.json.gz"), "wt") as f:
            json.dump({"lammps": version, "tolerance": TOL, "cases": cases}, f)
        with open(os.path.join(DATA, "ewald_dipole_lammps_summary.txt"), "w") as f:
            f.write(summary)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
