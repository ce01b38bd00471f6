"""Inertial-mode PID, seed 001 eq. (3), with the seed 000 integral torque box.

    T = I (k_d omega_e + k_p theta_e + k_i int(theta_e))

* theta_e is magnitude-limited (the attitude limiter, seed 001 "Attitude
  control modes": overshoot suppression); scaling the vector, not clipping
  components, keeps the eigenaxis of the slew.
* The integral torque box, seed 000 option 3 as flown: while |theta_e| or
  |omega_e| exceeds its limit on any axis (seed 001 "Inertial mode"), the
  integrator input is zeroed so the integral torque is held.
* The integrator is limited per axis (seed 000: 0.01 rad s).
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.linalg import matvec


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


@njit(cache=True)
def limit_attitude(theta_e, limit):
    mag = np.sqrt(np.sum(theta_e * theta_e))
    if mag > limit:
        return theta_e * (limit / mag)
    return theta_e.copy()


@njit(cache=True)
def in_integral_box(theta_e, omega_e, theta_lim, omega_lim):
    for i in range(3):
        if abs(theta_e[i]) > theta_lim or abs(omega_e[i]) > omega_lim:
            return False
    return True


@njit(cache=True, inline="always")
def pid_torque(theta_e, omega_e, integral, p):
    """Commanded body torque (N m); updates `integral` in place. Returns the
    torque and whether the integrator ran this cycle."""
    theta = limit_attitude(theta_e, p.attitude_limit)
    active = in_integral_box(theta_e, omega_e, p.box_theta_lim, p.box_omega_lim)
    if active:
        for i in range(3):
            integral[i] = min(max(integral[i] + theta[i] * p.dt, -p.integrator_limit), p.integrator_limit)
    torque = matvec(p.inertia_B, p.kd * omega_e + p.kp * theta + p.ki * integral)
    return torque, active
