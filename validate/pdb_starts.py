#!/usr/bin/python3
"""Issue 35, acceptance 5: a GROMACS-written and an OpenMM-written box of TIP4P-family water with
Na+/Cl- ions, as these codes write them, checked in so that CTest (tests/cli/pdb_start_tests.sh)
starts rotleap runs from them without editing.

GROMACS (Debian's gromacs 2022.5): `gmx solvate -cs tip4p.gro` fills a cube of the edge of
tip4p.gro's own box (1.86824 nm, 216 TIP4P waters), `gmx grompp` (oplsaa.ff, tip4p.itp, ions.itp;
a dummy steepest-descent .mdp with 0.8 nm cutoffs, only for the .tpr) and `gmx genion -np 3 -nn 3`
replace 6 waters with NA and CL, `gmx editconf -o` writes the PDB: residues SOL (OW HW1 HW2 MW), NA,
CL; CRYST1 18.682 A; coordinates from .gro's 0.001 nm (every third decimal 0).

OpenMM 7.7: `Modeller.addSolvent(ForceField('amber14/tip4pew.xml'), model='tip4pew', boxSize 1.9 nm
cube, ionicStrength 1 M)` and `PDBFile.writeFile`: residues HOH (O H1 H2 M, element EP for M) in
chain A, then NA and CL (atoms Na, Cl) in chain B; CRYST1 19.000 A.

    /usr/bin/python3 validate/pdb_starts.py
        writes validate/data/pdb_start_gromacs.pdb.gz and validate/data/pdb_start_openmm.pdb.gz
        (gzip -n: no name or time in the header) and prints the residue counts.  The waters'
        positions come from GROMACS's and OpenMM's equilibrated boxes; genion's and Modeller's
        choice of the ion sites is random, so a new run gives other files.  5 s.
"""
import collections
import gzip
import os
import shutil
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "data")

TOPOL = """#include "oplsaa.ff/forcefield.itp"
#include "oplsaa.ff/tip4p.itp"
#include "oplsaa.ff/ions.itp"
[ system ]
TIP4P water
[ molecules ]
SOL 216
"""
MDP = """integrator = steep
nsteps = 0
cutoff-scheme = Verlet
coulombtype = reaction-field
rcoulomb = 0.8
rvdw = 0.8
verlet-buffer-tolerance = -1
rlist = 0.8
"""


def gromacs(tmp):
    def gmx(*args, stdin=None):
        subprocess.run(["gmx", "-quiet"] + list(args), cwd=tmp, input=stdin, text=True, check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    gmx("solvate", "-cs", "tip4p.gro", "-box", "1.86824", "1.86824", "1.86824", "-o", "box.gro")
    with open(os.path.join(tmp, "topol.top"), "w") as f:
        f.write(TOPOL)
    with open(os.path.join(tmp, "em.mdp"), "w") as f:
        f.write(MDP)
    gmx("grompp", "-f", "em.mdp", "-c", "box.gro", "-p", "topol.top", "-o", "ions.tpr", "-maxwarn", "2")
    gmx("genion", "-s", "ions.tpr", "-o", "salt.gro", "-p", "topol.top", "-pname", "NA", "-nname", "CL",
        "-np", "3", "-nn", "3", "-seed", "7", stdin="SOL\n")
    gmx("editconf", "-f", "salt.gro", "-o", "gromacs.pdb")
    return os.path.join(tmp, "gromacs.pdb")


def openmm(tmp):
    import openmm as mm
    import openmm.app as app
    import openmm.unit as u
    ff = app.ForceField("amber14/tip4pew.xml")
    mod = app.Modeller(app.Topology(), [])
    mod.addSolvent(ff, model="tip4pew", boxSize=mm.Vec3(1.9, 1.9, 1.9) * u.nanometer, ionicStrength=1.0 * u.molar)
    path = os.path.join(tmp, "openmm.pdb")
    with open(path, "w") as f:
        app.PDBFile.writeFile(mod.topology, mod.positions, f)
    return path


def store(src, name):
    dst = os.path.join(DATA, name)
    with open(src, "rb") as f, open(dst, "wb") as out:
        with gzip.GzipFile(filename="", mode="wb", fileobj=out, mtime=0) as g:
            g.write(f.read())
    res = collections.Counter()
    seen = set()
    for line in open(src):
        if line.startswith(("ATOM", "HETATM")):
            key = (line[21], line[22:26], line[17:21])
            if key not in seen:
                seen.add(key)
                res[line[17:21].strip()] += 1
        if line.startswith("CRYST1"):
            cryst = line[6:33].split()
    print(f"{dst}: residues {dict(res)}, CRYST1 {' '.join(cryst)} A")


def main():
    tmp = tempfile.mkdtemp()
    try:
        store(gromacs(tmp), "pdb_start_gromacs.pdb.gz")
        store(openmm(tmp), "pdb_start_openmm.pdb.gz")
    finally:
        shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
