#!/usr/bin/env bash
# Quick start 2: install dependencies, build with -Werror and run every test; then the same
# tests once more under AddressSanitizer + UndefinedBehaviorSanitizer.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh test
jobs="$(nproc)"
cmake -S . -B build-test -DCMAKE_BUILD_TYPE=Release -DROTLEAP_WERROR=ON >/dev/null
cmake --build build-test -j"$jobs"
ctest --test-dir build-test --output-on-failure -j"$jobs"
# the library and the command also build without OpenMP (ROTLEAP_OPENMP=OFF: one thread); the
# pair rows once, portable (ROTLEAP_NO_CLONES): build-test compiled every instance with -Werror
cmake -S . -B build-noomp -DCMAKE_BUILD_TYPE=Release -DROTLEAP_WERROR=ON -DROTLEAP_OPENMP=OFF \
  -DROTLEAP_TESTS=OFF -DROTLEAP_NO_CLONES=ON >/dev/null
cmake --build build-noomp -j"$jobs"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DROTLEAP_WERROR=ON -DROTLEAP_SANITIZE=ON >/dev/null
cmake --build build-asan -j"$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j"$jobs"
