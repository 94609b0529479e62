#!/usr/bin/env bash
# Quick start 2: install dependencies, build with -Werror and run every test; then the same
# tests once more under AddressSanitizer + UndefinedBehaviorSanitizer.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh test
# The tests run side by side on a machine with fewer cores than threads: OpenMP threads that wait
# at a barrier sleep instead of spinning (GNU OpenMP spins 300,000 times first), which otherwise
# takes the core from the thread they wait for. A 2-thread PME run of the sanitizer pass took 24 s
# spinning and 3 s sleeping, at a load of 12. Results do not depend on it.
export OMP_WAIT_POLICY=passive
jobs="$(nproc)"
cmake -S . -B build-test -DCMAKE_BUILD_TYPE=Release -DROTLEAP_WERROR=ON >/dev/null
# the library and the command also build without OpenMP (ROTLEAP_OPENMP=OFF: one thread); the
# pair rows once, portable (ROTLEAP_NO_CLONES): build-test compiled every instance with -Werror.
# Not optimised (build type None: 25 s of CPU against 59 s for Release): it checks that the
# code compiles without OpenMP, the optimised code's warnings are build-test's.
cmake -S . -B build-noomp -DCMAKE_BUILD_TYPE=None -DROTLEAP_WERROR=ON -DROTLEAP_OPENMP=OFF \
  -DROTLEAP_TESTS=OFF -DROTLEAP_NO_CLONES=ON >/dev/null
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DROTLEAP_WERROR=ON -DROTLEAP_SANITIZE=ON >/dev/null

# Two pipelines side by side, so that neither phase leaves a core idle (the long compiles of the
# pair rows, forces/pair/kernels/, and the tail of a test pass with one test left running):
#  - the Release pass: build-test, its tests, then the Python package as `pip install .`
#    installs it (docs/python.md), from build-test's native module into a folder of that build
#    (the system's Python is left alone), and the binding's tests against the installed copy,
#    from outside the source tree (CTest's python_binding runs the same tests against the build
#    folder: the sanitizer pass runs it);
#  - the sanitizer pass: build-noomp and build-asan, then the tests under the sanitizers. The
#    builds run at the Release pass's priority: at nice 5 the ASan build (100 s of CPU) waited
#    for the whole Release pass and its tests, the longest phase, started only after 400 s.
# Each pipeline's output goes to its log; the Release log is printed when it ends, a failed
# build's log at once.
release_pass() {
  cmake --build build-test -j"$jobs" >build-test.log 2>&1 || { echo "building build-test failed:"; cat build-test.log; return 1; }
  echo "scripts/test.sh: built build-test (log: build-test.log)"
  ctest --test-dir build-test --output-on-failure -j"$jobs" -LE python
  local site="$PWD/build-test/python-site"
  rm -rf "$site"
  ROTLEAP_BUILD_DIR="$PWD/build-test" /usr/bin/python3 -m pip install -q --no-build-isolation --no-index --no-deps \
    --root-user-action=ignore --target "$site" .
  (cd build-test && PYTHONPATH="$site" ROTLEAP_CLI="$PWD/rotleap" /usr/bin/python3 -m pytest -q -p no:cacheprovider \
    ../tests/python)
}
release_pass >release-pass.log 2>&1 &
release=$!
for b in build-noomp build-asan; do
  if ! cmake --build "$b" -j"$jobs" >"$b.log" 2>&1; then
    echo "scripts/test.sh: building $b failed:" >&2
    cat "$b.log" >&2
    wait "$release" || true
    exit 1
  fi
done
echo "scripts/test.sh: built build-noomp and build-asan (logs: build-noomp.log, build-asan.log)"
# The sanitizer pass leaves out the tests labelled "long" (10^6-step numerical and statistical
# checks whose code the other tests run under the sanitizers too: tests/integrators/CMakeLists.txt)
# and "soak" (the kill-and-continue soak: tests/CMakeLists.txt), which the Release pass runs.
# One test more than cores: a third of the pass's CPU time is the kernel's (starting the many
# short sanitized processes of the CLI tests, strace), and it ran in 216 s with -j3 against 232 s
# with -j2 on this project's 2-core host.
asan=0
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j"$((jobs + 1))" -LE "long|soak" || asan=$?
rel=0
wait "$release" || rel=$?
echo "scripts/test.sh: the Release pass (release-pass.log):"
cat release-pass.log
if [ "$rel" -ne 0 ] || [ "$asan" -ne 0 ]; then
  echo "scripts/test.sh: FAILED (Release pass status $rel, sanitizer pass status $asan)" >&2
  exit 1
fi
echo "scripts/test.sh: all tests passed"
