#!/usr/bin/env bash
# Install the Debian 12 packages rotleap needs (as root; uses sudo otherwise).  Skips apt when
# everything is already installed.  Usage: scripts/deps.sh [build|example|test|validate|bench|python]
set -euo pipefail
build=(build-essential cmake pkg-config libgsl-dev libinih-dev libfftw3-dev)  # compiler, CMake, GSL, INI decks, FFTs (PME)
testdeps=(libcmocka-dev python3 python3-mdtraj python3-mdanalysis python3-ase strace python3-numpy python3-pytest
          python3-pip python3-setuptools python3-simtk libopenmm-plugins)
# unit tests; JSON check; MDTraj and MDAnalysis read our DCD, ASE our extended XYZ; strace
# injects failed writes (tests/io/inject_tests.sh); numpy, pytest, pip and setuptools: the Python
# package, its install and its tests (docs/python.md); OpenMM 7.7: the binding's to_openmm /
# from_openmm tests (tests/python/test_interop.py), which skip without it
python=(python3 python3-numpy python3-pytest python3-pip python3-setuptools)
example=(python3 python3-matplotlib)                          # PNG plots of the default job
validate=(python3-simtk libopenmm-plugins python3-numpy)      # OpenMM 7.7 cross-checks
bench=(lammps openmpi-bin python3-mdtraj)                     # LAMMPS side by side; sampling_speed's RDFs
want=("${build[@]}")
case "${1:-build}" in
  build) ;;
  example) want+=("${example[@]}") ;;
  test) want+=("${testdeps[@]}") ;;
  validate) want+=("${testdeps[@]}" "${validate[@]}") ;;
  python) want+=("${python[@]}") ;;
  bench) want+=("${example[@]}" "${validate[@]}" "${bench[@]}") ;;
  *) echo "usage: $0 [build|example|test|validate|bench|python]" >&2; exit 2 ;;
esac
missing=()
for p in "${want[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
echo "installing: ${missing[*]}" >&2
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
