#!/usr/bin/env bash
# PDB starts from other codes (issue 35, acceptance 5): a box GROMACS wrote (gmx solvate + genion
# + editconf: SOL with OW HW1 HW2 MW, NA, CL) and one OpenMM 7.7 wrote (Modeller.addSolvent +
# PDBFile.writeFile: HOH with O H1 H2 M, then NA, CL), both made by validate/pdb_starts.py and
# checked in, start runs as they are: the residue names go to the deck's species, the box is
# CRYST1's, the molecule counts are the file's, the energies finite.  Then: a 3-atom copy of the
# 4-site waters (M placed by the fit), system.residues for a name no default knows, and the
# errors (file:line for an unknown residue name; the deck key's own problems at its line).
# usage: pdb_start_tests.sh ROTLEAP SOURCE_DIR WORKDIR
set -u
rotleap=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }
# every number of a thermo CSV finite (no nan, no inf) and at least N rows
finite() { python3 -c "
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
sys.exit(not (len(rows) >= int(sys.argv[2]) and all(math.isfinite(float(v)) for r in rows for v in r.values())))" "$1" "$2"; }

gunzip -c "$src/validate/data/pdb_start_gromacs.pdb.gz" > box_gromacs.pdb
gunzip -c "$src/validate/data/pdb_start_openmm.pdb.gz" > box_openmm.pdb

cat > gromacs.ini <<'DECK'
[system]
species = tip4p:210 na-tip4pew:3 cl-tip4pew:3
start = box_gromacs.pdb
box = 18.682 A
temperature = 300 K
[interactions]
cutoff = 0.9 nm
[run]
steps = 20
timestep = 2 fs
[output]
thermo_every = 5
checkpoint_every = 20
progress = no
DECK
# OpenMM's Modeller does not minimise: O-O 1.9 A and O-Cl 1.85 A across the boundary; relax first
sed 's/^species = .*/species = tip4p-ew:207 na-tip4pew:4 cl-tip4pew:4/; s/^start = .*/start = box_openmm.pdb/;
     s/^box = .*/box = 19 A/; s/^timestep = 2 fs/timestep = 2 fs\nequilibrate = 200/' gromacs.ini > openmm.ini

for code in gromacs openmm; do
  "$rotleap" run $code.ini > $code.out 2> $code.err; rc=$?
  check "$code: the file starts a run as it is" '[ $rc = 0 ] && grep -q "^status = ok" $code.summary.txt'
  check "$code: energies finite over 20 steps" 'finite $code.thermo.csv 5'
  cryst=$(grep "^CRYST1" box_$code.pdb | cut -c7-33 | xargs)
  box=$(python3 -c "import sys; sys.path.insert(0, '$src/validate'); import rlcheckpoint as c
print(' '.join('%.3f' % (10 * x) for x in c.read('$code.chk')['box']))")
  check "$code: the run's box (its checkpoint's) is CRYST1's ($cryst A)" '[ "$box" = "$cryst" ]'
done
check "gromacs: 210 tip4p + 3 Na+ + 3 Cl- (residues SOL, NA, CL)" \
  'grep -q "^molecules = 216$" gromacs.summary.txt && grep -q "^species = tip4p x 210:" gromacs.summary.txt &&
   grep -q "^species = na-tip4pew x 3:" gromacs.summary.txt && grep -q "^species = cl-tip4pew x 3:" gromacs.summary.txt'
check "openmm: 207 tip4p-ew + 4 Na+ + 4 Cl- (residues HOH, NA, CL)" \
  'grep -q "^molecules = 215$" openmm.summary.txt && grep -q "^species = tip4p-ew x 207:" openmm.summary.txt &&
   grep -q "^species = na-tip4pew x 4:" openmm.summary.txt && grep -q "^species = cl-tip4pew x 4:" openmm.summary.txt'
check "openmm: relaxed from its clashes, the NVE run conserves energy (calE < 1e-3)" \
  'awk -F" = " "/^calE =/ {split(\$2, a, \" \"); exit !(a[1] + 0 < 1e-3)}" openmm.summary.txt'

# the deck's box must be the file's (to CRYST1's 0.001 A)
"$rotleap" energy gromacs.ini --set "system.box=18.69 A" > /dev/null 2> box.err; rc=$?
check "a deck box other than CRYST1's is refused, naming both" \
  '[ $rc = 1 ] && grep -q "the box of box_gromacs.pdb (1.8682 1.8682 1.8682 nm) differs from the deck" box.err'
# a count other than the file's: the error names the species and the file
"$rotleap" energy gromacs.ini --set "system.species=tip4p:211 na-tip4pew:3 cl-tip4pew:3" > /dev/null 2> cnt.err; rc=$?
check "a species count other than the file's is refused, naming the file and species" \
  '[ $rc = 1 ] && grep -q "box_gromacs.pdb: 210 residues of species .tip4p., the system has 211" cnt.err'

# the 4-site waters written as 3 atoms (M left out): M placed by the fit, the same energy to the
# file's resolution
"$rotleap" energy openmm.ini > e4.csv 2>/dev/null
grep -v "^HETATM.\{6\}M  " box_openmm.pdb > openmm3.pdb
"$rotleap" energy openmm.ini --set system.start=openmm3.pdb > e3.csv 2> e3.err; rc=$?
check "3-atom waters of TIP4P-Ew start the run (M placed by the fit)" \
  '[ $rc = 0 ] && [ $(grep -c "^HETATM" openmm3.pdb) = 629 ] && python3 -c "
import sys
a = dict(l.strip().split(\",\")[:2] for l in open(\"e4.csv\") if l.startswith(\"total,\"))
b = dict(l.strip().split(\",\")[:2] for l in open(\"e3.csv\") if l.startswith(\"total,\"))
sys.exit(not abs(float(a[\"total\"]) - float(b[\"total\"])) < 1e-3 * abs(float(a[\"total\"])))"'

# a residue name no default knows: refused at its line; system.residues maps it
sed 's/ SOL / WWW /' box_gromacs.pdb > www.pdb
"$rotleap" energy gromacs.ini --set system.start=www.pdb > /dev/null 2> www.err; rc=$?
check "an unknown residue name is refused at its file and line, naming the key" \
  '[ $rc = 1 ] && grep -q "www.pdb:5: residue WWW 1: no species of the system (tip4p, na-tip4pew, cl-tip4pew) has the residue name .WWW.; map it to one (a deck.s system.residues = WWW:SPECIES)" www.err'
"$rotleap" energy gromacs.ini > e_sol.csv 2>/dev/null
"$rotleap" energy gromacs.ini --set system.start=www.pdb --set "system.residues=WWW:tip4p" > e_www.csv 2>/dev/null; rc=$?
check "system.residues = WWW:tip4p: the same energies as SOL" '[ $rc = 0 ] && cmp -s e_sol.csv e_www.csv && grep -q "^total," e_sol.csv'

# system.residues' own problems, at the deck's line
printf 'residues = SOL:water NA\n' > bad_res.txt
sed "/^start = /r bad_res.txt" gromacs.ini > bad.ini
"$rotleap" energy bad.ini > /dev/null 2> bad.err; rc=$?
check "system.residues: an unknown species and a token without a colon, at the line" \
  '[ $rc = 2 ] && grep -q "bad.ini:4: system.residues: SOL:water: .water. is not a species of the deck (tip4p, na-tip4pew, cl-tip4pew)" bad.err &&
   grep -q "bad.ini:4: system.residues: .NA. is not RES:SPECIES" bad.err'
"$rotleap" energy gromacs.ini --set system.start=lattice --set "system.residues=SOL:tip4p" > /dev/null 2> lat.err; rc=$?
check "system.residues without a .pdb start is refused" \
  '[ $rc = 2 ] && grep -q "system.residues: names the residues of a .pdb start, and system.start is lattice" lat.err'

# no system.box or system.density: the start file's box (CRYST1, Lattice=, the checkpoint's), as
# GROMACS and OpenMM take a PDB's; a file without one is refused, naming what it lacks
grep -v "^box = " gromacs.ini > nobox.ini
"$rotleap" energy nobox.ini > e_nobox.csv 2> nobox.err; rc=$?
check "a PDB start without system.box: CRYST1's box, the same energies as with box = 18.682 A" \
  '[ $rc = 0 ] && cmp -s e_sol.csv e_nobox.csv'
grep -v "^CRYST1" box_gromacs.pdb > nocryst.pdb
"$rotleap" energy nobox.ini --set system.start=nocryst.pdb > /dev/null 2> nocryst.err; rc=$?
check "... and one without CRYST1 is refused at the start's line, saying so" \
  '[ $rc = 2 ] && grep -q "^--set: system.start: nocryst.pdb holds no box (no CRYST1 record): give system.box or system.density" nocryst.err'
sm="$src/tests/cli/stockmayer_short.ini"
"$rotleap" run "$sm" --set run.steps=10 --set output.trajectory_every=10 --set output.prefix="$work/smk" >/dev/null 2>&1
grep -v "^density" "$sm" > sm_nobox.ini
# (the checkpoint holds the box bit for bit, the XYZ to 10 decimals: 1e-10 sigma)
for f in smk.chk smk.xyz; do
  "$rotleap" energy "$sm" --set system.start="$work/$f" --json > "e_$f.json" 2>/dev/null
  "$rotleap" energy sm_nobox.ini --set system.start="$work/$f" --json > "e_nobox_$f.json" 2> "nobox_$f.err"; rc=$?
  tol=0; [ $f = smk.xyz ] && tol=1e-9
  check "a ${f##*.} start without system.density: its box, the same energy (relative $tol)" \
    '[ $rc = 0 ] && python3 -c "
import json, sys
a, b = (json.load(open(f))[\"energy\"][\"total\"] for f in sys.argv[1:3])
sys.exit(not abs(a - b) <= float(sys.argv[3]) * abs(a))" "e_$f.json" "e_nobox_$f.json" $tol'
done
sed '2s/Lattice="[^"]*" *//' smk.xyz > nolat.xyz
"$rotleap" energy sm_nobox.ini --set system.start="$work/nolat.xyz" > /dev/null 2> nolat.err; rc=$?
check "... and an XYZ without Lattice= is refused, saying so" \
  '[ $rc = 2 ] && grep -q "system.start: .*nolat.xyz holds no box (no Lattice= on its second line): give system.box or system.density" nolat.err'

echo "pdb_start_tests: $pass passed, $fail failed"
[ "$fail" = 0 ]
