"""EKF measurement models and update (sim/fsw/ekf_measurements.py) against
outside references: residuals and sensitivities against scipy rotations and
the truth sensor models (finite differences), the sequential scalar Joseph
update against the textbook batch Kalman update in numpy, and the
parameters against the spacecraft file."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from sim.fsw.ekf import ARCMIN, ekf_params_from_spacecraft
from sim.fsw.ekf_measurements import dss_residual, dss_sigma, rotvec_of, scalar_update, star_tracker_residual
from sim.spacecraft import load_spacecraft
from sim.truth.sensors import dss as truth_dss
from sim.attitude import mounting_dcm_XB
from sim.truth.sensors.sensor_geometry import tangent_angles

DEG = np.pi / 180.0
ARCSEC = DEG / 3600.0
SDO = load_spacecraft("sdo")
Q_BS = np.array(SDO.star_trackers[0].q_BS)   # tracker 1: boresight 38 deg from +Z toward +Y (sdo.yaml)


def quat(r: Rotation) -> np.ndarray:
    return r.as_quat(scalar_first=True)


def rot(q) -> Rotation:
    return Rotation.from_quat(q, scalar_first=True)


@pytest.mark.parametrize("angle", [0.0, 1e-9, 1e-3, 1.0, 3.0, np.pi - 1e-6])
def test_rotvec_matches_scipy(angle):
    r = Rotation.from_rotvec(angle * np.array([0.6, 0.0, -0.8]))
    for q in (quat(r), -quat(r)):       # both signs of the same rotation
        np.testing.assert_allclose(rotvec_of(q), r.as_rotvec(), rtol=0.0, atol=1e-12)


def test_star_tracker_residual_is_the_rotation_from_prediction_to_measurement():
    """z = rotation vector of (q_est (x) q_BS)^-1 (x) q_SN, computed by scipy."""
    rng = np.random.default_rng(11)
    q_est = quat(Rotation.random(random_state=rng))
    q_SN = quat(rot(q_est) * rot(Q_BS) * Rotation.from_rotvec([40 * ARCSEC, -25 * ARCSEC, 90 * ARCSEC]))
    expected = ((rot(q_est) * rot(Q_BS)).inv() * rot(q_SN)).as_rotvec()
    z = star_tracker_residual(q_est, q_SN, Q_BS, np.zeros((3, 3)))
    np.testing.assert_allclose(z / ARCSEC, expected / ARCSEC, atol=1e-9)


def test_star_tracker_sensitivity_matches_finite_differences():
    """H_att column j: the residual's change when the true attitude is
    q_est (x) exp(eps e_j / 2) and the tracker is perfect (eps = 1 arcsec)."""
    rng = np.random.default_rng(12)
    q_est = quat(Rotation.random(random_state=rng))
    H = np.zeros((3, 3))
    star_tracker_residual(q_est, quat(rot(q_est) * rot(Q_BS)), Q_BS, H)
    eps = ARCSEC
    for j in range(3):
        d = np.zeros(3)
        d[j] = eps
        q_SN = quat(rot(q_est) * Rotation.from_rotvec(d) * rot(Q_BS))
        column = star_tracker_residual(q_est, q_SN, Q_BS, np.zeros((3, 3))) / eps
        np.testing.assert_allclose(H[:, j], column, atol=1e-6)
    # and it is the body-to-tracker rotation, dcm_SB
    np.testing.assert_allclose(H, rot(Q_BS).as_matrix().T, atol=1e-15)


def _dss_angles_truth(q_BN, sun_N, dcm_DB):
    """Noise-free DSS output from the truth model's geometry and scipy."""
    s_D = dcm_DB @ rot(q_BN).inv().apply(sun_N)
    return np.array(tangent_angles(s_D))


# Sun direction in body axes: on the boresight, 5 deg off, 12 deg off (beyond the
# 10-deg best-accuracy cone, seed 001), and a mounting turned 3 deg off body X.
DSS_CASES = [((0.0, 0.0), (1.0, 0.0, 0.0, 0.0)), ((3.0, -4.0), (1.0, 0.0, 0.0, 0.0)),
             ((-8.5, 8.5), (1.0, 0.0, 0.0, 0.0)),
             ((2.0, 1.0), tuple(quat(Rotation.from_rotvec(3 * DEG * np.array([0.0, 0.6, 0.8])))))]


@pytest.mark.parametrize("tangent_deg, q_BD", DSS_CASES)
def test_dss_residual_and_sensitivity(tangent_deg, q_BD):
    rng = np.random.default_rng(13)
    q_est = quat(Rotation.random(random_state=rng))
    dcm_DB = mounting_dcm_XB(np.array(q_BD))
    a, b = np.radians(tangent_deg)
    s_D = np.array([1.0, np.tan(a), np.tan(b)])
    sun_N = rot(q_est).apply(dcm_DB.T @ (s_D / np.linalg.norm(s_D)))
    # at the true attitude the residual of a perfect sensor is zero
    H = np.zeros((3, 3))
    z, off = dss_residual(q_est, sun_N, _dss_angles_truth(q_est, sun_N, dcm_DB), dcm_DB, H)
    np.testing.assert_allclose(z / ARCSEC, 0.0, atol=1e-9)
    assert off == pytest.approx(np.arccos(s_D[0] / np.linalg.norm(s_D)), abs=1e-12)
    # H_att by finite differences of the truth geometry (eps = 1 arcsec)
    eps = ARCSEC
    for j in range(3):
        d = np.zeros(3)
        d[j] = eps
        q_true = quat(rot(q_est) * Rotation.from_rotvec(d))
        zj, _ = dss_residual(q_est, sun_N, _dss_angles_truth(q_true, sun_N, dcm_DB), dcm_DB, np.zeros((3, 3)))
        np.testing.assert_allclose(H[:2, j], zj / eps, atol=1e-5)


def test_dss_sigma_matches_the_sensor_data_sheet():
    """The flight software's DSS accuracy is the truth model's (same data
    sheet, seed 001: 0.24 arcmin within 10 deg, 3 arcmin toward the edges;
    3-sigma per angle)."""
    d = SDO.sensors.dss
    p = ekf_params_from_spacecraft(SDO)
    truth = truth_dss.make_dss_params(d.q_BD, d.fov_half_width_deg, d.inner_half_angle_deg,
                                      d.accuracy_inner_arcmin_3sigma, d.accuracy_edge_arcmin_3sigma,
                                      d.lit_fraction_min)
    for theta_deg in (0.0, 9.9, 10.0, 12.0, 15.9, 16.0, 20.0):
        ours = dss_sigma(np.radians(theta_deg), p.dss_inner_half_angle_rad, p.dss_fov_half_width_rad,
                         p.dss_sigma_inner_rad, p.dss_sigma_edge_rad)
        assert ours == pytest.approx(truth_dss.dss_sigma(np.radians(theta_deg), truth), rel=1e-12)
    assert p.dss_sigma_inner_rad == pytest.approx(0.08 * ARCMIN)    # 0.24 arcmin / 3


def test_parameters_from_the_spacecraft_file():
    """sdo.yaml / seed 001: trackers 30 arcsec transverse, 90 arcsec about the
    boresight (3-sigma); gyro 0.005 deg/sqrt(h) and 0.002 deg/h/sqrt(h)."""
    p = ekf_params_from_spacecraft(SDO)
    np.testing.assert_allclose(p.st_sigma_S / ARCSEC, [[10.0, 10.0, 30.0]] * 2)
    assert p.sigma_v == pytest.approx(0.005 * DEG / 60.0)
    assert p.sigma_u == pytest.approx(0.002 * DEG / 3600.0 / 60.0)
    assert p.dt == 0.2
    assert p.sun_sigma_rad == pytest.approx(2.0 / 3.0 * ARCSEC)


def test_sequential_scalar_updates_equal_the_batch_update():
    """Three independent scalar updates (each residual corrected by the
    correction already taken) equal the textbook batch update with
    K = P H^T (H P H^T + R)^-1 and the Joseph covariance
    (I - K H) P (I - K H)^T + K R K^T: linear Kalman filtering identities."""
    rng = np.random.default_rng(14)
    A = rng.standard_normal((6, 6))
    P = (A @ A.T + np.eye(6)) * 1e-10
    H_att = rng.standard_normal((3, 3))
    H = np.hstack([H_att, np.zeros((3, 3))])
    R = np.diag([1.0, 2.0, 9.0]) * 1e-10
    z = rng.standard_normal(3) * 1e-5
    K = P @ H.T @ np.linalg.inv(H @ P @ H.T + R)
    I_KH = np.eye(6) - K @ H
    P_ref = I_KH @ P @ I_KH.T + K @ R @ K.T
    dx_ref = K @ z
    P_seq, dx = P.copy(), np.zeros(6)
    for i in range(3):
        scalar_update(P_seq, dx, H_att[i].copy(), z[i], R[i, i], np.zeros(6))
    np.testing.assert_allclose(dx, dx_ref, rtol=1e-9, atol=1e-9 * np.abs(dx_ref).max())
    np.testing.assert_allclose(P_seq, P_ref, rtol=0.0, atol=1e-9 * np.abs(P_ref).max())
    np.testing.assert_array_equal(P_seq, P_seq.T)
    assert np.linalg.eigvalsh(P_seq).min() > 0.0


def test_scalar_update_returns_the_innovation_and_its_variance():
    P = np.diag([4.0, 1.0, 1.0, 1.0, 1.0, 1.0])
    r, var = scalar_update(P, np.zeros(6), np.array([1.0, 0.0, 0.0]), 3.0, 5.0, np.zeros(6))
    assert (r, var) == (3.0, 9.0)                 # h^T P h + R = 4 + 5
    assert P[0, 0] == pytest.approx(4.0 * 5.0 / 9.0)   # 1 / (1/4 + 1/5)


def test_dss_residual_wraps_to_the_short_angle():
    """An estimate with the Sun behind the sensor predicts alpha near 180 deg;
    the residual against a measured -1 deg is the short way round (-181 + 360
    = 179 deg, not -181 deg)."""
    q_est = np.array([1.0, 0.0, 0.0, 0.0])
    sun_N = np.array([-1.0, 0.0, 0.0])       # predicted alpha = atan2(0, -1) = 180 deg
    z, _ = dss_residual(q_est, sun_N, np.radians([-1.0, 0.0]), np.eye(3), np.zeros((3, 3)))
    assert np.degrees(z[0]) == pytest.approx(179.0)
    assert abs(z[1]) <= np.pi
