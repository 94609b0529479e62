"""The catalogue of named rigid models (`rotleap models`) as Python objects."""
from dataclasses import dataclass, field

import ctypes
import numpy as np

from ._native import lib, dptr, error_text

__all__ = ["Model", "catalog"]

MAX_SITES = 16  # RL_MOLECULE_MAX_SITES


@dataclass(frozen=True)
class Model:
    """A catalogue model: name, description, reference, units ('real': nm, amu, kJ/mol, e; 'lj':
    reduced), family (the rotation family it is integrated by), params {name: (default, unit)},
    and the molecule built with the default parameters: mass, inertia (principal moments, body
    X, Y, Z), site_names, sites (body frame, (nsites, 3)), site_mass, sigma, epsilon, charge,
    dipole and quadrupole (along body Z), per site."""
    name: str
    description: str
    reference: str
    units: str
    family: str
    params: dict
    mass: float
    inertia: np.ndarray = field(repr=False)
    site_names: tuple = field(repr=False)
    sites: np.ndarray = field(repr=False)
    site_mass: np.ndarray = field(repr=False)
    sigma: np.ndarray = field(repr=False)
    epsilon: np.ndarray = field(repr=False)
    charge: np.ndarray = field(repr=False)
    dipole: np.ndarray = field(repr=False)
    quadrupole: np.ndarray = field(repr=False)


def _model(i):
    def text(f):
        return lib.rlpy_catalog_text(i, f).decode()

    defaults = np.zeros(4)
    npar = lib.rlpy_catalog_params(i, dptr(defaults))
    params = {text(10 + k): (float(defaults[k]), text(20 + k)) for k in range(npar)}
    m = molecule(lambda *a: lib.rlpy_catalog_molecule(i, *a))
    return Model(text(0), text(1), text(2), text(3), text(4), params, **m)


def molecule(call):
    """The molecule native's call(mass, inertia, names, sites, site_mass, sigma, epsilon,
    charge, dipole, quadrupole) fills: {field of Model: value}."""
    mass, inertia = np.zeros(1), np.zeros(3)
    names = ctypes.create_string_buffer(8 * MAX_SITES)
    arrays = [np.zeros((MAX_SITES, 3))] + [np.zeros(MAX_SITES) for _ in range(6)]
    n = call(dptr(mass), dptr(inertia), names, *[dptr(a) for a in arrays])
    if n < 0:
        from .simulation import Error
        raise Error(error_text())
    raw = names.raw
    site_names = tuple(raw[8 * s:8 * s + 8].split(b"\0")[0].decode() for s in range(n))
    sites, site_mass, sigma, epsilon, charge, dipole, quad = (a[:n].copy() for a in arrays)
    return dict(mass=float(mass[0]), inertia=inertia, site_names=site_names, sites=sites, site_mass=site_mass,
                sigma=sigma, epsilon=epsilon, charge=charge, dipole=dipole, quadrupole=quad)


def catalog():
    """{name: Model} for every catalogue model, in the catalogue's order."""
    return {m.name: m for m in (_model(i) for i in range(lib.rlpy_catalog_count()))}
