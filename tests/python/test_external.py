"""A force term written in Python (Simulation.add_external_force): a uniform electric field on
point dipoles (torque mu x E, energy -mu.E) and a harmonic wall in z, checked by finite
differences of its energy through the simulation, and a single dipole in a field against the
pendulum it is."""
import numpy as np
import pytest

import rotleap
from conftest import example

MU = 3 ** 0.5           # the Stockmayer example's dipole (reduced)
E = np.array([0.3, -0.2, 1.1])
KAPPA, Z0 = 0.7, 1.5


def field_and_wall(sim, forces, torques):
    mu = MU * sim.axes
    torques += np.cross(mu, E)
    z = sim.positions[:, 2] - Z0
    forces[:, 2] -= KAPPA * z
    return float(-(mu @ E).sum() + 0.5 * KAPPA * (z * z).sum())


def rotated(axis, about, angle):
    a = about / np.linalg.norm(about)
    return axis * np.cos(angle) + np.cross(a, axis) * np.sin(angle) + a * (a @ axis) * (1 - np.cos(angle))


def test_finite_differences_of_the_external_energy():
    sets = {"run.equilibrate": 0, "system.count": 108}
    sim = rotleap.Simulation(example("stockmayer.ini"), set=sets)
    twin = rotleap.Simulation(example("stockmayer.ini"), set=sets)  # the same state, no field
    sim.add_external_force(field_and_wall)
    assert "external" in sim.energy_names
    u0 = sim.energies()["external"]
    assert u0 == pytest.approx(field_and_wall(sim, np.zeros((108, 3)), np.zeros((108, 3))), rel=1e-14)
    f_ext = sim.forces - twin.forces
    k_ext = sim.torques - twin.torques
    h = 1e-5
    x0, r0 = sim.positions, sim.axes
    for i in (0, 17, 99):
        x = x0.copy()
        x[i, 2] += h
        sim.positions = x
        up = sim.energies()["external"]
        x[i, 2] -= 2 * h
        sim.positions = x
        um = sim.energies()["external"]
        assert -(up - um) / (2 * h) == pytest.approx(f_ext[i, 2], rel=1e-7, abs=1e-9)
        sim.positions = x0
        for about in (np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), np.array([0.3, 0.5, -0.8])):
            r = r0.copy()
            r[i] = rotated(r0[i], about, h)
            sim.axes = r
            up = sim.energies()["external"]
            r[i] = rotated(r0[i], about, -h)
            sim.axes = r
            um = sim.energies()["external"]
            # dU/dangle = -torque . axis of rotation
            assert -(up - um) / (2 * h) == pytest.approx(k_ext[i] @ about / np.linalg.norm(about), rel=1e-7, abs=1e-9)
        sim.axes = r0
    sim.step(20)  # the dynamics with it
    assert np.isfinite(sim.energies()["external"])


def test_single_dipole_in_a_field():
    """A dipole of inertia I in a field E is a pendulum: its conserved energy is -mu E cos(theta0)
    (started at rest at theta0), and a small angle oscillates at omega = sqrt(mu E / I)."""
    Emag, inertia, theta0, h = 1.0, 0.025, 0.05, 0.002
    sim = rotleap.Simulation.from_model("stockmayer", 1, box=10.0, params={"mu": MU, "inertia": inertia},
                                        set={"interactions.cutoff": 2.5, "run.timestep": h, "run.steps": 1000,
                                             "run.equilibrate": 0, "system.temperature": 1.0})
    sim.velocities = np.zeros((1, 3))
    sim.angular_momenta = np.zeros((1, 3))
    sim.axes = np.array([[np.sin(theta0), 0.0, np.cos(theta0)]])
    field = np.array([0.0, 0.0, Emag])

    def dipole_in_field(s, forces, torques):
        mu = MU * s.axes
        torques += np.cross(mu, field)
        return float(-(mu @ field).sum())

    sim.add_external_force(dipole_in_field)
    omega = np.sqrt(MU * Emag / inertia)
    worst_theta, worst_e = 0.0, 0.0
    for k in range(1, 400):
        sim.step(1)
        r = sim.report()
        rho = sim.axes[0]
        theta = np.arctan2(rho[0], rho[2])
        assert r.energies["external"] == pytest.approx(-MU * Emag * np.cos(np.arccos(rho[2])), rel=1e-13)
        worst_e = max(worst_e, abs(r.conserved - (-MU * Emag * np.cos(theta0))))
        # at rest at t = -h/2 (the leapfrog's l(t - h/2) = 0): theta0 cos(omega (t + h/2)) / cos(omega h/2)
        worst_theta = max(worst_theta, abs(theta - theta0 * np.cos(omega * (k + 0.5) * h) / np.cos(omega * h / 2)))
    assert worst_e < 1e-6 * MU * Emag
    # small-angle pendulum over one period: its period correction (theta0/4)^2 = 1.6e-4 and the
    # leapfrog's (omega h)^2/24 = 1.2e-5 shift the phase by 1e-3 rad at most
    assert worst_theta < 2e-3 * theta0
    assert abs(sim.axes[0, 1]) < 1e-14   # it swings in its plane


def test_external_force_wrong_use():
    sim = rotleap.Simulation(example("stockmayer.ini"), set={"run.equilibrate": 0, "system.count": 108})
    with pytest.raises(TypeError, match="fn\\(sim, forces, torques\\)"):
        sim.add_external_force(42)

    class Boom(Exception):
        pass

    calls = []

    def sometimes(s, f, k):
        calls.append(1)
        if len(calls) == 5:
            raise Boom("in the field")
        return 0.0

    sim.add_external_force(sometimes)
    with pytest.raises(Boom, match="in the field"):
        sim.step(10)
    with pytest.raises(rotleap.Error, match="external force already"):
        sim.add_external_force(lambda s, f, k: 0.0)
    bad = rotleap.Simulation(example("stockmayer.ini"), set={"run.equilibrate": 0, "system.count": 108})
    with pytest.raises(TypeError, match="its energy"):
        bad.add_external_force(lambda s, f, k: None)
    nan = rotleap.Simulation(example("stockmayer.ini"), set={"run.equilibrate": 0, "system.count": 108})
    with pytest.raises(ValueError, match="not finite"):
        nan.add_external_force(lambda s, f, k: float("nan"))
