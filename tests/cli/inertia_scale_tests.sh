#!/usr/bin/env bash
# system.inertia_scale (issue 37): heavier rotors for larger steps.
#  - a free rigid body (one TIP4P molecule, no partner within the cutoff) is the same discrete
#    trajectory with moments s J, time step sqrt(s) h and angular momenta sqrt(s) L (the start draws
#    L from the Maxwell-Boltzmann distribution of the scaled moments with the same random numbers):
#    the orientations after 500 steps agree bit for bit and L is sqrt(s) times larger, which fails
#    if the scale reaches the start but not the integrator, or the other way round;
#  - the summary prints the scaled moments and says so; a run continues bit for bit; a checkpoint
#    continued with another scale is refused with the cause named; values outside [1, 100] and
#    non-numbers are deck errors naming the key.
# usage: inertia_scale_tests.sh ROTLEAP WORKDIR
set -u
rotleap=$1; work=$2
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }

cat > one.ini <<'DECK'
[system]
model = tip4p
count = 1
box = 2 nm
temperature = 298 K
seed = 5
[interactions]
cutoff = 0.9 nm
[run]
ensemble = nve
timestep = 2 fs
steps = 500
[output]
progress = no
DECK
"$rotleap" run one.ini --set output.prefix=s1 >/dev/null 2>s1.err
"$rotleap" run one.ini --set output.prefix=s4 --set system.inertia_scale=4 --set "run.timestep=4 fs" >/dev/null 2>s4.err
check "free body: moments 4 J at 2 h is the same trajectory" "python3 - <<'PY'
import sys
sys.path.insert(0, '$here/../../validate')
import rlcheckpoint as rc
a, b = rc.read('s1.chk'), rc.read('s4.chk')
same_A = a['A'] == b['A']
lr = [y / x for x, y in zip(a['l'][0], b['l'][0])]
ok = same_A and all(abs(q - 2.0) < 1e-14 for q in lr) and abs(b['time'] - 2 * a['time']) < 1e-12
print('orientations identical:', same_A, 'L ratios:', lr)
sys.exit(0 if ok else 1)
PY"
check "summary: scaled moments, named" "grep -q 'principal moments 0.0245828 0.0462046 0.0707874 amu nm^2 (the model.s times system.inertia_scale = 4' s4.summary.txt"

cat > liq.ini <<'DECK'
[system]
model = tip4p
count = 64
density = 1 g/cm3
seed = 3
inertia_scale = 4
[interactions]
cutoff = 0.6 nm
eps_rf = inf
lj = shifted-force
[run]
ensemble = nvt-langevin-dot
temperature = 298 K
tau = 1 ps
tau_rot = 0.05 ps
timestep = 6 fs
equilibrate = 200
[output]
thermo_every = 10
progress = no
DECK
"$rotleap" run liq.ini --set run.steps=60 --set output.prefix=full >/dev/null 2>full.err
"$rotleap" run liq.ini --set run.steps=30 --set output.prefix=part >/dev/null 2>part.err
"$rotleap" run liq.ini --set run.steps=60 --set system.start=part.chk --set output.prefix=part >/dev/null 2>cont.err
check "continues bit for bit" "cmp -s full.chk part.chk && cmp -s full.thermo.csv part.thermo.csv"
"$rotleap" run liq.ini --set run.steps=60 --set system.start=part.chk --set system.inertia_scale=1 --set output.prefix=other >/dev/null 2>other.err
check "another scale on continuation: refused, cause named" "grep -q 'system.inertia_scale, 1 in this deck' other.err"
for bad in 0.5 101 abc; do
  "$rotleap" run liq.ini --set system.inertia_scale=$bad --set output.prefix=bad >/dev/null 2>bad.err; rc=$?
  check "inertia_scale = $bad refused" "[ $rc -ne 0 ] && grep -q 'system.inertia_scale' bad.err && [ ! -e bad.chk ]"
done
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
