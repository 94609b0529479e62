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
