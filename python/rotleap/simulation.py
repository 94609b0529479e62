"""rotleap.Simulation: a deck's simulation, stepped and observed from Python."""
import ctypes
import os
import tempfile
import threading
import warnings

import numpy as np

from . import _native
from ._native import lib, dptr

__all__ = ["Error", "Simulation", "Report"]


class Error(Exception):
    """A failure of the rotleap library; the message is the library's (rl_last_error)."""


# body kinds (rotleap/system.h, rl_kind)
_KINDS = {0: "point", 1: "dipole", 2: "linear", 3: "spherical", 4: "symmetric", 5: "asymmetric"}
# quantities of rlpy_get/rlpy_set (native.c)
_POS, _VEL, _ANGMOM, _ORIENT, _AXIS, _FORCE, _TORQUE = range(7)
_VALUE_NAMES = ("step", "time", "last", "total", "potential", "ke_trans", "ke_rot", "temperature", "t_trans",
                "t_rot", "pressure", "conserved", "t_trans_mid", "t_rot_mid", "max_h_omega", "fallbacks")


def _fail(status=None):
    raise Error(_native.error_text() or "rotleap error %s" % status)


class Report:
    """What a reporter is called with.

    kind 'step' (the on-step values at `step`, before the step that left it; `last` for the report
    of the last state after run()): step, time, last, total, potential, kinetic, ke_trans, ke_rot,
    temperature, t_trans, t_rot, pressure (bar in real units), conserved, t_trans_mid, t_rot_mid,
    max_h_omega, fallbacks, virial (3x3), energies (dict: energy component -> value); forces()
    and torques() at that step (only during the call).
    kind 'state' (the state after the step: read it from the simulation): step, time."""

    def __init__(self, sim, kind, values, names):
        self._sim = sim
        self.kind = kind
        self.step = int(values[0])
        self.time = float(values[1])
        self.last = False
        if kind == "step":
            for k, name in enumerate(_VALUE_NAMES):
                setattr(self, name, float(values[k]))
            self.step = int(values[0])
            self.last = bool(values[2])
            self.fallbacks = int(values[15])
            self.kinetic = self.ke_trans + self.ke_rot
            nv = len(_VALUE_NAMES)
            self.virial = np.array(values[nv:nv + 9]).reshape(3, 3)
            self.energies = {n: float(values[nv + 9 + j]) for j, n in enumerate(names)}

    def _forces(self):
        if self.kind != "step" or self._sim._report is not self:
            raise Error("forces and torques of a report are read during a step reporter's call")
        s = self._sim
        f = np.empty((s.count, 3))
        k = np.empty((max(s._nrot, 1), 3))
        if lib.rlpy_report_forces(s._h, dptr(f), dptr(k)):
            _fail()
        return f, k[:s._nrot]

    def forces(self):
        """Forces (n, 3) at the report's step (a step report, during the reporter's call)."""
        return self._forces()[0]

    def torques(self):
        """Lab-frame torques (n_rotating, 3) at the report's step (as forces())."""
        return self._forces()[1]

    def __repr__(self):
        return "Report(%s, step=%d, time=%g)" % (self.kind, self.step, self.time)


class Simulation:
    """The simulation a deck describes, built as `rotleap run` builds it: the system in its
    starting state, the interactions, the relaxation (run.equilibrate) already done, and the
    production integrator at step 0, or, from a checkpoint of the same settings (system.start),
    at its step with its run record (random streams, barostat state, averages): the run goes on
    bit for bit as `rotleap run`'s continuation.  A checkpoint of other settings starts a new run
    from its state (RuntimeWarning).

    Simulation(path, set={"run.steps": 100}) or Simulation(text=DECK_TEXT); `set` holds deck
    overrides as `--set` gives them.  Relative paths in a deck are relative to the working
    directory, as for `rotleap run`.  Nothing is written to files unless a reporter writes."""

    def __init__(self, deck=None, *, text=None, set=None):
        if (deck is None) == (text is None):
            raise TypeError("Simulation(deck_path) or Simulation(text=deck_text): give one of them")
        sets = ["%s=%s" % (k, v) for k, v in (set or {}).items()]
        self._h = None
        self._running = False
        self._report = None
        self._external = None
        self._ext_raised = []
        self._streams = {}  # stream (_native.THERMO ...) -> the built-in reporter writing it
        tmp = None
        try:
            if text is not None:
                tmp = tempfile.TemporaryDirectory(prefix="rotleap-deck-")
                path = os.path.join(tmp.name, "deck.ini")
                with open(path, "w") as f:
                    f.write(text)
            else:
                path = os.fspath(deck)
            arr = (ctypes.c_char_p * max(len(sets), 1))(*[s.encode() for s in sets])
            h = lib.rlpy_open(path.encode(), arr, len(sets))
            if not h:
                msg = _native.error_text()
                raise Error(msg.replace(path, "<deck text>") if tmp else msg)
        finally:
            if tmp:
                tmp.cleanup()
        self._h = h
        note = lib.rlpy_note(h).decode()
        if note:  # what `rotleap run` notes on stderr for this start
            warnings.warn(note, RuntimeWarning, stacklevel=2)
        self.count = lib.rlpy_count(h)
        self._nrot = lib.rlpy_nrot(h)
        self.kind = _KINDS.get(lib.rlpy_kind(h), "?")
        self.model = lib.rlpy_model(h).decode()
        self.timestep = lib.rlpy_timestep(h)
        self.energy_every = lib.rlpy_energy_every(h)
        self.thermo_every = lib.rlpy_thermo_every(h)
        self.trajectory_every = lib.rlpy_trajectory_every(h)
        self.checkpoint_every = lib.rlpy_checkpoint_every(h)
        self.deck_steps = lib.rlpy_deck_steps(h)
        self.units = "real" if lib.rlpy_real_units(h) else "lj"
        self._energy_names()

    def _energy_names(self):
        h = self._h
        self.energy_names = [lib.rlpy_energy_name(h, j).decode() for j in range(lib.rlpy_nenergies(h))]
        self._nvalues = lib.rlpy_nvalues() + len(self.energy_names)

    @classmethod
    def from_model(cls, model, count, *, density=None, box=None, temperature=None, params=None, set=None):
        """A simulation built from a catalogue model, a count and a box (`box`: an edge or three,
        or `density`), without a deck file: the deck these make, with `params` ({name: value}
        of the model's parameters) and the other keys in `set` ({"run.timestep": "2 fs", ...});
        values are numbers in the model's units or strings with a unit ("298 K")."""
        lines = ["[system]", "model = %s" % model, "count = %d" % count]
        if box is not None:
            edges = [box] * 3 if isinstance(box, (int, float, str)) else list(box)
            lines.append("box = %s" % " ".join(str(e) for e in edges))
        if density is not None:
            lines.append("density = %s" % density)
        if temperature is not None:
            lines.append("temperature = %s" % temperature)
        if params:
            lines.append("[model]")
            lines += ["%s = %s" % kv for kv in params.items()]
        return cls(text="\n".join(lines) + "\n", set=set)

    # ------------------------------------------------------------------ lifecycle
    def _handle(self):
        if self._h is None:
            raise Error("the simulation is closed")
        return self._h

    def _idle(self):
        h = self._handle()
        if self._running:
            raise Error("the simulation is running: a reporter may read it, not step or change it")
        return h

    def close(self):
        """Free the simulation; any later use raises rotleap.Error."""
        if self._running:
            raise Error("the simulation is running: close it after run() returns")
        if self._h is not None:
            lib.rlpy_close(self._h)
            self._h = None

    @property
    def closed(self):
        """True after close()."""
        return self._h is None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            if getattr(self, "_h", None) is not None and not self._running:
                lib.rlpy_close(self._h)
                self._h = None
        except Exception:  # interpreter shutdown: the module may be gone
            pass

    # ------------------------------------------------------------------ stepping
    @property
    def current_step(self):
        """Production steps done (counted from the start's step: 0, or a checkpoint's)."""
        return lib.rlpy_step(self._handle())

    @property
    def time(self):
        """Simulated time of the current state (the deck's time unit: ps in real units)."""
        return lib.rlpy_time(self._handle())

    def step(self, n=1):
        """n production steps, no reporters.  Ctrl-C stops between two steps (KeyboardInterrupt)."""
        self._run(n, (), finish=False)

    def run(self, steps=None, reporters=()):
        """`steps` more steps (default: up to the deck's run.steps) with the reporters called on
        their cadence (see Reporter), then the report of the last state to the step reporters
        (last = True), as `rotleap run` writes its last thermo row, and finish(sim) of the
        reporters that have one (a CheckpointReporter writes the last state's checkpoint).  A
        reporter that raises stops the run with its exception; Ctrl-C stops it between two steps
        with KeyboardInterrupt."""
        if steps is None:
            steps = max(self.deck_steps - self.current_step, 0)
        reporters = list(reporters)
        self._run(steps, reporters, finish=True)
        for r in reporters:
            if callable(getattr(r, "finish", None)):
                r.finish(self)

    def checkpoint(self, path):
        """Write the checkpoint of the current state to `path` with the library's writer, as
        `rotleap run` writes PREFIX.chk: its run record marks the files the built-in Thermo-,
        Trajectory- and CheckpointReporter (its analysis journal) write for this simulation, as
        rotleap run marks its streams, so that `rotleap run` continues them; in a reporter, from a
        'state' reporter only."""
        h = self._handle()
        lens = (ctypes.c_long * _native.NSTREAMS)(*([-1] * _native.NSTREAMS))
        for k, owner in self._streams.items():
            lens[k] = owner._mark_length(k)
        if lib.rlpy_checkpoint(h, os.fsencode(path), lens):
            _fail()

    def _attach_stream(self, k, owner, path, skip=0):
        """owner (a built-in reporter) writes stream k at path: checkpoints mark it.  False if
        another reporter writes that stream already (then this one is not marked)."""
        if self._streams.get(k, owner) is not owner:
            return False
        if lib.rlpy_stream(self._handle(), k, os.fsencode(path), skip):
            _fail()
        self._streams[k] = owner
        return True

    def _detach_stream(self, k, owner):
        """owner no longer writes stream k (it closed its file)."""
        if self._streams.get(k) is owner:
            del self._streams[k]
            if self._h is not None:
                lib.rlpy_stream(self._h, k, None, 0)

    def _run(self, steps, reporters, finish):
        h = self._idle()
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)):
            raise TypeError("steps must be a whole number, not %r" % (steps,))
        if steps < 0:
            raise ValueError("steps = %d: a run takes 0 or more steps" % steps)
        reps, cadences = [], []
        for r in reporters:
            kind = getattr(r, "when", None)
            if kind not in ("step", "state") or not callable(getattr(r, "report", None)):
                raise TypeError("reporter %r: a reporter has when = 'step' or 'state', every and report(sim, report)" % (r,))
            e = r.cadence(self) if hasattr(r, "cadence") else r.every
            if e == 0 and hasattr(r, "cadence"):  # called at the end only (finish)
                continue
            reps.append(r)
            cadences.append(e)
        when = (ctypes.c_int * max(len(reps), 1))()
        every = (ctypes.c_long * max(len(reps), 1))()
        for i, (r, e) in enumerate(zip(reps, cadences)):
            kind = r.when
            if isinstance(e, bool) or not isinstance(e, (int, np.integer)) or e < 1:
                raise ValueError("reporter %r: every = %r must be a whole number >= 1" % (r, e))
            if kind == "step" and e % self.energy_every:
                raise ValueError("reporter %r: a step reporter's every (%d) must be a multiple of output.energy_every (%d)"
                                 % (r, e, self.energy_every))
            when[i] = 0 if kind == "step" else 1
            every[i] = e
        raised = []
        values = np.empty(self._nvalues)

        def call(i):
            try:
                isstep = lib.rlpy_report(h, dptr(values))
                rep = Report(self, "step" if isstep == 1 else "state", values, self.energy_names)
                self._report = rep
                reps[i].report(self, rep)
                return 0
            except BaseException as e:  # KeyboardInterrupt too: it stops the run, then is re-raised
                raised.append(e)
                return 1
            finally:
                self._report = None

        cb = _native.CALLBACK(call)
        done = ctypes.c_long(0)
        main = threading.current_thread() is threading.main_thread()
        self._running = True
        try:
            st = lib.rlpy_run(h, steps, len(reps), when, every, cb, 1 if finish else 0, 1 if main else 0,
                              ctypes.byref(done))
        finally:
            self._running = False
        self._raise_external()
        if raised:
            raise raised[0]
        if st == _native.INTERRUPTED:
            raise KeyboardInterrupt("rotleap: stopped at step %d" % self.current_step)
        if st:
            _fail(st)

    # ------------------------------------------------------------------ an external force
    def add_external_force(self, fn):
        """Add a force term written in Python: fn(sim, forces, torques) adds its forces (n, 3)
        and lab-frame torques (n_rotating, 3) to the arrays it is given (in place: they are the
        library's accumulators) and returns its energy.  It is called once per force computation
        (each step, and now: the forces are recomputed at the current state), from the thread
        that steps, and reads the state from sim (positions, axes, orientations); its energy is
        the component 'external' of the energies and of the potential, and it adds no virial.
        Cost: one Python call per step (about 10 us) plus what fn does with numpy
        (docs/python.md: a field on 256 dipoles adds 41 % to a 115 us step).  An exception
        in fn stops the step it is in and is raised by step()/run(); the simulation is then at
        the state of that unfinished step (rebuild or set the state before going on)."""
        h = self._idle()
        if not callable(fn):
            raise TypeError("add_external_force: fn(sim, forces, torques) -> energy is needed, not %r" % (fn,))
        n, nrot = self.count, self._nrot

        def call(f, k, virial, energy, forces_only):
            try:
                F = np.ctypeslib.as_array(f, shape=(n, 3))
                K = np.ctypeslib.as_array(k, shape=(nrot, 3)) if nrot else np.zeros((0, 3))
                u = fn(self, F, K)
                if isinstance(u, (bool, np.bool_)) or not isinstance(u, (int, float, np.integer, np.floating)):
                    raise TypeError("the external force returned %r: its energy (a number) is needed" % (u,))
                if not np.isfinite(u):
                    raise ValueError("the external force returned the energy %r, not finite" % (u,))
                energy[0] = float(u)
                return 0
            except BaseException as e:
                self._ext_raised.append(e)
                return 1

        cb = _native.FORCE_CALLBACK(call)
        if self._external is not None:
            raise Error("the simulation has an external force already")
        self._external = cb  # kept alive as long as the simulation
        st = lib.rlpy_add_external(h, cb)
        self._energy_names()
        self._raise_external()
        if st:
            _fail(st)

    def _raise_external(self):
        if self._ext_raised:
            e, self._ext_raised = self._ext_raised[0], []
            raise e

    # ------------------------------------------------------------------ values
    def report(self):
        """The on-step values of the current state (energies by term, kinetic energies,
        temperatures, pressure, virial, conserved quantity) as a 'step' Report."""
        h = self._idle()
        values = np.empty(self._nvalues)
        if lib.rlpy_observe(h, dptr(values)):
            _fail()
        return Report(self, "step", values, self.energy_names)

    def energies(self):
        """{'potential', 'kinetic', 'total', 'conserved', each energy component}: on-step values."""
        r = self.report()
        out = {"potential": r.potential, "kinetic": r.kinetic, "ke_trans": r.ke_trans, "ke_rot": r.ke_rot,
               "total": r.total, "conserved": r.conserved}
        out.update(r.energies)
        return out

    @property
    def pressure(self):
        """On-step pressure (bar in real units, reduced in lj)."""
        return self.report().pressure

    @property
    def box(self):
        """Box edges (3,) of the current state (nm in real units)."""
        L = np.empty(3)
        lib.rlpy_box(self._handle(), dptr(L))
        return L

    # ------------------------------------------------------------------ the state
    def _shape(self, q):
        n = self._nrot if q in (_ANGMOM, _TORQUE) else self.count
        return (n, 3, 3) if q == _ORIENT else (n, 3)

    def _get(self, q):
        h = self._handle()
        a = np.zeros(self._shape(q))
        if a.size == 0:
            return a
        if lib.rlpy_get(h, q, dptr(a)):
            _fail()
        return a

    def _set(self, q, name, value):
        h = self._idle()
        a = np.asarray(value)
        if a.dtype.kind not in "fiu":
            raise TypeError("%s: an array of real numbers is needed, not dtype %s" % (name, a.dtype))
        if a.shape != self._shape(q):
            raise ValueError("%s: shape %s, expected %s" % (name, a.shape, self._shape(q)))
        a = np.ascontiguousarray(a, dtype=np.float64)
        bad = ~np.isfinite(a)
        if bad.any():
            i = np.argwhere(bad)[0]
            raise ValueError("%s: element %s is %r, not finite" % (name, tuple(int(x) for x in i), a[tuple(i)]))
        if a.size and lib.rlpy_set(h, q, dptr(a)):
            _fail()

    positions = property(lambda s: s._get(_POS), lambda s, v: s._set(_POS, "positions", v),
                         doc="centres of mass (n, 3), a copy; setting one resumes the step at the new state")
    centres = positions
    velocities = property(lambda s: s._get(_VEL), lambda s, v: s._set(_VEL, "velocities", v),
                          doc="v(t - h/2), (n, 3): the leapfrog's half-step velocities, as a checkpoint holds them")
    angular_momenta = property(lambda s: s._get(_ANGMOM), lambda s, v: s._set(_ANGMOM, "angular_momenta", v),
                               doc="lab-frame l(t - h/2), (n_rotating, 3)")
    orientations = property(lambda s: s._get(_ORIENT), lambda s, v: s._set(_ORIENT, "orientations", v),
                            doc="A (n, 3, 3), lab to body (rows: the body axes in the lab); matrix bodies only")
    axes = property(lambda s: s._get(_AXIS), lambda s, v: s._set(_AXIS, "axes", v),
                    doc="unit axes (n, 3) of point dipoles and linear bodies")
    forces = property(lambda s: s._get(_FORCE), doc="forces at the current state (n, 3)")
    torques = property(lambda s: s._get(_TORQUE), doc="lab-frame torques at the current state (n_rotating, 3)")

    def molecule(self):
        """The simulation's molecule (the deck's model with its parameters) as a dict of the
        rotleap.Model fields mass, inertia, site_names, sites (body frame, (nsites, 3)),
        site_mass, sigma, epsilon, charge, dipole, quadrupole."""
        from .catalog import molecule
        h = self._handle()
        return molecule(lambda *a: lib.rlpy_molecule(h, *a))

    def site_positions(self):
        """Lab positions of every site (n, nsites, 3): the centre plus A^T times the body-frame
        site (matrix bodies), or the centre plus the site's z times the axis (axis bodies)."""
        m = self.molecule()
        x = self.positions
        if self.kind in ("dipole", "linear"):
            return x[:, None, :] + m["sites"][None, :, 2, None] * self.axes[:, None, :]
        if self.kind == "point":
            return x[:, None, :] + np.zeros((1, len(m["sites"]), 3))
        return x[:, None, :] + np.einsum("nji,sj->nsi", self.orientations, m["sites"])

    def interactions(self):
        """The deck's interaction settings: {cutoff, scheme ('site' or 'molecule'), lj
        ('plain', 'shifted', 'shifted-force', 'switched'), dispersion_correction (bool), eps_rf,
        coulomb ('rf', 'ewald', 'pme'), ewald_tolerance, ewald_alpha (0: derived), pme_grid
        (0s: derived), pme_order, ewald_boundary (inf: tin foil), ewald_kmax, dipole ('rf', 'sf')}."""
        v = np.zeros(17)
        lib.rlpy_interactions(self._handle(), dptr(v))
        return dict(cutoff=v[0], scheme=("site", "molecule")[int(v[1])],
                    lj=("plain", "shifted", "shifted-force", "switched")[int(v[2])],
                    dispersion_correction=bool(v[3]), eps_rf=v[4], coulomb=("rf", "ewald", "pme")[int(v[5])],
                    ewald_tolerance=v[6], ewald_alpha=v[7], pme_grid=tuple(int(g) for g in v[8:11]),
                    pme_order=int(v[11]), ewald_boundary=v[12], ewald_kmax=tuple(int(k) for k in v[13:16]),
                    dipole=("rf", "sf")[int(v[16])])

    @property
    def fallbacks(self):
        """Guarded rotation solves that needed Newton since the production began."""
        return lib.rlpy_fallbacks(self._handle())

    def __repr__(self):
        if self._h is None:
            return "<rotleap.Simulation closed>"
        return "<rotleap.Simulation %s, %d %s bodies, step %d>" % (self.model, self.count, self.kind, self.current_step)

