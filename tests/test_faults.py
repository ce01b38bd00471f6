"""Injected faults, end to end through the Runner (and, for thruster_failed_off,
through the truth plant directly): each fault must change exactly the outputs
it should, checked against physics, hand computations from sim/spacecraft/sdo.yaml,
or a fault-free reference run with the same seed.

Timing convention used throughout (sim/runner.py Runner.advance_to): a fault
commanded at t is applied at the top of the control cycle at t, before that
cycle's sensor sample and propagation. The telemetry frame at t holds the
truth state at t and the sensor record of the last completed cycle (sampled
at t - 0.2 s), so a sensor fault first shows in the frame at t + 0.2 s; the
wheel command in the frame at t is the one applied over [t, t + 0.2 s]
(one-cycle actuator delay, sim/loop.py).
"""
import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from sim import fault_injection
from sim.attitude import quat_rotate
from sim.faults import ThrusterFailedOff
from sim.records import empty_actuator_command
from sim.runner import Runner
from sim.scenario import ScenarioError, parse_scenario
from sim.spacecraft import load_spacecraft
from sim.truth import build, plant
from sim.truth import mass as massmod
from sim.truth.rigid_body import angular_momentum_B
from sim.truth.thrusters import FAIL_OFF

CYCLE_S = 0.2                       # sdo.yaml timing.control_dt_s
H0 = [20.0, -10.0, 5.0, 15.0]       # initial wheel momenta, N m s (test choice)
NO_DISTURBANCE = {"srp": False, "gravity_gradient": False}

# sdo.yaml numbers used for hand computations
JS = 0.1114                         # wheels.spin_inertia_kgm2
C_VISCOUS = 1.67e-4                 # wheels.viscous_Nm_per_rad_s
C_COULOMB = 0.002                   # wheels.coulomb_Nm
COULOMB_SPEED = 0.1                 # model.py default coulomb_smoothing_rad_s
C_SEIZED = 1.0                      # sim/fault_injection.py SEIZED_VISCOUS_Nm_per_rad_s (its stated Js/c = 0.11 s)
LBF_N = 4.4482216152605             # NIST SP 811
G0 = 9.80665                        # standard gravity
THR_F = 5.0 * LBF_N                 # thrusters: thrust_lbf 5.0 -> 22.24 N
THR_ISP = 285.0                     # thrusters: isp_s
THR_PULSE_S = 0.05                  # thrusters: pulse_s
CM_FULL = np.array([0.0, 0.05, -0.06])  # mass.cm_full_B_m
THR1_POS = np.array([-1.6, 1.0, 1.0])   # thrusters.units[0]
THR1_DIR = np.array([0.984807753012208, -0.17364817766693033, 0.0])
THR2_POS = np.array([-1.6, -1.0, 1.0])  # thrusters.units[1]
THR2_DIR = np.array([0.984807753012208, 0.17364817766693033, 0.0])
CSS_FULL_A = 1.0e-3                 # sensors.css.full_sun_current_A
CSS_NOISE_3SIGMA_A = 1.5e-5         # sensors.css.noise_A_3sigma
IRU_LSB_RAD = math.radians(0.5 / 3600.0)  # sensors.iru_units.lsb_arcsec
IRU_AXES = np.array([[1, 0, 0], [0, 1, 0], [0, 1, 0], [0, 0, 1], [0, 0, 1], [1, 0, 0]], float)  # channel_axes_B
RAD_S_PER_RPM = 2.0 * math.pi / 60.0


def _scenario(duration_s, commands=(), env=None, period_s=CYCLE_S, seed=5, **initial):
    data = {"name": "faults", "spacecraft": "sdo", "duration_s": duration_s, "seed": seed,
            "initial": {"mode": "INERTIAL", "h_wheels_Nms": H0, **initial}, "commands": list(commands),
            "output": {"period_s": period_s}}
    if env:
        data["environment"] = env
    return parse_scenario(data)


# These tests check what a fault does to the truth model and its sensors; the
# flight software's failure detection would answer some of them (drop an IRU
# channel, a wheel) and change the closed loop under test, so it is off here
# (tests/test_fsw_modes.py and the sdo_*_failure scenarios test it).
FDC_OFF = [{"t_s": 0.0, "type": "set_fdc_check", "check": c, "enabled": False}
           for c in ("limits", "iru", "wheel", "star_tracker")]


def _run(duration_s, commands=(), env=None, **initial):
    s, sc = _scenario(duration_s, FDC_OFF + list(commands), env, **initial)
    return Runner(s, sc).run()


def _faults_only(records):
    return [r for r in records if r.command.type != "set_fdc_check"]


def _inject(t_s, **fault):
    return {"t_s": t_s, "type": "inject_fault", "fault": fault}


def _clear(t_s, **fault):
    return {"t_s": t_s, "type": "clear_fault", "fault": fault}


def _col(res, name):
    return np.asarray(res.telemetry[name], float)


def _vec(res, prefix, unit="", axes="xyz"):
    return np.array([_col(res, f"{prefix}_{a}{unit}") for a in axes]).T


@pytest.fixture(scope="module")
def reference():
    """Fault-free 60 s Inertial hold, seed 5, full environment."""
    return _run(60.0)


# -- wheels -----------------------------------------------------------------------

def test_wheel_seized_locks_rotor_ignores_motor_and_conserves_momentum():
    t_inj = 10.0
    res = _run(60.0, [_inject(t_inj, kind="wheel_seized", wheel=1)], env=NO_DISTURBANCE)
    t = _col(res, "t_s")
    speed = _col(res, "wheel_speed_1_rpm") * RAD_S_PER_RPM
    s0 = speed[np.isclose(t, t_inj)][0]
    assert abs(s0) == pytest.approx(H0[0] / JS, rel=0.01)  # ~179.5 rad/s before the fault

    # speed relative to the body decays as exp(-t / tau), tau = Js / (c_seized + c_viscous)
    # = 0.1114 / 1.000167 = 0.11138 s (body coupling changes it by 3e-5, Coulomb by 1e-4,
    # RK4 at 0.05 s steps on this time constant by ~1e-3 over the cycle)
    tau = JS / (C_SEIZED + C_VISCOUS)
    s1 = speed[np.isclose(t, t_inj + CYCLE_S)][0]
    assert s1 / s0 == pytest.approx(math.exp(-CYCLE_S / tau), rel=2e-3)
    # ~0 within a second: exp(-1 / 0.1114) = 1.3e-4 of the initial speed
    after_1s = np.abs(speed[t >= t_inj + 1.0])
    assert after_1s.max() < 2e-4 * abs(s0)

    # the motor command no longer matters: the controller keeps asking for up to
    # 0.2 N m on wheel 1; a working motor would hold the rotor at u / c ~ 0.2 rad/s
    # against the seizure friction, the dead one lets it stop
    u = np.abs(_col(res, "wheel_cmd_1_Nm")[t >= t_inj + 2.0])
    assert u.max() > 0.1
    assert np.abs(speed[t >= t_inj + 2.0]).max() < 0.01 * u.max() / C_SEIZED

    # internal torque only (srp and gravity gradient off, no thruster or engine):
    # inertial total angular momentum conserved to 1e-6 N m s, while the seizure
    # hands the rotor's ~20 N m s to the body
    h_total = _vec(res, "h_total_N", "_Nms")
    assert np.abs(h_total - h_total[0]).max() < 1e-6
    assert abs(_col(res, "h_wheel_1_Nms")[-1]) < 1e-3


def test_wheel_drag_adds_c_times_speed_on_that_wheel(reference):
    t_inj, c_extra = 10.0, 1e-3  # sim/faults.py WheelDrag default viscous_Nm_per_rad_s
    res = _run(60.0, [_inject(t_inj, kind="wheel_drag", wheel=2)])
    t = _col(res, "t_s")
    # same seed, same everything before the fault
    pre = t <= t_inj
    assert np.array_equal(_col(res, "h_wheel_2_Nms")[pre], _col(reference, "h_wheel_2_Nms")[pre])

    # dh/dt of a rotor is exactly the torque on it (sim/truth/wheels.py):
    #   dh/dt = u - c_v speed - c_c tanh(speed / 0.1) - c_extra speed
    # with u the command applied over the cycle (telemetry wheel_cmd at the
    # cycle's start). Over each 0.2 s cycle, speed taken as the mean of its ends.
    def extra_drag(r):
        h = _col(r, "h_wheel_2_Nms")
        sp = _col(r, "wheel_speed_2_rpm") * RAD_S_PER_RPM
        u = _col(r, "wheel_cmd_2_Nm")
        s_mid = 0.5 * (sp[1:] + sp[:-1])
        nominal = u[:-1] - C_VISCOUS * s_mid - C_COULOMB * np.tanh(s_mid / COULOMB_SPEED)
        return nominal - np.diff(h) / np.diff(t), s_mid

    window = (t[:-1] >= t_inj) & (t[:-1] < t_inj + 10.0)
    drag, s_mid = extra_drag(res)
    assert np.abs(_col(res, "wheel_cmd_2_Nm")[:-1][window]).max() < 0.25  # inside the motor limit: no clip
    # hand: c_extra * speed = 1e-3 * ~89 rad/s = ~0.089 N m, to 1e-5 N m per cycle
    assert drag[window] == pytest.approx(c_extra * s_mid[window], abs=1e-5)
    assert np.mean(drag[window] / s_mid[window]) == pytest.approx(c_extra, rel=1e-3)
    # the fault-free run has no extra drag (same residual to 1e-8 N m)
    drag_ref, _ = extra_drag(reference)
    assert np.abs(drag_ref).max() < 1e-8
    # and the wheel's speed magnitude falls faster than without the fault
    sp, sp_ref = (np.abs(_col(r, "wheel_speed_2_rpm")) * RAD_S_PER_RPM for r in (res, reference))
    assert sp[-1] < sp_ref[-1] - 1.0


# -- IRU ---------------------------------------------------------------------------

def test_iru_bias_shifts_only_its_channel_by_the_bias(reference):
    t_inj, bias_deg_h, k = 10.0, 10.0, 2
    res = _run(60.0, [_inject(t_inj, kind="iru_bias", channel=k, bias_deg_h=bias_deg_h)])
    t = _col(res, "t_s")
    bias = math.radians(bias_deg_h) / 3600.0  # 10 deg/h = 4.848e-5 rad/s
    win = t >= t_inj + 10.0  # 40 s, 201 frames
    # The controller uses the IRU, so the true body rate changes a little too;
    # the channel shift must be the true-rate shift along its axis plus the bias
    # on channel k alone. Noise rows are identical (same seed); quantisation
    # (0.5 arcsec counts, carried) limits a 40 s mean to ~2 lsb / 40 s = 1.2e-7 rad/s.
    tol = 3.0 * IRU_LSB_RAD / 40.0
    d_omega = _vec(res, "omega_BN_B", "_rad_s") - _vec(reference, "omega_BN_B", "_rad_s")
    for ch in range(1, 7):
        shift = np.mean(_col(res, f"iru_rate_ch_{ch}_rad_s")[win] - _col(reference, f"iru_rate_ch_{ch}_rad_s")[win])
        true_shift = np.mean(d_omega[win] @ IRU_AXES[ch - 1])
        expected = bias if ch == k else 0.0
        assert shift - true_shift == pytest.approx(expected, abs=tol), f"channel {ch}"
        if ch != k:
            assert abs(shift) < 0.1 * bias, f"channel {ch}"


def test_iru_stuck_freezes_the_channel_during_a_slew():
    t_inj, k, partner = 20.0, 4, 5  # channels 4 and 5 both sense body Z (sdo.yaml channel_axes_B)
    q_target = Rotation.from_rotvec(np.radians(2.0) * np.array([0.0, 0.0, 1.0])).as_quat(scalar_first=True)
    res = _run(60.0, [{"t_s": 2.0, "type": "set_target_quaternion", "q_RN": q_target.tolist()},
                      _inject(t_inj, kind="iru_stuck", channel=k)])
    t = _col(res, "t_s")
    after = t >= t_inj
    stuck = _col(res, f"iru_rate_ch_{k}_rad_s")
    held = stuck[np.isclose(t, t_inj)][0]   # last output before the fault
    assert held > 5e-4                      # slewing about Z at ~1.1e-3 rad/s
    assert np.all(stuck[after] == held)     # frozen, bit for bit
    # meanwhile the body rate about Z changes by > 1e-3 rad/s and the partner channel follows it
    wz = _col(res, "omega_BN_B_z_rad_s")
    assert np.ptp(wz[after]) > 1e-3
    moving = _col(res, f"iru_rate_ch_{partner}_rad_s")
    assert np.ptp(moving[after]) > 1e-3
    # the frame at t_k holds the sample at t_k-1: the mean Z rate over [t_k-2, t_k-1]
    # (trapezoid of the truth), within a few 0.5-arcsec counts per cycle
    z_mean = 0.5 * (wz[:-2] + wz[1:-1])
    assert np.abs(moving[2:] - z_mean)[after[2:]].max() < 3 * IRU_LSB_RAD / CYCLE_S
    for ch in (1, 2, 3, 6):
        assert np.ptp(_col(res, f"iru_rate_ch_{ch}_rad_s")[after]) > 0.0, f"channel {ch} should not be frozen"


# -- star trackers, coarse Sun sensors ------------------------------------------------

def test_star_tracker_dropout_blanks_only_that_tracker(reference):
    t_inj, t_clr = 10.0, 40.0
    res = _run(60.0, [_inject(t_inj, kind="star_tracker_dropout", tracker=1),
                      _clear(t_clr, kind="star_tracker_dropout", tracker=1)])
    t = _col(res, "t_s")
    v1, v2 = _col(res, "st_valid_1"), _col(res, "st_valid_2")
    live = t > 0.0   # the frame at 0 precedes the first sample (empty record)
    # both trackers have a solution in the fault-free run (Sun ~90 deg off their boresights)
    assert np.all(_col(reference, "st_valid_1")[live] == 1) and np.all(_col(reference, "st_valid_2")[live] == 1)
    assert np.all(v1[live & (t <= t_inj)] == 1)
    assert np.all(v1[(t >= t_inj + CYCLE_S) & (t <= t_clr)] == 0)
    assert np.all(v1[t >= t_clr + CYCLE_S] == 1)   # cleared: back
    assert np.all(v2[live] == 1)


def test_css_failed_eye_reads_zero_and_nothing_else_changes(reference):
    t_inj, eye = 10.0, 1
    res = _run(60.0, [_inject(t_inj, kind="css_failed", eye=eye)])
    t = _col(res, "t_s")
    # eye 1 boresight (1, 1, 1)/sqrt(3) (sdo.yaml boresights_primary_B[0]); the Sun is near +X
    # at the identity attitude, so it reads full_sun * lit * cos = 1 mA * 0.577.
    b = np.ones(3) / math.sqrt(3.0)
    sun_B = _vec(reference, "sun_B")
    lit = _col(reference, "eclipse_lit_fraction")
    hand = CSS_FULL_A * lit * (sun_B @ b)
    ref_i = _col(reference, f"css_current_{eye}_A")
    live = t > 0.0
    assert hand[live].min() > 5e-4
    # 300-frame mean: noise 5e-6 A 1-sigma / sqrt(300) and a 2.4e-7 A step -> 3e-6 A
    assert np.mean(ref_i[live]) == pytest.approx(np.mean(hand[live]), abs=3e-6)
    assert np.abs(ref_i[live] - hand[live]).max() < CSS_NOISE_3SIGMA_A * 1.5 + 2.5e-7
    i = _col(res, f"css_current_{eye}_A")
    assert np.all(i[t >= t_inj + CYCLE_S] == 0.0)
    assert np.array_equal(i[t <= t_inj], ref_i[t <= t_inj])
    # the CSS is not used by the Inertial controller: every other output is bit-identical
    changed = [k for k in reference.telemetry
               if np.asarray(reference.telemetry[k]).tobytes() != np.asarray(res.telemetry[k]).tobytes()]
    assert changed == [f"css_current_{eye}_A"]


# -- thrusters ---------------------------------------------------------------------------

def test_thruster_stuck_on_burns_propellant_and_torques_the_body():
    t_inj, t_clr = 10.0, 20.0
    res = _run(30.0, [_inject(t_inj, kind="thruster_stuck_on", thruster=1),
                      _clear(t_clr, kind="thruster_stuck_on", thruster=1)], env=NO_DISTURBANCE)
    t = _col(res, "t_s")
    m = _col(res, "propellant_kg")
    flow = THR_F / (THR_ISP * G0)   # 22.24 N / (285 s * 9.80665) = 7.958e-3 kg/s

    def at(x, ts):
        return x[np.isclose(t, ts)][0]

    assert at(m, t_inj) == 900.0    # full tanks (sdo.yaml mass.propellant_kg)
    assert at(m, t_inj) - at(m, t_clr) == pytest.approx(flow * (t_clr - t_inj), rel=1e-8)
    assert np.all(m[t >= t_clr] == at(m, t_clr))  # cleared: no more flow
    assert at(m, t_inj + 1.0) == pytest.approx(900.0 - flow * 1.0, abs=1e-9)

    # torque (r - r_cm) x F about the full-tank centre of mass (it moves by
    # 0.15 m * 0.08 kg / 900 kg = 1.3e-5 m over the window: < 1e-3 N m)
    torque_hand = np.cross(THR1_POS - CM_FULL, THR_F * THR1_DIR)   # [4.094, 23.217, -14.629] N m
    torque_tlm = _vec(res, "torque_thrusters_B", "_Nm")
    inside = (t > t_inj) & (t < t_clr)
    assert torque_tlm[inside] == pytest.approx(np.tile(torque_hand, (inside.sum(), 1)), abs=1e-3)
    # the body picks it up: with srp and gravity gradient off, dH_N/dt = R(q) tau_B,
    # trapezoid over the telemetry attitude; its error ~ T |tau| (omega dt)^2 / 12 < 1e-2 N m s
    # for |omega| < 0.08 rad/s, against |delta H| = 277 N m s
    q = _vec(res, "q_BN", axes="wxyz")
    h = _vec(res, "h_total_N", "_Nms")
    win = (t >= t_inj) & (t <= t_clr)
    tau_N = np.array([quat_rotate(qi, torque_hand) for qi in q[win]])
    dh_expected = np.trapezoid(tau_N, t[win], axis=0)
    assert at(h, t_clr) - at(h, t_inj) == pytest.approx(dh_expected, abs=1e-2)
    assert np.abs(h[t <= t_inj] - h[0]).max() < 1e-9      # nothing before...
    assert np.abs(h[t >= t_clr] - at(h, t_clr)).max() < 1e-6  # ...nor after clearing


def test_thruster_failed_off_delivers_nothing():
    """No flight-software mode fires thrusters yet, so drive the plant: 4 pulses on thruster 2."""
    sc = load_spacecraft("sdo")
    epoch = _scenario(1.0)[0].epoch_utc
    p = build.make_truth_params(sc, build.World(epoch, 10.0, srp=False, gravity_gradient=False))
    r, v = build.default_orbit("sdo", epoch).to_rv()

    def one_cycle(pulses, failed):
        ts = build.make_truth_state(sc, p, [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0] * 4, r, v, 900.0)
        if failed:
            assert fault_injection.apply(ThrusterFailedOff(thruster=2), ts) == ""
            assert ts.thruster_faults[1, FAIL_OFF] == 1.0
        act = empty_actuator_command(sc.n_wheels, len(sc.thrusters.units))
        act.thruster_pulses[1] = pulses
        plant.set_environment(ts, p, 0.0)
        plant.propagate(ts, p, act)
        return ts

    def h_N(ts):
        j_prime = massmod.inertia_B(ts.x[-1], p.dyn.mass) - p.dyn.wheels.spin_inertia_B
        return quat_rotate(ts.x[0:4], angular_momentum_B(ts.x, j_prime, p.dyn.wheels))

    healthy, failed, idle = one_cycle(4.0, False), one_cycle(4.0, True), one_cycle(0.0, False)
    # healthy: 4 * 0.05 s * F / (Isp g0) = 0.2 * 7.958e-3 = 1.5916e-3 kg, and the torque impulse
    # (r - r_cm) x F * 0.2 s (body turns ~1e-4 rad meanwhile: < 1e-3 N m s)
    assert 900.0 - healthy.x[-1] == pytest.approx(4 * THR_PULSE_S * THR_F / (THR_ISP * G0), rel=1e-8)
    assert h_N(healthy) == pytest.approx(np.cross(THR2_POS - CM_FULL, THR_F * THR2_DIR) * 4 * THR_PULSE_S,
                                         abs=1e-3)
    # failed off: no propellant, no torque, no force: the same state as no command at all
    assert failed.x[-1] == 900.0
    assert np.array_equal(failed.x, idle.x)


# -- rejection and logging ------------------------------------------------------------

def test_bad_targets_are_rejected_with_what_exists_and_change_nothing():
    base = _run(20.0)
    bad = _run(20.0, [_inject(5.0, kind="thruster_stuck_on", thruster=9),
                      _inject(6.0, kind="wheel_seized", wheel=5),
                      _inject(7.0, kind="star_tracker_dropout", tracker=3),
                      _clear(8.0, kind="thruster_failed_off", thruster=12)])
    expected = [(5.0, "thruster 9 does not exist; this spacecraft has thrusters 1-8"),   # sdo.yaml: 8 thrusters
                (6.0, "wheel 5 does not exist; this spacecraft has wheels 1-4"),         # 4 wheels
                (7.0, "tracker 3 does not exist; this spacecraft has trackers 1-2"),     # 2 star trackers
                (8.0, "thruster 12 does not exist; this spacecraft has thrusters 1-8")]
    for rec, (t_s, reason) in zip(_faults_only(bad.commands), expected, strict=True):
        assert [(s.name, s.t_s, s.reason) for s in rec.stages] == [("queued", 0.0, ""), ("rejected", t_s, reason)]
    assert not [e for e in bad.events if e.kind == "fault"]
    assert base.telemetry.keys() == bad.telemetry.keys()
    for k in base.telemetry:
        assert np.asarray(base.telemetry[k]).tobytes() == np.asarray(bad.telemetry[k]).tobytes(), k
    # IRU channels and CSS eyes are bounded by the schema (six channels, sixteen eyes)
    for fault, words in (({"kind": "iru_stuck", "channel": 7}, "less than or equal to 6"),
                         ({"kind": "css_failed", "eye": 17}, "less than or equal to 16")):
        with pytest.raises(ScenarioError, match=words):
            _scenario(10.0, [_inject(1.0, **fault)])


def test_every_injection_and_clearing_is_a_fault_event_naming_the_unit():
    faults = [({"kind": "wheel_seized", "wheel": 1}, "wheel 1"),
              ({"kind": "wheel_drag", "wheel": 2}, "wheel 2"),
              ({"kind": "iru_stuck", "channel": 3}, "channel 3"),
              ({"kind": "iru_bias", "channel": 4, "bias_deg_h": 2.0}, "channel 4"),
              ({"kind": "star_tracker_dropout", "tracker": 2}, "tracker 2"),
              ({"kind": "thruster_failed_off", "thruster": 5}, "thruster 5"),
              ({"kind": "thruster_stuck_on", "thruster": 6}, "thruster 6"),
              ({"kind": "css_failed", "eye": 7}, "eye 7")]
    commands, expected = [], []
    for i, (f, unit) in enumerate(faults):
        t_on, t_off = 1.0 + i, 20.0 + i
        commands += [_inject(t_on, **f), _clear(t_off, **f)]
        words = f["kind"].replace("_", " ")
        expected += [(t_on, f"fault injected: {words} ({unit}"), (t_off, f"fault cleared: {words} ({unit}")]
    res = _run(30.0, commands)
    events = [e for e in res.events if e.kind == "fault"]
    got = sorted((e.t_s, e.message) for e in events)
    assert len(got) == len(expected) == 16
    for (t_got, msg), (t_exp, prefix) in zip(got, sorted(expected), strict=True):
        assert t_got == t_exp and msg.startswith(prefix), (t_got, msg, prefix)
    # each event points at its command, which completed
    by_id = {rec.id: rec for rec in res.commands}
    for e in events:
        assert by_id[e.data["command"]].state == "completed"
