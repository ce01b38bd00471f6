"""Calibration maneuvers (sim/calibration.py) checked against things outside
the code: scipy's Rotation for the delta quaternions and slew angles, the
seed papers' limits, and the geometry of a cross and a grid."""
import math

import numpy as np
import pytest
import yaml
from pydantic import ValidationError
from scipy.spatial.transform import Rotation

from sim.calibration import (
    CALIBRATION_ADAPTER,
    EveCruciform,
    OffpointGrid,
    ScheduledCalibration,
    delta_quat,
    duration_s,
    expand,
    slew_angle_arcsec,
)
from sim.commands import COMMAND_ADAPTER, SetTargetSnr

ARCSEC = math.pi / 180.0 / 3600.0   # rad per arcsec, written independently of the module


def _boresight_angles_rad(delta_q):
    """(pitch, yaw) of the target X axis in SNR, by scipy: yaw is the azimuth
    toward +Y, pitch the elevation toward -Z (right-handed about +Y)."""
    b = Rotation.from_quat(delta_q, scalar_first=True).apply([1.0, 0.0, 0.0])
    return math.atan2(-b[2], math.hypot(b[0], b[1])), math.atan2(b[1], b[0])


def _pointings_from_commands(cmds):
    """(pitch, yaw) in arcsec of each command, recovered through scipy."""
    return [tuple(a / ARCSEC for a in _boresight_angles_rad(c.delta_q)) for _, c in cmds]


# --- delta quaternion -------------------------------------------------------

@pytest.mark.parametrize("pitch_arcsec, yaw_arcsec", [
    (0, 0), (5, 0), (0, -5), (9000, 0), (0, 9000), (-9000, 9000), (9000, -9000), (1234.5, -678.9)])
def test_delta_quaternion_points_boresight_at_commanded_angles(pitch_arcsec, yaw_arcsec):
    q = delta_quat(pitch_arcsec, yaw_arcsec)
    pitch, yaw = _boresight_angles_rad(q)
    assert abs(pitch - pitch_arcsec * ARCSEC) < 1e-9
    assert abs(yaw - yaw_arcsec * ARCSEC) < 1e-9
    # the documented construction: yaw about +Z, then pitch about the new +Y (scipy intrinsic "ZY")
    ref = Rotation.from_euler("ZY", [yaw_arcsec * ARCSEC, pitch_arcsec * ARCSEC]).as_quat(scalar_first=True)
    assert min(np.abs(np.subtract(q, ref)).max(), np.abs(np.add(q, ref)).max()) < 1e-12
    # no roll about the boresight: the target Y axis stays in the SNR X-Y plane
    assert abs(Rotation.from_quat(q, scalar_first=True).apply([0.0, 1.0, 0.0])[2]) < 1e-12


def test_target_is_snr_times_delta_expressed_in_gci():
    # seed 001 "Inertial mode": desired quaternion = SNR quaternion times the delta quaternion.
    # q_RN = q_SN (x) q_RS (scipy r_SN * r_RS); the target boresight seen from S must be at the angles.
    r_SN = Rotation.from_rotvec([0.3, -1.1, 2.0])
    cmd = SetTargetSnr(delta_q=delta_quat(-4500.0, 7200.0))
    r_RN = r_SN * Rotation.from_quat(cmd.delta_q, scalar_first=True)
    b_S = r_SN.inv().apply(r_RN.apply([1.0, 0.0, 0.0]))
    assert abs(math.atan2(-b_S[2], math.hypot(b_S[0], b_S[1])) - (-4500.0 * ARCSEC)) < 1e-9
    assert abs(math.atan2(b_S[1], b_S[0]) - 7200.0 * ARCSEC) < 1e-9


def test_slew_angle_matches_scipy():
    for a, b in [((0, 0), (5, 0)), ((600, -600), (-600, 600)), ((9000, 0), (0, 0)), ((0, 9000), (9000, 0))]:
        qa, qb = delta_quat(*a), delta_quat(*b)
        ref = (Rotation.from_quat(qa, scalar_first=True).inv() * Rotation.from_quat(qb, scalar_first=True)).magnitude()
        assert abs(slew_angle_arcsec(qa, qb) - ref / ARCSEC) < 1e-6


# --- time tags --------------------------------------------------------------

@pytest.mark.parametrize("m", [EveCruciform(), OffpointGrid(), EveCruciform(dwell_s=0.0, allowance_s=120.0)])
def test_time_tags_start_at_t0_and_are_spaced_by_allowance_plus_dwell(m):
    t0 = 1000.0
    cmds = expand(m, t0)
    tags = np.array([t for t, _ in cmds])
    assert tags[0] == t0
    assert np.all(np.diff(tags) > 0)
    assert np.allclose(np.diff(tags), m.allowance_s + m.dwell_s, rtol=0, atol=1e-9)
    # ends with a return to Sun centre (identity delta), settled after one allowance
    assert cmds[-1][1].delta_q == (1.0, 0.0, 0.0, 0.0)
    assert duration_s(m) == pytest.approx(tags[-1] - t0 + m.allowance_s, abs=1e-9)
    # each command is a valid ground command for every door
    assert all(COMMAND_ADAPTER.validate_python(c.model_dump()) == c for _, c in cmds)


def test_expand_rejects_negative_start():
    with pytest.raises(ValueError, match="t0_s"):
        expand(EveCruciform(), -1.0)


# --- cruciform geometry -------------------------------------------------------

def test_cruciform_is_a_symmetric_cross_returning_to_centre():
    m = EveCruciform(step_arcsec=600.0, n_steps=4)
    pts = _pointings_from_commands(expand(m, 0.0))
    assert len(pts) == 4 * (4 + 1)
    centre = [i for i, (p, y) in enumerate(pts) if abs(p) < 1e-6 and abs(y) < 1e-6]
    assert centre == [4, 9, 14, 19]          # back through centre after each arm, and at the end
    arms = [pts[0:4], pts[5:9], pts[10:14], pts[15:19]]
    expected = [600.0 * k for k in range(1, 5)]
    # +pitch, -pitch (yaw zero), then +yaw, -yaw (pitch zero): points on the two axes
    for arm, axis, sign in zip(arms, (0, 0, 1, 1), (1, -1, 1, -1)):
        assert all(abs(pt[1 - axis]) < 1e-6 for pt in arm)
        assert np.allclose([pt[axis] for pt in arm], [sign * e for e in expected], atol=1e-6)
    # every slew, measured by scipy, is a step out along an arm or one arm length back
    rs = [Rotation.identity()] + [Rotation.from_quat(c.delta_q, scalar_first=True) for _, c in expand(m, 0.0)]
    slews = [(rs[i].inv() * rs[i + 1]).magnitude() / ARCSEC for i in range(len(rs) - 1)]
    assert np.allclose(sorted(set(np.round(slews, 6))), [600.0, 2400.0])


def test_cruciform_defaults_reach_the_papers_limit():
    m = EveCruciform()
    # seed 001 "Instrument calibrations ... point the SRB up to 2.5 degrees in pitch and yaw": 9000 arcsec
    assert m.n_steps * m.step_arcsec == pytest.approx(2.5 * 3600)
    # seed 000 "fast slew time requirements (2 - 5 minutes)"
    assert 120.0 <= m.allowance_s <= 300.0
    pts = _pointings_from_commands(expand(m, 0.0))
    assert max(max(abs(p), abs(y)) for p, y in pts) == pytest.approx(9000.0, abs=1e-6)


# --- grid geometry ------------------------------------------------------------

def test_grid_covers_a_centred_lattice_in_one_spacing_steps():
    m = OffpointGrid(spacing_arcsec=200.0, n_rows=3, n_cols=4)
    cmds = expand(m, 0.0)
    pts = _pointings_from_commands(cmds)
    grid = pts[:-1]
    want = {(round(p, 3), round(y, 3)) for p in (-200.0, 0.0, 200.0) for y in (-300.0, -100.0, 100.0, 300.0)}
    assert {(round(p, 3), round(y, 3)) for p, y in grid} == want and len(grid) == 12
    assert pts[-1] == pytest.approx((0.0, 0.0), abs=1e-9)
    rs = [Rotation.from_quat(c.delta_q, scalar_first=True) for _, c in cmds[:-1]]
    in_grid = [(rs[i].inv() * rs[i + 1]).magnitude() / ARCSEC for i in range(len(rs) - 1)]
    assert np.allclose(in_grid, 200.0, atol=1e-6)


# --- paper limits -------------------------------------------------------------
# seed 000: "a series of small slews (on the order of 5 arcsec - 9000 arcsec) with
#            fast slew time requirements (2 - 5 minutes)"
# seed 001: "point the SRB up to 2.5 degrees in pitch and yaw away from the center of the Sun"

@pytest.mark.parametrize("fields, names", [
    ({"maneuver": "eve_cruciform", "step_arcsec": 4.9}, ["step_arcsec", "5 to 9000 arcsec"]),
    ({"maneuver": "eve_cruciform", "step_arcsec": 9000.1, "n_steps": 1}, ["step_arcsec", "5 to 9000 arcsec"]),
    ({"maneuver": "eve_cruciform", "step_arcsec": 1000, "n_steps": 10}, ["n_steps", "step_arcsec", "9000 arcsec"]),
    ({"maneuver": "eve_cruciform", "allowance_s": 119}, ["allowance_s", "120 to 300 s"]),
    ({"maneuver": "offpoint_grid", "allowance_s": 301}, ["allowance_s", "120 to 300 s"]),
    ({"maneuver": "offpoint_grid", "spacing_arcsec": 2}, ["spacing_arcsec", "5 to 9000 arcsec"]),
    ({"maneuver": "offpoint_grid", "spacing_arcsec": 1000, "n_rows": 21}, ["n_rows", "spacing_arcsec", "9000 arcsec"]),
    # inside 2.5 deg per axis, but the corner is 11313 arcsec of slew from Sun centre
    ({"maneuver": "offpoint_grid", "spacing_arcsec": 4000}, ["spacing_arcsec", "slew", "5 to 9000 arcsec"]),
    # a 2 x 2 grid at 5 arcsec starts with a 3.5-arcsec slew from Sun centre to its corner: below 5 arcsec
    ({"maneuver": "offpoint_grid", "spacing_arcsec": 5, "n_rows": 2, "n_cols": 2}, ["spacing_arcsec", "slew"]),
])
def test_limits_rejected_with_field_and_range(fields, names):
    with pytest.raises(ValidationError) as err:
        CALIBRATION_ADAPTER.validate_python(fields)
    for n in names:
        assert n in str(err.value)


@pytest.mark.parametrize("fields", [
    {"maneuver": "eve_cruciform", "step_arcsec": 5.0, "n_steps": 1, "allowance_s": 120},
    {"maneuver": "eve_cruciform", "step_arcsec": 9000.0, "n_steps": 1, "allowance_s": 300},
    {"maneuver": "eve_cruciform", "step_arcsec": 900.0, "n_steps": 10},
    {"maneuver": "offpoint_grid", "spacing_arcsec": 5.0, "n_rows": 3, "n_cols": 3},
])
def test_limits_at_the_edges_accepted(fields):
    CALIBRATION_ADAPTER.validate_python(fields)


def test_unknown_maneuver_and_extra_field_rejected():
    with pytest.raises(ValidationError) as err:
        CALIBRATION_ADAPTER.validate_python({"maneuver": "barrel_roll"})
    assert "eve_cruciform" in str(err.value) and "offpoint_grid" in str(err.value)
    with pytest.raises(ValidationError, match="step_arcsecs"):
        CALIBRATION_ADAPTER.validate_python({"maneuver": "eve_cruciform", "step_arcsecs": 600})


# --- scenario item --------------------------------------------------------------

def test_scheduled_calibration_from_a_yaml_item():
    items = yaml.safe_load("- {t_s: 100, maneuver: eve_cruciform, step_arcsec: 600}\n"
                           "- {t_s: 9000, maneuver: offpoint_grid, n_rows: 3, n_cols: 3}\n")
    cal, grid = (ScheduledCalibration.model_validate(i) for i in items)
    assert cal.t_s == 100.0 and isinstance(cal.calibration, EveCruciform)
    assert cal.calibration.step_arcsec == 600.0 and cal.calibration.n_steps == 10   # default kept
    cmds = cal.commands()
    assert cmds[0][0] == 100.0 and len(cmds) == 44
    assert _pointings_from_commands(cmds[:1])[0] == pytest.approx((600.0, 0.0), abs=1e-6)
    assert isinstance(grid.calibration, OffpointGrid) and len(grid.commands()) == 10
    with pytest.raises(ValidationError, match="t_s"):
        ScheduledCalibration.model_validate({"t_s": -5, "maneuver": "eve_cruciform"})
