"""EKF propagation (sim/fsw/ekf_propagation.py) against outside references:
the discrete Phi and Qd against scipy's matrix exponential of the continuous
system (Van Loan, "Computing integrals involving the matrix exponential",
IEEE TAC 1978), the linearisation against the nonlinear error propagated with
scipy rotations, and the covariance product against numpy."""
import numpy as np
import pytest
from scipy.linalg import expm
from scipy.spatial.transform import Rotation

from sim.fsw.ekf_propagation import SERIES_X_MAX, propagate_covariance, transition_and_noise, transition_coefficients

DT = 0.2                                   # seed 001 "DeltaV": 200-msec control cycle
DEG = np.pi / 180.0
ARCSEC = DEG / 3600.0
AXIS = np.array([0.48, -0.6, 0.64])        # unit, off every body axis


def skew(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def van_loan(omega, dt, sigma_v, sigma_u):
    """Phi and Qd of dx/dt = F x + G w, E[w w^T] = Q delta(t), from one
    matrix exponential: expm([[-F, G Q G^T], [0, F^T]] dt) = [[., B12],
    [0, B22]], Phi = B22^T, Qd = Phi B12 (Van Loan 1978)."""
    F = np.zeros((6, 6))
    F[:3, :3] = -skew(omega)
    F[:3, 3:] = -np.eye(3)
    G = np.zeros((6, 6))
    G[:3, :3] = -np.eye(3)
    G[3:, 3:] = np.eye(3)
    Q = np.diag([sigma_v ** 2] * 3 + [sigma_u ** 2] * 3)
    A = np.zeros((12, 12))
    A[:6, :6] = -F
    A[:6, 6:] = G @ Q @ G.T
    A[6:, 6:] = F.T
    B = expm(A * dt)
    Phi = B[6:, 6:].T
    return Phi, Phi @ B[:6, 6:]


def ours(omega, dt, sigma_v, sigma_u):
    Phi, Qd = np.zeros((6, 6)), np.zeros((6, 6))
    transition_and_noise(np.asarray(omega, float), dt, sigma_v, sigma_u, Phi, Qd)
    return Phi, Qd


# |omega| over the control cycle: at rest; SDO's Sun-pointing drift (~1 deg/day,
# 2e-7 rad/s); seed 001 "Hardware complement": highest expected rate 2 deg/s and
# the IRU's polarity limit 10 deg/s; then either side of the series switch
# (x = |omega| dt = 0.2 at 1 rad/s) and a large x = 1 for the closed forms.
RATES_RAD_S = [0.0, 2e-7, 2.0 * DEG, 10.0 * DEG, 0.999, 1.001, 5.0]


@pytest.mark.parametrize("rate", RATES_RAD_S)
def test_transition_matrix_matches_van_loan(rate):
    """Phi: the attitude block is dimensionless, the attitude-bias block in
    seconds; both agree with expm to 1e-12 (rad per rad, and s)."""
    Phi, _ = ours(rate * AXIS, DT, 0.0, 0.0)
    Phi_ref, _ = van_loan(rate * AXIS, DT, 0.0, 0.0)
    np.testing.assert_allclose(Phi, Phi_ref, rtol=0.0, atol=1e-12)


@pytest.mark.parametrize("rate", RATES_RAD_S)
@pytest.mark.parametrize("noise", ["arw", "bias_walk"])
def test_process_noise_matches_van_loan(rate, noise):
    """Qd is linear in sigma_v^2 and sigma_u^2, so each part is checked alone
    with a unit density (scaling keeps expm's absolute error meaningful).
    Tolerance: 1e-10 of each part's largest element; at SDO's gyro (sigma_v =
    1.45e-6 rad/s^0.5, sigma_u = 1.6e-10 rad/s^1.5) that is 4e-23 rad^2 on
    the attitude block, 1e-5 of a micro-arcsecond in standard deviation."""
    sv, su = (1.0, 0.0) if noise == "arw" else (0.0, 1.0)
    _, Qd = ours(rate * AXIS, DT, sv, su)
    _, Qd_ref = van_loan(rate * AXIS, DT, sv, su)
    scale = np.abs(Qd_ref).max()
    np.testing.assert_allclose(Qd, Qd_ref, rtol=0.0, atol=1e-10 * scale)
    np.testing.assert_array_equal(Qd, Qd.T)


def test_process_noise_at_sdo_gyro_specification():
    """The same comparison in physical units with SDO's gyro (sdo.yaml:
    0.005 deg/sqrt(h) ARW, 0.002 deg/h/sqrt(h) rate random walk) at 2 deg/s."""
    sv = 0.005 * DEG / 60.0
    su = 0.002 * DEG / 3600.0 / 60.0
    omega = 2.0 * DEG * AXIS
    _, Qd = ours(omega, DT, sv, su)
    _, Qd_ref = van_loan(omega, DT, sv, su)
    np.testing.assert_allclose(Qd[:3, :3], Qd_ref[:3, :3], rtol=0.0, atol=1e-10 * sv ** 2 * DT)
    np.testing.assert_allclose(Qd[:3, 3:], Qd_ref[:3, 3:], rtol=0.0, atol=1e-10 * su ** 2 * DT ** 2)
    np.testing.assert_allclose(Qd[3:, 3:], Qd_ref[3:, 3:], rtol=0.0, atol=1e-10 * su ** 2 * DT)
    # the ARW part dominates the attitude block: sigma_v^2 dt, 4.2e-13 rad^2 = (0.134 arcsec)^2
    assert np.sqrt(Qd[0, 0]) / ARCSEC == pytest.approx(0.134, abs=0.001)


def test_coefficients_continuous_across_the_series_switch():
    below = np.array(transition_coefficients(SERIES_X_MAX * (1.0 - 1e-12)))
    above = np.array(transition_coefficients(SERIES_X_MAX * (1.0 + 1e-12)))
    np.testing.assert_allclose(below, above, rtol=1e-10)


def _propagated_error(q_est, b_est, dtheta0, dbias, omega_meas, dt):
    """The error after one step, by rotations alone (scipy): the truth turns
    at omega_meas - b_true, the estimate at omega_meas - b_est."""
    r_est = Rotation.from_quat(q_est, scalar_first=True)
    r_true = r_est * Rotation.from_rotvec(dtheta0)
    r_true = r_true * Rotation.from_rotvec((omega_meas - (b_est + dbias)) * dt)
    r_est = r_est * Rotation.from_rotvec((omega_meas - b_est) * dt)
    return (r_est.inv() * r_true).as_rotvec()


@pytest.mark.parametrize("rate_deg_s", [0.0, 2.0])
def test_linearisation_matches_the_rotations(rate_deg_s):
    """Phi applied to an error of 100 arcsec per axis and a bias error of
    1 deg/h per axis reproduces the error's change over a cycle given by the
    rotations themselves. The change is ~0.2 arcsec from the bias, plus
    ~0.1 arcsec from the -[omega x] coupling at 2 deg/s (seed 001's highest
    expected rate); the second-order residual is ~1e-4 arcsec."""
    rng = np.random.default_rng(3)
    q_est = Rotation.random(random_state=rng).as_quat(scalar_first=True)
    b_est = np.array([1.0, -2.0, 0.5]) * DEG / 3600.0
    omega_meas = rate_deg_s * DEG * AXIS + b_est
    dtheta0 = np.array([100.0, -100.0, 100.0]) * ARCSEC
    dbias = np.array([1.0, 1.0, -1.0]) * DEG / 3600.0
    Phi, _ = ours(omega_meas - b_est, DT, 0.0, 0.0)
    change_linear = Phi[:3, :3] @ dtheta0 + Phi[:3, 3:] @ dbias - dtheta0
    change = _propagated_error(q_est, b_est, dtheta0, dbias, omega_meas, DT) - dtheta0
    np.testing.assert_allclose(change / ARCSEC, change_linear / ARCSEC, rtol=0.0, atol=2e-4)
    coupling = -np.cross(omega_meas - b_est, dtheta0) * DT
    assert np.abs(coupling).max() / ARCSEC > (0.05 if rate_deg_s else -1.0)


def test_propagate_covariance_matches_numpy():
    rng = np.random.default_rng(4)
    A = rng.standard_normal((6, 6))
    P = A @ A.T + 6.0 * np.eye(6)
    Phi, Qd = ours(np.array([0.01, -0.02, 0.03]), DT, 1.0, 0.5)
    expected = Phi @ P @ Phi.T + Qd
    P_out = P.copy()
    propagate_covariance(P_out, Phi, Qd, np.zeros((6, 6)))
    np.testing.assert_allclose(P_out, expected, rtol=1e-13, atol=1e-13 * np.abs(expected).max())
    np.testing.assert_array_equal(P_out, P_out.T)
