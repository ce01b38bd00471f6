"""Inertial and Science modes wired together: targeting, the attitude
options, the CGT, the autonomy flag and the mode transitions (seed 001
"Inertial mode", "Science mode"; sim/fsw/flight_software.py)."""
import math

import numpy as np
import pytest

from sim.calibration import delta_quat
from sim.runner import Runner
from sim.scenario import parse_scenario

ARCSEC = math.pi / 180.0 / 3600.0


def _science(duration_s=300.0, commands=(), mode="SCIENCE", **kw):
    data = {"name": "t", "spacecraft": "sdo", "epoch_utc": "2026-06-21T00:00:00Z", "duration_s": duration_s,
            "seed": 4, "initial": {"mode": mode, "q_BN_frame": "snr", "target": "snr",
                                   "h_wheels_Nms": [-18.0, 5.0, 21.0, 0.0]},
            "commands": list(commands), "output": {"period_s": 1.0}, **kw}
    return parse_scenario(data)


def _run(*args, **kw):
    s, sc = _science(*args, **kw)
    return Runner(s, sc).run()


def _col(res, name, t_from=0.0, t_to=math.inf):
    t = np.array(res.telemetry["t_s"])
    x = np.array(res.telemetry[name])
    return x[(t >= t_from) & (t <= t_to)]


def _mode_events(res):
    return [(e.t_s, e.data["from"], e.data["to"], e.data["cause"]) for e in res.events if e.kind == "mode"]


@pytest.fixture(scope="module")
def handover():
    """Science; ground takes it to Inertial at 100 s (autonomy cleared on
    entry), and re-enables autonomy at 200 s."""
    return _run(300.0, [{"t_s": 100.0, "type": "set_mode", "mode": "INERTIAL"},
                        {"t_s": 200.0, "type": "enable_science_autonomy"}])


def test_entry_to_inertial_clears_autonomy_and_the_flag_brings_science_back(handover):
    """Seed 001 "Science mode": autonomy "is disabled on entry into Inertial
    mode to prevent the software switching back and forth"."""
    assert _mode_events(handover) == [(100.0, "SCIENCE", "INERTIAL", "ground"),
                                      (200.2, "INERTIAL", "SCIENCE", "autonomous")]
    assert set(_col(handover, "science_autonomy", 101.0, 199.0)) == {0.0}
    assert set(_col(handover, "mode", 101.0, 200.0)) == {"INERTIAL"}


def test_integral_carries_across_inertial_and_science(handover):
    """Seed 000: the integral term is what holds the steady state against the
    drag; a transition must not reset it. The integral changes by no more
    than a second's integration of the (arcsec-level) error across each switch."""
    for t in (100.0, 200.0):
        for a in "xyz":
            before, after = _col(handover, f"integral_B_{a}_rad_s", t - 1.0, t + 1.0)[[0, -1]]
            assert abs(after - before) < 2.0 * 5.0 * ARCSEC   # 2 s x 5 arcsec


def test_commanded_science_without_cgt_is_refused_with_reason():
    """Inertial 600 arcsec off the Sun: the CGT is saturated (+-95 arcsec fine
    range, seed 000), so a commanded Science entry is refused; GCI target, so
    no autonomous hand-over either."""
    s, sc = _science(30.0, [{"t_s": 5.0, "type": "set_mode", "mode": "SCIENCE"}], mode="INERTIAL")
    data = s.model_dump()
    data["initial"].update(q_BN=list(delta_quat(600.0, 0.0)), target="attitude")
    s, sc = parse_scenario(data)
    res = Runner(s, sc).run()
    stages = [(st.name, st.reason) for st in res.commands[0].stages]
    assert stages[-1][0] == "rejected" and "guide telescope 1" in stages[-1][1]
    assert set(_col(res, "mode")) == {"INERTIAL"}


def test_select_cgt_and_attitude_option_reach_telemetry():
    res = _run(20.0, [{"t_s": 5.0, "type": "select_cgt", "cgt": 3},
                      {"t_s": 5.0, "type": "set_attitude_option", "option": "star_tracker", "star_tracker": 2}])
    assert _col(res, "cgt", 0, 4).tolist() == [1.0] * 5 and set(_col(res, "cgt", 6)) == {3.0}
    assert set(_col(res, "star_tracker_flown", 6)) == {2.0} and set(_col(res, "attitude_option", 6)) == {0.0}
    assert set(_col(res, "mode")) == {"SCIENCE"}   # a CGT change keeps Science (all four see the Sun)


def test_small_offset_in_science_flies_on_the_guide_telescope():
    """A 40 arcsec pitch off-point in Science (inside the +-95 arcsec fine
    range, seed 000 "Introduction": small calibration steps fly in Science):
    the truth boresight settles 40 arcsec from the apparent Sun, and the
    pointing error against the new target is arcsec-level."""
    res = _run(300.0, [{"t_s": 20.0, "type": "set_target_snr", "delta_q": list(delta_quat(40.0, 0.0))}])
    assert set(_col(res, "mode")) == {"SCIENCE"}
    assert res.commands[0].state == "completed"
    sun_offset_arcsec = _col(res, "sun_angle_deg", 200.0) * 3600.0
    assert sun_offset_arcsec.mean() == pytest.approx(40.0, abs=1.5)
    assert _col(res, "point_err_arcsec", 200.0).max() < 3.0


def test_star_tracker_loss_keeps_knowledge_with_the_other_tracker_and_dss():
    """Seed 001: the star trackers and the DSS give two-out-of-three fault
    tolerance; with tracker 1 gone the EKF keeps the knowledge requirement
    [35, 70, 70] arcsec (3 sigma)."""
    res = _run(600.0, [{"t_s": 10.0, "type": "inject_fault",
                        "fault": {"kind": "star_tracker_dropout", "tracker": 1}}])
    assert set(_col(res, "st_used_1", 11.0)) == {0.0} and set(_col(res, "st_used_2", 11.0)) == {1.0}
    for axis, req in zip("xyz", (35.0, 70.0, 70.0)):
        e = _col(res, f"knowledge_err_B_{axis}_arcsec", 11.0)
        assert abs(e.mean()) + 3 * e.std() < req


def test_knowledge_error_is_estimate_minus_truth():
    """Its magnitude is the rotation angle between estimate and truth
    (est_err_arcsec, computed independently), to small-angle order."""
    res = _run(60.0)
    k = np.linalg.norm([_col(res, f"knowledge_err_B_{a}_arcsec") for a in "xyz"], axis=0)
    assert np.allclose(k, _col(res, "est_err_arcsec"), atol=1e-6)
