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
    rows = (tmp_path / "out-stockmayer.thermo.csv").read_text().splitlines()
    assert rows[0].startswith("step,time,total,potential") and rows[-1].startswith("1000,")
