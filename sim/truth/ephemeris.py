"""Truth ephemeris: the Sun and the Moon seen from the Earth, for the truth model only.

Positions come from ERFA (pyerfa), never from the low-precision formulas the
flight software carries (seed 001 "On-Board Ephemeris"): the truth must be
better than the on-board model so that the on-board error can be measured.

* Sun: ``erfa.epv00`` (simplified VSOP2000, Bretagnon & Moisson): the Earth's
  heliocentric and barycentric position and velocity. The geocentric Sun is
  minus the heliocentric Earth. Versus DE405 over 1900-2100: 3.7 km RMS,
  11.2 km max in position, 1.4 mm/s RMS in velocity (ERFA eraEpv00, note 4).
* Moon: ``erfa.moon98`` (Meeus, "Astronomical Algorithms", 2nd ed., p. 337):
  geocentric, GCRS. Versus ELP/MPP02: 2.9 arcsec RMS in direction, 6.1 km RMS
  in position; velocity is the analytical derivative (ERFA eraMoon98, notes 3, 6).

Frame: GCRS axes (= ICRS axes, geocentric). The J2000 mean equator and
equinox (the flight software's GCI, seed 001) differs from these axes by the
frame bias, about 23 mas; the truth neglects it (0.11 urad: 4.7 m at the Moon).
Units: m and m/s throughout. Time: ``t_s`` is SI seconds since the scenario
epoch. ERFA wants TDB for epv00 and TT for moon98; we pass TT to both:
TDB - TT is periodic with amplitude < 1.7 ms (ERFA eraDtdb, < 2 ms), which
moves the geocentric Sun by < 51 m along its 30 km/s path (3e-10 rad in
direction) and the Moon by < 2 m.

ERFA cannot be called from a numba kernel, so ``build_table`` tabulates the
states on a regular grid in Python and the kernels interpolate with cubic
Hermite polynomials on the stored positions and velocities (de Boor, "A
Practical Guide to Splines", ch. IV; error <= h^4/384 max|x''''|: ~1e-5 m for
the Moon at h = 600 s, see tests/test_environment.py for the measured value).

The Earth rotation angle (IAU 2000, ``erfa.era00``) lives here too, because
it is the other piece of "where is the world at time t" that needs ERFA.
"""
import math
from datetime import UTC, datetime
from typing import NamedTuple

import erfa
import numpy as np
from numba import njit

AU_M = erfa.DAU          # IAU 2012 Resolution B2: 149 597 870 700 m
DAY_S = erfa.DAYSEC      # 86400 s
NODE_MARGIN = 2          # nodes kept beyond each end of the requested span
# IERS Conventions (2010), eq. (5.15): ERA = 2 pi (0.7790572732640 + 1.00273781191135448 Tu),
# Tu in UT1 days, so the Earth turns at 2 pi * 1.00273781191135448 rad per UT1 day.
ERA_RATE_RAD_S = 2.0 * math.pi * 1.00273781191135448 / DAY_S


class EphemerisTable(NamedTuple):
    """Sun and Moon states on a regular grid of sim time (GCRS axes, SI units).

    Node k is at ``t0_s + k * step_s`` seconds since the scenario epoch."""
    t0_s: float
    step_s: float
    sun_N_m: np.ndarray             # (n, 3) geocentric Sun
    sun_v_N_m_s: np.ndarray         # (n, 3)
    moon_N_m: np.ndarray            # (n, 3) geocentric Moon
    moon_v_N_m_s: np.ndarray        # (n, 3)
    earth_v_bary_N_m_s: np.ndarray  # (n, 3) Earth's velocity about the solar-system barycentre


def _utc(epoch_utc: datetime) -> datetime:
    if epoch_utc.tzinfo is None:
        raise ValueError("epoch_utc must be timezone-aware (UTC)")
    return epoch_utc.astimezone(UTC)


def utc_jd(epoch_utc: datetime) -> tuple[float, float]:
    """The epoch as ERFA's two-part quasi-Julian Date in UTC (leap-second aware)."""
    t = _utc(epoch_utc)
    sec = t.second + t.microsecond * 1e-6
    return erfa.dtf2d("UTC", t.year, t.month, t.day, t.hour, t.minute, sec)


def tt_jd(epoch_utc: datetime) -> tuple[float, float]:
    """The epoch as a two-part Julian Date in TT (UTC -> TAI -> TT)."""
    tai1, tai2 = erfa.utctai(*utc_jd(epoch_utc))
    return erfa.taitt(tai1, tai2)


def build_table(epoch_utc: datetime, start_s: float, end_s: float, step_s: float = 600.0) -> EphemerisTable:
    """Tabulate the Sun, the Moon and the Earth's barycentric velocity over
    [start_s, end_s] seconds after ``epoch_utc``, with NODE_MARGIN extra nodes
    at each end so that the whole requested span interpolates."""
    if not (end_s >= start_s and step_s > 0.0):
        raise ValueError(f"need end_s >= start_s and step_s > 0, got {start_s}, {end_s}, {step_s}")
    n_span = math.ceil((end_s - start_s) / step_s)
    t0_s = start_s - NODE_MARGIN * step_s
    t_s = t0_s + step_s * np.arange(n_span + 1 + 2 * NODE_MARGIN)
    tt1, tt2 = tt_jd(epoch_utc)
    days = tt2 + t_s / DAY_S            # keep the big part in tt1: full resolution
    pvh, pvb = erfa.epv00(tt1, days)    # au, au/day (TDB ~ TT, see module docstring)
    moon = erfa.moon98(tt1, days)
    to_m_s = AU_M / DAY_S
    c = np.ascontiguousarray
    return EphemerisTable(float(t0_s), float(step_s),
                          c(-pvh["p"] * AU_M), c(-pvh["v"] * to_m_s),
                          c(moon["p"] * AU_M), c(moon["v"] * to_m_s),
                          c(pvb["v"] * to_m_s))


def earth_rotation_angle(epoch_utc: datetime, t_s: float = 0.0) -> tuple[float, float]:
    """(ERA in rad, its rate in rad/s) at t_s seconds after the epoch.

    UT1 is taken equal to UTC: |UT1 - UTC| < 0.9 s by definition of UTC, so the
    angle is off by < 0.9 s * 7.29e-5 rad/s = 6.6e-5 rad (13.5 arcsec)."""
    ut1, ut2 = utc_jd(epoch_utc)
    return float(erfa.era00(ut1, ut2 + t_s / DAY_S)), ERA_RATE_RAD_S


@njit(cache=True)
def locate(table, t_s):
    """(node index k, fraction u in [0, 1]) of t_s in the table. Outside the
    table is a programming error (the caller built too short a table): raise."""
    x = (t_s - table.t0_s) / table.step_s
    n = table.sun_N_m.shape[0]
    if not (x >= 0.0 and x <= n - 1):   # also catches NaN
        raise ValueError("ephemeris: time outside the table (build a longer table)")
    k = min(int(x), n - 2)
    return k, x - k


@njit(cache=True)
def hermite3(p, v, k, u, h):
    """Cubic Hermite interpolation of rows k, k+1 of positions p and velocities v
    at fraction u of a step of h seconds. Returns three scalars (no allocation)."""
    u2 = u * u
    u3 = u2 * u
    h00 = 2.0 * u3 - 3.0 * u2 + 1.0
    h10 = (u3 - 2.0 * u2 + u) * h
    h01 = -2.0 * u3 + 3.0 * u2
    h11 = (u3 - u2) * h
    x = h00 * p[k, 0] + h10 * v[k, 0] + h01 * p[k + 1, 0] + h11 * v[k + 1, 0]
    y = h00 * p[k, 1] + h10 * v[k, 1] + h01 * p[k + 1, 1] + h11 * v[k + 1, 1]
    z = h00 * p[k, 2] + h10 * v[k, 2] + h01 * p[k + 1, 2] + h11 * v[k + 1, 2]
    return x, y, z


@njit(cache=True)
def linear3(v, k, u):
    """Linear interpolation of rows k, k+1. Used for the Earth's barycentric
    velocity, whose derivative is not stored: the error, h^2/8 |v''| with
    |v''| ~ (2 pi / year)^2 * 30 km/s, is ~5e-5 m/s at h = 600 s, i.e. 2e-13 rad
    of aberration."""
    return (v[k, 0] + u * (v[k + 1, 0] - v[k, 0]),
            v[k, 1] + u * (v[k + 1, 1] - v[k, 1]),
            v[k, 2] + u * (v[k + 1, 2] - v[k, 2]))


@njit(cache=True)
def sun_moon3(table, t_s):
    """Sun and Moon positions as six scalars, for kernels that must not allocate."""
    k, u = locate(table, t_s)
    sx, sy, sz = hermite3(table.sun_N_m, table.sun_v_N_m_s, k, u, table.step_s)
    mx, my, mz = hermite3(table.moon_N_m, table.moon_v_N_m_s, k, u, table.step_s)
    return sx, sy, sz, mx, my, mz


@njit(cache=True)
def sun_position_N(table, t_s):
    """Geocentric Sun, GCRS axes, m."""
    k, u = locate(table, t_s)
    x, y, z = hermite3(table.sun_N_m, table.sun_v_N_m_s, k, u, table.step_s)
    return np.array([x, y, z])


@njit(cache=True)
def moon_position_N(table, t_s):
    """Geocentric Moon, GCRS axes, m."""
    k, u = locate(table, t_s)
    x, y, z = hermite3(table.moon_N_m, table.moon_v_N_m_s, k, u, table.step_s)
    return np.array([x, y, z])


@njit(cache=True)
def earth_velocity_bary_N(table, t_s):
    """Earth's velocity relative to the solar-system barycentre, m/s (for aberration)."""
    k, u = locate(table, t_s)
    x, y, z = linear3(table.earth_v_bary_N_m_s, k, u)
    return np.array([x, y, z])
