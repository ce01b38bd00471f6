"""Telemetry frames: a flat record (name -> number or short string) sampled
at the recorded rate, and the CSV writer for them.

The runner owns both sides of the wall, so a frame may hold truth values
(att_err_arcsec is truth against the current target) beside flight-software
values; names say which (q_BN truth, q_est_BN the flight software's estimate).
Flight-software values are those of the last completed control cycle.
"""
from __future__ import annotations

import functools
from typing import IO

import numpy as np
from numba import njit

from sim.attitude import ARCSEC_PER_RAD, quat_conj, quat_mul, quat_rotate, rotation_angle
from sim.fsw.cycle import F_INTEGRATOR_ACTIVE
from sim.modes import Mode
from sim.truth.rigid_body import IH, IQ, IW, angular_momentum_B
from sim.truth.wheels import wheel_speeds_rad_s

RPM_PER_RAD_S = 60.0 / (2.0 * np.pi)
XYZ = ("x", "y", "z")
WXYZ = ("w", "x", "y", "z")


def _vec(prefix: str, unit: str = "", axes=XYZ) -> list[str]:
    return [f"{prefix}_{a}{unit}" for a in axes]


def _wheels(prefix: str, unit: str, n: int) -> list[str]:
    return [f"{prefix}_{i + 1}_{unit}" for i in range(n)]


def always_fields(n_wheels: int = 4) -> list[str]:
    """The columns every telemetry file has."""
    return (["t_s", "mode"] + _vec("q_BN", axes=WXYZ) + _vec("omega_BN_B", "_rad_s")
            + _wheels("h_wheel", "Nms", n_wheels) + _vec("h_total_N", "_Nms") + ["att_err_arcsec"])


@functools.cache
def field_names(n_wheels: int = 4) -> tuple[str, ...]:
    return tuple(always_fields(n_wheels)) + tuple(
        ["h_total_Nms", "est_err_arcsec"] + _vec("q_est_BN", axes=WXYZ) + _vec("q_RN", axes=WXYZ)
        + _vec("theta_e_B", "_arcsec") + _vec("iru_rate_B", "_rad_s")
        + _vec("torque_cmd_B", "_Nm") + _vec("torque_undelivered_B", "_Nm")
        + ["integrator_active"] + _vec("integral_B", "_rad_s")
        + _wheels("wheel_speed", "rpm", n_wheels) + _wheels("wheel_cmd", "Nm", n_wheels))



@njit(cache=True)
def _numbers(t_s, x, body, s, rate_B, wheel_cmd):
    """The numeric fields in field_names() order (mode left out), compiled:
    telemetry is sampled often enough that Python-level math would dominate."""
    n = body.axes_B.shape[0]
    q_BN = x[IQ:IQ + 4]
    omega = x[IW:IW + 3]
    h = x[IH:IH + n]
    h_total_N = quat_rotate(q_BN, angular_momentum_B(x, body))
    head = np.array([t_s])
    return np.concatenate((
        head, q_BN, omega, h, h_total_N,
        np.array([rotation_angle(quat_mul(quat_conj(s.q_RN), q_BN)) * ARCSEC_PER_RAD,
                  np.sqrt(np.sum(h_total_N * h_total_N)),
                  rotation_angle(quat_mul(quat_conj(s.q_est_BN), q_BN)) * ARCSEC_PER_RAD]),
        s.q_est_BN, s.q_RN, s.theta_e * ARCSEC_PER_RAD, rate_B, s.torque_cmd_B, s.torque_undelivered_B,
        s.flags[F_INTEGRATOR_ACTIVE:F_INTEGRATOR_ACTIVE + 1], s.integral,
        wheel_speeds_rad_s(h, omega, body.axes_B, body.spin_inertia) * RPM_PER_RAD_S, wheel_cmd))


def sample(t_s: float, x: np.ndarray, body, fsw_state, sensors, act) -> tuple[str, np.ndarray]:
    """Every field at one instant: the mode's name and the numeric fields."""
    return (Mode(int(fsw_state.mode[0])).name,
            _numbers(t_s, x, body, fsw_state, sensors.iru_rate_B_rad_s, act.wheel_torque_Nm))


class Layout:
    """The fields a run records and where they sit among a sample's numbers.
    Recorded fields keep field_names() order, so they open with t_s, mode."""

    def __init__(self, fields: list[str], n_wheels: int):
        numeric = [n for n in field_names(n_wheels) if n != "mode"]
        if list(fields[:2]) != ["t_s", "mode"]:
            raise ValueError(f"recorded fields must open with t_s, mode; found {fields[:2]}")
        self.fields = list(fields)
        self.numeric_fields = [f for f in fields if f != "mode"]
        self.index = np.array([numeric.index(f) for f in self.numeric_fields], dtype=np.int64)


class Frame:
    """One recorded sample: the mode and the recorded numeric fields, in order."""
    __slots__ = ("mode", "values", "layout")

    def __init__(self, mode: str, values: np.ndarray, layout: Layout):
        self.mode, self.values, self.layout = mode, values, layout

    @property
    def t_s(self) -> float:
        return float(self.values[0])

    def as_dict(self) -> dict:
        out = dict(zip(self.layout.numeric_fields, self.values.tolist()))
        out["mode"] = self.mode
        return {f: out[f] for f in self.layout.fields}


def columns(frames: list[Frame], layout: Layout) -> dict[str, list]:
    """Recorded samples as one list per field."""
    table = np.array([f.values for f in frames]).reshape(len(frames), len(layout.numeric_fields))
    out = {f: table[:, i].tolist() for i, f in enumerate(layout.numeric_fields)}
    out["mode"] = [f.mode for f in frames]
    return {f: out[f] for f in layout.fields}


class CsvTelemetryWriter:
    """Writes frames to CSV with a header row. Floats are written with repr(),
    the shortest string that reads back to the same double: exact, and
    byte-identical from run to run."""

    def __init__(self, stream: IO[str], layout: Layout):
        self._stream = stream
        stream.write(",".join(layout.fields) + "\n")

    def write(self, frame: Frame) -> None:
        v = frame.values.tolist()
        self._stream.write(f"{v[0]!r},{frame.mode}," + ",".join(map(repr, v[1:])) + "\n")
