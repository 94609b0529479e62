"""Reporters for Simulation.run: objects with `when` ('step' or 'state'), `every` (steps) and
report(sim, report).  A 'step' reporter is called with the on-step values at step k (energies,
temperatures, pressure, forces) after the step that leaves k, when k is a multiple of every (a
multiple of output.energy_every), and once more with last = True after run()'s last step; a
'state' reporter after the step to k + 1 when k + 1 is a multiple of every, to read the state
(positions, orientations, half-step velocities) from the simulation."""
import io
import math
import os

__all__ = ["Reporter", "CallbackReporter", "ThermoReporter"]


class Reporter:
    """Base class: set when and every, override report(sim, report)."""
    when = "step"

    def __init__(self, every, when=None):
        self.every = every
        if when is not None:
            self.when = when

    def report(self, sim, report):
        raise NotImplementedError

    def __repr__(self):
        return "%s(every=%r, when=%r)" % (type(self).__name__, self.every, self.when)


class CallbackReporter(Reporter):
    """A function fn(sim, report) as a reporter."""

    def __init__(self, fn, every, when="step"):
        super().__init__(every, when)
        self.fn = fn

    def report(self, sim, report):
        self.fn(sim, report)


class ThermoReporter(Reporter):
    """The rows of `rotleap run`'s PREFIX.thermo.csv, same columns, same number formats, every
    `every` steps (default: the deck's output.thermo_every) and the row of the last state.  calE,
    the running relative standard deviation of the conserved quantity, is taken over every step
    with energies, as `rotleap run` takes it.  `file`: a path or a text file object."""

    def __init__(self, file, every=None):
        super().__init__(every, "step")
        self._file = file
        self._f = None
        self._n, self._mean, self._m2 = 0, 0.0, 0.0

    def cadence(self, sim):
        """Called on every step with energies (for calE); rows every self.every steps."""
        if self.every is None:
            self.every = sim.thermo_every
        if isinstance(self.every, bool) or not isinstance(self.every, int) or self.every < 1 \
                or self.every % sim.energy_every:
            raise ValueError("ThermoReporter: every = %r must be a multiple of output.energy_every (%d)"
                             % (self.every, sim.energy_every))
        return sim.energy_every

    def _open(self, sim):
        if isinstance(self._file, (str, bytes, os.PathLike)):
            self._f = open(self._file, "w")
            self._own = True
        else:
            self._f = self._file
            self._own = False
        self._f.write("step,time,total,potential%s,ke_trans,ke_rot,temperature,t_trans,t_rot,pressure,conserved,"
                      "calE,t_trans_mid,t_rot_mid\n" % "".join("," + n for n in sim.energy_names))

    def report(self, sim, r):
        if self._f is None:
            self._open(sim)
        if not r.last:  # the running statistics of the conserved quantity (Welford, as runrec.c)
            self._n += 1
            d = r.conserved - self._mean
            self._mean += d / self._n
            self._m2 += d * (r.conserved - self._mean)
        if r.step % self.every and not r.last:
            return
        sd = math.sqrt(self._m2 / (self._n - 1)) if self._n > 1 else 0.0
        calE = sd / abs(self._mean) if self._n > 1 else 0.0
        row = "%d,%.10g,%.10g,%.10g" % (r.step, r.time, r.total, r.potential)
        row += "".join(",%.10g" % r.energies[n] for n in sim.energy_names)
        row += ",%.10g,%.10g,%.6g,%.6g,%.6g,%.10g,%.10g,%s,%.6g,%.6g\n" % (
            r.ke_trans, r.ke_rot, r.temperature, r.t_trans, r.t_rot, r.pressure, r.conserved, _c_e4(calE),
            r.t_trans_mid, r.t_rot_mid)
        self._f.write(row)
        if r.last:
            self._f.flush()

    def close(self):
        if self._f is not None and self._own:
            self._f.close()
        self._f = None


def _c_e4(x):
    """C's %.4e (Python's gives the same digits; the exponent has at least two digits in both)."""
    return "%.4e" % x
