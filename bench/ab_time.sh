#!/bin/bash
# A/B timing of two builds of ffbench on this shared host: run `ffbench time ARGS...` with
# binary A and binary B alternately, ROUNDS times each, and print each one's best and median
# ms_per_step and their ratios (B/A).  Read the median ratio: a single run, even the best of a
# few, moves by 10-30 % here with other tenants' load.
#
#   bench/ab_time.sh ROUNDS CPU BIN_A BIN_B -- ARGS...
#   CPU: a CPU list for taskset (one-thread runs), or - for none.
#   e.g. bench/ab_time.sh 12 1 /tmp/ffbench_old build/bench/ffbench -- \
#          time tip4p 256 1 1000 --energy-every 1000 --h 0.006 --relax 200
set -euo pipefail
if [ $# -lt 5 ] || [ "$5" != "--" ]; then
  sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
R=$1 CPU=$2 A=$3 B=$4
shift 5
pre=()
[ "$CPU" != "-" ] && pre=(taskset -c "$CPU")
for r in $(seq "$R"); do
  for b in A B; do
    bin=${!b}
    t=$("${pre[@]}" "$bin" "$@" | grep -o 'ms_per_step=[0-9.]*' | cut -d= -f2)
    [ -n "$t" ] || { echo "ab_time.sh: $bin printed no ms_per_step" >&2; exit 1; }
    echo "$b $t"
  done
done | /usr/bin/python3 -c '
import sys, statistics as st
d = {}
for line in sys.stdin:
    k, v = line.split()
    d.setdefault(k, []).append(float(v))
for k in sorted(d):
    print("%s ms_per_step: best %.4f median %.4f over %d runs" % (k, min(d[k]), st.median(d[k]), len(d[k])))
print("B/A: best %.3f median %.3f" % (min(d["B"]) / min(d["A"]), st.median(d["B"]) / st.median(d["A"])))
'
