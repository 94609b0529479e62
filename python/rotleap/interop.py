"""Interop: trajectories as mdtraj.Trajectory; rigid-water systems to and from OpenMM.

Neither mdtraj nor OpenMM is needed to import rotleap: each function imports its package when it
is called, and raises ImportError saying which Debian package provides it."""
import math

import numpy as np

__all__ = ["to_mdtraj", "to_openmm", "from_openmm"]


def _need(name, debian):
    try:
        return __import__(name)
    except ImportError as e:
        raise ImportError("rotleap.%s needs %s (Debian: apt-get install %s)" % (
            "to_mdtraj" if name == "mdtraj" else "to_openmm/from_openmm", name, debian)) from e


def to_mdtraj(trajectory, topology=None):
    """An mdtraj.Trajectory of a DCD trajectory: a finished (closed) rotleap.TrajectoryReporter
    in DCD format (its PDB topology with it), or the path of a DCD (rotleap run's PREFIX.dcd)
    with `topology` (PREFIX.pdb).  Coordinates in nm, the box as unit cells, times in ps."""
    md = _need("mdtraj", "python3-mdtraj")
    from .reporters import TrajectoryReporter
    if isinstance(trajectory, TrajectoryReporter):
        if trajectory.format != "dcd":
            raise ValueError("to_mdtraj: %s is an extended XYZ (point dipoles or atoms): mdtraj reads the DCD "
                             "of site models" % trajectory.path)
        if trajectory._t is not None:
            raise ValueError("to_mdtraj: close() the TrajectoryReporter first (the DCD header counts its frames)")
        path = trajectory.path
        topology = topology or trajectory.topology or (path[:-4] if path.endswith(".dcd") else path) + ".pdb"
    else:
        path = str(trajectory)
        if topology is None:
            raise ValueError("to_mdtraj(%r): give the topology (the PDB rotleap run writes beside its DCD)" % path)
    return md.load_dcd(path, top=str(topology))


def _water(sim):
    """The molecule's OpenMM description: site masses, charges, sigma, epsilon, virtual-site
    weights of each massless site on the first three, and the constraints (i, j, length)."""
    m = sim.molecule()
    mass, s = m["site_mass"], m["sites"]
    if (m["dipole"] != 0).any() or (m["quadrupole"] != 0).any():
        raise ValueError("to_openmm: point dipoles and quadrupoles have no NonbondedForce counterpart")
    heavy = [a for a in range(len(s)) if mass[a] > 0]
    if heavy != [0, 1, 2]:
        raise ValueError("to_openmm: rigid water (three massive sites first, massless sites after) only; %s has "
                         "massive sites %s" % (sim.model, heavy))
    vsites = {}
    for a in range(3, len(s)):
        # s_a = w0 s0 + w1 s1 + w2 s2 with w0 + w1 + w2 = 1, in the plane of the three
        M = np.vstack([np.array([s[0], s[1], s[2]]).T, np.ones(3)])
        w, *_ = np.linalg.lstsq(M, np.append(s[a], 1.0), rcond=None)
        if np.abs(M @ w - np.append(s[a], 1.0)).max() > 1e-12:
            raise ValueError("to_openmm: site %s is not in the plane of the first three" % m["site_names"][a])
        vsites[a] = w
    cons = [(i, j, float(np.linalg.norm(s[i] - s[j]))) for i, j in ((0, 1), (0, 2), (1, 2))]
    return m, vsites, cons


def to_openmm(sim):
    """(openmm.System, positions) of a rigid-water simulation: its sites as particles with the
    model's masses (massless sites as ThreeParticleAverageSite virtual sites), O-H, O-H and H-H
    constraints, and a NonbondedForce as the deck says: reaction field (CutoffPeriodic with
    eps_rf; inf as 1e30) or PME (tin foil; the deck's alpha and grid, or its tolerance, from
    which OpenMM 7.7 derives the same alpha and grid as rotleap), every intramolecular pair
    excluded, plain LJ without switch, the dispersion correction as the deck says.  positions:
    (n * nsites, 3) numpy array in nm (the sites of the current state).  Requires
    interactions.scheme = site, lj = plain, and an orthorhombic box."""
    mm = _need("openmm", "python3-openmm")
    if sim.units != "real":
        raise ValueError("to_openmm: the system is in reduced units; OpenMM's are real (nm, kJ/mol, e)")
    ia = sim.interactions()
    if ia["scheme"] != "site" or ia["lj"] != "plain":
        raise ValueError("to_openmm: OpenMM's NonbondedForce cuts site by site with plain LJ: the deck has "
                         "interactions.scheme = %s, lj = %s (site, plain needed)" % (ia["scheme"], ia["lj"]))
    if ia["coulomb"] == "ewald":
        raise ValueError("to_openmm: interactions.coulomb = ewald: use rf or pme")
    if ia["coulomb"] == "pme" and (not math.isinf(ia["ewald_boundary"]) or ia["pme_order"] not in (0, 5)):
        raise ValueError("to_openmm: OpenMM's PME has tin-foil boundaries and B-spline order 5")
    m, vsites, cons = _water(sim)
    ns, n = len(m["sites"]), sim.count
    L = sim.box
    system = mm.System()
    system.setDefaultPeriodicBoxVectors(mm.Vec3(L[0], 0, 0), mm.Vec3(0, L[1], 0), mm.Vec3(0, 0, L[2]))
    nb = mm.NonbondedForce()
    nb.setCutoffDistance(ia["cutoff"])
    nb.setUseSwitchingFunction(False)
    nb.setUseDispersionCorrection(ia["dispersion_correction"])
    if ia["coulomb"] == "rf":
        nb.setNonbondedMethod(mm.NonbondedForce.CutoffPeriodic)
        nb.setReactionFieldDielectric(1e30 if math.isinf(ia["eps_rf"]) else ia["eps_rf"])
    else:
        nb.setNonbondedMethod(mm.NonbondedForce.PME)
        nb.setEwaldErrorTolerance(ia["ewald_tolerance"])
        if ia["ewald_alpha"] > 0 or any(ia["pme_grid"]):
            if not (ia["ewald_alpha"] > 0 and all(ia["pme_grid"])):
                raise ValueError("to_openmm: give both interactions.ewald_alpha and pme_grid, or neither")
            nb.setPMEParameters(ia["ewald_alpha"], *ia["pme_grid"])
    for i in range(n):
        base = i * ns
        for a in range(ns):
            system.addParticle(float(m["site_mass"][a]))
            nb.addParticle(float(m["charge"][a]), float(m["sigma"][a]) if m["epsilon"][a] > 0 else 1.0,
                           float(m["epsilon"][a]))
        for a, w in vsites.items():
            system.setVirtualSite(base + a, mm.ThreeParticleAverageSite(base, base + 1, base + 2, *map(float, w)))
        for a in range(ns):
            for b in range(a + 1, ns):
                nb.addException(base + a, base + b, 0.0, 1.0, 0.0)
        for a, b, d in cons:
            system.addConstraint(base + a, base + b, d)
    system.addForce(nb)
    return system, sim.site_positions().reshape(n * ns, 3)


def from_openmm(system, positions, *, velocities=None, set=None):
    """A rotleap.Simulation of a TIP4P-type OpenMM system (rigid waters of 3 or 4 sites each,
    constrained, M a virtual site, one NonbondedForce with CutoffPeriodic reaction field or PME):
    the catalogue model whose charges, LJ and geometry it has (to 1e-6), its box, cutoff and
    electrostatics as the deck's, and the state fitted molecule by molecule from `positions`
    (nm; centres of mass with the model's masses, orientations by the least-squares rotation of
    the body-frame sites onto the massive sites).  velocities: of the sites (nm/ps), to the
    molecules' centre-of-mass velocities and angular momenta; else zero.  set: other deck keys
    (run.timestep, run.steps, run.ensemble, ...)."""
    mm = _need("openmm", "python3-openmm")
    from .catalog import catalog
    from .simulation import Simulation
    pos = np.asarray(getattr(positions, "value_in_unit", lambda u: positions)(_nm(mm)), dtype=float).reshape(-1, 3)
    nbs = [f for f in system.getForces() if isinstance(f, mm.NonbondedForce)]
    if len(nbs) != 1 or system.getNumForces() > 1 + sum(isinstance(f, mm.CMMotionRemover) for f in system.getForces()):
        raise ValueError("from_openmm: one NonbondedForce (and at most a CMMotionRemover) is needed")
    nb = nbs[0]
    npart = system.getNumParticles()
    ns = 4 if npart > 3 and system.isVirtualSite(3) else 3
    if npart % ns or pos.shape[0] != npart:
        raise ValueError("from_openmm: %d particles, %d positions: not molecules of %d sites" % (npart, pos.shape[0], ns))
    n = npart // ns

    def param(k):
        q, sig, eps = nb.getParticleParameters(k)
        return q.value_in_unit(_e(mm)), sig.value_in_unit(_nm(mm)), eps.value_in_unit(_kj(mm))

    first = [param(k) for k in range(ns)]
    for i in range(1, n):
        if [param(i * ns + a) for a in range(ns)] != first:
            raise ValueError("from_openmm: molecule %d has other parameters than molecule 0" % i)
    cons = {}
    for c in range(system.getNumConstraints()):
        a, b, d = system.getConstraintParameters(c)
        if a < ns and b < ns:
            cons[(min(a, b), max(a, b))] = d.value_in_unit(_nm(mm))
    match = None
    for name, model in catalog().items():
        if model.units != "real" or len(model.sites) != ns:
            continue
        ok = all(abs(model.charge[a] - first[a][0]) < 1e-6 for a in range(ns))
        ok &= abs(model.epsilon[0] - first[0][2]) < 1e-6 * max(model.epsilon[0], 1) and \
            abs(model.sigma[0] - first[0][1]) < 1e-6
        ok &= all(abs(np.linalg.norm(model.sites[a] - model.sites[b]) - d) < 1e-6 for (a, b), d in cons.items())
        ok &= len(cons) == 3
        if ok:
            match = model
            break
    if match is None:
        raise ValueError("from_openmm: no catalogue water model has these charges %s, LJ (%g nm, %g kJ/mol) and "
                         "constraints %s" % ([round(f[0], 6) for f in first], first[0][1], first[0][2], cons))
    a, b, c = (v.value_in_unit(_nm(mm)) for v in system.getDefaultPeriodicBoxVectors())
    if abs(a[1]) + abs(a[2]) + abs(b[0]) + abs(b[2]) + abs(c[0]) + abs(c[1]) > 0:
        raise ValueError("from_openmm: an orthorhombic box is needed")
    keys = {"interactions.cutoff": nb.getCutoffDistance().value_in_unit(_nm(mm)), "interactions.scheme": "site",
            "interactions.lj": "plain",
            "interactions.dispersion_correction": "yes" if nb.getUseDispersionCorrection() else "no",
            "system.lattice": "sc", "system.temperature": "298 K", "run.equilibrate": 0, "run.timestep": "2 fs",
            "run.steps": 0}
    method = nb.getNonbondedMethod()
    if method == mm.NonbondedForce.CutoffPeriodic:
        eps = nb.getReactionFieldDielectric()
        keys["interactions.eps_rf"] = "inf" if eps >= 1e29 else repr(eps)
    elif method == mm.NonbondedForce.PME:
        keys["interactions.coulomb"] = "pme"
        keys["interactions.ewald_tolerance"] = repr(nb.getEwaldErrorTolerance())
        alpha, nx, ny, nz = nb.getPMEParameters()
        alpha = alpha.value_in_unit(_nm(mm) ** -1) if hasattr(alpha, "value_in_unit") else alpha
        if alpha > 0:
            keys["interactions.ewald_alpha"] = repr(alpha)
            keys["interactions.pme_grid"] = "%d %d %d" % (nx, ny, nz)
    else:
        raise ValueError("from_openmm: NonbondedForce method %d: CutoffPeriodic (reaction field) or PME" % method)
    if nb.getUseSwitchingFunction():
        raise ValueError("from_openmm: a switched LJ has no exact rotleap counterpart here")
    keys.update(set or {})
    sim = Simulation.from_model(match.name, n, box=[a[0], b[1], c[2]], set=keys)
    # the state: centres of mass and the rotation of the body frame onto the massive sites
    s = match.sites[:3]
    w = match.site_mass[:3]
    x = pos.reshape(n, ns, 3)[:, :3, :]
    com = (w[None, :, None] * x).sum(1) / w.sum()
    A = np.empty((n, 3, 3))
    for i in range(n):
        H = (s * w[:, None]).T @ (x[i] - com[i])      # sum_a w s_a (x_a - R)^T
        U, S, Vt = np.linalg.svd(H)
        D = np.diag([1.0, 1.0, np.sign(np.linalg.det(Vt.T @ U.T))])
        R = Vt.T @ D @ U.T                             # lab = R body
        A[i] = R.T                                     # rotleap's A: lab to body
    sim.positions = com
    sim.orientations = A
    if velocities is not None:
        v = np.asarray(getattr(velocities, "value_in_unit", lambda u: velocities)(_nm(mm) / _ps(mm)), dtype=float)
        v = v.reshape(n, ns, 3)[:, :3, :]
        vc = (w[None, :, None] * v).sum(1) / w.sum()
        lab = x - com[:, None, :]
        sim.velocities = vc
        sim.angular_momenta = (w[None, :, None] * np.cross(lab, v - vc[:, None, :])).sum(1)
    else:
        sim.velocities = np.zeros((n, 3))
        sim.angular_momenta = np.zeros((n, 3))
    return sim


def _nm(mm):
    return mm.unit.nanometer


def _ps(mm):
    return mm.unit.picosecond


def _e(mm):
    return mm.unit.elementary_charge


def _kj(mm):
    return mm.unit.kilojoule_per_mole
