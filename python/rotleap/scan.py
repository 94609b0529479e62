"""rotleap.scan: `rotleap scan` (the speed-accuracy trade of a deck over time steps and
integrators) with its table as numpy arrays."""
import csv
import ctypes
import os
import sys
import tempfile

import numpy as np

from ._native import lib

__all__ = ["scan", "ScanResult"]


class ScanResult:
    """What scan() returns: `table` {column: array} (PREFIX.scan.csv: one row per run, numbers
    as float64 arrays, text columns as str arrays; docs/performance.md and `rotleap scan --help`
    describe the columns), `curve` {column: array} (PREFIX.scan_calE.csv: calE against the run's
    length), and `text` (the table `rotleap scan` prints)."""

    def __init__(self, table, curve, text):
        self.table, self.curve, self.text = table, curve, text

    def __len__(self):
        return len(next(iter(self.table.values()))) if self.table else 0

    def __repr__(self):
        return "<rotleap.ScanResult: %d runs, columns %s>" % (len(self), ", ".join(self.table))


def _columns(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    head, body = rows[0], rows[1:]
    out = {}
    for j, name in enumerate(head):
        col = [r[j] if j < len(r) else "" for r in body]
        try:
            out[name] = np.array([float(x) if x not in ("", "n/a") else np.nan for x in col])
        except ValueError:
            out[name] = np.array(col, dtype=str)
    return out


def _capture(fd):
    """Redirect file descriptor fd into a temporary file; returns (saved fd, file)."""
    tmp = tempfile.TemporaryFile(mode="w+b")
    saved = os.dup(fd)
    os.dup2(tmp.fileno(), fd)
    return saved, tmp


def _restore(fd, saved, tmp):
    os.dup2(saved, fd)
    os.close(saved)
    tmp.seek(0)
    text = tmp.read().decode("utf-8", "replace")
    tmp.close()
    return text


def scan(deck, *, timesteps=None, integrators=None, steps=None, time=None, tolerance=None, analysis=False,
         set=None):
    """Run `rotleap scan DECK` (no plots) and return its table as arrays (a ScanResult).

    timesteps: "0.5,1,2 fs" or a list of numbers (as --timesteps takes bare numbers);
    integrators: "rl,rl-exact" or a list of names; steps (the same number per run) or time (the
    same simulated time, e.g. "0.4 ps"); tolerance (calE/calU, e.g. "1%"); analysis: each run's
    results, RDFs and TCFs too; set: deck overrides {"section.key": value}.  The files go to a
    temporary directory unless set gives output.prefix.  Its messages and table are captured (the
    table is ScanResult.text); a failure raises rotleap.Error with the messages."""
    from .simulation import Error
    args = [os.fspath(deck), "--no-plot"]
    if timesteps is not None:
        if not isinstance(timesteps, str):
            timesteps = ",".join(repr(float(h)) for h in timesteps)
        args += ["--timesteps", timesteps]
    if integrators is not None:
        args += ["--integrators", integrators if isinstance(integrators, str) else ",".join(integrators)]
    if steps is not None:
        args += ["--steps", str(int(steps))]
    if time is not None:
        args += ["--time", str(time)]
    if tolerance is not None:
        args += ["--tolerance", str(tolerance)]
    if analysis:
        args.append("--analysis")
    sets = dict(set or {})
    tmp = None
    if "output.prefix" not in sets:
        tmp = tempfile.TemporaryDirectory(prefix="rotleap-scan-")
        sets["output.prefix"] = os.path.join(tmp.name, "scan")
    for k, v in sets.items():
        args += ["--set", "%s=%s" % (k, v)]
    prefix = str(sets["output.prefix"])
    try:
        argv = (ctypes.c_char_p * len(args))(*[a.encode() for a in args])
        sys.stdout.flush()
        sys.stderr.flush()
        out = _capture(1)
        err = _capture(2)
        try:
            st = lib.rlpy_scan(len(args), argv)
        finally:
            err_text = _restore(2, *err)
            out_text = _restore(1, *out)
        if st:
            raise Error(err_text.strip() or "rotleap scan failed (status %d)" % st)
        return ScanResult(_columns(prefix + ".scan.csv"), _columns(prefix + ".scan_calE.csv"), out_text)
    finally:
        if tmp:
            tmp.cleanup()
