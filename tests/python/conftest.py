"""The binding's tests (pytest).  CTest runs them against the build tree (tests/python/run.sh sets
ROTLEAP_NATIVE, PYTHONPATH and ROTLEAP_CLI); run by hand, they test the installed package and
the `rotleap` on PATH."""
import os
import shutil
import subprocess

import pytest

SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


@pytest.fixture(scope="session")
def cli():
    exe = os.environ.get("ROTLEAP_CLI") or shutil.which("rotleap")
    if not exe:
        pytest.skip("no rotleap command (set ROTLEAP_CLI)")
    return os.path.abspath(exe)


def run_cli(cli, deck, cwd, *sets):
    args = [cli, "run", deck]
    for s in sets:
        args += ["--set", s]
    p = subprocess.run(args, cwd=cwd, capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return p


def example(name):
    return os.path.join(SRC, "examples", name)
