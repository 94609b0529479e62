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

# --- paths are never truncated, and output.prefix names a file (items 5, 11) ---------------
"$rotleap" run "$sm" --set run.steps=100 --set output.prefix="$work/a" >/dev/null 2>&1
"$rotleap" run "$sm" --set run.steps=200 --set output.prefix="$work/b" >/dev/null 2>&1
# D/aaa.chk is the first 511 characters of P = D/aaa.chkx/../b.chk, which names D/b.chk
d="$work/lp"
while [ $(( ${#d} + 200 )) -lt 480 ]; do d="$d/$(printf 'd%.0s' $(seq 199))"; done
d="$d/$(printf 'e%.0s' $(seq $(( 511 - ${#d} - 9 ))))"
mkdir -p "$d/aaa.chkx"; cp "$work/a.chk" "$d/aaa.chk"; cp "$work/b.chk" "$d/b.chk"
p="$d/aaa.chkx/../b.chk"
"$rotleap" run "$sm" --set run.steps=300 --set system.start="$p" --set output.prefix="$work/s" >out.txt 2>err.txt; code=$?
check "a system.start of ${#p} characters loads that file, not the one named by its first 511" \
  '[ $code -eq 0 ] && grep -q "this invocation: 100)" "$work/s.summary.txt"'
long=$(printf 'x%.0s' $(seq 5000))
one_problem "a system.start longer than the system's path limit is refused by its key" \
  "system.start: the path has 5004 characters, more than the system's limit of" "$sm" --set system.start="$long.chk"
one_problem "an output.prefix longer than the path limit allows is refused by its key" \
  "output.prefix has 5000 characters:" "$sm" --set output.prefix="$long"
check "... and nothing is written" '[ -z "$(ls "$work" | grep "^xxxx")" ]'
one_problem "an output.prefix whose file names would be too long is refused by its key" \
  "output.prefix: its last part has 250 characters" "$sm" --set output.prefix="$work/${long:0:250}"
deck "$work/${long:0:240}.ini" ''
timeout 30 "$rotleap" run "$work/${long:0:240}.ini" >out.txt 2>err.txt; code=$?
check "a default prefix (the deck's name) too long for its file names is refused as such" \
  '[ $code -eq 2 ] && grep -q "the default output.prefix (the deck.s name without .ini): its last part has 240 characters" err.txt'
mkdir -p outdir
deck dir.ini 's|^\[output\]|[output]\nprefix = outdir/|'
one_problem "an output.prefix ending in / is refused, saying what to write" \
  "dir.ini:17: output.prefix 'outdir/' names a directory: the outputs would be hidden files (outdir/.thermo.csv); write outdir/NAME" dir.ini
check "... and nothing is written in the directory" '[ -z "$(ls -A outdir)" ]'
one_problem "an output.prefix of .. is refused too" "output.prefix '..' names a directory" "$sm" --set output.prefix=..

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
