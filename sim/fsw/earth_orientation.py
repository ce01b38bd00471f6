"""On-board Earth orientation: GCI (mean equator and equinox of J2000) to the
Earth-fixed frame, and the precession that the Sun and Moon series need.

* Earth rotation angle, IERS Conventions (2010), eq. (5.15):
      ERA(Tu) = 2 pi (0.7790572732640 + 1.00273781191135448 Tu),
  Tu = JD(UT1) - 2451545.0, evaluated as 2 pi (frac(Tu) + 0.7790572732640
  + 0.00273781191135448 Tu) so that the whole turns do not eat the digits
  (ERFA eraEra00 does the same).
* Earth-fixed from GCI: r_E = R3(ERA) dcm_CN r_N. ``dcm_CN`` (GCI -> the
  celestial intermediate frame: the Earth's pole, and the origin from which
  ERA is counted) is a parameter frozen at an uploaded epoch, as on the
  truth side. The ground computes it (e.g. IAU 2006/2000A, ERFA c2i06a);
  ``intermediate_from_precession`` builds it on board from precession alone,
      dcm_CN ~ R3(GMST - ERA) P(T),
  because R3(GMST) P is the equinox-based Earth-fixed transformation without
  nutation (IERS 2010 sec. 5.5; GMST - ERA from eq. 5.32). Leaving out
  nutation tilts the pole by up to |(17.2" sin eps, 9.2")| = 11.5 arcsec
  (measured against c2i06a over 2010-2030: 9.9 arcsec, 0.29 km at the
  ground station; tests/test_fsw_ephemeris_orbit.py).
* Precession, IAU 1976 (Lieske et al. 1977, A&A 58, 1; as in Meeus,
  "Astronomical Algorithms", 2nd ed., 1998, eq. 21.3 with the starting epoch
  J2000.0): P = R3(-z_A) R2(theta_A) R3(-zeta_A) maps mean-of-J2000
  components to mean-of-date components.
* Mean obliquity of the ecliptic, IAU 1976 (Lieske et al. 1977; Meeus eq. 22.2).

R1, R2, R3 are frame (coordinate) rotations: R3(a) = [[c, s, 0], [-s, c, 0], [0, 0, 1]].
T is TT Julian centuries since J2000.0; angles in rad.
"""
import math

import numpy as np
from numba import njit

from sim.constants import ARCSEC_RAD

TWO_PI = 2.0 * math.pi
# IERS 2010 eq. 5.15
ERA_AT_J2000_TURNS = 0.7790572732640
ERA_RATE_TURNS_PER_UT1_DAY = 1.00273781191135448
ERA_RATE_RAD_S = TWO_PI * ERA_RATE_TURNS_PER_UT1_DAY / 86400.0


@njit(cache=True)
def earth_rotation_angle_rad(ut1_days_j2000):
    """ERA in [0, 2 pi), IERS 2010 eq. 5.15."""
    tu = ut1_days_j2000
    turns = (tu - math.floor(tu)) + ERA_AT_J2000_TURNS + (ERA_RATE_TURNS_PER_UT1_DAY - 1.0) * tu
    return TWO_PI * (turns - math.floor(turns))


@njit(cache=True)
def mat3_mul(a, b):
    """a @ b for 3 x 3 matrices, without a BLAS call (see sim/linalg.py)."""
    out = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i, 0] * b[0, j] + a[i, 1] * b[1, j] + a[i, 2] * b[2, j]
    return out


@njit(cache=True)
def rot1(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]])


@njit(cache=True)
def rot2(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])


@njit(cache=True)
def rot3(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


@njit(cache=True)
def precession_iau1976(t_tt_centuries):
    """P: mean equator and equinox of J2000 -> of date (Lieske et al. 1977)."""
    t = t_tt_centuries
    zeta = (2306.2181 * t + 0.30188 * t * t + 0.017998 * t * t * t) * ARCSEC_RAD
    z = (2306.2181 * t + 1.09468 * t * t + 0.018203 * t * t * t) * ARCSEC_RAD
    theta = (2004.3109 * t - 0.42665 * t * t - 0.041833 * t * t * t) * ARCSEC_RAD
    return mat3_mul(rot3(-z), mat3_mul(rot2(theta), rot3(-zeta)))


@njit(cache=True)
def mean_obliquity_iau1976_rad(t_tt_centuries):
    """Mean obliquity of the ecliptic of date (Meeus eq. 22.2)."""
    t = t_tt_centuries
    return (84381.448 - 46.8150 * t - 0.00059 * t * t + 0.001813 * t * t * t) * ARCSEC_RAD


@njit(cache=True)
def gmst_minus_era_rad(t_tt_centuries):
    """GMST - ERA: the accumulated precession in right ascension, IERS 2010 eq. 5.32."""
    t = t_tt_centuries
    return (0.014506 + t * (4612.156534 + t * (1.3915817 + t * (-0.00000044 + t * (-0.000029956
            + t * -0.0000000368))))) * ARCSEC_RAD


@njit(cache=True)
def intermediate_from_precession(t_tt_centuries):
    """dcm_CN (GCI -> celestial intermediate) from precession only, nutation
    neglected: R3(GMST - ERA) P(T)."""
    return mat3_mul(rot3(gmst_minus_era_rad(t_tt_centuries)), precession_iau1976(t_tt_centuries))


@njit(cache=True)
def earth_fixed_from_gci(dcm_CN, era_rad):
    """dcm_EN: r_E = dcm_EN r_N (E: Earth-fixed, polar motion neglected)."""
    return mat3_mul(rot3(era_rad), dcm_CN)


@njit(cache=True)
def ecliptic_of_date_to_gci(lam, beta, r, t_centuries):
    """Position from longitude, latitude (rad) and distance (m) on the mean
    ecliptic and equinox of date, to GCI (mean equator and equinox of J2000):
    rotate by the mean obliquity of date, then undo the IAU 1976 precession.
    Shared by the on-board Sun and Moon."""
    x = r * math.cos(beta) * math.cos(lam)
    y = r * math.cos(beta) * math.sin(lam)
    z = r * math.sin(beta)
    eps = mean_obliquity_iau1976_rad(t_centuries)
    ce, se = math.cos(eps), math.sin(eps)
    yq, zq = ce * y - se * z, se * y + ce * z      # mean equator of date
    p = precession_iau1976(t_centuries)            # J2000 -> date; transpose back
    out = np.empty(3)
    for i in range(3):
        out[i] = p[0, i] * x + p[1, i] * yq + p[2, i] * zq
    return out
