#!/usr/bin/python3
"""rotleap's pressure (virial) against LAMMPS (Debian `lammps`, /usr/bin/lmp), about 1 minute.

    /usr/bin/python3 validate/lammps_pressure.py [--rotleap build/rotleap] [--out DIR]
                                                [--nve-steps 20000]

Prints a table (and writes it to validate/lammps_pressure.md with --md).  Every rotleap output
goes under --out (default /tmp/rotleap_validate/lammps_pressure); nothing is written into the tree.

A. Stockmayer (256, rho* = 0.8, T* = 1.35, mu*^2 = 3, rc = 2.5, plain truncation of LJ and
   dipole: rotleap lj = plain, dipole = rf with eps_rf = 1; LAMMPS lj/cut/dipole/cut).  One
   liquid configuration with velocities from a rotleap checkpoint:
   - virial part W/(3V): rotleap `energy` (virial trace) against LAMMPS `compute pressure NULL
     virial`;
   - kinetic part: rotleap's thermo row at the checkpoint's step uses the on-step velocities
     v(t) = v(t-h/2) + (h/2) F(t)/m (eq. 9); LAMMPS is given exactly those, so its `press` is
     compared with that row (printed to 10 digits) and its `ke` with the row's ke_trans;
   - `rotleap energy` on the same checkpoint completes the stored half-step v(t-h/2) to on-step
     with run.timestep (since 568d3b8; before, it took them as they were): its pressure is
     checked against the row's and against (2 K(v(t)) + tr W)/(3V).
   - the LJ tail (dispersion_correction) against (16/3) pi rho^2 eps sigma^3 [(2/3)(s/rc)^9 -
     (s/rc)^3] with N(N-1) pairs.
B. 2CLJ (256, L* = 0.5, rho* = 0.5, T* ~ 2, rc = 3, plain LJ, site cutoff).  LAMMPS: 2 atoms of
   mass 0.5 per molecule, neigh_modify exclude molecule/intra all, fix rigid/nve molecule.
   - single configuration: the molecular virial W_mol = sum_pairs R_ij . f_ij.  From LAMMPS it is
     W_site - sum_a d_a . f_a (W_site = 3V * `compute pressure NULL pair`, f_a the dumped
     per-atom forces, d_a = site - centre of mass of its molecule, from unwrapped coordinates).
     This identity holds with periodic images because each site pair's R_ij is the centre
     separation of the image that pair used.  Checked against rotleap's tr W and against an
     independent numpy pair sum.  (sum_i R_i . F_i over unwrapped centres is NOT the periodic
     molecular virial; its value is printed to show by how much it misses.)
   - LAMMPS's own `press` with fix rigid: kinetic sum_atoms m v^2 (translation + rotation) +
     W_site + the fix's constraint virial, which fix rigid estimates from the velocity change of
     each half kick (at `run 0` a set-up guess).  So LAMMPS reports the atomic pressure; rotleap
     the molecular one, (2 K_trans + W_mol)/(3V).
   - NVE from the same state in both codes (--nve-steps at h = 0.002): time averages of
     rotleap's P, LAMMPS's press, and the molecular pressure recomputed from LAMMPS's dumps.
   - LJ tail: rotleap (4 N(N-1) site pairs) against LAMMPS `pair_modify tail yes` (4 N^2).
C. CO2 (EPM2, real units, 256 at 1.06 g/cm3, rc = 1 nm, plain LJ, Coulomb with eps_rf = 1,
   i.e. forces of a plain cut Coulomb: LAMMPS lj/cut/coul/cut, units real) from a checkpoint at
   rest (v(t-h/2) = 0, completed by `rotleap energy` to v(t) = (h/2) F/m): the pressure in bar
   that `rotleap energy` prints against LAMMPS's molecular virial pressure plus that kinetic
   part, in atm x 1.01325.  Checks the kJ mol^-1 nm^-3 -> bar factor end to end.
"""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import rlcheckpoint  # noqa: E402

NICE = ["nice", "-n", "15"]
ROWS = []          # (case, quantity, rotleap, lammps/reference, diff, tolerance, verdict)
NOTES = []


def row(case, what, a, b, tol, scale=None, rel=False, info_only=False):
    """One table row: |a - b| <= tol (absolute, or relative to |b| or to scale)."""
    d = a - b
    if rel:
        err = abs(d) / abs(b if scale is None else scale)
    else:
        err = abs(d)
    ok = "info" if info_only or tol is None else ("ok" if err <= tol else "FAIL")
    ROWS.append((case, what, a, b, err, tol, ok, "rel" if rel else "abs"))
    return ok


def sh(cmd, cwd=None):
    p = subprocess.run(NICE + cmd, cwd=cwd, capture_output=True, text=True)
    if p.returncode:
        sys.stderr.write("command failed: %s\n%s\n%s\n" % (" ".join(cmd), p.stdout[-3000:], p.stderr[-3000:]))
        raise SystemExit(1)
    return p.stdout


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def thermo_rows(path):
    with open(path) as f:
        head = f.readline().strip().split(",")
        return [dict(zip(head, (float(x) for x in line.split(",")))) for line in f if line.strip()]


# ---------------------------------------------------------------- rotleap

def rl_run(rl, deck, prefix, sets=()):
    cmd = [rl, "run", deck, "--set", "output.prefix=" + prefix, "--set", "output.progress=no"]
    for s in sets:
        cmd += ["--set", s]
    sh(cmd)
    return thermo_rows(prefix + ".thermo.csv")


def rl_energy(rl, deck, prefix, start, sets=()):
    cmd = [rl, "energy", deck, "--json", "--set", "output.prefix=" + prefix, "--set", "system.start=" + start]
    for s in sets:
        cmd += ["--set", s]
    return json.loads(sh(cmd))


def state(ck, E, h):
    """Centres, axes (linear/dipole bodies), half-step and on-step v and l, forces, torques."""
    sp = ck["species"][0]
    m = sp["mass"]
    r = np.array(ck["r"])
    vh = np.array(ck["v"])
    lh = np.array(ck["l"]) if ck["nrot"] else np.zeros((0, 3))
    F = np.array([mo["force"] for mo in E["molecules"]])
    K = np.array([mo["torque"] for mo in E["molecules"]])
    st = {"m": m, "r": r, "vh": vh, "lh": lh, "F": F, "K": K, "box": np.array(ck["box"]),
          "step": ck["step"], "sites": np.array(sp["sites"]), "J": np.array(sp["moments"])}
    st["rho"] = np.array(ck["rho"]) if ck["naxis"] else None
    st["von"] = vh + 0.5 * h * F / m
    st["lon"] = lh + 0.5 * h * K if ck["nrot"] else lh
    st["W"] = np.array(E["virial"]).reshape(3, 3)
    return st


def rotleap_state(rl, out, name, deck_text, h):
    """Run the deck under out/name, then read its checkpoint and evaluate it: (deck path, checkpoint
    path, the last thermo row, the checkpoint, `rotleap energy` of it, state())."""
    deck = os.path.join(out, name + ".ini")
    write(deck, deck_text)
    last = rl_run(rl, deck, os.path.join(out, name))[-1]
    chk = os.path.join(out, name + ".chk")
    ck = rlcheckpoint.read(chk)
    E = rl_energy(rl, deck, os.path.join(out, name + "_e"), chk)
    return deck, chk, last, ck, E, state(ck, E, h)


def site_positions(st):
    """Lab sites of axis bodies (linear molecules): r + z_a rho (body-frame sites on Z)."""
    d = st["sites"]
    assert np.allclose(d[:, :2], 0.0), "sites not on the body Z axis"
    return st["r"][:, None, :] + d[None, :, 2, None] * st["rho"][:, None, :]


# ---------------------------------------------------------------- LAMMPS

def lmp(inp, tmp, name):
    path = os.path.join(tmp, name + ".in")
    write(path, inp)
    log = os.path.join(tmp, name + ".log")
    sh(["lmp", "-in", path, "-log", log, "-screen", "none"], cwd=tmp)
    rows, head = [], None
    for line in open(log):
        t = line.split()
        if t and t[0] == "Step":
            head = t
            continue
        if head and len(t) == len(head) and re.match(r"^-?\d+$", t[0]):
            rows.append(dict(zip(head, (float(x) for x in t))))
        elif head and t[:2] == ["Loop", "time"]:
            head = None
    return rows


def read_dump(path):
    """Frames of a LAMMPS custom dump, each {step, cols: array sorted by id}."""
    frames = []
    with open(path) as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines):
        if lines[i].startswith("ITEM: TIMESTEP"):
            step = int(lines[i + 1])
            n = int(lines[i + 3])
            names = lines[i + 8].split()[2:]
            data = np.array([[float(x) for x in lines[i + 9 + k].split()] for k in range(n)])
            data = data[np.argsort(data[:, names.index("id")])]
            frames.append((step, {c: data[:, j] for j, c in enumerate(names)}))
            i += 9 + n
        else:
            i += 1
    return frames


def molecular_virial_from_dump(fr, nper, mass):
    """W_mol + the centre-of-mass kinetic part from one frame (atoms of a molecule consecutive)."""
    x = np.stack([fr["xu"], fr["yu"], fr["zu"]], 1).reshape(-1, nper, 3)
    f = np.stack([fr["fx"], fr["fy"], fr["fz"]], 1).reshape(-1, nper, 3)
    w = np.asarray(mass)[None, :, None]
    com = (w * x).sum(1) / w.sum(1)
    d = x - com[:, None, :]
    dsum = float((d * f).sum())                      # sum_a d_a . f_a
    naive = float((com * f.sum(1)).sum())            # sum_i R_i . F_i, unwrapped centres
    ke = None
    if "vx" in fr:
        v = np.stack([fr["vx"], fr["vy"], fr["vz"]], 1).reshape(-1, nper, 3)
        vcm = (w * v).sum(1) / w.sum(1)
        ke = 0.5 * float(w.sum()) * float((vcm * vcm).sum())   # w.sum(): the mass of one molecule
    return dsum, naive, ke


# ---------------------------------------------------------------- independent pair sum

def lj_virial_numpy(sites, box, rc, eps=1.0, sig=1.0):
    """Plain-cut LJ between sites of different molecules, site cutoff, minimum image per site
    pair.  Returns U, site forces, W_site = sum r.f, W_mol = sum R.f (R = r - d_a + d_b)."""
    n, ns, _ = sites.shape
    flat = sites.reshape(-1, 3)
    mol = np.repeat(np.arange(n), ns)
    centre = sites.mean(1)  # equal site masses
    d = (sites - centre[:, None, :]).reshape(-1, 3)
    U = Wsite = Wmol = 0.0
    f = np.zeros_like(flat)
    for a in range(len(flat) - 1):
        r = flat[a] - flat[a + 1:]
        r -= box * np.round(r / box)
        r2 = (r * r).sum(1)
        keep = (r2 < rc * rc) & (mol[a + 1:] != mol[a])
        r, r2 = r[keep], r2[keep]
        idx = np.nonzero(keep)[0] + a + 1
        s6 = (sig * sig / r2) ** 3
        U += float((4 * eps * (s6 * s6 - s6)).sum())
        fs = 24 * eps * (2 * s6 * s6 - s6) / r2
        fab = fs[:, None] * r
        f[a] += fab.sum(0)
        np.subtract.at(f, idx, fab)
        Wsite += float((r * fab).sum())
        R = r - d[a] + d[idx]
        Wmol += float((R * fab).sum())
    return U, f.reshape(n, ns, 3), Wsite, Wmol, d.reshape(n, ns, 3)


def blocks(x, nb=20):
    x = np.asarray(x, float)
    m = len(x) // nb
    b = x[:m * nb].reshape(nb, m).mean(1)
    return float(x.mean()), float(b.std(ddof=1) / math.sqrt(nb))


# ---------------------------------------------------------------- A. Stockmayer

SM_DECK = """[system]
model = stockmayer
count = 256
density = 0.8
orientations = random
temperature = 1.35
seed = 7
[model]
mu = 1.7320508075688772
inertia = 0.025
[interactions]
cutoff = 2.5
lj = plain
dipole = rf
eps_rf = 1
[run]
ensemble = nve
timestep = 0.002
steps = 200
equilibrate = 2000
equilibrate_timestep = 0.001
[output]
thermo_every = 50
sample_every = 0
"""


def stockmayer(rl, out):
    h, rc, mu, diam = 0.002, 2.5, math.sqrt(3.0), 0.5
    deck, chk, last, ck, E, st = rotleap_state(rl, out, "sm", SM_DECK, h)
    assert int(last["step"]) == st["step"]
    n, L = len(st["r"]), st["box"]
    V = float(np.prod(L))
    trW = float(np.trace(st["W"]))
    Kh = 0.5 * st["m"] * float((st["vh"] ** 2).sum())
    Kon = 0.5 * st["m"] * float((st["von"] ** 2).sum())
    # LAMMPS: on-step velocities; sphere of diameter 0.5 and density 6/pi/d^3 -> mass 1
    data = os.path.join(out, "sm.data")
    dens = 1.0 / (math.pi / 6.0 * diam ** 3)
    with open(data, "w") as g:
        g.write("Stockmayer from rotleap %s\n\n%d atoms\n1 atom types\n\n" % (chk, n))
        for c, ax in enumerate("xyz"):
            g.write("0 %.17g %slo %shi\n" % (L[c], ax, ax))
        g.write("\nAtoms # hybrid sphere dipole\n\n")
        for i in range(n):
            p = st["r"][i] - L * np.floor(st["r"][i] / L)
            u = st["rho"][i]
            g.write("%d 1 %.17g %.17g %.17g %.17g %.17g 0 %.17g %.17g %.17g\n" % (
                i + 1, p[0], p[1], p[2], diam, dens, mu * u[0], mu * u[1], mu * u[2]))
        g.write("\nVelocities\n\n")
        for i in range(n):
            v = st["von"][i]
            g.write("%d %.17g %.17g %.17g 0 0 0\n" % (i + 1, v[0], v[1], v[2]))
    inp = """units lj
atom_style hybrid sphere dipole
boundary p p p
read_data %s
pair_style lj/cut/dipole/cut %g
pair_coeff * * 1.0 1.0
fix 1 all nve/sphere update dipole
compute pvir all pressure NULL virial
compute ppair all pressure NULL pair
thermo_style custom step pe ke press c_pvir c_ppair vol
thermo_modify norm no format float %%.17g
run 0
""" % (data, rc)
    lr = lmp(inp, out, "sm")[0]
    case = "A Stockmayer"
    scale = n / V * 1.35                         # rho kT: the natural pressure scale
    row(case, "U (sanity)", E["energy"]["total"], lr["PotEng"], 1e-10, rel=True)
    row(case, "V", V, lr["Volume"], 1e-12, rel=True)
    row(case, "virial part tr W/3V vs c_pvir", trW / (3 * V), lr["c_pvir"], 1e-10, scale=scale, rel=True)
    row(case, "c_pair = c_pvir (no fix virial)", lr["c_ppair"], lr["c_pvir"], 1e-13, scale=scale, rel=True)
    row(case, "K_trans on-step: row vs LAMMPS ke", last["ke_trans"], lr["KinEng"], 1e-9, rel=True)
    row(case, "K_trans on-step: row vs v(t-h/2)+hF/2m", last["ke_trans"], Kon, 1e-9, rel=True)
    row(case, "LAMMPS press - c_pvir = 2K/3V", lr["Press"] - lr["c_pvir"], 2 * lr["KinEng"] / (3 * V), 1e-12, rel=True)
    row(case, "P: thermo row (%.10g) vs LAMMPS press", last["pressure"], lr["Press"], 1e-9, rel=True)
    row(case, "P: energy cmd vs (2K(v(t))+trW)/3V", E["pressure"], (2 * Kon + trW) / (3 * V), 1e-12, scale=scale, rel=True)
    row(case, "P: energy cmd vs thermo row", E["pressure"], last["pressure"], 1e-9, rel=True)
    NOTES.append("A: with the stored half-step v(t-h/2), as `rotleap energy` took them before 568d3b8, the "
                 "kinetic part would be off by 2[K(t-h/2) - K(t)]/(3V) = %.3e." % (2 * (Kh - Kon) / (3 * V)))
    # the LJ tail
    E2 = rl_energy(rl, deck, os.path.join(out, "sm_e2"), chk, ["interactions.dispersion_correction=yes"])
    Pt = (float(np.trace(np.array(E2["virial"]).reshape(3, 3))) - trW) / (3 * V)
    x = 1.0 / rc
    Pform = 16.0 / 3.0 * math.pi * n * (n - 1) / V ** 2 * ((2.0 / 3.0) * x ** 9 - x ** 3)
    row(case, "P_tail vs (16/3)pi N(N-1)/V^2 [..]", Pt, Pform, 1e-12, rel=True)
    return st


# ---------------------------------------------------------------- B. 2CLJ

C2_DECK = """[system]
model = 2clj
count = 256
density = 0.5
orientations = random
temperature = 2.0
seed = 5
[model]
elongation = 0.5
[interactions]
cutoff = 3.0
lj = plain
scheme = site
[run]
ensemble = nve
timestep = 0.002
steps = 200
equilibrate = 3000
equilibrate_timestep = 0.001
[output]
thermo_every = 10
sample_every = 0
"""


def c2_data(st, path, vel):
    n, L = len(st["r"]), st["box"]
    sites = site_positions(st)                       # (n, 2, 3), whole molecules
    rho, d = st["rho"], st["sites"][:, 2]
    J = st["J"][0]
    lines = ["2CLJ from rotleap\n", "%d atoms\n1 atom types\n" % (2 * n)]
    lines.append("".join("0 %.17g %slo %shi\n" % (L[c], ax, ax) for c, ax in enumerate("xyz")))
    lines.append("Masses\n\n1 0.5\n")
    at, vs = ["Atoms # molecular"], ["Velocities"]
    maxpar = 0.0
    for i in range(n):
        l = st["lon"][i] if vel == "on" else st["lh"][i]
        v = st["von"][i] if vel == "on" else st["vh"][i]
        maxpar = max(maxpar, abs(float(l @ rho[i])))
        w = (l - (l @ rho[i]) * rho[i]) / J            # linear body: omega = l_perp / J_perp
        for a in range(2):
            p = sites[i, a]
            img = np.floor(p / L)
            q = p - img * L
            k = 2 * i + a + 1
            at.append("%d %d 1 %.17g %.17g %.17g %d %d %d" % (k, i + 1, q[0], q[1], q[2], img[0], img[1], img[2]))
            va = v + np.cross(w, d[a] * rho[i])
            vs.append("%d %.17g %.17g %.17g" % (k, va[0], va[1], va[2]))
    write(path, "\n".join(lines) + "\n" + "\n".join(at[:1] + [""] + at[1:]) + "\n\n" +
          "\n".join(vs[:1] + [""] + vs[1:]) + "\n")
    return maxpar


def c2_input(data, rc, steps, every, dump, tail=False):
    return """units lj
atom_style molecular
boundary p p p
read_data %s
pair_style lj/cut %g
pair_coeff 1 1 1.0 1.0
pair_modify tail %s
neighbor 0.3 bin
neigh_modify exclude molecule/intra all delay 0 every 1 check yes
fix 1 all rigid/nve molecule
compute pvir all pressure NULL virial
compute ppair all pressure NULL pair
thermo_style custom step pe ke etotal press c_pvir c_ppair vol
thermo_modify norm no format float %%.17g
thermo %d
dump d all custom %d %s id mol xu yu zu fx fy fz vx vy vz
dump_modify d sort id format float %%.17g
timestep 0.002
run %d
""" % (data, rc, "yes" if tail else "no", every, every, dump, steps)


def twoclj(rl, out, nve_steps):
    h, rc = 0.002, 3.0
    deck, chk, last, ck, E, st = rotleap_state(rl, out, "c2", C2_DECK, h)
    n, L = len(st["r"]), st["box"]
    V = float(np.prod(L))
    trW = float(np.trace(st["W"]))
    case = "B 2CLJ"
    scale = n / V * 2.0
    # independent numpy pair sum
    U_np, f_np, Wsite_np, Wmol_np, d_np = lj_virial_numpy(site_positions(st), L, rc)
    row(case, "U: rotleap vs numpy", E["energy"]["total"], U_np, 1e-11, rel=True)
    row(case, "tr W: rotleap vs numpy sum R.f", trW, Wmol_np, 1e-10, scale=3 * V * scale, rel=True)
    row(case, "numpy: W_site - sum d.f = sum R.f", Wsite_np - float((d_np * f_np).sum()), Wmol_np, 1e-10,
        scale=3 * V * scale, rel=True)
    # LAMMPS, single configuration (run 0), on-step velocities
    data = os.path.join(out, "c2_on.data")
    maxpar = c2_data(st, data, "on")
    dump0 = os.path.join(out, "c2_0.dump")
    lr = lmp(c2_input(data, rc, 0, 1, dump0), out, "c2_0")[0]
    fr = read_dump(dump0)[0][1]
    dsum, naive, ke_cm = molecular_virial_from_dump(fr, 2, [0.5, 0.5])
    Wsite = 3 * V * lr["c_ppair"]
    Wmol = Wsite - dsum
    row(case, "U: rotleap vs LAMMPS pe", E["energy"]["total"], lr["PotEng"], 1e-11, rel=True)
    row(case, "W_site: numpy vs LAMMPS 3V c_pair", Wsite_np, Wsite, 1e-10, scale=3 * V * scale, rel=True)
    row(case, "molecular virial/3V: rotleap vs LAMMPS", trW / (3 * V), Wmol / (3 * V), 1e-10, scale=scale, rel=True)
    row(case, "K_trans(t): row vs LAMMPS COM velocities", last["ke_trans"], ke_cm, 1e-9, rel=True)
    row(case, "P_mol(t): row (%.10g) vs LAMMPS-derived", last["pressure"], (2 * ke_cm + Wmol) / (3 * V), 1e-9, rel=True)
    row(case, "naive sum R_i.F_i (unwrapped)/3V vs W_mol/3V", naive / (3 * V), Wmol / (3 * V), None,
        rel=True, info_only=True, scale=scale)
    row(case, "LAMMPS press at run 0 (set-up guess) vs P_mol", lr["Press"], (2 * ke_cm + Wmol) / (3 * V), None,
        rel=True, info_only=True)
    row(case, "LAMMPS ke (atoms) vs K_trans + K_rot (row)", lr["KinEng"], last["ke_trans"] + last["ke_rot"], 1e-9, rel=True)
    NOTES.append("B: max |l . rho| of the linear bodies (must be 0): %.2e; the on-step l = l(t-h/2) + (h/2) k." % maxpar)
    # tail: LAMMPS counts (2N)^2 site pairs, rotleap 4 N (N - 1)
    E2 = rl_energy(rl, deck, os.path.join(out, "c2_e2"), chk, ["interactions.dispersion_correction=yes"])
    Pt = (float(np.trace(np.array(E2["virial"]).reshape(3, 3))) - trW) / (3 * V)
    lt = lmp(c2_input(data, rc, 0, 1, os.path.join(out, "c2_t.dump"), tail=True), out, "c2_t")[0]
    Pt_l = lt["c_ppair"] - lr["c_ppair"]
    row(case, "P_tail: rotleap vs LAMMPS tail x (N-1)/N", Pt, Pt_l * (n - 1) / n, 1e-12, rel=True)
    x = 1.0 / rc
    row(case, "P_tail vs (16/3)pi 4N(N-1)/V^2 [..]", Pt,
        16.0 / 3.0 * math.pi * 4 * n * (n - 1) / V ** 2 * ((2.0 / 3.0) * x ** 9 - x ** 3), 1e-12, rel=True)

    # switched LJ: the tail includes the switching region (rl_lj_tail, 20-point Gauss-Legendre)
    rsw = 2.0
    E3 = rl_energy(rl, deck, os.path.join(out, "c2_e3"), chk, ["interactions.lj=switched", "interactions.switch=%g" % rsw])
    E4 = rl_energy(rl, deck, os.path.join(out, "c2_e4"), chk, ["interactions.lj=switched", "interactions.switch=%g" % rsw,
                                                              "interactions.dispersion_correction=yes"])
    Pts = (float(np.trace(np.array(E4["virial"]).reshape(3, 3))) - float(np.trace(np.array(E3["virial"]).reshape(3, 3)))) / (3 * V)
    r = np.linspace(rsw, rc, 200001)
    u = 4 * (r ** -12 - r ** -6)
    du = 4 * (-12 * r ** -13 + 6 * r ** -7)
    xs = (r - rsw) / (rc - rsw)
    S = 1 - 6 * xs ** 5 + 15 * xs ** 4 - 10 * xs ** 3
    dS = (-30 * xs ** 4 + 60 * xs ** 3 - 30 * xs ** 2) / (rc - rsw)
    g = r ** 3 * (du * (1 - S) - u * dS)
    hh = r[1] - r[0]
    wsw = hh / 3 * (g[0] + g[-1] + 4 * g[1:-1:2].sum() + 2 * g[2:-1:2].sum())      # Simpson
    wtail = 4 * (-12.0 / (9.0 * rc ** 9) + 6.0 / (3.0 * rc ** 3))                  # int_rc^inf r^3 u'
    row(case, "P_tail switched (rsw 2): rotleap vs Simpson", Pts,
        -2 * math.pi / (3 * V ** 2) * 4 * n * (n - 1) * (wsw + wtail), 1e-9, rel=True)

    # NVE from the same state: time averages
    every = 10
    t0 = time.time()
    rr = rl_run(rl, deck, os.path.join(out, "c2_nve"),
                ["system.start=" + chk, "run.steps=%d" % (st["step"] + nve_steps), "output.thermo_every=%d" % every])
    t_rl = time.time() - t0
    rr = [r for r in rr if r["step"] > st["step"]]
    dumpn = os.path.join(out, "c2_nve.dump")
    t0 = time.time()
    ln = lmp(c2_input(data, rc, nve_steps, every, dumpn), out, "c2_nve")
    t_l = time.time() - t0
    ln = [r for r in ln if r["Step"] > 0]
    frames = [f for f in read_dump(dumpn) if f[0] > 0]
    pm = []
    for (stp, fr), lrow in zip(frames, ln):
        assert int(lrow["Step"]) == stp
        ds, _, kc = molecular_virial_from_dump(fr, 2, [0.5, 0.5])
        pm.append((2 * kc + 3 * V * lrow["c_ppair"] - ds) / (3 * V))
    pm = np.array(pm)
    pl = np.array([r["Press"] for r in ln])
    prl = np.array([r["pressure"] for r in rr])
    m_rl, e_rl = blocks(prl)
    m_l, e_l = blocks(pl)
    m_m, e_m = blocks(pm)
    m_d, e_d = blocks(pl - pm)
    comb = math.sqrt(e_rl ** 2 + e_l ** 2)
    case = "B 2CLJ NVE %d steps" % nve_steps
    row(case, "<P>: rotleap vs LAMMPS press (3 sigma)", m_rl, m_l, 3 * comb)
    row(case, "<P>: rotleap vs LAMMPS P_mol (3 sigma)", m_rl, m_m, 3 * math.sqrt(e_rl ** 2 + e_m ** 2))
    # LAMMPS-internal, not a rotleap check: its press (atomic kinetic + fix rigid's constraint
    # virial, estimated from each half kick's velocity change) against the molecular pressure of
    # the same frames.  Equal in the continuous-time limit; the estimate's error is O(h) per
    # frame and O(h^2) on average, shown by the same run at 2 h.
    row(case, "LAMMPS-internal: <press - P_mol>, h = 0.002", m_d, 0.0, None, info_only=True)
    row(case, "LAMMPS-internal: rms(press - P_mol), h = 0.002", float(np.sqrt(((pl - pm) ** 2).mean())), 0.0,
        None, info_only=True)
    dump4 = os.path.join(out, "c2_h4.dump")
    n4 = nve_steps // 4
    l4 = lmp(c2_input(data, rc, n4, 5, dump4).replace("timestep 0.002", "timestep 0.004"), out, "c2_h4")
    l4 = [r for r in l4 if r["Step"] > 0]
    d4 = []
    for (stp, fr), lrow in zip([f for f in read_dump(dump4) if f[0] > 0], l4):
        assert int(lrow["Step"]) == stp
        ds, _, kc = molecular_virial_from_dump(fr, 2, [0.5, 0.5])
        d4.append(lrow["Press"] - (2 * kc + 3 * V * lrow["c_ppair"] - ds) / (3 * V))
    m4, e4 = blocks(d4)
    row(case, "LAMMPS-internal: <press - P_mol>, h = 0.004", m4, 0.0, None, info_only=True)
    row(case, "LAMMPS-internal: rms(press - P_mol), h = 0.004", float(np.sqrt((np.array(d4) ** 2).mean())), 0.0,
        None, info_only=True)
    NOTES.append("B NVE, LAMMPS-internal: <press - P_mol> = %.2e +- %.1e at h = 0.002 and %.2e +- %.1e at "
                 "h = 0.004 (ratio %.1f; h^2 gives 4); the rms per frame %.2e and %.2e (ratio %.1f; h gives 2). "
                 "LAMMPS's fix rigid pressure is the atomic one with a finite-difference constraint virial: "
                 "the molecular pressure up to O(h) noise and an O(h^2) bias. rotleap's virial is the "
                 "exact molecular virial of the configuration: no constraint force is estimated."
                 % (m_d, e_d, m4, e4, m4 / m_d, float(np.sqrt(((pl - pm) ** 2).mean())),
                    float(np.sqrt((np.array(d4) ** 2).mean())),
                    float(np.sqrt((np.array(d4) ** 2).mean())) / float(np.sqrt(((pl - pm) ** 2).mean()))))
    e_rl_tot = np.array([r["total"] for r in rr])
    e_l_tot = np.array([r["TotEng"] for r in ln])
    NOTES.append("B NVE: <P> rotleap %.5f +- %.5f, LAMMPS press %.5f +- %.5f, LAMMPS P_mol %.5f +- %.5f "
                 "(20 blocks); sd of P per sample %.3f (rotleap), %.3f (LAMMPS); E drift per molecule "
                 "rotleap %.2e, LAMMPS %.2e (sd %.2e, %.2e); wall time rotleap %.1f s, LAMMPS %.1f s."
                 % (m_rl, e_rl, m_l, e_l, m_m, e_m, prl.std(), pl.std(),
                    (e_rl_tot[-1] - e_rl_tot[0]) / n, (e_l_tot[-1] - e_l_tot[0]) / n,
                    e_rl_tot.std() / n, e_l_tot.std() / n, t_rl, t_l))


# ---------------------------------------------------------------- C. CO2, real units

CO2_DECK = """[system]
model = co2
count = 256
density = 1.06 g/cm3
temperature = 250 K
seed = 3
[interactions]
cutoff = 1.0 nm
lj = plain
scheme = site
eps_rf = 1
[run]
ensemble = nve
timestep = 2 fs
steps = 20
equilibrate = 600
equilibrate_timestep = 1 fs
[output]
thermo_every = 10
sample_every = 0
"""

KB_KJ = 0.00831446261815324         # include/rotleap/units.h (exact, SI 2019)
KC_RL = 138.93545764438198          # include/rotleap/units.h, kJ/mol nm e^-2
KC_LMP_REAL = 332.06371             # LAMMPS force->qqr2e for units real, kcal/mol A e^-2
NKTV2P_REAL = 68568.415             # LAMMPS force->nktv2p for units real, atm per kcal/mol/A^3
N_A = 6.02214076e23


def co2(rl, out):
    deck = os.path.join(out, "co2.ini")
    write(deck, CO2_DECK)
    rl_run(rl, deck, os.path.join(out, "co2"))
    chk = os.path.join(out, "co2.chk")
    chk0 = os.path.join(out, "co2_rest.chk")
    with open(chk0, "wb") as f:
        f.write(rlcheckpoint.zero_velocities(rlcheckpoint.load_bytes(chk)))
    ck = rlcheckpoint.read(chk0)
    E = rl_energy(rl, deck, os.path.join(out, "co2_e"), chk0)
    st = state(ck, E, 0.002)
    n, L = len(st["r"]), st["box"]
    V = float(np.prod(L))                        # nm^3
    trW = float(np.trace(st["W"]))               # kJ/mol
    names = ["O1", "C", "O2"]
    sig = {"O": 3.033, "C": 2.757}               # A
    eps = {"O": 80.507 * KB_KJ / 4.184, "C": 28.129 * KB_KJ / 4.184}   # kcal/mol
    qs = {"O": -0.3256, "C": 0.6512}
    mass = {"O": 15.9994, "C": 12.011}
    qscale = math.sqrt(KC_RL * 10.0 / 4.184 / KC_LMP_REAL)   # LAMMPS's qqr2e -> rotleap's kc
    sites = site_positions(st) * 10.0             # A
    LA = L * 10.0
    types = {"O": 1, "C": 2}
    at = []
    for i in range(n):
        for a, nm in enumerate(names):
            e = nm[0]
            p = sites[i, a]
            img = np.floor(p / LA)
            q = p - img * LA
            at.append("%d %d %d %.17g %.17g %.17g %.17g %d %d %d" % (3 * i + a + 1, i + 1, types[e], qs[e] * qscale,
                                                                     q[0], q[1], q[2], img[0], img[1], img[2]))
    data = os.path.join(out, "co2.data")
    write(data, "CO2 from rotleap\n\n%d atoms\n2 atom types\n\n" % (3 * n) +
          "".join("0 %.17g %slo %shi\n" % (LA[c], ax, ax) for c, ax in enumerate("xyz")) +
          "\nMasses\n\n1 %.17g\n2 %.17g\n\nAtoms # full\n\n" % (mass["O"], mass["C"]) + "\n".join(at) + "\n")
    dump = os.path.join(out, "co2.dump")
    inp = """units real
atom_style full
boundary p p p
read_data %s
pair_style lj/cut/coul/cut 10.0
pair_coeff 1 1 %.17g %.17g
pair_coeff 2 2 %.17g %.17g
pair_modify mix geometric
neigh_modify exclude molecule/intra all
compute ppair all pressure NULL pair
thermo_style custom step pe c_ppair vol
thermo_modify norm no format float %%.17g
dump d all custom 1 %s id mol xu yu zu fx fy fz
dump_modify d sort id format float %%.17g
run 0
""" % (data, eps["O"], sig["O"], eps["C"], sig["C"], dump)
    lr = lmp(inp, out, "co2")[0]
    fr = read_dump(dump)[0][1]
    dsum, _, _ = molecular_virial_from_dump(fr, 3, [mass["O"], mass["C"], mass["O"]])
    VA = lr["Volume"]
    P_atm = lr["c_ppair"] - dsum / (3 * VA) * NKTV2P_REAL   # molecular virial pressure, atm
    case = "C CO2 real units"
    row(case, "V (A^3 vs 1000 nm^3)", V * 1000.0, VA, 1e-12, rel=True)
    W_l = 3 * VA * lr["c_ppair"] / NKTV2P_REAL - dsum          # kcal/mol, LAMMPS's molecular virial
    exact = 4184.0 / N_A / 1e-30 / 101325.0                     # atm per kcal mol^-1 A^-3, CODATA 2018
    row(case, "tr W kJ/mol: rotleap vs LAMMPS x 4.184", trW, W_l * 4.184, 1e-10, rel=True)
    # the checkpoint is at rest, v(t-h/2) = 0; `rotleap energy` completes it to on-step,
    # v(t) = (h/2) F/m, whose kinetic part is added here in kcal/mol
    Kon = 0.5 * st["m"] * float((st["von"] ** 2).sum()) / 4.184
    row(case, "P bar (v(t-h/2) = 0): rotleap vs LAMMPS (2K(t)+W)/3V in SI -> bar", E["pressure"],
        (2 * Kon + W_l) / (3 * VA) * exact * 1.01325, 1e-12, rel=True)
    row(case, "P bar (v(t-h/2) = 0): rotleap vs LAMMPS atm (its nktv2p) x 1.01325", E["pressure"],
        (P_atm + 2 * Kon / (3 * VA) * NKTV2P_REAL) * 1.01325, None, rel=True, info_only=True)
    NOTES.append("C: LAMMPS's nktv2p for real units, %.3f atm per kcal mol^-1 A^-3, against CODATA-2018 N_A: "
                 "%.6f (relative %.1e); the charges given to LAMMPS are scaled by %.12f so that its "
                 "qqr2e = %.5f equals rotleap's kc. kJ mol^-1 nm^-3 = %.13f bar (rotleap: 16.605390671738467)."
                 % (NKTV2P_REAL, exact, NKTV2P_REAL / exact - 1.0, qscale, KC_LMP_REAL, 1e3 / N_A / 1e-27 / 1e5))


# ---------------------------------------------------------------- D. TIP4P, numpy only

TIP4P_DECK = """[system]
model = tip4p
count = 216
density = 1 g/cm3
orientations = random
seed = 11
temperature = 298 K
[interactions]
cutoff = 0.9 nm
scheme = site
lj = plain
eps_rf = 78.3
[run]
ensemble = nve
timestep = 2 fs
steps = 20
equilibrate = 600
equilibrate_timestep = 0.5 fs
[output]
thermo_every = 10
sample_every = 0
"""


def tip4p(rl, out):
    """The TIP4P kernel adds R (x) F per molecule pair (centre image), not r (x) f per site pair:
    checked against an independent numpy sum, and against the reference path (kernel = general)."""
    deck = os.path.join(out, "tip4p.ini")
    write(deck, TIP4P_DECK)
    rl_run(rl, deck, os.path.join(out, "tip4p"))
    chk = os.path.join(out, "tip4p.chk")
    ck = rlcheckpoint.read(chk)
    E = rl_energy(rl, deck, os.path.join(out, "tip4p_e"), chk)
    Eg = rl_energy(rl, deck, os.path.join(out, "tip4p_g"), chk, ["interactions.kernel=general"])
    n, L, rc, erf = ck["n"], np.array(ck["box"]), 0.9, 78.3
    V = float(np.prod(L))
    sites = np.array(rlcheckpoint.site_positions(ck)).reshape(n, 4, 3)
    d = (sites - np.array(ck["r"])[:, None, :]).reshape(-1, 3)
    q = np.tile([0.0, 0.52, 0.52, -1.04], n)
    lj = np.tile([1, 0, 0, 0], n).astype(bool)
    sig, eps = 0.315365, 0.1550 * 4.184
    krf = (erf - 1) / ((2 * erf + 1) * rc ** 3)
    crf = 1 / rc + krf * rc * rc
    flat = sites.reshape(-1, 3)
    mol = np.repeat(np.arange(n), 4)
    U = W = 0.0
    for a in range(len(flat) - 1):
        r = flat[a] - flat[a + 1:]
        r -= L * np.round(r / L)
        r2 = (r * r).sum(1)
        keep = (r2 < rc * rc) & (mol[a + 1:] != mol[a])
        idx = np.nonzero(keep)[0] + a + 1
        r, r2 = r[keep], r2[keep]
        fs = np.zeros(len(r2))
        if q[a] != 0.0:
            qq = KC_RL * q[a] * q[idx]
            U += float((qq * (1 / np.sqrt(r2) + krf * r2 - crf)).sum())
            fs += qq * (r2 ** -1.5 - 2 * krf)
        if lj[a]:
            m = lj[idx]
            s6 = (sig * sig / r2[m]) ** 3
            U += float((4 * eps * (s6 * s6 - s6)).sum())
            fs[m] += 24 * eps * (2 * s6 * s6 - s6) / r2[m]
        R = r - d[a] + d[idx]
        W += float((fs[:, None] * r * R).sum())
    trW, trWg = float(np.trace(np.array(E["virial"]).reshape(3, 3))), float(np.trace(np.array(Eg["virial"]).reshape(3, 3)))
    case = "D TIP4P (numpy)"
    scale = 3 * n * 298 * KB_KJ     # 3 N kT, kJ/mol: the virial's natural scale
    row(case, "U: rotleap vs numpy", E["energy"]["total"], U, 1e-10, rel=True)
    row(case, "tr W kJ/mol: rotleap (kernel) vs numpy", trW, W, 1e-10, scale=scale, rel=True)
    row(case, "tr W kJ/mol: kernel vs general path", trW, trWg, 1e-12, scale=scale, rel=True)
    kern = [ln.split("=", 1)[1].strip() for ln in open(os.path.join(out, "tip4p.summary.txt"))
            if ln.startswith("pair_kernels")]
    NOTES.append("D: TIP4P pair kernels of the run: %s; the virial's scale 3NkT = %.1f kJ/mol, tr W = %.1f "
                 "kJ/mol, W/3V = %.1f bar." % (kern[0] if kern else "?", scale, trW,
                                               trW / (3 * V) * 16.605390671738467))


READING = """## How to read this

- rotleap reports the **molecular** pressure P = (2 K_trans + tr W)/(3V), W = sum over molecule
  pairs of R_ij (x) f_ij, K_trans the centre-of-mass kinetic energy at the step (eq. 9:
  v(t) = v(t-h/2) + (h/2) F(t)/m). The single-configuration rows compare W with LAMMPS's pair
  virial (point particles: A) or with the molecular virial recomputed from LAMMPS's per-atom
  forces, W_site - sum_a d_a . f_a (B, C), which is exact with periodic images. sum_i R_i . F_i
  over unwrapped centres is not (row "naive": off by the pairs that interact across the box).
- LAMMPS with fix rigid reports the **atomic** pressure: sum over atoms of m v^2 (translation
  and rotation) plus the pair virial plus fix rigid's constraint virial, which it estimates from
  the velocity change of each half kick (fix_modify virial yes is the default). Its value at
  `run 0` is a set-up guess and is not the pressure of that state. Along a run it equals the
  molecular pressure up to O(h) noise per frame and an O(h^2) bias of the mean (rows
  "LAMMPS-internal", measured at h and 2h). These rows are not rotleap checks; the first
  version of this script tested the mean difference against 0 and it failed at 16 sigma, which
  is how the O(h^2) bias was found.
- The NVE averages come from the same start but separate after some hundred steps (chaos), so
  they are compared within 3 combined standard errors (20 blocks each).
- `rotleap energy` on a checkpoint completes the stored half-step velocities v(t-h/2) to
  on-step v(t) with run.timestep, as the run's thermo row for the same state does (row
  "energy cmd vs thermo row"; before 568d3b8 it took v(t-h/2), off by the note's amount).
- Tolerances: single-configuration virials 1e-10 relative to the natural scale (rho kT, or
  3NkT for TIP4P): both codes sum in double precision (observed <= 4e-14; an image or
  physics error would be >= 1e-4). Kinetic energies 1e-9 (the thermo CSV prints %.10g);
  pressures from the thermo CSV 1e-9 (printed %.10g since 568d3b8). Tail corrections 1e-12 against closed
  forms; 1e-9 against a Simpson integral (switched LJ; rotleap uses 20-point Gauss-Legendre).
  Real units: LAMMPS's virial converted to bar with the CODATA-2018 factor, 1e-12; LAMMPS's own
  atm constant differs from CODATA 2018 by 1.2e-7 (info row).

"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rotleap", default=os.path.join(HERE, "..", "build", "rotleap"))
    ap.add_argument("--out", default="/tmp/rotleap_validate/lammps_pressure")
    ap.add_argument("--nve-steps", type=int, default=20000)
    ap.add_argument("--md", help="also write the table to this markdown file")
    a = ap.parse_args()
    if os.path.isdir(a.out):
        shutil.rmtree(a.out)
    os.makedirs(a.out)
    rl = os.path.abspath(a.rotleap)
    t0 = time.time()
    stockmayer(rl, a.out)
    twoclj(rl, a.out, a.nve_steps)
    co2(rl, a.out)
    tip4p(rl, a.out)
    head = "| case | quantity (a vs b) | a | b | difference | tolerance | verdict |\n|---|---|---|---|---|---|---|\n"
    body = ""
    for case, what, x, y, err, tol, ok, kind in ROWS:
        t = "" if tol is None else "%.0e %s" % (tol, kind)
        body += "| %s | %s | %.12g | %.12g | %.2e %s | %s | %s |\n" % (case, what, x, y, err, kind, t, ok)
    notes = "".join("- %s\n" % s for s in NOTES)
    nfail = sum(r[6] == "FAIL" for r in ROWS)
    tail = "\n%d checks, %d failed (rows marked info are reported, not tested); %.0f s\n" % (
        sum(r[6] != "info" for r in ROWS), nfail, time.time() - t0)
    text = head + body + "\n" + notes + tail
    print(text)
    if a.md:
        with open(a.md, "w") as f:
            rev = subprocess.run(["git", "-C", HERE, "rev-parse", "--short", "HEAD"], capture_output=True,
                                 text=True).stdout.strip() or "?"
            f.write("# rotleap pressure against LAMMPS\n\n`%s`\n\nrotleap at %s (source tree HEAD when run); "
                    "LAMMPS: %s (Debian `lammps`)\n\n" % (
                        " ".join(["/usr/bin/python3", "validate/lammps_pressure.py"] + sys.argv[1:]), rev,
                        lammps_version()) + READING + "## Results\n\n" + text)
    return 1 if nfail else 0


def lammps_version():
    p = subprocess.run(["lmp", "-h"], capture_output=True, text=True)
    for line in p.stdout.splitlines():
        if "Large-scale" in line:
            return line.strip()
    return "?"


if __name__ == "__main__":
    sys.exit(main())
