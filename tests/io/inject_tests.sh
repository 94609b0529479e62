#!/usr/bin/env bash
# Failed writes are reported, once, with the system's reason (issue 30 item 2, library part).
# For every output the library writes (DCD created and appended, an XYZ trajectory stream, PDB,
# XYZ snapshot and checkpoint written atomically), strace fails the Nth call of each of write,
# pwrite64, fsync, ftruncate, rename and close with ENOSPC, for every N the output makes:
#   - the run must fail (no failure goes unnoticed), except for close: the dynamic loader's
#     closes (it stops with "error while loading shared libraries") and the directory's
#     read-only descriptor are not the library's outputs;
#   - its message names the file and says "No space left on device" exactly once, never
#     "I/O error" or "seek";
#   - an atomic file keeps its earlier content and leaves no NAME.tmp.* behind (except after a
#     failed fsync of the directory, which comes after the rename: the file is then the new one).
# usage: inject_tests.sh IO_INJECT WORKDIR     (exit 77 = SKIP without strace; under CI=true: FAIL)
set -u
bin=$1; work=$2
if ! command -v strace >/dev/null; then
  [ "${CI:-}" = true ] && { echo "FAIL: strace is not installed (Debian strace) and CI=true"; exit 1; }
  echo "skip: strace is not installed (Debian strace)"; exit 77
fi
# LeakSanitizer stops the process with ptrace, which strace holds: leaks are checked by the
# clean runs of the other tests
export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
failed=0 runs=0
fail() { echo "FAIL: $*"; failed=$((failed + 1)); }

prepare() { # mode
  rm -f out out.tmp.*
  case $1 in
    dcdappend) "$bin" dcd out || { echo "cannot prepare a DCD"; exit 1; } ;;
    pdb|xyzsnap|chk) echo "old content" > out ;;
  esac
}

calls_of=write,pwrite64,fsync,ftruncate,rename,close
for mode in dcd dcdappend xyz pdb xyzsnap chk; do
  # one clean run counts the calls; getppid() is the first call of io_inject's main: the calls
  # before it are the loader's and the sanitizer runtime's, which are not injected (19 closes
  # more under ASan than without)
  prepare $mode
  strace -f -qq -o calls.txt -e trace=$calls_of,getppid "$bin" $mode out || { fail "$mode: a clean run fails"; continue; }
  grep -q "getppid(" calls.txt || { fail "$mode: io_inject's getppid() marker not seen"; continue; }
  for sc in ${calls_of//,/ }; do
    calls=$(grep -c "^[0-9]* *$sc(" calls.txt)
    first=$(sed -n '/getppid(/q;p' calls.txt | grep -c "^[0-9]* *$sc(")
    caught=0
    for n in $(seq $((first + 1)) "$calls"); do
      prepare $mode
      strace -f -qq -o /dev/null -e trace=$sc -e inject=$sc:error=ENOSPC:when=$n "$bin" $mode out 2>err.txt
      code=$?; runs=$((runs + 1))
      if [ $sc = close ] && grep -q "error while loading shared libraries" err.txt; then continue; fi
      if [ $code -eq 0 ]; then
        [ $sc = close ] || fail "$mode: $sc #$n of $calls failed with ENOSPC, unnoticed (exit 0)"
        continue
      fi
      caught=$((caught + 1))
      what="$mode, $sc #$n of $calls"
      [ $code -eq 1 ] || fail "$what: exit $code, not 1: $(cat err.txt)"
      [ "$(grep -o "No space left on device" err.txt | wc -l)" -eq 1 ] || fail "$what: not one 'No space left on device': $(cat err.txt)"
      grep -q "out" err.txt || fail "$what: the message does not name the file: $(cat err.txt)"
      ! grep -qiE "I/O error|seek" err.txt || fail "$what: a wrong reason: $(cat err.txt)"
      case $mode in pdb|xyzsnap|chk)
        if ! grep -q "cannot sync its directory" err.txt; then
          [ "$(cat out)" = "old content" ] || fail "$what: the earlier file was replaced"
        fi
        ! ls out.tmp.* >/dev/null 2>&1 || fail "$what: a temporary file is left: $(ls out.tmp.*)"
      esac
      [ $n -eq 1 ] && echo "info  $what: $(cat err.txt)"
    done
    echo "check $mode: $sc: $calls calls ($first before main), $caught injected failures reported"
    # every output is written, synced and renamed or truncated through these calls
    case $mode:$sc in
      dcd:pwrite64|dcd:fsync|dcd:rename|dcdappend:pwrite64|dcdappend:fsync|dcdappend:ftruncate|xyz:write|\
      xyz:rename|pdb:write|pdb:fsync|pdb:rename|pdb:close|xyzsnap:write|xyzsnap:fsync|xyzsnap:rename|\
      xyzsnap:close|chk:write|chk:fsync|chk:rename|chk:close|dcd:close|dcdappend:close|xyz:close)
        [ $caught -ge 1 ] || fail "$mode: no injected $sc failure was reported" ;;
    esac
  done
done
echo "info  $runs runs under strace"
[ $failed -eq 0 ] && echo "all checks passed" || echo "$failed checks FAILED"
[ $failed -eq 0 ]
