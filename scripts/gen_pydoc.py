#!/usr/bin/env python3
"""docs/python-api.md: the API reference of the rotleap Python package, generated from its
docstrings with inspect (every public name of rotleap.__all__, its signature and docstring, and
those of its public methods and properties).

  scripts/gen_pydoc.py            rewrite docs/python-api.md
  scripts/gen_pydoc.py --check    exit 1 if docs/python-api.md is not what the docstrings give

(with the package importable: installed, or PYTHONPATH=python ROTLEAP_NATIVE=build/_rotleap_native.so);
tests/python/test_docs.py checks that the checked-in file is up to date."""
import inspect
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "docs", "python-api.md")


def doc(obj):
    d = inspect.getdoc(obj)
    return d.strip() + "\n" if d else "(no docstring)\n"


def signature(obj):
    try:
        return str(inspect.signature(obj))
    except (TypeError, ValueError):
        return "(...)"


def members(cls):
    out = []
    for name, value in cls.__dict__.items():
        if name.startswith("_") and name not in ("__init__",):
            continue
        if name == "__init__":
            continue
        if isinstance(value, property):
            out.append("- `%s` (property%s): %s" % (name, "" if value.fset is None else ", settable",
                                                   " ".join(doc(value).split())))
        elif isinstance(value, (classmethod, staticmethod)):
            f = value.__func__
            sig = signature(f).replace("(cls, ", "(")
            out.append("- `%s%s` (%s): %s" % (name, sig, type(value).__name__, " ".join(doc(f).split())))
        elif inspect.isfunction(value):
            sig = signature(value).replace("(self, ", "(").replace("(self)", "()")
            out.append("- `%s%s`: %s" % (name, sig, " ".join(doc(value).split())))
    return out


def generate():
    import rotleap
    lines = ["# rotleap Python API reference", "",
             "Generated from the docstrings by `scripts/gen_pydoc.py` (do not edit: edit the docstrings and run",
             "it; `tests/python/test_docs.py` fails when this file is out of date).  docs/python.md is the guide.",
             "", "## Module `rotleap`", "", doc(rotleap)]
    for name in rotleap.__all__:
        obj = getattr(rotleap, name)
        if inspect.isclass(obj):
            lines += ["## class `rotleap.%s%s`" % (name, signature(obj)), "", doc(obj)]
            m = members(obj)
            if m:
                lines += m + [""]
        elif callable(obj):
            lines += ["## `rotleap.%s%s`" % (name, signature(obj)), "", doc(obj)]
    return "\n".join(lines).rstrip("\n") + "\n"


def main():
    text = generate()
    if "--check" in sys.argv[1:]:
        old = open(OUT).read() if os.path.exists(OUT) else ""
        if old != text:
            print("docs/python-api.md is out of date: run scripts/gen_pydoc.py", file=sys.stderr)
            return 1
        return 0
    with open(OUT, "w") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
