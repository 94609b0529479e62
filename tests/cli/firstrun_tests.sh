#!/usr/bin/env bash
# What a new user reads (issue 31): calE of the conserved quantity under a thermostat, potentials
# that jump at the cutoff said before the run and named as the cause of a drift after it, the
# species' rotation path in the summary, and the default example's relaxation.
# usage: firstrun_tests.sh ROTLEAP SRCDIR WORKDIR
set -u
rotleap=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }
water="$src/tests/cli/water_scan.ini"
field() { grep "^$1 = " "$2" | head -1 | sed "s/^$1 = //; s/ .*//"; }

# --- item 1: under a thermostat calE is of the conserved quantity, as rotleap scan forms it
bussi=(--set run.ensemble=nvt-bussi --set run.temperature=298K --set run.tau=0.05ps --set run.steps=300 --set output.thermo_every=10)
"$rotleap" run "$water" "${bussi[@]}" --set output.prefix="$work/b" >/dev/null 2>err.txt; code=$?
"$rotleap" scan "$water" "${bussi[@]}" --timesteps 1fs --integrators rl --no-plot --set output.prefix="$work/b" >/dev/null 2>&1
calE_run=$(field calE b.summary.txt)
calE_scan=$(/usr/bin/python3 -c "import csv; print(next(csv.DictReader(open('b.scan.csv')))['calE'])")
calE_total=$(/usr/bin/python3 -c "
import csv, statistics as s
E = [float(r['total']) for r in csv.DictReader(open('b.thermo.csv'))]
print(s.stdev(E) / abs(s.mean(E)))")
check "Bussi: run's calE ($calE_run) is of the conserved quantity, like scan's ($calE_scan), not of the total energy ($calE_total)" \
  "[ $code -eq 0 ] && /usr/bin/python3 -c 'import sys; r, s, t = map(float, sys.argv[1:]); sys.exit(0 if r < 0.2 * t and 0.2 < r / s < 5 else 1)' $calE_run $calE_scan $calE_total"
check "the summary says which quantity calE is of" 'grep -q "^calE = .*(relative fluctuation of the conserved quantity: the total energy plus the energy the thermostat took out)" b.summary.txt'

# --- item 2: potentials that jump at the cutoff: said before the run, and a drift they cause is named
sm=(--set system.count=128 --set "model.mu=1.7320508" --set interactions.cutoff=2.5 --set interactions.lj=shifted-force
    --set interactions.eps_rf=inf --set run.steps=4000 --set run.equilibrate=200 --set run.equilibrate_timestep=0.001)
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" "${sm[@]}" --set interactions.dipole=rf --set output.prefix="$work/rf" >/dev/null 2>err.txt; code=$?
check "dipolar reaction field: a warning before the run that it heats at any time step, and the continuous alternative" \
  '[ $code -eq 0 ] && grep -q "warning: dipole-dipole reaction field (eps_rf = inf): the energy of a site pair jumps at the cutoff by up to .* so an NVE run heats at any time step; interactions.dipole = sf is continuous" err.txt'
check "... and after it, the drift it caused named as its, not the time step's (stderr and summary)" \
  'grep -q "warning: the conserved energy drifts by [0-9.]* +- .* the dipole-dipole energy jumps at the cutoff by orientation" err.txt && grep -q "^warning = the conserved energy drifts .* dipole-dipole energy jumps" rf.summary.txt && ! grep -q "time step .* is too large" rf.summary.txt'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" "${sm[@]}" --set interactions.dipole=sf --set output.prefix="$work/sf" >/dev/null 2>err.txt; code=$?
check "shifted force: continuous, no warning, no drift" '[ $code -eq 0 ] && [ ! -s err.txt ] && ! grep -q "^warning" sf.summary.txt'
"$rotleap" run "$water" --set interactions.cutoff=0.125nm --set run.steps=5 --set output.prefix="$work/short" >/dev/null 2>err.txt
check "a cutoff shorter than the LJ well is warned about" 'grep -q "warning: .*cutoff" err.txt'

# --- item 7: the summary names the species' family, rotation path, dof and moments
"$rotleap" run "$water" --set run.steps=5 --set output.prefix="$work/sp" >/dev/null 2>&1
check "the summary's species line: family, dof, rotation path, moments and their relative differences" \
  'grep -q "^species = tip4p x 64: asymmetric, 3+3 dof, rotation path: guarded quasi-analytic cubic (eqs. 28-36); principal moments .* amu nm^2, relative differences .* (X-Y) .* (Y-Z) .* (X-Z), equal below 1e-10" sp.summary.txt'
"$rotleap" run "$water" --set run.steps=5 --set run.integrator=rl-quaternion --set output.prefix="$work/sq" >/dev/null 2>&1
check "... and the path the integrator takes (rl-quaternion)" 'grep -q "rotation path: quaternions, eq. 23 iterated (rl-quaternion)" sq.summary.txt'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=5 --set output.prefix="$work/sd" >/dev/null 2>&1
check "... a point dipole's" 'grep -q "^species = stockmayer x 64: dipole, 3+2 dof, rotation path: rho rotated about l/I" sd.summary.txt'

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
