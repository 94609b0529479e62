"""Shared by the Python reader tests of tests/io: the reference files test_io_dcd and test_io_xyz
write, and the module import that SKIPs (exit 77) when a reader is not installed, or FAILs when
the environment has CI=true (a CI machine must have every test dependency: scripts/deps.sh test)."""
import os
import sys


def need(module, package):
    """Import `module` or exit: 77 (CTest SKIP), or 1 under CI=true."""
    try:
        return __import__(module, fromlist=["*"])
    except ImportError as e:
        if os.environ.get("CI") == "true":
            print(f"FAIL: {module} not importable ({e}) and CI=true; install Debian's {package}")
            sys.exit(1)
        print(f"skip: {module} not importable ({e}); install Debian's {package}")
        sys.exit(77)


def read_traj_ref(path):
    """io_traj_ref.txt: header lines 'key values...', then per frame 'box a b c' and natoms lines of
    x y z (Angstrom), then 'pdb' and the PDB's box and coordinates."""
    import numpy as np
    lines = open(path).read().split("\n")
    head = {}
    i = 0
    while not lines[i].startswith("box"):
        k, *v = lines[i].split()
        head[k] = v
        i += 1
    natoms = int(head["natoms"][0])
    frames, boxes, pdb = [], [], None
    while i < len(lines) and lines[i]:
        if lines[i] == "pdb":
            i += 1
            pdb = True
            continue
        box = [float(x) for x in lines[i].split()[1:]]
        xyz = np.array([[float(x) for x in lines[i + 1 + a].split()] for a in range(natoms)])
        i += 1 + natoms
        if pdb:
            pdb = (box, xyz)
        else:
            frames.append(xyz)
            boxes.append(box)
    return head, np.array(frames), np.array(boxes), pdb


failed = 0


def check(name, ok, detail=""):
    global failed
    print(f"check {name:<58} {detail} {'ok' if ok else 'FAIL'}")
    if not ok:
        failed += 1


def finish():
    sys.exit(1 if failed else 0)
