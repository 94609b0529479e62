/* rotleap — files: trajectories (DCD + PDB topology, extended XYZ), starting states (PDB, extended
 * XYZ) and checkpoints.  docs/files.md describes every format.
 *
 * Conventions shared by every function here:
 *  - Library code: nothing is printed, nothing exits.  Failures return an RL_E* status with a
 *    message (rl_last_error()) naming the file and, for text files, the line; for binary files,
 *    the record or byte offset.
 *  - Lengths in files: a `real` system (nm) is written in Angstrom (x 10) in DCD, PDB and
 *    extended XYZ, as MDTraj, VMD and OVITO expect; an `lj` system is written in sigma units as
 *    they are (no conversion).  Readers convert back.
 *  - Atoms: every body contributes its interaction sites (bodies in order, sites in species
 *    order); a body whose species has no sites contributes one atom at its centre.  Positions are
 *    written as the system holds them (molecules whole, not wrapped into the box).
 *  - Site names come from the rl_molecule of each species (`mols[species]`, the array may be NULL
 *    and entries may be NULL: the names are then "S1", "S2", ...).  A massless site called "M"
 *    (TIP4P's charge site) is written "MW" (the GROMACS/CHARMM name).
 *  - Files written whole (PDB, extended XYZ snapshots, checkpoints) are written atomically:
 *    NAME.tmp.<pid>, fsync, rename over NAME, fsync of the directory.  A crash leaves either the
 *    old or the new file, never a partial one. */
#ifndef ROTLEAP_IO_H
#define ROTLEAP_IO_H

#include <stddef.h>
#include <stdio.h>

#include "rotleap/molecule.h"
#include "rotleap/system.h"

#ifdef __cplusplus
extern "C" {
#endif

/* --------------------------------------------------------------------- atomic whole files */

typedef struct {
  FILE *fp;          /* write here                                              */
  char *path;        /* final name                                              */
  char *tmp;         /* NAME.tmp.<pid>                                          */
} rl_atomic_file;

/* Open NAME.tmp.<pid> for writing ("wb").  On success a->fp is the stream. */
int rl_atomic_open(rl_atomic_file *a, const char *path);
/* Flush, fsync, close, rename over the final name, fsync the directory.  On any failure the
 * temporary file is removed and the previous NAME is untouched.  Frees a's strings. */
int rl_atomic_commit(rl_atomic_file *a);
/* Close and remove the temporary file (accepts a never-opened, zeroed a). */
void rl_atomic_abort(rl_atomic_file *a);

/* Number of atoms the trajectory/topology writers emit for sys (see "Atoms" above). */
int rl_io_natoms(const rl_system *sys);
/* Factor from system lengths to file lengths: 10 (nm -> Angstrom) for real, 1 for lj. */
double rl_io_length_scale(const rl_system *sys);

/* ------------------------------------------------------------------------------ DCD */

/* CHARMM/NAMD DCD, little-endian, 32-bit Fortran record markers, CHARMM version 24 flag, with a
 * unit-cell record per frame (a, b, c in file length units, angles 90 degrees), float32
 * coordinates.  The frame count (NSET) in the header is updated after every frame, so a file cut
 * short by a crash stays readable up to its last complete frame. */
typedef struct rl_dcd rl_dcd;

/* Create (truncate) a DCD for sys's atoms.  first_step: step of the first frame; interval: steps
 * between frames; dt: time step (system time unit; stored in the header as float32, AKMA units
 * are not converted: readers use only NSET/NATOM/cell/coordinates).  title may be NULL. */
rl_dcd *rl_dcd_create(const char *path, const rl_system *sys, long first_step, long interval,
                      double dt, const char *title);
/* Reopen an existing DCD for appending after a restart: checks NATOM against sys, keeps the first
 * `keep_frames` frames (fewer present is an error) and discards the rest. */
rl_dcd *rl_dcd_append(const char *path, const rl_system *sys, long keep_frames);
/* Of an existing DCD: the step of its first frame (ISTART), the steps between frames (NSAVC) and
 * the number of complete frames in the file.  Any pointer may be NULL. */
int rl_dcd_info(const char *path, long *first_step, long *interval, long *frames);
/* Append one frame.  box: orthorhombic edge lengths in system units (NULL: no box, zeros). */
int rl_dcd_write_frame(rl_dcd *d, const rl_system *sys, const double box[3]);
long rl_dcd_frames(const rl_dcd *d);
/* Flush and close; returns the first error met while writing, if any.  Accepts NULL. */
int rl_dcd_close(rl_dcd *d);

/* ------------------------------------------------------------------------------ PDB */

/* PDB of the current state: CRYST1 (box in file units, 90 degrees; omitted if box is NULL), one
 * residue per body (residue name: the first three characters of the species name, upper case;
 * chain A, residue numbers modulo 10000), one ATOM record per atom with name from the site names,
 * element from the name's leading letters for massive sites of real-unit systems, TER and END.
 * Coordinates %8.3f: PDB resolves 1e-3 file units (1e-4 nm for real systems).  Used as the DCD
 * topology and as a final structure.  Written atomically.  More than 99999 atoms: serials wrap
 * (as in GROMACS/MDTraj output). */
int rl_pdb_write(const char *path, const rl_system *sys, const rl_molecule *const *mols,
                 const double box[3]);

/* Count residues (molecules) in a PDB, and optionally read its CRYST1 box (system units for the
 * given unit system; zeros if none). */
int rl_pdb_count(const char *path, rl_units units, int *nres, double box[3]);

/* Set positions and orientations of sys (species and counts already defined) from a PDB: ATOM/
 * HETATM records grouped into residues by (chain, residue number, residue name) in file order;
 * residue k is body k and must have as many atoms as its species has sites (one atom for a
 * site-less species).  If mols[species] is given, atom names must match the site names (MW
 * accepted for M).  Each molecule's centre and rotation come from a least-squares (Kabsch, via
 * Horn's quaternion) fit of the species' body-frame sites to the atoms, after making the residue
 * whole with the CRYST1 box if present.  A fit with RMS deviation above tol (system length units;
 * tol <= 0 selects 0.01 file units = 10x the PDB resolution) is an error naming the residue and
 * its first line.  Axis kinds take the fitted body Z axis; single-site bodies keep their
 * orientation.  Velocities and angular momenta are not touched.  rms_max (may be NULL) receives
 * the largest RMS fit error (system units); box (may be NULL) the CRYST1 box. */
int rl_pdb_read_state(const char *path, rl_system *sys, const rl_molecule *const *mols, double tol,
                      double *rms_max, double box[3]);

/* ---------------------------------------------------------------------- extended XYZ */

/* One frame of extended XYZ: N (bodies), then
 *   Lattice="Lx 0 0 0 Ly 0 0 0 Lz" Properties=species:S:1:pos:R:3:orientation:R:3 Time=t Step=s pbc="T T T"
 * and one line per body: species name, centre (file units, %.10f), body Z axis in the lab
 * (rl_system_get_axis; 0 0 0 for point bodies), %.17g so that a read gives the same unit vector.
 * Lattice and pbc are omitted if box is NULL.  fp: an open stream (a trajectory appends frames).
 * path is used in messages only. */
int rl_xyz_write_frame(FILE *fp, const char *path, const rl_system *sys, const double box[3],
                       double time, long step);
/* One-frame file, written atomically. */
int rl_xyz_write(const char *path, const rl_system *sys, const double box[3], double time, long step);

/* Read the first frame of an extended XYZ into sys (species and counts defined): the count must
 * equal the bodies; line k is body k; its species label must equal the species name (if the
 * species has a name).  Columns are located from Properties= (pos:R:3 required; the orientation
 * column may be called orientation, dipoles, axis or rho, and is required for dipole and linear
 * bodies; without Properties= the columns are species x y z [ox oy oz]).  The orientation is
 * normalised (|o| must be 1 within 1e-6; else an error with the line) and set with
 * rl_system_set_axis (for matrix kinds this sets a frame whose Z axis is o).  box (may be NULL)
 * receives the Lattice diagonal in system units (zeros if absent; a non-orthorhombic lattice is
 * an error). */
int rl_xyz_read_state(const char *path, rl_system *sys, double box[3]);
/* Number of bodies announced by the first line. */
int rl_xyz_count(const char *path, int *n);

/* ------------------------------------------------------------------------- checkpoints */

#define RL_CHECKPOINT_VERSION 1

/* Run data stored with the state.  The blob is opaque to the library (the run driver stores its
 * thermostat/RNG state and accumulators there). */
typedef struct {
  double time;       /* simulation time                                       */
  long step;         /* step count                                            */
  double box[3];     /* orthorhombic box, system length units                 */
  const void *blob;  /* write: caller bytes (may be NULL if blob_size = 0)    */
  size_t blob_size;
} rl_checkpoint_meta;

/* Write a checkpoint atomically: magic "RLCHKPT\0", format version, payload length, payload
 * (units, removed DOF, time, step, box, species table: name, kind, mass, moments, sites, count;
 * the state arrays exactly as stored: r, v, l, A, rho; the blob), CRC-32 (the zlib/IEEE 802.3
 * polynomial) of everything before it.  All numbers little-endian; doubles bit-exact. */
int rl_checkpoint_write(const char *path, const rl_system *sys, const rl_checkpoint_meta *meta);

/* Read a checkpoint into sys, whose units and species table (names, kinds, masses, moments and
 * sites to 1e-12 relative, counts) must match the file's: a difference is an error naming the
 * species and the field.  Checks magic, version, length (a truncated file is an error with the
 * expected and actual sizes) and CRC before touching sys; on success r, v, l, A, rho are restored
 * bit for bit, and the removed DOF.  meta receives time, step, box and a malloc'd copy of the
 * blob (meta->blob, free() it; NULL when blob_size = 0). */
int rl_checkpoint_read(const char *path, rl_system *sys, rl_checkpoint_meta *meta);

/* Build a new system from the checkpoint's species table and state (for "start from a
 * checkpoint" without a model definition).  NULL with a message on failure. */
rl_system *rl_checkpoint_load(const char *path, rl_checkpoint_meta *meta);

#ifdef __cplusplus
}
#endif
#endif
