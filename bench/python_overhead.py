#!/usr/bin/env python3
"""The cost of stepping from Python (issue 36: <= 2 % in blocks of >= 100 steps): the default
example's production run, `rotleap run` against rotleap.Simulation.step(BLOCK) in a loop,
alternated ROUNDS times in this one process.  Both are timed from the deck to the last step:
rotleap run's summary wall_seconds (scene, steps, its thermo rows, samples and files; its
samples and rows are made sparse here) against the Python side's construction and steps.

  bench/python_overhead.py ROTLEAP [--deck examples/tip4p.ini] [--steps 1000] [--block 100] [--rounds 5]
(with the package importable: installed, or PYTHONPATH=python ROTLEAP_NATIVE=build/_rotleap_native.so)"""
import argparse
import os
import re
import resource
import statistics
import subprocess
import tempfile
import time

import rotleap

ap = argparse.ArgumentParser()
ap.add_argument("rotleap")
ap.add_argument("--deck", default=os.path.join(os.path.dirname(__file__), "..", "examples", "tip4p.ini"))
ap.add_argument("--steps", type=int, default=1000)
ap.add_argument("--block", type=int, default=100)
ap.add_argument("--rounds", type=int, default=5)
a = ap.parse_args()
sets = {"run.equilibrate": 0, "run.steps": a.steps, "output.thermo_every": a.steps, "output.sample_every": a.steps}
work = tempfile.mkdtemp(prefix="rl-pybench-")
cli_t, py_t, cli_cpu, py_cpu = [], [], [], []


def child_cpu():
    u = resource.getrusage(resource.RUSAGE_CHILDREN)
    return u.ru_utime + u.ru_stime


for r in range(a.rounds):
    args = [a.rotleap, "run", os.path.abspath(a.deck), "--set", "output.prefix=%s/cli" % work]
    for k, v in sets.items():
        args += ["--set", "%s=%s" % (k, v)]
    c0 = child_cpu()
    subprocess.run(args, check=True, capture_output=True)
    cli_cpu.append(child_cpu() - c0)
    cli_t.append(float(re.search(r"wall_seconds = ([0-9.]+)", open(work + "/cli.summary.txt").read()).group(1)))
    t0, p0 = time.perf_counter(), time.process_time()
    sim = rotleap.Simulation(a.deck, set=sets)
    for _ in range(a.steps // a.block):
        sim.step(a.block)
    py_t.append(time.perf_counter() - t0)
    py_cpu.append(time.process_time() - p0)
    sim.close()
    print("round %d: rotleap run %.3f s (cpu %.3f s), python %.3f s (cpu %.3f s), ratio %.4f (cpu %.4f)" % (
        r, cli_t[-1], cli_cpu[-1], py_t[-1], py_cpu[-1], py_t[-1] / cli_t[-1], py_cpu[-1] / cli_cpu[-1]))
print("median: rotleap run %.3f s, python (blocks of %d) %.3f s; ratio of medians %.4f, median of ratios %.4f" % (
    statistics.median(cli_t), a.block, statistics.median(py_t), statistics.median(py_t) / statistics.median(cli_t),
    statistics.median([p / c for p, c in zip(py_t, cli_t)])))
print("cpu seconds (rotleap run: the whole process, with its start and files): median of ratios %.4f" % (
    statistics.median([p / c for p, c in zip(py_cpu, cli_cpu)])))
# the cost of stepping from Python itself: one call into the library per block, timed directly
sim = rotleap.Simulation(a.deck, set=dict(sets, **{"run.steps": 1}))
calls = 20000
best = min(timeit_call for timeit_call in (
    (lambda: (lambda t0: (sum(sim.step(0) or 0 for _ in range(calls)), time.perf_counter() - t0)[1])(time.perf_counter()))()
    for _ in range(5)))
t0 = time.perf_counter()
sim.step(a.block)
block = time.perf_counter() - t0
sim.close()
print("one call (step(0), best of 5 x %d): %.1f us; step(%d): %.1f ms; overhead of a block %.2e" % (
    calls, 1e6 * best / calls, a.block, 1e3 * block, best / calls / block))
