"""rotleap from Python: the same runs as `rotleap run`, reporters on their steps, the state as
arrays, and every wrong use a clear exception."""
import os
import signal
import threading
import time
import warnings

import numpy as np
import pytest

import rotleap
from conftest import MIXTURE, cli_deck, example, run_cli

# short versions of the examples: Stockmayer (point dipoles, reduced units, Bussi) and TIP4P
# (asymmetric tops, real units, Bussi; pressure in bar), each with its relaxation
STOCKMAYER = {"run.steps": 300, "run.equilibrate": 100}
TIP4P = {"run.steps": 60, "run.equilibrate": 20, "output.thermo_every": 10, "output.energy_every": 2}
NVE = {"run.steps": 200, "run.equilibrate": 50, "output.thermo_every": 20, "output.energy_every": 5}


def nve_deck(tmp_path):
    """stockmayer.ini as an NVE run from system.temperature (the run's thermostat keys dropped)."""
    text = open(example("stockmayer.ini")).read()
    for key in ("ensemble", "temperature", "tau"):
        text = text.replace("\n%s = " % key, "\n; %s = " % key)
    text = text.replace("[system]\n", "[system]\ntemperature = 1.35\n")
    path = tmp_path / "nve.ini"
    path.write_text(text)
    return str(path)


def sets_of(d):
    return ["%s=%s" % kv for kv in d.items()]


def small_sim(**extra):
    s = dict(STOCKMAYER)
    s.update(extra)
    return rotleap.Simulation(example("stockmayer.ini"), set=s)


def test_import():
    assert rotleap.__version__ == "0.1.0"
    for name in rotleap.__all__:
        assert hasattr(rotleap, name)


def checkpoint_parts(path):
    """A checkpoint file (docs/files.md) as its header, state section and run record sections
    {tag: bytes}."""
    data = path.read_bytes()
    magic = b"rotleap-run-5"
    m = data.index(magic)
    size = int.from_bytes(data[m - 8:m], "little")
    blob, sections, at = data[m:m + size], {}, 16
    while at < len(blob):
        tag, n = blob[at:at + 4].decode(), int.from_bytes(blob[at + 4:at + 12], "little")
        sections[tag] = blob[at + 12:at + 12 + n]
        at += 12 + n
    return data[:16], data[24:m - 8], sections


@pytest.mark.parametrize("deck,sets", [("stockmayer.ini", STOCKMAYER), ("tip4p.ini", TIP4P),
                                       ("nve", NVE)], ids=["stockmayer", "tip4p", "stockmayer-nve"])
def test_same_run_as_cli(cli, tmp_path, deck, sets):
    """The deck run by rotleap run and from Python with the built-in reporters: thermo,
    trajectory and checkpoint files byte for byte (the checkpoint's run record marks the
    thermo, trajectory, topology and analysis-journal streams as rotleap run marks its own);
    the final state (read back from rotleap run's checkpoint) bit for bit."""
    deck = nve_deck(tmp_path) if deck == "nve" else example(deck)
    sets = dict(sets, **{"output.trajectory_every": 20, "output.checkpoint_every": 40})
    run_cli(cli, deck, tmp_path, *sets_of(sets), "output.prefix=cli")
    sim = rotleap.Simulation(deck, set=sets)
    th = rotleap.ThermoReporter(str(tmp_path / "py.thermo.csv"))
    ext = "dcd" if sim.kind not in ("dipole", "linear", "point") else "xyz"
    tr = rotleap.TrajectoryReporter(tmp_path / ("py." + ext))
    chk = rotleap.CheckpointReporter(tmp_path / "py.chk")
    mid = []  # the checkpoint written at step 40, kept by a reporter called after chk's
    keep = rotleap.CallbackReporter(lambda s, r: mid.append(checkpoint_parts(tmp_path / "py.chk")), 40, "state")
    sim.run(reporters=[th, tr, chk, keep])
    th.close()
    tr.close()
    chk.close()
    cli_rows = (tmp_path / "cli.thermo.csv").read_text()
    assert (tmp_path / "py.thermo.csv").read_text() == cli_rows
    assert len(cli_rows.splitlines()) > 3
    assert (tmp_path / ("py." + ext)).read_bytes() == (tmp_path / ("cli." + ext)).read_bytes()
    if ext == "dcd":
        assert (tmp_path / "py.pdb").read_bytes() == (tmp_path / "cli.pdb").read_bytes()
    assert (tmp_path / "py.samples").read_bytes() == (tmp_path / "cli.samples").read_bytes()
    _, _, rec_c = checkpoint_parts(tmp_path / "cli.chk")
    assert {"MARK", "BOOK", "PHYS"} <= set(rec_c)
    assert (tmp_path / "py.chk").read_bytes() == (tmp_path / "cli.chk").read_bytes()
    assert mid and mid[0][1] != checkpoint_parts(tmp_path / "cli.chk")[1]  # step 40's was another state
    assert int.from_bytes(mid[0][2]["BOOK"][-24:-16], "little") == 40  # its run record's steps done
    back = rotleap.Simulation(deck, set=dict(sets, **{"system.start": str(tmp_path / "cli.chk")}))
    assert back.current_step == sim.current_step == sets["run.steps"]
    quantities = ["positions", "velocities", "angular_momenta"]
    quantities.append("axes" if sim.kind in ("dipole", "linear") else "orientations")
    for q in quantities:
        a, b = getattr(sim, q), getattr(back, q)
        assert a.shape == b.shape and a.size > 0
        assert np.array_equal(a, b), q


def test_reporters_called_at_their_steps():
    sim = small_sim(**{"output.energy_every": 5})
    seen = {"step": [], "state": [], "last": []}

    def on_step(s, r):
        (seen["last"] if r.last else seen["step"]).append(r.step)
        assert r.kind == "step" and np.isfinite(r.potential) and set(r.energies) == set(s.energy_names)
        assert r.forces().shape == (s.count, 3)

    def on_state(s, r):
        assert r.kind == "state" and s.current_step == r.step  # the state after the step
        seen["state"].append(r.step)

    reps = [rotleap.CallbackReporter(on_step, every=20), rotleap.CallbackReporter(on_state, every=7, when="state")]
    sim.run(100, reporters=reps)
    assert seen["step"] == list(range(0, 100, 20))
    assert seen["last"] == [100]
    assert seen["state"] == list(range(7, 101, 7))
    for v in seen.values():
        v.clear()
    sim.run(50, reporters=reps)  # steps are counted on: 100..149
    assert seen["step"] == [100, 120, 140] and seen["last"] == [150]
    assert seen["state"] == [105, 112, 119, 126, 133, 140, 147]


def test_split_runs_and_state_round_trip_are_bitwise():
    """run(150) = run(100) + run(50) = step(100), every array read and set back, step(50)."""
    a = small_sim()
    a.run(150)
    b = small_sim()
    b.run(100)
    b.run(50)
    c = small_sim()
    c.step(100)
    for q in ("positions", "velocities", "angular_momenta", "axes"):
        setattr(c, q, getattr(c, q))
    c.step(50)
    for q in ("positions", "velocities", "angular_momenta", "axes", "forces", "torques"):
        assert np.array_equal(getattr(a, q), getattr(b, q)), q
        assert np.array_equal(getattr(a, q), getattr(c, q)), q
    assert a.energies() == b.energies() == c.energies()


def test_state_arrays_are_copies_and_setters_apply():
    sim = small_sim()
    x = sim.positions
    x[0, 0] += 1e-3
    assert sim.positions[0, 0] != x[0, 0]  # a copy
    sim.positions = x
    assert sim.positions[0, 0] == x[0, 0]
    f_new = sim.forces  # forces at the new state
    sim.step(1)
    assert np.isfinite(f_new).all()
    e = sim.energies()
    assert set(e) >= {"potential", "kinetic", "total", "lj", "dipolar"}
    assert e["total"] == pytest.approx(e["potential"] + e["kinetic"], rel=1e-12)
    assert np.isfinite(sim.pressure)
    tip = rotleap.Simulation(example("tip4p.ini"), set={"run.equilibrate": 0})
    A = tip.orientations
    assert A.shape == (216, 3, 3)
    assert np.allclose(A @ A.transpose(0, 2, 1), np.eye(3), atol=1e-12)
    assert tip.torques.shape == (216, 3) and tip.angular_momenta.shape == (216, 3)
    B = A.copy()
    B[2] *= 1.01
    with pytest.raises(rotleap.Error, match="body 2"):
        tip.orientations = B
    assert np.array_equal(tip.orientations, A)  # left as it was
    with pytest.raises(ValueError, match=r"expected \(216, 3, 3\)"):
        tip.orientations = A.reshape(216, 9)
    with pytest.raises(rotleap.Error, match="no axis: use orientations"):
        tip.axes


def test_deck_text():
    text = open(example("stockmayer.ini")).read()
    sim = rotleap.Simulation(text=text, set={"run.equilibrate": 0, "system.count": 108})
    assert sim.count == 108 and sim.model == "stockmayer" and sim.units == "lj"
    sim.step(10)
    assert sim.current_step == 10


def test_wrong_use_raises():
    sim = small_sim()
    n = sim.count
    with pytest.raises(ValueError, match=r"shape \(3,\), expected \(%d, 3\)" % n):
        sim.positions = np.zeros(3)
    with pytest.raises(TypeError, match="real numbers"):
        sim.velocities = np.zeros((n, 3), dtype=complex)
    with pytest.raises(TypeError, match="real numbers"):
        sim.positions = [["a", "b", "c"]] * n
    bad = sim.velocities
    bad[5, 1] = np.nan
    with pytest.raises(ValueError, match=r"element \(5, 1\) is nan, not finite"):
        sim.velocities = bad
    with pytest.raises(rotleap.Error, match="no orientation matrix: use axes"):
        sim.orientations
    ax = sim.axes
    ax[3] *= 2.0
    with pytest.raises(rotleap.Error, match="body 3"):
        sim.axes = ax
    with pytest.raises(AttributeError):
        sim.forces = np.zeros((n, 3))
    with pytest.raises(ValueError, match="0 or more"):
        sim.step(-1)
    with pytest.raises(TypeError, match="whole number"):
        sim.step(2.5)
    with pytest.raises(ValueError, match="multiple of output.energy_every"):
        small_sim(**{"output.energy_every": 10}).run(10, reporters=[rotleap.CallbackReporter(lambda s, r: None, 5)])
    with pytest.raises(TypeError, match="when = 'step' or 'state'"):
        sim.run(10, reporters=[object()])
    with pytest.raises(rotleap.Error, match="unknown key 'temprature'"):
        rotleap.Simulation(text="[system]\nmodel = stockmayer\ntemprature = 3\n")
    with pytest.raises(rotleap.Error, match="nope.ini"):
        rotleap.Simulation("nope.ini")
    with pytest.raises(TypeError):
        rotleap.Simulation()
    # a reporter that raises stops the run with its exception, at its step
    class Boom(Exception):
        pass

    def boom(s, r):
        if r.step == 40:
            raise Boom("at 40")

    with pytest.raises(Boom, match="at 40"):
        sim.run(100, reporters=[rotleap.CallbackReporter(boom, every=10)])
    assert sim.current_step == 41
    # a reporter may read the simulation, not step or change it
    def nested(s, r):
        s.step(1)

    with pytest.raises(rotleap.Error, match="running"):
        sim.run(10, reporters=[rotleap.CallbackReporter(nested, every=10)])
    kept = []
    sim.run(10, reporters=[rotleap.CallbackReporter(lambda s, r: kept.append(r), every=10)])
    with pytest.raises(rotleap.Error, match="during a step reporter's call"):
        kept[0].forces()
    sim.step(3)  # still usable after all of that
    sim.close()
    for use in (lambda: sim.step(1), lambda: sim.run(1), lambda: sim.positions, lambda: sim.energies()):
        with pytest.raises(rotleap.Error, match="closed"):
            use()
    sim.close()  # twice is fine


def test_gil_released_while_stepping():
    sim = small_sim()
    count = [0]
    stop = threading.Event()

    def spin():
        while not stop.is_set():
            count[0] += 1

    t = threading.Thread(target=spin)
    t.start()
    try:
        c0 = count[0]
        sim.step(400)  # no Python runs in these steps: the other thread counts only if the GIL is free
        c1 = count[0]
    finally:
        stop.set()
        t.join()
    assert c1 - c0 > 1000


def test_ctrl_c_stops_a_run_cleanly():
    # the handler before the run: Python's default_int_handler, or SIG_IGN when the tests run in
    # a background job (a shell starts those with SIGINT ignored, as a CI runner may)
    before = signal.getsignal(signal.SIGINT)
    sim = small_sim()
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    t0 = time.time()
    with pytest.raises(KeyboardInterrupt, match="stopped at step"):
        sim.step(10 ** 8)
    assert time.time() - t0 < 30
    k = sim.current_step
    assert 0 < k < 10 ** 8
    sim.step(5)  # usable afterwards, and the handler that was there before is back
    assert sim.current_step == k + 5
    assert signal.getsignal(signal.SIGINT) is before


def test_catalogue_and_from_model():
    cat = rotleap.catalog()
    assert "tip4p" in cat and "stockmayer" in cat
    w = cat["tip4p"]
    assert w.units == "real" and w.family == "asymmetric" and w.site_names == ("O", "H1", "H2", "M")
    assert w.charge.sum() == pytest.approx(0.0, abs=1e-12) and w.mass == pytest.approx(18.0154)
    assert w.sites.shape == (4, 3) and (w.inertia > 0).all()
    assert cat["stockmayer"].params["mu"][0] == pytest.approx(3 ** 0.5)
    # the same system from a model, a count and a box as from the deck that names them
    text = open(example("stockmayer.ini")).read()
    sets = {"run.equilibrate": 0, "run.steps": 20}
    a = rotleap.Simulation(text=text, set=sets)
    keys = {"interactions.cutoff": 2.5, "interactions.lj": "shifted-force", "interactions.dipole": "sf",
            "run.ensemble": "nvt-bussi", "run.temperature": 1.35, "run.tau": 0.2, "run.timestep": 0.002,
            "system.orientations": "random"}
    keys.update(sets)
    b = rotleap.Simulation.from_model("stockmayer", 256, density=0.8, params={"mu": 1.7320508, "inertia": 0.025},
                                      set=keys)
    a.run()
    b.run()
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.axes, b.axes)
    with pytest.raises(rotleap.Error, match="no-such-model"):
        rotleap.Simulation.from_model("no-such-model", 10, box=3, set=keys)


def test_rotleap_run_continues_a_python_checkpoint(cli, tmp_path):
    """The built-in reporters' files are a run `rotleap run` continues: 150 steps from Python (in
    two calls) with thermo, trajectory and checkpoint (and its journal) under the names of
    output.prefix = py, the rest by rotleap run from py.chk under that prefix, give every file of
    300 steps of rotleap run byte for byte, results included (the journal is replayed).  Under
    another prefix, rotleap run continues the state and the averages bit for bit."""
    deck = example("stockmayer.ini")
    sets = dict(STOCKMAYER, **{"output.trajectory_every": 20, "output.checkpoint_every": 40})
    run_cli(cli, deck, tmp_path, *sets_of(sets), "output.prefix=whole")
    sim = rotleap.Simulation(deck, set=sets)
    reps = [rotleap.ThermoReporter(str(tmp_path / "py.thermo.csv")), rotleap.TrajectoryReporter(tmp_path / "py.xyz"),
            rotleap.CheckpointReporter(tmp_path / "py.chk")]
    sim.run(100, reporters=reps)
    sim.run(50, reporters=reps)  # the first call's row of the last state is replaced by step 100's
    for r in reps:
        r.close()
    run_cli(cli, deck, tmp_path, *sets_of(sets), "system.start=py.chk", "output.prefix=cont")
    _, whole, rec_w = checkpoint_parts(tmp_path / "whole.chk")
    _, cont, rec_c = checkpoint_parts(tmp_path / "cont.chk")
    assert cont == whole
    assert rec_c["BOOK"] == rec_w["BOOK"]  # the averages over the whole run, the thermostat's account
    run_cli(cli, deck, tmp_path, *sets_of(sets), "system.start=py.chk", "output.prefix=py")
    for ext in ("thermo.csv", "xyz", "samples", "results.txt", "tcf.csv", "chk"):
        assert (tmp_path / ("py." + ext)).read_bytes() == (tmp_path / ("whole." + ext)).read_bytes(), ext




# 64 Stockmayer dipoles (reduced units) under each kind of random stream a run record carries
CONTINUE = {"system.count": 64, "run.ensemble": "nvt-bussi", "run.temperature": 1.35, "run.tau": 0.2,
            "run.timestep": 0.004, "output.thermo_every": 5, "output.energy_every": 1}
CONTINUE_CASES = {"bussi": {}, "langevin": {"run.ensemble": "nvt-langevin"},
                  "barostat-mc": {"run.barostat": "mc", "run.pressure": 1.0, "run.barostat_interval": 5},
                  "barostat-c-rescale": {"run.barostat": "c-rescale", "run.pressure": 1.0, "run.barostat_interval": 2,
                                         "run.tau_p": 0.5, "run.compressibility": 0.1}}


@pytest.mark.parametrize("case", sorted(CONTINUE_CASES))
def test_python_continues_a_rotleap_run_checkpoint(cli, tmp_path, case):
    """A Simulation started from `rotleap run`'s checkpoint at step 30 continues that run with its
    run record (the thermostat's random stream and account, the barostat's stream and trial
    size, the neighbour list's origin, the averages): 30 more steps from Python give rotleap run's
    60-step state bit for bit, and a checkpoint whose BOOK (averages, thermostat account), RNG and
    OPST (the barostat's state) sections are rotleap run's.  (Before, the state went on without
    the record: the random streams started again from the seed.)"""
    deck = cli_deck("stockmayer_short.ini")
    sets = dict(CONTINUE, **CONTINUE_CASES[case])
    run_cli(cli, deck, tmp_path, *sets_of(sets), "run.steps=60", "output.prefix=whole")
    run_cli(cli, deck, tmp_path, *sets_of(sets), "run.steps=30", "output.prefix=half")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the same settings: nothing to note
        sim = rotleap.Simulation(deck, set=dict(sets, **{"run.steps": 60, "system.start": str(tmp_path / "half.chk")}))
    assert sim.current_step == 30
    chk = rotleap.CheckpointReporter(tmp_path / "py.chk", journal=False)
    sim.run(30, reporters=[chk])
    chk.close()
    _, whole, rec_w = checkpoint_parts(tmp_path / "whole.chk")
    _, py, rec_p = checkpoint_parts(tmp_path / "py.chk")
    assert py == whole
    for tag in ("BOOK", "RNG ", "OPST", "LIST"):
        assert rec_p.get(tag) == rec_w.get(tag), tag
    assert "RNG " in rec_w and ("OPST" in rec_w) == case.startswith("barostat")


def test_checkpoint_of_other_settings_starts_a_new_run(cli, tmp_path):
    """As rotleap run under another prefix: a checkpoint of other settings gives its state to a
    new run from step 0, with a warning naming the setting; a new run.seed continues the run with
    a new random stream, with a warning; a checkpoint that is not one is an Error naming it."""
    deck = cli_deck("stockmayer_short.ini")
    run_cli(cli, deck, tmp_path, *sets_of(CONTINUE), "run.steps=30", "output.prefix=half")
    start = {"run.steps": 60, "system.start": str(tmp_path / "half.chk")}
    with pytest.warns(RuntimeWarning, match=r"other settings \(run.tau: 0.2 reduced -> 0.5 reduced\): a new run from its state"):
        sim = rotleap.Simulation(deck, set=dict(CONTINUE, **start, **{"run.tau": 0.5}))
    assert sim.current_step == 0
    with pytest.warns(RuntimeWarning, match=r"run.seed = 7 differs .* new random stream from seed 7"):
        sim = rotleap.Simulation(deck, set=dict(CONTINUE, **start, **{"run.seed": 7}))
    assert sim.current_step == 30
    (tmp_path / "bad.chk").write_bytes((tmp_path / "half.chk").read_bytes()[:-40])
    with pytest.raises(rotleap.Error, match="bad.chk"):
        rotleap.Simulation(deck, set=dict(CONTINUE, **dict(start, **{"system.start": str(tmp_path / "bad.chk")})))


def test_mixture_same_run_as_cli(cli, tmp_path):
    """A mixture (Stockmayer dipoles in an LJ solvent) from Python: the analysis journal (which
    holds the box dipole moment, summed over the species that carry one: the binding gave the
    analysis the first species' molecule for every species, and stopped at the first sample) and
    the final state bit for bit those of rotleap run (its thermo file: test_thermo.py)."""
    deck = tmp_path / "mix.ini"
    deck.write_text(MIXTURE)
    run_cli(cli, str(deck), tmp_path, "output.prefix=cli")
    sim = rotleap.Simulation(str(deck))
    chk = rotleap.CheckpointReporter(tmp_path / "py.chk")
    sim.run(reporters=[chk])
    chk.close()
    assert (tmp_path / "py.samples").stat().st_size > 1000
    assert (tmp_path / "py.samples").read_bytes() == (tmp_path / "cli.samples").read_bytes()
    back = rotleap.Simulation(str(deck), set={"system.start": str(tmp_path / "cli.chk")})
    assert back.current_step == sim.current_step == 60
    for q in ("positions", "velocities", "angular_momenta"):
        assert np.array_equal(getattr(sim, q), getattr(back, q)), q
