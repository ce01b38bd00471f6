"""SNR (solar north reference) frame and the attitude target quaternion.

Seed 001 "SNR Target": "The SNR frame defines its X axis as the apparent Sun
unit vector (Sun vector corrected for velocity aberration). The SNR Y axis is
defined as the normalized cross product of the solar north pole, which is
approximated by an inertially constant unit vector determined by the
Carrington elements, and the apparent sun vector. The SNR Z axis then
completes the right-handed triad."
    X = apparent unit vector from the spacecraft to the Sun
    Y = (p x X) / |p x X|
    Z = X x Y   (the solar pole projected normal to X)

* Apparent Sun: geometric direction r_sun - r_sc (GCI), aberrated to first
  order by the spacecraft's barycentric velocity (sim/fsw/ephemeris_sun.py,
  ``aberrate_N``).
* Solar north pole p: right ascension 286.13 deg, declination 63.87 deg (ICRF),
  Report of the IAU Working Group on Cartographic Coordinates and Rotational
  Elements: 2015 (Archinal et al. 2018, Celest. Mech. Dyn. Astr. 130:22,
  Table 1), the IAU form of Carrington's elements. The 23 mas between ICRF
  and the FK5 GCI axes is neglected.
* q_SN: the attitude of S in N (sim/attitude.py convention), quat_to_dcm(q_SN)
  = dcm_NS = [X Y Z] as columns.

Target (seed 001 "Inertial mode"): the desired quaternion q_RN is by default
q_SN (the science target is the identity relative to SNR), or q_SN (x) dq for a
ground-commanded delta quaternion dq = q_RS, or a ground-commanded GCI
quaternion.
"""
import math

import numpy as np
from numba import njit

from sim.attitude import dcm_to_quat, quat_mul, quat_normalize
from sim.fsw.ephemeris_sun import aberrate_N

SOLAR_POLE_RA_DEG = 286.13
SOLAR_POLE_DEC_DEG = 63.87
TARGET_SNR, TARGET_SNR_DELTA, TARGET_GCI = 0, 1, 2


def solar_pole_N(ra_deg: float = SOLAR_POLE_RA_DEG, dec_deg: float = SOLAR_POLE_DEC_DEG) -> np.ndarray:
    """Unit vector of the solar north pole, GCI."""
    a, d = math.radians(ra_deg), math.radians(dec_deg)
    return np.array([math.cos(d) * math.cos(a), math.cos(d) * math.sin(a), math.sin(d)])


SOLAR_POLE_N = solar_pole_N()


@njit(cache=True)
def apparent_sun_unit_N(sun_N_m, r_sc_N_m, v_sc_bary_N_m_s):
    """Unit vector from the spacecraft to the apparent Sun, GCI."""
    u = sun_N_m - r_sc_N_m
    u = u / math.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
    return aberrate_N(u, v_sc_bary_N_m_s)


@njit(cache=True)
def snr_dcm_NS(sun_apparent_N, pole_N):
    """[X Y Z] as columns (S components -> N components)."""
    x = sun_apparent_N
    y = np.array([pole_N[1] * x[2] - pole_N[2] * x[1],
                  pole_N[2] * x[0] - pole_N[0] * x[2],
                  pole_N[0] * x[1] - pole_N[1] * x[0]])
    y = y / math.sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2])
    z = np.array([x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]])
    m = np.empty((3, 3))
    for i in range(3):
        m[i, 0], m[i, 1], m[i, 2] = x[i], y[i], z[i]
    return m


@njit(cache=True)
def snr_quat_from_sun(sun_apparent_N, pole_N):
    """q_SN, the SNR frame's attitude in GCI, from the apparent Sun unit vector."""
    return dcm_to_quat(snr_dcm_NS(sun_apparent_N, pole_N))


@njit(cache=True)
def snr_quat(sun_N_m, r_sc_N_m, v_sc_bary_N_m_s, pole_N):
    """q_SN from the geocentric Sun and spacecraft positions and the
    spacecraft's barycentric velocity."""
    return snr_quat_from_sun(apparent_sun_unit_N(sun_N_m, r_sc_N_m, v_sc_bary_N_m_s), pole_N)


@njit(cache=True)
def target_quat(kind, q_SN, dq_RS, q_RN_cmd):
    """q_RN: TARGET_SNR -> q_SN; TARGET_SNR_DELTA -> q_SN (x) dq_RS;
    TARGET_GCI -> the commanded q_RN_cmd. Scalar part made >= 0."""
    if kind == TARGET_SNR:
        q = q_SN.copy()
    elif kind == TARGET_SNR_DELTA:
        q = quat_mul(q_SN, dq_RS)
    elif kind == TARGET_GCI:
        q = q_RN_cmd.copy()
    else:
        raise ValueError("target_quat: kind must be TARGET_SNR, TARGET_SNR_DELTA or TARGET_GCI")
    q = quat_normalize(q)
    if q[0] < 0.0:
        q = -q
    return q
