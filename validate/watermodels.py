"""Rigid water models as OpenMM systems, for comparison with rotleap's catalogue.

The parameters are written down here from the literature (the same sources as models/catalog.c
cites), not read from rotleap, so a typo in either place shows up as a disagreement.  The
geometry of the sites is taken from the rotleap checkpoint being evaluated (that is the point of
a single-point comparison: the same positions), and is checked against the literature geometry
below (check_geometry).

Units: nm, kJ/mol, e, amu.
"""
import math
import os

try:
    import openmm as mm
except ImportError:  # OpenMM < 7.6 layout
    from simtk import openmm as mm

KCAL = 4.184
M_O, M_H = 15.9994, 1.008

# roh (nm), H-O-H (deg), O-M (nm; 0 = three-site), q_H (e), sigma_O (nm), eps_O (kJ/mol)
MODELS = {
    # Jorgensen et al., J. Chem. Phys. 79, 926 (1983): sigma 3.15365 A, eps 0.1550 kcal/mol
    "tip4p": dict(roh=0.09572, angle=104.52, rom=0.015, qh=0.52, sigma=0.315365, eps=0.1550 * KCAL),
    # Horn et al., J. Chem. Phys. 120, 9665 (2004): sigma 3.16435 A, eps 0.16275 kcal/mol
    "tip4p-ew": dict(roh=0.09572, angle=104.52, rom=0.0125, qh=0.52422, sigma=0.316435,
                     eps=0.16275 * KCAL),
    # Abascal & Vega, J. Chem. Phys. 123, 234505 (2005): sigma 3.1589 A, eps/k 93.2 K, d_OM 0.1546 A,
    # q_H 0.5564 e
    "tip4p-2005": dict(roh=0.09572, angle=104.52, rom=0.01546, qh=0.5564, sigma=0.31589,
                       eps=93.2 * 0.0083144626),
    # Berendsen et al., J. Phys. Chem. 91, 6269 (1987); LJ as GROMACS spce.itp / OpenMM spce.xml
    "spc-e": dict(roh=0.1, angle=109.47, rom=0.0, qh=0.4238, sigma=0.316557, eps=0.650194),
    # Jorgensen et al. 1983: sigma 3.15061 A, eps 0.1521 kcal/mol
    "tip3p": dict(roh=0.09572, angle=104.52, rom=0.0, qh=0.417, sigma=0.315061, eps=0.1521 * KCAL),
}

# OpenMM's own force-field files for the same models (for the informational cross-check only)
OPENMM_XML = {"tip4p-ew": "tip4pew.xml", "spc-e": "spce.xml", "tip3p": "tip3p.xml"}


def four_site(model):
    return MODELS[model]["rom"] > 0


def vsite_weights(model):
    """ThreeParticleAverageSite weights (w_O, w_H, w_H) placing M at O + rom * bisector."""
    p = MODELS[model]
    w_h = p["rom"] / (2.0 * p["roh"] * math.cos(math.radians(p["angle"]) / 2.0))
    return 1.0 - 2.0 * w_h, w_h, w_h


def site_params(model):
    """[(name, mass, charge, sigma, eps)] in rotleap's site order O, H1, H2[, M]."""
    p = MODELS[model]
    qo = 0.0 if four_site(model) else -2.0 * p["qh"]
    s = [("O", M_O, qo, p["sigma"], p["eps"]), ("H1", M_H, p["qh"], 1.0, 0.0),
         ("H2", M_H, p["qh"], 1.0, 0.0)]
    if four_site(model):
        s.append(("M", 0.0, -2.0 * p["qh"], 1.0, 0.0))
    return s


def check_geometry(model, d):
    """Largest deviation (nm) of the body-frame sites d (from a rotleap checkpoint) from the
    literature geometry: O-H distances, H-H distance, O-M distance, M on the weighted average,
    and the centre of mass at the origin."""
    p = MODELS[model]
    dist = lambda a, b: math.sqrt(sum((a[i] - b[i]) ** 2 for i in range(3)))
    half = math.radians(p["angle"]) / 2.0
    dev = [abs(dist(d[0], d[1]) - p["roh"]), abs(dist(d[0], d[2]) - p["roh"]),
           abs(dist(d[1], d[2]) - 2 * p["roh"] * math.sin(half))]
    masses = [s[1] for s in site_params(model)]
    com = [sum(masses[a] * d[a][i] for a in range(len(d))) / sum(masses) for i in range(3)]
    dev.append(max(abs(c) for c in com))
    if four_site(model):
        dev.append(abs(dist(d[0], d[3]) - p["rom"]))
        w = vsite_weights(model)
        m = [w[0] * d[0][i] + w[1] * d[1][i] + w[2] * d[2][i] for i in range(3)]
        dev.append(dist(m, d[3]))
    return max(dev)


def build_system(model, nmol, box, cutoff, eps_rf, rigid=False, pme_tolerance=None, dispersion_correction=False):
    """OpenMM System: NonbondedForce CutoffPeriodic (reaction field) with every intramolecular
    pair excluded, plain LJ (no switch, no dispersion correction), M as a ThreeParticleAverageSite.
    rigid=True adds O-H, O-H, H-H distance constraints (OpenMM recognises them as SETTLE).
    pme_tolerance: smooth PME instead of reaction field, alpha and grid from that
    ewaldErrorTolerance (eps_rf is then ignored); rotleap's coulomb = pme with ewald_tolerance
    derives the same ones (validate/ewald_openmm.py checks it).  dispersion_correction: OpenMM's LJ
    long-range correction (rotleap's interactions.dispersion_correction = yes)."""
    p = MODELS[model]
    sites = site_params(model)
    ns = len(sites)
    system = mm.System()
    system.setDefaultPeriodicBoxVectors(mm.Vec3(box[0], 0, 0), mm.Vec3(0, box[1], 0),
                                        mm.Vec3(0, 0, box[2]))
    nb = mm.NonbondedForce()
    nb.setCutoffDistance(cutoff)
    if pme_tolerance is None:
        nb.setNonbondedMethod(mm.NonbondedForce.CutoffPeriodic)
        nb.setReactionFieldDielectric(eps_rf)
    else:
        nb.setNonbondedMethod(mm.NonbondedForce.PME)
        nb.setEwaldErrorTolerance(pme_tolerance)
    nb.setUseDispersionCorrection(dispersion_correction)
    nb.setUseSwitchingFunction(False)
    w = vsite_weights(model) if four_site(model) else None
    rhh = 2 * p["roh"] * math.sin(math.radians(p["angle"]) / 2.0)
    for m in range(nmol):
        base = m * ns
        for name, mass, q, sig, eps in sites:
            system.addParticle(mass)
            nb.addParticle(q, sig, eps)
        if w:
            system.setVirtualSite(base + 3, mm.ThreeParticleAverageSite(base, base + 1, base + 2, *w))
        for a in range(ns):
            for b in range(a + 1, ns):
                nb.addException(base + a, base + b, 0.0, 1.0, 0.0)
        if rigid:
            system.addConstraint(base, base + 1, p["roh"])
            system.addConstraint(base, base + 2, p["roh"])
            system.addConstraint(base + 1, base + 2, rhh)
    system.addForce(nb)
    return system


def xml_crosscheck(model):
    """Compare this module's parameters with OpenMM's shipped force field XML (information only:
    the two may differ in the last printed digit, e.g. 0.1521 kcal/mol = 0.6363864 vs 0.636386).
    Returns a list of (field, ours, openmm, relative difference) or None if no XML."""
    if model not in OPENMM_XML:
        return None
    import xml.etree.ElementTree as ET
    path = os.path.join(os.path.dirname(mm.__file__), "app", "data", OPENMM_XML[model])
    root = ET.parse(path).getroot()
    atoms = {a.get("type"): a for a in root.iter("Atom") if a.get("charge") is not None}
    ours = site_params(model)
    out = []
    o = next(a for t, a in atoms.items() if t.endswith("-O"))
    h = next(a for t, a in atoms.items() if t.endswith("-H"))
    rel = lambda a, b: abs(a - b) / max(abs(b), 1e-300)
    for field, mine, theirs in (("q_H", ours[1][2], float(h.get("charge"))),
                                ("sigma_O", ours[0][3], float(o.get("sigma"))),
                                ("eps_O", ours[0][4], float(o.get("epsilon")))):
        out.append((field, mine, theirs, rel(mine, theirs)))
    bonds = [b for b in root.iter("Bond") if b.get("length")]
    if bonds:
        roh = float(bonds[0].get("length"))
        out.append(("r_OH", MODELS[model]["roh"], roh, rel(MODELS[model]["roh"], roh)))
    angles = [a for a in root.iter("Angle") if a.get("angle")]
    if angles:
        ang = math.degrees(float(angles[0].get("angle")))
        out.append(("HOH_deg", MODELS[model]["angle"], ang, rel(MODELS[model]["angle"], ang)))
    vs = [v for v in root.iter("VirtualSite")]
    if vs and four_site(model):
        w = float(vs[0].get("weight1"))
        out.append(("w_O", vsite_weights(model)[0], w, rel(vsite_weights(model)[0], w)))
    return out
