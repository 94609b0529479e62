/* The files of one run under output.prefix, and how they survive kills, failures and
 * continuations (docs/files.md, "How a run keeps its outputs").
 *
 *  - A run holds an advisory lock on PREFIX.lock (flock) for its whole life; a second run on
 *    the same prefix is refused, naming the holder's PID.
 *  - Streams, the files a run appends to (the thermo CSV, the trajectory, its PDB topology and
 *    the analysis samples), are written under their working name NAME.part and renamed to NAME
 *    when the run ends normally or on a signal.  A run that fails or is killed leaves them
 *    under NAME.part, and leaves an earlier run's NAME as it was.
 *  - Each checkpoint carries, per stream, a mark: which name held the stream, its length, and
 *    a hash of its bytes, taken after they were flushed and synced to disk (outputs_mark).  A
 *    continuation finds the file (either name) whose first `len` bytes hash to the mark, copies
 *    them to NAME.part if they are in NAME, drops whatever follows them and appends
 *    (outputs_resume): every row and frame up to the checkpoint is kept, whatever sequence of
 *    kills came before, and nothing another run wrote is ever spliced in.
 *  - Working files are created new beside their names and renamed into place, never written
 *    through a link; every write, flush, sync, close and rename is checked.
 *
 * Every function returns RL_OK or a status with rl_last_error() naming the file and the
 * system's reason. */
#ifndef ROTLEAP_APP_OUTPUTS_H
#define ROTLEAP_APP_OUTPUTS_H

#include <stdint.h>
#include <stdio.h>

enum { OUT_THERMO, OUT_TRAJ, OUT_TOPOLOGY, OUT_SAMPLES, OUT_NSTREAMS };
enum { MARK_NONE = 0, MARK_PART = 1, MARK_FINAL = 2 }; /* where a mark's stream was */

typedef struct {
  uint32_t where;   /* MARK_*: MARK_NONE for a stream the run did not write                */
  int64_t len;      /* bytes at the checkpoint                                              */
  int64_t skip;     /* leading bytes outside the hash (a DCD header, rewritten per frame)  */
  uint64_t hash;    /* FNV-1a (64 bits) of the bytes [skip, len)                            */
} out_mark;

typedef struct outputs outputs;

/* The names of the run's streams under `prefix`: PREFIX.thermo.csv, PREFIX.`traj_ext` (NULL:
 * no trajectory), PREFIX.pdb (with a "dcd" trajectory) and, with `samples`, PREFIX.samples.
 * Nothing is opened.  NULL on out of memory. */
outputs *outputs_alloc(const char *prefix, const char *traj_ext, int samples);
/* Closes what is open, releases the lock (removing PREFIX.lock), frees.  Accepts NULL. */
void outputs_free(outputs *o);

/* The lock on PREFIX.lock: RL_EINVAL naming the PID of the run that holds it. */
int outputs_lock(outputs *o);
/* RL_OK if files can be created safely where `prefix` puts them: the directory exists and is
 * writable, and is not writable by every user without the sticky bit (there another user could
 * swap rotleap's files for links between two calls). */
int outputs_check_dir(const char *prefix);

const char *outputs_path(const outputs *o, int k); /* NAME (NULL: a stream this run has no name for) */
const char *outputs_part(const outputs *o, int k); /* NAME.part                                       */

/* A new, empty working file for stream k, opened for writing (the stream's writer is the
 * returned FILE, which the outputs own: outputs_close closes it). */
FILE *outputs_create(outputs *o, int k);
/* Stream k's working file was created by its own writer (the DCD and PDB writers of io.h), with
 * `skip` leading bytes the writer rewrites in place (outside the hash). */
void outputs_started(outputs *o, int k, int64_t skip);
/* 1 if stream k is written by this run (created, started or resumed). */
int outputs_started_p(const outputs *o, int k);
/* Continue stream k from the mark `m` of a checkpoint.  The file whose first m->len bytes hash
 * to the mark is looked for at src_part and src_path (the working and the final name of the
 * stream of the run that wrote the checkpoint: this run's own names for a continuation under
 * the same prefix; those of the other prefix otherwise); it becomes this run's working file,
 * exactly m->len bytes long (truncated in place if it is this run's working file, else copied).
 * RL_EINVAL if neither file holds those bytes, saying what each holds. */
int outputs_resume(outputs *o, int k, const out_mark *m, const char *src_path, const char *src_part);
/* 1 if stream k's working file holds the bytes of mark m (an unfinished run's stream). */
int outputs_part_matches(const outputs *o, int k, const out_mark *m);
/* Open the working file prepared by outputs_resume for appending (FILE owned by the outputs). */
FILE *outputs_append(outputs *o, int k);

/* Flush the streams' FILEs, sync every working file to disk and fill marks[OUT_NSTREAMS] with
 * where each stream is, its length and hash (MARK_NONE for streams not written). */
int outputs_mark(outputs *o, out_mark marks[OUT_NSTREAMS]);
/* A stream written under its final name by another writer (the Python binding's reporters):
 * bytes [skip, hashed) of it are hashed into hash.  Start with {skip, skip, OUTPUTS_HASH_INIT}. */
typedef struct {
  int64_t skip, hashed;
  uint64_t hash;
} out_tracker;
/* Sync the file at `path` and mark its first `len` bytes (len < 0: all it holds), hashing on from
 * t (len must not be below t->hashed): m = {MARK_FINAL, len, t->skip, hash}, as outputs_mark and
 * outputs_commit mark a run's stream. */
int outputs_mark_file(const char *path, out_tracker *t, int64_t len, out_mark *m);
/* Close the FILEs the outputs own (checked).  The first failure is returned. */
int outputs_close(outputs *o);
/* Rename every working file over its name, sync the directory, and turn marks (from
 * outputs_mark, may be NULL) to MARK_FINAL. */
int outputs_commit(outputs *o, out_mark marks[OUT_NSTREAMS]);

/* Remove the working files this run created or copied (not those it continues in place): a
 * run that failed before its first step. */
void outputs_discard(outputs *o);

/* prefix + suffix, malloc'd: file names are as long as the OS allows, never truncated.  NULL on
 * out of memory. */
char *outputs_name(const char *prefix, const char *suffix);

/* FNV-1a (64 bits): the hash of the marks. */
uint64_t outputs_hash(uint64_t h, const void *bytes, size_t n);
#define OUTPUTS_HASH_INIT 14695981039346656037ULL

#endif
