"""Knowledge accuracy of the attitude EKF (sim/fsw/ekf.py) with SDO's sensors
as the truth models produce them (tests/ekf_testbed.py with GYRO_IRU_UNITS:
six quantised IRU channels through least-squares rate selection, the two star
trackers, the DSS), against seed 001's strictest knowledge requirement:

  seed 001 "Science requirements" (EVE): "[35, 70, 70] arcsec, 3 sigma, of
  knowledge with respect to the center of the solar disk", in effect "primarily
  during Inertial mode calibrations".

Measured per body axis X (roll about the Sun line), Y, Z as 3 x RMS of the
true estimation error. The truth has no sensor misalignment and the filter
gets the exact Sun direction, so this is the filter's share of the budget.
Sun pointing, the body wandering by 0.002 deg/s (300 s sinusoid) on every axis;
the filter starts 0.5 deg off with 0.5 deg and 0.1 deg/h 1-sigma.
"""
import ekf_testbed as tb
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from sim.fsw.ekf import OPTION_EKF, ekf_initial_state, ekf_params_from_spacecraft

REQUIREMENT_3SIGMA_ARCSEC = np.array([35.0, 70.0, 70.0])   # seed 001, above
T = 9000                        # 1800 s
DT = 0.2
T_LOSS_S = 600.0                # trackers drop out here in the loss cases
t_s = np.arange(1, T + 1) * DT


def _run(st_on, seed=5):
    sc, sp = tb.sdo_sensors()
    p = ekf_params_from_spacecraft(sc)
    q0 = tb.sun_pointing_q(tb.SUN_N)
    rng = np.random.default_rng(seed)
    truth = tb.Truth(q0, np.zeros(3), np.radians([0.002, 0.002, 0.002]), 300.0, tb.SUN_N, tb.GYRO_IRU_UNITS,
                     np.zeros(3), 0.0, 0.0)
    err0 = np.radians(0.5) * np.array([0.6, 0.0, -0.8])
    q_est0 = (Rotation.from_quat(q0, scalar_first=True) * Rotation.from_rotvec(err0)).as_quat(scalar_first=True)
    s = ekf_initial_state(q_est0, 2, np.radians(0.5), 0.1 * tb.DEG_H)
    out = tb.make_record(T, 2)
    tb.run(truth, s, p, np.full(T, OPTION_EKF), 0, st_on, sp.st.st, sp.dss, sp.iru, tb.iru_units_state(sc, sp),
           *tb.draw_noise(rng, T, 2, tb.GYRO_IRU_UNITS), out)
    return out


def _three_sigma(out, t0, t1):
    """(measured 3 x RMS error, filter's 3-sigma) per axis over (t0, t1], arcsec."""
    m = (t_s > t0) & (t_s <= t1)
    measured = 3.0 * np.sqrt(np.mean(out.err_B[m] ** 2, axis=0)) / tb.ARCSEC
    predicted = 3.0 * np.sqrt(np.mean(out.P_diag[m, :3], axis=0)) / tb.ARCSEC
    return measured, predicted


@pytest.fixture(scope="module")
def nominal():
    return _run(np.ones((T, 2), np.bool_))


def test_acquires_from_half_a_degree(nominal):
    """From 0.5 deg (1800 arcsec) the first tracker update lands the estimate;
    after 10 s every axis is within 10 arcsec (measured ~2.5 arcsec after 1 s)."""
    late = t_s >= 10.0
    assert np.abs(nominal.err_B[late]).max() / tb.ARCSEC < 10.0


def test_knowledge_with_two_trackers_dss_and_iru(nominal):
    """Steady state (300 to 1800 s), both trackers + DSS + IRU: measured
    3-sigma [2.6, 2.0, 2.0] arcsec (X, Y, Z) against [35, 70, 70]; the
    filter's own 3-sigma [2.9, 2.3, 2.3] arcsec covers it (its gyro noise is
    one channel's, twice the variance of the two-channel average it gets)."""
    measured, predicted = _three_sigma(nominal, 300.0, 1800.0)
    print(f"two trackers + DSS: measured 3-sigma {np.round(measured, 2)} arcsec, filter {np.round(predicted, 2)}")
    assert np.all(measured < REQUIREMENT_3SIGMA_ARCSEC)
    assert np.all(measured < 1.2 * predicted)
    # the drift-bias estimate is within the filter's 3-sigma of the IRU's true body bias
    assert np.all(np.abs(nominal.bias_err[-1]) < 3.0 * np.sqrt(nominal.P_diag[-1, 3:]))
    assert np.all(nominal.n_used == 3)


@pytest.mark.parametrize("lost", [0, 1])
def test_a_tracker_lost_the_filter_continues_on_the_rest(nominal, lost):
    """Tracker `lost` stops at 600 s; the filter goes on with the other
    tracker, the DSS and the IRU. The roll error, which both trackers saw
    transverse to their boresights, grows (measured 3-sigma 2.6 -> 3.0 to 3.3
    arcsec), Y and Z stay on the DSS (~2 arcsec); the covariance settles at
    a new bounded level."""
    st_on = np.ones((T, 2), np.bool_)
    st_on[int(T_LOSS_S / DT):, lost] = False
    out = _run(st_on)
    measured, predicted = _three_sigma(out, T_LOSS_S, 1800.0)
    before, before_predicted = _three_sigma(nominal, T_LOSS_S, 1800.0)
    print(f"tracker {lost + 1} lost: measured 3-sigma {np.round(measured, 2)} arcsec "
          f"(nominal {np.round(before, 2)}), filter {np.round(predicted, 2)} (nominal {np.round(before_predicted, 2)})")
    assert np.all(measured < REQUIREMENT_3SIGMA_ARCSEC)
    assert np.all(measured < 1.2 * predicted)
    assert predicted[0] > before_predicted[0]                  # it knows it lost information
    assert np.all(out.n_used[t_s > T_LOSS_S] == 2)
    # bounded: the roll covariance no longer grows over the last 10 minutes
    roll_var = out.P_diag[:, 0]
    assert roll_var[-1] < 1.05 * roll_var[t_s <= 1200.0][-1]


def test_both_trackers_lost_roll_drifts_within_its_covariance():
    """With only the DSS and the IRU after 600 s, roll about the Sun line is
    unobservable (the DSS boresight is body X): the filter's roll 3-sigma
    grows without bound (gyro noise and bias uncertainty; measured 2.9
    arcsec at 600 s -> 55 arcsec at 1800 s, passing the 35 arcsec requirement
    680 s after the loss), while the true roll error stays inside it (it
    grows with the real gyro errors: at most 8 arcsec here, as the IRU
    channels' true body bias is only ~0.001 deg/h). Pitch and yaw stay at the
    DSS's ~2 arcsec (3-sigma)."""
    st_on = np.ones((T, 2), np.bool_)
    st_on[int(T_LOSS_S / DT):, :] = False
    out = _run(st_on)
    after = t_s > T_LOSS_S
    roll_sigma = np.sqrt(out.P_diag[after, 0])
    assert np.all(np.diff(roll_sigma) > 0.0)
    assert roll_sigma[-1] * 3.0 / tb.ARCSEC > 35.0
    assert np.mean(np.abs(out.err_B[after, 0]) < 3.0 * roll_sigma) > 0.99
    measured, predicted = _three_sigma(out, T_LOSS_S, 1800.0)
    print(f"DSS + IRU only: measured 3-sigma {np.round(measured, 2)} arcsec, filter {np.round(predicted, 2)}, "
          f"roll 3-sigma at 1800 s {3.0 * roll_sigma[-1] / tb.ARCSEC:.1f} arcsec")
    assert np.all(measured[1:] < REQUIREMENT_3SIGMA_ARCSEC[1:])
    assert np.all(out.n_used[after] == 1)
