#!/usr/bin/env bash
# Robustness of the rotleap command (the CLI audit's defects): decks that libinih would misparse,
# bad or absurd values, outputs that would overwrite inputs, resource requests, continuations
# after kills and failures.  Every check names what it guards.
# usage: robust_tests.sh ROTLEAP SRCDIR WORKDIR
set -u
rotleap=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }
sm="$src/tests/cli/stockmayer_short.ini"
water="$src/tests/cli/water_scan.ini"

# --- long deck lines (libinih reads 200-byte pieces): read whole, refused once at their own line
long=$(printf 'a long explanatory comment %.0s' $(seq 12))
{ sed -n 1,5p "$sm"; echo "; $long = yes"; sed -n '6,$p' "$sm"; } > longcomment.ini
"$rotleap" energy longcomment.ini >out.txt 2>err.txt; code=$?
check "a comment line of ${#long}+ characters is a comment, nothing else" '[ $code -eq 0 ] && [ ! -s err.txt ]'
sed "s/^temperature = 1.35\$/temperature = 1.35 ; $long/" "$sm" > longinline.ini
"$rotleap" energy longinline.ini >out.txt 2>err.txt; code=$?
check "a long inline comment after a value is a comment" '[ $code -eq 0 ] && [ ! -s err.txt ]'
{ sed -n 1,5p "$sm"; echo "; $long"; sed -n '6,$p' "$sm" | sed 's/^timestep = .*/timestep = 2 fortnights/'; } > longline2.ini
want=$(grep -n "^timestep" longline2.ini | cut -d: -f1)
"$rotleap" run longline2.ini >out.txt 2>err.txt; code=$?
check "after a long comment an error keeps its own line number ($want)" \
  '[ $code -eq 2 ] && grep -q "longline2.ini:$want: run.timestep: " err.txt && grep -q "^rotleap run: 1 problem in" err.txt'
{ sed -n 1,5p "$sm"; echo "rdf = S-S$(printf ', S-S%.0s' $(seq 60))"; sed -n '6,$p' "$sm"; } > longkey.ini
"$rotleap" run longkey.ini >out.txt 2>err.txt; code=$?
check "a long key line is refused once, at its line, with the limit" \
  '[ $code -eq 2 ] && grep -q "longkey.ini:6: this line has [0-9]* characters, a deck line at most 199" err.txt && grep -q "^rotleap run: 1 problem in" err.txt'
head -c 3000 /dev/urandom | tr -d "\n" > bin.ini; printf '\0\0\0\n[system]\n' >> bin.ini
"$rotleap" run bin.ini >out.txt 2>err.txt; code=$?
check "a binary file given as the deck is refused in one line" '[ $code -eq 2 ] && grep -q "bin.ini: is not a text file" err.txt && [ "$(wc -l < err.txt)" -eq 2 ]'

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
