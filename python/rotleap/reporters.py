"""Reporters for Simulation.run: objects with `when` ('step' or 'state'), `every` (steps) and
report(sim, report).  A 'step' reporter is called with the on-step values at step k (energies,
temperatures, pressure, forces) after the step that leaves k, when k is a multiple of every (a
multiple of output.energy_every), and once more with last = True after run()'s last step; a
'state' reporter after the step to k + 1 when k + 1 is a multiple of every, to read the state
(positions, orientations, half-step velocities) from the simulation."""
import os

from ._native import lib, THERMO, TRAJ, TOPOLOGY, SAMPLES

__all__ = ["Reporter", "CallbackReporter", "ThermoReporter", "TrajectoryReporter", "CheckpointReporter"]


class Reporter:
    """Base class: set when and every, override report(sim, report)."""
    when = "step"

    def __init__(self, every, when=None):
        self.every = every
        if when is not None:
            self.when = when

    def report(self, sim, report):
        """Called at the reporter's steps with the simulation and a rotleap.Report."""
        raise NotImplementedError

    def __repr__(self):
        return "%s(every=%r, when=%r)" % (type(self).__name__, self.every, self.when)


class CallbackReporter(Reporter):
    """A function fn(sim, report) as a reporter."""

    def __init__(self, fn, every, when="step"):
        super().__init__(every, when)
        self.fn = fn

    def report(self, sim, report):
        """Calls fn(sim, report)."""
        self.fn(sim, report)


class ThermoReporter(Reporter):
    """The rows of `rotleap run`'s PREFIX.thermo.csv, formatted by the code that writes that file
    (app/thermo.c): the same columns (each energy term's; under a barostat the volume, density,
    box edges and pressure tensor; in a mixture each species' temperatures) and the same bytes,
    every `every` steps (default: the deck's output.thermo_every) and the row of the last state.
    calE, the running relative standard deviation of the conserved quantity, is the simulation's,
    over every step with energies since its production began, as `rotleap run` takes it.  `file`:
    a path or a text file object.  A file the reporter opened (a path) is a stream the
    simulation's checkpoints mark, as rotleap run marks its thermo file; when a later run() goes
    on, its row of the last state is replaced by the row of the next run's first step, as rotleap
    run's continuation replaces it."""

    def __init__(self, file, every=None):
        super().__init__(every, "step")
        self._file = file
        self._f = None
        self._own = False
        self._sim = None
        self._size = 0  # bytes written (the rows are ASCII)
        self._pre_last = None  # the size before the row of the last state, until a run goes on

    def cadence(self, sim):
        """Rows every self.every steps (a multiple of output.energy_every)."""
        if self.every is None:
            self.every = sim.thermo_every
        if isinstance(self.every, bool) or not isinstance(self.every, int) or self.every < 1 \
                or self.every % sim.energy_every:
            raise ValueError("ThermoReporter: every = %r must be a multiple of output.energy_every (%d)"
                             % (self.every, sim.energy_every))
        if self._f is None:
            self._open(sim)
        elif self._pre_last is not None and self._own:  # the run goes on: the last state's row goes
            self._f.flush()
            self._f.seek(self._pre_last)
            self._f.truncate()
            self._size = self._pre_last
        self._pre_last = None
        return self.every

    def _write(self, text):
        if text is None:
            from .simulation import _fail
            _fail()
        self._f.write(text if self._own else text.decode())
        self._size += len(text)

    def _open(self, sim):
        if isinstance(self._file, (str, bytes, os.PathLike)):
            self._f = open(self._file, "wb")
            self._own = True
            self._sim = sim
            sim._attach_stream(THERMO, self, self._file)
        else:
            self._f = self._file
            self._own = False
        self._write(lib.rlpy_thermo_header(sim._handle()))

    def _mark_length(self, k):
        """The bytes a checkpoint marks: all but the row of the last state (rotleap run's marks)."""
        self._f.flush()
        return self._size if self._pre_last is None else self._pre_last

    def report(self, sim, r):
        """Writes the row of r (at the reporter's steps and at the last state)."""
        if self._f is None:
            self._open(sim)
        if r.last:
            self._pre_last = self._size
        self._write(lib.rlpy_thermo_row(sim._handle()))
        if r.last:
            self._f.flush()

    def close(self):
        """Closes the file if the reporter opened it (a path); checkpoints no longer mark it."""
        if self._sim is not None:
            self._sim._detach_stream(THERMO, self)
            self._sim = None
        if self._f is not None and self._own:
            self._f.close()
        self._f = None


def _every(every, default, name):
    every = default if every is None else every
    if isinstance(every, bool) or not isinstance(every, int) or every < 1:
        raise ValueError("%s: every = %r must be a whole number >= 1 (the deck's is %r)" % (name, every, default))
    return every


class TrajectoryReporter(Reporter):
    """The trajectory `rotleap run` writes, by the library's writers: a DCD of the sites (with
    its PDB topology, the state when the run starts, at `topology`: default PATH with .pdb for
    .dcd) for site models, else an extended XYZ of centres and axes or orientations (`format`
    'dcd' or 'xyz' overrides the choice).  A frame every `every` steps (default the deck's
    output.trajectory_every), after the step to each multiple; the file is created when the
    first run() with the reporter starts.  close() finishes it (a DCD's header counts frames)."""

    def __init__(self, path, every=None, format=None, topology=None):
        super().__init__(every, "state")
        if format not in (None, "dcd", "xyz"):
            raise ValueError("TrajectoryReporter: format %r: 'dcd' or 'xyz'" % (format,))
        self.path, self.format, self.topology = os.fspath(path), format, topology
        self._t = None
        self._sim = None

    def cadence(self, sim):
        """Opens the file when the first run starts; frames every `every` steps."""
        self.every = _every(self.every, sim.trajectory_every, "TrajectoryReporter")
        if self._t is None:
            if self.format is None:
                self.format = "dcd" if lib.rlpy_site_trajectory(sim._handle()) else "xyz"
            top = None
            if self.format == "dcd":
                top = self.topology or (self.path[:-4] if self.path.endswith(".dcd") else self.path) + ".pdb"
            t = lib.rlpy_traj_open(sim._handle(), self.path.encode(), self.format == "dcd", self.every,
                                   top.encode() if top else None)
            if not t:
                from .simulation import _fail
                _fail()
            self._t, self._sim = t, sim
            skip = lib.rlpy_traj_skip(t)
            if skip < 0:
                from .simulation import _fail
                _fail()
            sim._attach_stream(TRAJ, self, self.path, skip)  # marked by the checkpoints, as rotleap run's
            if top:
                sim._attach_stream(TOPOLOGY, self, top)
        elif sim is not self._sim:
            raise ValueError("TrajectoryReporter: %s is written by another simulation" % self.path)
        return self.every

    def report(self, sim, r):
        """Writes the frame of the state after r's step."""
        if lib.rlpy_traj_frame(sim._handle(), self._t):
            from .simulation import _fail
            _fail()

    def _mark_length(self, k):
        return -1  # all the file holds: the frames are written through

    def close(self):
        """Finishes and closes the trajectory file (checkpoints no longer mark it)."""
        if self._sim is not None:
            self._sim._detach_stream(TRAJ, self)
            self._sim._detach_stream(TOPOLOGY, self)
        if self._t is not None:
            t, self._t = self._t, None
            if lib.rlpy_traj_close(t):
                from .simulation import _fail
                _fail()

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass


class CheckpointReporter(Reporter):
    """Checkpoints of the state, by the library's writer, as `rotleap run` writes PREFIX.chk:
    every `every` steps (default the deck's output.checkpoint_every) and after run()'s last step
    (finish), each replacing the last.  With `journal` (default), rotleap run's analysis runs
    from the first run() with the reporter on, its journal at PREFIX.samples beside PATH =
    PREFIX.chk (PATH.samples for another name), and each checkpoint marks the files of the
    simulation's built-in reporters (thermo, trajectory, topology, journal) as rotleap run marks
    its own: for the same deck the checkpoint is rotleap run's byte for byte, and `rotleap run`
    continues it (system.start = PATH), appending to those files under output.prefix = PREFIX.
    close() ends the journal."""

    def __init__(self, path, every=None, journal=True):
        super().__init__(every, "state")
        self.path = os.fspath(path)
        self.journal = (self.path[:-4] if self.path.endswith(".chk") else self.path) + ".samples" if journal else None
        self._sim = None

    def cadence(self, sim):
        """0 (at the end only) for every = None with the deck's output.checkpoint_every = 0."""
        if self.journal and self._sim is None and SAMPLES not in sim._streams:
            if lib.rlpy_journal_open(sim._handle(), self.journal.encode()):
                from .simulation import _fail
                _fail()
            self._sim = sim
            sim._attach_stream(SAMPLES, self, self.journal)
        if self.every is None and sim.checkpoint_every <= 0:
            return 0
        self.every = _every(self.every, sim.checkpoint_every, "CheckpointReporter")
        return self.every

    def _mark_length(self, k):
        return -1  # the journal as synced by the checkpoint

    def report(self, sim, r):
        """Writes the checkpoint of the state after r's step."""
        sim.checkpoint(self.path)

    def finish(self, sim):
        """Writes the checkpoint of the last state (called by run() after its last step)."""
        sim.checkpoint(self.path)

    def close(self):
        """Ends the analysis journal (later checkpoints mark no journal)."""
        sim, self._sim = self._sim, None
        if sim is not None:
            sim._detach_stream(SAMPLES, self)
            if sim._h is not None and lib.rlpy_journal_close(sim._h):
                from .simulation import _fail
                _fail()
