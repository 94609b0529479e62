#!/usr/bin/env python3
"""test_io_mdtraj: MDTraj (Debian python3-mdtraj) reads rotleap's DCD with its PDB topology.

usage: mdtraj_read.py TRAJ.dcd TOP.pdb REF.txt
REF.txt (written by test_io_dcd) holds what was written, in Angstrom at full precision.  MDTraj
works in nm.  Checks, one line each: frame and atom counts, residues, atom names, unit cell
lengths and angles, coordinates (float32 in the DCD: |error| <= 1e-5 A for |x| < 30 A), and the
PDB's own coordinates (3 decimals: |error| <= 5e-4 A).  Exit 77 (CTest SKIP) without MDTraj;
under CI=true exit 1 instead.  MDTraj's load_dcd ignores the header's time step (its time is
the frame index): mdanalysis_read.py checks that."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from io_ref import check, finish, need, read_traj_ref  # noqa: E402

np = need("numpy", "python3-numpy")
md = need("mdtraj", "python3-mdtraj")

dcd, pdb, ref = sys.argv[1:4]
head, frames, boxes, (pdb_box, pdb_xyz) = read_traj_ref(ref)
t = md.load_dcd(dcd, top=pdb)
print(f"info  MDTraj {md.version.version}: {t}")
check("MDTraj n_frames", t.n_frames == int(head["nframes"][0]), f"{t.n_frames}")
check("MDTraj n_atoms", t.n_atoms == int(head["natoms"][0]), f"{t.n_atoms}")
check("MDTraj n_residues (one per molecule)", t.topology.n_residues == int(head["nresidues"][0]),
      f"{t.topology.n_residues}")
names = [a.name for a in t.topology.residue(0).atoms] + [t.topology.atom(t.n_atoms - 1).name]
check("atom names of residue 1 and the last atom", names == head["names"], " ".join(names))
err = float(np.max(np.abs(t.unitcell_lengths * 10.0 - boxes)))
check("unit cell lengths (A) per frame (float32 in MDTraj)", err < 1e-5, f"max err {err:.2e}")
check("unit cell angles 90", bool(np.all(np.abs(t.unitcell_angles - 90.0) < 1e-9)))
err = float(np.max(np.abs(t.xyz * 10.0 - frames)))
check("DCD coordinates (A) vs written, float32", err < 1e-5, f"max err {err:.2e}")
p = md.load_pdb(pdb)
err = float(np.max(np.abs(p.xyz[0] * 10.0 - pdb_xyz)))
check("PDB coordinates (A) vs written, 3 decimals", err <= 5.0001e-4, f"max err {err:.2e}")
err = float(np.max(np.abs(p.unitcell_lengths[0] * 10.0 - pdb_box)))
check("PDB CRYST1 box (A)", err < 1e-3, f"max err {err:.2e}")
finish()
