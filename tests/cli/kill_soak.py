#!/usr/bin/env python3
"""Kill-and-continue soak (issue 30): a run is killed once, twice or three times -- by SIGKILL at a
random moment or at an injected system call (strace -e inject=SYSCALL:signal=KILL:when=N) -- and
continued each time from PREFIX.chk (or started again if it has none yet); the last attempt runs
to the end.  Its checkpoint, thermo file, trajectory, PDB and results must be byte for byte those
of a run never killed.  Six scenes: TIP4P (DCD + PDB) and Stockmayer (extended XYZ), one and two
threads, and Stockmayer under each barostat (Monte Carlo; semi-isotropic C-rescale).

  kill_soak.py ROTLEAP SRCDIR WORKDIR [--sequences N] [--seed S] [--starts] [--scenes a,b] [--short]

--starts   also kill at EVERY write/rename/fsync/ftruncate/openat/copy_file_range of a
           continuation's start (before its first step), one sequence per system call.
--sequences N   random sequences per scene (default 3; validate/ runs 100 per scene).
Exit status 0 if every sequence ends with identical files; prints one line per sequence and the
counts.  Needs strace (Debian strace)."""
import argparse
import filecmp
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import time

FILES = {"dcd": ["chk", "thermo.csv", "dcd", "pdb", "samples", "results.txt", "rdf.csv", "tcf.csv"],
         "xyz": ["chk", "thermo.csv", "xyz", "samples", "results.txt", "tcf.csv"]}
SYSCALLS = ["write", "rename", "fsync", "ftruncate", "openat", "copy_file_range"]
# LeakSanitizer cannot run under ptrace: a sanitizer build's runs under strace check no leaks
STRACE_ENV = dict(os.environ, ASAN_OPTIONS=(os.environ.get("ASAN_OPTIONS", "") + ":detect_leaks=0").lstrip(":"))


def scenes(src, short=False):
    water = os.path.join(src, "tests/cli/water_scan.ini")
    stock = os.path.join(src, "tests/cli/stockmayer_short.ini")
    common = ["--set", "output.checkpoint_every=40", "--set", "output.trajectory_every=10",
              "--set", "output.thermo_every=10", "--set", "output.progress=no"]
    n1, n2 = ("120", "200") if short else ("240", "400")
    npt = ["--set", "system.count=125", "--set", "run.ensemble=nvt-bussi", "--set", "run.temperature=1.35",
           "--set", "run.pressure=1.0", "--set", "run.timestep=0.004", "--set", "run.threads=1"]
    return {
        "tip4p-t1": (water, "dcd", common + ["--set", "run.steps=" + n1, "--set", "run.equilibrate=40", "--set", "run.threads=1"]),
        "tip4p-t2": (water, "dcd", common + ["--set", "run.steps=" + n1, "--set", "run.equilibrate=40", "--set", "run.threads=2"]),
        "stockmayer-t1": (stock, "xyz", common + ["--set", "run.steps=" + n2, "--set", "run.threads=1",
                                                  "--set", "run.ensemble=nvt-bussi", "--set", "run.temperature=1.35"]),
        "stockmayer-t2": (stock, "xyz", common + ["--set", "run.steps=" + n2, "--set", "run.threads=2",
                                                  "--set", "run.ensemble=nvt-langevin", "--set", "run.temperature=1.35",
                                                  "--set", "run.tau=0.05"]),
        # the barostats (issue 34): the box, the barostat's random stream, trial sizes and counts
        # travel in the checkpoint; a kill anywhere must still continue bit for bit
        "stockmayer-mc": (stock, "xyz", common + npt + ["--set", "run.steps=" + n2, "--set", "run.barostat=mc",
                                                        "--set", "run.barostat_interval=2"]),
        "stockmayer-cr": (stock, "xyz", common + npt + ["--set", "run.steps=" + n2, "--set", "run.barostat=c-rescale",
                                                        "--set", "run.barostat_interval=2", "--set", "run.compressibility=0.1",
                                                        "--set", "run.barostat_coupling=semiisotropic"]),
    }


def run(cmd, timeout=600):
    return subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=timeout, text=True)


def clean(prefix):
    d, base = os.path.split(prefix)
    for f in os.listdir(d):
        if f.startswith(base + "."):
            os.remove(os.path.join(d, f))


def command(rotleap, deck, args, prefix):
    cmd = [rotleap, "run", deck] + args + ["--set", "output.prefix=" + prefix]
    if os.path.exists(prefix + ".chk"):
        cmd += ["--set", "system.start=" + prefix + ".chk"]
    return cmd


def count_syscalls(cmd, log):
    """How many times each syscall of SYSCALLS is made by cmd (strace -c is not per-process
    exact under -f; count from a trace)."""
    r = subprocess.run(["strace", "-f", "-qq", "-o", log, "-e", "trace=" + ",".join(SYSCALLS)] + cmd,
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=STRACE_ENV)
    counts = {s: 0 for s in SYSCALLS}
    with open(log) as f:
        for line in f:
            m = re.match(r"(?:\d+\s+)?(\w+)\(", line)
            if m and m.group(1) in counts:
                counts[m.group(1)] += 1
    return r.returncode, counts


def start_syscalls(cmd, log):
    """The syscalls a continuation makes before its first step, as (name, index) pairs: those
    before the first write to its thermo file after the header (strace -y names the files)."""
    subprocess.run(["strace", "-f", "-qq", "-y", "-o", log, "-e", "trace=" + ",".join(SYSCALLS)] + cmd,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=STRACE_ENV)
    seen = {s: 0 for s in SYSCALLS}
    out = []
    with open(log) as f:
        for line in f:
            m = re.match(r"(?:\d+\s+)?(\w+)\((.*)", line)
            if not m or m.group(1) not in seen:
                continue
            name = m.group(1)
            seen[name] += 1
            # the dynamic loader's and the C library's own files: nothing of the run's yet
            if name == "openat" and re.search(r'"(/lib|/usr/lib|/etc|/proc|/sys)', m.group(2)):
                continue
            # the first row of this invocation: a write of a line starting with a digit to the thermo file
            if name == "write" and "thermo.csv.part>" in m.group(2) and re.search(r', "\d', m.group(2)):
                break
            out.append((name, seen[name]))
    return out


def kill_at(cmd, syscall, n):
    return subprocess.run(["strace", "-f", "-qq", "-o", "/dev/null", "-e", "trace=" + syscall,
                           "-e", "inject=%s:signal=KILL:when=%d" % (syscall, n)] + cmd,
                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=STRACE_ENV).returncode


def kill_after(cmd, seconds):
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        p.wait(timeout=seconds)
    except subprocess.TimeoutExpired:
        p.send_signal(signal.SIGKILL)
        p.wait()
    return p.returncode


def finish(rotleap, deck, args, prefix):
    r = run(command(rotleap, deck, args, prefix))
    return r.returncode, r.stderr.strip()


def compare(ref, prefix, kind):
    bad = []
    for ext in FILES[kind]:
        a, b = ref + "." + ext, prefix + "." + ext
        if os.path.exists(a) != os.path.exists(b) or (os.path.exists(a) and not filecmp.cmp(a, b, shallow=False)):
            bad.append(ext)
    leftovers = [f for f in os.listdir(os.path.dirname(prefix)) if f.startswith(os.path.basename(prefix) + ".")
                 and f.endswith(".part")]
    return bad, leftovers


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("rotleap")
    ap.add_argument("src")
    ap.add_argument("work")
    ap.add_argument("--sequences", type=int, default=3)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--starts", action="store_true")
    ap.add_argument("--scenes", default="")
    ap.add_argument("--short", action="store_true", help="half the steps (CTest)")
    a = ap.parse_args()
    if shutil.which("strace") is None:
        print("kill_soak: strace is not installed (Debian strace)")
        return 77 if os.environ.get("CI") != "true" else 1
    rng = random.Random(a.seed)
    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    allsc = scenes(a.src, a.short)
    names = a.scenes.split(",") if a.scenes else list(allsc)
    total = ok = kills = 0
    for name in names:
        deck, kind, args = allsc[name]
        ref = os.path.join(a.work, name + "-ref")
        t0 = time.time()
        r = run(command(a.rotleap, deck, args, ref))
        if r.returncode:
            print("kill_soak: the reference run %s failed: %s" % (name, r.stderr))
            return 1
        wall = time.time() - t0
        code, counts = count_syscalls(command(a.rotleap, deck, args, os.path.join(a.work, name + "-count")),
                                      os.path.join(a.work, "count.log"))
        plans = []
        for _ in range(a.sequences):
            plan = []
            for _ in range(rng.randint(1, 3)):
                if rng.random() < 0.5:
                    plan.append(("time", rng.uniform(0.05, 1.1) * wall))
                else:
                    s = rng.choice([s for s in SYSCALLS if counts[s] > 0])
                    plan.append((s, rng.randint(1, counts[s])))
            plans.append(plan)
        if a.starts:
            # a run killed after its second checkpoint, then a continuation killed at each system
            # call of its start, then a continuation to the end
            pre = os.path.join(a.work, name + "-start")
            first = None
            for n in range(2, 40):  # the first rename after which the run has a checkpoint
                clean(pre)
                kill_at(command(a.rotleap, deck, args, pre), "rename", n)
                if os.path.exists(pre + ".chk"):
                    first = ("rename", n)
                    break
            if first:
                for sc in start_syscalls(command(a.rotleap, deck, args, pre), os.path.join(a.work, "start.log")):
                    plans.append([first, sc])
            # a run that completed half the steps, extended: its files are copied to .part first
            clean(pre)
            half = [x if not x.startswith("run.steps=") else "run.steps=%d" % (int(x.split("=")[1]) // 2) for x in args]
            run(command(a.rotleap, deck, half, pre))
            for sc in start_syscalls(command(a.rotleap, deck, args, pre), os.path.join(a.work, "start.log")):
                plans.append([("complete-half", 0), sc])
            clean(pre)
        for i, plan in enumerate(plans):
            prefix = os.path.join(a.work, "%s-%d" % (name, i))
            clean(prefix)
            for what, x in plan:
                cmd = command(a.rotleap, deck, args, prefix)
                if what == "complete-half":
                    half = [y if not y.startswith("run.steps=") else "run.steps=%d" % (int(y.split("=")[1]) // 2) for y in args]
                    run(command(a.rotleap, deck, half, prefix))
                    continue
                if what == "time":
                    kill_after(cmd, x)
                else:
                    kill_at(cmd, what, x)
                kills += 1
            code, err = finish(a.rotleap, deck, args, prefix)
            bad, left = compare(ref, prefix, kind) if code == 0 else (["exit %d: %s" % (code, err)], [])
            total += 1
            desc = " ".join("%s@%s" % (w, ("%.2fs" % x) if w == "time" else x) for w, x in plan)
            if bad or left:
                print("sequence %s-%d (%s): FAIL %s %s" % (name, i, desc, ",".join(bad), " ".join(left)))
            else:
                ok += 1
                print("sequence %s-%d (%s): ok" % (name, i, desc))
                clean(prefix)
    print("%d sequences, %d kills: %d identical to the run never killed, %d not" % (total, kills, ok, total - ok))
    return 0 if ok == total else 1


if __name__ == "__main__":
    sys.exit(main())
