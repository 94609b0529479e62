"""rotleap: molecular dynamics of rigid molecules with Omelyan's revised angular-momentum leapfrog.

    import rotleap
    sim = rotleap.Simulation("examples/stockmayer.ini", set={"run.equilibrate": 0})
    sim.run(1000, reporters=[rotleap.CallbackReporter(lambda s, r: print(r.step, r.potential), every=100)])

docs/python.md describes the interface."""
from ._native import lib as _lib
from .simulation import Error, Report, Simulation
from .reporters import CallbackReporter, CheckpointReporter, Reporter, ThermoReporter, TrajectoryReporter
from .catalog import Model, catalog
from .scan import ScanResult, scan
from .interop import from_openmm, to_mdtraj, to_openmm

__version__ = _lib.rlpy_version().decode()
__all__ = ["Error", "Report", "Simulation", "Reporter", "CallbackReporter", "ThermoReporter", "TrajectoryReporter", "CheckpointReporter", "Model", "catalog", "scan", "ScanResult", "to_mdtraj", "to_openmm", "from_openmm"]
