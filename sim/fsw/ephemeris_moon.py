"""On-board lunar ephemeris: the geocentric Moon in GCI (mean equator and
equinox of J2000) from the Astronomical Almanac's low-precision formulae.

Seed 001 "On-Board Ephemeris": "Low-precision formulae for geocentric
coordinates of the Moon" (The Astronomical Almanac, 1994, ref. [7]; p. D46 in
the editions of the 1990s), flown on HST with "accuracy better than 0.36 deg".
Coefficients as reproduced in Vallado, "Fundamentals of Astrodynamics and
Applications", 4th ed., 2013, Algorithm 31 (MOON); T in Julian centuries
(TT ~ TDB) since J2000.0, angles in degrees:

    lambda = 218.32 + 481267.8813 T + 6.29 sin(134.9 + 477198.85 T)
             - 1.27 sin(259.2 - 413335.38 T) + 0.66 sin(235.7 + 890534.23 T)
             + 0.21 sin(269.9 + 954397.70 T) - 0.19 sin(357.5 + 35999.05 T)
             - 0.11 sin(186.6 + 966404.05 T)
    beta   = 5.13 sin(93.3 + 483202.03 T) + 0.28 sin(228.2 + 960400.87 T)
             - 0.28 sin(318.3 + 6003.18 T) - 0.17 sin(217.6 - 407332.20 T)
    pi     = 0.9508 + 0.0518 cos(134.9 + 477198.85 T) + 0.0095 cos(259.2 - 413335.38 T)
             + 0.0078 cos(235.7 + 890534.23 T) + 0.0028 cos(269.9 + 954397.70 T)
    r      = a_e / sin(pi)

The AA quotes 0.3 deg in longitude, 0.2 deg in latitude and 0.003 deg in
parallax (~1200 km at the Moon's distance). lambda and beta are referred to
the mean ecliptic and equinox of date: they are turned to the mean equator
of date by the mean obliquity and precessed back to J2000 with the IAU 1976
matrix (sim/fsw/earth_orientation.py). Without that step the Moon would be
off by the precession since 2000, 0.36 deg by 2026, the whole error budget.
Measured against ERFA moon98 (the truth) every 1.75 h over 2010-2030
(tests/test_fsw_ephemeris_sun_moon.py): direction 0.369 deg max, 0.11 deg
RMS, 99.9th percentile 0.346 deg; the seed's 0.36 deg is exceeded in three
short spells (2010, 2026, 2028; 0.04 % of the samples); distance within 1250 km.
"""
import math

from numba import njit

from sim.fsw.earth_orientation import ecliptic_of_date_to_gci
from sim.fsw.onboard_time import DAYS_PER_JULIAN_CENTURY, tt_days_j2000

A_E_M = 6378140.0   # the Earth's equatorial radius of the AA's parallax (IAU 1976 system)


@njit(cache=True)
def _sind(x):
    return math.sin(math.radians(x))


@njit(cache=True)
def _cosd(x):
    return math.cos(math.radians(x))


@njit(cache=True)
def moon_ecliptic_of_date(t):
    """(lambda rad, beta rad, r m): mean ecliptic and equinox of date; t in Julian centuries."""
    m1 = 134.9 + 477198.85 * t
    m2 = 259.2 - 413335.38 * t
    m3 = 235.7 + 890534.23 * t
    m4 = 269.9 + 954397.70 * t
    lam = (218.32 + 481267.8813 * t + 6.29 * _sind(m1) - 1.27 * _sind(m2) + 0.66 * _sind(m3)
           + 0.21 * _sind(m4) - 0.19 * _sind(357.5 + 35999.05 * t) - 0.11 * _sind(186.6 + 966404.05 * t))
    beta = (5.13 * _sind(93.3 + 483202.03 * t) + 0.28 * _sind(228.2 + 960400.87 * t)
            - 0.28 * _sind(318.3 + 6003.18 * t) - 0.17 * _sind(217.6 - 407332.20 * t))
    par = 0.9508 + 0.0518 * _cosd(m1) + 0.0095 * _cosd(m2) + 0.0078 * _cosd(m3) + 0.0028 * _cosd(m4)
    return math.radians(lam % 360.0), math.radians(beta), A_E_M / _sind(par)


@njit(cache=True)
def moon_position_tt_N(t_tt_days_j2000):
    """Geocentric Moon, GCI (mean equator and equinox of J2000), m; TT days since J2000.0."""
    t = t_tt_days_j2000 / DAYS_PER_JULIAN_CENTURY
    lam, beta, r = moon_ecliptic_of_date(t)
    return ecliptic_of_date_to_gci(lam, beta, r, t)


@njit(cache=True)
def moon_position_N(clock, t_s):
    """Geocentric Moon, GCI, m, at sim time t_s (UTC seconds since the clock's epoch)."""
    return moon_position_tt_N(tt_days_j2000(clock, t_s))
