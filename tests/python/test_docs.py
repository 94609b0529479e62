"""docs/python.md's tutorial runs as written (in a scratch directory holding examples/)."""
import os
import re
import shutil

from conftest import SRC


def test_tutorial(tmp_path, capsys):
    text = open(os.path.join(SRC, "docs", "python.md")).read()
    part = text[text.index("## Tutorial"):]
    code = re.search(r"```python\n(.*?)```", part, re.S).group(1)
    shutil.copytree(os.path.join(SRC, "examples"), tmp_path / "examples")
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        exec(compile(code, "docs/python.md", "exec"), {})
    finally:
        os.chdir(cwd)
    out = capsys.readouterr().out
    assert "U/N =" in out and "fallbacks: 0" in out
    eps = float(re.search(r"eps = (\S+)", out).group(1))
    assert 1 < eps < 1e3
    try:
        import matplotlib  # noqa: F401
        assert (tmp_path / "stockmayer-energy.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    except ImportError:
        pass
    rows = (tmp_path / "out-stockmayer.thermo.csv").read_text().splitlines()
    assert rows[0].startswith("step,time,total,potential") and rows[-1].startswith("1000,")


def test_api_reference_is_up_to_date():
    """docs/python-api.md is what scripts/gen_pydoc.py makes of the docstrings."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("gen_pydoc", os.path.join(SRC, "scripts", "gen_pydoc.py"))
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    text = open(os.path.join(SRC, "docs", "python-api.md")).read()
    assert text == gen.generate(), "docs/python-api.md is out of date: run scripts/gen_pydoc.py"
