"""Spacecraft-file sections for mass properties and the surface model."""
from __future__ import annotations

import numpy as np
from pydantic import Field, field_validator, model_validator

from sim.spacecraft.model import NonNegative, Positive, Strict, Vec3, check_unit_vector

Matrix3 = tuple[Vec3, Vec3, Vec3]


def check_inertia(m: Matrix3) -> Matrix3:
    a = np.array(m, dtype=float)
    if not np.allclose(a, a.T, rtol=0, atol=1e-9):
        raise ValueError("inertia must be symmetric")
    if np.linalg.eigvalsh(a).min() <= 0:
        raise ValueError("inertia must be positive definite")
    return m


class MassProperties(Strict):
    propellant_kg: NonNegative = Field(description="propellant at full tanks (part of mass_kg)")
    inertia_empty_B_kgm2: Matrix3 = Field(description="inertia about the centre of mass with empty tanks")
    cm_full_B_m: Vec3 = Field(description="centre of mass with full tanks, structure frame")
    cm_empty_B_m: Vec3 = Field(description="centre of mass with empty tanks, structure frame")

    _inertia = field_validator("inertia_empty_B_kgm2")(check_inertia)


class Facet(Strict):
    name: str
    area_m2: Positive
    normal_B: Vec3 = Field(description="outward unit normal")
    centroid_B_m: Vec3
    rho_specular: float = Field(ge=0, le=1)
    rho_diffuse: float = Field(ge=0, le=1)

    _unit = field_validator("normal_B")(check_unit_vector)

    @model_validator(mode="after")
    def _energy(self) -> "Facet":
        if self.rho_specular + self.rho_diffuse > 1.0:
            raise ValueError(f"rho_specular + rho_diffuse = {self.rho_specular + self.rho_diffuse:g} "
                             "exceeds 1 (the rest is absorbed)")
        return self


class Surface(Strict):
    facets: list[Facet] = Field(min_length=1)
