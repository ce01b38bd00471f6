"""Truth acceleration model of a spacecraft about the Earth, GCI (GCRS axes), SI.

At least as complete as the flight software's on-board model (seed 001
"On-Board Ephemeris": J2, J3, J4, C22, S22, Sun and Moon, SRP):

* Geopotential U = mu/r [1 + sum_n (R/r)^n sum_m P_nm(sin phi)(C_nm cos m lam + S_nm sin m lam)],
  a = grad U (Montenbruck & Gill, "Satellite Orbits", 2000, sec. 3.2), with
  C_n0 = -J_n. Zonal terms J2, J3, J4 in closed form, the gradient of U's
  zonal part written in Cartesian coordinates (as tabulated in Vallado,
  "Fundamentals of Astrodynamics and Applications", 4th ed., ch. 8; checked
  against the gradient of U in tests/test_gravity_orbit.py); the degree-2 order-2 term
  from U_22 = 3 mu R^2 (C22 (x^2 - y^2) + 2 S22 x y) / r^5 in Earth-fixed axes
  (P_22(sin phi) = 3 cos^2 phi).
* Sun and Moon as third bodies, a = mu_b [(s - r)/|s - r|^3 - s/|s|^3]
  (M&G eq. 3.37) in Battin's form, which avoids subtracting two nearly equal
  terms: a = -mu_b/|d|^3 (r + F(q) s), d = r - s, q = r.(r - 2 s)/s.s,
  F(q) = q (3 + 3 q + q^2) / (1 + (1 + q)^1.5) (Battin, "An Introduction to the
  Mathematics and Methods of Astrodynamics", 1999, eq. 8.60-8.61, p. 389).
* Solar radiation pressure, cannonball (M&G eq. 3.75; Vallado eq. 8-44):
  a = nu P (1 AU/|d|)^2 C_r A/m d/|d|, d = r - r_sun, P = 4.56e-6 N/m^2 at
  1 AU (M&G eq. 3.69), nu the lit fraction (eclipse.py).

Earth-fixed frame: the celestial-to-intermediate matrix (IAU 2006/2000A, erfa
c2i06a) is frozen at the scenario epoch, then the Earth rotation angle turns
about the pole. Neglected: the drift of precession-nutation over the scenario
(precession ~0.05 arcsec/day, nutation's fortnightly and semi-annual terms
< 0.6 arcsec: < 3 arcsec of pole over a month, 2e-7 m/s^2 of J2 at LEO) and
polar motion (~0.3 arcsec). Without the matrix the zonal axis would be the
J2000 pole, 0.15 deg off the true pole by 2026 (IAU 2006 precession,
~20 arcsec/year in declination): 4e-5 m/s^2 at LEO.

Every kernel works on scalars and returns tuples, so that the orbit
derivative built on them allocates nothing.
"""
import math
from datetime import datetime
from typing import NamedTuple

import erfa
import numpy as np
from numba import njit

from sim.constants import (
    C22,
    J2,
    J3,
    J4,
    MU_EARTH_M3_S2,
    MU_MOON_M3_S2,
    MU_SUN_M3_S2,
    P_SUN_1AU_N_M2,
    R_EQ_EGM2008_M,
    S22,
)
from sim.truth.ephemeris import AU_M, earth_rotation_angle, sun_moon3, tt_jd


class GravityParams(NamedTuple):
    mu_m3_s2: float
    r_eq_m: float
    j2: float
    j3: float
    j4: float
    c22: float
    s22: float
    era0_rad: float         # Earth rotation angle at t_s = 0
    era_rate_rad_s: float
    dcm_CN: np.ndarray      # (3, 3) GCRS -> CIRS (celestial intermediate) at the epoch: v_C = dcm_CN v_N
    mu_sun_m3_s2: float
    mu_moon_m3_s2: float
    zonal_on: float         # 1.0 / 0.0: J2, J3, J4
    tesseral_on: float      # 1.0 / 0.0: C22, S22
    third_body_on: float    # 1.0 / 0.0: Sun and Moon


def make_gravity_params(epoch_utc: datetime, zonal: bool = True, tesseral: bool = True,
                        third_body: bool = True) -> GravityParams:
    """The truth gravity field for a scenario starting at ``epoch_utc``."""
    era0, rate = earth_rotation_angle(epoch_utc)
    dcm_CN = np.ascontiguousarray(erfa.c2i06a(*tt_jd(epoch_utc)))
    return GravityParams(MU_EARTH_M3_S2, R_EQ_EGM2008_M, J2, J3, J4, C22, S22, era0, rate, dcm_CN,
                         MU_SUN_M3_S2, MU_MOON_M3_S2, float(zonal), float(tesseral), float(third_body))


@njit(cache=True)
def zonal3(x, y, z, g):
    """J2 + J3 + J4 acceleration in pole-aligned axes (x, y, z in m)."""
    r = math.sqrt(x * x + y * y + z * z)
    ux, uy, s = x / r, y / r, z / r
    s2 = s * s
    q = g.r_eq_m / r
    k = g.mu_m3_s2 / (r * r)
    f2 = -1.5 * g.j2 * k * q * q
    f3 = -2.5 * g.j3 * k * q * q * q
    f4 = 1.875 * g.j4 * k * q * q * q * q
    h = f2 * (1.0 - 5.0 * s2) + f3 * s * (3.0 - 7.0 * s2) + f4 * (1.0 - 14.0 * s2 + 21.0 * s2 * s2)
    az = (f2 * s * (3.0 - 5.0 * s2) + f3 * (6.0 * s2 - 7.0 * s2 * s2 - 0.6)
          + f4 * s * (5.0 - 70.0 / 3.0 * s2 + 21.0 * s2 * s2))
    return h * ux, h * uy, az


@njit(cache=True)
def sectoral22_3(x, y, z, g):
    """C22/S22 acceleration in Earth-fixed axes: the gradient of
    U_22 = 3 mu R^2 W / r^5, W = C22 (x^2 - y^2) + 2 S22 x y."""
    r2 = x * x + y * y + z * z
    r = math.sqrt(r2)
    k = 3.0 * g.mu_m3_s2 * g.r_eq_m * g.r_eq_m / (r2 * r2 * r)
    w = g.c22 * (x * x - y * y) + 2.0 * g.s22 * x * y
    c = 5.0 * w / r2
    return (k * (2.0 * g.c22 * x + 2.0 * g.s22 * y - c * x),
            k * (2.0 * g.s22 * x - 2.0 * g.c22 * y - c * y),
            -k * c * z)


@njit(cache=True)
def third_body3(rx, ry, rz, sx, sy, sz, mu_b):
    """Differential (perturbing) acceleration of a body at s on a satellite at r,
    both geocentric (Battin eq. 8.60-8.61)."""
    dx, dy, dz = rx - sx, ry - sy, rz - sz
    ss = sx * sx + sy * sy + sz * sz
    q = (rx * (rx - 2.0 * sx) + ry * (ry - 2.0 * sy) + rz * (rz - 2.0 * sz)) / ss
    f = q * (3.0 + 3.0 * q + q * q) / (1.0 + (1.0 + q) ** 1.5)
    d = math.sqrt(dx * dx + dy * dy + dz * dz)
    k = -mu_b / (d * d * d)
    return k * (rx + f * sx), k * (ry + f * sy), k * (rz + f * sz)


@njit(cache=True)
def _harmonics3(x, y, z, t_s, g):
    """Zonal and sectoral terms, computed in the Earth's axes and returned in N."""
    m = g.dcm_CN
    xc = m[0, 0] * x + m[0, 1] * y + m[0, 2] * z
    yc = m[1, 0] * x + m[1, 1] * y + m[1, 2] * z
    zc = m[2, 0] * x + m[2, 1] * y + m[2, 2] * z
    ax, ay, az = zonal3(xc, yc, zc, g)
    ax, ay, az = g.zonal_on * ax, g.zonal_on * ay, g.zonal_on * az
    if g.tesseral_on != 0.0:
        th = g.era0_rad + g.era_rate_rad_s * t_s
        c, s = math.cos(th), math.sin(th)
        bx, by, bz = sectoral22_3(c * xc + s * yc, -s * xc + c * yc, zc, g)  # C -> Earth-fixed
        ax += c * bx - s * by                                                 # Earth-fixed -> C
        ay += s * bx + c * by
        az += bz
    return (m[0, 0] * ax + m[1, 0] * ay + m[2, 0] * az,   # C -> N: dcm_CN transposed
            m[0, 1] * ax + m[1, 1] * ay + m[2, 1] * az,
            m[0, 2] * ax + m[1, 2] * ay + m[2, 2] * az)


@njit(cache=True)
def gravity_accel3(x, y, z, t_s, g, ephem):
    """Total gravitational acceleration at (x, y, z) m, GCI, as three scalars."""
    r2 = x * x + y * y + z * z
    k = -g.mu_m3_s2 / (r2 * math.sqrt(r2))
    ax, ay, az = k * x, k * y, k * z
    if g.zonal_on != 0.0 or g.tesseral_on != 0.0:
        hx, hy, hz = _harmonics3(x, y, z, t_s, g)
        ax, ay, az = ax + hx, ay + hy, az + hz
    if g.third_body_on != 0.0:
        sx, sy, sz, mx, my, mz = sun_moon3(ephem, t_s)
        bx, by, bz = third_body3(x, y, z, sx, sy, sz, g.mu_sun_m3_s2)
        cx, cy, cz = third_body3(x, y, z, mx, my, mz, g.mu_moon_m3_s2)
        ax, ay, az = ax + bx + cx, ay + by + cy, az + bz + cz
    return ax, ay, az


@njit(cache=True)
def gravity_accel_N(r_N_m, t_s, g, ephem):
    """Point mass + J2 + J3 + J4 + C22/S22 + Sun + Moon, m/s^2, GCI."""
    ax, ay, az = gravity_accel3(r_N_m[0], r_N_m[1], r_N_m[2], t_s, g, ephem)
    return np.array([ax, ay, az])


@njit(cache=True)
def srp3(rx, ry, rz, sx, sy, sz, lit_fraction, area_m2, mass_kg, cr):
    """Cannonball SRP as three scalars: pushes away from the Sun."""
    dx, dy, dz = rx - sx, ry - sy, rz - sz
    d = math.sqrt(dx * dx + dy * dy + dz * dz)
    k = lit_fraction * P_SUN_1AU_N_M2 * (AU_M / d) ** 2 * cr * area_m2 / mass_kg / d
    return k * dx, k * dy, k * dz


@njit(cache=True)
def srp_accel_cannonball_N(r_N_m, sun_N_m, lit_fraction, area_m2, mass_kg, cr):
    """Solar radiation pressure on a sphere-like body, m/s^2, GCI."""
    ax, ay, az = srp3(r_N_m[0], r_N_m[1], r_N_m[2], sun_N_m[0], sun_N_m[1], sun_N_m[2],
                      lit_fraction, area_m2, mass_kg, cr)
    return np.array([ax, ay, az])
