"""SDO IRU channels, star-tracker exclusion zones and wheel tachometers
against seed 001 "Hardware complement" and "Safehold", and the flight-software
rate selection over the IRU channels."""
import numpy as np
import pytest
from sdo_sensor_setup import ARCSEC, DT, Q_IDENTITY, SUITE, no_faults, rotated_toward

from sim.fsw.rate_selection import least_squares_rate
from sim.truth.sensors import (
    iru_units,
    star_tracker,
    star_tracker_exclusion,
    tachometer,
)
from sim.truth.sensors.star_tracker import StarTrackerParams

IRU_CFG = SUITE.iru_units.model_dump(exclude={"bias_deg_h"})
IRU_P = iru_units.make_iru_units_params(**IRU_CFG, dt=DT)
IRU_QUIET = iru_units.make_iru_units_params(**{**IRU_CFG, "arw_deg_per_sqrt_h": 0.0, "rrw_deg_h_per_sqrt_h": 0.0},
                                            dt=DT)
COUNT_RATE = 0.5 * ARCSEC / DT          # seed 001: 0.5 arcsec/bit; seed 000 "Option three": ~1.2e-5 rad/s
DEG = np.pi / 180


class IruRun:
    """Samples the six channels the way the runner does: sample at t_k, then
    the body turns until t_k+1."""

    def __init__(self, p, omega_B, bias_ch=None):
        self.p, self.theta, self.omega = p, np.zeros(3), np.asarray(omega_B, float)
        bias_ch = np.zeros(6) if bias_ch is None else bias_ch
        self.state = iru_units.iru_units_initial_state(bias_ch, self.theta, self.omega, p)
        self.fault = no_faults(6, iru_units.N_FAULT_SLOTS)

    def step(self, noise=None):
        rate, valid = np.zeros(6), np.zeros(6, dtype=np.bool_)
        noise = np.zeros(iru_units.N_NOISE) if noise is None else noise
        iru_units.iru_units_sample(self.theta, self.state, self.p, noise, self.fault, rate, valid)
        self.theta = self.theta + self.omega * DT
        return rate, valid

    def run(self, n, noises=None):
        out = [self.step() if noises is None else self.step(noises[i]) for i in range(n)]
        return np.array([o[0] for o in out]), np.array([o[1] for o in out])


def test_iru_channel_output_counts_half_arcsec_bits():
    omega = np.array([3.3e-5, -7.7e-6, 1.0e-3])
    rates, valid = IruRun(IRU_QUIET, omega).run(500)
    assert COUNT_RATE == pytest.approx(1.2e-5, rel=0.02)
    assert rates / COUNT_RATE == pytest.approx(np.round(rates / COUNT_RATE), abs=1e-9)
    # quantisation error is carried: the 100-s mean is the true channel rate within one count / 500
    assert rates.mean(axis=0) == pytest.approx(IRU_P.ch_axes_B @ omega, abs=COUNT_RATE / 500 * 1.01)
    assert valid.all()


def test_every_body_axis_is_sensed_by_two_units():
    units_per_axis = [{iru_units.UNIT_OF_CHANNEL[k] for k in range(6) if abs(IRU_P.ch_axes_B[k, axis]) > 0.5}
                      for axis in range(3)]
    assert all(len(u) == 2 for u in units_per_axis)


@pytest.mark.parametrize("rate_deg_s", [0.01, 0.1, 2.0, 5.0, 9.99])
def test_iru_rate_sign_and_size_correct_up_to_10_deg_s(rate_deg_s):
    # seed 001: "maintains the correct rate polarity up to 10 deg/sec"
    rng = np.random.default_rng(20)
    for sign in (1.0, -1.0):
        omega = sign * rate_deg_s * DEG * np.ones(3)
        rates, valid = IruRun(IRU_P, omega).run(20, rng.standard_normal((20, iru_units.N_NOISE)))
        assert valid.all()
        assert (np.sign(rates) == sign).all()
        assert rates == pytest.approx(np.full_like(rates, sign * rate_deg_s * DEG), abs=COUNT_RATE + 2e-5)


@pytest.mark.parametrize("rate_deg_s", [12.0, 50.0, -20.0])
def test_iru_saturates_above_10_deg_s_with_the_true_sign(rate_deg_s):
    # assumption (iru_units docstring): the rebalance loop holds +-10 deg/s and flags itself
    rates, valid = IruRun(IRU_QUIET, rate_deg_s * DEG * np.ones(3)).run(10)
    assert not valid.any()
    # within one count (plus float rounding of the count difference)
    assert rates == pytest.approx(np.full_like(rates, np.sign(rate_deg_s) * 10 * DEG), abs=COUNT_RATE * 1.001)


def test_iru_angle_random_walk_and_bias_walk_statistics():
    fine = {**IRU_CFG, "lsb_arcsec": 1e-6}             # counts too fine to matter here
    arw = np.radians(SUITE.iru_units.arw_deg_per_sqrt_h) / 60   # rad/sqrt(s)
    rng = np.random.default_rng(21)
    p = iru_units.make_iru_units_params(**{**fine, "rrw_deg_h_per_sqrt_h": 0.0}, dt=DT)
    rates, _ = IruRun(p, np.zeros(3)).run(6000, rng.standard_normal((6000, iru_units.N_NOISE)))
    # IEEE Std 952: angle random walk N gives a rate noise N / sqrt(dt) over samples of dt
    assert rates.std(axis=0) == pytest.approx(np.full(6, arw / np.sqrt(DT)), rel=0.04)
    rrw_deg_h = 1.0                                     # exaggerated so the walk shows in 6000 samples
    p = iru_units.make_iru_units_params(**{**fine, "arw_deg_per_sqrt_h": 0.0, "rrw_deg_h_per_sqrt_h": rrw_deg_h}, dt=DT)
    rates, _ = IruRun(p, np.zeros(3)).run(6000, rng.standard_normal((6000, iru_units.N_NOISE)))
    # rate random walk K: the bias changes by K sqrt(dt) per sample
    k = np.radians(rrw_deg_h) / 3600 / 60
    assert np.diff(rates, axis=0).std(axis=0) == pytest.approx(np.full(6, k * np.sqrt(DT)), rel=0.04)


def test_iru_channel_bias_appears_on_its_channel():
    bias = np.radians(np.array(SUITE.iru_units.bias_deg_h)) / 3600
    rates, _ = IruRun(IRU_QUIET, np.zeros(3), bias).run(2000)
    assert rates.mean(axis=0) == pytest.approx(bias, abs=COUNT_RATE / 2000 * 1.01)


@pytest.mark.parametrize("lost_unit", [0, 1, 2])
def test_least_squares_rate_from_any_two_units(lost_unit):
    rng = np.random.default_rng(22 + lost_unit)
    trusted = np.array([u != lost_unit for u in iru_units.UNIT_OF_CHANNEL])
    for omega in rng.uniform(-0.03, 0.03, (20, 3)):
        rates, valid = IruRun(IRU_P, omega).run(3, rng.standard_normal((3, iru_units.N_NOISE)))
        omega_B, ok = least_squares_rate(rates[-1], IRU_P.ch_axes_B, trusted & valid[-1])
        assert ok
        # one count plus the ARW noise (3.3e-6 rad/s 1-sigma)
        assert omega_B == pytest.approx(omega, abs=COUNT_RATE + 1.5e-5)
        oracle = np.linalg.lstsq(IRU_P.ch_axes_B[trusted], rates[-1][trusted], rcond=None)[0]
        assert omega_B == pytest.approx(oracle, abs=1e-15)


def test_least_squares_rate_with_one_unit_left_is_not_ok():
    only_unit_1 = np.array([True, True, False, False, False, False])
    omega_B, ok = least_squares_rate(np.array([1e-3, 2e-3, 0, 0, 0, 0]), IRU_P.ch_axes_B, only_unit_1)
    assert not ok
    assert omega_B == pytest.approx([1e-3, 2e-3, 0.0], abs=1e-15)   # the unseen Z component is left at zero


def iru_twin_runs(set_fault, n=40, fault_from=15):
    """The same noise through a healthy and a faulted IRU; the fault set from sample fault_from on."""
    noises = np.random.default_rng(23).standard_normal((n, iru_units.N_NOISE))
    omega = lambda k: np.array([1e-3, -2e-3, 4e-4]) * (1 + 0.05 * k)   # a changing rate: stuck must show
    healthy, faulty = IruRun(IRU_P, omega(0)), IruRun(IRU_P, omega(0))
    out = []
    for k in range(n):
        if k == fault_from:
            set_fault(faulty.fault)
        healthy.omega = faulty.omega = omega(k)
        out.append((healthy.step(noises[k])[0], faulty.step(noises[k])[0]))
    return np.array([o[0] for o in out]), np.array([o[1] for o in out])


def test_iru_stuck_channel_holds_its_last_value_and_nothing_else_changes():
    healthy, faulty = iru_twin_runs(lambda f: f.__setitem__((2, iru_units.FAULT_STUCK), 1.0))
    assert (faulty[15:, 2] == healthy[14, 2]).all()
    assert np.ptp(healthy[15:, 2]) > 10 * COUNT_RATE           # the true channel kept moving
    others = [0, 1, 3, 4, 5]
    assert np.array_equal(healthy[:, others], faulty[:, others]) and np.array_equal(healthy[:15], faulty[:15])


def test_iru_excess_bias_shifts_only_its_channel():
    bias = 2.5e-4
    healthy, faulty = iru_twin_runs(lambda f: f.__setitem__((4, iru_units.FAULT_EXCESS_BIAS), bias), n=215)
    shift = faulty[15:, 4] - healthy[15:, 4]
    assert shift.mean() == pytest.approx(bias, abs=COUNT_RATE / 200 * 1.01)   # counted, so exact on average
    assert np.abs(shift - bias).max() <= 2 * COUNT_RATE   # each of the two outputs within one count
    others = [0, 1, 2, 3, 5]
    assert np.array_equal(healthy[:, others], faulty[:, others]) and np.array_equal(healthy[:15], faulty[:15])


# ---------------------------------------------------------------- star trackers

ST_BASE = StarTrackerParams(np.array([[0.945518575599, -0.325568154457, 0.0, 0.0],   # sim/spacecraft/sdo.yaml
                                      [0.945518575599, 0.325568154457, 0.0, 0.0]]), np.full((2, 3), 5e-5))
ST_P = star_tracker_exclusion.make_star_tracker_exclusion_params(ST_BASE, **SUITE.star_tracker_exclusion.model_dump())
EARTH_RADIUS = np.arcsin(6378.137 / 42164.0)   # geosynchronous orbit: 8.7 deg
MOON_RADIUS = np.radians(0.26)
FAR = np.array([-1.0, 0.0, 0.0])               # the body's -X: 90 deg from both boresights
SUN_ON_X = np.array([1.0, 0.0, 0.0])           # nominal Sun pointing


def st_measure(sun_N=SUN_ON_X, lit=1.0, earth_N=FAR, moon_N=FAR, fault=None, noise=None):
    q, valid = np.zeros((2, 4)), np.zeros(2, dtype=np.bool_)
    noise = np.zeros(6) if noise is None else noise
    star_tracker_exclusion.star_tracker_exclusion_sample(
        Q_IDENTITY, sun_N, lit, earth_N, EARTH_RADIUS, moon_N, MOON_RADIUS, ST_P, noise,
        no_faults(2, star_tracker_exclusion.N_FAULT_SLOTS) if fault is None else fault, q, valid)
    return q, valid


def away_from_other(k, angle_deg):
    """A direction angle_deg from tracker k's boresight, on the side away from the other tracker."""
    b = ST_P.boresight_B
    return rotated_toward(b[k], 2 * b[k] - b[1 - k], np.radians(angle_deg))


def test_star_tracker_sun_exclusion_is_55_deg():
    # seed 001: "55-deg Sun exclusion zone provided by the A-STR shade"
    assert list(st_measure(sun_N=away_from_other(0, 54.9))[1]) == [False, True]
    assert list(st_measure(sun_N=away_from_other(0, 55.1))[1]) == [True, True]
    # in eclipse there is no Sun to exclude
    assert list(st_measure(sun_N=away_from_other(0, 30.0), lit=0.0)[1]) == [True, True]
    # nominal Sun pointing (+X on the Sun): both trackers see stars, "well outside" the zone
    assert st_measure()[1].all()


@pytest.mark.parametrize("body, radius, limb_deg", [("earth", EARTH_RADIUS, 25.0), ("moon", MOON_RADIUS, 10.0)])
def test_star_tracker_earth_and_moon_exclusion_add_the_angular_radius(body, radius, limb_deg):
    edge_deg = limb_deg + np.degrees(radius)   # assumptions (the sensors section of sim/spacecraft/sdo.yaml) beyond the limb
    inside = st_measure(**{f"{body}_N": away_from_other(1, edge_deg - 0.1)})[1]
    outside = st_measure(**{f"{body}_N": away_from_other(1, edge_deg + 0.1)})[1]
    assert list(inside) == [True, False] and list(outside) == [True, True]


def test_star_tracker_dropout_blanks_only_its_tracker_and_keeps_the_base_noise():
    noise = np.random.default_rng(24).standard_normal(6)
    q_base, _ = np.zeros((2, 4)), None
    star_tracker.star_tracker_sample(Q_IDENTITY, ST_BASE, noise, q_base, np.zeros(2, dtype=np.bool_))
    fault = no_faults(2, 1)
    fault[0, star_tracker_exclusion.FAULT_DROPOUT] = 1.0
    q, valid = st_measure(noise=noise, fault=fault)
    assert list(valid) == [False, True]
    assert not q[0].any() and np.array_equal(q[1], q_base[1])
    assert np.array_equal(st_measure(noise=noise)[0], q_base)   # no fault, no exclusion: the existing model


# ---------------------------------------------------------------- tachometers

TACH_P = tachometer.make_tachometer_params(**SUITE.tachometers.model_dump(), dt=DT)
PULSE_RATE = 2 * np.pi / SUITE.tachometers.pulses_per_rev / DT   # one pulse per sample, rad/s


def tach_run(speed_of_k, n, fault=None):
    fault = no_faults(4, tachometer.N_FAULT_SLOTS) if fault is None else fault
    state = tachometer.tachometer_initial_state(speed_of_k(0))
    out, valid = np.zeros((n, 4)), np.zeros((n, 4), dtype=np.bool_)
    for k in range(n):
        tachometer.tachometer_sample(speed_of_k(k), state, TACH_P, fault, out[k], valid[k])
    return out, valid


def test_tachometer_counts_pulses_and_carries_the_remainder():
    speeds = np.array([123.4, -55.5, 0.3, 600.0])      # rad/s; E-wheel 6000 rpm = 628 rad/s
    out, valid = tach_run(lambda k: speeds, 500)
    assert valid.all()
    assert out / PULSE_RATE == pytest.approx(np.round(out / PULSE_RATE), abs=1e-9)
    assert np.abs(out - speeds).max() <= PULSE_RATE
    assert out.mean(axis=0) == pytest.approx(speeds, abs=PULSE_RATE / 500 * 1.01)


def test_tachometer_reads_the_mean_speed_over_the_sample():
    # constant acceleration a: the mean speed over [t_k-1, t_k] is w(t_k) - a dt / 2
    w0, a = np.array([100.0, -20.0, 5.0, 300.0]), np.array([2.0, -1.0, 0.5, -3.0])
    out, _ = tach_run(lambda k: w0 + a * k * DT, 300)
    t = np.arange(300)[:, None] * DT
    assert np.abs(out[1:] - (w0 + a * (t[1:] - DT / 2))).max() <= PULSE_RATE


def test_tachometer_failure_blanks_only_its_wheel():
    fault = no_faults(4, 1)
    fault[3, tachometer.FAULT_FAILED] = 1.0
    speeds = np.array([10.0, 20.0, 30.0, 40.0])
    healthy, _ = tach_run(lambda k: speeds, 5)
    out, valid = tach_run(lambda k: speeds, 5, fault)
    assert not valid[:, 3].any() and valid[:, :3].all()
    assert not out[:, 3].any() and np.array_equal(out[:, :3], healthy[:, :3])
