"""Mass properties that move with the propellant.

Between the full-tank and empty-tank states the inertia about the centre of
mass and the centre of mass itself are interpolated linearly in propellant
mass (an assumption: it treats the propellant as a rigid lump that shrinks in
place, which ignores slosh and tank geometry; seed 001 "DeltaV" discusses slosh
separately). The rate of change of inertia, dJ/dt = dJ/dm * dm/dt, enters
Euler's equation so that angular momentum is conserved through a burn whose
thrust passes through the centre of mass (the jet-damping torque of the
exhaust is neglected).
"""
from typing import NamedTuple

import numpy as np
from numba import njit


class MassParams(NamedTuple):
    dry_kg: float
    propellant_full_kg: float
    inertia_full_B: np.ndarray   # (3, 3) about the full-tank centre of mass, kg m^2
    inertia_empty_B: np.ndarray  # (3, 3) about the empty-tank centre of mass
    cm_full_B: np.ndarray        # (3,) centre of mass, m, in the body (structure) frame
    cm_empty_B: np.ndarray


def make_mass_params(total_kg, propellant_kg, inertia_full_B, inertia_empty_B, cm_full_B, cm_empty_B) -> MassParams:
    if not 0.0 <= propellant_kg < total_kg:
        raise ValueError(f"propellant ({propellant_kg} kg) must be in [0, total mass {total_kg} kg)")
    return MassParams(float(total_kg - propellant_kg), float(propellant_kg), np.array(inertia_full_B, float),
                      np.array(inertia_empty_B, float), np.array(cm_full_B, float), np.array(cm_empty_B, float))


@njit(cache=True)
def fill_fraction(m_prop_kg, p):
    if p.propellant_full_kg <= 0.0:
        return 0.0
    return min(max(m_prop_kg / p.propellant_full_kg, 0.0), 1.0)


@njit(cache=True)
def inertia_B(m_prop_kg, p):
    """Inertia about the current centre of mass, kg m^2."""
    f = fill_fraction(m_prop_kg, p)
    return p.inertia_empty_B + f * (p.inertia_full_B - p.inertia_empty_B)


@njit(cache=True)
def inertia_rate_per_kg(p):
    """dJ/dm_prop, kg m^2 per kg of propellant."""
    if p.propellant_full_kg <= 0.0:
        return np.zeros((3, 3))
    return (p.inertia_full_B - p.inertia_empty_B) / p.propellant_full_kg


@njit(cache=True)
def centre_of_mass_B(m_prop_kg, p):
    f = fill_fraction(m_prop_kg, p)
    return p.cm_empty_B + f * (p.cm_full_B - p.cm_empty_B)


@njit(cache=True)
def total_mass_kg(m_prop_kg, p):
    return p.dry_kg + max(m_prop_kg, 0.0)
