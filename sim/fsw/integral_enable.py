"""When the integral torque may act: the three options of seed 000's trade
study ("Trade study on disabling the integral torque").

* Option 1, simplified Routh criterion, eq. (1): k_i < k_p,eff k_d k_t, with
  k_t the ratio of delivered to desired torque (the torque scaling of the last
  cycle) and k_p,eff the effective attitude gain through the attitude limiter.
* Option 2, PD torque and attitude saturation: the integral acts only while
  the PD torque is below the actuator saturation torque tau_sat and the
  attitude error is not limited.
* Option 3, the integral torque box (flown): |theta_e| < theta_lim and
  |omega_e| < omega_lim, on every axis (seed 001 "Inertial mode": "if the
  attitude and/or rate errors for any axis exceed database specified
  limits"), or axis by axis when the box is configured per axis.
"""
import numpy as np
from numba import njit

ROUTH, PD_SATURATION, BOX = 1, 2, 3


@njit(cache=True)
def _routh(theta_e, theta_limited, k_t, p):
    mag = np.sqrt(np.sum(theta_e * theta_e))
    kp_eff = p.kp if mag == 0.0 else p.kp * np.sqrt(np.sum(theta_limited * theta_limited)) / mag
    return p.ki < kp_eff * p.kd * k_t


@njit(cache=True)
def _pd_unsaturated(theta_e, pd_torque_B, p):
    if np.sqrt(np.sum(theta_e * theta_e)) > p.attitude_limit:
        return False
    return np.max(np.abs(pd_torque_B)) < p.torque_sat


@njit(cache=True)
def inside_box(theta_e, omega_e, p, out):
    """Per axis whether the errors are inside the box; returns all axes inside.
    Also the flight software's "slewing has stopped" (seed 000: omega_lim is
    "small enough to indicate slewing has stopped")."""
    inside = True
    for i in range(3):
        ok = abs(theta_e[i]) <= p.box_theta_lim and abs(omega_e[i]) <= p.box_omega_lim
        out[i] = ok
        inside = inside and ok
    return inside


@njit(cache=True, inline="always")
def integral_enabled(theta_e, omega_e, theta_limited, pd_torque_B, k_t, p, out):
    """Write into out (3,) whether each axis may use its integral torque."""
    if p.box_option == ROUTH:
        out[:] = _routh(theta_e, theta_limited, k_t, p)
    elif p.box_option == PD_SATURATION:
        out[:] = _pd_unsaturated(theta_e, pd_torque_B, p)
    else:
        inside = inside_box(theta_e, omega_e, p, out)
        if not p.box_per_axis:
            out[:] = inside
