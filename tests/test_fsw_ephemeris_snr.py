"""SNR frame and target quaternion (sim/fsw/snr.py) against the truth's
apparent Sun (sim/truth/eclipse.py sun_vector_apparent_N), ERFA and scipy.

Seed 001 "SNR Target": X = apparent Sun unit vector, Y = unit(pole x X),
Z completes the right-handed triad; "Inertial mode": q_c is the SNR
quaternion, optionally times a ground-commanded delta quaternion, or a
ground-commanded inertial quaternion.
"""
import math
from datetime import datetime

import erfa
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from sim.attitude import quat_to_dcm
from sim.fsw.ephemeris_task import (SPACECRAFT, SUN, EphemerisTaskParams, ephemeris_task_run, init_task,
                                    observer_bary_velocity_N)
from sim.fsw.ground_station import white_sands_E_m
from sim.fsw.onboard_time import make_clock
from sim.fsw.orbit_propagator import make_orbit_params
from sim.fsw.snr import (SOLAR_POLE_N, TARGET_GCI, TARGET_SNR, TARGET_SNR_DELTA, snr_dcm_NS, snr_quat,
                         target_quat)
from sim.truth.eclipse import sun_vector_apparent_N
from sim.truth.ephemeris import build_table, earth_velocity_bary_N, sun_position_N, tt_jd, utc_jd
from sim.truth.gravity import make_gravity_params
from sim.truth.orbit import propagate_orbit, sdo_orbit

ARCSEC = math.pi / 180.0 / 3600.0
EPOCHS = ["2010-06-01T00:00:00+00:00", "2018-01-01T06:00:00+00:00", "2026-03-20T12:00:00+00:00",
          "2030-12-01T18:00:00+00:00"]


def _angle(u, v):
    return math.atan2(np.linalg.norm(np.cross(u, v)), float(np.dot(u, v)))


def _truth_case(epoch_iso, t_s):
    """Truth Sun, spacecraft state (SDO orbit, truth gravity) and the Earth's
    barycentric velocity at t_s after the epoch."""
    epoch = datetime.fromisoformat(epoch_iso)
    table = build_table(epoch, 0.0, max(t_s, 1.0))
    r0, v0 = sdo_orbit(epoch).to_rv()
    x = propagate_orbit(np.concatenate([r0, v0]), 0.0, t_s / 60.0, 60, make_gravity_params(epoch), table,
                        np.zeros(3))[-1] if t_s > 0 else np.concatenate([r0, v0])
    return epoch, table, x, sun_position_N(table, t_s), earth_velocity_bary_N(table, t_s)


def test_solar_pole_is_iau_wgccre():
    """Archinal et al. 2018 (IAU WGCCRE 2015), Table 1: the Sun's pole at
    RA 286.13 deg, Dec 63.87 deg; erfa.s2c gives its unit vector."""
    assert np.linalg.norm(SOLAR_POLE_N - erfa.s2c(math.radians(286.13), math.radians(63.87))) < 1e-15


@pytest.mark.parametrize("epoch_iso", EPOCHS)
def test_snr_with_truth_inputs_matches_truth_apparent_sun(epoch_iso):
    """Fed the truth's Sun, spacecraft state and Earth barycentric velocity,
    the SNR X axis is the truth's apparent Sun (same first-order aberration):
    < 2 arcsec required, 1e-6 arcsec expected (round-off). Y is normal to the
    solar pole, Z leans to solar north, the triad is right-handed and
    orthonormal, and q_SN is scipy's Rotation.from_matrix of [X Y Z]."""
    _, _, x, sun, v_earth = _truth_case(epoch_iso, 3000.0)
    q = snr_quat(sun, x[:3], v_earth + x[3:], SOLAR_POLE_N)
    m = quat_to_dcm(q)
    expected_x = sun_vector_apparent_N(x[:3], x[3:], sun, v_earth)
    assert _angle(m[:, 0], expected_x) < 2.0 * ARCSEC
    assert _angle(m[:, 0], expected_x) < 1e-6 * ARCSEC
    assert abs(m[:, 1] @ SOLAR_POLE_N) < 1e-12
    assert m[:, 2] @ SOLAR_POLE_N > math.cos(math.radians(7.3))   # the pole is 7.25 deg from the ecliptic pole
    assert np.allclose(m.T @ m, np.eye(3), atol=1e-12)
    assert abs(np.linalg.det(m) - 1.0) < 1e-12
    assert np.allclose(np.cross(m[:, 0], m[:, 1]), m[:, 2], atol=1e-12)
    dcm = snr_dcm_NS(expected_x, SOLAR_POLE_N)
    q_scipy = Rotation.from_matrix(dcm).as_quat(scalar_first=True)
    assert min(np.linalg.norm(q - q_scipy), np.linalg.norm(q + q_scipy)) < 1e-9


def test_target_quaternions():
    """q_RN = q_SN (x) dq (scipy: r_SN * r_dq): a 2.5 deg pitch offset (seed 001:
    calibrations point "up to 2.5 degrees in pitch and yaw away from the
    center of the Sun") puts the target X axis 2.5 deg from the apparent Sun;
    the GCI target is the commanded quaternion; an unknown kind is refused."""
    _, _, x, sun, v_earth = _truth_case(EPOCHS[2], 0.0)
    q_SN = snr_quat(sun, x[:3], v_earth + x[3:], SOLAR_POLE_N)
    dq = Rotation.from_rotvec([0.0, math.radians(2.5), 0.0]).as_quat(scalar_first=True)
    none = np.array([1.0, 0.0, 0.0, 0.0])
    q_RN = target_quat(TARGET_SNR_DELTA, q_SN, dq, none)
    r = Rotation.from_quat(q_SN, scalar_first=True) * Rotation.from_quat(dq, scalar_first=True)
    assert (r.inv() * Rotation.from_quat(q_RN, scalar_first=True)).magnitude() < 1e-12
    x_R = quat_to_dcm(q_RN)[:, 0]
    assert abs(_angle(x_R, quat_to_dcm(q_SN)[:, 0]) - math.radians(2.5)) < 1e-12
    assert np.allclose(target_quat(TARGET_SNR, q_SN, dq, none), q_SN * np.sign(q_SN[0]), atol=1e-15)
    q_cmd = Rotation.from_euler("zyx", [40.0, -10.0, 5.0], degrees=True).as_quat(scalar_first=True)
    assert np.allclose(target_quat(TARGET_GCI, q_SN, dq, -q_cmd), q_cmd * np.sign(q_cmd[0]), atol=1e-15)
    with pytest.raises(ValueError, match="kind"):
        target_quat(7, q_SN, dq, q_cmd)


@pytest.mark.parametrize("epoch_iso", EPOCHS)
def test_snr_from_onboard_ephemeris_within_2_arcsec(epoch_iso):
    """End to end: the on-board ephemeris task (VSOP87 Sun, RK4 orbit from the
    truth's initial state, velocities differenced at 1 s) gives an SNR X axis
    within 2 arcsec (seed 001, the solar ephemeris' accuracy) of the truth's
    apparent Sun 60 s later. Measured: 0.13-0.20 arcsec at these epochs (the
    Sun series' error, 0.46 arcsec at worst over 2010-2030)."""
    epoch, _, x, sun, v_earth = _truth_case(epoch_iso, 60.0)
    u1, u2 = utc_jd(epoch)
    clock = make_clock(u1, float(erfa.dat(epoch.year, epoch.month, epoch.day, 0.0)), 0.0, u2)
    orbit = make_orbit_params(clock, erfa.c2i06a(*tt_jd(epoch)), 25.0, 3000.0, 1.3)
    p = EphemerisTaskParams(orbit, white_sands_E_m(), 1.0)
    r0, v0 = sdo_orbit(epoch).to_rv()
    s = init_task(p, np.concatenate([r0, v0]), 0.0)
    ephemeris_task_run(p, s, 60)
    q = snr_quat(s.pos_N_m[SUN], s.pos_N_m[SPACECRAFT], observer_bary_velocity_N(s), SOLAR_POLE_N)
    expected_x = sun_vector_apparent_N(x[:3], x[3:], sun, v_earth)
    assert _angle(quat_to_dcm(q)[:, 0], expected_x) < 2.0 * ARCSEC
