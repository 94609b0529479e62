#!/usr/bin/python3
"""Issue 35, acceptance 3: Stockmayer dipoles in a Lennard-Jones solvent (reduced units), a single
point of rotleap (`system.species`, Lorentz-Berthelot mixing) against LAMMPS `run 0`: energy,
forces and torques per molecule to 1e-12.

The configuration: 27 Stockmayer (mu* = sqrt 3, sigma = epsilon = 1) and 81 LJ atoms (sigma 1.2,
epsilon 0.8) at rho* = 0.8 on an fcc lattice, species shuffled, after 20 NVE steps at h = 0.002
from T* = 1.35 (rotleap's XYZ trajectory: centres to 10 decimals, dipole directions to 17 digits;
both codes read the same decimal text).  Plain truncation at rc = 2.5 of LJ and of the dipole-dipole
term: rotleap lj = plain, dipole = rf with eps_rf = 1; LAMMPS lj/cut/dipole/cut with the unlike
pair given explicitly (sigma 1.1, epsilon sqrt 0.8), atom_style hybrid sphere dipole.

    /usr/bin/python3 validate/mixture_lammps.py [--rotleap build/rotleap] [--write]
        runs rotleap and LAMMPS (lmp) and compares; --write stores the configuration
        (validate/data/mixture_lammps.xyz) and LAMMPS's numbers (validate/data/mixture_lammps.json)
    /usr/bin/python3 validate/mixture_lammps.py --check [--rotleap build/rotleap]
        CTest (cli_species_lammps): rotleap on the checked-in configuration against the
        checked-in LAMMPS numbers, without LAMMPS

Tolerance: |dE|/|E|, max |dF|/max |F| and max |dtau|/max |tau| below 1e-12 (round-off of sums over
~3000 pairs in two orders).  Standard library only.  About 5 s.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "data")
MU, RC = math.sqrt(3.0), 2.5
SOLVENT = (1.2, 0.8)  # sigma, epsilon
DECK = """[system]
species = stockmayer:27 lj:81
density = 0.8
lattice = fcc
temperature = 1.35
seed = 11
%s
[molecule lj]
units = lj
site = A 0 0 0 mass 1 sigma %r epsilon %r
[interactions]
cutoff = %r
lj = plain
dipole = rf
eps_rf = 1
[run]
steps = %d
timestep = 0.002
[output]
thermo_every = 10
trajectory_every = %d
progress = no
""" 
TOL = 1e-12


def sh(cmd, cwd=None):
    p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    if p.returncode:
        sys.exit("failed (%d): %s\n%s%s" % (p.returncode, " ".join(cmd), p.stdout, p.stderr))
    return p.stdout


def deck(start, steps, traj, box=None):
    text = DECK % ("start = " + start if start else "", SOLVENT[0], SOLVENT[1], RC, steps, traj)
    # the single point: the box as the XYZ file writes it (10 decimals), which LAMMPS gets too
    return text.replace("density = 0.8", "box = " + box) if box else text


def make_config(rl, tmp):
    path = os.path.join(tmp, "make.ini")
    open(path, "w").write(deck("", 20, 20))
    sh([rl, "run", path, "--set", "output.prefix=" + os.path.join(tmp, "make")])
    lines = open(os.path.join(tmp, "make.xyz")).read().splitlines()
    n = int(lines[0])
    return "\n".join(lines[:n + 2]) + "\n"  # the frame at step 20


def parse_xyz(text):
    lines = text.splitlines()
    n = int(lines[0])
    lat = lines[1].split('Lattice="')[1].split('"')[0].split()
    L = [float(lat[0]), float(lat[4]), float(lat[8])]
    bodies = []
    for ln in lines[2:2 + n]:
        t = ln.split()
        bodies.append((t[-1], [t[1], t[2], t[3]], [t[4], t[5], t[6]]))  # name, centre, axis (text)
    return L, bodies


def rotleap(rl, xyz_path, tmp):
    path = os.path.join(tmp, "point.ini")
    lat = open(xyz_path).read().splitlines()[1].split('Lattice="')[1].split('"')[0].split()
    open(path, "w").write(deck(xyz_path, 0, 0, "%s %s %s" % (lat[0], lat[4], lat[8])))
    E = json.loads(sh([rl, "energy", path, "--json", "--set", "output.prefix=" + os.path.join(tmp, "point")]))
    return {"energy": E["energy"]["total"], "force": [m["force"] for m in E["molecules"]],
            "torque": [m["torque"] for m in E["molecules"]]}


def lammps(xyz_text, tmp):
    L, bodies = parse_xyz(xyz_text)
    data = os.path.join(tmp, "mix.data")
    with open(data, "w") as g:
        g.write("rotleap mixture\n\n%d atoms\n2 atom types\n\n" % len(bodies))
        for c, ax in enumerate("xyz"):
            g.write("0 %.17g %slo %shi\n" % (L[c], ax, ax))
        g.write("\nAtoms # hybrid sphere dipole\n\n")
        for i, (name, r, u) in enumerate(bodies):
            dip = [MU * float(x) for x in u] if name == "stockmayer" else [0.0, 0.0, 0.0]
            g.write("%d %d %s %s %s 1 1.9098593171027443 0 %.17g %.17g %.17g\n" % (
                i + 1, 1 if name == "stockmayer" else 2, r[0], r[1], r[2], dip[0], dip[1], dip[2]))
    inp = """units lj
atom_style hybrid sphere dipole
atom_modify map array
boundary p p p
read_data %s
pair_style lj/cut/dipole/cut %r
pair_coeff 1 1 1.0 1.0
pair_coeff 2 2 %r %r
pair_coeff 1 2 %r %r
compute pe all pe/atom
compute sum all reduce sum c_pe
thermo_style custom step pe c_sum
thermo_modify norm no format float %%.17g
dump d all custom 1 %s id fx fy fz tqx tqy tqz c_pe
dump_modify d sort id format float %%.17g
run 0
""" % (data, RC, SOLVENT[1], SOLVENT[0], math.sqrt(SOLVENT[1]), 0.5 * (1.0 + SOLVENT[0]), os.path.join(tmp, "mix.dump"))
    open(os.path.join(tmp, "mix.in"), "w").write(inp)
    sh(["lmp", "-in", "mix.in", "-log", "mix.log", "-screen", "none"], cwd=tmp)
    rows = open(os.path.join(tmp, "mix.dump")).read().splitlines()
    k = rows.index(next(r for r in rows if r.startswith("ITEM: ATOMS")))
    force, torque, pe = [], [], []
    for r in rows[k + 1:]:
        t = r.split()
        force.append([float(x) for x in t[1:4]])
        torque.append([float(x) for x in t[4:7]])
        pe.append(float(t[7]))
    return {"energy": math.fsum(pe), "force": force, "torque": torque,
            "lammps": subprocess.run(["lmp", "-h"], capture_output=True, text=True).stdout.split("\n")[1].strip()}


def compare(a, b):
    dE = abs(a["energy"] - b["energy"]) / abs(b["energy"])
    def rel(key):
        m = max(abs(x) for v in b[key] for x in v)
        return max(abs(x - y) for u, v in zip(a[key], b[key]) for x, y in zip(u, v)) / m
    rows = [("energy", dE), ("forces", rel("force")), ("torques", rel("torque"))]
    ok = len(a["force"]) == len(b["force"]) and all(d < TOL for _, d in rows)
    for name, d in rows:
        print("%-8s rotleap vs LAMMPS: %.3e relative (tolerance %g) %s" % (name, d, TOL, "ok" if d < TOL else "FAIL"))
    return ok


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rotleap", default=os.path.join(os.path.dirname(HERE), "build", "rotleap"))
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--write", action="store_true")
    a = ap.parse_args()
    rl = os.path.abspath(a.rotleap)
    xyz_path, json_path = os.path.join(DATA, "mixture_lammps.xyz"), os.path.join(DATA, "mixture_lammps.json")
    with tempfile.TemporaryDirectory() as tmp:
        if a.check:
            ref = json.load(open(json_path))
            print("checked-in LAMMPS numbers (%s)" % ref.get("lammps", "?"))
            sys.exit(0 if compare(rotleap(rl, xyz_path, tmp), ref) else 1)
        xyz = make_config(rl, tmp)
        p = os.path.join(tmp, "mix.xyz")
        open(p, "w").write(xyz)
        lr = lammps(xyz, tmp)
        ok = compare(rotleap(rl, p, tmp), lr)
        if a.write:
            open(xyz_path, "w").write(xyz)
            json.dump(lr, open(json_path, "w"), indent=0)
            print("wrote", xyz_path, json_path)
        sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
