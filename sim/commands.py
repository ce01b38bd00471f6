"""Ground commands: typed models defined once, used by every door (scenario
files, REST, the console), and their lifecycle.

A command is validated on arrival by its schema, then checked by the flight
software at the next control cycle against the current mode:

    queued -> accepted | rejected(reason) -> executing -> completed | failed(reason)
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Annotated, ClassVar, Literal, Union

from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    TypeAdapter,
    model_validator,
)

from sim.calibration import CalibrationManeuver
from sim.faults import Fault
from sim.modes import Mode
from sim.spacecraft.model import Quat, check_unit_quaternion

# a quaternion field that must be unit (the check names the norm it found)
UnitQuat = Annotated[Quat, AfterValidator(check_unit_quaternion)]


class CommandBase(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)
    legal_modes: ClassVar[tuple[Mode, ...]] = ()
    hazardous: ClassVar[bool] = False


class SetTargetQuaternion(CommandBase):
    """Slew to, and hold, an inertially fixed (GCI) target attitude q_RN."""
    type: Literal["set_target_quaternion"] = "set_target_quaternion"
    q_RN: UnitQuat = Field(description="target attitude of the reference frame R in GCI, scalar-first [w, x, y, z]")
    legal_modes: ClassVar = (Mode.INERTIAL,)


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
    delta_q: UnitQuat = Field((1.0, 0.0, 0.0, 0.0),
                          description="delta quaternion q_RS of the target R in the SNR frame S, [w, x, y, z]")
    legal_modes: ClassVar = (Mode.INERTIAL, Mode.SCIENCE)


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


class DeltaHArgs(BaseModel):
    """What DeltaH needs on entry: the wheel targets (seed 001 "DeltaH": "drive
    the reaction wheels to a desired wheel speed"), and the tip-off
    contingency flag (K_p / 10, rate nulling)."""
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)
    wheel_momentum_Nms: list[float] | None = Field(
        None, description="target momentum of each wheel, N m s (or give wheel_speed_rpm; neither: all zero)")
    wheel_speed_rpm: list[float] | None = Field(None, description="target speed of each wheel, rpm")
    tipoff: bool = Field(False, description="launch-vehicle separation contingency: K_p / 10")

    @model_validator(mode="after")
    def _one_target(self):
        if self.wheel_momentum_Nms is not None and self.wheel_speed_rpm is not None:
            raise ValueError("give wheel_momentum_Nms or wheel_speed_rpm, not both")
        return self


class DeltaVArgs(BaseModel):
    """The four things DeltaV entry needs (seed 001 "DeltaV": "(1) desired
    attitude target for DeltaV burn, (2) burn duration, including any settling
    burn length, (3) whether the main engine will be used, and (4) desired set
    of thrusters")."""
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)
    target_q_RN: UnitQuat = Field(description="burn attitude, GCI, scalar-first [w, x, y, z]")
    duration_s: float = Field(gt=0, le=6 * 3600, description="burn length including the settling burn, s",
                              examples=[60.0])
    main_engine: bool = Field(description="true: main engine (after the settling burn); false: ACS thrusters only")
    thruster_set: Literal["primary", "redundant"] = Field("primary", description="ACS thruster set")


MODE_NAMES = Literal["SUNACQ", "INERTIAL", "SCIENCE", "DELTAH", "DELTAV", "SAFEHOLD"]


class SetMode(CommandBase):
    """Command a mode transition (a forced mode change: hazardous), refused
    with a reason when the transition is not allowed from the current mode
    (docs/modes.md). DELTAV needs `deltav`; DELTAH takes `deltah`."""
    type: Literal["set_mode"] = "set_mode"
    mode: MODE_NAMES = Field(description="target mode")
    deltah: DeltaHArgs | None = Field(None, description="DELTAH only: wheel targets, tip-off flag")
    deltav: DeltaVArgs | None = Field(None, description="DELTAV only (required): the burn")
    legal_modes: ClassVar = tuple(Mode)
    hazardous: ClassVar = True

    @model_validator(mode="after")
    def _args_fit_mode(self):
        if self.mode == "DELTAV" and self.deltav is None:
            raise ValueError("mode DELTAV needs deltav: {target_q_RN, duration_s, main_engine, thruster_set}")
        if self.deltav is not None and self.mode != "DELTAV":
            raise ValueError(f"deltav is for mode DELTAV, not {self.mode}")
        if self.deltah is not None and self.mode != "DELTAH":
            raise ValueError(f"deltah is for mode DELTAH, not {self.mode}")
        return self


class StartDeltaH(CommandBase, DeltaHArgs):
    """Start a momentum unload (DeltaH) from Inertial, or from SunAcq for the
    tip-off contingency; it returns to that mode when done."""
    type: Literal["start_deltah"] = "start_deltah"
    legal_modes: ClassVar = (Mode.INERTIAL, Mode.SUNACQ)
    hazardous: ClassVar = True


class StartDeltaV(CommandBase, DeltaVArgs):
    """Start a DeltaV burn from Inertial (ground command only)."""
    type: Literal["start_deltav"] = "start_deltav"
    legal_modes: ClassVar = (Mode.INERTIAL,)
    hazardous: ClassVar = True


class SetDeltaVTarget(CommandBase):
    """Change the DeltaV attitude target during a burn (seed 001: "this target
    may be changed during a maneuver")."""
    type: Literal["set_deltav_target"] = "set_deltav_target"
    q_RN: UnitQuat = Field(description="new burn attitude, GCI, [w, x, y, z]")
    legal_modes: ClassVar = (Mode.DELTAV,)


class SelectThrusterSet(CommandBase):
    """Fly the primary or the redundant set of four ACS thrusters."""
    type: Literal["select_thruster_set"] = "select_thruster_set"
    thruster_set: Literal["primary", "redundant"] = Field(description="set of four thrusters")
    legal_modes: ClassVar = tuple(Mode)
    hazardous: ClassVar = True


class SetFdcCheck(CommandBase):
    """Enable or disable one failure-detection check."""
    type: Literal["set_fdc_check"] = "set_fdc_check"
    check: Literal["limits", "iru", "wheel", "star_tracker"] = Field(description="the check")
    enabled: bool = Field(description="true: the check runs and responds")
    legal_modes: ClassVar = tuple(Mode)


class StartCalibration(CommandBase):
    """Fly a calibration maneuver from the library (sim/calibration.py: the EVE
    cruciform, an off-point grid): the ground expands it into time-tagged
    set_target_snr commands from now, in the same queue (seed 001 "SNR
    Target": the delta quaternion "greatly simplifies the calibration
    maneuvers"). Inertial only: seed 001 "Inertial mode" performs them."""
    type: Literal["start_calibration"] = "start_calibration"
    maneuver: CalibrationManeuver
    legal_modes: ClassVar = (Mode.INERTIAL,)


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
GROUND_PROCEDURES = (StartCalibration,)      # expanded by the runner (the ground) into flight-software commands
_ALL = (SetTargetQuaternion, SetTargetSnr, ResetIntegrator, SetAttitudeOption, EnableScienceAutonomy, SelectCgt,
        SetMode, StartDeltaH, StartDeltaV, SetDeltaVTarget, SelectThrusterSet, SetFdcCheck, StartCalibration,
        InjectFault, ClearFault)
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
