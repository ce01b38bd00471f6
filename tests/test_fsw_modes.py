"""Flight software II: the SunAcq and Safehold laws against their analytic
form, DeltaH/DeltaV book-keeping against conservation laws, and the mode
machine's transitions, refusals and FDC responses in short runs (seed 001
"Attitude control modes", eq. (6), (7); docs/modes.md)."""
import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from sim.fsw.build_modes import ace_params
from sim.fsw.deltah import system_momentum_error_Nms
from sim.fsw.safehold import css_rates, make_ace_state
from sim.fsw.sunacq import SunLawParams, sun_pointing_error_B, sunacq_torque_B
from sim.runner import Runner
from sim.scenario import parse_scenario
from sim.spacecraft import load_spacecraft

SDO = load_spacecraft("sdo")
I_DIAG = np.diag(np.array(SDO.inertia_B_kgm2))
PLUS_X = np.array([1.0, 0.0, 0.0])


def _run(mode="INERTIAL", duration_s=60.0, commands=(), **initial):
    """A short SDO run; Science autonomy off (so Inertial stays Inertial)."""
    data = {"name": "t", "spacecraft": "sdo", "epoch_utc": "2026-06-21T00:00:00Z", "duration_s": duration_s,
            "seed": 5, "initial": {"mode": mode, "q_BN_frame": "snr", "target": "snr",
                                   "h_wheels_Nms": [-18.0, 5.0, 21.0, 0.0], **initial},
            "commands": [{"t_s": 0.0, "type": "enable_science_autonomy", "enabled": False}] + list(commands),
            "output": {"period_s": 0.2}}
    s, sc = parse_scenario(data)
    return Runner(s, sc).run()


def _modes(res):
    return [(e.t_s, e.data["from"], e.data["to"], e.data["cause"]) for e in res.events if e.kind == "mode"]


def _rejections(res):
    return {r.command.type: r.stages[-1].reason for r in res.commands if r.state == "rejected"}


# -- the laws --------------------------------------------------------------------
def test_sunacq_torque_turns_plus_x_toward_the_sun():
    """Eq. (6) as a body torque: an impulse along the torque rotates the body
    so the Sun angle falls (checked with scipy's Rotation: the Sun vector in
    the new body frame is closer to +X)."""
    p = SunLawParams(0.0025, 0.07, 0.1, PLUS_X)
    rng = np.random.default_rng(1)
    for s_N in rng.normal(size=(50, 3)):
        s = s_N / np.linalg.norm(s_N)
        t = sunacq_torque_B(s, True, np.zeros(3), I_DIAG, p)
        dphi = 1e-3 * (t / I_DIAG) / np.linalg.norm(t / I_DIAG)   # a small body rotation along the response
        s_new = Rotation.from_rotvec(dphi).inv().apply(s)         # an inertial vector seen from the turned body
        assert s_new @ PLUS_X > s @ PLUS_X


def test_sunacq_attitude_limit_and_eclipse_rate_only():
    """|s_d x s| is capped at the limit (seed 001: attitude limiting in SunAcq),
    also at and beyond 90 deg where sin() would fall back to zero; in eclipse
    T = -K_d omega exactly."""
    for angle_deg in (30.0, 90.0, 150.0, 179.9, 180.0):
        s = Rotation.from_euler("z", angle_deg, degrees=True).apply(PLUS_X)
        e = sun_pointing_error_B(s, PLUS_X, 0.1)
        assert np.linalg.norm(e) == pytest.approx(min(0.1, math.sin(math.radians(angle_deg))) if angle_deg < 90
                                                  else 0.1, abs=1e-12)
    p = SunLawParams(0.0025, 0.07, 0.1, PLUS_X)
    w = np.array([0.01, -0.02, 0.03])
    np.testing.assert_allclose(sunacq_torque_B(PLUS_X, False, w, I_DIAG, p), -0.07 * I_DIAG * w, rtol=1e-15)


def test_safehold_css_rate_is_the_perpendicular_body_rate():
    """Eq. (7): ds/dt x s = omega - (omega.s) s for an inertially fixed Sun
    (ds/dt = s x omega in the body frame). Differenced over 0.2 s at a
    constant rate, the filter converges to it within the differencing
    error: the backward difference crossed with the newest vector is off
    by a relative |w| dt / 2 (the chord against the tangent), bounded here
    by |w|^2 dt = 3.2e-6 rad/s."""
    ap = ace_params(SDO)
    a = make_ace_state()
    # w perpendicular to s: s turns in the plane normal to w, so the
    # perpendicular rate is w itself, constant, and the filter's lag drops out
    s0 = np.array([0.8, 0.36, -0.48])
    w = np.cross(s0, [0.0, 0.0, 1.0])
    w *= 0.004 / np.linalg.norm(w)
    for k in range(400):
        s_B = Rotation.from_rotvec(w * k * ap.dt).inv().apply(s0)   # body turning at w, the Sun fixed
        css_rates(s_B, True, a, ap)
    perp = w - (w @ s_B) * s_B
    np.testing.assert_allclose(a.rate_perp_B, perp, rtol=0.0, atol=np.linalg.norm(w) ** 2 * ap.dt)


def test_deltah_exit_quantity_is_the_system_momentum_error():
    """|sum a_i J w_i + I omega - sum a_i h_target,i| from its parts."""
    axes = np.array(SDO.wheels.axes_B)
    J = SDO.wheels.spin_inertia_kgm2
    speeds = np.array([100.0, -50.0, 20.0, 300.0])
    h_t = np.array([6.0, -6.0, 6.0, -6.0])
    omega = np.array([1e-3, -2e-3, 5e-4])
    expect = np.linalg.norm(axes.T @ (J * speeds - h_t) + I_DIAG * omega)
    assert system_momentum_error_Nms(speeds, h_t, omega, I_DIAG, axes, J) == pytest.approx(expect, rel=1e-12)


# -- the mode machine --------------------------------------------------------------
def test_illegal_transitions_are_refused_with_a_reason_and_change_nothing():
    """docs/modes.md: DeltaV is entered from Inertial only; set_deltav_target
    needs DeltaV; DeltaH's entry modes are Inertial and SunAcq."""
    q = [1.0, 0.0, 0.0, 0.0]
    res = _run("SCIENCE", 10.0, [
        {"t_s": 1.0, "type": "start_deltav", "target_q_RN": q, "duration_s": 60, "main_engine": False},
        {"t_s": 2.0, "type": "set_deltav_target", "q_RN": q},
        {"t_s": 3.0, "type": "start_deltah"},
        {"t_s": 4.0, "type": "set_mode", "mode": "DELTAH"},
    ])
    rej = _rejections(res)
    assert "start_deltav is not legal in SCIENCE" in rej["start_deltav"]
    assert "set_deltav_target is not legal in SCIENCE" in rej["set_deltav_target"]
    assert "not legal in SCIENCE" in rej["start_deltah"]
    assert "SCIENCE -> DELTAH is not an allowed transition" in rej["set_mode"]
    assert set(res.telemetry["mode"]) == {"SCIENCE"}
    assert _modes(res) == []


def test_deltah_returns_to_the_mode_it_came_from_and_logs_its_cause():
    """Seed 001 "DeltaH": "the mode exits to the mode from which it was
    entered"; telemetry mode_prev / mode_cause follow (cause 0 ground,
    2 autonomous)."""
    res = _run("INERTIAL", 300.0, [{"t_s": 1.0, "type": "start_deltah",
                                    "wheel_momentum_Nms": [6.0, -6.0, 6.0, -6.0]}], target="snr")
    modes = _modes(res)
    assert modes[0][1:] == ("INERTIAL", "DELTAH", "ground")
    back = [m for m in modes if m[1] == "DELTAH"]
    assert back and back[0][2:] == ("INERTIAL", "autonomous")
    t = np.array(res.telemetry["t_s"])
    i = int(np.searchsorted(t, back[0][0])) + 1
    assert res.telemetry["mode_prev"][i] == 3.0 and res.telemetry["mode_cause"][i] == 2.0   # DELTAH, autonomous
    assert res.telemetry["h_sys_err_Nms"][i] < 3.0


def test_processor_reset_hands_the_wheels_to_the_ace():
    """Seed 001 "Safehold": it runs in the ACE. After the heartbeat is missed
    (5 cycles, sdo.yaml) the ACE is in Safehold (cause FDC); the ground cannot
    leave Safehold while the processor is down, and can once it is back."""
    res = _run("INERTIAL", 60.0, [
        {"t_s": 10.0, "type": "inject_fault", "fault": {"kind": "processor_reset", "duration_s": 20.0}},
        {"t_s": 15.0, "type": "set_mode", "mode": "SUNACQ"},
        {"t_s": 40.0, "type": "set_mode", "mode": "SUNACQ"},
    ])
    modes = _modes(res)
    assert modes[0][1:] == ("INERTIAL", "SAFEHOLD", "fdc")
    assert modes[0][0] == pytest.approx(10.0 + 5 * 0.2, abs=0.21)
    assert "main processor is down" in _rejections(res)["set_mode"]
    assert modes[-1][1:] == ("SAFEHOLD", "SUNACQ", "ground") and modes[-1][0] == pytest.approx(40.0)


def test_an_fdc_check_can_be_disabled_by_command():
    """With the IRU check off, a stuck channel is never isolated; on, it is
    (sdo_iru_failure.yaml runs the enabled case in full)."""
    slew = [0.9961946980917455, 0.08715574274765817, 0.0, 0.0]
    cmds = [{"t_s": 5.0, "type": "inject_fault", "fault": {"kind": "iru_stuck", "channel": 1}},
            {"t_s": 10.0, "type": "set_target_quaternion", "q_RN": slew}]
    off = _run("INERTIAL", 120.0, [{"t_s": 1.0, "type": "set_fdc_check", "check": "iru", "enabled": False}] + cmds,
               q_BN_frame="gci", q_BN=[1.0, 0.0, 0.0, 0.0], target="attitude")
    on = _run("INERTIAL", 120.0, cmds, q_BN_frame="gci", q_BN=[1.0, 0.0, 0.0, 0.0], target="attitude")
    assert min(off.telemetry["iru_ch_use_1"]) == 1.0
    assert on.telemetry["iru_ch_use_1"][-1] == 0.0
    assert any(e.kind == "fdc" and "IRU channel 1" in e.message for e in on.events)


def test_rate_limit_fdc_takes_inertial_to_sunacq():
    """sdo.yaml fsw.fdc: Inertial's rate limit is 1 deg/s, held 5 s, response
    SunAcq. Started at 1.5 deg/s, Inertial's wheel torque cannot slow the
    body below the limit within 5 s (0.35 N m against 3963 kg m^2 takes
    minutes), so the check fires at 5 s."""
    res = _run("INERTIAL", 20.0, omega_BN_B_rad_s=[0.0, math.radians(1.5), 0.0])
    modes = _modes(res)
    assert modes and modes[0][1:] == ("INERTIAL", "SUNACQ", "fdc")
    assert modes[0][0] == pytest.approx(5.0, abs=0.41)
    fdc = [e for e in res.events if e.kind == "fdc"]
    assert fdc and fdc[0].data["check"] == "limits" and fdc[0].data["response"] == "to SUNACQ"


def test_deltav_target_changes_mid_burn_on_the_redundant_set():
    """Seed 001 "DeltaV": "this target may be changed during a maneuver"; an
    ACS-only burn (off-pulsing) on the redundant set: thrusters 5-8 fire,
    1-4 never; after a 2 deg retarget the attitude follows (the PD's
    steady error under the off-pulsing's residual torque is small) and the
    burn ends in Inertial at its time."""
    q2 = Rotation.from_euler("y", 2.0, degrees=True).as_quat(scalar_first=True).tolist()
    res = _run("INERTIAL", 200.0, [
        {"t_s": 10.0, "type": "start_deltav", "target_q_RN": [1.0, 0.0, 0.0, 0.0], "duration_s": 150.0,
         "main_engine": False, "thruster_set": "redundant"},
        {"t_s": 60.0, "type": "set_deltav_target", "q_RN": q2},
    ], q_BN_frame="gci", q_BN=[1.0, 0.0, 0.0, 0.0], target="attitude")
    tel = {k: np.array(v) for k, v in res.telemetry.items() if k != "mode"}
    t = tel["t_s"]
    burn = (t > 10.5) & (t < 159.5)
    assert all(tel[f"thr_pulses_{i}"][burn].max() == 0.0 for i in range(1, 5))
    assert all(tel[f"thr_pulses_{i}"][burn].sum() > 0.0 for i in range(5, 9))
    # the truth's attitude against the new target, from its quaternion
    late = (t > 120.0) & (t < 159.5)
    q = np.stack([tel[f"q_BN_{a}"][late] for a in "wxyz"], axis=1)
    err_deg = (Rotation.from_quat(q, scalar_first=True) * Rotation.from_quat(q2, scalar_first=True).inv()).magnitude()
    assert np.degrees(err_deg).max() < 0.5
    assert _modes(res)[-1][1:] == ("DELTAV", "INERTIAL", "autonomous")
    assert _modes(res)[-1][0] == pytest.approx(160.0, abs=0.41)
    # the ACS thrusters gave the delta-V: 4 x 22.24 N x cos 10 deg for ~150 s on ~3000 kg (minus off-pulsing)
    dv = tel["deltav_est_m_s"].max()
    assert 0.7 * 4 * 22.24 * 0.985 * 150.0 / 3000.0 < dv < 4 * 22.24 * 0.985 * 150.0 / 2990.0


def test_commands_wait_for_the_processor_and_its_clock_catches_up():
    """While the main processor is down every flight-software command is
    refused with the reason; after processor_failed is cleared 10 min later
    the on-board ephemeris has caught up: the on-board Sun is within 2 arcsec
    of the truth's (seed 001 "On-Board Ephemeris"; without the catch-up it
    would lag the Sun's ~0.04 arcsec/s motion by 600 s, ~25 arcsec)."""
    res = _run("INERTIAL", 700.0, [
        {"t_s": 10.0, "type": "inject_fault", "fault": {"kind": "processor_failed"}},
        {"t_s": 20.0, "type": "reset_integrator"},
        {"t_s": 610.0, "type": "clear_fault", "fault": {"kind": "processor_failed"}},
    ])
    assert "main processor is down" in _rejections(res)["reset_integrator"]
    t = np.array(res.telemetry["t_s"])
    err = np.array(res.telemetry["sun_fsw_err_arcsec"])
    assert err[t > 615.0].max() < 2.0
    assert _modes(res)[0][1:] == ("INERTIAL", "SAFEHOLD", "fdc")


def test_no_false_wheel_failure_after_safehold():
    """The wheel check does not run in Safehold; its memory of speeds and
    commands from before is cleared on the way out, so the wheel momentum the
    ACE moved in 5 min is not taken for a failure back in SunAcq."""
    res = _run("INERTIAL", 420.0, [
        {"t_s": 5.0, "type": "set_mode", "mode": "SAFEHOLD"},
        {"t_s": 305.0, "type": "set_mode", "mode": "SUNACQ"},
    ], q_BN=[0.9659258262890683, 0.0, 0.0, 0.25881904510252074])   # 30 deg off the Sun: the ACE works
    wheels = np.array([res.telemetry[f"h_wheel_{i}_Nms"] for i in range(1, 5)])
    assert np.abs(wheels[:, -1] - wheels[:, 0]).max() > 3.0          # the ACE did move the wheels
    assert not [e for e in res.events if e.kind == "fdc" and e.data["check"] == "wheel"]
    assert min(res.telemetry["wheel_ok_1"]) == 1.0


def test_non_finite_inputs_are_schema_errors():
    """NaN passes a naive |q| - 1 check; the schema refuses it, and infinities."""
    from pydantic import ValidationError

    from sim.commands import COMMAND_ADAPTER
    for bad in ({"type": "set_deltav_target", "q_RN": [float("nan"), 0, 0, 0]},
                {"type": "start_deltah", "wheel_speed_rpm": [float("inf"), 0, 0, 0]},
                {"type": "start_deltav", "target_q_RN": [1, 0, 0, 0], "duration_s": float("nan"),
                 "main_engine": True}):
        with pytest.raises(ValidationError):
            COMMAND_ADAPTER.validate_python(bad)


def test_start_calibration_expands_into_timed_target_commands():
    """The console's calibration picker sends start_calibration; the ground
    side expands it (sim/calibration.py expand: one command per pointing at
    t0 + k (allowance + dwell), then the return to Sun centre) into the same
    queue, each with its own lifecycle. A 1 x 3 grid at 300 arcsec, 120 + 60 s
    per point, from t = 10 s: tags 10, 190, 370 and the return at 550 s.
    Refused outside Inertial (seed 001: calibrations fly in Inertial)."""
    grid = {"maneuver": "offpoint_grid", "n_rows": 1, "n_cols": 3}
    res = _run("INERTIAL", 700.0, [{"t_s": 10.0, "type": "start_calibration", "maneuver": grid}])
    parent = next(r for r in res.commands if r.command.type == "start_calibration")
    assert parent.state == "completed"
    steps = [r for r in res.commands if r.source == f"calibration:{parent.id}"]
    assert [r.due_s for r in steps] == pytest.approx([10.0, 190.0, 370.0, 550.0], abs=1e-9)
    assert all(r.command.type == "set_target_snr" for r in steps)
    assert steps[-1].command.delta_q == (1.0, 0.0, 0.0, 0.0)
    assert all(r.state == "completed" for r in steps)          # each slew settled within its allowance
    refused = _run("SCIENCE", 5.0, [{"t_s": 1.0, "type": "start_calibration", "maneuver": grid}])
    assert "not legal in SCIENCE" in _rejections(refused)["start_calibration"]
