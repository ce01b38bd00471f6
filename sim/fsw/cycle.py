"""One flight-software control cycle, compiled: rates, ephemeris and target,
attitude determination, the control law of the current mode, the torque
filter, distribution to the actuators.

The mode machine and command handling stay in Python (flight_software.py);
this kernel returns an event code (state.EVENT_*) when something needs their
attention. Records: sim/fsw/state.py.
"""
import numpy as np
from numba import njit

from sim.attitude import error_quat, small_angle_error
from sim.fsw.distribution import distribute
from sim.fsw.ekf import attitude_cycle
from sim.fsw.integral_enable import inside_box
from sim.fsw.pid import pid_torque
from sim.fsw.rate_selection import least_squares_rate
from sim.fsw.science import cgt_errors_B, science_acquired, science_errors
from sim.fsw.state import (
    EVENT_CGT_LOST,
    EVENT_NONE,
    EVENT_SCIENCE_ACQUIRED,
    EVENT_SLEW_SETTLED,
    F_CGT_OK,
    F_WATCH_SLEW,
)
from sim.fsw.targeting import ephemeris_tick
from sim.fsw.torque_filter import BANK_INERTIAL, BANK_SCIENCE, filter_torque
from sim.fsw.wheel_bias import wheel_bias_cycle
from sim.modes import Mode

INERTIAL = int(Mode.INERTIAL)
SCIENCE = int(Mode.SCIENCE)


@njit(cache=True)
def mode_uses_wheels(mode):
    """The wheel-based modes, whose wheel torques pass the zero-speed logic (seed 001)."""
    return mode == INERTIAL or mode == SCIENCE


@njit(cache=True)
def torque_scale(s):
    """Delivered over desired torque of the last cycle, k_t of seed 000 eq. (1)
    (the distribution scales the whole vector, so one number says it)."""
    cmd = np.sqrt(np.sum(s.torque_cmd_B * s.torque_cmd_B))
    if cmd == 0.0:
        return 1.0
    return 1.0 - np.sqrt(np.sum(s.torque_undelivered_B * s.torque_undelivered_B)) / cmd


@njit(cache=True, inline="always")
def pid_mode_law(rec, s, p):
    """Inertial (seed 001 eq. 1-3) and Science (eq. 4-5): errors, the PID with
    the integral torque box, the mode's torque filter. Returns an event."""
    theta_q = small_angle_error(error_quat(s.q_RN, s.q_est_BN))
    cgt_ok = cgt_errors_B(rec, s, p)
    s.flags[F_CGT_OK] = 1.0 if cgt_ok else 0.0
    event = EVENT_NONE
    bank = BANK_INERTIAL
    if s.mode[0] == SCIENCE and cgt_ok:
        science_errors(s, theta_q)
        bank = BANK_SCIENCE
    else:
        s.theta_e[:] = theta_q
        if s.mode[0] == SCIENCE:
            event = EVENT_CGT_LOST      # flown on the quaternion this cycle; the mode machine leaves Science
        elif science_acquired(s, p, cgt_ok):
            event = EVENT_SCIENCE_ACQUIRED
    s.omega_e[:] = -s.ekf.omega_est_B   # eq. (2), (5): the IRU rate less the estimated bias
    torque, torque_int = pid_torque(s.theta_e, s.omega_e, s.integral, s.int_active, torque_scale(s), p.pid)
    s.torque_pid_B[:] = torque
    s.torque_int_B[:] = torque_int
    filter_torque(s.torque_pid_B, p.tf, s.tf, bank, s.torque_cmd_B)
    if event == EVENT_NONE and s.flags[F_WATCH_SLEW] > 0.0 and inside_box(s.theta_e, s.omega_e, p.pid,
                                                                           np.zeros(3)):
        s.flags[F_WATCH_SLEW] = 0.0
        event = EVENT_SLEW_SETTLED
    return event


@njit(cache=True, inline="always")
def fsw_cycle(rec, s, p, act):
    rate, _ = least_squares_rate(rec.iru_rate_ch_rad_s, p.iru_ch_axes_B, rec.iru_ch_valid & s.iru_ch_use)
    s.rate_B[:] = rate
    ephemeris_tick(s, p)
    attitude_cycle(s.att_option[0], s.st_select[0], s.ekf, p.ekf, s.rate_B, rec.st_q_SN, rec.st_valid, s.sun_N,
                   rec.dss_angles_rad, rec.dss_valid)
    event = EVENT_NONE
    if mode_uses_wheels(s.mode[0]):
        event = pid_mode_law(rec, s, p)
    else:
        s.torque_pid_B[:] = 0.0
        s.torque_cmd_B[:] = 0.0
    s.torque_undelivered_B[:] = distribute(s.torque_cmd_B, p.dist, p.torque_limit, act.wheel_torque_Nm)
    if mode_uses_wheels(s.mode[0]):
        s.wheel_bias_Nm[:] = act.wheel_torque_Nm
        wheel_bias_cycle(rec.tach_speed_rad_s, rec.tach_valid, p.wb, p.torque_limit, act.wheel_torque_Nm)
        s.wheel_bias_Nm[:] = act.wheel_torque_Nm - s.wheel_bias_Nm
    return event
