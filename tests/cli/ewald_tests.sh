#!/usr/bin/env bash
# Ewald and smooth PME from a deck (interactions.coulomb = ewald | pme, issue 33): bad input
# refused at the line of its key; the reaction field unchanged when coulomb is not given; the
# energy by term from the terms, PME against Ewald, explicit parameters against derived ones,
# 1 against 2 threads; the run and its summary print alpha, the grid and the estimated error;
# checkpoint continuation bit for bit; scan; the dielectric constant's boundary; point dipoles
# (Stockmayer) with coulomb = ewald or pme: the terms, pme against ewald, alpha independence, an
# NVE run.
# usage: ewald_tests.sh ROTLEAP SRCDIR WORKDIR
set -u
rotleap=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
pass=0; fail=0
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }
quiet() { ! grep -qv "^rotleap [a-z]*: note: " "$1"; }
pme="$src/tests/cli/water_pme.ini"
sm="$src/tests/cli/stockmayer_short.ini"

# --- bad input: one problem each, at the line of the key that causes it, naming it
# bad NAME EXPECTED SED-SCRIPT [DECK]: the deck edited by SED-SCRIPT must be refused with exit 2,
# one problem, whose message (after "FILE:LINE: ") contains EXPECTED, LINE being the line where
# the sed script left the key named first in EXPECTED
bad() {
  local name=$1 want=$2 script=$3 deck=${4:-$pme}
  sed "$script" "$deck" > "$name.ini"
  local key=${want%%[ :=]*}; key=${key#interactions.}
  local line; line=$(grep -n "^$key *=" "$name.ini" | head -1 | cut -d: -f1)
  "$rotleap" energy "$name.ini" >out.txt 2>"$name.err"; local code=$?
  check "$name: refused at $name.ini:$line, naming the key" \
    '[ $code -eq 2 ] && grep -qF "$name.ini:$line: $want" "$name.err" && grep -q "^rotleap energy: 1 problem in" "$name.err"'
}
bad tol_high "interactions.ewald_tolerance = 0.2: tolerance = 0.2 must lie in (0, 0.1)" 's/^ewald_tolerance = .*/ewald_tolerance = 0.2/'
bad tol_zero "interactions.ewald_tolerance = 0: tolerance = 0 must lie in (0, 0.1)" 's/^ewald_tolerance = .*/ewald_tolerance = 0/'
bad grid_coarse "interactions.pme_grid = 4 5 6: grid[0] = 4 is below the spline order 5" 's/^coulomb = pme/&\npme_grid = 4 5 6/'
bad grid_nyquist "interactions.pme_grid = 6: grid[0] = 6 is too coarse for tolerance 0.0005" 's/^coulomb = pme/&\npme_grid = 6/'
bad grid_two "interactions.pme_grid: '8 9' has two numbers" 's/^coulomb = pme/&\npme_grid = 8 9/'
bad order "interactions.pme_order: 13 is above the maximum 12" 's/^coulomb = pme/&\npme_order = 13/'
bad alpha_small "interactions.ewald_alpha = 1 /nm: alpha = 1 with cutoff = 0.6: alpha cutoff = 0.6 is below sqrt(-ln 0.2)" 's/^coulomb = pme/&\newald_alpha = 1 \/nm/'
bad alpha_unit "interactions.ewald_alpha: unit '/s' is not an inverse length unit" 's/^coulomb = pme/&\newald_alpha = 3 \/s/'
bad kmax_coarse "interactions.ewald_kmax = 2: kmax = 2 2 2, kmax_sq = 0 is too coarse for tolerance 0.0005" 's/^coulomb = pme/coulomb = ewald\newald_kmax = 2/'
bad kmax_pme "interactions.ewald_kmax is only used with coulomb = ewald (coulomb = pme here)" 's/^coulomb = pme/&\newald_kmax = 5/'
bad grid_ewald "interactions.pme_grid is only used with coulomb = pme (coulomb = ewald here)" 's/^coulomb = pme/coulomb = ewald\npme_grid = 20/'
bad tol_rf "interactions.ewald_tolerance is only used with coulomb = ewald or pme (coulomb = rf here)" 's/^coulomb = pme/coulomb = rf/'
bad epsrf_pme "interactions.eps_rf is only used with coulomb = rf (coulomb = pme here" 's/^coulomb = pme/&\neps_rf = 80/'
bad dipole_ewald "interactions.dipole is only used with coulomb = rf (coulomb = ewald here" 's/^dipole = sf/&\ncoulomb = ewald/' "$sm"
bad dipole_pme "interactions.dipole is only used with coulomb = rf (coulomb = pme here" 's/^dipole = sf/dipole = rf\ncoulomb = pme/' "$sm"
bad boundary "interactions.ewald_boundary: '0.5' is not tinfoil, vacuum or a dielectric constant >= 1" 's/^coulomb = pme/&\newald_boundary = 0.5/'
bad scheme "interactions.scheme = molecule does not go with coulomb = pme" 's/^coulomb = pme/&\nscheme = molecule/'
bad cutoff_box "interactions.cutoff 0.7 is larger than half the shortest box edge" 's/^cutoff = .*/cutoff = 0.7 nm/'
"$rotleap" energy "$src/examples/n2.ini" --set interactions.coulomb=ewald --set interactions.scheme=site >out.txt 2>err.txt; code=$?
check "a quadrupole-only model (N2, no charges) is refused for Ewald, naming coulomb" \
  '[ $code -eq 2 ] && grep -q "^--set: interactions.coulomb = ewald needs point charges: model n2: .* carries a quadrupole" err.txt'

# --- the reaction field is what it was: coulomb = rf (the default) changes nothing
"$rotleap" energy "$src/examples/tip4p.ini" --json >rf_default.json 2>/dev/null
"$rotleap" energy "$src/examples/tip4p.ini" --json --set interactions.coulomb=rf >rf_given.json 2>/dev/null
check "coulomb = rf is the default, to the byte, with no Ewald term" \
  'cmp -s rf_default.json rf_given.json && grep -q "\"terms\": \[\"pair\"\]" rf_default.json && ! grep -q ewald rf_default.json'

# --- energies by term from the terms; PME against Ewald; explicit against derived; threads
e() { local out=$1; shift; "$rotleap" energy "$pme" --json --set run.threads=1 "$@" >"$out" 2>"$out.err"; }
e pme.json
e pme_t2.json --set run.threads=2
e pme_grid.json --set "interactions.pme_grid=17 17 17" --set interactions.pme_order=5
e pme_grid1.json --set interactions.pme_grid=17
e alpha_nm.json --set "interactions.ewald_alpha=4.5 /nm"
e alpha_A.json --set "interactions.ewald_alpha=0.45 /A"
e tight_pme.json --set interactions.ewald_tolerance=1e-6
e tight_ewald.json --set interactions.ewald_tolerance=1e-6 --set interactions.coulomb=ewald
e nist.json --set interactions.coulomb=ewald --set "interactions.ewald_alpha=5.6 /nm" --set interactions.ewald_kmax=5 --set interactions.ewald_kmax2=26
e vacuum.json --set interactions.ewald_boundary=vacuum
e eps1.json --set interactions.ewald_boundary=1
/usr/bin/python3 - <<'PY' > py.txt
import json
J = lambda f: json.load(open(f))
ok = lambda c, m: print(("ok " if c else "FAIL ") + m)
a = J("pme.json")
E = a["energy"]
comps = ["lj", "coulomb", "dipolar", "quadrupolar", "dispersion", "ewald_recip", "ewald_self", "ewald_intra",
         "ewald_background", "ewald_surface"]
ok(a["terms"] == ["pair", "pme"], "the terms are pair (with the Ewald real space in its kernels) and pme")
ok(sorted(k for k in E if k != "total") == sorted(comps), "energy by term: the components of the two terms")
ok(abs(sum(E[k] for k in comps) - E["total"]) <= 1e-12 * abs(E["ewald_self"]), "the components sum to the total")
ok(E["coulomb"] < 0 and E["ewald_surface"] == 0 and E["ewald_background"] == 0,
   "the pair term's coulomb is the Ewald real space (negative in water); tin foil, neutral: no surface or background energy")
b = J("pme_t2.json")
ok(all(a["energy"][k] == b["energy"][k] for k in comps if k.startswith("ewald")), "2 threads: the reciprocal terms' energies to the bit")
ok(abs(a["energy"]["total"] - b["energy"]["total"]) <= 1e-12 * abs(E["ewald_self"]), "2 threads: the total to round-off")
# PME's derived grid for this box (1.2439 nm, alpha from 5e-4 and 0.6 nm) is 17^3: given explicitly, the same bits
ok(J("pme_grid.json") == a and J("pme_grid1.json") == a, "pme_grid = 17 17 17 (and = 17), pme_order = 5: the derived choice, to the bit")
ok(J("alpha_nm.json") == J("alpha_A.json") and J("alpha_nm.json")["energy"] != E, "ewald_alpha 4.5 /nm = 0.45 /A, and it is used")
t, w = J("tight_pme.json")["energy"], J("tight_ewald.json")["energy"]
ok(abs(t["total"] - w["total"]) <= 1e-5 * abs(w["total"]) and t["coulomb"] == w["coulomb"],
   "PME and Ewald at tolerance 1e-6: one energy (1e-5 relative), the same real-space sum")
f1 = J("tight_pme.json")["molecules"]; f2 = J("tight_ewald.json")["molecules"]
num = sum((x - y) ** 2 for m1, m2 in zip(f1, f2) for x, y in zip(m1["force"], m2["force"]))
den = sum(x ** 2 for m in f2 for x in m["force"])
ok((num / den) ** 0.5 <= 1e-4, "PME and Ewald at tolerance 1e-6: molecular forces agree to 1e-4 RMS relative (%.2g)" % (num / den) ** 0.5)
n = J("nist.json")
ok(n["terms"] == ["pair", "ewald"], "coulomb = ewald with the NIST SPC/E setup (alpha 5.6 /nm, kmax 5, kmax2 26)")
v, v1 = J("vacuum.json")["energy"], J("eps1.json")["energy"]
ok(v == v1 and v["ewald_surface"] > 0 and abs(v["total"] - v["ewald_surface"] - E["total"]) <= 1e-9 * abs(E["ewald_self"]),
   "ewald_boundary = vacuum (= 1): the surface term, positive, added to the tin-foil energy")
PY
while read -r st msg; do check "$msg" '[ "$st" = ok ]'; done < py.txt
check "the energy checks ran" '[ "$(wc -l < py.txt)" -ge 12 ]'

# --- a run: what it prints, its summary, the dielectric constant's boundary
"$rotleap" run "$pme" --set output.prefix="$work/run" >out.txt 2>err.txt; code=$?
want='smooth PME: alpha = 4.38043 /nm (from tolerance 0.0005 and cutoff 0.6 nm), grid 17 x 17 x 17 (from the tolerance), order 5, tin-foil boundary; estimated RMS force error on a charge'
check "the run prints alpha, the grid and the estimated RMS force error before it starts and in its summary" \
  '[ $code -eq 0 ] && grep -qF "rotleap run: note: electrostatics: $want" err.txt && grep -qF "electrostatics = $want" run.summary.txt'
check "the thermo file has the Ewald terms' columns" \
  'head -1 run.thermo.csv | grep -q ",lj,coulomb,dipolar,quadrupolar,dispersion,ewald_recip,ewald_self,ewald_intra,ewald_background,ewald_surface,"'
check "the dielectric constant takes the Ewald sum's tin-foil boundary" \
  'grep -q "^dielectric_constant = .*Ewald sum in tin-foil (conducting) surroundings" run.results.txt'

# --- checkpoint continuation bit for bit (2 threads): 2N steps against N + continue N
args=(--set run.threads=2 --set output.checkpoint_every=20)
"$rotleap" run "$pme" "${args[@]}" --set output.prefix="$work/A" >/dev/null 2>A.err
"$rotleap" run "$pme" "${args[@]}" --set run.steps=20 --set output.prefix="$work/B" >/dev/null 2>B.err
"$rotleap" run "$pme" "${args[@]}" --set system.start="$work/B.chk" --set output.prefix="$work/B" >/dev/null 2>>B.err
check "PME runs: no error" 'quiet A.err && quiet B.err && [ -e A.chk ] && [ -e B.chk ]'
check "PME: checkpoint after 2N steps = after N + a continuation of N, byte for byte" 'cmp -s A.chk B.chk'
check "PME: thermo files byte for byte" 'cmp -s A.thermo.csv B.thermo.csv'
"$rotleap" run "$pme" "${args[@]}" --set system.start="$work/B.chk" --set run.steps=60 --set interactions.coulomb=rf \
  --set interactions.ewald_tolerance= --set output.prefix="$work/B" >/dev/null 2>C.err; code=$?
check "a continuation under the same prefix with another coulomb is refused, naming it" \
  '[ $code -ne 0 ] && grep -q "interactions.coulomb: pme -> (not used)" C.err'
"$rotleap" run "$pme" "${args[@]}" --set system.start="$work/B.chk" --set run.steps=60 --set interactions.pme_order=6 \
  --set output.prefix="$work/B" >/dev/null 2>C.err; code=$?
check "... and so is one with another pme_order" '[ $code -ne 0 ] && grep -q "interactions.pme_order: 5 -> 6" C.err'

# --- scan with a PME deck
"$rotleap" scan "$pme" --timesteps 1,2fs --steps 10 --no-plot --set output.prefix="$work/scan" >out.txt 2>err.txt; code=$?
check "rotleap scan runs a PME deck and says which electrostatics it used" \
  '[ $code -eq 0 ] && grep -qF "# electrostatics: $want" out.txt && [ "$(wc -l < scan.scan.csv)" -eq 3 ]'

# --- point dipoles: a Stockmayer deck with coulomb = ewald (the real space in the pair term's
# Stockmayer rows, its dipolar component, since 2026-11-28; the term ewald-real before)
sed 's/^dipole = .*/coulomb = ewald/' "$sm" > sm_ewald.ini
"$rotleap" energy sm_ewald.ini --json >sme.json 2>sme.err; code=$?
check "Stockmayer, coulomb = ewald: the pair term (with the dipolar real space) and the term ewald" \
  '[ $code -eq 0 ] && ! grep -q "\"dipolar\": 0," sme.json && grep -q "\"terms\": \[\"pair\", \"ewald\"\]" sme.json'
sed 's/^dipole = .*/coulomb = pme/' "$sm" > sm_pme.ini
# point dipoles alone without pme_order: the order chosen with the mesh, said, recorded and kept by
# a continuation (40 steps against 20 + 20, byte for byte); a given order is the deck's
"$rotleap" run sm_pme.ini --set run.steps=40 --set output.prefix="$work/smpA" >/dev/null 2>smpA.err; code=$?
"$rotleap" run sm_pme.ini --set run.steps=20 --set output.prefix="$work/smpB" >/dev/null 2>/dev/null
"$rotleap" run sm_pme.ini --set run.steps=40 --set system.start="$work/smpB.chk" --set output.prefix="$work/smpB" >/dev/null 2>/dev/null
"$rotleap" run sm_pme.ini --set interactions.pme_order=5 --set run.steps=2 --set output.prefix="$work/smp5" >/dev/null 2>smp5.err
check "Stockmayer, coulomb = pme, no pme_order: the order chosen from the tolerance, a continuation bit for bit; pme_order = 5 is kept" \
  '[ $code -eq 0 ] && grep -q "grid [0-9]* x [0-9]* x [0-9]* (from the tolerance), order [4-8] (from the tolerance)" smpA.err && cmp -s smpA.chk smpB.chk && grep -q "(from the tolerance), order 5, " smp5.err'
# (the mesh given: derived from tolerance 1e-6 for these dipoles it would need more than 512^3 points
# at order 5, whose dipolar forces converge as h^3)
"$rotleap" energy sm_pme.ini --json --set interactions.ewald_tolerance=1e-6 --set interactions.pme_grid=64 --set interactions.pme_order=8 >smp.json 2>smp.err; code=$?
"$rotleap" energy sm_ewald.ini --json --set interactions.ewald_tolerance=1e-6 >smk.json 2>/dev/null
check "Stockmayer, coulomb = pme: the mesh version (64^3, order 8), within 1e-6 of the k-vector sum at tolerance 1e-6" \
  '[ $code -eq 0 ] && grep -q "\"terms\": \[\"pair\", \"pme\"\]" smp.json && python3 - smp.json smk.json <<PYEOF
import json, sys
a, b = (json.load(open(f))["energy"]["total"] for f in sys.argv[1:3])
print("pme %.12g ewald %.12g" % (a, b))
sys.exit(not abs(a - b) <= 1e-6 * abs(b))
PYEOF'
for a in 2.5 3.0; do
  "$rotleap" energy sm_ewald.ini --json --set interactions.ewald_alpha=$a --set interactions.ewald_kmax=$([ $a = 2.5 ] && echo 20 || echo 24) \
    >sme_$a.json 2>/dev/null
done
check "... the sum independent of alpha (2.5 and 3 /sigma, converged): energy within 1e-9, forces and torques 1e-8" \
  'python3 - sme_2.5.json sme_3.0.json <<PYEOF
import json, math, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
ea, eb = a["energy"]["total"], b["energy"]["total"]
def rel(k):
    num = sum((x - y) ** 2 for ma, mb in zip(a["molecules"], b["molecules"]) for x, y in zip(ma[k], mb[k]))
    return math.sqrt(num / sum(y * y for mb in b["molecules"] for y in mb[k]))
print("dU %.2e dF %.2e dT %.2e" % (abs(ea - eb) / abs(ea), rel("force"), rel("torque")))
sys.exit(not (abs(ea - eb) <= 1e-9 * abs(ea) and rel("force") <= 1e-8 and rel("torque") <= 1e-8))
PYEOF'
"$rotleap" run sm_ewald.ini --set run.steps=2000 --set output.prefix="$work/sme" >sme_run.txt 2>sme_run.err; code=$?
drift=$(sed -n 's/^conserved_drift = \([^ ]*\) kT.*/\1/p' sme.summary.txt)
check "... an NVE run of 2000 steps: ok, says what it sums, conserved drift $drift below 0.02 kT per molecule per time unit" \
  '[ $code -eq 0 ] && grep -q "^status = ok" sme.summary.txt && grep -q "^electrostatics = Ewald of point dipoles: alpha" sme.summary.txt && python3 -c "import sys; sys.exit(not abs($drift) < 0.02)"'
check "... and its dielectric constant uses the Ewald boundary, without the reaction-field heating note" \
  'grep -q "^dielectric_constant = .*Ewald sum in tin-foil" sme.results.txt && ! grep -q "dielectric_heating_note" sme.results.txt'

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
