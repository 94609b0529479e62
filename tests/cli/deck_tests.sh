#!/usr/bin/env bash
# The deck reader and its messages (issue 30 items 5, 7, 11; issue 31 item 4): paths of any
# length the system accepts, never truncated; decks that are not text files or never end; the
# line format (comments, indentation, empty values); each problem named once, at its own line.
# usage: deck_tests.sh ROTLEAP SRCDIR WORKDIR
set -u
rotleap=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }
sm="$src/tests/cli/stockmayer_short.ini"
# one_problem NAME MESSAGE ARGS...: the deck is refused (exit 2) with MESSAGE and no other problem
one_problem() {
  local name=$1 msg=$2; shift 2
  timeout 30 "$rotleap" run "$@" >out.txt 2>err.txt; code=$?
  check "$name" '[ $code -eq 2 ] && grep -q -- "$msg" err.txt && grep -q "^rotleap run: 1 problem in" err.txt'
}
# a deck: the short Stockmayer deck with sed's edits (deck NAME SED-SCRIPT)
deck() { sed -e "$2" "$sm" > "$1"; }

# --- model parameters refused at their lines (item 11) ------------------------------------
deck i0.ini 's|^mu = 1.5|mu = 1.5\ninertia = 0|'
one_problem "inertia = 0 is refused at its line" "i0.ini:9: \[model\] inertia: model stockmayer: inertia 0 must be positive" i0.ini
printf '[system]\nmodel = 2clj\ncount = 108\ndensity = 0.6\ntemperature = 2\n[model]\nelongation = 0\n[interactions]\ncutoff = 2.5\n[run]\nsteps = 10\ntimestep = 0.001\n' > e0.ini
one_problem "elongation = 0 is refused at its line" "e0.ini:7: \[model\] elongation: model 2clj: elongation 0 must be positive" e0.ini
one_problem "a model parameter from --set is named as such" "--set: \[model\] elongation: model 2clj: elongation 0 must be positive" \
  e0.ini --set model.elongation=0.5 --set model.elongation=0

# --- the relaxation's step, checked with the deck (item 11) ------------------------------
one_problem "an absurd run.equilibrate_timestep is refused before the relaxation" \
  "--set: run.equilibrate_timestep 1 reduced is too large for stockmayer at 1.35 reduced (system.temperature, the relaxation's)" \
  "$sm" --set run.equilibrate=10 --set run.equilibrate_timestep=1 --set output.prefix="$work/eq"
check "... and nothing is written" '[ ! -e "$work/eq.thermo.csv" ] && [ ! -e "$work/eq.summary.txt" ]'
"$rotleap" run "$sm" --set run.equilibrate_timestep=1 --set run.steps=2 --set output.prefix="$work/eq0" >out.txt 2>err.txt; code=$?
check "an unused run.equilibrate_timestep (no relaxation) is not checked against the rotation" '[ $code -eq 0 ]'

# --- an invalid choice is the only problem reported (issue 31 item 4) ----------------------
deck nvt.ini 's|^temperature = 1.35|; none|; s|^\[run\]|[run]\nensemble = nvt-bussi\ntemperature = 1.35|'
one_problem "an invalid run.ensemble is reported alone (no run.temperature or system.temperature noise)" \
  "run.ensemble: 'nvt-foo' is not one of" nvt.ini --set run.ensemble=nvt-foo
one_problem "... also from an NVE deck with run.temperature given" \
  "run.ensemble: 'nvt-foo' is not one of" "$sm" --set run.ensemble=nvt-foo --set run.temperature=1.35
one_problem "an invalid interactions.lj does not make interactions.switch unused" \
  "interactions.lj: 'switchd' is not one of" "$sm" --set interactions.lj=switchd --set interactions.switch=1.5

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
