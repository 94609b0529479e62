#!/usr/bin/env bash
# Reliability of rotleap run's outputs (issue 30): failed writes, a full disk, failed runs, two
# runs on one prefix, long paths, links planted in the output directory, continuations that change
# the simulation, signals, and messages that must name the right cause.  System calls are made to
# fail deterministically with strace fault injection (Debian strace): the N-th write to a given
# file is found in a trace of the same run, then made to fail with ENOSPC.
# usage: reliability_tests.sh ROTLEAP SRCDIR WORKDIR
set -u
rotleap=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }
sm="$src/tests/cli/stockmayer_short.ini"
water="$src/tests/cli/water_scan.ini"
have_strace=0; command -v strace >/dev/null && have_strace=1
# LeakSanitizer cannot run under ptrace: the sanitizer build's runs under strace check no leaks
strace() { ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" command strace "$@"; }
if [ $have_strace -eq 0 ] && [ "${CI:-}" = true ]; then echo "reliability_tests: strace is missing (Debian strace)"; exit 1; fi

# write_index PATTERN CMD...: the index (1-based, among all write calls) of the second write to a
# file whose name matches PATTERN, in a trace of CMD (run under another prefix of the same length,
# fulx for full, so that the traced run leaves full's files alone; it makes the same calls)
write_index() {
  local pat=$1; shift
  local args=("${@/full/fulx}")
  strace -f -qq -y -o trace.log -e trace=write "${args[@]}" >/dev/null 2>&1
  grep '^[0-9 ]*write(' trace.log | grep -n "${pat/full/fulx}" | sed -n 2p | cut -d: -f1 >/dev/null
  grep '^[0-9 ]*write(' trace.log | grep -n . | grep "${pat/full/fulx}" | sed -n 2p | cut -d: -f1
}

# --- item 2 and 3: a write that fails stops the run, naming the file and the system's reason; the
# rows written before it stay in the working file, and an earlier run's complete files stay
"$rotleap" run "$sm" --set run.steps=200 --set output.trajectory_every=10 --set output.prefix="$work/full" >/dev/null 2>&1
md5sum full.thermo.csv full.xyz full.summary.txt full.chk > full.md5
if [ $have_strace -eq 1 ]; then
  for pat in 'full.thermo.csv.part>' 'full.xyz.part>'; do
    # the same run (another seed, so that it is another run) with more rows, so that its rows go out in several writes
    cmd=("$rotleap" run "$sm" --set run.steps=3000 --set output.thermo_every=1 --set output.trajectory_every=10 --set system.seed=5 --set output.prefix="$work/full")
    n=$(write_index "$pat" "${cmd[@]}")
    rm -f full.*.part
    strace -f -qq -o /dev/null -e trace=write -e inject=write:error=ENOSPC:when=$n "${cmd[@]}" >out.txt 2>err.txt; code=$?
    f=${pat%>}
    check "ENOSPC on the write #$n ($f): exit 1, the file and 'No space left on device' named once" \
      '[ $code -eq 1 ] && [ "$(grep -c "$f.*No space left on device" err.txt)" -eq 1 ] && ! grep -q "I/O error\|seek failed" err.txt'
    check "ENOSPC ($f): the earlier run's complete files are as they were" 'md5sum -c --quiet full.md5'
    check "ENOSPC ($f): the failed run's rows are under .part, with a summary saying status = error" \
      '[ -s full.thermo.csv.part ] && grep -q "^status = error" full.summary.txt.part && grep -q "^error = .*No space left on device" full.summary.txt.part'
    rm -f full.*.part full.chk.prev
  done
  # an fsync that fails at a checkpoint (a disk that failed to store the rows): the run stops
  cmd=("$rotleap" run "$sm" --set run.steps=200 --set output.checkpoint_every=50 --set output.prefix="$work/fs")
  strace -f -qq -o /dev/null -e trace=fsync -e inject=fsync:error=EIO:when=1 "${cmd[@]}" >out.txt 2>err.txt; code=$?
  check "a failed fsync stops the run with the file and the reason" '[ $code -eq 1 ] && grep -q "fs\..*: .*Input/output error" err.txt'
fi

# --- item 4: one prefix, one run at a time
"$rotleap" run "$sm" --set run.steps=100000000 --set output.prefix="$work/lock" >/dev/null 2>&1 &
pid=$!
for i in $(seq 300); do [ -e lock.thermo.csv.part ] && break; sleep 0.02; done
"$rotleap" run "$sm" --set run.steps=10 --set output.prefix="$work/lock" >out.txt 2>err.txt; code=$?
check "a second run on a prefix in use is refused, naming the holder's PID" \
  '[ $code -eq 1 ] && grep -q "output.prefix = $work/lock is in use by another rotleap run (PID $pid" err.txt'
"$rotleap" scan "$sm" --no-plot --steps 2 --set output.prefix="$work/lock" >out.txt 2>err.txt; code=$?
check "rotleap scan on a prefix in use is refused too" '[ $code -eq 1 ] && grep -q "is in use by another rotleap run (PID $pid" err.txt'
kill -INT $pid; sleep 0.2; kill -TERM $pid 2>/dev/null; wait $pid; code=$?
check "SIGINT then SIGTERM: the second signal stops at once (default action)" '[ $code -eq 143 ] || [ $code -eq 130 ]'
"$rotleap" run "$sm" --set run.steps=10 --set output.prefix="$work/lock" >/dev/null 2>err.txt; code=$?
check "once the holder is gone, the prefix is free (and the lock file removed)" '[ $code -eq 0 ] && [ ! -e lock.lock ]'

# --- item 5: paths are never truncated
long="$work/$(printf 'd%.0s' $(seq 200))/$(printf 'e%.0s' $(seq 200))/$(printf 'f%.0s' $(seq 200))"
mkdir -p "$long"
"$rotleap" run "$sm" --set run.steps=20 --set output.prefix="$long/run" >/dev/null 2>err.txt; code=$?
check "an output.prefix of ${#long}+ characters writes where it says" '[ $code -eq 0 ] && [ -s "$long/run.thermo.csv" ] && [ -s "$long/run.chk" ]'
"$rotleap" run "$sm" --set run.steps=40 --set system.start="$long/run.chk" --set output.prefix="$long/run" >/dev/null 2>err.txt; code=$?
check "and a system.start that long continues that checkpoint" '[ $code -eq 0 ] && grep -q "^steps = 40 of 40 (this invocation: 20)" "$long/run.summary.txt"'

# --- item 6: links planted where rotleap writes are replaced, never followed
echo precious > victim.txt
ln -s "$work/victim.txt" "$work/ln.thermo.csv.part"
ln -s "$work/victim.txt" "$work/ln.xyz.part"
ln -s "$work/victim.txt" "$work/ln.chk"
"$rotleap" run "$sm" --set run.steps=20 --set output.trajectory_every=10 --set output.prefix="$work/ln" >/dev/null 2>err.txt; code=$?
check "symlinks at the working files and the checkpoint: their target is untouched" \
  '[ $code -eq 0 ] && [ "$(cat victim.txt)" = precious ] && [ ! -L ln.chk ] && [ -s ln.thermo.csv ]'
mkdir -p open; chmod 0777 open
"$rotleap" run "$sm" --set run.steps=20 --set output.prefix="$work/open/x" >/dev/null 2>err.txt; code=$?
check "a world-writable directory without the sticky bit is refused" '[ $code -eq 1 ] && grep -q "writable by every user and has no sticky bit" err.txt && [ ! -e open/x.thermo.csv ]'
chmod 1777 open
"$rotleap" run "$sm" --set run.steps=20 --set output.prefix="$work/open/x" >/dev/null 2>err.txt; code=$?
check "with the sticky bit (as /tmp) it is used" '[ $code -eq 0 ]'
cp "$sm" g.thermo.csv.prev
"$rotleap" run g.thermo.csv.prev --set run.steps=5 --set output.prefix="$work/g" >/dev/null 2>err.txt; code=$?
check "PREFIX.thermo.csv.prev is covered by the overwrite guard" '[ $code -eq 1 ] && grep -q "would overwrite the deck" err.txt'

# --- item 10: a continuation that changes the simulation under the same prefix is refused
"$rotleap" run "$sm" --set run.steps=20 --set output.prefix="$work/phys" >/dev/null 2>&1
cp phys.thermo.csv phys.before
"$rotleap" run "$sm" --set run.steps=40 --set run.timestep=0.004 --set interactions.cutoff=1.8 --set system.start="$work/phys.chk" \
  --set output.prefix="$work/phys" >/dev/null 2>err.txt; code=$?
check "another run.timestep and cutoff under the same prefix: refused, naming both keys and values" \
  '[ $code -eq 1 ] && grep -q "run.timestep: 0.002 reduced -> 0.004 reduced" err.txt && grep -q "interactions.cutoff: 2 reduced -> 1.8 reduced" err.txt && cmp -s phys.before phys.thermo.csv'
"$rotleap" run "$sm" --set run.steps=40 --set run.timestep=0.004 --set system.start="$work/phys.chk" \
  --set output.prefix="$work/phys2" >/dev/null 2>err.txt; code=$?
check "under another prefix: a new run from the state, said so" \
  '[ $code -eq 0 ] && grep -q "starting a new run from its state" err.txt && grep -q "^steps = 40 of 40 (this invocation: 40)" phys2.summary.txt'

# --- item 11: messages that name the right cause
"$rotleap" run "$water" --set run.steps=4 --set output.trajectory_every=1 --set run.equilibrate=0 --set output.prefix="$work/ov" >/dev/null 2>&1
/usr/bin/python3 - <<'PY'
lines = open("ov.pdb").read().splitlines(True)
atoms = [l for l in lines if l.startswith("ATOM")]
first = [l for l in atoms if int(l[22:26]) == 1]
out, k = [], 0
for l in lines:
    if l.startswith("ATOM") and int(l[22:26]) == 2:
        src = first[k]; k += 1
        l = l[:30] + "%8.3f%8.3f%8.3f" % (float(src[30:38]) + 0.5, float(src[38:46]), float(src[46:54])) + l[54:]
    out.append(l)
open("overlap.pdb", "w").write("".join(out))
PY
"$rotleap" run "$water" --set system.start="$work/overlap.pdb" --set output.prefix="$work/ov2" >/dev/null 2>err.txt; code=$?
check "overlapping molecules in a PDB start are named as such (molecules 0 and 1), not as a too-large step" \
  '[ $code -eq 1 ] && grep -q "it has overlapping molecules; molecule [01] .* from molecule [01].s in $work/overlap.pdb" err.txt'
"$rotleap" run "$water" --set system.temperature=1e-30K --set run.equilibrate=0 --set run.steps=50 --set output.prefix="$work/cold" >/dev/null 2>err.txt; code=$?
check "a start at 1e-30 K is not called unstable" '[ $code -eq 0 ] && grep -q "^status = ok" cold.summary.txt'

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
