"""Spacecraft-file sections for the SDO sensor models of sim/truth/sensors/
(seed 001 "Hardware complement"). Each section's field names are the keyword
arguments of its module's make_*_params, so a validated section builds its
parameters with make_x_params(**section.model_dump(), ...); the extras are
the control cycle dt (IRU, tachometers), the existing StarTrackerParams
(exclusion), and the IRU's bias_deg_h, which goes to its initial state.
"""
from __future__ import annotations

from typing import Annotated

import numpy as np
from pydantic import Field, field_validator, model_validator
from scipy.spatial import ConvexHull, QhullError

from sim.spacecraft.model import (
    NonNegative,
    Positive,
    Quat,
    Strict,
    Vec3,
    check_unit_quaternion,
    check_unit_vector,
)

Fraction = Annotated[float, Field(ge=0, le=1)]
HalfAngleDeg = Annotated[float, Field(gt=0, lt=180)]
IRU_UNIT_OF_CHANNEL = (0, 0, 1, 1, 2, 2)   # as sim/truth/sensors/iru_units.py


def check_unit_vectors(vectors: list[Vec3]) -> list[Vec3]:
    for v in vectors:
        check_unit_vector(v)
    return vectors


def covering_radius_deg(directions) -> float:
    """Largest angle from any direction in space to its nearest given one
    (deg): the farthest points are the circumcentres of the facets of the
    directions' convex hull, at acos(facet offset) from their vertices."""
    d = np.asarray(directions, float)
    try:
        hull = ConvexHull(d)
    except QhullError:
        return 180.0   # flat or too few: a whole side of the sphere is unseen
    offsets = -hull.equations[:, 3]
    if offsets.min() <= 0.0:
        return 180.0   # the origin is not inside: a hemisphere is unseen
    return float(np.degrees(np.arccos(np.clip(offsets.min(), -1.0, 1.0))))


class IruUnits(Strict):
    """Three two-axis IRUs as six channels; channels 2k, 2k+1 belong to unit k."""
    channel_axes_B: list[Vec3] = Field(min_length=6, max_length=6, description="unit sensing axis per channel")
    lsb_arcsec: Positive = Field(description="angle per count of the rate-integrating output")
    arw_deg_per_sqrt_h: NonNegative = Field(description="angle random walk")
    rrw_deg_h_per_sqrt_h: NonNegative = Field(description="rate random walk (bias drift)")
    rate_max_deg_s: Positive = Field(description="rate up to which the output keeps its sign; held there above")
    bias_deg_h: list[float] = Field(min_length=6, max_length=6, description="initial bias per channel")

    _unit = field_validator("channel_axes_B")(check_unit_vectors)

    @field_validator("channel_axes_B")
    @classmethod
    def _any_two_units_span(cls, axes: list[Vec3]) -> list[Vec3]:
        a = np.array(axes)
        for lost in range(3):
            rows = [k for k, u in enumerate(IRU_UNIT_OF_CHANNEL) if u != lost]
            if np.linalg.matrix_rank(a[rows], tol=1e-3) < 3:
                raise ValueError(f"with unit {lost + 1} failed the other units' channels do not span 3-D space; "
                                 "allowed: axes such that any two units sense all three body axes")
        return axes


class StarTrackerExclusion(Strict):
    sun_half_angle_deg: HalfAngleDeg = Field(description="Sun exclusion about the boresight, from the Sun centre")
    earth_limb_half_angle_deg: Annotated[float, Field(ge=0, lt=180)] = Field(description="beyond the Earth's limb")
    moon_limb_half_angle_deg: Annotated[float, Field(ge=0, lt=180)] = Field(description="beyond the Moon's limb")


class Css(Strict):
    boresights_primary_B: list[Vec3] = Field(min_length=8, max_length=8, description="unit boresights, set 1")
    boresights_backup_B: list[Vec3] = Field(min_length=8, max_length=8, description="unit boresights, set 2")
    fov_half_angle_deg: Annotated[float, Field(gt=0, le=90)] = Field(description="half-angle of each eye's cone")
    full_sun_current_A: Positive = Field(description="output at normal incidence, whole disk lit")
    noise_A_3sigma: NonNegative
    lsb_A: NonNegative = Field(description="converter step; 0 for none")

    _unit = field_validator("boresights_primary_B", "boresights_backup_B")(check_unit_vectors)

    @model_validator(mode="after")
    def _each_set_sees_everywhere(self) -> Css:
        for name in ("boresights_primary_B", "boresights_backup_B"):
            radius = covering_radius_deg(getattr(self, name))
            if radius > self.fov_half_angle_deg:
                raise ValueError(f"{name}: some Sun directions are {radius:.1f} deg from every eye, beyond "
                                 f"fov_half_angle_deg = {self.fov_half_angle_deg:g}; allowed: each set of eyes "
                                 "sees every direction (seed 001: full 4-pi coverage per set)")
        return self


class Dss(Strict):
    q_BD: Quat = Field(description="attitude of the sensor frame in B; boresight is its +X")
    fov_half_width_deg: Annotated[float, Field(gt=0, lt=90)] = Field(description="limit of each tangent angle")
    inner_half_angle_deg: Positive = Field(description="best accuracy inside this off-boresight angle")
    accuracy_inner_arcmin_3sigma: NonNegative
    accuracy_edge_arcmin_3sigma: NonNegative
    lit_fraction_min: Fraction = Field(description="below this lit fraction of the disk, no output")

    _unit = field_validator("q_BD")(check_unit_quaternion)

    @model_validator(mode="after")
    def _inner_inside_fov(self) -> Dss:
        if self.inner_half_angle_deg >= self.fov_half_width_deg:
            raise ValueError(f"inner_half_angle_deg ({self.inner_half_angle_deg:g}) must be below "
                             f"fov_half_width_deg ({self.fov_half_width_deg:g})")
        return self


class GuideTelescope(Strict):
    q_BG: Quat = Field(description="nominal attitude of the telescope frame in B; boresight is its +X")
    misalignment_arcsec: Vec3 = Field(description="small rotation of the true frame from nominal, G axes")

    _unit = field_validator("q_BG")(check_unit_quaternion)


class GuideTelescopes(Strict):
    units: list[GuideTelescope] = Field(min_length=4, max_length=4)
    fov_half_angle_deg: Annotated[float, Field(gt=0, lt=90)]
    fine_range_arcsec: Positive = Field(description="each offset saturates here")
    noise_arcsec_3sigma: NonNegative
    lit_fraction_min: Fraction

    @model_validator(mode="after")
    def _range_inside_fov(self) -> GuideTelescopes:
        if self.fine_range_arcsec > self.fov_half_angle_deg * 3600.0:
            raise ValueError(f"fine_range_arcsec ({self.fine_range_arcsec:g}) must lie inside the field of view "
                             f"(fov_half_angle_deg = {self.fov_half_angle_deg:g} = "
                             f"{self.fov_half_angle_deg * 3600.0:g} arcsec)")
        return self


class Tachometers(Strict):
    pulses_per_rev: int = Field(ge=1, description="tachometer pulses per wheel revolution")


class SensorSuite(Strict):
    """The sensors section of a spacecraft file. The IRU and the star trackers
    are always there (every mode needs rates and attitude); a spacecraft
    without coarse Sun sensors, a digital Sun sensor, guide telescopes or
    wheel tachometers leaves that section out (null)."""
    iru_units: IruUnits
    star_tracker_exclusion: StarTrackerExclusion
    css: Css | None = None
    dss: Dss | None = None
    guide_telescopes: GuideTelescopes | None = None
    tachometers: Tachometers | None = None
