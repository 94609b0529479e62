"""Interop: a trajectory as an mdtraj.Trajectory, and rigid water to and from OpenMM with the
same single-point energy (OpenMM's Reference platform, double precision: 1e-9 relative, as
validate/single_point.py and validate/ewald_openmm.py take it)."""
import numpy as np
import pytest

import rotleap
from conftest import example

# the default example's water, 20 relaxation steps from its lattice: plain LJ cut site by site
WATER = {"run.equilibrate": 20, "run.steps": 40, "system.count": 125, "interactions.cutoff": 0.7}


def omm_energy(system, positions):
    mm = pytest.importorskip("openmm")
    ctx = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName("Reference"))
    ctx.setPositions(positions)
    ctx.computeVirtualSites()
    moved = np.abs(ctx.getState(getPositions=True).getPositions(asNumpy=True).value_in_unit(mm.unit.nanometer)
                   - positions).max()
    assert moved < 1e-12  # OpenMM's M where rotleap has it
    return ctx.getState(getEnergy=True).getPotentialEnergy().value_in_unit(mm.unit.kilojoule_per_mole)


@pytest.mark.parametrize("sets", [{}, {"interactions.eps_rf": "inf"},
                                  {"interactions.coulomb": "pme", "interactions.ewald_tolerance": 5e-4}],
                         ids=["rf", "rf-inf", "pme"])
def test_openmm_single_point_and_back(sets):
    pytest.importorskip("openmm")
    text = open(example("tip4p.ini")).read()
    if "interactions.coulomb" in sets:  # the deck's eps_rf is for the reaction field only
        text = "\n".join(line for line in text.splitlines() if not line.startswith("eps_rf")) + "\n"
    sim = rotleap.Simulation(text=text, set=dict(WATER, **sets))
    system, pos = rotleap.to_openmm(sim)
    assert system.getNumParticles() == 4 * 125 and system.getNumConstraints() == 3 * 125 and system.isVirtualSite(3)
    u_rl = sim.energies()["potential"]
    u_omm = omm_energy(system, pos)
    assert abs(u_rl - u_omm) <= 1e-9 * abs(u_omm), (u_rl, u_omm)
    back = rotleap.from_openmm(system, pos, set={"run.steps": 10})
    assert back.model == "tip4p" and back.count == 125 and np.array_equal(back.box, sim.box)
    a, b = sim.interactions(), back.interactions()  # the deck's settings come back
    keys = ["cutoff", "scheme", "lj", "dispersion_correction", "coulomb"]
    keys.append("eps_rf" if a["coulomb"] == "rf" else "ewald_tolerance")
    assert {k: b[k] for k in keys} == {k: a[k] for k in keys}
    assert np.abs(back.site_positions() - sim.site_positions()).max() < 1e-12
    assert back.energies()["potential"] == pytest.approx(u_rl, rel=1e-11)
    back.step(10)


def test_openmm_wrong_use():
    pytest.importorskip("openmm")
    with pytest.raises(ValueError, match="reduced units"):
        rotleap.to_openmm(rotleap.Simulation(example("stockmayer.ini"), set={"run.equilibrate": 0}))
    with pytest.raises(ValueError, match="scheme = molecule"):
        rotleap.to_openmm(rotleap.Simulation(example("tip4p.ini"), set=dict(WATER, **{"interactions.scheme": "molecule"})))


def test_mdtraj_trajectory(tmp_path):
    md = pytest.importorskip("mdtraj")
    sim = rotleap.Simulation(example("tip4p.ini"), set=WATER)
    tr = rotleap.TrajectoryReporter(tmp_path / "w.dcd", every=10)
    sim.run(reporters=[tr])
    with pytest.raises(ValueError, match="close"):
        rotleap.to_mdtraj(tr)
    tr.close()
    t = rotleap.to_mdtraj(tr)
    assert isinstance(t, md.Trajectory)
    assert t.n_frames == 4 and t.n_atoms == 4 * 125 and t.topology.n_residues == 125
    # the last frame is the state the run ended in (DCD: single precision, Angstrom)
    assert np.abs(t.xyz[-1] - sim.site_positions().reshape(-1, 3)).max() < 2e-6
    assert np.allclose(t.unitcell_lengths[-1], sim.box, rtol=1e-6)
    xyz = rotleap.TrajectoryReporter(tmp_path / "s.xyz", every=10)
    s2 = rotleap.Simulation(example("stockmayer.ini"), set={"run.equilibrate": 0, "run.steps": 10})
    s2.run(reporters=[xyz])
    xyz.close()
    with pytest.raises(ValueError, match="extended XYZ"):
        rotleap.to_mdtraj(xyz)
