#!/usr/bin/env bash
# Fuzz the deck parser with libFuzzer (Debian clang-14 + libclang-rt-14-dev) under ASan+UBSan.
#   tests/fuzz/run_fuzz.sh [SECONDS=600]
# The corpus lives in tests/fuzz/corpus (seeded with the example decks; libFuzzer adds what it
# finds).  Exits non-zero on any crash, hang (>10 s per input), leak or sanitizer report.
set -euo pipefail
cd "$(dirname "$0")/../.."
secs=${1:-600}
dpkg-query -W -f='${Status}' clang libclang-rt-14-dev libgsl-dev libinih-dev 2>/dev/null | grep -c "ok installed" | grep -q 4 ||
  { apt-get update -qq && apt-get install -y -qq clang libclang-rt-14-dev libgsl-dev libinih-dev >/dev/null; }
out=build-fuzz; mkdir -p "$out"
lib=$(ls core/*.c models/*.c integrators/*.c)
clang -std=c17 -g -O1 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -fsanitize=fuzzer,address,undefined \
  -fno-sanitize-recover=undefined -Iinclude $lib app/deck.c app/quantity.c tests/fuzz/fuzz_deck.c \
  -o "$out/fuzz_deck" $(pkg-config --cflags --libs gsl inih) -lm
for f in examples/*.ini tests/cli/*.ini; do cp -n "$f" tests/fuzz/corpus/ 2>/dev/null || true; done
mkdir -p "$out/new"
"$out/fuzz_deck" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
  "$out/new" tests/fuzz/corpus 2>&1 | tail -25
