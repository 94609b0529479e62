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

# --- decks that are not text files or never end (item 7) -----------------------------------
one_problem "/dev/zero as the deck is refused at once" "/dev/zero: is not a regular file (a character device)" /dev/zero
ln -sf /dev/zero zero.ini
one_problem "a deck linked to /dev/zero is refused at once" "zero.ini: is not a regular file (a character device)" zero.ini
ln -sf /dev/zero zero.chk
one_problem "a system.start linked to /dev/zero is refused by its key, not read" \
  "system.start: zero.chk is not a regular file (a character device)" "$sm" --set system.start=zero.chk
cat /dev/zero | timeout 30 "$rotleap" run /dev/stdin >out.txt 2>err.txt; code=$?
check "NUL bytes from a pipe end the read at once" '[ $code -eq 2 ] && grep -q "is not a text file (a NUL byte on line 1)" err.txt'
tr '\0' 'a' < /dev/zero | timeout 30 "$rotleap" run /dev/stdin >out.txt 2>err.txt; code=$?
check "an endless line from a pipe stops at the size limit" '[ $code -eq 2 ] && grep -q "is longer than 1048576 bytes (1 MiB), the most a deck may have" err.txt'
yes 'this is no key' | timeout 30 "$rotleap" run /dev/stdin >out.txt 2>err.txt; code=$?
check "an endless stream of bad lines stops after 100 problems" \
  '[ $code -eq 2 ] && [ "$(grep -c "not a valid deck line" err.txt)" -eq 100 ] && grep -q "stopped reading at line 100" err.txt'
{ cat "$sm"; for i in $(seq 20000); do echo "; a comment line of some length, to make the deck large $i"; done; } > big.ini
one_problem "a deck over 1 MiB is refused by its size" "big.ini: is [0-9]* bytes, more than the 1048576 bytes (1 MiB) a deck may have" big.ini
# a line of exactly 199 characters is read, and the line after it too; one of 200 is refused
deck l199.ini "s|^\\[output\\]|[output]\\nrdf = S-S$(printf ',%.0s' $(seq 190))|"
len=$(grep "^rdf" l199.ini | tr -d '\n' | wc -c)
"$rotleap" run l199.ini --set output.prefix="$work/l199" --set run.steps=20 >out.txt 2>err.txt; code=$?
check "a line of 199 characters ($len) is read, and the line after it (thermo_every = 10: rows 0 10 20)" \
  '[ $len -eq 199 ] && [ $code -eq 0 ] && [ "$(tail -n +2 l199.thermo.csv | cut -d, -f1 | tr "\n" " ")" = "0 10 20 " ]'
sed -i 's|^rdf = S-S|rdf = S-S,|' l199.ini
one_problem "a line of 200 characters is refused at its line" "l199.ini:17: this line has 200 characters, a deck line at most 199" l199.ini

# --- the line format: comments, indentation, empty values (item 11) ------------------------
deck cmt.ini 's|^\[output\]|[output]\nprefix = cmt # a note|; s|^temperature = 1.35|temperature = 1.35 # the start|'
"$rotleap" run cmt.ini --set run.steps=2 >out.txt 2>err.txt; code=$?
check "'# note' after a blank is a comment in every value (prefix, temperature)" \
  '[ $code -eq 0 ] && [ -s cmt.thermo.csv ] && [ -z "$(ls | grep "#")" ]'
deck semi.ini 's|^\[output\]|[output]\nprefix = semi ; a note|'
"$rotleap" run semi.ini --set run.steps=2 >out.txt 2>err.txt; code=$?
check "'; note' after a blank is a comment too" '[ $code -eq 0 ] && [ -s semi.thermo.csv ]'
deck hash.ini 's|^\[output\]|[output]\nprefix = run#2|'
"$rotleap" run hash.ini --set run.steps=2 >out.txt 2>err.txt; code=$?
check "a # with no blank before it is part of the value" '[ $code -eq 0 ] && [ -s "run#2.thermo.csv" ]'
one_problem "--set with ' #' in a value is refused (a deck would read a comment)" \
  "--set: output.prefix: 'out # note' contains ' #'" "$sm" --set "output.prefix=out # note"
deck empty.ini 's|^\[output\]|[output]\nprefix =|'
one_problem "an empty output.prefix is refused, saying what to write" \
  "empty.ini:17: output.prefix has no value: write a path prefix" empty.ini
check "... and no hidden file is written" '[ ! -e .thermo.csv ] && [ ! -e .summary.txt ]'
deck es.ini 's|^\[system\]|[system]\nstart =|'
one_problem "an empty system.start is refused, not taken as the lattice" "es.ini:3: system.start has no value" es.ini
deck ind.ini 's|^density = 0.8|  density = 0.8|'
"$rotleap" energy ind.ini >ind.txt 2>err.txt; code=$?
"$rotleap" energy "$sm" >flat.txt 2>/dev/null
check "an indented key is read as its own key, not as a continuation" '[ $code -eq 0 ] && [ ! -s err.txt ] && cmp -s ind.txt flat.txt'
deck cont.ini 's|^lj = shifted-force|lj = shifted\n   -force|'
one_problem "an indented line with no key is reported at its own line: a value does not continue" \
  "cont.ini:12: an indented line does not continue the value of the line before it" cont.ini

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

# --- a section name beyond libinih's 49 characters is refused at its line, not cut silently ----
long_sec=$(printf 'x%.0s' $(seq 60))
deck sec.ini "s|^\[output\]|[output$long_sec]|"
one_problem "a section name of 66 characters is refused at its line" "the section name \[outputxxx" sec.ini

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
