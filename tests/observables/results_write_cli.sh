#!/usr/bin/env bash
# rotleap run when PREFIX.results.txt, .rdf.csv or .tcf.csv cannot be written (CLI audit D6): exit 1,
# the file and the reason on stderr; the other outputs (thermo, summary, checkpoint and the other
# analysis files) are written as usual.  A directory in place of the file stands for any failure.
# usage: results_write_cli.sh ROTLEAP WORKDIR
source "$(dirname "$0")/cli_check.sh"
cat > sm.ini <<'DECK'
[system]
model = stockmayer
count = 32
density = 0.8
temperature = 1.35
[interactions]
cutoff = 1.5
lj = shifted-force
dipole = sf
[run]
steps = 60
timestep = 0.002
[output]
thermo_every = 10
sample_every = 5
rdf = S-S
discard = 0
progress = no
DECK
"$rotleap" run sm.ini --set output.prefix=ok >out.txt 2>err.txt; code=$?
check "a run whose files can be written exits 0" '[ $code -eq 0 ] && [ ! -s err.txt ]'
for x in results.txt rdf.csv tcf.csv; do
  p=bad_${x%%.*}
  mkdir "$p.$x"
  "$rotleap" run sm.ini --set output.prefix=$p >out.txt 2>err.txt; code=$?
  check "$x unwritable: exit 1" '[ $code -eq 1 ]'
  check "$x unwritable: stderr names the file and the reason" 'grep -q "cannot write the results: .*$p\.$x.*Is a directory" err.txt'
  check "$x unwritable: thermo, summary and checkpoint written; the summary says status = error and why" '[ -s $p.thermo.csv ] && grep -q "^status = error" $p.summary.txt && grep -q "^error = cannot write the results: .*$p\.$x" $p.summary.txt && [ -s $p.chk ]'
  for y in results.txt rdf.csv tcf.csv; do
    [ $y = $x ] && continue
    check "$x unwritable: $y written" '[ -s $p.$y ]'
  done
  check "$x unwritable: no temporary file left" '[ -z "$(ls | grep "\.tmp\.")" ]'
done
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
