#!/usr/bin/env bash
# CTest's entry to the binding's tests: pytest over tests/python with the build tree's native
# module, package and command.  Skips (77) without numpy or pytest, or fails where CI=true.
#   run.sh NATIVE_MODULE ROTLEAP_CLI SRCDIR
set -uo pipefail
py=/usr/bin/python3
if ! $py -c "import numpy, pytest" 2>/dev/null; then
  echo "python tests: numpy or pytest missing (Debian python3-numpy, python3-pytest)"
  [ "${CI:-}" = true ] && exit 1
  exit 77
fi
export ROTLEAP_NATIVE=$1 ROTLEAP_CLI=$2 PYTHONPATH=$3/python${PYTHONPATH:+:$PYTHONPATH}
exec $py -m pytest -q -p no:cacheprovider "$3/tests/python"
