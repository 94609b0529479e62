#!/usr/bin/env bash
# Checkpoint continuation is bit for bit: 2N steps in one run, and N steps + a continuation of the
# checkpoint under the same prefix + N steps, give byte-identical final checkpoints (state, time,
# thermostat account, random stream, accumulators, output marks) and thermo files; under another
# prefix the state and the rows from step N are the same.  For NVE and every NVT thermostat
# (Stockmayer), and final checkpoints for TIP4P in a small and a larger box, for dipoles with a
# cell grid and for TIP4P on two threads.
# usage: restart_tests.sh ROTLEAP SRCDIR WORKDIR [PART]: PART = stockmayer (every thermostat,
# energy_every, another seed), tip4p (216 and 512 TIP4P), cells (1,000 dipoles with a cell grid),
# threads (512 TIP4P on two threads); all by default.  CTest runs the parts as four tests.
set -u
rotleap=$1; src=$2; work=$3; part=${4:-all}
mkdir -p "$work"; cd "$work" || exit 1
deck="$src/tests/cli/stockmayer_short.ini"
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }
# quiet FILE: nothing on stderr but the notes said before a run (what jumps at the cutoff)
quiet() { ! grep -qv "^rotleap [a-z]*: note: " "$1"; }
same_state() {
  python3 -c 'import sys; sys.path.insert(0, sys.argv[1]); import rlcheckpoint as c
a, b = c.read(sys.argv[2]), c.read(sys.argv[3])
sys.exit(0 if all(a[k] == b[k] for k in ("r", "v", "l", "A", "rho", "step", "time")) else 1)' "$src/validate" "$1" "$2"
}
# three_runs NAME DECK ARGS...: NAME-A (2N = 100 steps in one run, a checkpoint at N), NAME-B
# (N steps, its checkpoint kept as NAME-Bn.chk), then NAME-B continued under its own prefix to
# 2N, and NAME-C: NAME-Bn.chk continued under another prefix (new files from step N); their
# errors in NAME.err; then the first checks: the continued run's files are the uninterrupted
# run's, byte for byte (checkpoint, thermo rows), and the other prefix's state is the same
three_runs() {
  local name=$1 dk=$2; shift 2
  local N=${HALF:-50}
  "$rotleap" run "$dk" "$@" --set run.steps=$((2 * N)) --set output.checkpoint_every=$N --set output.prefix="$work/$name-A" >/dev/null 2>"$name.err" || true
  "$rotleap" run "$dk" "$@" --set run.steps=$N --set output.prefix="$work/$name-B" >/dev/null 2>>"$name.err" || true
  cp "$work/$name-B.chk" "$work/$name-Bn.chk"; cp "$work/$name-B.samples" "$work/$name-Bn.samples"
  "$rotleap" run "$dk" "$@" --set run.steps=$((2 * N)) --set system.start="$work/$name-B.chk" --set output.prefix="$work/$name-B" >/dev/null 2>>"$name.err" || true
  "$rotleap" run "$dk" "$@" --set run.steps=$((2 * N)) --set system.start="$work/$name-Bn.chk" --set output.prefix="$work/$name-C" >/dev/null 2>>"$name.err" || true
  check "$name: all runs succeeded" "quiet $name.err && [ -e $name-A.chk ] && [ -e $name-B.chk ] && [ -e $name-C.chk ]"
  check "$name: final checkpoints byte-identical (2N vs N + continuation + N)" "cmp -s $name-A.chk $name-B.chk"
  check "$name: thermo files byte-identical" "cmp -s $name-A.thermo.csv $name-B.thermo.csv"
  check "$name: under another prefix, the same state (new files from step N)" "same_state $name-A.chk $name-C.chk"
}
if [ $part = all ] || [ $part = stockmayer ]; then
for ens in nve nvt-isokinetic nvt-bussi nvt-langevin nvt-langevin-dot nvt-langevin-dot-obabo; do
  extra=(); [ "$ens" != nve ] && extra=(--set run.temperature=1.35)
  case $ens in nvt-bussi|nvt-langevin) extra+=(--set run.tau=0.05) ;; nvt-langevin-dot*) extra+=(--set run.tau=0.05 --set run.tau_rot=0.08) ;; esac
  common=(--set run.ensemble=$ens "${extra[@]}" --set output.thermo_every=5 --set output.trajectory_every=10)
  three_runs "$ens" "$deck" "${common[@]}"
  check "$ens: under another prefix, the thermo rows from step N on are the uninterrupted run's" \
    'diff <(awk -F, "NR>1 && \$1>=50" "$ens-A.thermo.csv") <(awk -F, "NR>1" "$ens-C.thermo.csv") >/dev/null'
  check "$ens: summaries agree (averages over all 2N steps), under both prefixes" \
    'diff <(grep -vE "wall_seconds|this invocation|summary of" "$ens-A.summary.txt") <(grep -vE "wall_seconds|this invocation|summary of" "$ens-B.summary.txt") >/dev/null && diff <(grep -vE "wall_seconds|this invocation|summary of" "$ens-A.summary.txt") <(grep -vE "wall_seconds|this invocation|summary of" "$ens-C.summary.txt") >/dev/null'
  check "$ens: trajectory continued in place (10 frames, the uninterrupted run's), and from step N under another prefix" \
    '[ "$(grep -c "^64$" "$ens-A.xyz")" -eq 10 ] && cmp -s "$ens-A.xyz" "$ens-B.xyz" && cmp -s <(tail -n $((5*66)) "$ens-A.xyz") "$ens-C.xyz"'
done
fi
if [ $part = all ] || [ $part = tip4p ]; then
# TIP4P (examples/tip4p.ini): its rows' batches must not depend on which candidates beyond the
# pruning radius the neighbour list holds, i.e. on when the list was built.  216 molecules take
# the small-box path (other images of a neighbour within the pruning radius), 512 do not.
for cnt in 216 512; do
  tw=(--set system.count=$cnt --set run.equilibrate=200 --set output.thermo_every=10 --set output.rdf=)
  three_runs "tip4p$cnt" "$src/examples/tip4p.ini" "${tw[@]}"
done
fi
if [ $part = all ] || [ $part = cells ]; then
# A box with a cell grid (1,000 dipoles: 7 cells per edge) and a pair loop on two threads (512
# TIP4P): the list, and so the order of the pair sums, depends on the centres at its build.  The
# checkpoint carries them (rl_forcefield_list_origin) and the restart builds the same list;
# without them both continued to round-off only (as did 1,024 TIP4P with its 5 cells per edge).
# The whole-file comparison covers the origin in the run record too; same_state compares the
# state arrays alone (r, v, l, A, rho), which is what a list rebuilt from the restart's own
# centres changed.
three_runs "stockmayer1000" "$deck" --set system.count=1000 --set run.ensemble=nvt-bussi --set run.temperature=1.35 \
  --set run.tau=0.05 --set output.thermo_every=10 --set output.sample_every=0
check "stockmayer1000 (a cell grid): state bit for bit after the restart" 'same_state stockmayer1000-A.chk stockmayer1000-B.chk'
fi
if [ $part = all ] || [ $part = threads ]; then
HALF=20 three_runs "tip4p512-t2" "$src/examples/tip4p.ini" --set system.count=512 --set run.threads=2 --set run.equilibrate=20 \
  --set output.thermo_every=10 --set output.rdf= --set output.sample_every=0
check "tip4p512-t2 (two threads): state bit for bit after the restart" 'same_state tip4p512-t2-A.chk tip4p512-t2-B.chk'
fi
if [ $part = all ] || [ $part = stockmayer ]; then
# output.energy_every = 5: forces only on four steps in five.  The continuation stays bit for bit
# (the averages are over the steps that are multiples of 5, counted from step 0 in both), and the
# trajectory and the thermo rows (apart from calE, a running statistic over the averaged steps)
# are those of energy_every = 1.
ee=(--set run.ensemble=nvt-bussi --set run.temperature=1.35 --set run.tau=0.05 --set output.thermo_every=5 --set output.trajectory_every=10 --set output.energy_every=5)
three_runs "ee-stockmayer" "$deck" "${ee[@]}"
check "energy_every: summary says so, and its averages agree after a restart" \
  'grep -q "^energy_every = 5 " ee-stockmayer-A.summary.txt && diff <(grep -vE "wall_seconds|this invocation|summary of" ee-stockmayer-A.summary.txt) <(grep -vE "wall_seconds|this invocation|summary of" ee-stockmayer-B.summary.txt) >/dev/null'
check "energy_every: Stockmayer trajectory and thermo rows as with energy_every = 1" \
  'cmp -s ee-stockmayer-A.xyz nvt-bussi-A.xyz && diff <(cut -d, -f1-16,18- ee-stockmayer-A.thermo.csv) <(cut -d, -f1-16,18- nvt-bussi-A.thermo.csv) >/dev/null'
fi
if [ $part = all ] || [ $part = tip4p ]; then
three_runs "ee-tip4p216" "$src/examples/tip4p.ini" --set system.count=216 --set run.equilibrate=200 --set output.thermo_every=10 --set output.rdf= --set output.energy_every=5
check "energy_every: TIP4P thermo rows (U, pressure, conserved) as with energy_every = 1" \
  'diff <(cut -d, -f1-16,18- ee-tip4p216-A.thermo.csv) <(cut -d, -f1-16,18- tip4p216-A.thermo.csv) >/dev/null'
fi
if [ $part = all ] || [ $part = stockmayer ]; then
# Another run.seed under the same stochastic thermostat: the run continues (step count, averages)
# with a new random stream from that seed, and says so; the same seed is the bit-for-bit case above.
common=(--set run.ensemble=nvt-langevin --set run.temperature=1.35 --set run.tau=0.05 --set output.thermo_every=5)
"$rotleap" run "$deck" "${common[@]}" --set run.steps=100 --set run.seed=5 --set system.start="$work/nvt-langevin-Bn.chk" \
  --set output.prefix="$work/reseed" >/dev/null 2>reseed.err; code=$?
check "another run.seed continues with a new stream and says so" \
  '[ $code -eq 0 ] && grep -q "run.seed = 5 differs from the seed 2 of the run that wrote" reseed.err && grep -q "steps = 100 of 100 (this invocation: 50)" reseed.summary.txt'
check "the new stream differs from the old one after step N" \
  '! diff <(awk -F, "NR>1 && \$1>50" nvt-langevin-A.thermo.csv) <(awk -F, "NR>1 && \$1>50" reseed.thermo.csv) >/dev/null'
fi
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
