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
 *    a new NAME.tmp.XXXXXX beside NAME (six random characters; created with O_CREAT | O_EXCL |
 *    O_NOFOLLOW, mode 0666 minus the umask), fsync, rename over NAME, fsync of the directory.  A
 *    crash leaves either the old or the new file, never a partial one.  Nothing is ever written
 *    through a symbolic or hard link planted at an output's name: whole files and new files
 *    (rl_file_create) replace the name, files continued in place (rl_file_open_existing, a DCD
 *    appended to) are refused if the name is a link.
 *  - Every write, flush, fsync, seek, rename and close is checked; the first failure is returned
 *    with a message naming the file and the system's reason for that failure ("No space left on
 *    device"), once.
 *  - Readers follow links but accept only regular files (a FIFO or /dev/zero is "not a regular
 *    file"), bound every count read from a file by the file's size, and refuse text lines longer
 *    than 65,536 characters (PDB: 1,024) and NUL bytes, naming file:line. */
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
  char *tmp;         /* NAME.tmp.XXXXXX                                         */
  void *io;          /* internal: the stream's descriptor and first write error */
} rl_atomic_file;

/* Create a new NAME.tmp.XXXXXX beside path and open a stream on it for writing.  On success
 * a->fp is the stream; the errno of its first failed write is kept for rl_atomic_commit's
 * message. */
int rl_atomic_open(rl_atomic_file *a, const char *path);
/* Flush, fsync, close, rename over the final name, fsync the directory.  The first failure is
 * returned, with the file and the system's reason ("out.chk: cannot write out.chk.tmp.q3Xz9A: No
 * space left on device"); up to the rename the temporary file is then removed and the previous
 * NAME is untouched (a failed sync of the directory after the rename is reported too: NAME is
 * then the new file).  Frees a's strings. */
int rl_atomic_commit(rl_atomic_file *a);
/* Close and remove the temporary file (accepts a never-opened, zeroed a). */
void rl_atomic_abort(rl_atomic_file *a);

/* ------------------------------------------------------------ working files written in place */

/* A NEW empty regular file at path, open for reading and writing (*fd, close-on-exec): created
 * as a temporary beside it (O_CREAT | O_EXCL | O_NOFOLLOW, mode 0666 minus the umask) and
 * renamed over path, so that whatever had that name (a file, a symbolic link, a hard link to
 * another file) is replaced, never followed or written through; the directory is then synced.
 * For files a run writes as it goes (trajectories, thermo rows, journals). */
int rl_file_create(const char *path, int *fd);
/* Open an existing file (flags: O_RDONLY, O_WRONLY or O_RDWR, optionally O_APPEND, O_TRUNC; not
 * O_CREAT) without following a symbolic link at path (O_NOFOLLOW: "is a symbolic link: refusing
 * to follow it"), refusing anything but a regular file ("not a regular file (a FIFO)") and, when
 * writing, a file with more than one hard link ("has 2 hard links: refusing to write through a
 * link"); O_TRUNC is applied only after these checks.  *fd is close-on-exec. */
int rl_file_open_existing(const char *path, int flags, int *fd);

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

/* AKMA time unit in ps (CHARMM's internal unit, 4.888821e-14 s), in which CHARMM and NAMD store a
 * DCD's time step and MDAnalysis reads it. */
#define RL_DCD_AKMA_PS 0.04888821

/* Create a DCD for sys's atoms as a new file (rl_file_create: a link at path is replaced, never
 * written through).  first_step: step of the first frame (ISTART); interval: steps between frames
 * (NSAVC); dt: the integration time step in the system's time unit, stored in the header (DELTA,
 * float32) in AKMA units for a real system (dt / RL_DCD_AKMA_PS) and as it is (reduced time) for
 * an lj system.  title may be NULL. */
rl_dcd *rl_dcd_create(const char *path, const rl_system *sys, long first_step, long interval,
                      double dt, const char *title);
/* Reopen an existing DCD for appending after a restart (rl_file_open_existing: a symbolic link,
 * a non-regular file or a file with other hard links is refused): checks the layout and NATOM
 * against sys, keeps the first `keep_frames` frames (fewer present is an error) and discards the
 * rest. */
rl_dcd *rl_dcd_append(const char *path, const rl_system *sys, long keep_frames);
/* Of an existing DCD: the step of its first frame (ISTART), the steps between frames (NSAVC) and
 * the number of complete frames in the file.  Any pointer may be NULL. */
int rl_dcd_info(const char *path, long *first_step, long *interval, long *frames);
/* Of an existing DCD: the bytes before its first frame (header, title and atom-count records)
 * and the bytes of one frame.  Frame k occupies [header + k frame, header + (k + 1) frame); the
 * header is rewritten in place after each frame (NSET, NSTEP), the frames never are. */
int rl_dcd_layout(const char *path, long *header_bytes, long *frame_bytes);
/* Append one frame (one pwrite at the end, then the header's frame count), with the system's box
 * as its unit cell (zeros without a box).  After a failed write, this and
 * rl_dcd_sync return the status of that failure again without a new message. */
int rl_dcd_write_frame(rl_dcd *d, const rl_system *sys);
long rl_dcd_frames(const rl_dcd *d);
/* Make the frames written so far durable: rewrite the header's frame count, fsync.  (Frames are
 * written with write(2), without a user-space buffer: there is nothing to flush.)  An error names
 * the file and the system's reason. */
int rl_dcd_sync(rl_dcd *d);
/* Close; returns the first error met while writing or closing, if any.  An error met earlier is
 * returned as it is (its message is not repeated or replaced).  Accepts NULL. */
int rl_dcd_close(rl_dcd *d);

/* ------------------------------------------------------------------------------ PDB */

/* PDB of the current state: CRYST1 (the system's box in file units, 90 degrees; omitted without
 * a box), one
 * residue per body (residue name: the first three characters of the species name, upper case;
 * chain A, residue numbers modulo 10000), one ATOM record per atom with name from the site names,
 * element from the name's leading letters for massive sites of real-unit systems, TER and END.
 * Coordinates %8.3f: PDB resolves 1e-3 file units (1e-4 nm for real systems).  Used as the DCD
 * topology and as a final structure.  Written atomically.  More than 99999 atoms: serials wrap
 * (as in GROMACS/MDTraj output). */
int rl_pdb_write(const char *path, const rl_system *sys, const rl_molecule *const *mols);

/* Count residues (molecules) in a PDB, and optionally read its CRYST1 box (system units for the
 * given unit system; zeros if none). */
int rl_pdb_count(const char *path, rl_units units, int *nres, double box[3]);

/* Set positions and orientations of sys (species and counts already defined) from a PDB: ATOM/
 * HETATM records grouped into residues by (chain, residue number, residue name) in file order;
 * residue k is body k and must have as many atoms as its species has sites (one atom for a
 * site-less species; a mixture: see rl_pdb_read_state_residues).  If mols[species] is given,
 * atom names must name the sites (the names rl_pdb_read_state_residues lists; a massless site
 * may be left out).  Each molecule's centre and rotation come from a least-squares (Kabsch, via
 * Horn's quaternion) fit of the species' body-frame sites to the atoms, after making the residue
 * whole with the CRYST1 box if present.  A fit with RMS deviation above tol (system length units;
 * tol <= 0 selects 0.01 file units = 10x the PDB resolution) is an error naming the residue and
 * its first line.  Axis kinds take the fitted body Z axis; single-site bodies keep their
 * orientation.  Velocities and angular momenta are not touched.  rms_max (may be NULL) receives
 * the largest RMS fit error (system units); box (may be NULL) the CRYST1 box. */
int rl_pdb_read_state(const char *path, rl_system *sys, const rl_molecule *const *mols, double tol,
                      double *rms_max, double box[3]);

/* A residue name (as in columns 18-21 of a PDB, any case) and the species it stands for. */
typedef struct {
  char name[8];
  int species; /* index into the system's species */
} rl_pdb_residue;

/* rl_pdb_read_state for mixtures: with several species, or a map (nmap > 0), each residue's
 * species comes from its name (columns 18-21, any case): the map's entry first, then a species
 * of that name or the residue name rl_pdb_write gives it, then a default alias that fits one
 * species only: HOH WAT SOL H2O TIP3 TIP4 T3P T4P T4E SPC -> the water (sites O, H1, H2 and
 * at most one massless more), NA NA+ SOD -> Na+, CL CL- CLA -> Cl- (a one-site species named
 * na..., cl..., or whose site is Na, Cl).  The residues of a species are its bodies in file
 * order, in any order among other species; each species' count must be the file's.  Atom names
 * (any case, any order within the residue) may be the sites', GROMACS's (OW HW1 HW2 MW), CHARMM's
 * OH2, and for the one massless site of a molecule M, MW, EP (OpenMM), EPW (AMBER), OM or LP;
 * that massless site may be left out (3-atom waters of a 4-site model) and is then placed by
 * the fit of the others.  Errors name the file, the line and the residue.  Without a map,
 * residue k is body k when the system has one species (whatever the residue names), or when
 * every residue has the name rl_pdb_write gives body k's species (rotleap's own mixtures). */
int rl_pdb_read_state_residues(const char *path, rl_system *sys, const rl_molecule *const *mols,
                               const rl_pdb_residue *map, int nmap, double tol, double *rms_max, double box[3]);

/* ---------------------------------------------------------------------- extended XYZ */

/* One frame of extended XYZ: N (bodies), then
 *   Lattice="Lx 0 0 0 Ly 0 0 0 Lz" Properties=species:S:1:pos:R:3:orientation:R:3 Time=t Step=s pbc="T T T"
 * and one line per body: species name, centre (file units, %.10f), body Z axis in the lab
 * (rl_system_get_axis; 0 0 0 for point bodies), %.17g so that a read gives the same unit vector.
 * Lattice (the system's box) and pbc are omitted without a box.  fp: an open stream (a trajectory appends frames).
 * path is used in messages only. */
int rl_xyz_write_frame(FILE *fp, const char *path, const rl_system *sys, double time, long step);
/* One-frame file, written atomically. */
int rl_xyz_write(const char *path, const rl_system *sys, double time, long step);

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
/* The box of the Lattice= key on the comment line, in system units of `units` (file lengths in A
 * for real units, sigma for LJ); zeros without one. */
int rl_xyz_box(const char *path, rl_units units, double box[3]);

/* ------------------------------------------------------------------------- checkpoints */

#define RL_CHECKPOINT_VERSION 1

/* Run data stored with the state.  The blob is opaque to the library (the run driver stores its
 * thermostat/RNG state and accumulators there). */
typedef struct {
  double time;       /* simulation time                                       */
  long step;         /* step count                                            */
  double box[3];     /* read: the box in the file (it becomes the system's); write: ignored,
                        the system's box is written                               */
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
