"""Under CI (CI=true, as .ci/run sets it) a skipped test fails: conftest.py's hooks."""
import os
import shutil
import subprocess
import sys


def test_a_skip_fails_under_ci(tmp_path):
    shutil.copy(os.path.join(os.path.dirname(__file__), "conftest.py"), tmp_path)
    (tmp_path / "test_skips.py").write_text(
        "import pytest\n\ndef test_missing():\n    pytest.importorskip('no_such_module_rotleap')\n\n"
        "def test_fine():\n    pass\n")
    (tmp_path / "test_module_skips.py").write_text(
        "import pytest\npytest.importorskip('no_such_module_rotleap')\n\ndef test_never():\n    pass\n")
    args = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", str(tmp_path)]
    env = {k: v for k, v in os.environ.items() if k != "CI"}
    off = subprocess.run(args, cwd=tmp_path, env=env, capture_output=True, text=True)
    assert off.returncode == 0, off.stdout
    assert "1 passed, 2 skipped" in off.stdout
    on = subprocess.run(args, cwd=tmp_path, env=dict(env, CI="true"), capture_output=True, text=True)
    assert on.returncode != 0
    assert "1 failed, 1 passed, 1 error" in on.stdout, on.stdout
    assert "no_such_module_rotleap" in on.stdout and "under CI a skip is a failure" in on.stdout
