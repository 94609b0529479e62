"""Shared pieces of the Stockmayer validations (stockmayer_lammps_nvt.py, npt_stockmayer.py,
npt_lammps.py): block averages, z-scores, running rotleap and LAMMPS at nice 10, reading their
outputs, and writing a Markdown table.  Standard library only."""
import math
import os
import subprocess
import time

from mdtable import blocks, write_md  # noqa: F401  (blocks: re-exported for the Stockmayer scripts)

# LAMMPS: point dipoles of mass 1 (spheres of diameter 1) on an fcc lattice of nc^3 cells at number
# density rho, random dipoles of length mu, velocities at T (format fields rho, nc, seed, mu, T)
LAMMPS_START = """units lj
atom_style hybrid sphere dipole
boundary p p p
lattice fcc {rho}
region box block 0 {nc} 0 {nc} 0 {nc}
create_box 1 box
create_atoms 1 box
set type 1 diameter 1.0
set type 1 density 1.9098593171027440
set type 1 dipole/random {seed} {mu!r}
velocity all create {T} {seed} mom yes rot no dist gaussian
"""


def z(a, b):
    """(mean, error) pairs: the difference over the combined error."""
    return (a[0] - b[0]) / math.sqrt(a[1] ** 2 + b[1] ** 2)


def run_rotleap(rotleap, work, name, deck_text, after_step=0):
    """Writes WORK/NAME.ini, runs it at nice 10; returns (thermo rows after step after_step as dicts of
    strings, the results.txt text, wall seconds)."""
    deck = os.path.join(work, name + ".ini")
    with open(deck, "w") as f:
        f.write(deck_text)
    t0 = time.time()
    subprocess.run(["nice", "-n", "10", rotleap, "run", deck], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    wall = time.time() - t0
    lines = open(os.path.join(work, name + ".thermo.csv")).read().splitlines()
    head = lines[0].split(",")
    rows = [dict(zip(head, l.split(","))) for l in lines[1:]]
    return [r for r in rows if int(r["step"]) > after_step], open(os.path.join(work, name + ".results.txt")).read(), wall


def run_lammps(lmp, work, name, inp_text, columns):
    """Runs LAMMPS on inp_text at nice 10; returns (the rows of its last thermo table whose header starts
    with `columns`, without its first row, as floats; wall seconds; LAMMPS's version line)."""
    inp, log = os.path.join(work, "in." + name), os.path.join(work, "log." + name)
    with open(inp, "w") as f:
        f.write(inp_text)
    t0 = time.time()
    p = subprocess.run(["nice", "-n", "10", lmp, "-in", inp, "-log", log, "-screen", "none", "-nocite"],
                       capture_output=True, text=True)
    wall = time.time() - t0
    text = open(log).read()
    if p.returncode:
        raise RuntimeError("lmp failed: %s\n%s" % (p.stderr, text[-2000:]))
    lines = text.splitlines()
    head = [i for i, l in enumerate(lines) if l.split()[:len(columns)] == columns][-1]
    rows = []
    for l in lines[head + 2:]:  # the first row is the state the previous run ended in
        w = l.split()
        if len(w) != len(lines[head].split()) or not w[0].isdigit():
            break
        rows.append([float(v) for v in w])
    return rows, wall, next((l for l in lines if l.startswith("LAMMPS (")), "LAMMPS")


def finish(md, lines, ok):
    """Writes the Markdown lines (and an Overall line) to md, prints them; the exit status."""
    text = "\n".join(lines + ["", "Overall: %s." % ("pass" if ok else "FAIL")]) + "\n"
    write_md(md, text)
    print(text)
    return 0 if ok else 1


def verdict(zv):
    return "yes" if abs(zv) <= 3 else "NO"
