"""Null-space wheel-speed bias (seed 001 "Attitude control modes": the RWA
torques pass "through logic that distributes the RWA momentum to minimize
passing through zero wheel speed"). Checked against physics (no body torque,
body-frame wheel momentum conserved), the pyramid geometry by hand,
scipy.optimize.linprog as the max-min oracle, and the sdo.yaml drag model."""
import itertools

import numpy as np
import pytest
from scipy.optimize import linprog

from sim.fsw.distribution import distribution_matrix
from sim.fsw.wheel_bias import (GAIN_PER_S, H_MIN_NMS, H_TARGET_NMS, LIMIT_NM, TIE_NMS, WheelBiasParams,
                                add_wheel_bias, make_wheel_bias_params, null_level, null_shift, null_vector,
                                wheel_bias_cycle, wheel_bias_torque)
from sim.spacecraft import load_spacecraft

SC = load_spacecraft("sdo", {})
AXES = np.array(SC.wheels.axes_B)
G = AXES.T                                   # 3 x 4, spin axes as columns
J = SC.wheels.spin_inertia_kgm2
H_CAP = SC.wheels.h_max_Nms                  # seed 001: 70 N m s per RWA
LIMIT_SW = SC.wheels.torque_limit_sw_Nm      # seed 001: 0.2 N m software limit
DT = SC.timing.control_dt_s                  # seed 001: 200 ms control cycle
P = make_wheel_bias_params(AXES, J, H_CAP)
N = P.null_B
SEED000_H = np.array([-36.95, 0.0, 36.95, 0.0])  # seed 000: wheels with system momentum [0, 64, 0] N m s
ALL_VALID = np.ones(4, bool)


def _bias(h, valid=ALL_VALID, p=P):
    u = np.zeros(len(h))
    c = wheel_bias_torque(np.asarray(h, float), valid, p.null_B, p.gain_per_s, p.limit_Nm, p.h_target_Nms,
                          p.h_cap_Nms, u)
    return u, c


def test_null_vector_of_the_sdo_pyramid():
    """Seed 001 pyramid: wheels 1, 3 and 2, 4 are opposite about X, so
    a1 + a3 = a2 + a4 and [1, -1, 1, -1] / 2 spins no body momentum."""
    assert N == pytest.approx(np.array([1.0, -1.0, 1.0, -1.0]) / 2, abs=1e-12)
    assert np.linalg.norm(G @ N) < 1e-12
    assert np.linalg.norm(N) == pytest.approx(1.0, abs=1e-15)
    assert isinstance(P, WheelBiasParams)
    assert (P.gain_per_s, P.limit_Nm, P.h_min_Nms, P.h_target_Nms) == (GAIN_PER_S, LIMIT_NM, H_MIN_NMS,
                                                                       H_TARGET_NMS)


def test_bias_torque_puts_no_torque_on_the_body():
    """Conservation: body torque -G u is zero for any wheel state."""
    rng = np.random.default_rng(7)
    for _ in range(200):
        h = rng.uniform(-70.0, 70.0, 4) * rng.choice([1.0, 0.05], 4)
        u, _ = _bias(h)
        assert np.linalg.norm(G @ u) < 1e-12          # N m
        assert np.max(np.abs(u)) <= LIMIT_NM + 1e-15  # N m, budget per wheel


def test_seed000_wheels_at_zero_are_shifted_to_the_target():
    """Seed 000's two wheels at zero: the smallest shift that puts every wheel
    at h_target is c = 2 h_target (|n_i| = 1/2), positive on the tie; the
    command saturates at the budget, rotors gaining momentum along +n."""
    c = null_shift(SEED000_H, N, H_TARGET_NMS, H_CAP)
    assert c == pytest.approx(2 * H_TARGET_NMS, abs=1e-12)
    assert np.min(np.abs(SEED000_H + c * N)) == pytest.approx(H_TARGET_NMS, abs=1e-12)
    u, c2 = _bias(SEED000_H)
    assert c2 == c
    assert u == pytest.approx(LIMIT_NM * np.array([1.0, -1.0, 1.0, -1.0]), abs=1e-15)


def _lp_oracle(h, n, level, cap):
    """linprog over every sign pattern s: max t s.t. s_i (h_i + c n_i) >= t,
    t <= level, |h_i + c n_i| <= max(cap, |h_i|); then min |c| reaching t*."""
    caps = np.maximum(cap, np.abs(h))
    best_t = -np.inf
    for s in itertools.product([-1.0, 1.0], repeat=len(h)):
        s = np.array(s)
        # variables (c, t): -s_i n_i c + t <= s_i h_i ; +-n_i c <= caps -+ h_i
        a = np.vstack([np.column_stack([-s * n, np.ones(4)]), np.column_stack([n, np.zeros(4)]),
                       np.column_stack([-n, np.zeros(4)])])
        b = np.concatenate([s * h, caps - h, caps + h])
        r = linprog([0.0, -1.0], A_ub=a, b_ub=b, bounds=[(None, None), (None, level)])
        if r.status == 0:
            best_t = max(best_t, r.x[1])
    c_min = np.inf
    for s in itertools.product([-1.0, 1.0], repeat=len(h)):
        s = np.array(s)
        # variables (cp, cm) >= 0, c = cp - cm: min cp + cm s.t. s_i (h_i + c n_i) >= t* and the caps
        a = np.vstack([np.column_stack([-s * n, s * n]), np.column_stack([n, -n]), np.column_stack([-n, n])])
        b = np.concatenate([s * h - (best_t - 1e-9), caps - h, caps + h])
        r = linprog([1.0, 1.0], A_ub=a, b_ub=b, bounds=[(0, None), (0, None)])
        if r.status == 0:
            c_min = min(c_min, r.fun)
    return best_t, c_min


@pytest.mark.parametrize("level", [H_TARGET_NMS, 60.0])
def test_shift_against_linprog(level):
    """The chosen shift reaches the best floor over all sign patterns (within
    the hysteresis TIE_NMS) with no larger a shift than the oracle's; level 60
    is the plain max-min |h_i| inside the 70 N m s capacity."""
    rng = np.random.default_rng(3)
    cases = [SEED000_H, np.array([-36.95, 0.3, 36.95, -0.2]), np.array([50.0, 1.0, -20.0, 65.0])]
    for _ in range(8):
        h = rng.uniform(-60.0, 60.0, 4)
        h[rng.integers(4)] = rng.uniform(-1.0, 1.0)   # one wheel near zero
        cases.append(h)
    for h in cases:
        t_star, c_min = _lp_oracle(h, N, level, H_CAP)
        c = null_shift(h, N, level, H_CAP)
        g = null_level(h, N, c, level)
        assert t_star - TIE_NMS - 1e-9 <= g <= t_star + 1e-9      # N m s
        assert abs(c) <= c_min + 1e-7                              # N m s
        assert np.max(np.abs(h + c * N)) <= max(H_CAP, np.max(np.abs(h))) + 1e-9
        assert np.min(np.abs(h + c * N)) >= min(np.min(np.abs(h)), level)  # the floor never drops


def _run(h0, minutes, bias=True, drag=True):
    """Closed loop at the 0.2 s cycle: ideal attitude hold (the minimum-norm
    distribution u = D T cancels the wheel-drag reaction on the body) plus the
    bias; rotors gain momentum at u + drag. Drag: sdo.yaml viscous + Coulomb."""
    b, cf = SC.wheels.viscous_Nm_per_rad_s, SC.wheels.coulomb_Nm
    dist = distribution_matrix(AXES)
    h = np.array(h0, float)
    hist, u_hist = [], []
    for _ in range(round(minutes * 60 / DT)):
        w = h / J
        d = -(b * w + cf * np.sign(w)) if drag else np.zeros(4)
        u = dist @ (G @ d)                     # -G u = G d: the body feels no net torque
        assert np.max(np.abs(u)) <= LIMIT_SW   # within the limit: distribute would not scale it
        u_att = u.copy()
        if bias:
            wheel_bias_cycle(w, ALL_VALID, P, LIMIT_SW, u, np.empty(4))
        h += (u + d) * DT
        hist.append(h.copy())
        u_hist.append((u_att, u))
    return np.array(hist), u_hist


def test_loop_drift_free_reaches_the_floor_and_conserves_momentum():
    h, uh = _run(SEED000_H, minutes=10, drag=False)
    hb0 = G @ SEED000_H
    assert np.max(np.linalg.norm(h @ G.T - hb0, axis=1)) < 1e-9                     # N m s
    # saturated at the budget until wheels 2, 4 reach the floor: 5 N m s / 0.02 N m = 250 s
    t_floor = (np.argmax(np.min(np.abs(h), axis=1) >= H_MIN_NMS) + 1) * DT
    assert t_floor == pytest.approx(H_MIN_NMS / LIMIT_NM, abs=DT + 1e-9)
    assert np.min(np.abs(h[-1])) >= H_TARGET_NMS - TIE_NMS - 1e-9
    assert max(np.max(np.abs(u - ua)) for ua, u in uh) <= LIMIT_NM + 1e-15


@pytest.mark.parametrize("h0", [SEED000_H + np.array([0.0, 2.0, 0.0, 2.0]), SEED000_H])
def test_loop_holds_the_floor_against_sdo_drag(h0):
    """Wheels 2, 4 start at 2 (or 0) N m s; drag pulls the null component
    toward the least-drag pattern (seed 000's, two wheels at zero); the bias
    must bring them to h_min and hold them there."""
    h, uh = _run(h0, minutes=15)
    hb0 = G @ h0
    assert np.max(np.linalg.norm(h @ G.T - hb0, axis=1)) < 1e-9                     # N m s
    m = np.min(np.abs(h), axis=1)
    reached = np.argmax(m >= H_MIN_NMS)
    assert reached > 0 and np.all(m[reached:] >= H_MIN_NMS)
    assert np.all(np.sign(h[-1])[h0 != 0] == np.sign(h0)[h0 != 0])   # the short way: no wheel crossed zero
    assert max(np.max(np.abs(u)) for _, u in uh) <= LIMIT_SW + 1e-15
    assert max(np.max(np.abs(u - ua)) for ua, u in uh) <= LIMIT_NM + 1e-15
    # without the bias the same drag leaves wheels 2 and 4 near zero
    h_off, _ = _run(h0, minutes=15, bias=False)
    assert np.min(np.abs(h_off[-1])) < 1.0                # N m s: left alone, drag parks them near zero


def test_three_wheels_do_nothing():
    axes3 = AXES[:3]
    assert np.all(null_vector(axes3) == 0.0)
    p3 = make_wheel_bias_params(axes3, J, H_CAP)
    u, c = _bias(SEED000_H[:3], np.ones(3, bool), p3)
    assert c == 0.0 and np.all(u == 0.0)
    # a failed wheel taken out of use in the four-wheel array: same
    p4 = make_wheel_bias_params(AXES, J, H_CAP, in_use=[True, True, False, True])
    assert np.all(p4.null_B == 0.0)
    u, c = _bias(SEED000_H, ALL_VALID, p4)
    assert c == 0.0 and np.all(u == 0.0)
    with pytest.raises(ValueError):
        null_vector(np.vstack([AXES, [1.0, 0.0, 0.0]]))   # two-dimensional null space


def test_invalid_tach_gives_zero_and_cycle_leaves_command_alone():
    for k in range(4):
        valid = ALL_VALID.copy()
        valid[k] = False
        u, c = _bias(SEED000_H, valid)
        assert c == 0.0 and np.all(u == 0.0)
        u_cmd = np.array([0.1, -0.05, 0.02, 0.0])
        u_out = u_cmd.copy()
        wheel_bias_cycle(SEED000_H / J, valid, P, LIMIT_SW, u_out, np.empty(4))
        assert np.all(u_out == u_cmd)


def test_wheels_above_target_get_no_bias():
    u, c = _bias(np.array([-30.0, 10.0, 25.0, -8.0]))
    assert c == 0.0 and np.all(u == 0.0)


def test_attitude_torque_has_priority_within_the_software_limit():
    bias = LIMIT_NM * np.array([1.0, -1.0, 1.0, -1.0])
    u_att = np.array([0.195, 0.0, -0.1, 0.05])
    out = np.zeros(4)
    s = add_wheel_bias(u_att, bias, LIMIT_SW, out)
    assert s == pytest.approx(0.005 / 0.02, abs=1e-12)             # wheel 1 headroom 0.005 N m
    assert np.max(np.abs(out)) == pytest.approx(LIMIT_SW, abs=1e-15)
    assert G @ out == pytest.approx(G @ u_att, abs=1e-15)           # body torque untouched
    s = add_wheel_bias(u_att, -bias, LIMIT_SW, out)                 # bias away from the limit: all of it
    assert s == 1.0 and out == pytest.approx(u_att - bias, abs=1e-15)
    u_att = np.array([0.2, -0.2, 0.0, 0.0])                         # no headroom: no bias
    s = add_wheel_bias(u_att, bias, LIMIT_SW, out)
    assert s == 0.0 and np.all(out == u_att)
