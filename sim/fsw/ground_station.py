"""On-board ground-station ephemeris: geodetic (WGS84) -> Earth-fixed -> GCI.

Seed 001 "On-Board Ephemeris": "Determining the locations of the two
dedicated ground stations is performed by transformation from geodetic to
GCI, mean-of-J2000 coordinates." The station is SDO's dedicated ground
station at White Sands, New Mexico (seed 001, "The SDO Mission").

* Geodetic -> Earth-fixed on the WGS84 ellipsoid (a = 6378137 m,
  1/f = 298.257223563: NIMA TR8350.2, 3rd ed., Table 3.1), as in Vallado,
  "Fundamentals of Astrodynamics and Applications", 4th ed., 2013, sec. 3.2
  (site vector): N = a / sqrt(1 - e^2 sin^2 phi),
      r_E = [(N + h) cos phi cos lam, (N + h) cos phi sin lam, (N (1 - e^2) + h) sin phi].
* Earth-fixed -> GCI: r_N = dcm_CN^T R3(-ERA) r_E (sim/fsw/earth_orientation.py);
  polar motion (~0.3 arcsec, ~10 m) is neglected.
"""
import math

import numpy as np
from numba import njit

from sim.constants import WGS84_A_M, WGS84_INV_F
from sim.fsw.earth_orientation import earth_rotation_angle_rad
from sim.fsw.onboard_time import ut1_days_j2000

WGS84_E2 = (2.0 - 1.0 / WGS84_INV_F) / WGS84_INV_F     # e^2 = f (2 - f)

# Assumption: the public location of NASA's White Sands Complex (Las Cruces, NM),
# to about 0.01 deg; SDO's two dedicated antennas stand there.
WHITE_SANDS_LAT_DEG = 32.54
WHITE_SANDS_LON_DEG = -106.61
WHITE_SANDS_HEIGHT_M = 1450.0


@njit(cache=True)
def geodetic_to_earth_fixed(lat_rad, lon_rad, height_m):
    """WGS84 geodetic latitude, east longitude (rad) and height (m) -> Earth-fixed m."""
    sp, cp = math.sin(lat_rad), math.cos(lat_rad)
    n = WGS84_A_M / math.sqrt(1.0 - WGS84_E2 * sp * sp)
    return np.array([(n + height_m) * cp * math.cos(lon_rad),
                     (n + height_m) * cp * math.sin(lon_rad),
                     (n * (1.0 - WGS84_E2) + height_m) * sp])


@njit(cache=True)
def earth_fixed_to_gci(r_E_m, era_rad, dcm_CN):
    """r_N = dcm_CN^T R3(-ERA) r_E."""
    c, s = math.cos(era_rad), math.sin(era_rad)
    xc = c * r_E_m[0] - s * r_E_m[1]
    yc = s * r_E_m[0] + c * r_E_m[1]
    zc = r_E_m[2]
    out = np.empty(3)
    for i in range(3):
        out[i] = dcm_CN[0, i] * xc + dcm_CN[1, i] * yc + dcm_CN[2, i] * zc
    return out


@njit(cache=True)
def station_position_N(station_E_m, clock, dcm_CN, t_s):
    """Ground station in GCI, m, at sim time t_s (ERA from UT1 = UTC + DUT1)."""
    return earth_fixed_to_gci(station_E_m, earth_rotation_angle_rad(ut1_days_j2000(clock, t_s)), dcm_CN)


def white_sands_E_m() -> np.ndarray:
    """The White Sands station, Earth-fixed, m."""
    return geodetic_to_earth_fixed(math.radians(WHITE_SANDS_LAT_DEG), math.radians(WHITE_SANDS_LON_DEG),
                                   WHITE_SANDS_HEIGHT_M)
