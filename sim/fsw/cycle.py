"""One flight-software control cycle, compiled: estimate, control law of the
current mode, distribution to the actuators.

The mode machine and command handling stay in Python (flight_software.py);
this kernel returns an event code when something needs their attention.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.attitude import error_quat, small_angle_error
from sim.fsw.distribution import distribute
from sim.fsw.estimation import estimate_attitude
from sim.fsw.integral_enable import inside_box
from sim.fsw.pid import PidParams, pid_torque
from sim.fsw.rate_selection import least_squares_rate
from sim.modes import Mode

INERTIAL = int(Mode.INERTIAL)

EVENT_NONE = 0
EVENT_SLEW_SETTLED = 1

# flags[] slots
F_WATCH_SLEW = 0
N_FLAGS = 1


class FswParams(NamedTuple):
    pid: PidParams
    dist: np.ndarray        # (N, 3) wheel distribution matrix
    torque_limit: float     # software wheel torque limit, N m
    source: int             # estimation.SOURCE_*
    st_index: int
    q_BS: np.ndarray        # (4,) the flight software's mounting of the selected tracker
    iru_ch_axes_B: np.ndarray  # (6, 3) the flight software's IRU channel axes
    dt: float


class FswState(NamedTuple):
    mode: np.ndarray                 # (1,) int64
    q_est_BN: np.ndarray             # (4,)
    q_RN: np.ndarray                 # (4,) commanded target
    integral: np.ndarray             # (3,) integral of theta_e, rad s
    theta_e: np.ndarray              # (3,) rad, body axes
    omega_e: np.ndarray              # (3,) rad/s
    torque_cmd_B: np.ndarray         # (3,) N m
    torque_undelivered_B: np.ndarray  # (3,) N m withheld by the scaling
    flags: np.ndarray                # (N_FLAGS,) float
    rate_B: np.ndarray               # (3,) body rate from the IRU channels in use, rad/s
    int_active: np.ndarray           # (3,) bool: the integral torque acts on this axis
    torque_int_B: np.ndarray         # (3,) N m, the integral torque in torque_cmd_B
    iru_ch_use: np.ndarray           # (6,) bool: channels rate selection may use (FDC clears failed ones)


@njit(cache=True)
def torque_scale(s):
    """Delivered over desired torque of the last cycle, k_t of seed 000 eq. (1)
    (the distribution scales the whole vector, so one number says it)."""
    cmd = np.sqrt(np.sum(s.torque_cmd_B * s.torque_cmd_B))
    if cmd == 0.0:
        return 1.0
    return 1.0 - np.sqrt(np.sum(s.torque_undelivered_B * s.torque_undelivered_B)) / cmd


@njit(cache=True, inline="always")
def inertial_law(rate_B, s, p):
    """Seed 001 eq. (1)-(3): errors against the target and the PID torque."""
    s.theta_e[:] = small_angle_error(error_quat(s.q_RN, s.q_est_BN))
    s.omega_e[:] = -rate_B
    torque, torque_int = pid_torque(s.theta_e, s.omega_e, s.integral, s.int_active, torque_scale(s), p.pid)
    s.torque_cmd_B[:] = torque
    s.torque_int_B[:] = torque_int
    settled = inside_box(s.theta_e, s.omega_e, p.pid, np.zeros(3))
    if settled and s.flags[F_WATCH_SLEW] > 0.0:
        s.flags[F_WATCH_SLEW] = 0.0
        return EVENT_SLEW_SETTLED
    return EVENT_NONE


@njit(cache=True, inline="always")
def fsw_cycle(rec, s, p, act):
    rate, _ = least_squares_rate(rec.iru_rate_ch_rad_s, p.iru_ch_axes_B, rec.iru_ch_valid & s.iru_ch_use)
    s.rate_B[:] = rate
    k = p.st_index
    s.q_est_BN[:] = estimate_attitude(p.source, s.q_est_BN, s.rate_B, rec.st_q_SN[k], rec.st_valid[k], p.q_BS,
                                      p.dt)
    event = EVENT_NONE
    if s.mode[0] == INERTIAL:
        event = inertial_law(s.rate_B, s, p)
    else:
        s.torque_cmd_B[:] = 0.0
    s.torque_undelivered_B[:] = distribute(s.torque_cmd_B, p.dist, p.torque_limit, act.wheel_torque_Nm)
    return event
