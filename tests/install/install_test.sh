#!/usr/bin/env bash
# The installed library as a user's program sees it: `cmake --install` into a fresh prefix, then
# examples/free_top.c built against that prefix alone, once with pkg-config and once with
# find_package(rotleap) (target rotleap::rotleap), and each program run: it must load the
# installed librotleap.so.0 (its soname) and integrate the free top.
#   install_test.sh BUILD_DIR SOURCE_DIR WORK_DIR C_COMPILER
set -euo pipefail
build=$1 src=$2 work=$3 cc=$4
rm -rf "$work"
mkdir -p "$work"
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" >"$work/install.log"
lib=$(dirname "$(find "$prefix" -name librotleap.so.0 | head -1)")
[ -n "$lib" ] || { echo "no librotleap.so.0 under $prefix"; exit 1; }
[ "$(readlink "$lib/librotleap.so.0")" = "librotleap.so.0.1.0" ] || { echo "librotleap.so.0 -> $(readlink "$lib/librotleap.so.0")"; exit 1; }
args=(--inertia 0.6 1.2 1.7 --angmom 1 0.5 0.3 --h 0.01 --steps 1000 --solver cubic)
check() { # the program's output and the library it loaded
  local out
  out=$(LD_LIBRARY_PATH="$lib" "$1" "${args[@]}")
  # the library's soname, which the programs record
  grep -q 'Library soname: \[librotleap.so.0\]' <<<"$(readelf -d "$lib/librotleap.so.0.1.0")" || { echo "soname"; exit 1; }
  grep -q "^fallbacks = 0$" <<<"$out" || { echo "$1 printed: $out"; exit 1; }
  local deps
  deps=$(LD_LIBRARY_PATH="$lib" ldd "$1")
  grep -q "librotleap.so.0 => $lib/librotleap.so.0" <<<"$deps" || { echo "$1 does not load $lib/librotleap.so.0:"; echo "$deps"; exit 1; }
  echo "ok: $2"
}
# 1. pkg-config
pc=$(dirname "$(find "$prefix" -name rotleap.pc | head -1)")
flags=$(PKG_CONFIG_PATH="$pc" pkg-config --cflags --libs rotleap)
# shellcheck disable=SC2086
"$cc" -std=c17 -D_POSIX_C_SOURCE=200809L -o "$work/free_top_pc" "$src/examples/free_top.c" $flags
check "$work/free_top_pc" "pkg-config rotleap: $flags"
# 2. find_package(rotleap)
mkdir -p "$work/consumer"
cp "$src/examples/free_top.c" "$work/consumer/"
cat >"$work/consumer/CMakeLists.txt" <<'CM'
cmake_minimum_required(VERSION 3.18)
project(consumer LANGUAGES C)
find_package(rotleap 0.1 REQUIRED)
add_executable(free_top free_top.c)
target_link_libraries(free_top PRIVATE rotleap::rotleap)
CM
cmake -S "$work/consumer" -B "$work/consumer/build" -DCMAKE_C_COMPILER="$cc" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release >"$work/consumer.log" 2>&1 || { cat "$work/consumer.log"; exit 1; }
cmake --build "$work/consumer/build" >>"$work/consumer.log" 2>&1 || { cat "$work/consumer.log"; exit 1; }
check "$work/consumer/build/free_top" "find_package(rotleap), rotleap::rotleap"
