#!/usr/bin/env python3
"""test_io_mdanalysis: MDAnalysis (Debian python3-mdanalysis) reads rotleap's DCD with its PDB
topology, including the time axis (issue 31 item 5).

usage: mdanalysis_read.py TRAJ.dcd TOP.pdb REF.txt
REF.txt (written by test_io_dcd): coordinates and boxes in Angstrom, the time step in ps, the
frame interval and the first frame's step.  MDAnalysis reads DELTA in AKMA units (CHARMM/NAMD):
u.trajectory.dt must be interval x time step in ps, and frame k's time (first_step + k interval)
x time step, to float32 precision.  Exit 77 (SKIP) without MDAnalysis; under CI=true exit 1."""
import os
import sys
import warnings

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from io_ref import check, finish, need, read_traj_ref  # noqa: E402

np = need("numpy", "python3-numpy")
with warnings.catch_warnings():
    warnings.simplefilter("ignore")  # MDAnalysis 2.4 imports the deprecated xdrlib
    mda = need("MDAnalysis", "python3-mdanalysis")

dcd, pdb, ref = sys.argv[1:4]
head, frames, boxes, _ = read_traj_ref(ref)
h, every, first = float(head["timestep_ps"][0]), int(head["interval"][0]), int(head["first_step"][0])
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    u = mda.Universe(pdb, dcd)
tr = u.trajectory
print(f"info  MDAnalysis {mda.__version__}: {tr.n_frames} frames, {u.atoms.n_atoms} atoms, dt = {tr.dt!r} ps")
check("MDAnalysis n_frames", tr.n_frames == int(head["nframes"][0]), f"{tr.n_frames}")
check("MDAnalysis n_atoms", u.atoms.n_atoms == int(head["natoms"][0]), f"{u.atoms.n_atoms}")
want = every * h
check("u.trajectory.dt = interval x time step (ps)", abs(tr.dt - want) <= 1e-6 * want, f"{tr.dt:.9g} vs {want:.9g}")
times = np.array([ts.time for ts in tr])
want_t = (first + every * np.arange(tr.n_frames)) * h
err = float(np.max(np.abs(times - want_t) / want_t))
check("frame times = (first_step + k interval) x time step (ps)", err <= 1e-6,
      f"{times[0]:.6g}..{times[-1]:.6g} ps, rel err {err:.1e}")
xyz = np.array([ts.positions.copy() for ts in tr])
err = float(np.max(np.abs(xyz - frames)))
check("DCD coordinates (A) vs written, float32", err < 1e-5, f"max err {err:.2e}")
dims = np.array([ts.dimensions.copy() for ts in tr])
err = float(np.max(np.abs(dims[:, :3] - boxes)))
check("unit cell lengths (A) and angles 90", err < 1e-5 and bool(np.all(np.abs(dims[:, 3:] - 90) < 1e-9)),
      f"max err {err:.2e}")
finish()
