#!/usr/bin/env bash
# Several species per deck (issue 35): system.species = NAME:COUNT ..., interactions.mixing and
# interactions.pairs.  A Stockmayer fluid in an LJ solvent (reduced units) runs and its summary
# names each species; a mixture of the catalogue's stockmayer and the same dipole written as a
# [molecule] gives the one-species energies and forces to round-off from one start; geometric
# mixing equals Lorentz-Berthelot with the geometric pair given as an override; and the errors:
# a count of 0, unknown species or sites in pair overrides, a molecule named like a catalogue
# model, system.species with system.model, species in two unit systems.
# usage: species_tests.sh ROTLEAP WORKDIR
set -u
rotleap=$1; work=$2
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }
# the largest relative difference of two `rotleap energy` outputs (every number, 1 + |b| scale)
maxrel() {
  python3 - "$1" "$2" <<'PY'
import sys
a = [l.strip().split(',') for l in open(sys.argv[1])]
b = [l.strip().split(',') for l in open(sys.argv[2])]
m = 0.0 if len(a) == len(b) and len(a) > 10 else 1.0
for x, y in zip(a, b):
    for u, v in zip(x, y):
        try: m = max(m, abs(float(u) - float(v)) / (1 + abs(float(v))))
        except ValueError: m = m if u == v else 1.0
print(m)
PY
}

cat > mix.ini <<'DECK'
[system]
species = stockmayer:27 lj:81
density = 0.8
lattice = fcc
temperature = 1.35
seed = 3
[molecule lj]
units = lj
site = A 0 0 0 mass 1 sigma 1 epsilon 1
[interactions]
cutoff = 2.0
lj = shifted-force
dipole = sf
[run]
steps = 50
timestep = 0.002
[output]
thermo_every = 10
progress = no
DECK

# --- a mixture runs; the summary names each species ----------------------------------------
"$rotleap" run mix.ini > run.out 2> run.err; code=$?
check "mixture runs (Stockmayer in LJ solvent)" '[ $code = 0 ] && grep -q "^status = ok" mix.summary.txt'
check "summary: model = stockmayer + lj" 'grep -q "^model = stockmayer + lj$" mix.summary.txt'
check "summary: one line per species with its path" 'grep -q "^species = stockmayer x 27: dipole, 3+2 dof, rotation path: rho rotated" mix.summary.txt &&
  grep -q "^species = lj x 81: point, 3+0 dof, rotation path: none" mix.summary.txt'
check "checkpoint records the species" 'strings mix.chk | grep -q "system.species = stockmayer:27 lj:81"'
check "energy conserved over 50 steps (calE < 1e-3)" 'awk -F" = " "/^calE =/ {split(\$2, a, \" \"); exit !(a[1] + 0 < 1e-3)}" mix.summary.txt'

# --- a mixture's checkpoint continues the run bit for bit ------------------------------------
"$rotleap" run mix.ini --set output.prefix=full --set output.checkpoint_every=25 > /dev/null 2>&1
"$rotleap" run mix.ini --set output.prefix=half --set run.steps=25 > /dev/null 2>&1
"$rotleap" run mix.ini --set output.prefix=half --set system.start=half.chk > /dev/null 2>&1; code=$?
check "a mixture continued from its checkpoint ends bit for bit as one run" '[ $code = 0 ] && cmp -s full.chk half.chk && cmp -s full.thermo.csv half.thermo.csv'

# --- one species through system.species is system.model + count, byte for byte --------------
sed 's/^species = .*/model = stockmayer\ncount = 108/' mix.ini > one.ini
sed 's/^species = .*/species = stockmayer:108/' mix.ini > one_sp.ini
"$rotleap" energy one.ini > one.csv 2>&1; "$rotleap" energy one_sp.ini > one_sp.csv 2>&1
check "species = stockmayer:108 equals model + count (energy output identical)" 'cmp -s one.csv one_sp.csv && grep -q "^total," one.csv'

# --- a two-species mixture of equal dipoles is the one-species system -----------------------
sed 's/^steps = 50/steps = 1/; /^thermo_every/a trajectory_every = 1' one.ini > traj.ini
"$rotleap" run traj.ini --set output.prefix=t > /dev/null 2>&1
sed '57,110s/ stockmayer$/ sm/' t.xyz > mix.xyz
sed 's/^species = .*/species = stockmayer:54 sm:54/; s/^lattice = fcc/start = mix.xyz/' mix.ini > sm.ini
cat >> sm.ini <<'DECK'
[molecule sm]
units = lj
site = S 0 0 0 mass 1 sigma 1 epsilon 1 dipole 0 0 1.7320508075688772
inertia = 0.025
DECK
sed 's/^lattice = fcc/start = t.xyz/' one.ini > onex.ini
"$rotleap" energy sm.ini > sm.csv 2>&1; "$rotleap" energy onex.ini > onex.csv 2>&1
rel=$(maxrel sm.csv onex.csv)
check "stockmayer:54 + equal user dipole:54 = stockmayer x 108 to 1e-12 (got $rel)" 'python3 -c "import sys; sys.exit(not $rel < 1e-12)"'

# --- mixing rules and pair overrides ----------------------------------------------------------
sed 's/sigma 1 epsilon 1/sigma 1.2 epsilon 0.8/' mix.ini > lb.ini
sed 's/^dipole = sf/&\nmixing = geometric/' lb.ini > geo.ini
sed 's/^dipole = sf/&\npairs = stockmayer:S lj:A sigma 1.0954451150103321 epsilon 0.89442719099991586/' lb.ini > ovr.ini
for k in lb geo ovr; do "$rotleap" energy $k.ini > $k.csv 2>&1; done
check "geometric mixing differs from Lorentz-Berthelot" 'grep -q "^lj," lb.csv && ! cmp -s lb.csv geo.csv'
rel=$(maxrel geo.csv ovr.csv)
check "Lorentz-Berthelot + the geometric pair as an override = geometric (got $rel)" 'python3 -c "import sys; sys.exit(not $rel < 1e-14)"'

# --- errors -----------------------------------------------------------------------------------
err() { "$rotleap" energy "$@" > e.out 2> e.err; echo $?; }
code=$(err mix.ini --set system.species="stockmayer:27 lj:0")
check "count 0 refused" '[ $code = 2 ] && grep -q "system.species: lj:0: the count must be a whole number >= 1 (leave out a species with no molecules)" e.err'
code=$(err mix.ini --set interactions.pairs="stockmayer:S lj:B sigma 1 epsilon 1")
check "pair override: unknown site named, with the sites it has" '[ $code = 2 ] && grep -q "interactions.pairs: species lj has no site .B. (its sites: A)" e.err'
code=$(err mix.ini --set interactions.pairs="water:O lj:A sigma 1 epsilon 1")
check "pair override: unknown species named" '[ $code = 2 ] && grep -q "interactions.pairs: .water. is not a species of the deck (stockmayer, lj)" e.err'
sed 's/^\[molecule lj\]/[molecule argon]/; s/ lj:81/ argon:81/' mix.ini > clash.ini
code=$(err clash.ini)
check "a molecule named like a catalogue model refused at its line" '[ $code = 2 ] && grep -q "clash.ini:7: \[molecule argon\]: the catalogue has a model of that name" e.err'
code=$(err mix.ini --set system.model=stockmayer)
check "system.species with system.model refused" '[ $code = 2 ] && grep -q "system.model: give system.species or system.model and system.count, not both" e.err'
code=$(err mix.ini --set system.species="stockmayer:27 argon:81")
check "species in two unit systems refused" '[ $code = 2 ] && grep -q "argon is in real units, stockmayer in reduced (lj)" e.err'
code=$(err mix.ini --set system.species="stockmayer:27 lj")
check "NAME without a count refused" '[ $code = 2 ] && grep -q "system.species: .lj. is not NAME:COUNT" e.err'

# --- salt water (real units, catalogue ions); what mixtures cannot do yet is refused -----------
cat > salt.ini <<'DECK'
[system]
species = spc-e:64 na-spce:2 cl-spce:2
density = 1 g/cm3
seed = 5
temperature = 298 K
[interactions]
cutoff = 0.6 nm
[run]
steps = 10
timestep = 1 fs
[output]
thermo_every = 5
progress = no
DECK
"$rotleap" run salt.ini > salt.out 2>&1; code=$?
check "SPC/E with Na+ and Cl- runs (real units)" '[ $code = 0 ] && grep -q "^species = na-spce x 2: point, 3+0 dof" salt.summary.txt && grep -q "^molecules = 68$" salt.summary.txt'
"$rotleap" run salt.ini --set system.lattice=random --set output.prefix=ins1 > /dev/null 2>&1; code=$?
"$rotleap" run salt.ini --set system.lattice=random --set output.prefix=ins2 > /dev/null 2>&1
check "random insertion start runs, the same for the same seed" '[ $code = 0 ] && grep -q "^status = ok" ins1.summary.txt && cmp -s ins1.thermo.csv ins2.thermo.csv && ! cmp -s ins1.thermo.csv salt.thermo.csv'
code=$(err mix.ini --set system.lattice=random --set system.density=2.5 --set interactions.cutoff=1.5)
check "random insertion in a box too full: a clear error" '[ $code = 1 ] && grep -q "system.lattice = random: molecule [0-9]* of 108 (.*) found no place in 10000 tries" e.err'
code=$(err salt.ini --set output.trajectory_every=5)
check "a site model's DCD trajectory in a mixture refused" '[ $code = 2 ] && grep -q "species spc-e is a site model" e.err'
"$rotleap" scan salt.ini > e.out 2> e.err; code=$?
check "rotleap scan refuses a mixture" '[ $code = 2 ] && grep -q "a mixture (system.species) cannot be scanned yet" e.err'

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
