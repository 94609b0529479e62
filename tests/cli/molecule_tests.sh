#!/usr/bin/env bash
# Molecules a deck defines (issue 35): [molecule NAME] in the deck or in system.molecules.
# Acceptance 1: TIP4P written out site by site, and a Stockmayer dipole, run bit for bit as the
# catalogue's tip4p and stockmayer (trajectory, thermo, checkpoint state and run record; only the
# name differs).  The summary's family and near-miss warning, symmetrize = yes, and the errors of
# acceptance 6 at their file and line.
# usage: molecule_tests.sh ROTLEAP SRCDIR WORKDIR
set -u
rotleap=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }
same_chk() { python3 "$src/tests/cli/chk_same_state.py" "$1" "$2" >/dev/null; }

# --- acceptance 1: TIP4P --------------------------------------------------------------------
cp "$src/tests/cli/tip4p_sites.mol" water.mol
cat > cat.ini <<'DECK'
[system]
model = tip4p
count = 64
density = 1 g/cm3
seed = 7
temperature = 298 K
[interactions]
cutoff = 0.6 nm
[run]
ensemble = nvt-bussi
temperature = 298 K
timestep = 2 fs
steps = 40
[output]
thermo_every = 10
checkpoint_every = 20
trajectory_every = 10
sample_every = 0
progress = no
DECK
sed 's/^model = tip4p/model = water\nmolecules = water.mol/' cat.ini > user.ini
"$rotleap" run cat.ini --set output.prefix=c >/dev/null 2>&1
"$rotleap" run user.ini --set output.prefix=u >/dev/null 2>&1; code=$?
check "TIP4P written out site by site runs" '[ $code -eq 0 ] && grep -q "^species = water x 64: asymmetric" u.summary.txt'
check "... its trajectory (DCD) is the catalogue tip4p's, byte for byte" 'cmp -s c.dcd u.dcd'
check "... and its thermo rows" 'cmp -s c.thermo.csv u.thermo.csv'
check "... its PDB topology differs in the residue name only" 'cmp -s c.pdb <(sed "s/ WAT A / TIP A /" u.pdb)'
check "... its checkpoint holds the same state and run record, bit for bit" 'same_chk c.chk u.chk'
check "... and takes the same pair kernel" 'k=$(grep ^pair_kernels c.summary.txt) && [ -n "$k" ] && [ "$k" = "$(grep ^pair_kernels u.summary.txt)" ]'
# the comparison can fail: H1 one digit off
sed 's/site = H1 0.07569503272636612/site = H1 0.07569503272636613/' water.mol > water2.mol
"$rotleap" run user.ini --set system.molecules=water2.mol --set output.prefix=u2 >/dev/null 2>&1; code=$?
check "a hydrogen moved by 1e-17 nm (one ulp) gives another checkpoint (the DCD holds single precision)" \
  '[ $code -eq 0 ] && [ -s u2.chk ] && ! same_chk c.chk u2.chk'
# the molecule in the deck itself, units in A and kcal/mol
{ sed '/^molecules =/d' user.ini; sed -n '/^\[molecule/,$p' water.mol; } > inline.ini
"$rotleap" run inline.ini --set output.prefix=i >/dev/null 2>&1
check "... the same in the deck itself" 'cmp -s c.dcd i.dcd && same_chk c.chk i.chk'

# a continuation with other charges in the molecule file is another simulation: refused, naming the site
sed 's/charge 0.52/charge 0.53/; s/charge -1.04/charge -1.06/' water.mol > water3.mol

"$rotleap" run user.ini --set system.molecules=water3.mol --set output.prefix=u --set system.start=u.chk --set run.steps=60 >out.txt 2>err.txt; code=$?
check "a continuation whose molecule has other charges is refused, naming each site that changed" \
  '[ $code -ne 0 ] && grep -q "another simulation than this deck asks for (molecule.water.site.H1: 0.07569503272636612 0 0.058588227661829494 mass 1.008 charge 0.52 .*-> .*charge 0.53.*molecule.water.site.M: .*charge -1.04" err.txt'
"$rotleap" run user.ini --set output.prefix=u --set system.start=u.chk --set run.steps=60 >out.txt 2>err.txt; code=$?
"$rotleap" run cat.ini --set output.prefix=c --set system.start=c.chk --set run.steps=60 >/dev/null 2>&1
check "... the same molecule continues, as the catalogue model does" '[ $code -eq 0 ] && cmp -s c.dcd u.dcd && same_chk c.chk u.chk'

# --- acceptance 1: Stockmayer ---------------------------------------------------------------
sm="$src/tests/cli/stockmayer_short.ini"
{ cat "$sm"; echo "checkpoint_every = 100"; echo "trajectory_every = 50"; } > sc.ini
sed -e 's/^model = stockmayer/model = dipol/' -e '/^mu = /d' \
    -e 's/^\[model\]/[molecule dipol]\nunits = lj\ninertia = 0.025\nsite = S 0 0 0 mass 1 sigma 1 epsilon 1 dipole 0 0 1.5/' sc.ini > su.ini
"$rotleap" run sc.ini --set output.prefix=sc >/dev/null 2>&1
"$rotleap" run su.ini --set output.prefix=su >/dev/null 2>&1; code=$?
check "a Stockmayer dipole written as a molecule runs as a point dipole" '[ $code -eq 0 ] && grep -q "^species = dipol x 64: dipole, 3+2 dof" su.summary.txt'
check "... bit for bit as the catalogue stockmayer (thermo, XYZ but its name column)" \
  'cmp -s sc.thermo.csv su.thermo.csv && cmp -s sc.xyz <(sed "s/ dipol$/ stockmayer/" su.xyz)'
check "... checkpoint state and run record" 'same_chk sc.chk su.chk'

# --- families, the near-miss warning and symmetrize ------------------------------------------
# short_run MODEL COUNT DENSITY TEMPERATURE: the rest of a deck, 20 NVE steps at 2 fs
short_run() {
  printf '[system]\nmodel = %s\ncount = %s\ndensity = %s\ntemperature = %s\n[interactions]\ncutoff = 0.6 nm\n' "$@"
  printf '[run]\ntimestep = 2 fs\nsteps = 20\n[output]\nprogress = no\nsample_every = 0\n'
}
python3 - > h.txt <<'PY'
import math
r, ang = 0.10136, 105.99 * math.pi / 180
rho = 2 * r * math.sin(0.5 * ang) / math.sqrt(3); z = math.sqrt(r * r - rho * rho)
for k in range(3):
    print("site = H%d %.6f %.6f %.6f nm mass 1.008 charge 0.3331" % (k + 1, rho * math.cos(2 * math.pi * k / 3), rho * math.sin(2 * math.pi * k / 3), -z))
PY
cat > nh3.ini <<DECK
[molecule ammonia]
; NH3 (Eckl et al. 2008) with its H coordinates rounded to 1e-6 nm: a symmetric top by 6e-6
site = N 0 0 0 nm mass 14.007 charge -0.9993 sigma 3.376 A epsilon 182.9 K
$(cat h.txt)
DECK
short_run ammonia 64 '0.6 g/cm3' '240 K' >> nh3.ini
"$rotleap" run nh3.ini >/dev/null 2>&1
check "a symmetric top with rounded coordinates is integrated as asymmetric, and warned about with the key that fixes it" \
  'grep -q "^species = ammonia x 64: asymmetric.*relative differences 6.27e-06 (X-Y)" nh3.summary.txt &&
   grep -q "^warning = two principal moments of ammonia differ by 6.27e-06 relative.*add symmetrize = yes to \[molecule ammonia\]" nh3.summary.txt'
sed 's/^\[system\]/symmetrize = yes\n[system]/' nh3.ini > nh3s.ini
"$rotleap" run nh3s.ini >/dev/null 2>&1
check "... symmetrize = yes makes it a symmetric top, with no warning" \
  'grep -q "^species = ammonia x 64: symmetric, 3+3 dof, rotation path: Omega_Z = theta_Z" nh3s.summary.txt && ! grep -q "^warning" nh3s.summary.txt'
cat > lin.ini <<'DECK'
[molecule oco]
site = O1 0 0 -1.149 A mass 15.9994 charge -0.3256 sigma 3.033 A epsilon 80.507 K
site = C  0 0 0 A mass 12.011 charge 0.6512 sigma 2.757 A epsilon 28.129 K
site = O2 0 0 1.149 A mass 15.9994 charge -0.3256 sigma 3.033 A epsilon 80.507 K
mixing = geometric
DECK
short_run oco 27 '0.5 g/cm3' '300 K' >> lin.ini
"$rotleap" run lin.ini >/dev/null 2>&1
check "a linear molecule lands on the linear family (rho only, 3+2 dof)" 'grep -q "^species = oco x 27: linear, 3+2 dof" lin.summary.txt'

# --- bad definitions: each at its file and line (acceptance 6) ------------------------------
# bad NAME LINE-PATTERN MESSAGE: the molecule file bad.mol refused at LINE-PATTERN with MESSAGE
bad() {
  local msg=$2
  "$rotleap" run user.ini --set system.molecules=bad.mol >out.txt 2>err.txt; code=$?
  check "$1" '[ $code -eq 2 ] && grep -q -- "$msg" err.txt'
}
mol() { { echo "; a bad molecule"; echo "[molecule water]"; cat; } > bad.mol; }
printf 'site = O 0 0 0 mass 16 sigma 0.3 nm epsilon 0.6\nsite = H 0.1 0 0 mass 1 charge 0.4\nsite = X 0.1 0 0 mass 0 charge -0.4\n' | mol
bad "coincident sites: refused at the second one's line" "bad.mol:5: \[molecule water\] sites H and X coincide"
printf 'site = O 0 0 0 mass 16\nsite = H 0.1 0 0 charge 0.4\n' | mol
bad "a site without a mass" "bad.mol:4: site H has no mass: write mass M (mass 0 for a massless site"
printf 'site = O 0 0 0 mass 0 charge 1\nsite = H 0.1 0 0 mass 0 charge -1\n' | mol
bad "no mass at all" "bad.mol:2: \[molecule water\]: molecule water: total mass is zero"
printf 'site = O 0 0 0 mass 16 sigma -0.3 nm epsilon 0.6\nsite = H 0.1 0 0 mass 1\n' | mol
bad "a negative sigma" "bad.mol:3: site O: sigma -0.3 must be >= 0"
printf 'site = O 0 0 0 mass 16\nsite = H 0.1 nan 0 mass 1\n' | mol
bad "a coordinate that is not finite" "bad.mol:4: site H: position: 'nan' is not a finite number"
printf 'site = O 0 0 0 mass 16\nsite = H 0.1 0 0 mass -1\n' | mol
bad "a negative mass" "bad.mol:4: site H: mass -1 must be >= 0"
printf 'site = O 0 0 0 mass 16 charge inf\nsite = H 0.1 0 0 mass 1\n' | mol
bad "an infinite charge" "bad.mol:3: site O: charge: 'inf' is not a finite number"
printf 'site = A 0 0 0 mass 1\nsite = B 0 0 0.1 mass 1\nsite = Q 0.0001 0 0.05 mass 0 charge 1\n' | mol
bad "a linear molecule with a site off its axis: at that site's line" "bad.mol:5: \[molecule water\]: molecule water: site 2 (Q) is 0.0001 off the axis of a linear molecule"
printf '[molecule tip4p]\nsite = O 0 0 0 mass 16\n' > bad.mol
bad "a molecule named as a catalogue model" "bad.mol:1: \[molecule tip4p\]: the catalogue has a model of that name"
printf 'site = O 0 0 0 mass 16\ncolour = blue\n' | mol
bad "an unknown key" "bad.mol:4: \[molecule water\]: unknown key 'colour'"
printf 'site = O 0 0 0 mass 16\n[system]\ncount = 3\n' | mol
bad "a molecule file with another section" "bad.mol:4: \[system\]: a molecule file holds \[molecule NAME\] sections only"
printf 'site = O 0 0 0 mass 16 sigma 3 A\n' | mol
bad "sigma without epsilon" "bad.mol:3: site O: give sigma and epsilon together"
printf 'site = O 0 0 0 mass 16 sigma 3 parsec epsilon 1\n' | mol
bad "a unit that is not a length" "bad.mol:3: site O: sigma: unit 'parsec' is not a length unit"
"$rotleap" run user.ini --set system.molecules=nothere.mol >out.txt 2>err.txt; code=$?
check "a molecule file that is not there: at the key's line" '[ $code -eq 2 ] && grep -q "^--set: system.molecules: cannot open nothere.mol: No such file" err.txt && grep -q "^rotleap run: 1 problem" err.txt'
{ sed '/^molecules =/d' user.ini; printf '[molecule water]\nsite = O 0 0 0 mass 16\n[molecule water]\nsite = H 0 0 0 mass 1\n'; } > twice.ini
"$rotleap" run twice.ini >out.txt 2>err.txt; code=$?
check "a molecule defined twice: at the second header, naming the first" '[ $code -eq 2 ] && grep -q "twice.ini:22: \[molecule water\] is defined twice (first at twice.ini:20)" err.txt'

echo "molecule tests: $pass passed, $fail failed"
[ $fail -eq 0 ]
