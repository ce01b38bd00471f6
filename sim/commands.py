"""Ground commands: typed models defined once, used by every door (scenario
files, REST, the console), and their lifecycle.

A command is validated on arrival by its schema, then checked by the flight
software at the next control cycle against the current mode:

    queued -> accepted | rejected(reason) -> executing -> completed | failed(reason)
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Annotated, ClassVar, Literal, Union

from pydantic import BaseModel, ConfigDict, Field, TypeAdapter, field_validator

from sim.faults import Fault
from sim.modes import Mode
from sim.spacecraft.model import Quat, check_unit_quaternion


class CommandBase(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)
    legal_modes: ClassVar[tuple[Mode, ...]] = ()
    hazardous: ClassVar[bool] = False


class SetTargetQuaternion(CommandBase):
    """Slew to, and hold, an inertially fixed (GCI) target attitude q_RN."""
    type: Literal["set_target_quaternion"] = "set_target_quaternion"
    q_RN: Quat = Field(description="target attitude of the reference frame R in GCI, scalar-first [w, x, y, z]")
    legal_modes: ClassVar = (Mode.INERTIAL,)

    @field_validator("q_RN")
    @classmethod
    def _unit(cls, q: Quat) -> Quat:
        return check_unit_quaternion(q)


class ResetIntegrator(CommandBase):
    """Zero the integral of the attitude error (seed 000: the command kept for
    when the held integral torque cannot get back inside the box)."""
    type: Literal["reset_integrator"] = "reset_integrator"
    legal_modes: ClassVar = (Mode.INERTIAL, Mode.SCIENCE)


class SetTargetSnr(CommandBase):
    """Target the on-board SNR frame (seed 001 "SNR Target"), optionally
    times a delta quaternion that points the spacecraft away from it by a
    known angle (calibration maneuvers). Identity: the default science target."""
    type: Literal["set_target_snr"] = "set_target_snr"
    delta_q: Quat = Field((1.0, 0.0, 0.0, 0.0),
                          description="delta quaternion q_RS of the target R in the SNR frame S, [w, x, y, z]")
    legal_modes: ClassVar = (Mode.INERTIAL, Mode.SCIENCE)

    @field_validator("delta_q")
    @classmethod
    def _unit(cls, q: Quat) -> Quat:
        return check_unit_quaternion(q)


class SetAttitudeOption(CommandBase):
    """Select how the attitude is determined (seed 001 "Attitude
    determination"): the Kalman filter, one star tracker's quaternion, or
    IRU propagation."""
    type: Literal["set_attitude_option"] = "set_attitude_option"
    option: Literal["ekf", "star_tracker", "iru"] = Field(description="attitude determination method")
    star_tracker: int = Field(1, ge=1, le=2, description="tracker flown by option star_tracker (1 or 2)")
    legal_modes: ClassVar = tuple(Mode)


class EnableScienceAutonomy(CommandBase):
    """Allow (or forbid) the autonomous Inertial -> Science transition when
    the controlling guide telescope is in its acquisition range."""
    type: Literal["enable_science_autonomy"] = "enable_science_autonomy"
    enabled: bool = Field(True, description="true: allow the transition; false: forbid it")
    legal_modes: ClassVar = tuple(Mode)


class SelectCgt(CommandBase):
    """Select the controlling guide telescope (seed 001 "Science mode")."""
    type: Literal["select_cgt"] = "select_cgt"
    cgt: int = Field(ge=1, le=4, description="guide telescope number, 1 to 4")
    legal_modes: ClassVar = tuple(Mode)


class SetMode(CommandBase):
    """Command a mode transition; refused with a reason when the transition
    is not allowed from the current mode."""
    type: Literal["set_mode"] = "set_mode"
    mode: Literal["INERTIAL", "SCIENCE"] = Field(description="target mode")
    legal_modes: ClassVar = tuple(Mode)


class InjectFault(CommandBase):
    """Break something in the simulated world (not a flight-software command)."""
    type: Literal["inject_fault"] = "inject_fault"
    fault: Fault
    legal_modes: ClassVar = tuple(Mode)
    hazardous: ClassVar = True


class ClearFault(CommandBase):
    """Repair a fault injected before (the same fault description)."""
    type: Literal["clear_fault"] = "clear_fault"
    fault: Fault
    legal_modes: ClassVar = tuple(Mode)
    hazardous: ClassVar = True


WORLD_COMMANDS = (InjectFault, ClearFault)  # handled by the runner, not the flight software
_ALL = (SetTargetQuaternion, SetTargetSnr, ResetIntegrator, SetAttitudeOption, EnableScienceAutonomy, SelectCgt,
        SetMode, InjectFault, ClearFault)
Command = Annotated[Union[_ALL], Field(discriminator="type")]
COMMAND_ADAPTER: TypeAdapter = TypeAdapter(Command)
COMMAND_TYPES = {c.model_fields["type"].default: c for c in _ALL}

def split_time_tag(data, inner: str):
    """A time-tagged item is flat in a file (`t_s` beside the item's own
    fields) and nested in the model: {t_s, inner: {the rest}}."""
    if isinstance(data, dict) and inner not in data:
        data = dict(data)
        t = data.pop("t_s", None)
        return {"t_s": t, inner: data} if t is not None else {inner: data}
    return data


QUEUED, ACCEPTED, REJECTED, EXECUTING, COMPLETED, FAILED = (
    "queued", "accepted", "rejected", "executing", "completed", "failed")
FINAL_STAGES = (REJECTED, COMPLETED, FAILED)


@dataclass
class Stage:
    name: str
    t_s: float
    reason: str = ""


@dataclass
class CommandRecord:
    id: int
    command: CommandBase
    source: str          # who sent it: "scenario", "operator", ...
    due_s: float         # time tag: delivered at the first control cycle at or after it
    stages: list[Stage] = field(default_factory=list)

    @property
    def state(self) -> str:
        return self.stages[-1].name if self.stages else QUEUED

    @property
    def done(self) -> bool:
        return self.state in FINAL_STAGES

    def args(self) -> dict:
        return self.command.model_dump(exclude={"type"})

    def describe(self) -> str:
        return f"command {self.id} {self.command.type}"
