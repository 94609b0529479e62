"""The same deck from Python and by `rotleap run`, one kind of deck each (barostats, a mixture,
PME, the Langevin thermostats, a molecule the deck defines): the ThermoReporter's file is rotleap
run's PREFIX.thermo.csv byte for byte, every optional column included (the barostat's volume,
density, edges and pressure tensor; each species' temperatures; each energy term), and the
CheckpointReporter's checkpoint (whose run record marks the thermo file and the analysis journal)
is rotleap run's PREFIX.chk byte for byte.  Short runs: a fraction of a second each."""
import pytest

import rotleap
from conftest import MIXTURE, cli_deck, example, run_cli

SHORT = cli_deck("stockmayer_short.ini")  # 64 Stockmayer dipoles, reduced units, NVE
NPT = {"system.count": 125, "run.ensemble": "nvt-bussi", "run.temperature": 1.35, "run.tau": 0.2,
       "run.pressure": 1.0, "run.timestep": 0.004, "run.steps": 40, "output.thermo_every": 5,
       "output.energy_every": 1, "output.checkpoint_every": 20}
LANGEVIN = {"system.count": 27, "interactions.cutoff": 1.4, "run.ensemble": "nvt-langevin", "run.temperature": 1.35,
            "run.tau": 0.2, "run.steps": 30, "output.thermo_every": 5}
ISOKINETIC = {k: v for k, v in LANGEVIN.items() if k != "run.tau"}

CASES = {
    # volume, density, Lx, Ly, Lz and the pressure tensor after the common columns
    "barostat-mc": (SHORT, dict(NPT, **{"run.barostat": "mc", "run.barostat_interval": 5})),
    "barostat-mc-anisotropic": (SHORT, dict(NPT, **{"run.barostat": "mc", "run.barostat_interval": 5,
                                                    "run.barostat_coupling": "anisotropic"})),
    "barostat-c-rescale": (SHORT, dict(NPT, **{"run.barostat": "c-rescale", "run.barostat_interval": 2,
                                               "run.tau_p": 0.5, "run.compressibility": 0.1})),
    # t_trans_NAME (and t_rot_NAME for a rotating species) of every species
    "mixture": (MIXTURE, {"system.species": "stockmayer:8 lj:24", "interactions.cutoff": 1.5, "run.steps": 30,
                          "output.thermo_every": 5, "output.checkpoint_every": 15}),
    # the Ewald energy terms ewald_recip, ewald_self, ewald_intra, ...
    "pme": (cli_deck("water_pme.ini"), {"run.equilibrate": 10, "run.steps": 10, "system.count": 32,
                                        "interactions.cutoff": "0.45 nm"}),
    "ewald": (cli_deck("water_pme.ini"), {"run.equilibrate": 10, "run.steps": 10, "system.count": 32,
                                          "interactions.cutoff": "0.45 nm", "interactions.coulomb": "ewald"}),
    # the other integrators of the rotation (quaternions; NO_SQUISH) on TIP4P
    "rl-quaternion": (example("tip4p.ini"), {"run.integrator": "rl-quaternion", "system.count": 64,
                                             "interactions.cutoff": "0.6 nm", "run.equilibrate": 10,
                                             "run.steps": 20, "output.thermo_every": 5}),
    "no-squish": (example("tip4p.ini"), {"run.integrator": "no-squish", "system.count": 64,
                                         "interactions.cutoff": "0.6 nm", "run.equilibrate": 10,
                                         "run.steps": 20, "output.thermo_every": 5}),
    "langevin": (SHORT, LANGEVIN),
    "langevin-dot": (SHORT, dict(LANGEVIN, **{"run.ensemble": "nvt-langevin-dot"})),
    "langevin-dot-obabo": (SHORT, dict(LANGEVIN, **{"run.ensemble": "nvt-langevin-dot-obabo"})),
    "isokinetic": (SHORT, dict(ISOKINETIC, **{"run.ensemble": "nvt-isokinetic", "run.equilibrate": 20})),
    # TIP4P written out site by site in a molecule file (an asymmetric top the deck defines)
    "user-molecule": (example("tip4p.ini"), {"system.model": "water", "system.molecules": cli_deck("tip4p_sites.mol"),
                                             "system.count": 64, "interactions.cutoff": "0.6 nm",
                                             "run.equilibrate": 10, "run.steps": 20, "output.thermo_every": 5}),
}
COLUMNS = {"barostat-mc": ",volume,density,Lx,Ly,Lz,Pxx,Pyy,Pzz,Pxy,Pxz,Pyz\n",
           "mixture": ",t_trans_stockmayer,t_rot_stockmayer,t_trans_lj\n",
           "pme": ",ewald_recip,ewald_self,ewald_intra,"}


def deck_path(tmp_path, deck):
    if "\n" not in deck:
        return deck
    path = tmp_path / "deck.ini"
    path.write_text(deck)
    return str(path)


@pytest.mark.parametrize("case", sorted(CASES))
def test_thermo_and_checkpoint_same_as_cli(cli, tmp_path, case):
    deck, sets = CASES[case]
    deck = deck_path(tmp_path, deck)
    run_cli(cli, deck, tmp_path, *["%s=%s" % kv for kv in sets.items()], "output.prefix=cli", "output.progress=no")
    sim = rotleap.Simulation(deck, set=sets)
    th = rotleap.ThermoReporter(str(tmp_path / "py.thermo.csv"))
    chk = rotleap.CheckpointReporter(tmp_path / "py.chk")
    sim.run(reporters=[th, chk])
    th.close()
    chk.close()
    cli_rows = (tmp_path / "cli.thermo.csv").read_text()
    assert len(cli_rows.splitlines()) >= 4
    if case in COLUMNS:
        assert COLUMNS[case] in cli_rows.splitlines(True)[0]
    assert (tmp_path / "py.thermo.csv").read_text() == cli_rows
    assert (tmp_path / "py.samples").read_bytes() == (tmp_path / "cli.samples").read_bytes()
    assert (tmp_path / "py.chk").read_bytes() == (tmp_path / "cli.chk").read_bytes()
