#!/usr/bin/env bash
# Fuzz the file readers and the deck parser with libFuzzer (Debian clang-14 + libclang-rt-14-dev)
# under ASan + UBSan, one target after another:
#   tests/fuzz/run_fuzz.sh [TARGET|all] [SECONDS]
# TARGET: deck (app/deck.c), pdb (rl_pdb_count, rl_pdb_read_state), xyz (rl_xyz_count,
# rl_xyz_read_state), dcd (rl_dcd_info, rl_dcd_layout, rl_dcd_append's read path on a copy),
# checkpoint (rl_checkpoint_load, rl_checkpoint_read); all (default) runs the five.  SECONDS per
# target, default 300 (5 minutes).  Limits: 10 s per input, -rss_limit_mb=2048,
# -malloc_limit_mb=1024 (a single allocation above 1 GB is a bug: every count is bounded by the
# file's size).  Inputs start from tests/fuzz/corpus (deck) or tests/fuzz/corpus-TARGET; what
# libFuzzer finds goes to build-fuzz/new-TARGET and is merged (-merge=1: only inputs that add
# coverage) into the checked-in corpus, which CTest replays (fuzz_replay_TARGET).  Prints, per
# target, the executions, crashes, OOMs, timeouts and sanitizer reports (also in
# build-fuzz/summary.txt); exits non-zero if any target had one.  Runs under nice -n 10.
set -euo pipefail
cd "$(dirname "$0")/../.."
what=${1:-all}
secs=${2:-300}
all=(deck pdb xyz dcd checkpoint)
case $what in
  all) targets=("${all[@]}") ;;
  deck|pdb|xyz|dcd|checkpoint) targets=("$what") ;;
  *) echo "usage: $0 [deck|pdb|xyz|dcd|checkpoint|all] [SECONDS=300]" >&2; exit 2 ;;
esac
dpkg-query -W -f='${Status}\n' clang-14 libclang-rt-14-dev libgsl-dev libinih-dev 2>/dev/null | grep -c "ok installed" | grep -q 4 ||
  { apt-get update -qq && apt-get install -y -qq clang-14 libclang-rt-14-dev libgsl-dev libinih-dev >/dev/null; }
cc=$(command -v clang-14 || command -v clang)
out=build-fuzz
mkdir -p "$out/obj"
flags=(-std=c17 -g -O1 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -DROTLEAP_NO_CLONES -Iinclude
       -fsanitize=address,undefined -fno-sanitize-recover=undefined $(pkg-config --cflags gsl inih))
# the library, compiled once (again when a source or a header is newer than its object)
newest_header=$(find include core models io observables forces integrators run -name '*.h' -printf '%T@ %p\n' | sort -n | tail -1 | cut -d' ' -f2)
objs=()
for src in core/*.c models/*.c io/*.c observables/*.c forces/*.c forces/pair/*.c forces/pair/kernels/*/*.c integrators/*.c integrators/paths/*.c integrators/stepops/*.c run/*.c; do
  obj=$out/obj/$(echo "$src" | tr / _).o
  if [ ! "$obj" -nt "$src" ] || [ ! "$obj" -nt "$newest_header" ]; then
    "$cc" "${flags[@]}" -fsanitize=fuzzer-no-link -c "$src" -o "$obj"
  fi
  objs+=("$obj")
done
export TMPDIR=${TMPDIR:-/dev/shm}  # the targets write each input to a scratch file there
[ -w "$TMPDIR" ] || export TMPDIR=/tmp
: > "$out/summary.txt"
bad=0
for t in "${targets[@]}"; do
  extra=(); corpus=tests/fuzz/corpus-$t
  if [ "$t" = deck ]; then
    extra=(app/deck.c app/deck_molecule.c app/quantity.c); corpus=tests/fuzz/corpus
    for f in examples/*.ini tests/cli/*.ini; do cp -n "$f" "$corpus/" 2>/dev/null || true; done
  fi
  "$cc" "${flags[@]}" -fsanitize=fuzzer tests/fuzz/fuzz_$t.c "${extra[@]}" "${objs[@]}" -o "$out/fuzz_$t" \
    $(pkg-config --libs gsl inih) -lm
  dict=(); [ -f tests/fuzz/$t.dict ] && dict=(-dict=tests/fuzz/$t.dict)
  rm -rf "$out/new-$t" "$out/artifacts-$t"; mkdir -p "$out/new-$t" "$out/artifacts-$t"
  set +e
  nice -n 10 "$out/fuzz_$t" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -print_final_stats=1 -artifact_prefix="$out/artifacts-$t/" "${dict[@]}" "$out/new-$t" "$corpus" > "$out/fuzz-$t.log" 2>&1
  code=$?
  set -e
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out/fuzz-$t.log" | tail -1)
  crashes=$(ls "$out/artifacts-$t" | grep -c '^crash-' || true)
  ooms=$(ls "$out/artifacts-$t" | grep -c '^oom-' || true)
  timeouts=$(ls "$out/artifacts-$t" | grep -c '^timeout-' || true)
  leaks=$(ls "$out/artifacts-$t" | grep -c '^leak-' || true)
  reports=$(grep -cE "ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:" "$out/fuzz-$t.log" || true)
  peak=$(sed -n 's/^stat::peak_rss_mb: *//p' "$out/fuzz-$t.log" | tail -1)
  line="$t: ${secs} s, ${execs:-0} executions, $crashes crashes, $ooms OOMs, $timeouts timeouts, $leaks leaks, $reports sanitizer reports, peak RSS ${peak:-?} MB, libFuzzer exit $code"
  echo "$line" | tee -a "$out/summary.txt"
  if [ "$code" -ne 0 ] || [ $((crashes + ooms + timeouts + leaks + reports)) -ne 0 ]; then
    bad=1
    tail -40 "$out/fuzz-$t.log"
  else
    "$out/fuzz_$t" -merge=1 "$corpus" "$out/new-$t" > "$out/merge-$t.log" 2>&1 || true
  fi
done
exit $bad
