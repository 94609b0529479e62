#!/usr/bin/env bash
# rotleap scan: usage errors; a small water scan (64 TIP4P, NVE) whose table and CSVs must be
# consistent with each other and with what the integrators guarantee; a scan with an unstable
# step size that must report the blow-up and keep the other runs.
# usage: scan_tests.sh ROTLEAP SRCDIR WORKDIR
set -u
rotleap=$1; src=$2; work=$3
mkdir -p "$work"; cd "$work" || exit 1
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }
deck="$src/tests/cli/water_scan.ini"

"$rotleap" scan "$deck" --integrators rl,leapfrog-of-doom --set output.prefix="$work/u" >out.txt 2>err.txt; code=$?
check "unknown integrator exits 2" '[ $code -eq 2 ]'
check "unknown integrator is named, known ones listed" 'grep -q "unknown integrator .leapfrog-of-doom. (known: rl rl-exact" err.txt'
"$rotleap" scan "$deck" --timesteps 1,-2 fs --set output.prefix="$work/u" >out.txt 2>err.txt; code=$?
check "negative time step refused" '[ $code -eq 2 ] && grep -q "not a positive time step" err.txt'
"$rotleap" scan "$deck" --timesteps 1,2ps --set output.prefix="$work/u" >out.txt 2>err.txt; code=$?
check "a step no rotation can follow is refused before running" '[ $code -eq 2 ] && grep -q "1 ps is too large for tip4p at 298 K: h times the thermal angular velocity" err.txt'
"$rotleap" scan "$deck" --timesteps 1,2fs --steps 3 --no-plot --set output.prefix="$work/unit" >out.txt 2>err.txt; code=$?
check "the last value's unit applies to the bare ones (1,2fs)" '[ $code -eq 0 ] && cut -d, -f2 "$work/unit.scan.csv" | tr "\n" " " | grep -q "^h_fs 1 2 $"'
"$rotleap" scan "$deck" --steps 10 --time 1ps --set output.prefix="$work/u" >out.txt 2>err.txt; code=$?
check "--steps with --time refused" '[ $code -eq 2 ] && grep -q "not both" err.txt'
"$rotleap" scan "$deck" --tolerance lots --set output.prefix="$work/u" >out.txt 2>err.txt; code=$?
check "bad tolerance refused" '[ $code -eq 2 ] && grep -q "tolerance" err.txt'
check "no output after usage errors" '[ ! -e "$work/u.scan.csv" ]'

# equal simulated time (0.4 ps) at 0.5, 1, 2 fs, guarded cubic against the exact solve
"$rotleap" scan "$deck" --timesteps 0.5,1,2 fs --integrators rl,rl-exact --time 0.4ps --tolerance 1% \
  --no-plot --set output.prefix="$work/w" >out.txt 2>err.txt; code=$?
check "scan exits 0" '[ $code -eq 0 ]'
csv="$work/w.scan.csv"
check "CSV: header + 6 runs" '[ "$(wc -l < "$csv")" -eq 7 ]'
check "table and file outputs written" 'grep -q "largest time step with calE/calU <= 1%" out.txt && [ -s "$work/w.scan.txt" ] && [ -s "$work/w.scan_calE.csv" ]'
# column checks in python (standard library): awk would miss the quoted status field
/usr/bin/python3 - "$csv" > py.txt <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
by = {(r["integrator"], float(r["h_fs"])): r for r in rows}
ok = lambda c, m: print(("ok " if c else "FAIL ") + m)
ok(all(r["status"] == "ok" for r in rows), "every run ok")
ok(all(int(r["steps"]) == round(400 / float(r["h_fs"])) == int(r["steps_done"]) for r in rows), "equal time: steps = 0.4 ps / h")
for h in (0.5, 1, 2):  # the guarded cubic is the exact solve to round-off: same trajectory
    a, b = float(by[("rl", h)]["calE"]), float(by[("rl-exact", h)]["calE"])
    ok(abs(a - b) <= 1e-5 * a, "rl = rl-exact at %g fs (%g, %g)" % (h, a, b))
e = [float(by[("rl", h)]["calE"]) for h in (0.5, 1, 2)]
ok(e[0] < e[1] < e[2], "calE grows with h: %s" % e)
ok(2.0 < e[1] / e[0] < 8.0, "calE(1 fs)/calE(0.5 fs) = %.2f is near 4 (second order)" % (e[1] / e[0]))
ok(all(float(r["ortho_error"]) < 1e-12 for r in rows), "rigid to round-off")
ok(float(by[("rl", 0.5)]["rdf_distance_O-O"]) == 0.0, "reference run has RDF distance 0")
ok(all(0 < float(by[("rl", h)]["rdf_distance_O-O"]) < 0.2 for h in (1, 2)), "larger steps: small positive RDF distances")
ok(all(by[("rl", h)]["rdf_distance_O-O"] == by[("rl-exact", h)]["rdf_distance_O-O"] for h in (0.5, 1, 2)),
   "same trajectory, same RDF distance (rl, rl-exact)")
ok(all((r["meets_tolerance"] == "yes") == (float(r["calE_over_calU"]) <= 0.01) for r in rows), "tolerance marks consistent")
ok(all(abs(float(r["t_rot_over_t_trans"]) - float(r["t_rot"]) / float(r["t_trans"])) < 1e-4 for r in rows), "T ratio")
ok(all(float(r["ns_per_day"]) > 0 and float(r["wall_s_per_step"]) > 0 for r in rows), "costs measured")
PY
while read -r res msg; do check "scan CSV: $msg" '[ "$res" = ok ]'; done < py.txt
check "python checks ran" '[ "$(wc -l < py.txt)" -ge 12 ]'

# every integrator by its deck name, one step size: the names map to the right methods
"$rotleap" scan "$deck" --timesteps 1fs --integrators rl,rl-exact,rl-quaternion,rl-hybrid,fincham,no-squish \
  --steps 100 --no-plot --set output.prefix="$work/all" >out.txt 2>err.txt; code=$?
check "scan of all six integrators exits 0" '[ $code -eq 0 ]'
/usr/bin/python3 - "$work/all.scan.csv" > py2.txt <<'PY'
import csv, sys
r = {x["integrator"]: x for x in csv.DictReader(open(sys.argv[1]))}
ok = lambda c, m: print(("ok " if c else "FAIL ") + m)
ok(len(r) == 6 and all(x["status"] == "ok" for x in r.values()), "six runs, all ok")
it = {k: float(x["iterations_per_body_step"]) for k, x in r.items()}
ok(all((it[k] > 1) == (k in ("rl-quaternion", "fincham")) for k in it), "iterations only for the iterative methods: %s" % it)
e = {k: float(x["calE"]) for k, x in r.items()}
ok(e["rl"] == e["rl-exact"], "rl = rl-exact")
ok(all(e[k] != e["rl"] and 0.5 < e[k] / e["rl"] < 2 for k in ("rl-quaternion", "rl-hybrid", "fincham", "no-squish")),
   "other methods: other trajectories, similar calE at 1 fs: %s" % e)
ok(all(float(x["ortho_error"]) < 1e-12 for x in r.values()), "all rigid to round-off")
PY
while read -r res msg; do check "all integrators: $msg" '[ "$res" = ok ]'; done < py2.txt
check "python checks ran (2)" '[ "$(wc -l < py2.txt)" -eq 5 ]'
"$rotleap" scan "$src/tests/cli/stockmayer_short.ini" --integrators rl,fincham --steps 20 --no-plot \
  --set output.prefix="$work/sm" >out.txt 2>err.txt; code=$?
check "a baseline on dipoles: the run says why it cannot, the scan goes on" '[ $code -eq 0 ] && grep -q "fincham.*has no baseline for species" err.txt && grep -q "^rl,.*\"ok\"$" "$work/sm.scan.csv"'

# a checkpoint start (half-step v, l completed with run.timestep) and per-run analysis files
"$rotleap" run "$deck" --set run.steps=50 --set output.prefix="$work/c" >/dev/null 2>&1
"$rotleap" scan "$deck" --set system.start="$work/c.chk" --set run.equilibrate=0 --timesteps 1,2fs --steps 50 \
  --analysis --no-plot --set output.rdf=O-O --set output.prefix="$work/an" >out.txt 2>err.txt; code=$?
check "scan from a checkpoint with --analysis" '[ $code -eq 0 ] && grep -c "\"ok\"$" "$work/an.scan.csv" | grep -q 2'
check "per-run analysis files" '( for h in 1 2; do for x in results.txt rdf.csv tcf.csv; do [ -s "$work/an.rl.h$h.$x" ] || exit 1; done; done )'
# a per-run analysis file that cannot be written (a directory in its place): the scan finishes,
# names the file and exits 1, as rotleap run does; the scan's own files and the other runs' are written
rm -f "$work"/an2.*; mkdir -p "$work/an2.rl.h2.rdf.csv"
"$rotleap" scan "$deck" --set system.start="$work/c.chk" --set run.equilibrate=0 --timesteps 1,2fs --steps 50 \
  --analysis --no-plot --set output.rdf=O-O --set output.prefix="$work/an2" >out.txt 2>err.txt; code=$?
check "unwritable per-run analysis file: exit 1, named, the rest written" \
  '[ $code -eq 1 ] && grep -q "an2.rl.h2.rdf.csv" err.txt && [ -s "$work/an2.scan.csv" ] && [ -s "$work/an2.rl.h1.rdf.csv" ] && [ -s "$work/an2.rl.h2.results.txt" ]'

# an unstable step: the run at 20 fs stops with the cause; the 1 fs run is kept; the scan succeeds
"$rotleap" scan "$deck" --timesteps 1,20 fs --integrators rl --steps 100 --no-plot \
  --set output.prefix="$work/b" >out.txt 2>err.txt; code=$?
check "scan with a blow-up exits 0" '[ $code -eq 0 ]'
check "blow-up named with its step and cause" 'grep -q "rl at h = 20 fs: step [0-9]* (t = .*): the total energy jumped" err.txt'
check "blow-up in the CSV status, the stable run kept" 'grep -q "^rl,20,100,[0-9]*,.*energy jumped" "$work/b.scan.csv" && grep -q "^rl,1,100,100,.*,\"ok\"$" "$work/b.scan.csv"'

# output.tconf: the configurational temperatures as columns (n/a without it), and with --analysis
# in each run's results
"$rotleap" scan "$deck" --set system.start="$work/c.chk" --set run.equilibrate=0 --timesteps 1,2fs --steps 60 \
  --analysis --no-plot --set output.tconf=yes --set output.sample_every=5 --set output.prefix="$work/tc" >out.txt 2>err.txt; code=$?
check "scan with output.tconf: tconf_trans, tconf_rot numbers in K-range, per-run results have them" \
  '[ $code -eq 0 ] && /usr/bin/python3 -c "import csv,sys; rows=list(csv.DictReader(open(sys.argv[1]))); sys.exit(not (len(rows) == 2 and all(100 < float(r[\"tconf_trans\"]) < 600 and 100 < float(r[\"tconf_rot\"]) < 600 for r in rows)))" "$work/tc.scan.csv" && grep -q "Tc_trans" out.txt && grep -q "^tconf_rotational = " "$work/tc.rl.h1.results.txt"'
check "scan without output.tconf: the columns say n/a" 'cut -d, -f16,17 "$work/w.scan.csv" | sed -n 2p | grep -q "^n/a,n/a$"'

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
