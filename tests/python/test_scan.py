"""rotleap.scan: the table of `rotleap scan` as numpy arrays, the same numbers as the command's."""
import csv
import os
import subprocess

import numpy as np
import pytest

import rotleap
from conftest import SRC

DECK = os.path.join(SRC, "tests", "cli", "water_scan.ini")
ARGS = dict(timesteps="1,2 fs", integrators="rl,rl-exact", steps=20)


def test_scan_table_as_arrays(cli, tmp_path):
    r = rotleap.scan(DECK, **ARGS)
    assert len(r) == 4 and "rotleap scan of" in r.text
    assert r.table["calE"].dtype == np.float64 and np.isfinite(r.table["calE"]).all()
    assert list(r.table["integrator"]) == ["rl", "rl", "rl-exact", "rl-exact"]
    assert list(r.table["h_fs"]) == [1.0, 2.0, 1.0, 2.0]
    assert set(r.curve) >= {"integrator", "h_fs", "step", "calE"}
    p = subprocess.run([cli, "scan", DECK, "--timesteps", "1,2", "fs", "--integrators", "rl,rl-exact", "--steps", "20",
                        "--no-plot", "--set", "output.prefix=%s/cli" % tmp_path], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    with open(tmp_path / "cli.scan.csv") as f:
        rows = list(csv.DictReader(f))
    for name, col in r.table.items():
        if name in ("wall_s_per_step", "ns_per_day"):  # timings
            continue
        want = [row[name] for row in rows]
        if col.dtype.kind == "f":
            want = [float(x) if x not in ("", "n/a") else np.nan for x in want]
            assert np.array_equal(col, np.array(want), equal_nan=True), name
        else:
            assert list(col) == want, name


def test_scan_errors():
    with pytest.raises(rotleap.Error, match="unknown integrator 'nope'"):
        rotleap.scan(DECK, integrators="nope")
    with pytest.raises(rotleap.Error, match="not both"):
        rotleap.scan(DECK, steps=10, time="1 ps")
