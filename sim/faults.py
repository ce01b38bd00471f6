"""Faults a scenario or an operator can inject: the command models.

Faults belong to the world, not to the flight software: the runner applies
them to the truth state (sim/fault_injection.py), and the flight software must
notice them from its sensors (seed 001 "Hardware complement": FDC reconfigures
rate selection after an IRU failure). This module holds only the models, so
that the command model (which the flight software imports) stays clear of
sim.truth.
"""
from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import BaseModel, ConfigDict, Field

N_IRU_CHANNELS = 6   # three two-axis units (seed 001 "Hardware complement")
N_CSS_EYES = 16      # two sets of eight (seed 001 "Hardware complement")


class FaultBase(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class WheelSeized(FaultBase):
    kind: Literal["wheel_seized"] = "wheel_seized"
    wheel: int = Field(ge=1, description="wheel number, from 1")


class WheelDrag(FaultBase):
    kind: Literal["wheel_drag"] = "wheel_drag"
    wheel: int = Field(ge=1)
    # le: c dt / J_s must stay inside RK4's stability limit (2.78) for truth steps
    # up to 0.3 s with the 0.11 kg m^2 SDO rotor; a seized wheel is its own fault
    viscous_Nm_per_rad_s: float = Field(1e-3, gt=0, le=1.0, description="extra viscous drag")


class IruStuck(FaultBase):
    kind: Literal["iru_stuck"] = "iru_stuck"
    channel: int = Field(ge=1, le=N_IRU_CHANNELS, description="IRU channel, 1-6 (unit k: channels 2k-1, 2k)")


class IruBias(FaultBase):
    kind: Literal["iru_bias"] = "iru_bias"
    channel: int = Field(ge=1, le=N_IRU_CHANNELS)
    bias_deg_h: float = Field(1.0, description="excess rate bias")


class StarTrackerDropout(FaultBase):
    kind: Literal["star_tracker_dropout"] = "star_tracker_dropout"
    tracker: int = Field(ge=1)


class ThrusterFailedOff(FaultBase):
    kind: Literal["thruster_failed_off"] = "thruster_failed_off"
    thruster: int = Field(ge=1)


class ThrusterStuckOn(FaultBase):
    kind: Literal["thruster_stuck_on"] = "thruster_stuck_on"
    thruster: int = Field(ge=1)


class CssFailed(FaultBase):
    kind: Literal["css_failed"] = "css_failed"
    eye: int = Field(ge=1, le=N_CSS_EYES, description="coarse Sun sensor eye, 1-16 (1-8 primary set)")


def describe(f: FaultBase) -> str:
    args = ", ".join(f"{k} {v}" for k, v in f.model_dump(exclude={"kind"}).items())
    return f"{f.kind.replace('_', ' ')} ({args})"


class ProcessorReset(FaultBase):
    """The main processor resets: down for duration_s, then back up with the
    ACE in Safehold (seed 001: Safehold runs in the ACE, apart from it)."""
    kind: Literal["processor_reset"] = "processor_reset"
    # ge 2 s: longer than the ACE's heartbeat timeout (1 s, sdo.yaml), so the ACE takes over
    duration_s: float = Field(10.0, ge=2.0, le=3600, description="time the processor is down")


class ProcessorFailed(FaultBase):
    """The main processor stops until the fault is cleared."""
    kind: Literal["processor_failed"] = "processor_failed"


PROCESSOR_FAULTS = (ProcessorReset, ProcessorFailed)


Fault = Annotated[Union[WheelSeized, WheelDrag, IruStuck, IruBias, StarTrackerDropout, ThrusterFailedOff,
                        ThrusterStuckOn, CssFailed, ProcessorReset,
                        ProcessorFailed], Field(discriminator="kind")]
FAULT_KINDS = {c.model_fields["kind"].default: c for c in Fault.__origin__.__args__}
