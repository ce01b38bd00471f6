"""On-board spacecraft ephemeris: fixed-step RK4 of the orbit under the
flight software's own acceleration model, GCI (mean equator and equinox of J2000), SI.

Seed 001 "On-Board Ephemeris": "numerical integration of the acceleration
model using a standard fourth-order Runge-Kutta routine ... 2.9 km in both
radial and transverse directions after seven days ... J2, J3, J4, C22, and
S22, Sun and Moon gravitational effects, and the solar radiation pressure".

* Geopotential (Montenbruck & Gill, "Satellite Orbits", 2000, sec. 3.2,
  U = mu/r [1 + sum (R/r)^n P_nm(sin phi)(C_nm cos m lam + S_nm sin m lam)],
  C_n0 = -J_n), differentiated in Cartesian form (Vallado, "Fundamentals of
  Astrodynamics and Applications", 4th ed., 2013, sec. 8.6.1 for J2..J4):
      J2: a = -3/2 J2 mu R^2 / r^5 [x (1 - 5 s^2), y (1 - 5 s^2), z (3 - 5 s^2)]
      J3: a = -5/2 J3 mu R^3 / r^7 [x (3 z - 7 z^3/r^2), y (...), 6 z^2 - 7 z^4/r^2 - 3/5 r^2]
      J4: a = 15/8 J4 mu R^4 / r^7 [x (1 - 14 s^2 + 21 s^4), y (...), z (5 - 70/3 s^2 + 21 s^4)]
  with s = z / r, in the Earth's intermediate axes; C22/S22 from the gradient
  of U22 = 3 mu R^2 (C22 (x^2 - y^2) + 2 S22 x y) / r^5 in Earth-fixed axes
  (P_22(sin phi) = 3 cos^2 phi). Earth-fixed = R3(ERA) dcm_CN GCI
  (sim/fsw/earth_orientation.py: ERA from UT1 ~ UTC, dcm_CN uploaded).
* Sun and Moon (sim/fsw/ephemeris_sun.py, ephemeris_moon.py) as third
  bodies: a = mu_b [(s - r)/|s - r|^3 - s/|s|^3] (M&G eq. 3.37).
* SRP, cannonball: a = nu P (1 au / |d|)^2 Cr A / m d/|d|, d = r - r_sun,
  P = 4.56e-6 N/m^2 (M&G eq. 3.69, 3.75), with the on-board area, mass and
  Cr; nu from a cylindrical shadow (M&G sec. 3.4.2): 0 behind the Earth
  within one Earth radius of the Sun line, else 1.
* RK4 (e.g. M&G sec. 4.1.1), the Sun and Moon evaluated at the stage times.

GM and the coefficients: WGS84 GM (NIMA TR8350.2, 3rd ed., Table 3.1) and
EGM2008 (Pavlis et al. 2012, JGR 117, B04406), tide-free, unnormalised with
N_nm = sqrt((2 - delta_0m)(2n + 1)(n - m)!/(n + m)!) (M&G sec. 3.2).
GM_sun and the Moon/Earth mass ratio: IERS Conventions (2010), Table 1.1.
Measured against the truth (sim/truth/orbit.py) after seven days on the SDO
orbit: tests/test_fsw_ephemeris_orbit.py.
"""
import math
from typing import NamedTuple

import numpy as np
from numba import njit

from sim import constants as K
from sim.constants import AU_M, P_SUN_1AU_N_M2
from sim.fsw.earth_orientation import earth_rotation_angle_rad
from sim.fsw.ephemeris_moon import moon_position_tt_N
from sim.fsw.ephemeris_sun import sun_position_tt_N
from sim.fsw.onboard_time import OnboardClock, tt_days_j2000, ut1_days_j2000

R_EARTH_SHADOW_M = K.WGS84_A_M


class OrbitModelParams(NamedTuple):
    clock: OnboardClock
    dcm_CN: np.ndarray        # (3, 3) uploaded GCI -> celestial intermediate
    mu_m3_s2: float
    r_eq_m: float
    j2: float
    j3: float
    j4: float
    c22: float
    s22: float
    mu_sun_m3_s2: float
    mu_moon_m3_s2: float
    srp_area_m2: float        # on-board cannonball area (0: no SRP)
    mass_kg: float
    cr: float


def make_orbit_params(clock: OnboardClock, dcm_CN, srp_area_m2: float, mass_kg: float, cr: float) -> OrbitModelParams:
    dcm = np.ascontiguousarray(dcm_CN, dtype=float)
    if dcm.shape != (3, 3) or not np.allclose(dcm @ dcm.T, np.eye(3), atol=1e-9):
        raise ValueError("dcm_CN must be a 3 x 3 rotation matrix (GCI -> celestial intermediate)")
    if not (srp_area_m2 >= 0.0 and mass_kg > 0.0 and 0.0 <= cr <= 2.0):
        raise ValueError(f"need srp_area_m2 >= 0, mass_kg > 0, 0 <= cr <= 2; got {srp_area_m2}, {mass_kg}, {cr}")
    return OrbitModelParams(clock, dcm, K.MU_EARTH_M3_S2, K.R_EQ_EGM2008_M, K.J2, K.J3, K.J4, K.C22, K.S22,
                            K.MU_SUN_M3_S2, K.MU_MOON_M3_S2, float(srp_area_m2), float(mass_kg), float(cr))


@njit(cache=True)
def geopotential_C(xc, yc, zc, era_rad, p):
    """Central body + J2..J4 + C22/S22, in and returned in intermediate (C) axes."""
    r2 = xc * xc + yc * yc + zc * zc
    r = math.sqrt(r2)
    s = zc / r
    s2 = s * s
    mu, re = p.mu_m3_s2, p.r_eq_m
    k0 = -mu / (r2 * r)
    k2 = -1.5 * p.j2 * mu * re * re / (r2 * r2 * r)
    k3 = -2.5 * p.j3 * mu * re ** 3 / (r2 * r2 * r2 * r)
    k4 = 1.875 * p.j4 * mu * re ** 4 / (r2 * r2 * r2 * r)
    h = k0 + k2 * (1.0 - 5.0 * s2) + k3 * (3.0 * zc - 7.0 * zc * s2) + k4 * (1.0 - 14.0 * s2 + 21.0 * s2 * s2)
    az = (k0 * zc + k2 * zc * (3.0 - 5.0 * s2) + k3 * (6.0 * zc * zc - 7.0 * zc * zc * s2 - 0.6 * r2)
          + k4 * zc * (5.0 - 70.0 / 3.0 * s2 + 21.0 * s2 * s2))
    ax, ay = h * xc, h * yc
    c, sn = math.cos(era_rad), math.sin(era_rad)
    xe, ye = c * xc + sn * yc, -sn * xc + c * yc            # C -> Earth-fixed
    k = 3.0 * mu * re * re / (r2 * r2 * r)
    w5 = 5.0 * (p.c22 * (xe * xe - ye * ye) + 2.0 * p.s22 * xe * ye) / r2
    bx = k * (2.0 * p.c22 * xe + 2.0 * p.s22 * ye - w5 * xe)
    by = k * (2.0 * p.s22 * xe - 2.0 * p.c22 * ye - w5 * ye)
    return ax + c * bx - sn * by, ay + sn * bx + c * by, az - k * w5 * zc


@njit(cache=True)
def third_body(rx, ry, rz, b, mu_b):
    dx, dy, dz = b[0] - rx, b[1] - ry, b[2] - rz
    d3 = (dx * dx + dy * dy + dz * dz) ** 1.5
    b3 = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]) ** 1.5
    return (mu_b * (dx / d3 - b[0] / b3), mu_b * (dy / d3 - b[1] / b3), mu_b * (dz / d3 - b[2] / b3))


@njit(cache=True)
def cylindrical_lit(rx, ry, rz, sun):
    """1.0 in sunlight, 0.0 inside the Earth's cylindrical shadow."""
    sn = math.sqrt(sun[0] * sun[0] + sun[1] * sun[1] + sun[2] * sun[2])
    along = (rx * sun[0] + ry * sun[1] + rz * sun[2]) / sn
    if along >= 0.0:
        return 1.0
    perp2 = rx * rx + ry * ry + rz * rz - along * along
    return 1.0 if perp2 > R_EARTH_SHADOW_M * R_EARTH_SHADOW_M else 0.0


@njit(cache=True)
def acceleration_N(r_N_m, t_s, sun_N_m, moon_N_m, p):
    """Total modelled acceleration, m/s^2, GCI, given the Sun and Moon at t_s."""
    m = p.dcm_CN
    x, y, z = r_N_m[0], r_N_m[1], r_N_m[2]
    xc = m[0, 0] * x + m[0, 1] * y + m[0, 2] * z
    yc = m[1, 0] * x + m[1, 1] * y + m[1, 2] * z
    zc = m[2, 0] * x + m[2, 1] * y + m[2, 2] * z
    era = earth_rotation_angle_rad(ut1_days_j2000(p.clock, t_s))
    gx, gy, gz = geopotential_C(xc, yc, zc, era, p)
    out = np.empty(3)
    for i in range(3):   # C -> N: dcm_CN transposed
        out[i] = m[0, i] * gx + m[1, i] * gy + m[2, i] * gz
    sx, sy, sz = third_body(x, y, z, sun_N_m, p.mu_sun_m3_s2)
    mx, my, mz = third_body(x, y, z, moon_N_m, p.mu_moon_m3_s2)
    out[0] += sx + mx
    out[1] += sy + my
    out[2] += sz + mz
    if p.srp_area_m2 > 0.0:
        nu = cylindrical_lit(x, y, z, sun_N_m)
        dx, dy, dz = x - sun_N_m[0], y - sun_N_m[1], z - sun_N_m[2]
        d = math.sqrt(dx * dx + dy * dy + dz * dz)
        k = nu * P_SUN_1AU_N_M2 * (AU_M / d) ** 2 * p.cr * p.srp_area_m2 / p.mass_kg / d
        out[0] += k * dx
        out[1] += k * dy
        out[2] += k * dz
    return out


@njit(cache=True)
def _axpy(x, a, y):
    """x + a y as an element loop (array expressions cost compile time)."""
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        out[i] = x[i] + a * y[i]
    return out


@njit(cache=True)
def _derivative(x6, t_s, sun, moon, p):
    a = acceleration_N(x6[0:3], t_s, sun, moon, p)
    return np.array([x6[3], x6[4], x6[5], a[0], a[1], a[2]])


@njit(cache=True)
def rk4_step_given(x6, t_s, dt_s, sun0, moon0, sun_mid, moon_mid, sun1, moon1, p):
    """[r_N_m, v_N_m_s] at t_s + dt_s from x6 at t_s, the Sun and Moon given
    at t_s, t_s + dt_s/2 and t_s + dt_s (the ephemeris task has them anyway)."""
    h2 = 0.5 * dt_s
    k1 = _derivative(x6, t_s, sun0, moon0, p)
    k2 = _derivative(_axpy(x6, h2, k1), t_s + h2, sun_mid, moon_mid, p)
    k3 = _derivative(_axpy(x6, h2, k2), t_s + h2, sun_mid, moon_mid, p)
    k4 = _derivative(_axpy(x6, dt_s, k3), t_s + dt_s, sun1, moon1, p)
    out = np.empty(6)
    for i in range(6):
        out[i] = x6[i] + (dt_s / 6.0) * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
    return out


@njit(cache=True)
def rk4_step(x6, t_s, dt_s, p):
    """[r_N_m, v_N_m_s] at t_s + dt_s from x6 at t_s (returns a new array)."""
    d0 = tt_days_j2000(p.clock, t_s)
    h_days = dt_s / 86400.0
    return rk4_step_given(x6, t_s, dt_s, sun_position_tt_N(d0), moon_position_tt_N(d0),
                          sun_position_tt_N(d0 + 0.5 * h_days), moon_position_tt_N(d0 + 0.5 * h_days),
                          sun_position_tt_N(d0 + h_days), moon_position_tt_N(d0 + h_days), p)


@njit(cache=True)
def propagate(x0_6, t0_s, dt_s, n_steps, p):
    """States at t0_s + k dt_s, k = 0..n_steps, as an (n_steps + 1, 6) array."""
    out = np.empty((n_steps + 1, 6))
    x = x0_6.copy()
    for k in range(n_steps + 1):
        if k > 0:
            x = rk4_step(x, t0_s + (k - 1) * dt_s, dt_s, p)
        for j in range(6):   # element loops: numba's array setitem costs seconds to compile
            out[k, j] = x[j]
    return out
