"""Readers for rotleap's text outputs, and the CPU choice for pinned timings, shared by the bench
scripts (standard library only)."""
import os
import time


def keyvals(path):
    """PREFIX.summary.txt or PREFIX.results.txt -> {key: value text}."""
    out = {}
    with open(path) as f:
        for line in f:
            if "=" in line and not line.startswith("#"):
                k, v = line.split("=", 1)
                out[k.strip()] = v.strip()
    return out


def cpu_model():
    """The CPU's model name (Linux /proc/cpuinfo), for the benchmark tables: rotleap's pair rows
    differ by instruction set (ffbench's rows=: avx512, avx2 or portable)."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def tokens(text):
    """'model=tip4p N=216 ms_per_step=1.5 ...' lines (bench/ffbench's output) -> {key: value text}."""
    kv = {}
    for line in text.splitlines():
        for tok in line.split():
            if "=" in tok:
                k, v = tok.split("=", 1)
                kv[k] = v
    return kv


def idlest_cpu(seconds=1.0):
    """The CPU (of those this process may use) with the most idle time over `seconds` (/proc/stat)."""
    allowed = sorted(os.sched_getaffinity(0))

    def idle():
        out = {}
        for ln in open("/proc/stat"):
            f = ln.split()
            if f[0].startswith("cpu") and f[0] != "cpu":
                out[int(f[0][3:])] = int(f[4]) + int(f[5])  # idle + iowait
        return out
    a = idle()
    time.sleep(seconds)
    b = idle()
    return max(allowed, key=lambda c: b.get(c, 0) - a.get(c, 0))


def pin_row(threads, pin, allowed):
    """Pin this process (and so its children and OpenMM's worker threads) for a one-thread row:
    pin = "auto" (the idlest CPU now), a CPU number, or "none"; other rows get `allowed` back.
    Returns the CPU pinned to, or None."""
    if threads == 1 and pin != "none":
        cpu = idlest_cpu() if pin == "auto" else int(pin)
        os.sched_setaffinity(0, {cpu})
        return cpu
    os.sched_setaffinity(0, allowed)
    return None
