#!/usr/bin/env bash
# CLI checks: every deck problem is reported with its line and nothing runs; a short run writes
# its thermo CSV and summary; energy --json is one valid JSON object; docs/deck.md is current.
# usage: cli_tests.sh ROTLEAP SRCDIR WORKDIR
set -u
rotleap=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }
# quiet FILE: nothing on stderr but the notes said before a run (what jumps at the cutoff)
quiet() { ! grep -qv "^rotleap [a-z]*: note: " "$1"; }

"$rotleap" run "$src/tests/cli/bad.ini" --set output.prefix="$work/bad" >out.txt 2>err.txt; code=$?
check "bad deck exits 2" '[ $code -eq 2 ]'
for msg in "bad.ini:6: unknown key 'temprature' in \[system\]" \
           "bad.ini:8: interactions.cutoff 1.2 is larger than half the shortest box edge" \
           "bad.ini:9: interactions.lj: 'shifty' is not one of" \
           "bad.ini:11: run.steps: 'ten' is not a whole number" \
           "bad.ini:12: run.timestep: unit 'fortnights' is not a time unit (use fs, ps, ns)" \
           "bad.ini:13: run.ensemble = nvt-bussi needs run.temperature" \
           "bad.ini:15: output.thermo_every: 0 is below the minimum 1" \
           "bad.ini:17: unknown section \[colour\]" \
           "nothing was run"; do
  check "bad deck reports: $msg" 'grep -q "$msg" err.txt'
done
check "bad deck writes no output" '[ ! -e "$work/bad.thermo.csv" ] && [ ! -e "$work/bad.summary.txt" ]'

"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set output.prefix="$work/sm" --set run.steps=100 >out.txt 2>err.txt; code=$?
check "short run exits 0" '[ $code -eq 0 ]'
check "--set run.steps=100 honoured" 'grep -q "steps = 100 of 100" "$work/sm.summary.txt"'
check "thermo CSV has header + 11 rows (steps 0, 10, ..., 100: the last state too)" \
  '[ "$(tail -n +2 "$work/sm.thermo.csv" | cut -d, -f1 | tr "\n" " ")" = "$(seq -s " " 0 10 100) " ]'
check "no .part left behind" '[ ! -e "$work/sm.thermo.csv.part" ]'
check "quiet when not a terminal" '[ ! -s err.txt ]'
check "dipole = sf reports no dielectric constant from the reaction-field formula" \
  'grep -q "dielectric_constant = n/a (dipole = sf" "$work/sm.results.txt"'

"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.timestep=-0.002 --set output.prefix="$work/neg" >out.txt 2>err.txt; code=$?
check "negative time step rejected" '[ $code -eq 2 ] && grep -q "run.timestep -0.002 must be positive" err.txt'
check "a bad time step is reported once, not again through its defaults" '! grep -q "equilibrate_timestep\|run.tau" err.txt && grep -q "1 problem in" err.txt'
sed -e '/^timestep/d' -e 's/^\[run\]$/[run]\nensemble = nvt-bussi\ntemperature = 1.35/' \
  "$src/tests/cli/stockmayer_short.ini" > nodt.ini
"$rotleap" run nodt.ini --set output.prefix="$work/nodt" >out.txt 2>err.txt; code=$?
check "a missing time step is reported once, not again through tau or the relaxation step" \
  '[ $code -eq 2 ] && grep -q "run.timestep is required" err.txt && ! grep -q "equilibrate_timestep\|run.tau" err.txt'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set system.count=4294967404 --set output.prefix="$work/big" >out.txt 2>err.txt; code=$?
check "a count beyond int is refused, not wrapped (and reported once)" \
  '[ $code -eq 2 ] && grep -q "system.count: 4294967404 is above the maximum" err.txt && grep -q "1 problem in" err.txt'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=99999999999999999999 --set output.prefix="$work/big" >out.txt 2>err.txt; code=$?
check "a step count beyond long is refused, not clamped" '[ $code -eq 2 ] && grep -q "run.steps: 99999999999999999999 is above the maximum" err.txt'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.timestep=5 --set output.prefix="$work/abs" >out.txt 2>err.txt; code=$?
check "absurd time step rejected" '[ $code -eq 2 ] && grep -q "no step can follow the rotation" err.txt'
# the default skin: 0.1 cutoff at 2 fs for water, sqrt(v h / 0.0015 rc) times that at 8 fs (0.1756 nm
# for TIP4P at 298 K, rc 0.9 nm), and a given skin as given
for spec in "2fs 0.09" "8fs 0.1756" "8fs@0.05 0.05"; do
  set -- $spec; h=${1%@*}; sk=""; want=$2; [ "$h" != "$1" ] && sk="--set interactions.skin=${1#*@}"
  rm -f "$work/skin.summary.txt"
  "$rotleap" run "$src/examples/tip4p.ini" --set run.timestep=$h --set run.steps=2 --set run.equilibrate=0 $sk \
    --set output.prefix="$work/skin" >/dev/null 2>&1
  check "skin for $1: $want nm" 'grep -q "^neighbour_list = skin $want nm, " "$work/skin.summary.txt"'
done
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set output.energy_every=3 --set output.prefix="$work/ee3" >out.txt 2>err.txt; code=$?
check "thermo_every not a multiple of energy_every rejected" '[ $code -eq 2 ] && grep -q "output.thermo_every = 10 must be a multiple of output.energy_every = 3" err.txt && [ ! -e "$work/ee3.summary.txt" ]'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set system.model=stockmayr >out.txt 2>err.txt; code=$?
check "unknown model names the known ones" '[ $code -eq 2 ] && grep -q "unknown model .stockmayr. (known: stockmayer" err.txt'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set model.charge=1 >out.txt 2>err.txt; code=$?
check "unknown model parameter" '[ $code -eq 2 ] && grep -q "model stockmayer has no parameter .charge." err.txt'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set output.prefix=/nonexistent/dir/x >out.txt 2>err.txt; code=$?
check "unwritable prefix is an error before running" '[ $code -eq 1 ] && grep -q "output.prefix = /nonexistent/dir/x: the directory /nonexistent/dir: No such file or directory" err.txt'

"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.timestep=0.05 --set run.steps=2000 --set output.prefix="$work/blow" >out.txt 2>err.txt; code=$?
check "blow-up ends the run with exit 1" '[ $code -eq 1 ]'
check "blow-up message names the step and the cause" 'grep -qE "step [0-9]+ \(t = .*\): the total energy jumped by .* reduce run.timestep" err.txt'
check "blow-up keeps the rows written under .part names and marks the summary" '[ -s "$work/blow.thermo.csv.part" ] && grep -q "status = error" "$work/blow.summary.txt.part" && [ ! -e "$work/blow.thermo.csv" ] && grep -q "the rows and frames of this run up to the failure are in" err.txt'
# the same blow-up with energies every 10 steps only (forces only in between): still stopped,
# named, and no NaN written
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.timestep=0.05 --set run.steps=2000 --set output.energy_every=10 \
  --set output.prefix="$work/blow10" >out.txt 2>err.txt; code=$?
check "blow-up with energy_every = 10 ends the run with exit 1, named" '[ $code -eq 1 ] && grep -qE "step [0-9]+ \(t = .*\): (the total energy jumped by .* since its last evaluation|molecule [0-9]+ moved|the total energy is not finite).* reduce run.timestep" err.txt'
check "blow-up with energy_every = 10 writes no NaN" '[ -s "$work/blow10.thermo.csv.part" ] && ! grep -qi nan "$work/blow10.thermo.csv.part" "$work/blow10.summary.txt.part"'

L=4.3088694997
{ echo 64; echo "Lattice=\"$L 0 0 0 $L 0 0 0 $L\" Properties=species:S:1:pos:R:3:orientation:R:3"
  for i in $(seq 0 63); do j=$i; [ $i -eq 5 ] && j=4
    awk -v i=$j -v L=$L 'BEGIN{a=L/4; printf "stockmayer %.6f %.6f %.6f 0 0 1\n", (i%4+0.5)*a, (int(i/4)%4+0.5)*a, (int(i/16)+0.5)*a}'; done; } > overlap.xyz
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set system.start="$work/overlap.xyz" --set output.prefix="$work/ov" >out.txt 2>err.txt; code=$?
check "overlapping molecules in the start are an error naming them" '[ $code -ne 0 ] && grep -q "overlapping sites: site 0 of body 4 and site 0 of body 5" err.txt'

# a run that blows up at its first step leaves an earlier run's outputs under its prefix as
# they were: trajectory, thermo rows, summary, checkpoint (a pair at 0.4 sigma: not an overlap
# of sites, but forces that throw a molecule across the box)
{ echo 64; echo "Lattice=\"$L 0 0 0 $L 0 0 0 $L\" Properties=species:S:1:pos:R:3:orientation:R:3"
  for i in $(seq 0 63); do j=$i; dx=0; [ $i -eq 5 ] && { j=4; dx=0.4; }
    awk -v i=$j -v L=$L -v dx=$dx 'BEGIN{a=L/4; printf "stockmayer %.6f %.6f %.6f 0 0 1\n", (i%4+0.5)*a+dx, (int(i/4)%4+0.5)*a, (int(i/16)+0.5)*a}'; done; } > close.xyz
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=50 --set output.trajectory_every=10 \
  --set output.prefix="$work/keep" >/dev/null 2>&1
(cd "$work" && md5sum keep.xyz keep.thermo.csv keep.summary.txt keep.chk) > keep.md5
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set system.start="$work/close.xyz" --set output.trajectory_every=10 \
  --set output.prefix="$work/keep" >out.txt 2>err.txt; code=$?
check "a blow-up at the first step keeps the earlier trajectory, thermo, summary and checkpoint" \
  '[ $code -eq 1 ] && grep -q "step 0 (t = 0 reduced): molecule 4 moved" err.txt && (cd "$work" && md5sum -c --quiet "$OLDPWD/keep.md5") && ! ls "$work"/keep.*part* >/dev/null 2>&1'

"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set system.start="$work/close.xyz" --set run.equilibrate=50 \
  --set run.equilibrate_timestep=0.01 --set output.prefix="$work/eqfail" >out.txt 2>err.txt; code=$?
check "a relaxation that blows up stops there, named, with its time step and the unit of t (not at the run's step 0)" \
  '[ $code -eq 1 ] && grep -q "during equilibration (run.equilibrate_timestep = 0.01 reduced; t in reduced units): step [0-9]* (t = .*): molecule [0-9]* moved .* reduce run.equilibrate_timestep (now 0.01)" err.txt'
sed '/^temperature/d' "$src/tests/cli/stockmayer_short.ini" > notemp.ini
"$rotleap" run notemp.ini --set system.start="$work/keep.chk" --set output.prefix="$work/notemp" >out.txt 2>err.txt; code=$?
check "NVE from a checkpoint without system.temperature says what the temperature is for" \
  '[ $code -eq 2 ] && grep -q "system.temperature is required for an NVE run: it draws the starting velocities, and sets the default neighbour-list skin" err.txt'

"$rotleap" run "$src/tests/cli/water_scan.ini" --set system.model=co2 --set output.prefix="$work/co2rdf" >out.txt 2>err.txt; code=$?
check "an RDF pair the model lacks is a deck problem at its line, naming the model's sites" \
  '[ $code -eq 2 ] && grep -q "water_scan.ini:19: output.rdf: model co2 has no site .O. (its sites: O1 C O2)" err.txt'

# energy from a checkpoint: the kinetic part of the pressure from on-step velocities, as the
# run's own last thermo row (which the checkpoint's state is)
"$rotleap" energy "$src/tests/cli/stockmayer_short.ini" --set system.start="$work/keep.chk" --json > keep_energy.json 2>err.txt
check "energy from a checkpoint gives the pressure of the run's last thermo row (1e-9)" '/usr/bin/python3 -c "
import json, sys
p = json.load(open(\"keep_energy.json\"))[\"pressure\"]
q = float(open(\"$work/keep.thermo.csv\").read().split()[-1].split(\",\")[14])
sys.exit(0 if abs(p - q) <= 1e-9 * abs(q) else 1)"'

# a gas with no pair in range: U is 0 throughout, and its relative fluctuation is n/a, not NaN
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set system.density=0.0001 --set run.steps=20 \
  --set output.prefix="$work/gas" >out.txt 2>err.txt; code=$?
check "a gas's calU is n/a, and no output has a NaN" \
  '[ $code -eq 0 ] && grep -q "^calU = n/a" "$work/gas.summary.txt" && grep -q "^calU = n/a" "$work/gas.results.txt" && ! grep -qi "nan" "$work"/gas.*'

# trajectories and continuations: a start from another prefix's checkpoint starts a new
# trajectory (no frames spliced onto an unrelated one); a continuation of this prefix drops
# the frames a killed run wrote past its checkpoint
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=50 --set output.prefix="$work/tra" >/dev/null 2>&1
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=100 --set output.trajectory_every=10 \
  --set output.prefix="$work/trb" >/dev/null 2>&1
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=100 --set output.trajectory_every=10 \
  --set system.start="$work/tra.chk" --set output.prefix="$work/trb" >/dev/null 2>&1; code=$?
check "a start from another prefix's checkpoint writes a new trajectory (steps 60-100)" \
  '[ $code -eq 0 ] && [ "$(grep -o "Step=[0-9]*" "$work/trb.xyz" | tr "\n" " ")" = "Step=60 Step=70 Step=80 Step=90 Step=100 " ]'
tail -n 66 "$work/trb.xyz" | sed "s/Step=100/Step=110/" >> "$work/trb.xyz" # as if killed at step 115
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=130 --set output.trajectory_every=10 \
  --set system.start="$work/trb.chk" --set output.prefix="$work/trb" >/dev/null 2>&1; code=$?
check "a continuation drops the frames past its checkpoint and appends (steps 60-130 once each)" \
  '[ $code -eq 0 ] && [ "$(grep -o "Step=[0-9]*" "$work/trb.xyz" | tr "\n" " ")" = "$(seq -f "Step=%g" -s " " 60 10 130) " ]'

"$rotleap" energy "$src/tests/cli/stockmayer_short.ini" --json >energy.json 2>err.txt; code=$?
check "energy --json exits 0" '[ $code -eq 0 ]'
if command -v python3 >/dev/null; then
  check "energy --json is valid JSON with 64 molecules" \
    'python3 -c "import json,sys; d=json.load(open(\"energy.json\")); assert len(d[\"molecules\"])==64 and \"total\" in d[\"energy\"] and len(d[\"molecules\"][0][\"torque\"])==3"'
fi
# Water NVT at the edge of stability (issue 7): at 10 fs the run completes and warns that the
# conserved energy drifts; at 12 fs the fastest librations pass the leapfrog's limit h omega = 2,
# the Bussi thermostat hides the heating, and the drift monitor stops the run within its 1 ps
# window, naming the step and cause, keeping the rows and the last checkpoint (step 80).
nvt="--set run.ensemble=nvt-bussi --set run.temperature=298K --set run.tau=0.1ps --set run.steps=1000 --set run.equilibrate=1000 --set output.checkpoint_every=20 --set output.progress=no"
"$rotleap" run "$src/tests/cli/water_scan.ini" $nvt --set run.timestep=10fs --set output.prefix="$work/w10" >out.txt 2>err.txt; code=$?
check "water NVT at 10 fs completes" '[ $code -eq 0 ] && grep -q "status = ok" "$work/w10.summary.txt"'
check "water NVT at 10 fs warns of the drift" 'grep -q "^warning = the conserved energy drifts" "$work/w10.summary.txt" && grep -q "warning: the conserved energy drifts by .* the time step .* is too large" err.txt'
"$rotleap" run "$src/tests/cli/water_scan.ini" $nvt --set run.timestep=12fs --set output.prefix="$work/w12" >out.txt 2>err.txt; code=$?
check "water NVT at 12 fs is stopped" '[ $code -eq 1 ] && grep -q "status = error" "$work/w12.summary.txt.part"'
check "the stop names step, drift and cause" 'grep -qE "step [0-9]+ \(t = .* ps\): the conserved energy drifted by [0-9.]+ kT per molecule per ps .* integration error is heating the system; reduce run.timestep" err.txt'
check "the rows before the stop are kept" '[ "$(grep -c "^[0-9]" "$work/w12.thermo.csv.part")" -ge 1 ]'
"$rotleap" run "$src/tests/cli/water_scan.ini" $nvt --set run.timestep=12fs --set run.steps=84 --set run.equilibrate=0 \
  --set system.start="$work/w12.chk" --set output.prefix="$work/w12r" >out.txt 2>err.txt; code=$?
check "the last checkpoint (step 80) is readable and continues" '[ $code -eq 0 ] && grep -q "steps = 84 of 84 (this invocation: 4)" "$work/w12r.summary.txt"'
check "no water NVT run wrote NaN" '! grep -qi nan "$work/w10.thermo.csv" "$work/w12.thermo.csv.part"'
check "conserved drift reported for a stable run" '"$rotleap" run "$src/tests/cli/water_scan.ini" $nvt --set run.timestep=2fs --set run.steps=600 --set output.prefix="$work/w2" >/dev/null 2>&1 && grep -qE "^conserved_drift = -?0\.0" "$work/w2.summary.txt" && ! grep -q "^warning" "$work/w2.summary.txt"'

"$rotleap" run "$src/examples/stockmayer.ini" --set run.ensemble=nve --set run.temperature= --set run.tau= \
  --set system.temperature=1.35 --set run.steps=10 --set run.equilibrate=0 --set output.prefix="$work/unset" >out.txt 2>err.txt; code=$?
check "--set key= returns a key to its default (an NVT deck run as NVE)" '[ $code -eq 0 ] && grep -q "status = ok" "$work/unset.summary.txt"'

"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.thermostat_groups=all --set run.steps=10 \
  --set output.prefix="$work/grp" >out.txt 2>err.txt; code=$?
check "run.thermostat_groups without Bussi is refused by name" '[ $code -eq 2 ] && grep -q "run.thermostat_groups is only used with ensemble = nvt-bussi" err.txt'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.ensemble=nvt-bussi --set run.temperature=1.35 \
  --set run.thermostat_groups=all --set run.steps=10 --set output.prefix="$work/grp" >out.txt 2>err.txt; code=$?
check "run.thermostat_groups = all runs under Bussi, mid-step temperatures in the thermo CSV" '[ $code -eq 0 ] && head -1 "$work/grp.thermo.csv" | grep -q ",t_trans_mid,t_rot_mid$"'

"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.ensemble=nvt-langevin --set run.temperature=1.35 \
  --set run.tau=0.05 --set run.steps=20 --set output.prefix="$work/lgv" >out.txt 2>err.txt; code=$?
check "nvt-langevin runs with run.tau, its results use the canonical formula" '[ $code -eq 0 ] && grep -q "(canonical formula)" "$work/lgv.results.txt"'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.ensemble=nvt-langevin --set run.temperature=1.35 \
  --set run.tau=-1 --set run.steps=20 --set output.prefix="$work/lgv" >out.txt 2>err.txt; code=$?
check "nvt-langevin with a negative tau is refused by name" '[ $code -eq 2 ] && grep -q "run.tau must be positive" err.txt'
"$rotleap" run "$src/tests/cli/water_scan.ini" --set run.ensemble=nvt-langevin --set run.temperature=298K \
  --set run.integrator=no-squish --set run.steps=5 --set output.prefix="$work/lgv" >out.txt 2>err.txt; code=$?
check "nvt-langevin with a baseline rotation method is refused, naming both" '[ $code -ne 0 ] && grep -q "Langevin thermostat splits the rotation into two half steps, which the baseline no-squish" err.txt'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.ensemble=nvt-langevin-dot --set run.temperature=1.35 \
  --set run.tau=0.05 --set run.tau_rot=0.02 --set run.steps=20 --set output.prefix="$work/dot" >out.txt 2>err.txt; code=$?
check "nvt-langevin-dot runs with run.tau_rot, recorded in its checkpoint, results by the canonical formula" \
  '[ $code -eq 0 ] && grep -aq "^run.tau_rot = 0.02 reduced$" "$work/dot.chk" && grep -q "(canonical formula)" "$work/dot.results.txt"'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.ensemble=nvt-langevin --set run.temperature=1.35 \
  --set run.tau_rot=0.02 --set run.steps=20 --set output.prefix="$work/dot" >out.txt 2>err.txt; code=$?
check "run.tau_rot under nvt-langevin is refused by name" '[ $code -eq 2 ] && grep -q "run.tau_rot is only used with ensemble = nvt-langevin-dot" err.txt'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.ensemble=nvt-langevin-dot-obabo --set run.temperature=1.35 \
  --set run.tau_rot=-1 --set run.steps=20 --set output.prefix="$work/dot" >out.txt 2>err.txt; code=$?
check "nvt-langevin-dot-obabo with a negative tau_rot is refused by name" '[ $code -eq 2 ] && grep -q "run.tau_rot must be positive" err.txt'

"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.ensemble=nvt-bussi --set run.temperature=1.35 --set run.steps=50 \
  --set output.prefix="$work/eqnvt" >/dev/null 2>&1
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set system.start="$work/eqnvt.chk" --set run.steps=30 \
  --set output.prefix="$work/prodnve" >out.txt 2>err.txt; code=$?
check "NVE production from an NVT checkpoint starts a new run" '[ $code -eq 0 ] && grep -q "written by a run with other settings (run.ensemble: nvt-bussi -> nve; .*): starting a new run" err.txt && grep -q "steps = 30 of 30 (this invocation: 30)" "$work/prodnve.summary.txt"'

for v in "interactions.kernel=general" "interactions.kernel=auto" "run.threads=2"; do
  "$rotleap" energy "$src/tests/cli/water_scan.ini" --set "$v" --json > "energy_$v.json" 2>err.txt
done
check "kernel = general, auto and 2 threads give one energy (1e-12)" '/usr/bin/python3 -c "
import json, sys
e = [json.load(open(\"energy_%s.json\" % v))[\"energy\"][\"total\"] for v in (\"interactions.kernel=general\", \"interactions.kernel=auto\", \"run.threads=2\")]
sys.exit(0 if max(abs(x - e[0]) for x in e) <= 1e-12 * abs(e[0]) else 1)"'

k=0
for v in "1 g/cm3" "1" "1000 kg/m3"; do
  "$rotleap" energy "$src/tests/cli/water_scan.ini" --set "system.density=$v" --json > "energy_rho$k.json" 2>err.txt
  k=$((k + 1))
done
check "a bare real density is in g/cm3, as documented (not amu/nm3)" '/usr/bin/python3 -c "
import json, sys
e = [json.load(open(\"energy_rho%d.json\" % k))[\"energy\"][\"total\"] for k in range(3)]
sys.exit(0 if e[0] != 0 and max(abs(x - e[0]) for x in e) <= 1e-12 * abs(e[0]) else 1)"'

"$rotleap" run "$src/tests/cli/water_scan.ini" --set run.steps=20 --set output.prefix="$work/dc1" >/dev/null 2>&1
"$rotleap" run "$src/tests/cli/water_scan.ini" --set system.start="$work/dc1.chk" --set run.steps=40 \
  --set output.trajectory_every=10 --set output.prefix="$work/dc2" >out.txt 2>err.txt; code=$?
check "a continuation with no DCD yet starts one" '[ $code -eq 0 ] && [ -s "$work/dc2.dcd" ]'
"$rotleap" run "$src/tests/cli/water_scan.ini" --set system.start="$work/dc2.chk" --set run.steps=60 \
  --set output.trajectory_every=10 --set output.prefix="$work/dc2" >out.txt 2>err.txt; code=$?
check "a continuation of a DCD that starts at step 30 keeps its 2 frames and appends 2 (NSET 4, ISTART 30)" \
  '[ $code -eq 0 ] && [ "$(/usr/bin/python3 -c "import struct; h = open(\"$work/dc2.dcd\", \"rb\").read(20); print(*struct.unpack(\"<3i\", h[8:20]))")" = "4 30 10" ]'
cp "$work/dc2.dcd" dc2_before.dcd
"$rotleap" run "$src/tests/cli/water_scan.ini" --set system.start="$work/dc2.chk" --set run.steps=80 \
  --set output.trajectory_every=5 --set output.prefix="$work/dc2" >out.txt 2>err.txt; code=$?
check "a continuation with another trajectory interval is refused, naming both, and the DCD stays" \
  '[ $code -eq 1 ] && grep -q "dc2.chk was written with other output settings (output.trajectory_every: 10 -> 5)" err.txt && cmp -s dc2_before.dcd "$work/dc2.dcd"'

# a continuation under the same prefix keeps the first run's thermo rows; a start past
# run.steps is refused and changes no thermo row
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=100 --set output.prefix="$work/cont" >/dev/null 2>&1
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=200 --set system.start="$work/cont.chk" \
  --set output.prefix="$work/cont" >/dev/null 2>&1; code=$?
check "a continuation keeps the earlier thermo rows (steps 0, 10, ..., 200 once each)" \
  '[ $code -eq 0 ] && [ "$(tail -n +2 "$work/cont.thermo.csv" | cut -d, -f1 | tr "\n" " ")" = "$(seq -s " " 0 10 200) " ]'
cp "$work/cont.thermo.csv" cont_before.csv
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=150 --set system.start="$work/cont.chk" \
  --set output.prefix="$work/cont" >out.txt 2>err.txt; code=$?
check "a checkpoint past run.steps is refused, naming both, and the thermo rows stay" \
  '[ $code -ne 0 ] && grep -q "is at step 200, past run.steps = 150" err.txt && cmp -s cont_before.csv "$work/cont.thermo.csv"'

# SIGTERM during the run: the step ends, and checkpoint, thermo rows and summary are written
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=100000000 --set output.prefix="$work/sig" >out.txt 2>err.txt &
pid=$!
for i in $(seq 200); do [ "$(wc -l < "$work/sig.thermo.csv.part" 2>/dev/null || echo 0)" -ge 3 ] && break; sleep 0.1; done
kill -TERM $pid; wait $pid; code=$?
check "SIGTERM stops the run cleanly: exit 143, checkpoint, thermo rows, status = interrupted" \
  '[ $code -eq 143 ] && [ -s "$work/sig.chk" ] && [ ! -e "$work/sig.thermo.csv.part" ] && [ "$(wc -l < "$work/sig.thermo.csv")" -ge 3 ] && grep -q "status = interrupted" "$work/sig.summary.txt" && grep -q "terminated (SIGTERM) at step" err.txt'

printf '[system]\nmodel = 2clj\ncount = 108\ndensity = 0.6\ntemperature = 2\n[model]\nelongation = 0\n[interactions]\ncutoff = 2.5\n[run]\nsteps = 10\ntimestep = 0.001\n' > e0.ini
"$rotleap" run e0.ini --set output.prefix="$work/e0" >out.txt 2>err.txt; code=$?
check "2clj with elongation 0 is refused (one site, no rotation)" '[ $code -eq 2 ] && grep -q "elongation 0 must be positive" err.txt'

"$rotleap" run "$src/tests/cli/water_scan.ini" --set "system.density=6 g/cm3" --set interactions.cutoff=0.3 \
  --set run.equilibrate=0 --set run.steps=20 --set output.prefix="$work/ovl" >out.txt 2>err.txt; code=$?
check "a blow-up from an overlapping start names the overlap, not only the time step" \
  '[ $code -ne 0 ] && grep -q "overlapping molecules are the likelier cause" err.txt'
"$rotleap" run "$src/tests/cli/water_scan.ini" --set run.timestep=40fs --set run.steps=20 --set output.prefix="$work/bigdt" >out.txt 2>err.txt; code=$?
check "a blow-up from a relaxed start blames the time step alone" '[ $code -ne 0 ] && grep -q "reduce run.timestep" err.txt && ! grep -q overlapping err.txt'

"$rotleap" run "$src/tests/cli/water_scan.ini" --set system.box=2 --set output.prefix="$work/msg" >out.txt 2>err.txt
check "box from --set next to a deck density: named as such" 'grep -q "not both (box from --set)" err.txt'
"$rotleap" run "$src/tests/cli/water_scan.ini" --set "system.density=1 g/l" --set output.prefix="$work/msg" >out.txt 2>err.txt
check "a bad density unit is reported once" 'grep -q "unit .g/l. is not a density unit" err.txt && grep -q "1 problem in" err.txt'
"$rotleap" run "$work" >out.txt 2>err.txt; code=$?
check "a directory given as the deck is named as one" '[ $code -eq 2 ] && grep -q "is a directory, not a deck" err.txt'

"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=103 --set output.energy_every=5 --set output.prefix="$work/ev5" >/dev/null 2>&1
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=103 --set output.energy_every=1 --set output.prefix="$work/ev1" >/dev/null 2>&1
check "the last state's row has its energies even between energy steps (same row as energy_every = 1)" \
  '[ "$(tail -n 1 "$work/ev5.thermo.csv" | cut -d, -f1-16)" = "$(tail -n 1 "$work/ev1.thermo.csv" | cut -d, -f1-16)" ] && tail -n 1 "$work/ev5.thermo.csv" | grep -q "^103,"'

"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=0 --set output.prefix="$work/zero" >/dev/null 2>&1
check "a run of 0 steps reports its averages as n/a, not zeros" 'grep -q "^U_per_molecule = n/a" "$work/zero.summary.txt"'

# continuations: with no step left the last row stays; a start from another prefix's checkpoint
# takes none of this prefix's old rows; after SIGKILL the rows in the .part file are kept
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=200 --set system.start="$work/cont.chk" \
  --set output.prefix="$work/cont" >/dev/null 2>&1
check "a continuation with no step left keeps every row, the last too" \
  '[ "$(tail -n +2 "$work/cont.thermo.csv" | cut -d, -f1 | tr "\n" " ")" = "$(seq -s " " 0 10 200) " ]'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=100 --set output.prefix="$work/other" >/dev/null 2>&1
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=300 --set system.start="$work/cont.chk" \
  --set output.prefix="$work/other" >/dev/null 2>&1
check "a start from another prefix's checkpoint writes only its own rows" \
  '[ "$(tail -n +2 "$work/other.thermo.csv" | cut -d, -f1 | head -1)" = 200 ]'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=100000000 --set output.checkpoint_every=50 \
  --set output.trajectory_every=10 --set output.prefix="$work/kill" >/dev/null 2>&1 &
pid=$!
for i in $(seq 200); do [ -e "$work/kill.chk" ] && [ "$(wc -l < "$work/kill.thermo.csv.part")" -ge 30 ] && break; sleep 0.1; done
kill -KILL $pid; wait $pid 2>/dev/null
last=$(grep -c . "$work/kill.thermo.csv.part")
to=$(( (last + 20) * 10 ))
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=$to --set output.checkpoint_every=50 \
  --set output.trajectory_every=10 --set system.start="$work/kill.chk" --set output.prefix="$work/kill" >/dev/null 2>&1; code=$?
check "after SIGKILL a continuation keeps the rows of the killed run's .part (0 .. $to, no gap)" \
  '[ $code -eq 0 ] && [ ! -e "$work/kill.thermo.csv.part.old" ] && [ "$(tail -n +2 "$work/kill.thermo.csv" | cut -d, -f1 | tr "\n" " ")" = "$(seq -s " " 0 10 $to) " ]'
check "after SIGKILL a continuation keeps the killed run's trajectory from its .part (steps 10 .. $to, no gap)" \
  '[ ! -e "$work/kill.xyz.part" ] && [ "$(grep -o "Step=[0-9]*" "$work/kill.xyz" | tr "\n" " ")" = "$(seq -f "Step=%g" -s " " 10 10 $to) " ]'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=-99999999999999999999 --set output.prefix="$work/neg" >out.txt 2>err.txt
check "a step count below long is called below the minimum" 'grep -q "is below the minimum" err.txt'

"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set run.steps=2200 --set output.sample_every=1 \
  --set output.prefix="$work/lags" >/dev/null 2>&1
check "correlation functions stop at 1000 lags and say so" \
  'grep -q "^correlation_functions = from the first 2200 of 2200 samples, lags up to 1000" "$work/lags.results.txt" && [ "$(wc -l < "$work/lags.tcf.csv")" -eq 1002 ]'

# interactions.precision = mixed: the TIP4P kernel's single-precision rows where the CPU has AVX2
# (the summary says which precision ran); a model without such rows warns and runs in double
"$rotleap" run "$src/tests/cli/water_scan.ini" --set interactions.precision=mixed --set run.steps=50 \
  --set run.equilibrate=50 --set output.prefix="$work/wmix" >out.txt 2>err.txt; code=$?
# the mixed rows are the AVX2 ones: a CPU without AVX2, or a build without the CPU-specific
# clones (the sanitizer builds), runs the portable rows, in double, with a warning
if grep -q avx2 /proc/cpuinfo 2>/dev/null && grep -q fma /proc/cpuinfo && \
   ! grep -q "^pair_kernels = tip4p (portable rows" "$work/wmix.summary.txt"; then want=mixed; else want=double; fi
check "precision = mixed runs TIP4P in $want precision and says so" \
  '[ $code -eq 0 ] && grep -q "^pair_kernels = tip4p (.*, $want precision)" "$work/wmix.summary.txt" &&
   { [ $want = mixed ] || grep -q "interactions.precision = mixed has no effect here" err.txt; }'
"$rotleap" run "$src/tests/cli/stockmayer_short.ini" --set interactions.precision=mixed --set run.steps=20 \
  --set output.prefix="$work/smix" >out.txt 2>err.txt; code=$?
check "precision = mixed for Stockmayer warns and runs in double" \
  '[ $code -eq 0 ] && grep -q "interactions.precision = mixed has no effect here" err.txt && grep -q "double precision)" "$work/smix.summary.txt"'

"$rotleap" deck-keys --markdown > deck.md
check "docs/deck.md matches rotleap deck-keys --markdown" 'cmp -s deck.md "$src/docs/deck.md"'

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
