#!/usr/bin/python3
"""Single-point cross-check of rotleap against OpenMM 7.7 (issue 6, part 1).

Run (from the repository root, after building rotleap):
    /usr/bin/python3 validate/single_point.py [--rotleap build/rotleap] [--models tip4p,...]
                                              [--no-write]
OpenMM 7.7 from Debian: apt-get install -y python3-simtk libopenmm-plugins python3-numpy.
About 1 minute on 2 cores (most of it the four 1.5 ps liquid runs).

For each water model (tip4p, tip4p-ew, spc-e, tip3p) and five configurations
    sc-aligned       125 molecules, simple-cubic lattice, all orientations equal, rc 0.75 nm
    sc-random        125 molecules, simple-cubic lattice, random orientations,    rc 0.75 nm
    fcc-random-rfinf 108 molecules, fcc lattice, random orientations, rc 0.70 nm, eps_rf = inf
    random-noncubic  130 molecules at random centres (no centre pair closer than 0.26 nm) with
                     random orientations in a 1.55 x 1.60 x 1.70 nm box, read by rotleap from a
                     PDB (rotleap fits each molecule), rc 0.75 nm
    liquid           216 molecules, 1 g/cm3, relaxed from a lattice and run 1.5 ps NVT at 298 K
                     by rotleap itself (examples/tip4p.ini setup), rc 0.9 nm
(eps_rf 78.3 unless stated) the script
  1. makes the configuration with `rotleap run` (0 steps for the starts; the liquid run for the
     liquid) and takes its checkpoint: positions r and orientation matrices A bit for bit;
  2. evaluates it with `rotleap energy --json` (deck: scheme = site, lj = plain,
     dispersion_correction = no, start = the checkpoint);
  3. builds the same system in OpenMM (validate/watermodels.py: NonbondedForce CutoffPeriodic,
     reaction-field dielectric, all intramolecular pairs excluded, no switching, no dispersion
     correction, TIP4P's M a ThreeParticleAverageSite), with the site positions r + A^T d from the
     checkpoint, and evaluates it on the Reference platform (double precision) and, for
     information, on the CPU platform;
  4. reduces OpenMM's atom forces (virtual-site forces already distributed onto O, H1, H2) to
     molecular forces F = sum f_a and torques K = sum (r_a - R) x f_a, R the centre of mass with
     rotleap's masses (O 15.9994, H 1.008);
  5. compares: |E_rl - E_omm| / |E_omm| <= 1e-10, and RMS relative force and torque error
     sqrt(sum |F_rl - F_omm|^2 / sum |F_omm|^2) <= 1e-8 (same for K).

It writes (unless --no-write) validate/data/sp_<model>_<config>.chk.gz (the checkpoint, with v and
l zeroed so it compresses; positions and orientations untouched), validate/data/
single_point_reference.json.gz (OpenMM Reference energies, molecular forces and torques: what the
CTest tests/validate/check_single_point.py compares rotleap against without OpenMM), and
validate/data/single_point_summary.txt (the table printed at the end).  Exit status 1 if any
comparison fails.
"""
import argparse
import gzip
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True
sys.path.insert(0, HERE)
import rlcheckpoint  # noqa: E402
import watermodels  # noqa: E402

try:
    import openmm as mm
    from openmm import unit
except ImportError:
    from simtk import openmm as mm
    from simtk import unit

TOL_E, TOL_F, TOL_K = 1e-10, 1e-8, 1e-8
ROOT = os.path.dirname(HERE)
DATA = os.path.join(HERE, "data")

CONFIGS = [
    dict(name="sc-aligned", count=125, density=1.0, lattice="sc", orientations="aligned",
         cutoff=0.75, eps_rf="78.3", symmetric=True),
    dict(name="sc-random", count=125, density=1.0, lattice="sc", orientations="random",
         cutoff=0.75, eps_rf="78.3"),
    dict(name="fcc-random-rfinf", count=108, density=1.0, lattice="fcc", orientations="random",
         cutoff=0.70, eps_rf="inf"),
    dict(name="random-noncubic", count=130, box=(1.55, 1.60, 1.70), pdb=True, cutoff=0.75,
         eps_rf="78.3"),
    dict(name="liquid", count=216, density=1.0, lattice="sc", orientations="random",
         cutoff=0.9, eps_rf="78.3", liquid=True),
]
SEEDS = {"tip4p": 11, "tip4p-ew": 12, "spc-e": 13, "tip3p": 14}


def eps_value(s):
    return 1e30 if s == "inf" else float(s)   # OpenMM: (1e30 - 1)/(2e30 + 1) = 1/2 exactly


def run(cmd, **kw):
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if p.returncode:
        sys.exit("failed: %s\n%s%s" % (" ".join(cmd), p.stdout, p.stderr))
    return p.stdout


def deck_text(model, cfg, start=None, box=None, seed=1, steps=0, extra_run=""):
    sysl = ["[system]", "model = %s" % model, "count = %d" % cfg["count"]]
    if box is not None:
        sysl.append("box = %s" % " ".join(repr(float(b)) for b in box))
    else:
        sysl.append("density = %r g/cm3" % cfg["density"])
    if start:
        sysl.append("start = %s" % start)
    else:
        sysl += ["lattice = %s" % cfg["lattice"], "orientations = %s" % cfg["orientations"]]
    sysl += ["seed = %d" % seed, "temperature = 298 K"]
    return "\n".join(sysl + [
        "[interactions]", "cutoff = %r nm" % cfg["cutoff"], "scheme = site", "lj = plain",
        "dispersion_correction = no", "eps_rf = %s" % cfg["eps_rf"],
        "[run]", "steps = %d" % steps, "timestep = 1 fs" if not extra_run else extra_run,
        "[output]", "progress = no", "sample_every = 0", ""])


def random_pdb(path, model, cfg, d, seed):
    """Random centres (minimum-image centre distance >= 0.26 nm) and uniformly random rotations;
    sites c + R d written as a rotleap-style PDB (Angstrom, CRYST1)."""
    rng = np.random.default_rng(seed)
    box = np.array(cfg["box"])
    centres = []
    while len(centres) < cfg["count"]:
        c = rng.random(3) * box
        if all(np.linalg.norm((c - o) - box * np.round((c - o) / box)) >= 0.26 for o in centres):
            centres.append(c)
    names = ["O", "H1", "H2", "MW"][:len(d)]
    lines = ["CRYST1%9.3f%9.3f%9.3f%7.2f%7.2f%7.2f P 1           1" % (*(10 * box), 90, 90, 90)]
    serial = 0
    for i, c in enumerate(centres):
        q = rng.normal(size=4)
        w, x, y, z = q / np.linalg.norm(q)
        R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                      [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                      [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
        for a, da in enumerate(d):
            serial += 1
            p = 10 * (c + R @ np.array(da))
            lines.append("ATOM  %5d %-4s %-3s A%4d    %8.3f%8.3f%8.3f%6.2f%6.2f          %2s"
                         % (serial, names[a], "HOH", i + 1, *p, 1.0, 0.0,
                            "" if names[a] == "MW" else names[a][0]))
        lines.append("TER")
    lines.append("END")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def make_checkpoint(rotleap, work, model, cfg, template_d):
    """Run rotleap to produce the configuration; return the checkpoint bytes (v, l zeroed)."""
    seed = SEEDS[model]
    tag = "%s_%s" % (model, cfg["name"])
    deck = os.path.join(work, tag + ".ini")
    if cfg.get("pdb"):
        pdb = os.path.join(work, tag + ".pdb")
        random_pdb(pdb, model, cfg, template_d, seed)
        text = deck_text(model, cfg, start=pdb, box=cfg["box"], seed=seed)
    elif cfg.get("liquid"):
        text = deck_text(model, cfg, seed=seed, steps=500, extra_run=(
            "timestep = 2 fs\nensemble = nvt-bussi\ntemperature = 298 K\ntau = 0.1 ps\n"
            "equilibrate = 1000\nequilibrate_timestep = 0.5 fs"))
        text = text.replace("temperature = 298 K\n[interactions]", "[interactions]")
    else:
        text = deck_text(model, cfg, seed=seed)
    with open(deck, "w") as f:
        f.write(text)
    run([rotleap, "run", deck, "--set", "output.prefix=" + os.path.join(work, tag)])
    with open(os.path.join(work, tag + ".chk"), "rb") as f:
        return rlcheckpoint.zero_velocities(f.read())


def rotleap_energy(rotleap, work, model, cfg, chk_path, box):
    deck = os.path.join(work, "energy.ini")
    with open(deck, "w") as f:
        f.write(deck_text(model, cfg, start=chk_path, box=box))
    return json.loads(run([rotleap, "energy", deck, "--json"]))


def openmm_eval(model, ck, cfg, platform):
    nmol = ck["n"]
    d = ck["species"][0]["sites"]
    system = watermodels.build_system(model, nmol, ck["box"], cfg["cutoff"], eps_value(cfg["eps_rf"]))
    pos = np.array(rlcheckpoint.site_positions(ck))
    ctx = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName(platform))
    ctx.setPositions(pos)
    ctx.computeVirtualSites()
    st = ctx.getState(getEnergy=True, getForces=True, getPositions=True)
    e = st.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole)
    f = np.array(st.getForces(asNumpy=True).value_in_unit(unit.kilojoule_per_mole / unit.nanometer))
    x = np.array(st.getPositions(asNumpy=True).value_in_unit(unit.nanometer))
    ns = len(d)
    vsite_move = float(np.max(np.abs(x - pos)))      # OpenMM's M vs rotleap's r + A^T d_M
    masses = np.array([s[1] for s in watermodels.site_params(model)])
    F = np.zeros((nmol, 3))
    K = np.zeros((nmol, 3))
    fsq = ksq = 0.0
    com_dev = 0.0
    vs_force = 0.0
    for i in range(nmol):
        xa, fa = x[i * ns:(i + 1) * ns], f[i * ns:(i + 1) * ns]
        R = (masses[:, None] * xa).sum(0) / masses.sum()   # M has mass 0
        com_dev = max(com_dev, float(np.max(np.abs(R - np.array(ck["r"][i])))))
        if ns == 4:
            # OpenMM 7.7 still reports the force on the virtual site after distributing it onto
            # O, H1, H2: the molecule's force and torque come from the three real atoms only.
            vs_force = max(vs_force, float(np.max(np.abs(fa[3]))))
            xa, fa = xa[:3], fa[:3]
        ka = np.cross(xa - R, fa)
        F[i] = fa.sum(0)
        K[i] = ka.sum(0)
        fsq += float(np.sum(fa ** 2))
        ksq += float(np.sum(ka ** 2))
    natoms = nmol * (3 if ns == 4 else ns)
    # scales of the single-atom contributions (RMS |f_a| and RMS |(r_a - R) x f_a|): the
    # denominators where the molecular sums vanish by symmetry (config "symmetric")
    return dict(energy=e, F=F, K=K, vsite_move=vsite_move, com_dev=com_dev, vs_force=vs_force,
                fscale=math.sqrt(fsq / natoms), kscale=math.sqrt(ksq / natoms))


def rel_rms(a, b, scale=None):
    """sqrt(sum |a - b|^2 / sum |b|^2); with scale: sqrt(mean |a - b|^2) / scale (for molecular
    sums that vanish by symmetry, where sum |b|^2 is round-off)."""
    if scale is not None:
        return float(np.sqrt(np.sum((a - b) ** 2) / len(b)) / scale)
    return float(np.sqrt(np.sum((a - b) ** 2) / np.sum(b ** 2)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rotleap", default=os.path.join(ROOT, "build", "rotleap"))
    ap.add_argument("--models", default="tip4p,tip4p-ew,spc-e,tip3p")
    ap.add_argument("--no-write", action="store_true", help="do not update validate/data/")
    args = ap.parse_args()
    rotleap = os.path.abspath(args.rotleap)
    t0 = time.time()
    work = tempfile.mkdtemp(prefix="rotleap-sp-")
    rows, refs, ok = [], [], True
    print("OpenMM %s; tolerances: energy %.0e relative, force/torque %.0e RMS relative"
          % (mm.version.version, TOL_E, TOL_F))
    for model in args.models.split(","):
        xml = watermodels.xml_crosscheck(model)
        if xml:
            print("  %s vs OpenMM's %s (information): %s" % (model, watermodels.OPENMM_XML[model],
                  ", ".join("%s %.9g/%.9g (%.1e)" % r for r in xml)))
        template_d = None
        for cfg in CONFIGS:
            tag = "%s_%s" % (model, cfg["name"])
            chk = make_checkpoint(rotleap, work, model, cfg, template_d)
            ck = rlcheckpoint.parse(chk)
            d = ck["species"][0]["sites"]
            template_d = template_d or d
            geo = watermodels.check_geometry(model, d)
            chk_path = os.path.join(work, tag + "_sp.chk")
            with open(chk_path, "wb") as f:
                f.write(chk)
            rl = rotleap_energy(rotleap, work, model, cfg, chk_path, ck["box"])
            Erl = rl["energy"]["total"]
            Frl = np.array([m["force"] for m in rl["molecules"]])
            Krl = np.array([m["torque"] for m in rl["molecules"]])
            ref = openmm_eval(model, ck, cfg, "Reference")
            cpu = openmm_eval(model, ck, cfg, "CPU")
            sym = cfg.get("symmetric", False)
            fs, ks = (ref["fscale"], ref["kscale"]) if sym else (None, None)
            r = dict(model=model, config=cfg["name"], n=ck["n"], E_rl=Erl, E_ref=ref["energy"],
                     dE=abs(Erl - ref["energy"]) / abs(ref["energy"]),
                     dF=rel_rms(Frl, ref["F"], fs), dK=rel_rms(Krl, ref["K"], ks),
                     cpu_dE=abs(cpu["energy"] - ref["energy"]) / abs(ref["energy"]),
                     cpu_dF=rel_rms(cpu["F"], ref["F"], fs), cpu_dK=rel_rms(cpu["K"], ref["K"], ks),
                     geo=geo, vsite=ref["vsite_move"], com=ref["com_dev"], vsf=ref["vs_force"],
                     lj=rl["energy"]["lj"], coul=rl["energy"]["coulomb"])
            r["ok"] = r["dE"] <= TOL_E and r["dF"] <= TOL_F and r["dK"] <= TOL_K
            if sym:  # both codes must see the symmetry: molecular F and K zero to round-off
                r["zero"] = max(rel_rms(Frl, 0 * Frl, fs), rel_rms(Krl, 0 * Krl, ks),
                                rel_rms(ref["F"], 0 * Frl, fs), rel_rms(ref["K"], 0 * Krl, ks))
                r["ok"] &= r["zero"] <= TOL_F
            ok &= r["ok"]
            rows.append(r)
            print("  %-9s %-17s N=%3d  E_omm %+.10f  dE %.1e  dF %.1e  dK %.1e  | CPU dE %.1e "
                  "dF %.1e dK %.1e  [geom %.0e, M %.0e, com %.0e]  %s"
                  % (model, cfg["name"], ck["n"], ref["energy"], r["dE"], r["dF"], r["dK"],
                     r["cpu_dE"], r["cpu_dF"], r["cpu_dK"], geo, r["vsite"], r["com"],
                     "ok" if r["ok"] else "FAIL"), flush=True)
            refs.append(dict(model=model, config=cfg["name"], chk="sp_%s.chk.gz" % tag,
                             count=ck["n"], box=ck["box"], cutoff=cfg["cutoff"],
                             eps_rf=cfg["eps_rf"], energy=ref["energy"],
                             force_scale=fs, torque_scale=ks,
                             forces=[[float("%.14g" % v) for v in row] for row in ref["F"]],
                             torques=[[float("%.14g" % v) for v in row] for row in ref["K"]]))
            if not args.no_write:
                os.makedirs(DATA, exist_ok=True)
                with gzip.GzipFile(os.path.join(DATA, "sp_%s.chk.gz" % tag), "wb", mtime=0) as g:
                    g.write(chk)
    elapsed = time.time() - t0
    summary = ["# validate/single_point.py: rotleap energy vs OpenMM %s (%s)"
               % (mm.version.version, time.strftime("%Y-%m-%d")),
               "# tolerances: energy %.0e relative; force, torque %.0e RMS relative; %.0f s"
               % (TOL_E, TOL_F, elapsed),
               "model      config             N   E_OpenMM_Reference(kJ/mol)  E_rotleap(kJ/mol)        "
               "rel_dE   rms_dF   rms_dK   CPU_dE   CPU_dF   CPU_dK"]
    for r in rows:
        summary.append("%-10s %-17s %4d  %+.12f  %+.12f  %.1e  %.1e  %.1e  %.1e  %.1e  %.1e%s"
                       % (r["model"], r["config"], r["n"], r["E_ref"], r["E_rl"], r["dE"], r["dF"],
                          r["dK"], r["cpu_dE"], r["cpu_dF"], r["cpu_dK"], ("  *" if "zero" in r else "") + ("" if r["ok"] else "  FAIL")))
    mx = lambda k: max(r[k] for r in rows)
    summary.append("max: rel_dE %.1e  rms_dF %.1e  rms_dK %.1e | CPU vs Reference: dE %.1e  dF %.1e  "
                   "dK %.1e | geometry vs literature %.1e nm, OpenMM M vs rotleap M %.1e nm, "
                   "centre of mass vs checkpoint r %.1e nm, force left on M %.1e"
                   % (mx("dE"), mx("dF"), mx("dK"), mx("cpu_dE"), mx("cpu_dF"), mx("cpu_dK"),
                      mx("geo"), mx("vsite"), mx("com"), mx("vsf")))
    summary.append("* sc-aligned: molecular forces and torques vanish by symmetry (both codes: RMS <= "
                   "%.0e of the atom scale); rms_dF, rms_dK there are RMS differences divided by the "
                   "RMS atom force f_a and atom torque (r_a - R) x f_a, not by the (zero) molecular RMS"
                   % max([r["zero"] for r in rows if "zero" in r] or [0]))
    summary.append("result: %s" % ("all within tolerance" if ok else "DISAGREEMENT (see FAIL rows)"))
    print("\n".join(summary))
    if not args.no_write:
        with open(os.path.join(DATA, "single_point_summary.txt"), "w") as f:
            f.write("\n".join(summary) + "\n")
        with gzip.GzipFile(os.path.join(DATA, "single_point_reference.json.gz"), "wb", mtime=0) as g:
            g.write(json.dumps({
                "generated_by": "/usr/bin/python3 validate/single_point.py --rotleap BUILD/rotleap",
                "openmm": mm.version.version, "platform": "Reference",
                "tolerance": {"energy_rel": TOL_E, "force_rms_rel": TOL_F, "torque_rms_rel": TOL_K},
                "deck": {"scheme": "site", "lj": "plain", "dispersion_correction": "no"},
                "configs": refs}, separators=(",", ":")).encode())
    shutil.rmtree(work)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
