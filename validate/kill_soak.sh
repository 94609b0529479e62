#!/usr/bin/env bash
# The kill-and-continue soak of issue 30's acceptance: for TIP4P (DCD + PDB) and Stockmayer
# (extended XYZ), on one and two threads, and Stockmayer under the Monte Carlo and the
# semi-isotropic C-rescale barostat (issue 34), 100 sequences each of one to three SIGKILLs (at random
# moments and at injected system calls: write, rename, fsync, ftruncate, openat, copy_file_range),
# each continued from its checkpoint to the end, plus a kill at every system call of a
# continuation's start (in place and of a completed run extended); checkpoint, thermo file,
# trajectory, PDB, journal and results compared byte for byte with a run never killed.
#   validate/kill_soak.sh [BUILD=build] [SEQUENCES=100]
# Run time: about 7 minutes on 2 cores (validate/kill_soak.txt has the last run's counts).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}; n=${2:-100}
command -v strace >/dev/null || { echo "validate/kill_soak.sh: needs strace (apt-get install strace)"; exit 1; }
start=$(date +%s)
/usr/bin/python3 tests/cli/kill_soak.py "$build/rotleap" "$PWD" "$PWD/$build/kill_soak_full" --starts --sequences "$n" |
  tee "$build/kill_soak_full.log" | grep -v ": ok$" || true
end=$(date +%s)
{ echo "# validate/kill_soak.sh $build $n at $(git rev-parse --short HEAD), $(date -u +%Y-%m-%d), $(nproc) cores, $((end - start)) s"
  grep -c ": ok$" "$build/kill_soak_full.log" | sed 's/^/sequences identical to the run never killed: /'
  grep -c ": FAIL" "$build/kill_soak_full.log" | sed 's/^/sequences that differ: /' || true
  tail -1 "$build/kill_soak_full.log"; } > validate/kill_soak.txt
cat validate/kill_soak.txt
tail -1 "$build/kill_soak_full.log" | grep -q " 0 not$"
