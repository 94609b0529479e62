#!/usr/bin/env python3
"""The pair term's kernel tree is what docs/interactions.md ("Kernels: the files") says it is.

  tests/forces/kernel_tree.py SOURCE_DIR

Every row file forces/pair/kernels/<instruction set>/<pattern>_<vdw>_<elec>.c
  - sits in a folder of an instruction set (portable, avx512, avx2, avx2_mixed) and has a name of
    a known pattern (sites, tip4p, dipole), vdw (lj) and an electrostatics of kernels/elec/;
  - includes ../elec/<elec>.h (the electrostatics its name says) and no other electrostatics;
  - defines the row set rl_rows_<instruction set>_<pattern>_<vdw>_<elec> and nothing else
    (no code of its own: no braces);
  - is listed in forces/pair/pair.cmake, declared in kernels/kernel.h and named in the table of
    docs/interactions.md;
and every row file that table names exists.  Prints one line per check; exit status 1 on any
failure."""
import os
import re
import sys

ISAS = ["portable", "avx512", "avx2", "avx2_mixed"]
PATTERNS = ["sites", "tip4p", "dipole"]
VDWS = ["lj"]


def main(src):
    pair = os.path.join(src, "forces", "pair")
    kern = os.path.join(pair, "kernels")
    elecs = sorted(f[:-2] for f in os.listdir(os.path.join(kern, "elec")) if f.endswith(".h") and f != "elec.h")
    cmake = open(os.path.join(pair, "pair.cmake")).read()
    kernel_h = open(os.path.join(kern, "kernel.h")).read()
    doc = open(os.path.join(src, "docs", "interactions.md")).read()
    m = re.search(r"^## Kernels: the files.*?(?=^## )", doc, re.S | re.M)
    section = m.group(0) if m else ""
    fails = 0

    def check(what, ok):
        nonlocal fails
        print("%s: %s" % ("ok  " if ok else "FAIL", what))
        fails += not ok

    check("docs/interactions.md has the section \"Kernels: the files\"", bool(section))
    check("kernels/elec/ holds electrostatics (%s)" % ", ".join(elecs), len(elecs) >= 2)
    files = []
    for isa in sorted(os.listdir(kern)):
        d = os.path.join(kern, isa)
        if not os.path.isdir(d) or isa == "elec":
            continue
        check("kernels/%s/ is an instruction set's folder" % isa, isa in ISAS)
        for f in sorted(os.listdir(d)):
            if f.endswith(".c"):
                files.append((isa, f))
    check("there are row files", len(files) > 0)
    for isa, f in files:
        rel = "kernels/%s/%s" % (isa, f)
        parts = f[:-2].split("_")
        ok_name = len(parts) == 3 and parts[0] in PATTERNS and parts[1] in VDWS and parts[2] in elecs
        check("%s is named <pattern>_<vdw>_<elec>" % rel, ok_name)
        if not ok_name:
            continue
        text = open(os.path.join(kern, isa, f)).read()
        code = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
        inc = re.findall(r'#include\s+"\.\./elec/(\w+)\.h"', code)
        check("%s includes ../elec/%s.h and no other electrostatics" % (rel, parts[2]), inc == [parts[2]])
        setname = "rl_rows_%s_%s" % (isa, f[:-2])
        defs = re.findall(r"\b(rl_rows_\w+)\b", code)
        check("%s defines the row set %s only" % (rel, setname), defs == [setname])
        check("%s holds no code of its own" % rel, "{" not in code)
        check("%s is listed in pair.cmake" % rel, "kernels/%s/%s" % (isa, f) in cmake)
        check("%s is declared in kernels/kernel.h" % rel, re.search(r"\b%s\b" % setname, kernel_h) is not None)
        row = re.search(r"^\| `kernels/%s/`: ([^|]*)\|" % isa, section, re.M)
        check("%s is in the table of docs/interactions.md" % rel, row is not None and "`%s`" % f in row.group(1))
    for isa, names in re.findall(r"^\| `kernels/(\w+)/`: ([^|]*)\|", section, re.M):
        for f in re.findall(r"`([\w.]+\.c)`", names):
            check("docs name kernels/%s/%s, which exists" % (isa, f), (isa, f) in files)
    print("%d failure(s)" % fails)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "."))
