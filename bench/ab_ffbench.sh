#!/bin/bash
# The issue-32 speed check: `ffbench time` for TIP4P 256 and 2,048 and Stockmayer 1,000 on 1 and
# 2 threads, with two builds alternated in one run: each round visits every row and runs the old
# and the new binary back to back (in the order old, new in odd rounds and new, old in even ones),
# so both see the same share of a shared host.  Prints per row the median ms_per_step of each
# and the median of the rounds' ratios new/old.
#
#   bench/ab_ffbench.sh ROUNDS OLD_FFBENCH NEW_FFBENCH [STEPS_TIP4P_256 STEPS_TIP4P_2048 STEPS_SM_1000]
#   e.g. bench/ab_ffbench.sh 7 /work/base32/build/bench/ffbench build/bench/ffbench
set -euo pipefail
if [ $# -lt 3 ]; then
  sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
R=$1 OLD=$2 NEW=$3
S256=${4:-400} S2048=${5:-60} SSM=${6:-200}
rows=("tip4p 256 1 $S256" "tip4p 256 2 $S256" "tip4p 2048 1 $S2048" "tip4p 2048 2 $S2048"
      "stockmayer 1000 1 $SSM" "stockmayer 1000 2 $SSM")
for r in $(seq "$R"); do
  for row in "${rows[@]}"; do
    if [ $((r % 2)) -eq 1 ]; then order="old new"; else order="new old"; fi
    for b in $order; do
      if [ "$b" = old ]; then bin=$OLD; else bin=$NEW; fi
      # shellcheck disable=SC2086
      t=$("$bin" time $row | grep -o 'ms_per_step=[0-9.]*' | cut -d= -f2)
      [ -n "$t" ] || { echo "ab_ffbench.sh: $bin time $row printed no ms_per_step" >&2; exit 1; }
      echo "$r|$row|$b|$t"
    done
  done
done | /usr/bin/python3 -c '
import sys, statistics as st
d, order = {}, []
for line in sys.stdin:
    r, row, b, t = line.strip().split("|")
    if row not in d:
        d[row] = {}
        order.append(row)
    d[row].setdefault(int(r), {})[b] = float(t)
print("| model N threads steps | old ms/step (median) | new ms/step (median) | new/old (median of rounds) | rounds |")
print("|---|---|---|---|---|")
for row in order:
    rs = d[row]
    old = [v["old"] for v in rs.values()]
    new = [v["new"] for v in rs.values()]
    q = [v["new"] / v["old"] for v in rs.values()]
    print("| %s | %.4f | %.4f | %.3f | %d |" % (row, st.median(old), st.median(new), st.median(q), len(q)))
'
