"""Command model and lifecycle: queued -> accepted | rejected(reason) ->
executing -> completed | failed(reason), every stage time-stamped."""
import math

import numpy as np
import pytest
from pydantic import ValidationError
from scipy.spatial.transform import Rotation

from sim.commands import COMMAND_ADAPTER, ResetIntegrator
from sim.modes import Mode
from sim.runner import Runner
from sim.scenario import parse_scenario


def _scenario(duration_s=400.0, commands=(), overrides=None, **initial):
    data = {"name": "t", "spacecraft": "sdo", "duration_s": duration_s, "seed": 3,
            "initial": {"mode": "INERTIAL", **initial}, "commands": list(commands), "output": {"period_s": 1.0}}
    if overrides:
        data["overrides"] = overrides
    return parse_scenario(data)


def _target(deg, axis=(0, 0, 1)):
    return Rotation.from_rotvec(np.radians(deg) * np.asarray(axis) / np.linalg.norm(axis)).as_quat(
        scalar_first=True).tolist()


def _stages(rec):
    return [(s.name, s.t_s, s.reason) for s in rec.stages]


def test_schema_rejects_non_unit_quaternion_naming_the_field():
    with pytest.raises(ValidationError) as err:
        COMMAND_ADAPTER.validate_python({"type": "set_target_quaternion", "q_RN": [1, 1, 0, 0]})
    assert "q_RN" in str(err.value) and "unit quaternion" in str(err.value)


def test_schema_lists_allowed_types_for_unknown_type():
    with pytest.raises(ValidationError) as err:
        COMMAND_ADAPTER.validate_python({"type": "fire_everything"})
    assert "set_target_quaternion" in str(err.value) and "reset_integrator" in str(err.value)


def test_slew_lifecycle_and_limited_slew_rate():
    s, sc = _scenario(commands=[{"t_s": 20.0, "type": "set_target_quaternion", "q_RN": _target(5, (1, 2, 3))}])
    r = Runner(s, sc)
    res = r.run()
    rec = res.commands[0]
    names = [st[0] for st in _stages(rec)]
    assert names == ["queued", "accepted", "executing", "completed"]
    assert _stages(rec)[1][1] == 20.0  # delivered at the first control cycle at its time tag
    t = np.array(res.telemetry["t_s"])
    rate = np.linalg.norm([res.telemetry[f"omega_BN_B_{a}_rad_s"] for a in "xyz"], axis=0)
    # steady slew of a PD law with a magnitude-limited attitude error: K_p theta_a = K_d omega,
    # omega = k_p / k_d * theta_a (seed 000 gains, 7e-3 rad limit)
    g = sc.fsw.inertial
    assert rate.max() == pytest.approx(g.kp_per_s2 / g.kd_per_s * g.attitude_limit_rad, rel=0.05)
    # completion means inside the integral torque box: truth error then within
    # the box's 250 arcsec (seed 000) plus the star tracker's noise
    done = _stages(rec)[-1][1]
    err = np.array(res.telemetry["att_err_arcsec"])[t >= done]
    assert err.max() < 250 + 30


def test_reset_integrator_completes_in_its_cycle_and_zeroes_the_integral():
    s, sc = _scenario(duration_s=200.0, commands=[{"t_s": 150.0, "type": "reset_integrator"}],
                      h_wheels_Nms=[-20.0, 0.0, 20.0, 0.0])
    res = Runner(s, sc).run()
    assert [n for n, _, _ in _stages(res.commands[0])] == ["queued", "accepted", "executing", "completed"]
    assert {t for _, t, _ in _stages(res.commands[0])[1:]} == {150.0}
    t = np.array(res.telemetry["t_s"])
    iy = np.array(res.telemetry["integral_B_y_rad_s"])
    assert abs(iy[t == 149.0][0]) > 1e-5   # wheel drag was being integrated away...
    assert abs(iy[t == 150.0][0]) < abs(iy[t == 149.0][0]) / 10  # ...and restarted from zero


def test_illegal_command_for_mode_is_rejected_with_reason_and_changes_nothing():
    s, sc = _scenario(duration_s=10.0, commands=[{"t_s": 2.0, "type": "reset_integrator"},
                                                 {"t_s": 2.0, "type": "set_target_quaternion",
                                                  "q_RN": _target(1)}])
    r = Runner(s, sc)
    r.fsw.state.mode[0] = int(Mode.SAFEHOLD)  # a mode where neither is legal
    r.fsw.state.integral[:] = [1e-3, 2e-3, 3e-3]
    target = r.fsw.state.q_RN.copy()
    res = r.run()
    for rec in res.commands:
        (name, t, reason) = _stages(rec)[1]
        assert name == "rejected" and t == 2.0
        assert "SAFEHOLD" in reason and "INERTIAL" in reason
    assert np.array_equal(r.fsw.state.integral, [1e-3, 2e-3, 3e-3])
    assert np.array_equal(r.fsw.state.q_RN, target)
    assert any(e.kind == "command" and e.severity == "warning" and "rejected" in e.message for e in res.events)


def test_new_target_supersedes_an_executing_slew():
    s, sc = _scenario(duration_s=300.0, commands=[
        {"t_s": 10.0, "type": "set_target_quaternion", "q_RN": _target(5)},
        {"t_s": 30.0, "type": "set_target_quaternion", "q_RN": _target(-1)}])
    res = Runner(s, sc).run()
    first, second = res.commands
    assert _stages(first)[-1] == ("failed", 30.0, "superseded by command 2")
    assert _stages(second)[-1][0] == "completed"


def test_slew_that_cannot_settle_in_time_fails_with_reason():
    """A slew is allowed its angle at the limiter's rate k_p/k_d x attitude
    limit (seed 001 eq. 3 with theta_e held at the limit: k_d omega = k_p
    theta_lim) plus the allowance; 10 deg at 0.07192/0.467055 x 7e-3 rad =
    1.078e-3 rad/s is 162 s, and an allowance of 1 s cannot cover the settling."""
    s, sc = _scenario(duration_s=400.0, overrides={"fsw": {"slew_allowance_s": 1.0}},
                      commands=[{"t_s": 10.0, "type": "set_target_quaternion", "q_RN": _target(10)}])
    res = Runner(s, sc).run()
    name, t, reason = _stages(res.commands[0])[-1]
    expected_s = math.radians(10.0) / (0.07192 / 0.467055 * 7.0e-3) + 1.0
    assert name == "failed" and abs(t - (10.0 + expected_s)) < 0.5 and f"{expected_s:.0f} s" in reason


def test_live_submission_shares_the_queue_with_scenario_commands():
    s, sc = _scenario(duration_s=20.0, commands=[{"t_s": 5.0, "type": "reset_integrator"}])
    r = Runner(s, sc)
    r.advance_to(r.cycle_at(2.0))
    live = r.submit(ResetIntegrator(), "operator")
    r.run()
    assert live.id == 2 and live.source == "operator"
    # a live command reaches the flight software at the next control cycle
    assert [st.t_s for st in live.stages][1] == pytest.approx(2.0)
    assert [st.name for st in live.stages][-1] == "completed"
