"""Inertial- and Science-mode PID, seed 001 eq. (3), with the integral
torque logic of seed 000.

    T = I (k_d omega_e + k_p theta_e + k_i int(theta_e))

* theta_e is magnitude-limited (the attitude limiter, seed 001 "Attitude
  control modes": overshoot suppression); scaling the vector, not clipping
  components, keeps the eigenaxis of the slew.
* When the integral may act: sim/fsw/integral_enable.py (options 1-3).
* How it is disabled (seed 000 "Integral torque reset analysis"):
  HOLD (flown): zero the integrator input, the integral torque is held;
  ZERO: zero the integral torque but keep integrating;
  ZERO_RESET: zero the integral torque and reset the integrator on re-entry.
* The integrator is limited per axis (seed 000: 0.01 rad s).
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.fsw.integral_enable import integral_enabled
from sim.linalg import matvec

HOLD, ZERO, ZERO_RESET = 0, 1, 2
DISABLE_METHODS = {"hold": HOLD, "zero": ZERO, "zero_reset": ZERO_RESET}


class PidParams(NamedTuple):
    inertia_B: np.ndarray   # (3, 3) the flight software's inertia
    kp: float
    kd: float
    ki: float
    integrator_limit: float
    box_theta_lim: float
    box_omega_lim: float
    attitude_limit: float
    dt: float
    box_option: int         # integral_enable.ROUTH | PD_SATURATION | BOX
    box_per_axis: bool
    disable_method: int     # HOLD | ZERO | ZERO_RESET
    torque_sat: float       # actuator saturation torque for option 2, N m


@njit(cache=True)
def limit_attitude(theta_e, limit):
    mag = np.sqrt(np.sum(theta_e * theta_e))
    if mag > limit:
        return theta_e * (limit / mag)
    return theta_e.copy()


@njit(cache=True, inline="always")
def pid_torque(theta_e, omega_e, integral, active, k_t, p):
    """Commanded body torque (N m) and the integral torque in it (N m).
    Updates `integral` and `active` (3,) in place; active holds, per axis,
    whether the integral torque acts (on entry: whether it acted last cycle).
    k_t: delivered over desired torque of the last cycle (option 1)."""
    theta = limit_attitude(theta_e, p.attitude_limit)
    pd = matvec(p.inertia_B, p.kd * omega_e + p.kp * theta)
    was = active.copy()
    integral_enabled(theta_e, omega_e, theta, pd, k_t, p, active)
    use = np.zeros(3)
    for i in range(3):
        on = active[i]
        if p.disable_method == ZERO_RESET and on and not was[i]:
            integral[i] = 0.0
        if on or p.disable_method == ZERO:
            integral[i] = min(max(integral[i] + theta[i] * p.dt, -p.integrator_limit), p.integrator_limit)
        if on or p.disable_method == HOLD:
            use[i] = integral[i]
    torque_int = matvec(p.inertia_B, p.ki * use)
    return pd + torque_int, torque_int
