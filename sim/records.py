"""The records that cross the wall between truth model and flight software.

The truth side writes a SensorRecord each control cycle; the flight software
reads it and writes an ActuatorCommand; the runner carries both across.
Neither side imports the other: they share only these layouts.
"""
from typing import NamedTuple

import numpy as np
from numba import njit


class SensorRecord(NamedTuple):
    iru_rate_ch_rad_s: np.ndarray  # (6,) each IRU channel: differenced, quantised angle counts over the cycle
    iru_ch_valid: np.ndarray       # (6,) bool
    st_q_SN: np.ndarray            # (n_st, 4) each tracker's measured attitude of its own frame S (0 when invalid)
    st_valid: np.ndarray           # (n_st,) bool
    css_current_A: np.ndarray      # (16,) coarse Sun sensor currents, primary set then backup set
    dss_angles_rad: np.ndarray     # (2,) digital Sun sensor tangent-plane angles alpha, beta
    dss_valid: np.ndarray          # (1,) bool
    gt_offset_G_rad: np.ndarray    # (4, 2) each guide telescope's S_y, S_z (seed 001 eq. 4)
    gt_valid: np.ndarray           # (4,) bool
    gt_in_range: np.ndarray        # (4,) bool: inside the fine range (not saturated)
    tach_speed_rad_s: np.ndarray   # (n_wheels,) wheel tachometers
    tach_valid: np.ndarray         # (n_wheels,) bool


class ActuatorCommand(NamedTuple):
    wheel_torque_Nm: np.ndarray   # (n_wheels,) motor torque commands
    thruster_pulses: np.ndarray   # (n_thrusters,) pulses this cycle, 0..max_pulses_per_cycle (float)
    engine_on: np.ndarray         # (1,) main engine on for the whole cycle: 1.0, else 0.0


def empty_sensor_record(n_star_trackers: int, n_wheels: int, n_css: int = 16, n_gt: int = 4) -> SensorRecord:
    """Absent sensors have zero units (n_css, n_gt) or never turn valid (DSS, tachometers)."""
    def flags(n):
        return np.zeros(n, dtype=np.bool_)

    return SensorRecord(np.zeros(6), flags(6), np.zeros((n_star_trackers, 4)), flags(n_star_trackers),
                        np.zeros(n_css), np.zeros(2), flags(1), np.zeros((n_gt, 2)), flags(n_gt), flags(n_gt),
                        np.zeros(n_wheels), flags(n_wheels))


def empty_actuator_command(n_wheels: int, n_thrusters: int) -> ActuatorCommand:
    return ActuatorCommand(np.zeros(n_wheels), np.zeros(n_thrusters), np.zeros(1))


@njit(cache=True)
def copy_command(src: ActuatorCommand, dst: ActuatorCommand) -> None:
    """Latch a command (numba-compatible: called from the cycle loop)."""
    dst.wheel_torque_Nm[:] = src.wheel_torque_Nm
    dst.thruster_pulses[:] = src.thruster_pulses
    dst.engine_on[:] = src.engine_on
