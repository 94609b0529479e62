#!/usr/bin/env bash
# Quick start 2: install dependencies, build with -Werror and run every test; then the same
# tests once more under AddressSanitizer + UndefinedBehaviorSanitizer.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh test
jobs="$(nproc)"
cmake -S . -B build-test -DCMAKE_BUILD_TYPE=Release -DROTLEAP_WERROR=ON >/dev/null
# the library and the command also build without OpenMP (ROTLEAP_OPENMP=OFF: one thread); the
# pair rows once, portable (ROTLEAP_NO_CLONES): build-test compiled every instance with -Werror
cmake -S . -B build-noomp -DCMAKE_BUILD_TYPE=Release -DROTLEAP_WERROR=ON -DROTLEAP_OPENMP=OFF \
  -DROTLEAP_TESTS=OFF -DROTLEAP_NO_CLONES=ON >/dev/null
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DROTLEAP_WERROR=ON -DROTLEAP_SANITIZE=ON >/dev/null
# The three builds run side by side: each is held up by the long compiles of the pair rows (forces/pair/kernels/), so
# in turn they would leave the other cores idle for minutes.  Each build's output goes to its
# own log, printed if it fails.
builds=(build-test build-noomp build-asan)
pids=()
for b in "${builds[@]}"; do
  cmake --build "$b" -j"$jobs" >"$b.log" 2>&1 &
  pids+=($!)
done
failed=0
for i in "${!builds[@]}"; do
  if ! wait "${pids[$i]}"; then
    echo "scripts/test.sh: building ${builds[$i]} failed:" >&2
    cat "${builds[$i]}.log" >&2
    failed=1
  fi
done
[ "$failed" -eq 0 ]
echo "scripts/test.sh: built build-test, build-noomp and build-asan (logs: build-*.log)"
ctest --test-dir build-test --output-on-failure -j"$jobs"
# The Python package as `pip install .` installs it (docs/python.md), from build-test's native
# module into a folder of that build (the system's Python is left alone); the binding's tests
# then run against the installed copy, from outside the source tree.
site="$PWD/build-test/python-site"
rm -rf "$site"
ROTLEAP_BUILD_DIR="$PWD/build-test" /usr/bin/python3 -m pip install -q --no-build-isolation --no-index --no-deps \
  --root-user-action=ignore --target "$site" .
(cd build-test && PYTHONPATH="$site" ROTLEAP_CLI="$PWD/rotleap" /usr/bin/python3 -m pytest -q -p no:cacheprovider \
  ../tests/python)
# The sanitizer pass leaves out the tests labelled "long" (10^6-step numerical and statistical
# checks whose code the other tests run under the sanitizers too: tests/integrators/CMakeLists.txt),
# which the Release pass above ran in full.
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j"$jobs" -LE long
