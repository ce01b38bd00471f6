"""The records that cross the wall between truth model and flight software.

The truth side writes a SensorRecord each control cycle; the flight software
reads it and writes an ActuatorCommand; the runner carries both across.
Neither side imports the other: they share only these layouts.
"""
from typing import NamedTuple

import numpy as np
from numba import njit


class SensorRecord(NamedTuple):
    iru_rate_B_rad_s: np.ndarray  # (3,) rate from differenced, quantised angle counts
    iru_valid: np.ndarray         # (3,) bool
    st_q_SN: np.ndarray           # (n_st, 4) each tracker's measured attitude of its own frame S
    st_valid: np.ndarray          # (n_st,) bool


class ActuatorCommand(NamedTuple):
    wheel_torque_Nm: np.ndarray   # (n_wheels,) motor torque commands
    thruster_pulses: np.ndarray   # (n_thrusters,) pulses this cycle, 0..max_pulses_per_cycle (float)
    engine_on: np.ndarray         # (1,) main engine on for the whole cycle: 1.0, else 0.0


def empty_sensor_record(n_star_trackers: int) -> SensorRecord:
    q = np.zeros((n_star_trackers, 4))
    q[:, 0] = 1.0
    return SensorRecord(np.zeros(3), np.ones(3, dtype=np.bool_), q, np.ones(n_star_trackers, dtype=np.bool_))


def empty_actuator_command(n_wheels: int, n_thrusters: int) -> ActuatorCommand:
    return ActuatorCommand(np.zeros(n_wheels), np.zeros(n_thrusters), np.zeros(1))


@njit(cache=True)
def copy_command(src: ActuatorCommand, dst: ActuatorCommand) -> None:
    """Latch a command (numba-compatible: called from the cycle loop)."""
    dst.wheel_torque_Nm[:] = src.wheel_torque_Nm
    dst.thruster_pulses[:] = src.thruster_pulses
    dst.engine_on[:] = src.engine_on
