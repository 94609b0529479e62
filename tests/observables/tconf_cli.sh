#!/usr/bin/env bash
# output.tconf (issue 37): rotleap run reports the configurational temperature (translational,
# rotational, total) with error bars and units; nothing without it; a continuation gives the results
# of the uninterrupted run bit for bit (the sums are journaled) and one that changes output.tconf is
# refused; a force field whose forces jump at the cutoff gets the note that the estimate is biased.
# usage: tconf_cli.sh ROTLEAP WORKDIR
source "$(dirname "$0")/cli_check.sh"
cat > sm.ini <<'DECK'
[system]
model = stockmayer
count = 64
density = 0.8
temperature = 1.35
[interactions]
cutoff = 2.0
lj = shifted-force
dipole = sf
[run]
steps = 400
timestep = 0.002
ensemble = nvt-bussi
temperature = 1.35
tau = 0.05
equilibrate = 200
[output]
sample_every = 5
tconf = yes
progress = no
DECK
val() { sed -n "s/^$2 = \([^ ]*\).*/\1/p" "$1"; }
"$rotleap" run sm.ini --set output.prefix=A >/dev/null 2>A.err; code=$?
check "a run with output.tconf = yes succeeds" "[ $code = 0 ]"
for k in tconf_translational tconf_rotational tconf; do
  check "$k: a value, an error bar and the unit" "grep -q '^$k = [0-9.]* +- [0-9.e+-]* epsilon/k_B (' A.results.txt"
done
T=$(val A.results.txt tconf_translational); Tr=$(val A.results.txt tconf_rotational)
check "T_conf within 15 % of the thermostat's 1.35 (trans $T, rot $Tr)" \
  "awk -v a=$T -v b=$Tr 'BEGIN { exit !(a > 1.15 && a < 1.55 && b > 1.15 && b < 1.55) }'"
check "continuous forces: no bias note" "! grep -q '^tconf_note' A.results.txt"
"$rotleap" run sm.ini --set output.prefix=N --set output.tconf=no >/dev/null 2>&1
check "output.tconf = no (the default): no tconf lines" "! grep -q '^tconf' N.results.txt"
check "... and the other results as with it" "diff <(grep -v '^tconf' A.results.txt) N.results.txt >/dev/null"
# half the run, then its continuation: the results of the uninterrupted run
"$rotleap" run sm.ini --set output.prefix=B --set run.steps=200 >/dev/null 2>&1
"$rotleap" run sm.ini --set output.prefix=B --set system.start=B.chk >/dev/null 2>B.err; code=$?
check "the continuation succeeds" "[ $code = 0 ]"
check "continued results identical to the uninterrupted run's" "cmp -s A.results.txt B.results.txt"
"$rotleap" run sm.ini --set output.prefix=C --set run.steps=200 --set output.tconf=no >/dev/null 2>&1
"$rotleap" run sm.ini --set output.prefix=C --set system.start=C.chk >/dev/null 2>C.err; code=$?
check "a continuation that turns output.tconf on is refused, naming it" "[ $code != 0 ] && grep -q 'output.tconf' C.err"
# TIP4P with plain LJ and eps_rf 78.3: forces jump at the cutoff
cat > w.ini <<'DECK'
[system]
model = tip4p
count = 27
density = 0.997 g/cm3
temperature = 300 K
[interactions]
cutoff = 0.42 nm
lj = plain
eps_rf = 78.3
[run]
steps = 60
timestep = 1 fs
ensemble = nvt-langevin
temperature = 300 K
[output]
sample_every = 3
tconf = yes
progress = no
DECK
"$rotleap" run w.ini --set output.prefix=W >/dev/null 2>&1
check "TIP4P: tconf in K" "grep -q '^tconf_rotational = [0-9.]* +- [0-9.e+-]* K (' W.results.txt"
check "TIP4P plain LJ, eps_rf 78.3: the note that the estimate is biased, naming the terms" \
  "grep -q '^tconf_note = biased: .*lj (energy jumps), coulomb (force jumps)' W.results.txt"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
