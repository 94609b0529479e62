#!/usr/bin/env bash
# The barostats from a deck (run.barostat, issue 34): 2N steps in one run and N steps + a
# continuation of the checkpoint + N steps give byte-identical final checkpoints and thermo files,
# for the Monte Carlo barostat (isotropic and anisotropic) and for C-rescale (the barostat's own
# random stream and trial size travel in the checkpoint's OPST section); the thermo file has the
# volume, density and box edges; bad keys are refused naming the key; a box that would shrink
# below twice the cutoff stops the run with the step and the cause, its last checkpoint kept.
# usage: barostat_tests.sh ROTLEAP SRCDIR WORKDIR
set -u
rotleap=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
deck="$src/tests/cli/stockmayer_short.ini"
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }
npt=(--set system.count=125 --set run.ensemble=nvt-bussi --set run.temperature=1.35 --set run.pressure=1.0 --set run.timestep=0.004)
# three_runs NAME ARGS...: NAME-A 2N steps; NAME-B N steps, then continued to 2N under its prefix
three_runs() {
  local name=$1; shift
  local N=60
  "$rotleap" run "$deck" "${npt[@]}" "$@" --set run.steps=$((2 * N)) --set output.checkpoint_every=$N --set output.prefix="$work/$name-A" >/dev/null 2>"$name.err" || true
  "$rotleap" run "$deck" "${npt[@]}" "$@" --set run.steps=$N --set output.prefix="$work/$name-B" >/dev/null 2>>"$name.err" || true
  "$rotleap" run "$deck" "${npt[@]}" "$@" --set run.steps=$((2 * N)) --set system.start="$work/$name-B.chk" --set output.prefix="$work/$name-B" >/dev/null 2>>"$name.err" || true
  check "$name: all runs succeeded" "[ ! -s $name.err ] && [ -e $name-A.chk ] && [ -e $name-B.chk ]"
  check "$name: final checkpoints byte-identical (2N vs N + continuation + N)" "cmp -s $name-A.chk $name-B.chk"
  check "$name: thermo files byte-identical" "cmp -s $name-A.thermo.csv $name-B.thermo.csv"
  check "$name: results files byte-identical (the analysis journal's box records replayed)" "cmp -s $name-A.results.txt $name-B.results.txt"
  check "$name: the box moved (volume column)" "awk -F, 'NR==1{for(i=1;i<=NF;i++) if(\$i==\"volume\") c=i} NR==2{v=\$c} END{exit !(\$c != v)}' $name-A.thermo.csv"
}
three_runs mc --set run.barostat=mc --set run.barostat_interval=3
three_runs mc-aniso --set run.barostat=mc --set run.barostat_interval=2 --set run.barostat_coupling=anisotropic
three_runs crescale --set run.barostat=c-rescale --set run.barostat_interval=2 --set run.tau_p=0.5 --set run.compressibility=0.1
# the results under a barostat: block averages of the box, enthalpy, kappa_T, the barostat's own numbers;
# with every step in the thermo file and nothing discarded, the means are the thermo columns' means
"$rotleap" run "$deck" "${npt[@]}" --set run.barostat=mc --set run.barostat_interval=2 --set run.steps=300 --set output.thermo_every=1 \
  --set output.discard=0 --set output.prefix="$work/res-mc" >/dev/null 2>res.err
"$rotleap" run "$deck" "${npt[@]}" --set run.barostat=c-rescale --set run.barostat_interval=2 --set run.compressibility=0.1 \
  --set run.steps=300 --set output.thermo_every=1 --set output.discard=0 --set output.prefix="$work/res-cr" >/dev/null 2>>res.err
for b in mc cr; do
  for key in volume density box_Lx box_Ly box_Lz enthalpy_per_molecule isothermal_compressibility; do
    check "results ($b) has $key" "grep -q '^$key = [0-9]' res-$b.results.txt"
  done
  # thermo: the last row is the final state, not a step of the averages; P0 = 1, kT = 1.35, N = 125
  read -r mV mrho mH kap < <(awk -F, 'NR==1{for(i=1;i<=NF;i++) h[$i]=i} NR>1{r[NR]=$0} END{n=0; for(i=2;i<NR;i++){split(r[i],c,","); V=c[h["volume"]]; n++; sv+=V; svv+=V*V; sr+=c[h["density"]]; sh+=(c[3]+1.0*V)/125} m=sv/n; printf "%.10g %.10g %.10g %.10g\n", m, sr/n, sh/n, (svv/n-m*m)/(1.35*m)}' res-$b.thermo.csv)
  check "results ($b): volume is the thermo mean $mV" "awk -v x=$mV '/^volume = /{exit !((\$3-x)^2 < (1e-7*x)^2)}' res-$b.results.txt"
  check "results ($b): density is the thermo mean $mrho" "awk -v x=$mrho '/^density = /{exit !((\$3-x)^2 < (1e-7*x)^2)}' res-$b.results.txt"
  check "results ($b): enthalpy is <total + P0 V>/N = $mH" "awk -v x=$mH '/^enthalpy_per_molecule = /{exit !((\$3-x)^2 < (1e-6*x)^2)}' res-$b.results.txt"
  check "results ($b): kappa_T is <dV^2>/(kT <V>) = $kap" "awk -v x=$kap '/^isothermal_compressibility = /{exit !((\$3-x)^2 < (1e-4*x)^2)}' res-$b.results.txt"
done
check "results (mc): acceptance and trial step" "grep -q '^mc_acceptance = 0\.[0-9]* ([0-9]* of 150 trials' res-mc.results.txt && grep -q '^mc_trial_step = [0-9.e-]* sigma^3' res-mc.results.txt"
check "results (c-rescale): effective energy drift" "grep -q '^crescale_effective_energy_drift = [-0-9.e]* +- [0-9.e-]* kT per molecule per tau' res-cr.results.txt"
check "results (no barostat): no volume lines" "'$rotleap' run '$deck' --set output.prefix=$work/nve-res >/dev/null 2>&1 && ! grep -q '^volume\|^isothermal' nve-res.results.txt"
check "results: no errors" "[ ! -s res.err ]"
# the dielectric constant under a barostat takes the mean volume (the volume line's), not the deck's box
"$rotleap" run "$deck" "${npt[@]}" --set run.barostat=c-rescale --set run.barostat_interval=2 --set run.compressibility=0.1 \
  --set interactions.dipole=rf --set interactions.eps_rf=inf --set run.steps=300 --set output.sample_every=5 \
  --set output.prefix="$work/eps-cr" >/dev/null 2>eps.err
rc=$?
check "dielectric constant under a barostat: at the mean volume, the volume line's" \
  "[ $rc -eq 0 ] && awk '/^volume = /{v=\$3} /^dielectric_constant = /{for(i=1;i<NF;i++) if(\$i==\"volume\") w=\$(i+1)} END{exit !(v > 0 && (w-v)^2 < (1e-6*v)^2)}' eps-cr.results.txt"
three_runs crescale-semi --set run.barostat=c-rescale --set run.barostat_interval=2 --set run.tau_p=0.5 --set run.compressibility=0.1 --set run.barostat_coupling=semiisotropic
check "semi-isotropic: Lx = Ly on every row, Lz apart from them at the end" "awk -F, 'NR==1{for(i=1;i<=NF;i++) h[\$i]=i; next} {if (\$h[\"Lx\"] != \$h[\"Ly\"]) bad=1; lx=\$h[\"Lx\"]; lz=\$h[\"Lz\"]} END{exit bad || lx == lz}' crescale-semi-A.thermo.csv"
check "semi-isotropic: the checkpoint's settings name the coupling" "grep -aq 'barostat_coupling = semiisotropic' crescale-semi-A.chk"
# RDFs under a barostat: to the cutoff at most (the box shrinks below the deck's at once here), each
# sample normalised with its own volume (g -> 1 at the cutoff); a continuation gives the same file
"$rotleap" run "$deck" "${npt[@]}" --set run.barostat=c-rescale --set run.compressibility=0.1 --set run.steps=600 \
  --set output.sample_every=10 --set output.rdf=S-S --set output.checkpoint_every=300 --set output.prefix="$work/rdf-A" >/dev/null 2>rdf.err
rc=$?
"$rotleap" run "$deck" "${npt[@]}" --set run.barostat=c-rescale --set run.compressibility=0.1 --set run.steps=300 \
  --set output.sample_every=10 --set output.rdf=S-S --set output.prefix="$work/rdf-B" >/dev/null 2>>rdf.err
"$rotleap" run "$deck" "${npt[@]}" --set run.barostat=c-rescale --set run.compressibility=0.1 --set run.steps=600 \
  --set output.sample_every=10 --set output.rdf=S-S --set system.start="$work/rdf-B.chk" --set output.prefix="$work/rdf-B" >/dev/null 2>>rdf.err
check "rdf under a barostat: the run succeeds" "[ $rc -eq 0 ] && [ ! -s rdf.err ]"
check "rdf under a barostat: to the cutoff (2), g near 1 there" "[ -s rdf-A.rdf.csv ] && tail -1 rdf-A.rdf.csv | awk -F, '{exit !(\$1 < 2.0 && \$1 > 1.9 && \$2 > 0.8 && \$2 < 1.25)}'"
check "rdf under a barostat: a continuation gives the same rdf and results" "cmp -s rdf-A.rdf.csv rdf-B.rdf.csv && cmp -s rdf-A.results.txt rdf-B.results.txt"
# rotleap scan with a barostat deck: the barostat runs in every run of the scan, and the table and CSV
# give <rho> and <V> with their errors per step size
"$rotleap" scan "$deck" "${npt[@]}" --set run.barostat=mc --set run.barostat_interval=2 --set output.sample_every=10 \
  --timesteps 0.002,0.004 --steps 600 --no-plot --set output.prefix="$work/scan" >scan.out 2>scan.err
rc=$?
check "scan with a barostat exits 0" "[ $rc -eq 0 ]"
check "scan table: NPT, the barostat, rho and V columns" "grep -q 'NPT (Bussi)' scan.out && grep -q '^# barostat: Monte Carlo at 1' scan.out && grep -q ' rho  *+-  *V  *+- ' scan.out"
check "scan CSV: density and volume with errors, for both steps, the box moved from the start's 0.8" \
  "/usr/bin/python3 -c \"
import csv, sys
rows = list(csv.DictReader(open('scan.scan.csv')))
ok = len(rows) == 2 and all(r['status'] == 'ok' for r in rows)
for r in rows:
    rho, e, V = float(r['density']), float(r['density_err']), float(r['volume'])
    ok = ok and 0.4 < rho < 0.78 and 0 < e < 0.1 and abs(V * rho / 125 - 1) < 0.05  # <V><1/V> >= 1: Jensen
sys.exit(0 if ok else 1)\""
check "scan without a barostat: no density columns" "'$rotleap' scan '$deck' --timesteps 0.002 --steps 20 --no-plot --set output.prefix=$work/scan0 >/dev/null 2>&1 && ! head -1 scan0.scan.csv | grep -q density"
check "thermo header has volume, density, box edges, pressure tensor" "head -1 mc-A.thermo.csv | grep -q ',volume,density,Lx,Ly,Lz,Pxx,Pyy,Pzz,Pxy,Pxz,Pyz$'"
for b in mc cr; do
  check "pressure tensor ($b): its trace / 3 is the pressure column, every row; off-diagonals finite" "awk -F, 'NR==1{for(i=1;i<=NF;i++) h[\$i]=i; next} {p=\$h[\"pressure\"]; t=(\$h[\"Pxx\"]+\$h[\"Pyy\"]+\$h[\"Pzz\"])/3; if ((t-p)^2 > 1e-14*(1+p*p) || \$h[\"Pxy\"] !~ /^-?[0-9]/ || \$h[\"Pyz\"] !~ /^-?[0-9]/) bad=1} END{exit bad}' res-$b.thermo.csv"
done
check "no barostat: no volume columns" "'$rotleap' run '$deck' --set output.prefix=$work/nve >/dev/null 2>&1 && ! head -1 nve.thermo.csv | grep -q volume"
# a continuation whose deck has no barostat (or another) is another simulation
"$rotleap" run "$deck" "${npt[@]}" --set run.steps=130 --set system.start="$work/mc-B.chk" --set output.prefix="$work/mc-B" >/dev/null 2>other.err
check "a continuation without the barostat is refused as another simulation" "grep -q 'run.barostat' other.err"
# bad input, each naming its key
bad() { # NAME FRAGMENT ARGS...
  local name=$1 frag=$2; shift 2
  "$rotleap" run "$deck" --set output.prefix="$work/bad" "$@" >/dev/null 2>"bad-$name.err"
  local rc=$?
  check "bad $name: refused naming $frag" "[ $rc -ne 0 ] && grep -q -- '$frag' bad-$name.err"
}
bad pressure-only "run.pressure is only used with a barostat" --set run.pressure=1
bad no-pressure "needs run.pressure" --set run.barostat=mc --set run.ensemble=nvt-bussi --set run.temperature=1.35
bad no-thermostat "needs a stochastic thermostat" --set run.barostat=mc --set run.pressure=1
bad compressibility "run.compressibility must be positive" "${npt[@]}" --set run.barostat=c-rescale --set run.compressibility=0
bad tau_p "run.tau_p must be positive" "${npt[@]}" --set run.barostat=c-rescale --set run.tau_p=-1
bad tau_p-mc "run.tau_p is only used with run.barostat = c-rescale" "${npt[@]}" --set run.barostat=mc --set run.tau_p=1
bad aniso-crescale "anisotropic needs run.barostat = mc" "${npt[@]}" --set run.barostat=c-rescale --set run.barostat_coupling=anisotropic
bad semi-mc "semiisotropic needs run.barostat = c-rescale" "${npt[@]}" --set run.barostat=mc --set run.barostat_coupling=semiisotropic
bad interval "must be a multiple of output.energy_every" "${npt[@]}" --set run.barostat=c-rescale --set run.barostat_interval=3 --set output.energy_every=2 --set output.thermo_every=10
bad pressure-unit "run.pressure: reduced (lj) units take no unit suffix" "${npt[@]}" --set run.barostat=mc --set run.pressure="1 bar"
bad pressure-absurd-lj "run.pressure = 1e4 is beyond" "${npt[@]}" --set run.barostat=mc --set run.pressure=1e4
bad pressure-absurd-negative "run.pressure = -2e3 is beyond" "${npt[@]}" --set run.barostat=c-rescale --set run.pressure=-2e3
bad pressure-absurd-real "run.pressure = 101325 is beyond +-1e5 bar" --set run.ensemble=nvt-bussi --set run.barostat=mc --set run.pressure=101325 --set system.model=tip4p --set system.count=64 --set system.density=1 --set system.temperature=298 --set run.temperature=298 --set interactions.cutoff=0.5
bad small-box "interactions.cutoff 2 is larger than half the shortest box edge" "${npt[@]}" --set system.count=27 --set run.barostat=mc
# collapse: an absurd pressure shrinks the box below twice the cutoff; the run stops naming the step
# and the cause, and keeps its last checkpoint
"$rotleap" run "$deck" "${npt[@]}" --set interactions.cutoff=2.6 --set run.barostat=c-rescale --set run.pressure=30 --set run.barostat_interval=1 \
  --set run.tau_p=1 --set run.steps=400 --set output.checkpoint_every=5 --set output.prefix="$work/collapse" >/dev/null 2>collapse.err
rc=$?
check "collapse: the run stops (exit != 0)" "[ $rc -ne 0 ]"
check "collapse: the message names the step and the cause" "grep -q 'would shrink the box edge' collapse.err && grep -q 'at step [0-9]' collapse.err && grep -q 'twice the cutoff' collapse.err"
check "collapse: the last checkpoint is kept" "[ -e collapse.chk ] && grep -q 'collapse.chk (step 10) continues' collapse.err"
# the same for the Monte Carlo barostat: a trial below twice the cutoff stops the run (not rejected:
# that would bias the volume's law near the bound)
"$rotleap" run "$deck" "${npt[@]}" --set interactions.cutoff=2.6 --set run.barostat=mc --set run.pressure=50 --set run.barostat_interval=1 \
  --set run.steps=2000 --set output.checkpoint_every=5 --set output.prefix="$work/collapse-mc" >/dev/null 2>collapse-mc.err
rc=$?
check "collapse (mc): the run stops (exit != 0)" "[ $rc -ne 0 ]"
check "collapse (mc): the message names the step and the cause" "grep -q 'Monte Carlo barostat would shrink the box edge' collapse-mc.err && grep -q 'at step [0-9]' collapse-mc.err && grep -q 'twice the cutoff' collapse-mc.err"
check "collapse (mc): the last checkpoint is kept" "[ -e collapse-mc.chk ] && grep -q 'collapse-mc.chk (step [0-9]*) continues' collapse-mc.err"
echo "barostat tests: $pass passed, $fail failed"
[ $fail -eq 0 ]
