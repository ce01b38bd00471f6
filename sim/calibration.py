"""SDO instrument calibration maneuvers, expanded into time-tagged ground
commands (`SetTargetSnr` with a delta quaternion and a dwell).

Seed 000: "a series of small slews (on the order of 5 arcsec - 9000 arcsec)
with fast slew time requirements (2 - 5 minutes)", e.g. "the EVE Cruciform
calibration maneuver". Seed 001 "Inertial mode": the target may be "the SNR
quaternion [times] a ground-commanded delta quaternion, which allows the
spacecraft to be pointed away from the default target by a known angle";
"Instrument calibrations require that the spacecraft point the SRB up to 2.5
degrees in pitch and yaw away from the center of the Sun".

Off-point geometry. A pointing (pitch, yaw) is the delta quaternion
q_RS = Rz(yaw) (x) Ry(pitch): yaw about SNR +Z, then pitch about the yawed
+Y (an azimuth-elevation mount; scipy ``from_euler("ZY", [yaw, pitch])``).
It carries the boresight (body +X) to

    b_S = [cos(pitch) cos(yaw), cos(pitch) sin(yaw), -sin(pitch)]

so yaw = atan2(b_y, b_x) and pitch = atan2(-b_z, hypot(b_x, b_y)) exactly:
positive yaw moves the boresight toward SNR +Y, positive pitch toward -Z
(right-handed rotations), and the target Y axis stays in the SNR X-Y plane
(no roll about the boresight). Chosen over the rotation vector [0, p, y]
because the commanded angles are then exact, not first-order.

Off-points beyond the guide telescopes' fine range (seed 000: "approximately
+-95 arcsec") take the Sun out of the CGT, so such maneuvers belong in
Inertial mode; expand() emits only the target commands, the mode is the
operator's (or the scenario's) to set.
"""
from __future__ import annotations

import math
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    TypeAdapter,
    field_validator,
    model_validator,
)

from sim.attitude import ARCSEC_PER_RAD

STEP_MIN_ARCSEC, STEP_MAX_ARCSEC = 5.0, 9000.0      # seed 000: slews "5 arcsec - 9000 arcsec"
OFFPOINT_MAX_ARCSEC = 2.5 * 3600.0                   # seed 001: "up to 2.5 degrees in pitch and yaw"
ALLOWANCE_MIN_S, ALLOWANCE_MAX_S = 120.0, 300.0      # seed 000: "slew time requirements (2 - 5 minutes)"
_TOL_ARCSEC = 1e-6                                   # float slack so that e.g. 10 x 900 arcsec == 9000 passes


def _range_error(field: str, value: float, lo: float, hi: float, unit: str, source: str) -> ValueError:
    return ValueError(f"{field}: expected {lo:g} to {hi:g} {unit} ({source}), found {value:g}")


def _check_step(field: str, v: float) -> float:
    if not STEP_MIN_ARCSEC <= v <= STEP_MAX_ARCSEC:
        raise _range_error(field, v, STEP_MIN_ARCSEC, STEP_MAX_ARCSEC, "arcsec",
                           "seed 000: small slews of 5 - 9000 arcsec")
    return v


def delta_quat(pitch_arcsec: float, yaw_arcsec: float) -> tuple[float, float, float, float]:
    """q_RS = Rz(yaw) (x) Ry(pitch), scalar-first (see the module docstring)."""
    p, y = pitch_arcsec / ARCSEC_PER_RAD, yaw_arcsec / ARCSEC_PER_RAD
    cp, sp, cy, sy = math.cos(p / 2), math.sin(p / 2), math.cos(y / 2), math.sin(y / 2)
    # Hamilton product [cy, 0, 0, sy] (x) [cp, 0, sp, 0], written out.
    return (cy * cp, -sy * sp, cy * sp, sy * cp)


def slew_angle_arcsec(q_a, q_b) -> float:
    """Eigen-axis angle of the slew from target q_a to q_b (angle of q_a^* (x) q_b).
    atan2 rather than acos keeps 5-arcsec steps accurate."""
    a, b = np.asarray(q_a, float), np.asarray(q_b, float)
    w = a[0] * b[0] + a[1:] @ b[1:]
    v = a[0] * b[1:] - b[0] * a[1:] - np.cross(a[1:], b[1:])
    return 2.0 * math.atan2(float(np.linalg.norm(v)), abs(float(w))) * ARCSEC_PER_RAD


class _ManeuverBase(BaseModel):
    """Shared checks; each maneuver declares dwell_s and allowance_s with its own defaults."""
    model_config = ConfigDict(extra="forbid", frozen=True)

    @field_validator("allowance_s", check_fields=False)
    @classmethod
    def _allowance(cls, v: float) -> float:
        if not ALLOWANCE_MIN_S <= v <= ALLOWANCE_MAX_S:
            raise _range_error("allowance_s", v, ALLOWANCE_MIN_S, ALLOWANCE_MAX_S, "s",
                               "seed 000: slew time requirements of 2 - 5 minutes")
        return v

    def _extent_fields(self) -> tuple[str, float]:
        raise NotImplementedError

    def pointings_arcsec(self) -> list[tuple[float, float]]:
        """Every commanded (pitch, yaw) in order, ending at Sun centre (0, 0)."""
        raise NotImplementedError

    @model_validator(mode="after")
    def _limits(self):
        # Extent first: it is cheap and bounds the number of points enumerated below.
        names, extent = self._extent_fields()
        if extent > OFFPOINT_MAX_ARCSEC + _TOL_ARCSEC:
            raise ValueError(f"{names}: the farthest point is {extent:g} arcsec from Sun centre in pitch or yaw; "
                             f"expected at most {OFFPOINT_MAX_ARCSEC:g} arcsec (seed 001: up to 2.5 degrees "
                             f"in pitch and yaw)")
        # Every slew, including the first (from Sun centre) and the returns.
        pts = [(0.0, 0.0)] + self.pointings_arcsec()
        qs = [delta_quat(p, y) for p, y in pts]
        for i in range(len(qs) - 1):
            a = slew_angle_arcsec(qs[i], qs[i + 1])
            if not STEP_MIN_ARCSEC - _TOL_ARCSEC <= a <= STEP_MAX_ARCSEC + _TOL_ARCSEC:
                raise ValueError(f"{names}: slew {i} from (pitch, yaw) = ({pts[i][0]:g}, {pts[i][1]:g}) to "
                                 f"({pts[i + 1][0]:g}, {pts[i + 1][1]:g}) arcsec is {a:.6g} arcsec; expected "
                                 f"{STEP_MIN_ARCSEC:g} to {STEP_MAX_ARCSEC:g} arcsec per step "
                                 f"(seed 000: small slews of 5 - 9000 arcsec)")
        return self


class EveCruciform(_ManeuverBase):
    """The EVE cruciform (seed 000): a cross through Sun centre. Arms in order
    +pitch, -pitch, +yaw, -yaw; each goes out from Sun centre in n_steps steps
    of step_arcsec and returns to centre in one slew (a reference point
    between arms, and each return is at most the arm, so within 9000 arcsec).

    Defaults are assumptions: 10 x 900 arcsec = 2.5 deg arms, the full seed-001
    range (NASA's SDO news describes the cruciform as about 2.5 deg each way);
    allowance 300 s, the top of seed 000's 2-5 min, because the returns are
    the full arm; dwell 180 s so the 44 points take about 5.8 h (NASA reported
    a cruciform of about six hours)."""
    maneuver: Literal["eve_cruciform"] = "eve_cruciform"
    step_arcsec: float = Field(900.0, description="step along each arm, 5 to 9000 arcsec",
                               json_schema_extra={"minimum": STEP_MIN_ARCSEC, "maximum": STEP_MAX_ARCSEC})
    n_steps: int = Field(10, ge=1, description="points on each arm")
    dwell_s: float = Field(180.0, ge=0, description="time on each point after the allowance")
    allowance_s: float = Field(300.0, description="slew-plus-settle time before each dwell, 120 to 300 s",
                               json_schema_extra={"minimum": ALLOWANCE_MIN_S, "maximum": ALLOWANCE_MAX_S})

    @field_validator("step_arcsec")
    @classmethod
    def _step(cls, v: float) -> float:
        return _check_step("step_arcsec", v)

    def _extent_fields(self):
        return "n_steps x step_arcsec", self.n_steps * self.step_arcsec

    def pointings_arcsec(self):
        out = []
        for axis, sign in ((0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0)):
            for k in range(1, self.n_steps + 1):
                p = [0.0, 0.0]
                p[axis] = sign * k * self.step_arcsec
                out.append((p[0], p[1]))
            out.append((0.0, 0.0))
        return out


class OffpointGrid(_ManeuverBase):
    """An HMI/AIA-style off-point grid (flat-field style): n_rows pitch values
    x n_cols yaw values at spacing_arcsec, centred on Sun centre, flown row by
    row in a serpentine so every in-grid slew is exactly one spacing; the
    first slew (centre to a corner) and the final return are validated too.

    Defaults are assumptions: 5 x 5 at 300 arcsec (+-600 arcsec, the Sun stays
    partly in the imagers' field); allowance 120 s, the bottom of seed 000's
    2-5 min, enough for 300-arcsec steps; dwell 60 s."""
    maneuver: Literal["offpoint_grid"] = "offpoint_grid"
    spacing_arcsec: float = Field(300.0, description="grid spacing, 5 to 9000 arcsec",
                                  json_schema_extra={"minimum": STEP_MIN_ARCSEC, "maximum": STEP_MAX_ARCSEC})
    # Upper bound 99 is an assumption: a typo must not expand into millions of commands.
    n_rows: int = Field(5, ge=1, le=99, description="pitch values (rows)")
    n_cols: int = Field(5, ge=1, le=99, description="yaw values (columns)")
    dwell_s: float = Field(60.0, ge=0, description="time on each point after the allowance")
    allowance_s: float = Field(120.0, description="slew-plus-settle time before each dwell, 120 to 300 s",
                               json_schema_extra={"minimum": ALLOWANCE_MIN_S, "maximum": ALLOWANCE_MAX_S})

    @field_validator("spacing_arcsec")
    @classmethod
    def _spacing(cls, v: float) -> float:
        return _check_step("spacing_arcsec", v)

    def _extent_fields(self):
        return "n_rows, n_cols x spacing_arcsec", (max(self.n_rows, self.n_cols) - 1) / 2 * self.spacing_arcsec

    def pointings_arcsec(self):
        def axis(n):   # centred: -(n-1)/2 .. +(n-1)/2 spacings
            return [(i - (n - 1) / 2) * self.spacing_arcsec for i in range(n)]
        yaws, out = axis(self.n_cols), []
        for r, pitch in enumerate(axis(self.n_rows)):
            for yaw in (yaws if r % 2 == 0 else yaws[::-1]):
                out.append((pitch, yaw))
        return out + [(0.0, 0.0)]


CalibrationManeuver = Annotated[EveCruciform | OffpointGrid, Field(discriminator="maneuver")]
CALIBRATION_ADAPTER: TypeAdapter = TypeAdapter(CalibrationManeuver)
MANEUVER_TYPES = {c.model_fields["maneuver"].default: c for c in (EveCruciform, OffpointGrid)}


def expand(maneuver: EveCruciform | OffpointGrid, t0_s: float) -> list[tuple[float, Any]]:
    """Time-tagged commands: the first at t0_s, each pointing followed by its
    allowance + dwell before the next, the last a return to Sun centre
    (identity delta). Tags are t0 + k * period, not a running sum, so they do
    not drift however long the list."""
    # imported here: sim.commands imports this module for start_calibration's model
    from sim.commands import SetTargetSnr

    if t0_s < 0:
        raise ValueError(f"t0_s: expected >= 0 s, found {t0_s:g}")
    period_s = maneuver.allowance_s + maneuver.dwell_s
    return [(t0_s + k * period_s, SetTargetSnr(delta_q=delta_quat(p, y)))
            for k, (p, y) in enumerate(maneuver.pointings_arcsec())]


def duration_s(maneuver: EveCruciform | OffpointGrid) -> float:
    """From the first command until the final return to Sun centre has had its
    allowance (settled; no dwell is owed there, science resumes)."""
    n = len(maneuver.pointings_arcsec())
    return (n - 1) * (maneuver.allowance_s + maneuver.dwell_s) + maneuver.allowance_s


class ScheduledCalibration(BaseModel):
    """A calibration in a scenario's list: `t_s` beside the maneuver's own
    fields, e.g. ``{t_s: 100, maneuver: eve_cruciform, step_arcsec: 600}``."""
    model_config = ConfigDict(extra="forbid", frozen=True)
    t_s: float = Field(ge=0, description="sim time of the first command")
    calibration: CalibrationManeuver

    @model_validator(mode="before")
    @classmethod
    def _split(cls, data: Any) -> Any:
        from sim.commands import (
            split_time_tag,  # here: sim.commands imports this module
        )

        return split_time_tag(data, "calibration")

    def commands(self) -> list[tuple[float, Any]]:
        return expand(self.calibration, self.t_s)
