"""Criteria and rotleap runs of the short NVE comparison (validate/nve_short.py,
tests/validate/check_nve.py).  Standard library only, so the CTest needs neither numpy nor OpenMM.

Criteria (justification in validate/README.md):
  1. trajectory: over the first WINDOW = 100 steps, max_t |U_rl(t) - U_omm(t)| / N must be at
     most RATIO = 0.05 of max_t |U_rl,h(t) - U_rl,h/2(t)| / N, the change of rotleap's own
     trajectory when the step is halved (which also moves the start: v(-h/2) = 0 means
     v(0) = (h/2) a(0), so this yardstick is the effect of an O(h) perturbation of the dynamics,
     the size of error a wrong start convention, mass or inertia would make).
  2. conservation: rotleap's calE over the run (sd of E over |<E>|, steps 1..499) at most 2 x
     OpenMM's, and |E(499) - E(1)| / N at most 2 x OpenMM's.
"""
import csv
import math
import os
import subprocess
import sys

STEPS, H = 500, 0.001
WINDOW = 100
RATIO = 0.05


def rotleap_deck(start, box, steps, h, prefix):
    return ("[system]\nmodel = tip4p\ncount = 216\nbox = %s\nstart = %s\ntemperature = 298 K\n"
            "[interactions]\ncutoff = 0.9 nm\nscheme = site\nlj = plain\ndispersion_correction = no\n"
            "eps_rf = 78.3\n[run]\nensemble = nve\nsteps = %d\ntimestep = %r ps\n"
            "[output]\nprefix = %s\nthermo_every = 1\nprogress = no\nsample_every = 0\n"
            % (" ".join(repr(b) for b in box), start, steps, h, prefix))


def rotleap_series(rotleap, work, start, box, steps, h, tag):
    """[(step, total, potential)] from rotleap run's thermo file."""
    deck = os.path.join(work, tag + ".ini")
    with open(deck, "w") as f:
        f.write(rotleap_deck(start, box, steps, h, os.path.join(work, tag)))
    p = subprocess.run([rotleap, "run", deck], capture_output=True, text=True)
    if p.returncode:
        sys.exit("rotleap run failed:\n" + p.stdout + p.stderr)
    with open(os.path.join(work, tag + ".thermo.csv")) as f:
        return [(int(r["step"]), float(r["total"]), float(r["potential"])) for r in csv.DictReader(f)]


def metrics(rl, rl_half, omm, n):
    """The two criteria; every series is [(step, total, potential)] (rl_half at h/2)."""
    U_rl = {s: u for s, _, u in rl}
    U_half = {s: u for s, _, u in rl_half}
    U_omm = {s: u for s, _, u in omm}
    d_omm = max(abs(U_rl[s] - U_omm[s]) for s in range(1, WINDOW + 1)) / n
    d_h = max(abs(U_rl[s] - U_half[2 * s]) for s in range(1, WINDOW + 1)) / n
    first = {s: abs(U_rl[s] - U_omm[s]) / n for s in (1, 10, 50, 100, 200, 300, 400, 499)}

    last = min(rl[-1][0], omm[-1][0])   # the steps both series have: compare steps 1..last

    def cal(series):
        e = [t for s, t, _ in series if 1 <= s <= last]
        mean = sum(e) / len(e)
        sd = math.sqrt(sum((x - mean) ** 2 for x in e) / len(e))
        return sd / abs(mean), abs(e[-1] - e[0]) / n

    calE_rl, drift_rl = cal(rl)
    calE_omm, drift_omm = cal(omm)
    ok1 = d_omm <= RATIO * d_h
    ok2 = calE_rl <= 2 * calE_omm and drift_rl <= 2 * drift_omm
    return dict(d_omm=d_omm, d_h=d_h, first=first, calE_rl=calE_rl, calE_omm=calE_omm,
                drift_rl=drift_rl, drift_omm=drift_omm, ok1=ok1, ok2=ok2)


def report(m):
    lines = ["first %d steps: max |U_rotleap - U_OpenMM|/N = %.3e kJ/mol; rotleap's own time-step "
             "error max |U(h) - U(h/2)|/N = %.3e kJ/mol; ratio %.4f (criterion <= %g): %s"
             % (WINDOW, m["d_omm"], m["d_h"], m["d_omm"] / m["d_h"], RATIO, "ok" if m["ok1"] else "FAIL"),
             "|U_rotleap - U_OpenMM|/N at step " + ", ".join("%d: %.1e" % kv for kv in m["first"].items()),
             "calE over %d steps: rotleap %.3e, OpenMM %.3e (criterion rotleap <= 2 x OpenMM); "
             "|E(end) - E(1)|/N: rotleap %.2e, OpenMM %.2e kJ/mol (criterion rotleap <= 2 x OpenMM): %s"
             % (STEPS, m["calE_rl"], m["calE_omm"], m["drift_rl"], m["drift_omm"],
                "ok" if m["ok2"] else "FAIL")]
    return lines
