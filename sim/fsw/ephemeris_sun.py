"""On-board solar ephemeris: the geocentric Sun in GCI (mean equator and
equinox of J2000), from a truncated VSOP87 series, and the apparent (aberrated)
Sun direction.

Seed 001 "On-Board Ephemeris" takes the Sun from Bretagnon's tables
(ref. [6]) with "better than 2 arcseconds during the ten-year SDO mission";
here the same theory's later form, VSOP87 (Bretagnon & Francou 1988, A&A
202, 309), truncated as in Meeus, "Astronomical Algorithms", 2nd ed., 1998:

1. Heliocentric Earth, VSOP87D (ecliptic and equinox of date): Meeus ch. 32,
   eq. 32.1-32.2 and Appendix III "Earth" (the same truncation is Table A4.2
   of Reda & Andreas 2004, NREL/TP-560-34302):
       L = (L0 + L1 tau + ... + L5 tau^5) / 1e8 rad, Li = sum A cos(B + C tau),
   likewise B (B0, B1) and R (R0..R4, au); tau = Julian millennia (TT) since J2000.
2. Geocentric Sun: longitude L + 180 deg, latitude -B (Meeus ch. 25, "higher
   accuracy").
3. VSOP dynamical ecliptic -> FK5 (Meeus eq. 32.3): lambda' = lambda - 1.397 deg T
   - 0.00031 deg T^2; d lambda = -0.09033", d beta = +0.03916" (cos lambda' - sin lambda').
4. Ecliptic of date -> mean equator of date by the mean obliquity (IAU 1976,
   Meeus eq. 22.2), then to J2000 by the transpose of the IAU 1976 precession
   matrix (sim/fsw/earth_orientation.py). Nutation does not enter: GCI is a
   mean frame. FK5 J2000 and the truth's ICRS axes differ by the 23 mas frame
   bias, which is left out.

The position is geometric (no light time, like the truth). Measured against
ERFA epv00 (the truth, sim/truth/ephemeris.py) every 0.37 day over 2010-2030
(tests/test_fsw_ephemeris_sun_moon.py): direction 0.46 arcsec max, 0.18
arcsec RMS (seed 001 asks < 2 arcsec); distance within 360 km.

Apparent direction: first-order stellar aberration by the observer's
barycentric velocity v, u' = (u + beta - (u . beta) u) / |...|, beta = v / c
(Explanatory Supplement to the Astronomical Almanac, 3rd ed., Urban &
Seidelmann 2013, expr. 7.40 to first order; ERFA eraAb evaluates the full
expression, to which the test compares: the second-order terms are ~1e-8 rad).
"""
import math

import numpy as np
from numba import njit

from sim.constants import ARCSEC_RAD, AU_M, C_LIGHT_M_S
from sim.fsw.earth_orientation import ecliptic_of_date_to_gci
from sim.fsw.onboard_time import DAYS_PER_JULIAN_CENTURY, tt_days_j2000

# Meeus Appendix III, Earth: rows (A, B rad, C rad per Julian millennium), A in 1e-8 rad (L, B) or 1e-8 au (R).
_L0 = ((175347046.0, 0.0, 0.0), (3341656.0, 4.6692568, 6283.07585), (34894.0, 4.6261, 12566.1517),
       (3497.0, 2.7441, 5753.3849), (3418.0, 2.8289, 3.5231), (3136.0, 3.6277, 77713.7715),
       (2676.0, 4.4181, 7860.4194), (2343.0, 6.1352, 3930.2097), (1324.0, 0.7425, 11506.7698),
       (1273.0, 2.0371, 529.691), (1199.0, 1.1096, 1577.3435), (990.0, 5.233, 5884.927),
       (902.0, 2.045, 26.298), (857.0, 3.508, 398.149), (780.0, 1.179, 5223.694),
       (753.0, 2.533, 5507.553), (505.0, 4.583, 18849.228), (492.0, 4.205, 775.523),
       (357.0, 2.92, 0.067), (317.0, 5.849, 11790.629), (284.0, 1.899, 796.298),
       (271.0, 0.315, 10977.079), (243.0, 0.345, 5486.778), (206.0, 4.806, 2544.314),
       (205.0, 1.869, 5573.143), (202.0, 2.458, 6069.777), (156.0, 0.833, 213.299),
       (132.0, 3.411, 2942.463), (126.0, 1.083, 20.775), (115.0, 0.645, 0.98),
       (103.0, 0.636, 4694.003), (102.0, 0.976, 15720.839), (102.0, 4.267, 7.114),
       (99.0, 6.21, 2146.17), (98.0, 0.68, 155.42), (86.0, 5.98, 161000.69),
       (85.0, 1.3, 6275.96), (85.0, 3.67, 71430.7), (80.0, 1.81, 17260.15),
       (79.0, 3.04, 12036.46), (75.0, 1.76, 5088.63), (74.0, 3.5, 3154.69),
       (74.0, 4.68, 801.82), (70.0, 0.83, 9437.76), (62.0, 3.98, 8827.39),
       (61.0, 1.82, 7084.9), (57.0, 2.78, 6286.6), (56.0, 4.39, 14143.5),
       (56.0, 3.47, 6279.55), (52.0, 0.19, 12139.55), (52.0, 1.33, 1748.02),
       (51.0, 0.28, 5856.48), (49.0, 0.49, 1194.45), (41.0, 5.37, 8429.24),
       (41.0, 2.4, 19651.05), (39.0, 6.17, 10447.39), (37.0, 6.04, 10213.29),
       (37.0, 2.57, 1059.38), (36.0, 1.71, 2352.87), (36.0, 1.78, 6812.77),
       (33.0, 0.59, 17789.85), (30.0, 0.44, 83996.85), (30.0, 2.74, 1349.87),
       (25.0, 3.16, 4690.48))
_L1 = ((628331966747.0, 0.0, 0.0), (206059.0, 2.678235, 6283.07585), (4303.0, 2.6351, 12566.1517),
       (425.0, 1.59, 3.523), (119.0, 5.796, 26.298), (109.0, 2.966, 1577.344),
       (93.0, 2.59, 18849.23), (72.0, 1.14, 529.69), (68.0, 1.87, 398.15),
       (67.0, 4.41, 5507.55), (59.0, 2.89, 5223.69), (56.0, 2.17, 155.42),
       (45.0, 0.4, 796.3), (36.0, 0.47, 775.52), (29.0, 2.65, 7.11),
       (21.0, 5.34, 0.98), (19.0, 1.85, 5486.78), (19.0, 4.97, 213.3),
       (17.0, 2.99, 6275.96), (16.0, 0.03, 2544.31), (16.0, 1.43, 2146.17),
       (15.0, 1.21, 10977.08), (12.0, 2.83, 1748.02), (12.0, 3.26, 5088.63),
       (12.0, 5.27, 1194.45), (12.0, 2.08, 4694.0), (11.0, 0.77, 553.57),
       (10.0, 1.3, 6286.6), (10.0, 4.24, 1349.87), (9.0, 2.7, 242.73),
       (9.0, 5.64, 951.72), (8.0, 5.3, 2352.87), (6.0, 2.65, 9437.76),
       (6.0, 4.67, 4690.48))
_L2 = ((52919.0, 0.0, 0.0), (8720.0, 1.0721, 6283.0758), (309.0, 0.867, 12566.152),
       (27.0, 0.05, 3.52), (16.0, 5.19, 26.3), (16.0, 3.68, 155.42), (10.0, 0.76, 18849.23),
       (9.0, 2.06, 77713.77), (7.0, 0.83, 775.52), (5.0, 4.66, 1577.34), (4.0, 1.03, 7.11),
       (4.0, 3.44, 5573.14), (3.0, 5.14, 796.3), (3.0, 6.05, 5507.55), (3.0, 1.19, 242.73),
       (3.0, 6.12, 529.69), (3.0, 0.31, 398.15), (3.0, 2.28, 553.57), (2.0, 4.38, 5223.69),
       (2.0, 3.75, 0.98))
_L3 = ((289.0, 5.844, 6283.076), (35.0, 0.0, 0.0), (17.0, 5.49, 12566.15), (3.0, 5.2, 155.42),
       (1.0, 4.72, 3.52), (1.0, 5.3, 18849.23), (1.0, 5.97, 242.73))
_L4 = ((114.0, 3.142, 0.0), (8.0, 4.13, 6283.08), (1.0, 3.84, 12566.15))
_L5 = ((1.0, 3.14, 0.0),)
_B0 = ((280.0, 3.199, 84334.662), (102.0, 5.422, 5507.553), (80.0, 3.88, 5223.69),
       (44.0, 3.7, 2352.87), (32.0, 4.0, 1577.34))
_B1 = ((9.0, 3.9, 5507.55), (6.0, 1.73, 5223.69))
_R0 = ((100013989.0, 0.0, 0.0), (1670700.0, 3.0984635, 6283.07585), (13956.0, 3.05525, 12566.1517),
       (3084.0, 5.1985, 77713.7715), (1628.0, 1.1739, 5753.3849), (1576.0, 2.8469, 7860.4194),
       (925.0, 5.453, 11506.77), (542.0, 4.564, 3930.21), (472.0, 3.661, 5884.927),
       (346.0, 0.964, 5507.553), (329.0, 5.9, 5223.694), (307.0, 0.299, 5573.143),
       (243.0, 4.273, 11790.629), (212.0, 5.847, 1577.344), (186.0, 5.022, 10977.079),
       (175.0, 3.012, 18849.228), (110.0, 5.055, 5486.778), (98.0, 0.89, 6069.78),
       (86.0, 5.69, 15720.84), (86.0, 1.27, 161000.69), (65.0, 0.27, 17260.15),
       (63.0, 0.92, 529.69), (57.0, 2.01, 83996.85), (56.0, 5.24, 71430.7),
       (49.0, 3.25, 2544.31), (47.0, 2.58, 775.52), (45.0, 5.54, 9437.76),
       (43.0, 6.01, 6275.96), (39.0, 5.36, 4694.0), (38.0, 2.39, 8827.39),
       (37.0, 0.83, 19651.05), (37.0, 4.9, 12139.55), (36.0, 1.67, 12036.46),
       (35.0, 1.84, 2942.46), (33.0, 0.24, 7084.9), (32.0, 0.18, 5088.63),
       (32.0, 1.78, 398.15), (28.0, 1.21, 6286.6), (28.0, 1.9, 6279.55),
       (26.0, 4.59, 10447.39))
_R1 = ((103019.0, 1.10749, 6283.07585), (1721.0, 1.0644, 12566.1517), (702.0, 3.142, 0.0),
       (32.0, 1.02, 18849.23), (31.0, 2.84, 5507.55), (25.0, 1.32, 5223.69), (18.0, 1.42, 1577.34),
       (10.0, 5.91, 10977.08), (9.0, 1.42, 6275.96), (9.0, 0.27, 5486.78))
_R2 = ((4359.0, 5.7846, 6283.0758), (124.0, 5.579, 12566.152), (12.0, 3.14, 0.0),
       (9.0, 3.63, 77713.77), (6.0, 1.87, 5573.14), (3.0, 5.47, 18849.23))
_R3 = ((145.0, 4.273, 6283.076), (7.0, 3.92, 12566.15))
_R4 = ((4.0, 2.56, 6283.08),)


def _stack(series):
    """One (n, 4) array: columns power of tau, A, B, C (numba freezes module arrays as constants)."""
    return np.array([(p, a, b, c) for p, s in enumerate(series) for a, b, c in s])


VSOP_L = _stack((_L0, _L1, _L2, _L3, _L4, _L5))
VSOP_B = _stack((_B0, _B1))
VSOP_R = _stack((_R0, _R1, _R2, _R3, _R4))
TERMS = VSOP_L.shape[0] + VSOP_B.shape[0] + VSOP_R.shape[0]   # 195 (Meeus: 129 + 7 + 59)


@njit(cache=True)
def _series(table, tau):
    """sum_p tau^p sum_i A_i cos(B_i + C_i tau) * 1e-8 (Meeus eq. 32.2), by Horner."""
    acc = np.zeros(6)
    for k in range(table.shape[0]):
        acc[int(table[k, 0])] += table[k, 1] * math.cos(table[k, 2] + table[k, 3] * tau)
    out = 0.0
    for i in range(5, -1, -1):
        out = out * tau + acc[i]
    return out * 1e-8


@njit(cache=True)
def earth_heliocentric_lbr(tau):
    """VSOP87D heliocentric (L rad, B rad, R au) of the Earth, ecliptic and
    equinox of date; tau in Julian millennia (TT) since J2000.0."""
    return _series(VSOP_L, tau), _series(VSOP_B, tau), _series(VSOP_R, tau)


@njit(cache=True)
def sun_position_tt_N(t_tt_days_j2000):
    """Geocentric Sun, GCI (mean equator and equinox of J2000), m; TT days since J2000.0."""
    t = t_tt_days_j2000 / DAYS_PER_JULIAN_CENTURY
    ell, b, r_au = earth_heliocentric_lbr(t / 10.0)
    lam = ell + math.pi                    # geocentric, VSOP dynamical frame of date
    beta = -b
    lam_p = lam - math.radians(1.397 * t + 0.00031 * t * t)       # Meeus eq. 32.3
    lam = lam - 0.09033 * ARCSEC_RAD
    beta = beta + 0.03916 * ARCSEC_RAD * (math.cos(lam_p) - math.sin(lam_p))
    r = r_au * AU_M
    return ecliptic_of_date_to_gci(lam, beta, r, t)


@njit(cache=True)
def sun_position_N(clock, t_s):
    """Geocentric Sun, GCI, m, at sim time t_s (UTC seconds since the clock's epoch)."""
    return sun_position_tt_N(tt_days_j2000(clock, t_s))


@njit(cache=True)
def aberrate_N(u_N, v_obs_N_m_s):
    """Apparent direction of a unit vector u_N seen by an observer moving at
    v_obs_N_m_s relative to the solar-system barycentre (first order in v/c)."""
    bx, by, bz = v_obs_N_m_s[0] / C_LIGHT_M_S, v_obs_N_m_s[1] / C_LIGHT_M_S, v_obs_N_m_s[2] / C_LIGHT_M_S
    d = u_N[0] * bx + u_N[1] * by + u_N[2] * bz
    px, py, pz = u_N[0] + bx - d * u_N[0], u_N[1] + by - d * u_N[1], u_N[2] + bz - d * u_N[2]
    n = math.sqrt(px * px + py * py + pz * pz)
    return np.array([px / n, py / n, pz / n])
