"""Sun Acquisition, seed 001 eq. (6):

    T = K_p (s x s_d) + K_d omega           (eclipse: T = K_d omega)

with s the CSS Sun vector in the body frame, s_d the desired one (+X) and
omega the IRU rate. Seed 001 writes T with the sign of a wheel (reaction)
torque; the body torque applied here is its negative,
T_B = K_p (s_d x s) - K_d omega, which turns the body so that s moves toward
s_d (with d s/dt = s x omega in the body frame, omega along s_d x s does).

Attitude limiting (seed 001 "Attitude control modes": used in SunAcq) caps
|s_d x s|, and beyond 90 deg of Sun angle holds it at the cap along the
rotation axis: sin() alone would fall to zero at the anti-Sun attitude,
where acquisition starts (seed 001 Fig. 8). The capped term over K_d sets the
slew rate, k_p / k_d * limit.

Gains are K = k * I (the decoupled inertia, diagonal).
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.linalg import cross


class SunLawParams(NamedTuple):
    kp_per_s2: float
    kd_per_s: float
    error_limit: float       # cap of |s_d x s|
    sun_desired_B: np.ndarray  # (3,) unit, s_d


@njit(cache=True)
def sun_pointing_error_B(sun_B, sun_desired_B, limit):
    """The limited proportional error s_d x s (rad, small-angle sense)."""
    e = cross(sun_desired_B, sun_B)
    mag = np.sqrt(np.sum(e * e))
    beyond_90 = np.sum(sun_B * sun_desired_B) < 0.0
    if mag > limit or (beyond_90 and mag > 1e-12):
        return e * (limit / mag)
    if beyond_90:   # exactly anti-Sun: any axis perpendicular to s_d will do; take the one of least inertia, Y or Z
        a = np.array([0.0, 0.0, 1.0]) if abs(sun_desired_B[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e = cross(sun_desired_B, a)
        return e * (limit / np.sqrt(np.sum(e * e)))
    return e


@njit(cache=True)
def sunacq_torque_B(sun_B, sun_ok, rate_B, inertia_diag, p):
    """Body torque command, N m: eq. (6), rate-only when the CSS see no Sun."""
    t = np.empty(3)
    e = sun_pointing_error_B(sun_B, p.sun_desired_B, p.error_limit) if sun_ok else np.zeros(3)
    for i in range(3):
        t[i] = inertia_diag[i] * (p.kp_per_s2 * e[i] - p.kd_per_s * rate_B[i])
    return t
