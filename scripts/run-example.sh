#!/usr/bin/env bash
# Quick start 1: install dependencies, build everything, run the main job on the default example.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh example
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DROTLEAP_TESTS=OFF >/dev/null
cmake --build build -j"$(nproc)"
# The default example: TIP4P water at 298 K and 1 g/cm3 (examples/tip4p.ini says what to expect).
mkdir -p out
./build/rotleap run examples/tip4p.ini --set output.prefix=out/tip4p
/usr/bin/python3 scripts/plot.py out/tip4p
echo "outputs in out/: tip4p.thermo.csv, .summary.txt, .results.txt, .rdf.csv, .tcf.csv, .chk, .energy.png, .rdf.png"
