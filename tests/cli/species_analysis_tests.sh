#!/usr/bin/env bash
# Analysis per species of a mixture (issue 35): output.rdf between sites of any species, each
# species' translational and rotational temperatures (thermo columns and results), its MSD and
# self-diffusion.  Known answers: the first-shell coordination numbers of a simple-cubic lattice
# (whatever species sit on its sites, each site has 6 neighbours: n_AA + n_AB = 6); the
# temperatures weighted by their degrees of freedom give the system's; free particles fly
# straight, so each species' MSD is t^2 <v^2> = t^2 kB T_s g_s / (N_s m_s) from its temperature.
# usage: species_analysis_tests.sh ROTLEAP WORKDIR
set -u
rotleap=$1; work=$2
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
pass=0; fail=0
py=/usr/bin/python3; [ -x "$py" ] || py=python3 # pyenv's shim takes seconds to start on a loaded machine
lt() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a + 0 < b + 0) }'; }   # a < b
dist() { awk -v a="$1" -v b="$2" 'BEGIN { d = a - b; print d < 0 ? -d : d }'; }
check() { if eval "$2"; then echo "check $1 ok"; pass=$((pass+1)); else echo "check $1 FAIL"; fail=$((fail+1)); fi; }

# --- free LJ atoms of two masses (no LJ: a site without sigma and epsilon) -------------------
cat > free.ini <<'DECK'
[system]
species = a:48 b:16
density = 0.2
lattice = sc
temperature = 1.0
seed = 7
[molecule a]
units = lj
site = A 0 0 0 mass 1
[molecule b]
units = lj
site = B 0 0 0 mass 4
[interactions]
cutoff = 2.0
[run]
steps = 40
timestep = 0.005
[output]
thermo_every = 10
sample_every = 2
discard = 0
progress = no
DECK

# --- RDFs between species on a lattice at rest: the first shell holds 6 neighbours -----------
sed 's/^temperature = 1.0/temperature = 1e-12/; s/^steps = 40/steps = 2/; s/^sample_every = 2/sample_every = 1/' free.ini > lat.ini
"$rotleap" run lat.ini --set output.rdf="A-A, a-b, b-a, b:B-b:B" > lat.out 2>&1; code=$?
check "mixture RDFs run and name their columns as written" '[ $code = 0 ] && head -1 lat.rdf.csv | grep -q "^r_sigma,g_A-A,g_a-b,g_b-a,g_b:B-b:B$"'
# n_XY = sum over the first shell of g(r) x shell volume x P / (V N_X), P the ordered pairs
$py - lat.rdf.csv 48 16 64 0.2 > coord.txt <<'PY'
import math, sys
rows = [l.strip().split(',') for l in open(sys.argv[1])][1:]
na, nb, n, rho = int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5])
V = n / rho
a = rho ** (-1.0 / 3.0)
r = [float(x[0]) for x in rows]
dr = 2 * r[0]
def coord(col, nx, pairs):
    s = 0.0
    for k, x in enumerate(rows):
        if 0.9 * a < r[k] < 1.1 * a:
            shell = 4.0 / 3.0 * math.pi * ((k + 1) ** 3 - k ** 3) * dr ** 3
            s += float(x[col]) * shell * pairs / (V * nx)
    return s
naa, nab, nba, nbb = coord(1, na, na * (na - 1)), coord(2, na, na * nb), coord(3, nb, na * nb), coord(4, nb, nb * (nb - 1))
print(naa + nab, nba + nbb, naa, nab, nba, nbb)
PY
read -r sa sb naa nab nba nbb < coord.txt
check "sc lattice: n_AA + n_AB = 6 for A (got $sa: $naa + $nab)" 'lt $(dist $sa 6) 1e-4'
check "sc lattice: n_BA + n_BB = 6 for B (got $sb: $nba + $nbb)" 'lt $(dist $sb 6) 1e-4'
check "both species have neighbours of both species" 'lt 0.5 $naa && lt 0.5 $nab && lt 0.5 $nba && lt 0.5 $nbb'

# --- output.rdf's errors name the key and what there is ------------------------------------
err() { "$rotleap" energy "$@" > e.out 2> e.err; echo $?; }
code=$(err free.ini --set output.rdf="A-c")
check "unknown name refused, naming sites and species" '[ $code = 2 ] && grep -q "output.rdf: .c. is neither a site of the first species a (its sites: A) nor a species of one site; write SPECIES:SITE (species: a, b)" e.err'
code=$(err free.ini --set output.rdf="a:B-b")
check "a site the species lacks refused" '[ $code = 2 ] && grep -q "output.rdf: species a has no site .B. (its sites: A)" e.err'

# --- per-species temperatures: Stockmayer dipoles in an LJ solvent ---------------------------
cat > mix.ini <<'DECK'
[system]
species = stockmayer:16 lj:48
density = 0.8
lattice = sc
temperature = 1.35
seed = 3
[molecule lj]
units = lj
site = A 0 0 0 mass 1 sigma 1 epsilon 1
[interactions]
cutoff = 1.9
lj = shifted-force
dipole = sf
[run]
steps = 20
timestep = 0.002
[output]
thermo_every = 2
sample_every = 2
discard = 0
rdf = S-S, stockmayer:S-lj, lj:A-lj:A
progress = no
DECK
"$rotleap" run mix.ini > mix.out 2>&1; code=$?
check "mixture runs with per-species columns" '[ $code = 0 ] && head -1 mix.thermo.csv | grep -q ",t_trans_stockmayer,t_rot_stockmayer,t_trans_lj$"'
# every row: sum_s g_s T_s = g T, translational (g_s = (3N - 3) N_s / N), rotational (2 N_s for
# the dipoles) and total
$py - mix.thermo.csv > sums.txt <<'PY'
import sys
rows = [l.strip().split(',') for l in open(sys.argv[1])]
h = rows[0]
c = {k: i for i, k in enumerate(h)}
N, Ns, Nl = 64, 16, 48
gt, gr = 3 * N - 3, 2 * Ns
worst = 0.0
for x in rows[1:]:
    v = lambda k: float(x[c[k]])
    tt = (gt * Ns / N * v("t_trans_stockmayer") + gt * Nl / N * v("t_trans_lj")) / gt
    tr = v("t_rot_stockmayer")
    tot = (gt * tt + gr * tr) / (gt + gr)
    for a, b in ((tt, v("t_trans")), (tr, v("t_rot")), (tot, v("temperature"))):
        worst = max(worst, abs(a - b) / b)
print(worst, len(rows) - 1)
PY
read -r worst nrows < sums.txt
check "per-species T weighted by dof sum to t_trans, t_rot, temperature in $nrows rows (worst $worst)" '[ "$nrows" = 11 ] && lt $worst 2e-5'
check "results: per-species temperatures, ions/atoms without a rotational one" 'grep -q "^temperature_translational_lj = " mix.results.txt && grep -q "^temperature_rotational_stockmayer = " mix.results.txt && grep -q "^temperature_rotational_lj = n/a (lj: point particles" mix.results.txt'
check "summary: the kernel of each pair of species" 'grep -q "^pair_kernels_by_species = stockmayer/stockmayer: stockmayer; stockmayer/lj: general; lj/lj: charge-lj (general: the reference routine)$" mix.summary.txt'
check "P1/P2 of the dipoles only (no zero vector of the atoms)" 'grep -q "^orientation_vector = molecular dipole mu_i of the molecules of stockmayer" mix.results.txt && ! grep -q correlation_error mix.results.txt'

# --- a continuation replays the mixture's analysis journal: the same files as one run --------
"$rotleap" run mix.ini --set output.prefix=half --set run.steps=10 > /dev/null 2>&1
"$rotleap" run mix.ini --set output.prefix=half --set system.start=half.chk > /dev/null 2>&1; code=$?
check "a mixture continued from its checkpoint: results, RDFs, tcf and thermo as one run" '[ $code = 0 ] && cmp -s half.thermo.csv mix.thermo.csv && cmp -s half.rdf.csv mix.rdf.csv && cmp -s half.tcf.csv mix.tcf.csv && cmp -s half.results.txt mix.results.txt'

# --- per-species MSD of free particles: t^2 kB T_s (3N - 3) / (N m_s) -------------------------
"$rotleap" run free.ini > free.out 2>&1; code=$?
$py - free.tcf.csv free.results.txt > msd.txt <<'PY'
import sys
rows = [l.strip().split(',') for l in open(sys.argv[1])]
c = {k: i for i, k in enumerate(rows[0])}
T = {}
for l in open(sys.argv[2]):
    for s in "ab":
        if l.startswith("temperature_translational_%s = " % s): T[s] = float(l.split()[2])
N, m = 64, {"a": 1.0, "b": 4.0}
worst, mix = 0.0, 0.0
for x in rows[2:]:
    t = float(x[0])
    for s in "ab":
        want = t * t * T[s] * (3 * N - 3) / (N * m[s])
        worst = max(worst, abs(float(x[c["msd_sigma2_" + s]]) - want) / want)
    tot = (48 * float(x[c["msd_sigma2_a"]]) + 16 * float(x[c["msd_sigma2_b"]])) / 64
    mix = max(mix, abs(tot - float(x[c["msd_sigma2"]])) / float(x[c["msd_sigma2"]]))
print(worst, mix, len(rows) - 2)
PY
read -r worst mix nlag < msd.txt
check "free flight: MSD of each species = t^2 kB T_s g_s / (N_s m_s) over $nlag lags (worst $worst)" '[ $code = 0 ] && [ "$nlag" -ge 8 ] && lt $worst 2e-5'
check "the species' MSDs weighted by count are the total's (worst $mix)" 'lt $mix 2e-5'
check "self_diffusion per species" 'grep -q "^self_diffusion_a = " free.results.txt && grep -q "^self_diffusion_b = " free.results.txt'

# --- a one-species deck keeps its files: no species columns --------------------------------
sed 's/^species = .*/species = a:64/' free.ini > one.ini
"$rotleap" run one.ini > one.out 2>&1
check "one species: no per-species columns or lines" '! grep -q "t_trans_a" one.thermo.csv && ! grep -q "msd_sigma2_a" one.tcf.csv && ! grep -q "_a = " one.results.txt'

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
