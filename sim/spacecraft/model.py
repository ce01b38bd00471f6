"""Typed, validated spacecraft definition: shared types and the core sections
(the aggregate is sim/spacecraft/definition.py).

Every field carries its unit in the name where it is not SI. The YAML files
cite a seed section, or say "assumption", beside every number.
"""
from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]
Positive = Annotated[float, Field(gt=0)]
NonNegative = Annotated[float, Field(ge=0)]

UNIT_TOL = 1e-6


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


def check_unit_quaternion(q: Quat) -> Quat:
    norm = float(np.linalg.norm(q))
    if not abs(norm - 1.0) <= UNIT_TOL:   # written so that NaN fails too
        raise ValueError(f"expected a unit quaternion [w, x, y, z] (norm 1 +- {UNIT_TOL:g}), found norm {norm:.9g}")
    return q


def check_unit_vector(v: Vec3) -> Vec3:
    norm = float(np.linalg.norm(v))
    if abs(norm - 1.0) > UNIT_TOL:
        raise ValueError(f"expected a unit vector (norm 1 +- {UNIT_TOL:g}), found norm {norm:.9g}")
    return v


class Timing(Strict):
    truth_dt_s: Positive = Field(description="fixed RK4 step of the truth model")
    control_dt_s: Positive = Field(description="flight-software control cycle")
    actuator_delay_cycles: Literal[0, 1] = Field(
        1, description="cycles between sensor sample and actuator command taking effect")

    @model_validator(mode="after")
    def _cycle_is_whole_steps(self) -> "Timing":
        ratio = self.control_dt_s / self.truth_dt_s
        if abs(ratio - round(ratio)) > 1e-9 or round(ratio) < 1:
            raise ValueError(
                f"control_dt_s ({self.control_dt_s:g}) must be a whole multiple of truth_dt_s ({self.truth_dt_s:g})")
        return self


class Wheels(Strict):
    axes_B: list[Vec3] = Field(min_length=3, description="spin axis of each wheel, unit vectors in B")
    spin_inertia_kgm2: Positive
    h_max_Nms: Positive = Field(description="momentum capacity; motor torque that would exceed it is cut")
    torque_max_Nm: Positive = Field(description="hardware motor torque limit")
    torque_limit_sw_Nm: Positive = Field(description="flight-software commanded torque limit")
    viscous_Nm_per_rad_s: NonNegative = Field(description="viscous drag coefficient")
    coulomb_Nm: NonNegative = Field(description="Coulomb drag torque")
    coulomb_smoothing_rad_s: Positive = Field(
        0.1, description="speed scale of tanh() used for the Coulomb sign, so RK4 sees a smooth force")

    @field_validator("axes_B")
    @classmethod
    def _unit_axes(cls, axes: list[Vec3]) -> list[Vec3]:
        for a in axes:
            check_unit_vector(a)
        if np.linalg.matrix_rank(np.array(axes)) < 3:
            raise ValueError("wheel axes must span 3-D space (rank 3) for three-axis control")
        return axes

    @model_validator(mode="after")
    def _sw_below_hw(self) -> "Wheels":
        if self.torque_limit_sw_Nm > self.torque_max_Nm:
            raise ValueError(
                f"torque_limit_sw_Nm ({self.torque_limit_sw_Nm:g}) must not exceed torque_max_Nm ({self.torque_max_Nm:g})")
        return self


class StarTracker(Strict):
    q_BS: Quat = Field(description="mounting: attitude of the sensor frame S in B; boresight is S's +Z")
    noise_boresight_arcsec_3sigma: NonNegative
    noise_transverse_arcsec_3sigma: NonNegative

    @field_validator("q_BS")
    @classmethod
    def _unit(cls, q: Quat) -> Quat:
        return check_unit_quaternion(q)
