#!/usr/bin/env python3
"""test_io_ase: ASE (Debian python3-ase) reads rotleap's extended XYZ, orientations included
(issue 31 item 5).

usage: ase_read.py TRAJ.xyz REF.txt
REF.txt (written by test_io_xyz): per frame 'frame STEP TIME LX LY LZ' and one line per body
'NAME x y z ox oy oz' (%.17g).  Checks per frame: count, cell and pbc, Step/Time, positions
(printed with 10 decimals: |error| <= 5e-11), the orientation column bit for bit (%.17g) and the
species names (column name; species is ASE's dummy element X).  Exit 77 (SKIP) without ASE;
under CI=true exit 1."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from io_ref import check, finish, need  # noqa: E402

np = need("numpy", "python3-numpy")
ase_io = need("ase.io", "python3-ase")
ase = need("ase", "python3-ase")

xyz, ref = sys.argv[1:3]
frames = []
for line in open(ref):
    w = line.split()
    if w[0] == "frame":
        frames.append({"step": int(w[1]), "time": float(w[2]), "box": [float(x) for x in w[3:6]],
                       "names": [], "x": [], "o": []})
    else:
        frames[-1]["names"].append(w[0])
        frames[-1]["x"].append([float(x) for x in w[1:4]])
        frames[-1]["o"].append([float(x) for x in w[4:7]])
got = ase_io.read(xyz, index=":", format="extxyz")
print(f"info  ASE {ase.__version__}: {len(got)} frames of {len(got[0])} bodies")
check("ASE reads every frame", len(got) == len(frames), f"{len(got)}")
for k, (a, f) in enumerate(zip(got, frames)):
    n = len(f["names"])
    check(f"frame {k}: body count", len(a) == n, f"{len(a)}")
    check(f"frame {k}: cell (orthorhombic) and pbc",
          np.allclose(a.cell.array, np.diag(f["box"]), rtol=0, atol=5e-11) and bool(np.all(a.pbc)))
    check(f"frame {k}: Step and Time", a.info.get("Step") == f["step"] and a.info.get("Time") == f["time"],
          f"{a.info.get('Step')} {a.info.get('Time')}")
    err = float(np.max(np.abs(a.positions - np.array(f["x"]))))
    check(f"frame {k}: positions, 10 decimals", err <= 5e-11, f"max err {err:.1e}")
    o = a.arrays.get("orientation")
    check(f"frame {k}: orientation column bit for bit", o is not None and np.array_equal(o, np.array(f["o"])))
    names = a.arrays.get("name")
    check(f"frame {k}: species names (column name)", names is not None and list(names) == f["names"],
          " ".join(sorted(set(f["names"]))))
    check(f"frame {k}: species column is ASE's dummy element X", set(a.get_chemical_symbols()) == {"X"})
finish()
