#!/usr/bin/env bash
# PREFIX.results.txt, .rdf.csv and .tcf.csv of rotleap run (issue 31 items 1-4): every result has its
# unit (reduced units named, the heat capacity in k_B) and an error bar, the diffusion's fit error is
# called a lower bound, calE is that of the conserved quantity under a thermostat (of the total
# energy in NVE) and says so, the dielectric constant under the dipolar reaction field carries a
# note on its heating, and the averages start where output.discard (auto or a step count) says.
# usage: results_labels_cli.sh ROTLEAP WORKDIR
source "$(dirname "$0")/cli_check.sh"
cat > sm.ini <<'DECK'
[system]
model = stockmayer
count = 32
density = 0.8
temperature = 1.35
[interactions]
cutoff = 1.6
lj = shifted-force
dipole = rf
eps_rf = 10
[run]
steps = 400
timestep = 0.002
ensemble = nvt-bussi
temperature = 1.35
tau = 0.02
equilibrate = 400
[output]
thermo_every = 1
sample_every = 4
rdf = S-S
progress = no
DECK
cat > w.ini <<'DECK'
[system]
model = tip4p
count = 32
density = 1 g/cm3
temperature = 298 K
[interactions]
cutoff = 0.45 nm
[run]
steps = 200
timestep = 1 fs
ensemble = nvt-bussi
temperature = 298 K
equilibrate = 400
[output]
sample_every = 4
rdf = O-O
progress = no
DECK
# the value after "KEY = " and the relative rms fluctuation of a thermo column over the steps the
# analysis had (every row but the run's last state)
val() { sed -n "s/^$2 = \([^ ]*\).*/\1/p" "$1"; }
relfluct() { awk -F, -v c="$2" -v last="$3" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == c) k = i; next }
  $1 < last { n++; d = $k - m; m += d / n; s += d * ($k - m) } END { printf "%.10g\n", sqrt(s / n) / (m < 0 ? -m : m) }' "$1"; }
near() { awk -v a="$1" -v b="$2" -v r="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= r * (b < 0 ? -b : b)) }'; }

"$rotleap" run sm.ini --set output.discard=0 --set output.prefix=sm >out.txt 2>err.txt; code=$?
r=sm.results.txt
check "Stockmayer NVT runs" '[ $code -eq 0 ] && [ -s $r ]'
for kv in "U_per_molecule epsilon" "temperature epsilon/k_B" "temperature_translational epsilon/k_B" \
          "temperature_rotational epsilon/k_B" "pressure epsilon/sigma^3" "mean_square_force (epsilon/sigma)^2" \
          "mean_square_torque epsilon^2"; do
  key=${kv%% *}; unit=$(printf %s "${kv#* }" | sed 's/[].^*[]/\\&/g')
  check "reduced units: $key has an error bar and the unit ${kv#* }" 'grep -q "^$key = [-0-9.e+]* +- [0-9.e+-]* $unit\( \|$\)" $r'
done
check "the heat capacity has an error bar, in k_B" 'grep -q "^heat_capacity_per_molecule = [0-9.e+-]* +- [0-9.e+-]* k_B (canonical formula)" $r'
check "the self-diffusion is in sigma^2/tau with a block error; its fit error is called a lower bound" \
  'grep -q "^self_diffusion = [-0-9.e+]* +- [0-9.e+-]* sigma^2/tau (Einstein, .*error: standard error of D over .*lower bound" $r'
for k in calE calU calE_over_calU dielectric_constant; do
  check "$k has an error bar" 'grep -q "^$k = [0-9.e+-]* +- " $r'
done
calE=$(val $r calE); cons=$(relfluct sm.thermo.csv conserved 400); tot=$(relfluct sm.thermo.csv total 400)
check "NVT calE ($calE) is the conserved quantity's ($cons), not the total energy's ($tot)" \
  'near "$calE" "$cons" 1e-4 && ! near "$calE" "$tot" 0.5'
check "NVT calE says which energy" 'grep -q "^calE = .*(relative rms fluctuation of the conserved quantity: the total energy plus the energy the thermostat took out" $r'
check "the dielectric constant under dipole = rf notes the reaction field's heating" 'grep -q "^dielectric_heating_note = .*interactions.dipole = rf.*jumps at the cutoff" $r'
check "tcf.csv columns carry their units" '[ "$(head -1 sm.tcf.csv)" = "lag_time_tau,dipole_P1,dipole_P2,vacf_sigma2_per_tau2,omega_acf_per_tau2,msd_sigma2" ]'
check "rdf.csv's r carries its unit" '[ "$(head -1 sm.rdf.csv)" = "r_sigma,g_S-S" ]'
check "output.discard = 0: averages from step 0" 'grep -q "^averages_from = step 0 (t = 0 tau): 0 steps discarded; 400 of 400 steps" $r'

"$rotleap" run sm.ini --set output.discard=0 --set run.ensemble=nve --set run.temperature= --set run.tau= \
  --set output.prefix=nve >out.txt 2>err.txt; code=$?
calE=$(val nve.results.txt calE); tot=$(relfluct nve.thermo.csv total 400)
check "NVE calE ($calE) is the total energy's ($tot), and says so" \
  '[ $code -eq 0 ] && near "$calE" "$tot" 1e-4 && grep -q "^calE = .*(relative rms fluctuation of the total energy, the conserved quantity of NVE" nve.results.txt'

"$rotleap" run sm.ini --set interactions.dipole=sf --set output.prefix=sf >out.txt 2>err.txt
check "dipole = sf: no dielectric constant and no heating note" 'grep -q "^dielectric_constant = n/a (dipole = sf" sf.results.txt && ! grep -q heating_note sf.results.txt'

"$rotleap" run w.ini --set output.prefix=w >out.txt 2>err.txt; code=$?
r=w.results.txt
for kv in "U_per_molecule kJ/mol" "temperature K" "pressure bar" "mean_square_force (kJ/mol/nm)^2" \
          "mean_square_torque (kJ/mol)^2"; do
  key=${kv%% *}; unit=$(printf %s "${kv#* }" | sed 's/[].^*[]/\\&/g')
  check "real units: $key in ${kv#* }" 'grep -q "^$key = [-0-9.e+]* +- [0-9.e+-]* $unit\( \|$\)" $r'
done
check "real units: self-diffusion in nm^2/ps" 'grep -q "^self_diffusion = .* nm^2/ps (Einstein" $r'
check "TIP4P (charges, no point dipoles): no heating note" '[ $code -eq 0 ] && ! grep -q heating_note $r'
check "real units: tcf.csv and rdf.csv headers" '[ "$(head -1 w.tcf.csv)" = "lag_time_ps,dipole_P1,dipole_P2,vacf_nm2_per_ps2,omega_acf_per_ps2,msd_nm2" ] && [ "$(head -1 w.rdf.csv)" = "r_nm,g_O-O" ]'

# output.discard: auto by default (Chodera's detection, said so), a step count, or beyond the run
check "output.discard = auto by default, and says how many steps it left out" \
  'grep -q "^equilibration = auto (output.discard): the start in the first half of the run that maximises the number of uncorrelated samples" $r && grep -q "^averages_from = step [0-9]* (t = [0-9.e+-]* ps): [0-9]* steps discarded" $r'
"$rotleap" run sm.ini --set output.discard=100 --set output.prefix=d100 >out.txt 2>err.txt
# the configurations at steps 4, 8, ..., 400: those from step 100 on are averaged
check "output.discard = 100: averages from step 100, 100 steps and the 24 configurations before it left out" \
  'grep -q "^equilibration = output.discard = 100 steps" d100.results.txt && grep -q "^averages_from = step 100 (t = 0.2 tau): 100 steps discarded; 300 of 400 steps with energies and 76 of 100 sampled configurations" d100.results.txt'
u100=$(val d100.results.txt U_per_molecule)
want=$(awk -F, 'NR > 1 && $1 >= 100 && $1 < 400 { s += $4; n++ } END { printf "%.10g\n", s / n / 32 }' sm.thermo.csv)
check "output.discard = 100: U_per_molecule ($u100) is the mean of steps 100-399 ($want)" 'near "$u100" "$want" 1e-7'
"$rotleap" run sm.ini --set output.discard=1000 --set output.prefix=dall >out.txt 2>err.txt; code=$?
check "output.discard beyond the run: nothing averaged, said so, no number" \
  '[ $code -eq 0 ] && grep -q "^averages_from = n/a: the discarded steps cover the whole run" dall.results.txt && grep -q "^U_per_molecule = n/a" dall.results.txt && ! grep -qi nan dall.results.txt'
"$rotleap" run sm.ini --set output.discard=some --set output.prefix=bad >out.txt 2>err.txt; code=$?
check "output.discard = some is refused" '[ $code -ne 0 ] && grep -q "output.discard: .some. is not a whole number" err.txt'
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
