"""Spacecraft-file sections for thrusters and the main engine."""
from __future__ import annotations

from pydantic import Field, field_validator

from sim.spacecraft.model import Positive, Strict, Vec3, check_unit_vector


class Thruster(Strict):
    position_B_m: Vec3
    direction_B: Vec3 = Field(description="unit direction of the force on the spacecraft")
    thrust_lbf: Positive
    isp_s: Positive
    set: str = Field(pattern="^(primary|redundant)$")

    _unit = field_validator("direction_B")(check_unit_vector)


class Thrusters(Strict):
    pulse_s: Positive = Field(description="length of one pulse")
    max_pulses_per_cycle: int = Field(ge=1)
    units: list[Thruster] = Field(min_length=1)


class MainEngine(Strict):
    position_B_m: Vec3
    direction_B: Vec3 = Field(description="unit thrust direction, misalignment included")
    thrust_lbf: Positive
    isp_s: Positive

    _unit = field_validator("direction_B")(check_unit_vector)
