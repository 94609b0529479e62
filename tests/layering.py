#!/usr/bin/env python3
"""The library's layering (issue 32): each folder may include only headers of its own layer or a
lower one, nothing in the library includes app/, and no header of core/ includes integrators/ or
models/.  From the bottom up:

  core/          the system and its cell, rotation geometry, errors, threads
  models/        molecule types and the catalogue
  io/            file formats
  forces/        force terms (forces/pair/: the pair term, its list and kernels)
  observables/   analysis of configurations (uses the sites' charges: above forces)
  integrators/   the leapfrog core, rotation paths (integrators/paths/), step operators
  run/           the run driver
  app/           the rotleap command (and python/, the binding, at the same level)

Public headers (include/rotleap/) belong to the layer that implements them.  Every
`#include "..."` of every .c and .h is resolved to a file and its layer; a violation prints the
file, the line and the two layers.  Exit status 0 when there is none.
  tests/layering.py SRCDIR"""
import os
import re
import sys

LAYERS = ["core", "models", "io", "forces", "observables", "integrators", "run", "app"]
PUBLIC = {  # include/rotleap/NAME.h -> the layer implementing it
    "error.h": "core", "units.h": "core", "system.h": "core", "geometry.h": "core",
    "molecule.h": "models", "catalog.h": "models", "io.h": "io",
    "forces.h": "forces", "forcefield.h": "forces", "terms.h": "forces", "ewald.h": "forces", "observables.h": "observables",
    "rotation.h": "integrators", "integrator.h": "integrators", "stepops.h": "integrators",
    "run.h": "run", "rotleap.h": "app",
}


def layer_of(path, src):
    rel = os.path.relpath(path, src)
    top = rel.split(os.sep)[0]
    if top == "include":
        return PUBLIC.get(os.path.basename(rel), "unknown public header %s" % rel)
    if top == "python":
        return "app"
    return top if top in LAYERS else None


def main():
    src = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
    bad = 0
    checked = 0
    for top in LAYERS + ["include"]:
        for root, _, files in os.walk(os.path.join(src, top)):
            for f in files:
                if not f.endswith((".c", ".h")):
                    continue
                path = os.path.join(root, f)
                mine = layer_of(path, src)
                for n, line in enumerate(open(path, errors="replace"), 1):
                    m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
                    if not m:
                        continue
                    inc = m.group(1)
                    cand = [os.path.normpath(os.path.join(root, inc)), os.path.join(src, "include", inc)]
                    target = next((c for c in cand if os.path.exists(c)), None)
                    if target is None:
                        print("%s:%d: #include \"%s\" does not resolve to a file of the tree" % (os.path.relpath(path, src), n, inc))
                        bad += 1
                        continue
                    theirs = layer_of(target, src)
                    checked += 1
                    if theirs not in LAYERS or mine not in LAYERS:
                        print("%s:%d: %s: %s" % (os.path.relpath(path, src), n, inc, theirs if theirs not in LAYERS else mine))
                        bad += 1
                    elif LAYERS.index(theirs) > LAYERS.index(mine):
                        print("%s:%d: %s (%s) includes %s (%s), a higher layer" % (os.path.relpath(path, src), n, mine, f, inc, theirs))
                        bad += 1
    print("layering: %d includes checked, %d violations" % (checked, bad))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
