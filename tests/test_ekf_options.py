"""The three attitude options selectable by ground command (seed 001
"Attitude determination and targeting": the EKF; with it disabled, "the
quaternion from one of the star trackers or the attitude propagated using the
IRU rate measurements"), through sim/fsw/ekf.py's attitude_cycle, checked
against scipy rotations and closed forms."""
import ekf_testbed as tb
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from sim.fsw.ekf import (
    OPTION_EKF,
    OPTION_IRU,
    OPTION_STAR_TRACKER,
    attitude_cycle,
    ekf_initial_state,
    ekf_params_from_spacecraft,
)

SC, SP = tb.sdo_sensors()
P = ekf_params_from_spacecraft(SC)
DT = P.dt
Q_BS = P.st_q_BS
ARCSEC = tb.ARCSEC


def rot(q) -> Rotation:
    return Rotation.from_quat(q, scalar_first=True)


def quat(r: Rotation) -> np.ndarray:
    return r.as_quat(scalar_first=True)


def same_rotation(q_a, q_b, atol_arcsec=1e-6):
    return (rot(q_a).inv() * rot(q_b)).magnitude() / ARCSEC < atol_arcsec


class Sensors:
    """Perfectly known inputs for one cycle: tracker quaternions with the
    seed-001 noise drawn here, DSS angles of the true attitude, all valid."""

    def __init__(self, rng, q_true):
        r = rot(q_true)
        self.st_q_SN = np.array([quat(r * rot(Q_BS[k]) * Rotation.from_rotvec(P.st_sigma_S[k] * rng.standard_normal(3)))
                                 for k in range(2)])
        self.st_valid = np.ones(2, np.bool_)
        s_B = r.inv().apply(tb.SUN_N)
        self.dss_angles = np.array([np.arctan2(s_B[1], s_B[0]), np.arctan2(s_B[2], s_B[0])])
        self.dss_valid = np.ones(1, np.bool_)

    def args(self):
        return self.st_q_SN, self.st_valid, tb.SUN_N, self.dss_angles, self.dss_valid


def test_fly_a_star_tracker():
    """EKF off, tracker 2 selected: each cycle the estimate is that tracker's
    measurement carried to the body, q_SN (x) q_BS^-1 (scipy), and its
    attitude covariance that tracker's noise in body axes; with the selected
    tracker invalid the estimate propagates with the IRU (bias held)."""
    rng = np.random.default_rng(21)
    q_true = quat(Rotation.random(random_state=rng))
    bias = np.array([0.3, -0.2, 0.1]) * tb.DEG_H
    s = ekf_initial_state(q_true, 2, 100 * ARCSEC, 0.1 * tb.DEG_H, bias_B=bias)
    rate = np.radians([0.05, -0.02, 0.01])
    for _ in range(20):
        q_true = quat(rot(q_true) * Rotation.from_rotvec(rate * DT))
        sens = Sensors(rng, q_true)
        n = attitude_cycle(OPTION_STAR_TRACKER, 1, s, P, rate + bias, *sens.args())
        assert n == 1
        assert same_rotation(s.q_est_BN, quat(rot(sens.st_q_SN[1]) * rot(Q_BS[1]).inv()))
    dcm_BS = rot(Q_BS[1]).as_matrix()
    # rtol 1e-9: the spacecraft file gives the mounting to 12 digits, scipy renormalises it
    np.testing.assert_allclose(s.P[:3, :3], dcm_BS @ np.diag(P.st_sigma_S[1] ** 2) @ dcm_BS.T, rtol=1e-9)
    np.testing.assert_array_equal(s.bias_B, bias)                   # the filter is off: bias held
    assert not s.st_updated.any() and not s.dss_updated[0]
    # the selected tracker drops out (the other one is still valid): IRU propagation
    q_before = s.q_est_BN.copy()
    sens = Sensors(rng, q_true)
    sens.st_valid[1] = False
    assert attitude_cycle(OPTION_STAR_TRACKER, 1, s, P, rate + bias, *sens.args()) == 0
    assert same_rotation(s.q_est_BN, quat(rot(q_before) * Rotation.from_rotvec(rate * DT)))


def test_iru_propagation_ignores_the_sensors():
    """EKF off, IRU option: with a constant measured rate the estimate after
    N cycles is q0 (x) exp(N (omega_meas - bias_est) dt) exactly (scipy),
    though trackers and DSS are valid every cycle."""
    rng = np.random.default_rng(22)
    q0 = quat(Rotation.random(random_state=rng))
    bias = np.array([1.0, -2.0, 0.5]) * tb.DEG_H
    s = ekf_initial_state(q0, 2, 10 * ARCSEC, 0.1 * tb.DEG_H, bias_B=bias)
    omega_meas = np.radians([0.5, -0.3, 0.2])
    N = 500
    for _ in range(N):
        sens = Sensors(rng, q0)           # valid, but must not be used
        assert attitude_cycle(OPTION_IRU, 0, s, P, omega_meas, *sens.args()) == 0
    expected = rot(q0) * Rotation.from_rotvec((omega_meas - bias) * N * DT)
    assert same_rotation(s.q_est_BN, quat(expected), atol_arcsec=1e-6)
    np.testing.assert_array_equal(s.bias_B, bias)
    assert not s.st_updated.any() and not s.dss_updated[0]


def test_iru_propagation_covariance_grows_as_the_closed_form():
    """At zero rate the error obeys d(dtheta)/dt = -dbias - eta_v,
    d(dbias)/dt = eta_u, so per axis var(dtheta) = s0^2 + sb^2 t^2 + sv^2 t
    + su^2 t^3 / 3 and cov(dtheta, dbias) = -(sb^2 t + su^2 t^2 / 2)
    (random walk and integrated random walk). After 600 s with SDO's gyro:
    10 arcsec -> 13.8 arcsec 1-sigma."""
    s0, sb = 10 * ARCSEC, 0.01 * tb.DEG_H
    s = ekf_initial_state([1.0, 0.0, 0.0, 0.0], 2, s0, sb)
    rng = np.random.default_rng(23)
    sens = Sensors(rng, np.array([1.0, 0.0, 0.0, 0.0]))
    N = 3000
    for _ in range(N):
        attitude_cycle(OPTION_IRU, 0, s, P, np.zeros(3), *sens.args())
    t = N * DT
    sv, su = P.sigma_v, P.sigma_u
    var = s0 ** 2 + sb ** 2 * t ** 2 + sv ** 2 * t + su ** 2 * t ** 3 / 3.0
    cov = -(sb ** 2 * t + su ** 2 * t ** 2 / 2.0)
    np.testing.assert_allclose(s.P_diag[:3], var, rtol=1e-9)
    np.testing.assert_allclose(np.diag(s.P[:3, 3:]), cov, rtol=1e-9)
    np.testing.assert_allclose(s.P_diag[3:], sb ** 2 + su ** 2 * t, rtol=1e-9)
    assert np.sqrt(var) / ARCSEC == pytest.approx(13.8, abs=0.1)


def test_ekf_uses_every_valid_enabled_sensor():
    """EKF on: both trackers and the DSS update the estimate and leave their
    innovations for telemetry; a tracker deselected by ground (st_use) or
    invalid, or the DSS disabled, is skipped."""
    rng = np.random.default_rng(24)
    q_true = tb.sun_pointing_q(tb.SUN_N)            # the Sun on the DSS boresight
    s = ekf_initial_state(quat(rot(q_true) * Rotation.from_rotvec([0.0, 50 * ARCSEC, 0.0])), 2, 100 * ARCSEC,
                          0.1 * tb.DEG_H)
    sens = Sensors(rng, q_true)
    assert attitude_cycle(OPTION_EKF, 0, s, P, np.zeros(3), *sens.args()) == 3
    assert s.st_updated.all() and s.dss_updated[0]
    assert np.all(s.st_innov_var > 0.0) and np.all(s.dss_innov_var > 0.0)
    # the 50 arcsec pitch error shows in the DSS / tracker innovations and is mostly removed
    assert (rot(s.q_est_BN).inv() * rot(q_true)).magnitude() / ARCSEC < 15.0
    s.st_use[0] = False
    assert attitude_cycle(OPTION_EKF, 0, s, P, np.zeros(3), *Sensors(rng, q_true).args()) == 2
    assert not s.st_updated[0] and s.st_updated[1]
    s.dss_use[0] = False
    sens = Sensors(rng, q_true)
    sens.st_valid[1] = False
    assert attitude_cycle(OPTION_EKF, 0, s, P, np.zeros(3), *sens.args()) == 0
    assert not s.st_updated.any() and not s.dss_updated[0]


def test_switching_options_in_flight():
    """SDO sensors (truth models) in Sun pointing, options by ground command:
    EKF 0-300 s, IRU 300-600 s, star tracker 1 600-900 s, EKF 900-1200 s.
    The IRU leg starts from the EKF's few-arcsec estimate and drifts only by
    the gyro's residual errors, within the filter's own growing 3-sigma; the
    tracker leg has the tracker's own error, RMS magnitude sqrt(2 10^2 + 30^2)
    = 33.2 arcsec (seed 001: 30 and 90 arcsec 3-sigma; as test_estimation.py);
    the filter, switched back on, is at its few-arcsec level again in 10 s."""
    T = 6000
    t = np.arange(1, T + 1) * DT
    options = np.full(T, OPTION_EKF)
    options[(t > 300) & (t <= 600)] = OPTION_IRU
    options[(t > 600) & (t <= 900)] = OPTION_STAR_TRACKER
    q0 = tb.sun_pointing_q(tb.SUN_N)
    truth = tb.Truth(q0, np.zeros(3), np.radians([0.002, 0.002, 0.002]), 300.0, tb.SUN_N, tb.GYRO_IRU_UNITS,
                     np.zeros(3), 0.0, 0.0)
    s = ekf_initial_state(q0, 2, 60 * ARCSEC, 0.1 * tb.DEG_H)
    out = tb.make_record(T, 2)
    rng = np.random.default_rng(25)
    tb.run(truth, s, P, options, 0, np.ones((T, 2), np.bool_), SP.st.st, SP.dss, SP.iru, tb.iru_units_state(SC, SP),
           *tb.draw_noise(rng, T, 2, tb.GYRO_IRU_UNITS), out)
    err = np.linalg.norm(out.err_B, axis=1) / ARCSEC
    ekf1, iru = (t > 100) & (t <= 300), (t > 300) & (t <= 600)
    tracker, ekf2 = (t > 600) & (t <= 900), t > 910
    assert err[ekf1].max() < 5.0
    roll_sigma = np.sqrt(out.P_diag[iru, 0]) / ARCSEC
    assert roll_sigma[-1] > 3.0 * roll_sigma[0]                   # the IRU leg's covariance grows
    assert np.all(np.abs(out.err_B[iru]) < 3.0 * np.sqrt(out.P_diag[iru, :3]))
    assert np.sqrt(np.mean(err[tracker] ** 2)) == pytest.approx(33.2, rel=0.1)
    assert err[ekf2].max() < 5.0
    assert np.all(out.n_used[iru] == 0) and np.all(out.n_used[tracker] == 1) and np.all(out.n_used[ekf2] == 3)
    print(f"max error: EKF {err[ekf1].max():.1f}, IRU leg {err[iru].max():.1f}, tracker RMS "
          f"{np.sqrt(np.mean(err[tracker] ** 2)):.1f}, EKF again {err[ekf2].max():.1f} arcsec")
