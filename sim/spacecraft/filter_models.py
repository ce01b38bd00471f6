"""Typed, validated specification of the flight software's torque-command
filters (seed 001 "Attitude control modes": "Control torques ... may be
filtered with up to a fourth-order discrete filter, with a different design
possible in each mode and for each axis of control").

A filter is given as its analog prototype's design numbers; the flight software
designs and discretises it at parameter-build time (sim/fsw/filter_design.py).
Frequencies are of the *discrete* filter, in Hz: the design prewarps them, so
the digital response has its edges exactly there.

The numbers for SDO are `fsw.torque_filters` of sim/spacecraft/sdo.yaml.
"""
from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import Field, model_validator

from sim.spacecraft.model import Positive, Strict

MAX_ORDER = 4  # seed 001: "up to a fourth-order discrete filter"

Order = Annotated[int, Field(ge=1, le=MAX_ORDER, description=f"filter order, 1..{MAX_ORDER} (seed 001)")]


class EllipticSpec(Strict):
    """Elliptic (Cauer) low-pass: equiripple in the passband and the stopband."""
    kind: Literal["elliptic"]
    order: Order
    pass_Hz: Positive = Field(description="passband edge: gain within ripple_dB from DC to here")
    ripple_dB: Positive = Field(description="peak-to-peak passband ripple, dB")
    stop_Hz: Positive = Field(description="stopband edge: attenuation >= stop_atten_dB from here to Nyquist")
    stop_atten_dB: Positive = Field(description="minimum stopband attenuation below the passband peak, dB")

    @model_validator(mode="after")
    def _edges_ordered(self) -> "EllipticSpec":
        if self.stop_Hz <= self.pass_Hz:
            raise ValueError(f"stop_Hz ({self.stop_Hz:g}) must exceed pass_Hz ({self.pass_Hz:g})")
        return self


class ButterworthSpec(Strict):
    """Butterworth low-pass: maximally flat, -3 dB at cutoff_Hz."""
    kind: Literal["butterworth"]
    order: Order
    cutoff_Hz: Positive = Field(description="-3 dB frequency")


FilterSpec = Annotated[Union[EllipticSpec, ButterworthSpec], Field(discriminator="kind")]


class AxisFilters(Strict):
    """One filter per body axis; null means the axis is not filtered."""
    x: FilterSpec | None = None
    y: FilterSpec | None = None
    z: FilterSpec | None = None

    def per_axis(self) -> tuple:
        return self.x, self.y, self.z


class TorqueFilters(Strict):
    """Filter banks, one per mode that filters its torque command."""
    inertial: AxisFilters = Field(description="seed 001 'Inertial mode': a second-order elliptic filter")
    science: AxisFilters = Field(
        description="seed 001 'Science mode': 2nd-order elliptic on X, 2nd-order low-pass on Y, 3rd-order elliptic on Z")


def load_torque_filters(name: str) -> TorqueFilters:
    """The torque filters of spacecraft `name` (its `fsw.torque_filters`)."""
    from sim.spacecraft import load_spacecraft

    return load_spacecraft(name, {}).fsw.torque_filters
