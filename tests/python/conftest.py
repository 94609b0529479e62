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


# a mixture deck: Stockmayer dipoles in an LJ solvent (issue 35's species), Bussi NVT
MIXTURE = """[system]
species = stockmayer:27 lj:81
density = 0.8
lattice = fcc
temperature = 1.35
seed = 3
[molecule lj]
units = lj
site = A 0 0 0 mass 1 sigma 1 epsilon 1
[interactions]
cutoff = 2.0
lj = shifted-force
dipole = sf
[run]
ensemble = nvt-bussi
temperature = 1.35
tau = 0.2
steps = 60
timestep = 0.002
[output]
thermo_every = 10
sample_every = 5
checkpoint_every = 30
progress = no
"""


def example(name):
    return os.path.join(SRC, "examples", name)


def cli_deck(name):
    """A deck or molecule file of the CLI tests (tests/cli)."""
    return os.path.join(SRC, "tests", "cli", name)


def _ci():
    return os.environ.get("CI") == "true"


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """Under CI (CI=true, as .ci/run sets it) a test that skips (a missing module such as
    openmm or mdtraj, or no rotleap command) fails instead, naming the reason."""
    outcome = yield
    rep = outcome.get_result()
    if _ci() and rep.skipped and not hasattr(rep, "wasxfail"):
        reason = rep.longrepr[2] if isinstance(rep.longrepr, tuple) else str(rep.longrepr)
        rep.outcome = "failed"
        rep.longrepr = "CI=true: this test would have been skipped (%s); under CI a skip is a failure" % reason


@pytest.hookimpl(tryfirst=True)
def pytest_collectreport(report):
    """The same for a whole module skipped when it is collected."""
    if _ci() and report.skipped:
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else str(report.longrepr)
        report.outcome = "failed"
        report.longrepr = "CI=true: this module would have been skipped (%s); under CI a skip is a failure" % reason
