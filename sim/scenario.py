"""Scenario files: spacecraft + initial state + time-tagged commands + output
specification + expectations, as YAML validated by pydantic.

`load_scenario` turns every problem into one ScenarioError whose message names
the file, the field path, what was expected and what was found.
"""
from __future__ import annotations

import typing
from datetime import datetime, timezone
from pathlib import Path
from typing import Any, Literal

import yaml
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    field_validator,
    model_validator,
)

from sim import spacecraft as spacecraft_files
from sim.calibration import MANEUVER_TYPES, ScheduledCalibration, duration_s
from sim.commands import COMMAND_TYPES, Command, split_time_tag
from sim.expectations import Expectation
from sim.faults import FAULT_KINDS
from sim.fsw.filter_design import make_torque_filter_params
from sim.modes import INITIAL_MODES, Mode
from sim.spacecraft.definition import Spacecraft
from sim.spacecraft.model import Quat, Vec3, check_unit_quaternion
from sim.telemetry_fields import always_fields, names_for
from sim.truth.orbit import OrbitElements

DEFAULT_EPOCH = datetime(2026, 3, 20, 12, 0, 0, tzinfo=timezone.utc)


class ScenarioError(Exception):
    """A bad scenario file; the message is meant for the user as it is."""


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class InitialState(Strict):
    mode: str = Field("INERTIAL", description="initial mode name")
    q_BN: Quat = Field((1.0, 0.0, 0.0, 0.0), description="initial attitude, in the frame q_BN_frame")
    q_BN_frame: Literal["gci", "snr"] = Field(
        "gci", description="gci: q_BN is the attitude in GCI; snr: q_BN is relative to the SNR frame at the epoch")
    omega_BN_B_rad_s: Vec3 = (0.0, 0.0, 0.0)
    h_wheels_Nms: list[float] | None = Field(None, description="axial momentum of each wheel; zero when absent")
    propellant_kg: float | None = Field(None, ge=0, description="propellant on board; full tanks when absent")
    target: Literal["attitude", "snr"] = Field(
        "attitude", description="initial target: the initial attitude (GCI), or the on-board SNR frame")
    target_q_RN: Quat | None = Field(None, description="initial GCI target; the initial attitude when absent")

    @field_validator("q_BN", "target_q_RN")
    @classmethod
    def _unit(cls, q):
        return q if q is None else check_unit_quaternion(q)

    @model_validator(mode="after")
    def _one_target(self) -> "InitialState":
        if self.target == "snr" and self.target_q_RN is not None:
            raise ValueError("target_q_RN: a GCI target cannot be given with target: snr; give one of them")
        return self

    @field_validator("mode")
    @classmethod
    def _known_mode(cls, m: str) -> str:
        names = [x.name for x in INITIAL_MODES]
        if m not in names:
            raise ValueError(f"expected one of {names} (DELTAH and DELTAV are entered by command: start_deltah, start_deltav), found {m!r}")
        return m


class ScheduledCommand(Strict):
    """A time-tagged command: `t_s` beside the command's own fields."""
    t_s: float = Field(ge=0, description="sim time at which the command is delivered")
    command: Command

    @model_validator(mode="before")
    @classmethod
    def _split(cls, data: Any) -> Any:
        return split_time_tag(data, "command")


class Environment(Strict):
    """Which parts of the world act; each disturbance can be switched off."""
    srp: bool = Field(True, description="solar radiation pressure force and torque")
    gravity_gradient: bool = True
    engine_torque: bool = Field(True, description="main-engine misalignment torque")
    zonal: bool = Field(True, description="J2, J3, J4")
    tesseral: bool = Field(True, description="C22, S22")
    third_body: bool = Field(True, description="Sun and Moon gravity")


class OutputSpec(Strict):
    period_s: float = Field(1.0, gt=0, description="telemetry sample period")
    fields: list[str] | None = Field(None, description="extra fields to record; all when absent")


class Scenario(Strict):
    name: str
    description: str = ""
    spacecraft: str
    overrides: dict[str, Any] = Field(default_factory=dict, description="spacecraft parameters to change")
    epoch_utc: datetime = DEFAULT_EPOCH
    duration_s: float = Field(gt=0)
    seed: int = Field(0, ge=0)
    initial: InitialState = InitialState()
    orbit: OrbitElements | None = Field(None, description="initial osculating elements; the spacecraft's when absent")
    environment: Environment = Environment()
    commands: list[ScheduledCommand] = Field(default_factory=list)
    calibrations: list[ScheduledCalibration] = Field(
        default_factory=list, description="calibration maneuvers, expanded into time-tagged target commands")
    output: OutputSpec = OutputSpec()
    expect: list[Expectation] = Field(default_factory=list)

    @field_validator("epoch_utc")
    @classmethod
    def _utc(cls, t: datetime) -> datetime:
        return t.replace(tzinfo=timezone.utc) if t.tzinfo is None else t.astimezone(timezone.utc)

    @field_validator("spacecraft")
    @classmethod
    def _known_spacecraft(cls, name: str) -> str:
        if name not in spacecraft_files.available():
            raise ValueError(f"expected one of {spacecraft_files.available()}, found {name!r}")
        return name

    @model_validator(mode="after")
    def _consistent(self) -> "Scenario":
        for i, c in enumerate(self.commands):
            if c.t_s > self.duration_s:
                raise ValueError(f"commands.{i}.t_s: {c.t_s:g} s is past the end of the run "
                                 f"(duration_s = {self.duration_s:g})")
        for i, c in enumerate(self.calibrations):
            end = c.t_s + duration_s(c.calibration)
            if end > self.duration_s:
                raise ValueError(f"calibrations.{i}: the maneuver ends at {end:g} s, past the end of the run "
                                 f"(duration_s = {self.duration_s:g})")
        return self

    def scheduled_commands(self) -> list[tuple[float, Any]]:
        """Every time-tagged command: the commands, then the calibrations' expansions."""
        out = [(c.t_s, c.command) for c in self.commands]
        for c in self.calibrations:
            out.extend(c.commands())
        return out

    def spacecraft_config(self) -> Spacecraft:
        return spacecraft_files.load_spacecraft(self.spacecraft, self.overrides)

    def recorded_fields(self, sc: Spacecraft) -> list[str]:
        names = names_for(sc)
        if self.output.fields is None:
            return list(names)
        wanted = set(always_fields(sc.n_wheels)) | set(self.output.fields) | {e.field for e in self.expect}
        return [n for n in names if n in wanted]


def _spacecraft_checks(s: Scenario, sc: Spacecraft) -> list[str]:
    """Checks that need the spacecraft itself."""
    problems = []
    h = s.initial.h_wheels_Nms
    if s.initial.propellant_kg is not None and s.initial.propellant_kg > sc.mass.propellant_kg:
        problems.append(f"initial.propellant_kg: {s.initial.propellant_kg:g} kg exceeds the full load of "
                        f"{sc.mass.propellant_kg:g} kg")
    if h is not None and len(h) != sc.n_wheels:
        problems.append(f"initial.h_wheels_Nms: expected {sc.n_wheels} values (one per wheel), found {len(h)}")
    cycle = sc.timing.control_dt_s
    ratio = s.output.period_s / cycle
    if abs(ratio - round(ratio)) > 1e-9:
        problems.append(f"output.period_s: expected a whole multiple of the control cycle ({cycle:g} s), "
                        f"found {s.output.period_s:g}")
    if sc.fsw.ephemeris is None and "snr" in (s.initial.target, s.initial.q_BN_frame):
        problems.append("initial: target or q_BN_frame 'snr' needs the on-board ephemeris (fsw.ephemeris), "
                        "which this spacecraft does not have")
    section = {"SUNACQ": "sun_acquisition", "SAFEHOLD": "safehold"}.get(s.initial.mode)
    if section and getattr(sc.fsw, section) is None:
        problems.append(f"initial.mode: {s.initial.mode} needs fsw.{section}, which this spacecraft does not have")
    try:
        make_torque_filter_params(sc.fsw.torque_filters, cycle)
    except ValueError as err:   # a filter that cannot be built at this control rate
        problems.append(f"fsw.{err}")
    known = names_for(sc)
    for i, f in enumerate(s.output.fields or []):
        if f not in known:
            problems.append(f"output.fields.{i}: unknown field {f!r}; allowed: {', '.join(known)}")
    for i, e in enumerate(s.expect):
        if e.field not in known:
            problems.append(f"expect.{i}.field: unknown field {e.field!r}; allowed: {', '.join(known)}")
    return problems


def _loc(loc: tuple) -> str:
    parts = []
    for p in loc:
        # The discriminated union adds the tag and our wrapper a "command" level:
        # neither is something the user wrote.
        if p in ("command", "calibration") or p in COMMAND_TYPES or p in FAULT_KINDS or p in MANEUVER_TYPES:
            continue
        parts.append(str(p))
    return ".".join(parts)


def _first_model(annotation) -> type[BaseModel] | None:
    """The model inside an annotation such as list[X], X | None, Annotated[Union[X, ...], ...]."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in typing.get_args(annotation):
        found = _first_model(arg)
        if found is not None:
            return found
    return None


def _allowed_fields(root: type[BaseModel], loc: tuple) -> list[str]:
    """The field names allowed where loc's last element was found."""
    model: type[BaseModel] | None = root
    for p in loc[:-1]:
        if p in COMMAND_TYPES or p in FAULT_KINDS or p in MANEUVER_TYPES:
            model = COMMAND_TYPES.get(p) or FAULT_KINDS.get(p) or MANEUVER_TYPES[p]
        elif isinstance(p, str):
            if model is None or p not in model.model_fields:
                return []
            model = _first_model(model.model_fields[p].annotation)
    if model is None:
        return []
    names = list(model.model_fields)
    return ["t_s", *names] if model in COMMAND_TYPES.values() else names


def _message(e: dict, root: type[BaseModel]) -> tuple[tuple, str]:
    """(where, what) of one pydantic error, in the user's words."""
    loc, kind, found = e["loc"], e["type"], e.get("input")
    if kind == "extra_forbidden":
        allowed = _allowed_fields(root, loc)
        return loc, f"unknown field {loc[-1]!r}" + (f"; allowed: {', '.join(allowed)}" if allowed else "")
    if kind in ("union_tag_invalid", "union_tag_not_found"):
        tag = e.get("ctx", {}).get("discriminator", "'type'").strip("'")
        kinds = {"type": ("command type", COMMAND_TYPES), "maneuver": ("calibration maneuver", MANEUVER_TYPES)}
        noun, names = kinds.get(tag, ("fault kind", FAULT_KINDS))
        allowed = ", ".join(names)
        what = f"unknown {noun} {found.get(tag)!r}" if kind == "union_tag_invalid" else "missing"
        return (*loc, tag), f"{what}; allowed: {allowed}"
    msg = e["msg"].removeprefix("Value error, ")
    if kind not in ("value_error", "missing") and not isinstance(found, dict):
        msg += f" (found {found!r})"
    return loc, msg


def _format_errors(err: ValidationError, root: type[BaseModel], prefix: str = "") -> list[str]:
    lines = []
    for e in err.errors(include_url=False):
        loc, msg = _message(e, root)
        where = prefix + _loc(loc)
        lines.append(f"{where}: {msg}" if where else msg)
    return lines


def parse_scenario(data: Any, source: str = "<scenario>") -> tuple[Scenario, Spacecraft]:
    def fail(lines: list[str]):
        raise ScenarioError("\n".join(f"{source}: {line}" for line in lines))

    if data is None:
        fail(["the file is empty; expected a scenario mapping (name, spacecraft, duration_s, ...)"])
    if not isinstance(data, dict):
        fail([f"expected a mapping at the top level, found {type(data).__name__}"])
    try:
        s = Scenario.model_validate(data)
    except ValidationError as err:
        fail(_format_errors(err, Scenario))
    try:
        sc = s.spacecraft_config()
    except ValidationError as err:
        fail(_format_errors(err, Spacecraft, prefix="overrides."))
    problems = _spacecraft_checks(s, sc)
    if problems:
        fail(problems)
    return s, sc


def load_scenario(path: str | Path) -> tuple[Scenario, Spacecraft]:
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as err:
        raise ScenarioError(f"{path}: cannot read the scenario file ({err.strerror})") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        where = f":{mark.line + 1}:{mark.column + 1}" if mark else ""
        raise ScenarioError(f"{path}{where}: not valid YAML ({getattr(err, 'problem', err)})") from None
    return parse_scenario(data, str(path))


def initial_mode(s: Scenario) -> Mode:
    return Mode[s.initial.mode]
