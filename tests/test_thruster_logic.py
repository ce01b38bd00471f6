"""Thruster command logic (sim/fsw/thruster_logic.py) on SDO's thruster suite
(sim/spacecraft/sdo.yaml `thrusters:`; seed 001 "Hardware complement", "DeltaV").

Oracles outside the code: a hand-written cross product, scipy.optimize.linprog
for the least-propellant (on-pulse) and most-thrust (off-pulse) duties and for
the torque authority along a direction, and the arithmetic of error feedback."""
import numpy as np
import pytest
from scipy.optimize import linprog

from sim.fsw.thruster_logic import (
    delivered_force_B,
    delivered_torque_B,
    make_thruster_logic_params,
    propellant_used_kg,
    set_duty,
    thruster_pulses,
)
from sim.spacecraft import load_spacecraft

LBF_N = 4.4482216152605  # NIST SP 811, Appendix B.8
G0_M_S2 = 9.80665        # standard gravity (3rd CGPM, 1901)

SC = load_spacecraft("sdo")
UNITS = SC.thrusters.units
CM_B_M = np.array(SC.mass.cm_full_B_m)
CYCLE_S = SC.timing.control_dt_s          # seed 001 "DeltaV": 200-msec control cycle
PULSE_S = SC.thrusters.pulse_s            # seed 001 "DeltaV": 50-msec pulses
MAX_PULSES = SC.thrusters.max_pulses_per_cycle  # seed 001 "DeltaV": up to four per cycle


def _params(units=UNITS):
    return make_thruster_logic_params(
        [u.position_B_m for u in units], [u.direction_B for u in units],
        [u.thrust_lbf * LBF_N for u in units], [u.isp_s for u in units], [u.set for u in units],
        CM_B_M, MAX_PULSES, PULSE_S, CYCLE_S)


P = _params()
RNG = np.random.default_rng(7)


def _m(set_index):
    """(3, 4) torque matrix of a set, N m per unit duty."""
    return P.torque_B[P.sets[set_index]].T


def _duty(torque_B, off_pulse, set_index=0):
    d = np.empty(4)
    k = set_duty(np.asarray(torque_B, float), off_pulse, P.pinv[set_index], P.null[set_index], d)
    return d, k


def _linprog_sum(torque_B, sign, set_index=0):
    """Optimal sum of duties with M d = T, 0 <= d <= 1: sign +1 minimises, -1 maximises."""
    res = linprog(sign * np.ones(4), A_eq=_m(set_index), b_eq=torque_B, bounds=[(0.0, 1.0)] * 4)
    assert res.status == 0
    return sign * res.fun


def _feasible_torques(n):
    """Torques inside the authority by construction: M d for random duties in [0, 1]."""
    return [_m(0) @ RNG.uniform(0.0, 1.0, 4) for _ in range(n)]


def test_geometry_matches_hand_cross_product():
    """Thruster 1 (sdo.yaml: primary at [-1.6, 1, 1], cant -10 deg about Z), 5 lbf."""
    u = UNITS[0]
    f = u.thrust_lbf * LBF_N * np.array(u.direction_B)
    r = np.array(u.position_B_m) - CM_B_M
    torque = [r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]]
    assert np.allclose(P.torque_B[0], torque, atol=1e-9)           # N m
    assert np.allclose(P.force_B[0], f, atol=1e-12)                # N
    assert P.flow_kg_s[0] == pytest.approx(5.0 * LBF_N / (285.0 * G0_M_S2), rel=1e-12)
    assert P.sets.tolist() == [[0, 1, 2, 3], [4, 5, 6, 7]]         # seed 001: four primary, four redundant


def test_on_pulse_reproduces_torque_with_least_propellant():
    for t in _feasible_torques(50):
        d, k = _duty(t, off_pulse=False)
        assert k == 1.0
        assert np.all((d >= 0.0) & (d <= 1.0))
        assert np.allclose(_m(0) @ d, t, atol=1e-9)                 # N m
        assert d.sum() == pytest.approx(_linprog_sum(t, +1), abs=1e-6)


def test_off_pulse_reproduces_torque_with_most_thrust():
    for t in _feasible_torques(50) + [np.zeros(3)]:
        d, k = _duty(t, off_pulse=True)
        assert k == 1.0
        assert np.all((d >= 0.0) & (d <= 1.0))
        assert np.allclose(_m(0) @ d, t, atol=1e-9)                 # N m
        assert d.sum() == pytest.approx(_linprog_sum(t, -1), abs=1e-6)


@pytest.mark.parametrize("off_pulse", [False, True])
def test_torque_beyond_authority_keeps_its_direction(off_pulse):
    """Seed 001 "Attitude control modes": scaled so the direction stays constant;
    the kept magnitude is the authority along that direction (linprog: max s with
    M d = s u, 0 <= d <= 1)."""
    for _ in range(20):
        u = RNG.normal(size=3)
        u /= np.linalg.norm(u)
        d, k = _duty(1000.0 * u, off_pulse)                          # 1000 N m: far beyond authority
        delivered = _m(0) @ d
        angle = np.arctan2(np.linalg.norm(np.cross(delivered, u)), delivered @ u)  # well conditioned near 0
        assert angle < 1e-9                                          # rad
        assert d.max() == pytest.approx(1.0, abs=1e-12)
        res = linprog([0, 0, 0, 0, -1.0], A_eq=np.column_stack([_m(0), -u]), b_eq=np.zeros(3),
                      bounds=[(0.0, 1.0)] * 4 + [(0.0, None)])
        assert np.linalg.norm(delivered) == pytest.approx(-res.fun, abs=1e-6)   # N m
        assert 1000.0 * k == pytest.approx(-res.fun, abs=1e-6)


@pytest.mark.parametrize("off_pulse", [False, True])
def test_pulse_carry_follows_demand_over_cycles(off_pulse):
    """Error feedback: after N cycles each thruster's pulse total is within half a
    pulse of N * duty * max_pulses, so the mean torque error is at most
    0.5 * sum_i |one pulse's torque_i| / N."""
    n_cycles = 100
    demand = _m(0) @ np.array([0.37, 0.11, 0.52, 0.29])            # N m, inside the authority
    d, _ = _duty(demand, off_pulse)
    carry, pulses = np.zeros(8), np.zeros(8)
    total, torque_sum = np.zeros(8), np.zeros(3)
    for _ in range(n_cycles):
        thruster_pulses(demand, off_pulse, 0, P, carry, pulses)
        assert np.all(pulses == np.round(pulses)) and pulses.min() >= 0 and pulses.max() <= MAX_PULSES
        total += pulses
        torque_sum += delivered_torque_B(pulses, P)
    assert np.all(np.abs(total[:4] - n_cycles * d * MAX_PULSES) <= 0.5 + 1e-9)
    pulse_torque = np.linalg.norm(P.torque_B[:4], axis=1) * PULSE_S / CYCLE_S   # N m, one pulse averaged
    assert np.linalg.norm(torque_sum / n_cycles - demand) <= 0.5 * pulse_torque.sum() / n_cycles


@pytest.mark.parametrize("off_pulse", [False, True])
def test_redundant_set_fires_only_thrusters_5_to_8(off_pulse):
    carry, pulses, total = np.full(8, 0.3), np.zeros(8), np.zeros(8)
    for t in _feasible_torques(10):
        thruster_pulses(t * 0.9, off_pulse, 1, P, carry, pulses)
        assert np.all(pulses[:4] == 0.0) and np.all(carry[:4] == 0.0)
        total += pulses
    assert np.all(total[4:] > 0.0)


def test_status_of_a_full_cycle_on_the_primary_set():
    """Four pulses on each primary thruster: the whole 200 ms cycle on (seed 001)."""
    pulses = np.array([4.0, 4.0, 4.0, 4.0, 0.0, 0.0, 0.0, 0.0])
    thrust_N = 5.0 * LBF_N
    force = delivered_force_B(pulses, P)
    assert force == pytest.approx([4 * thrust_N * np.cos(np.radians(10.0)), 0.0, 0.0], abs=1e-9)   # N
    assert np.allclose(delivered_torque_B(pulses, P), P.torque_B[:4].sum(axis=0), atol=1e-12)    # N m
    assert propellant_used_kg(pulses, P) == pytest.approx(4 * 0.2 * thrust_N / (285.0 * G0_M_S2), rel=1e-12)


def test_unbalanced_set_is_refused():
    """A primary thruster turned to fire forward: no positive null vector, so
    on-pulsing could not produce every torque direction."""
    units = [u.model_copy() for u in UNITS]
    units[0] = units[0].model_copy(update={"direction_B": tuple(-np.array(units[0].direction_B))})
    with pytest.raises(ValueError, match="'primary'.*one sign"):
        _params(units)
    with pytest.raises(ValueError, match="needs 4"):
        _params(UNITS[:7])
