# Shared by the observables' CLI tests (sourced): arguments ROTLEAP WORKDIR, a fresh WORKDIR as the
# current directory, and check NAME CONDITION, which prints one line per check and counts them.
set -u
rotleap=$1; work=$2
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }
