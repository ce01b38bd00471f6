"""On-board orbit propagator, Earth orientation and ground station
(sim/fsw/orbit_propagator.py, earth_orientation.py, ground_station.py,
ephemeris_task.py) against the truth model (sim/truth) and ERFA.

Requirement: seed 001 "On-Board Ephemeris": "accuracy requirements of 2.9 km
in both radial and transverse directions after seven days of propagation".
"""
import math
from datetime import datetime

import erfa
import numpy as np
import pytest

from sim.fsw.earth_orientation import ERA_RATE_RAD_S, intermediate_from_precession
from sim.fsw.ephemeris_task import (MOON, SPACECRAFT, STATION, SUN, EphemerisTaskParams, ephemeris_task_run,
                                    init_task)
from sim.fsw.ground_station import (WHITE_SANDS_HEIGHT_M, WHITE_SANDS_LAT_DEG, WHITE_SANDS_LON_DEG,
                                    station_position_N, white_sands_E_m)
from sim.fsw.onboard_time import make_clock, tt_days_j2000
from sim.fsw.orbit_propagator import acceleration_N, make_orbit_params, propagate
from sim.truth.eclipse import lit_fraction
from sim.truth.ephemeris import build_table, moon_position_N, sun_position_N, tt_jd, utc_jd
from sim.truth.gravity import gravity_accel_N, make_gravity_params, srp_accel_cannonball_N
from sim.truth.orbit import rk4_orbit_step, sdo_orbit

EPOCH = datetime.fromisoformat("2026-03-20T12:00:00+00:00")   # sim.scenario.DEFAULT_EPOCH, equinox: daily eclipses
DAY_S = 86400.0
ARCSEC = math.pi / 180.0 / 3600.0
# Cannonball SRP for both sides: assumption, of the order of SDO's ~3000 kg and
# ~25 m^2 Sun-facing area (sim/spacecraft/sdo.yaml facets); Cr 1.3.
AREA_M2, MASS_KG, CR = 25.0, 3000.0, 1.3
TAI_MINUS_UTC_S = 37.0   # IERS Bulletin C: since 2017-01-01


def _clock():
    u1, u2 = utc_jd(EPOCH)
    return make_clock(u1, TAI_MINUS_UTC_S, 0.0, u2)


def _dcm_uploaded():
    """What the ground uploads: the truth's own frame (IAU 2006/2000A c2i06a at the epoch)."""
    return erfa.c2i06a(*tt_jd(EPOCH))


def _dcm_precession_only():
    return intermediate_from_precession(tt_days_j2000(_clock(), 0.0) / 36525.0)


def _rot_angle(a, b):
    return math.acos(min(1.0, (np.trace(a @ b.T) - 1.0) / 2.0))


def test_precession_only_frame_is_within_nutation_of_c2i06a():
    """The on-board frame without nutation vs IAU 2006/2000A (erfa.c2i06a):
    apart by the nutation of the pole, whose leading (18.6-year) term is
    17.2 arcsec in longitude and 9.2 arcsec in obliquity (IAU 1980), i.e.
    |(17.2 sin 23.44 deg, 9.2)| = 11.5 arcsec; the CIO origin of ERA does not
    take the equation of the equinoxes. Measured 2010-2030: 9.9 arcsec max."""
    worst = 0.0
    for year in range(2010, 2031, 2):
        tt1, tt2 = erfa.dtf2d("TT", year, 5, 1, 0, 0, 0.0)
        ours = intermediate_from_precession(((tt1 - 2451545.0) + tt2) / 36525.0)
        worst = max(worst, _rot_angle(ours, erfa.c2i06a(tt1, tt2)))
    assert 1.0 * ARCSEC < worst < 12.0 * ARCSEC


def test_acceleration_matches_truth_model():
    """Same uploaded frame, same Sun and Moon (the truth's), sunlit point: the
    on-board geopotential, third bodies and SRP equal the truth's
    (gravity_accel_N + srp_accel_cannonball_N) to 1e-12 m/s^2 (round-off;
    the total is 0.22 m/s^2 at geosynchronous radius)."""
    g = make_gravity_params(EPOCH)
    table = build_table(EPOCH, 0.0, DAY_S)
    p = make_orbit_params(_clock(), _dcm_uploaded(), AREA_M2, MASS_KG, CR)
    rng = np.random.default_rng(7)
    for t_s in (0.0, 20000.0, 80000.0):
        sun, moon = sun_position_N(table, t_s), moon_position_N(table, t_s)
        for radius in (7.0e6, 4.2164e7):
            r = rng.normal(size=3)
            r *= radius / np.linalg.norm(r)
            r = r if r @ sun > 0 else -r   # sunlit
            truth = gravity_accel_N(r, t_s, g, table) + srp_accel_cannonball_N(r, sun, 1.0, AREA_M2, MASS_KG, CR)
            ours = acceleration_N(r, t_s, sun, moon, p)
            assert np.linalg.norm(ours - truth) < 1e-12


@pytest.fixture(scope="module")
def seven_days():
    """Truth trajectory over seven days from SDO's orbit (60 s RK4 steps,
    truth SRP with the conical shadow, held over each step as in the truth
    integrator), and the initial state."""
    dt, n = 60.0, int(7 * DAY_S / 60.0)
    r0, v0 = sdo_orbit(EPOCH).to_rv()
    x0 = np.concatenate([r0, v0])
    g = make_gravity_params(EPOCH)
    table = build_table(EPOCH, 0.0, n * dt)
    x, work = x0.copy(), np.empty((5, 6))
    out = [x0.copy()]
    for k in range(n):
        sun = sun_position_N(table, k * dt)
        a_srp = srp_accel_cannonball_N(x[:3], sun, lit_fraction(x[:3], sun), AREA_M2, MASS_KG, CR)
        rk4_orbit_step(x, k * dt, dt, g, table, a_srp, work)
        out.append(x.copy())
    return x0, dt, n, np.array(out)


@pytest.mark.parametrize("frame", ["uploaded", "precession_only"])
def test_seven_day_propagation_within_2_9_km(seven_days, frame):
    """Seed 001: radial and transverse within 2.9 km after seven days.
    Measured (SDO orbit from 2026-03-20, 60 s steps): radial 3 m at the end
    (18 m at most), transverse 330 m (uploaded c2i06a frame) and 318 m
    (precession-only frame); the transverse drift comes from the Moon's
    0.3 deg ephemeris error."""
    x0, dt, n, truth = seven_days
    dcm = _dcm_uploaded() if frame == "uploaded" else _dcm_precession_only()
    fsw = propagate(x0, 0.0, dt, n, make_orbit_params(_clock(), dcm, AREA_M2, MASS_KG, CR))
    d = fsw[:, :3] - truth[:, :3]
    radial = truth[:, :3] / np.linalg.norm(truth[:, :3], axis=1, keepdims=True)
    normal = np.cross(truth[:, :3], truth[:, 3:])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    transverse = np.cross(normal, radial)
    err_r = np.abs(np.sum(d * radial, axis=1))
    err_t = np.abs(np.sum(d * transverse, axis=1))
    assert err_r.max() < 2.9e3 and err_t.max() < 2.9e3
    assert err_r.max() < 100.0 and err_t[-1] < 1.0e3   # the measured margin, so that a regression shows


def test_ground_station_matches_erfa_gd2gc_and_truth_rotation():
    """White Sands geodetic -> GCI against erfa.gd2gc (WGS84) turned by the
    truth's Earth rotation (ERA of UTC at the epoch plus its rate, c2i06a
    frame): < 1 mm with the uploaded frame (measured 0.06 mm, the time
    resolution); with the precession-only frame the nutation (< 12 arcsec)
    moves it < 0.4 km (6378 km * 12 arcsec = 0.37 km; measured 0.29 km)."""
    g = make_gravity_params(EPOCH)
    r_E = erfa.gd2gc(1, math.radians(WHITE_SANDS_LON_DEG), math.radians(WHITE_SANDS_LAT_DEG), WHITE_SANDS_HEIGHT_M)
    assert np.linalg.norm(white_sands_E_m() - r_E) < 1e-6
    clock = _clock()
    for t_s in (0.0, 12345.0, 3.5 * DAY_S):
        th = g.era0_rad + g.era_rate_rad_s * t_s
        c, s = math.cos(th), math.sin(th)
        r_C = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ r_E
        truth = g.dcm_CN.T @ r_C
        assert np.linalg.norm(station_position_N(white_sands_E_m(), clock, _dcm_uploaded(), t_s) - truth) < 1e-3
        assert np.linalg.norm(station_position_N(white_sands_E_m(), clock, _dcm_precession_only(), t_s)
                              - truth) < 0.4e3


def test_task_differenced_velocities():
    """Seed 001: velocities from differencing successive positions at the
    1 s sample time. The difference is the velocity at the mid-sample: against
    the RK4 state velocities (mean of the two samples, 1e-4 m/s: their
    difference is O(dt^2 |jerk|)), the analytical Earth rotation of the station
    (omega x r at mid-sample, 1 mm/s: time is kept in days, resolved to
    2e-12 day = 0.17 us, 0.07 mm of station motion per sample), and the truth's Sun and Moon
    velocities (epv00: 0.5 m/s, measured 0.35 m/s over two years; moon98:
    10 m/s, measured 5.9 m/s: the AA series' own error)."""
    clock = _clock()
    orbit = make_orbit_params(clock, _dcm_uploaded(), AREA_M2, MASS_KG, CR)
    p = EphemerisTaskParams(orbit, white_sands_E_m(), 1.0)
    r0, v0 = sdo_orbit(EPOCH).to_rv()
    s = init_task(p, np.concatenate([r0, v0]), 0.0)
    table = build_table(EPOCH, 0.0, 2 * DAY_S)
    pole_N = orbit.dcm_CN[2]
    for _ in range(3):
        ephemeris_task_run(p, s, 3599)
        v_prev = s.x_sc[3:].copy()
        ephemeris_task_run(p, s, 1)
        t = s.t_s[0]
        assert np.linalg.norm(s.vel_N_m_s[SPACECRAFT] - 0.5 * (v_prev + s.x_sc[3:])) < 1e-4
        r_mid = 0.5 * (s.pos_N_m[STATION] + s.prev_N_m[STATION])
        v_station = ERA_RATE_RAD_S * np.cross(pole_N, r_mid)
        assert np.linalg.norm(s.vel_N_m_s[STATION] - v_station) < 1e-3
        k, u = divmod((t - 0.5 - table.t0_s) / table.step_s, 1.0)
        k = int(k)
        v_sun = (1 - u) * table.sun_v_N_m_s[k] + u * table.sun_v_N_m_s[k + 1]
        v_moon = (1 - u) * table.moon_v_N_m_s[k] + u * table.moon_v_N_m_s[k + 1]
        assert np.linalg.norm(s.vel_N_m_s[SUN] - v_sun) < 0.5
        assert np.linalg.norm(s.vel_N_m_s[MOON] - v_moon) < 10.0
