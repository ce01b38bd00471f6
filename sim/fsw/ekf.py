"""The six-state attitude EKF of SDO and the two ways of flying without it
(seed 001 "Attitude determination and targeting" and "Inertial mode": "a
six-state filter that uses IRU, DSS, and ST measurements as inputs, and
estimates the attitude errors and gyro drift bias errors", heritage TRMM and
WMAP; "The Kalman filter can be disabled, and in this case the attitude
solution is then simply the quaternion from one of the star trackers or the
attitude propagated using the IRU rate measurements, depending on which option
is selected by ground command").

The filter is the multiplicative EKF (Lefferts, Markley & Shuster 1982;
Markley & Crassidis 2014, sec. 6.2, Table 6.3): the estimate is a quaternion
q_est_BN and a gyro bias bias_B; the filter's state is the small error
[dtheta (rad, body axes), dbias (rad/s)] with covariance P (6, 6); after each
sensor's update the error is folded into q_est_BN and bias_B and reset to zero,
so the quaternion stays a unit quaternion and never enters the covariance.

Each cycle (ekf_cycle): propagate over the last cycle with the IRU rate
measured over it, minus the bias (ekf_propagation.py), then update with every
valid and enabled star tracker, then the DSS (ekf_measurements.py), one
sensor at a time. The caller supplies the on-board Sun unit vector in GCI
(the on-board ephemeris is another module) and selects the option.

Per sensor, the state keeps for telemetry the innovations of the last update
(the scalar residuals before each component's update) and their predicted
variances, so the normalised innovation r^2 / var is available to the ground
and to failure detection.

The kernels that take the state and parameter records carry inline="always"
(docs/architecture.md "Inlined kernels": each call that LLVM does not inline
pays a reference count on every array of the records); the small math they
call is left to LLVM.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.attitude import (
    quat_conj,
    quat_from_rotvec,
    quat_mul,
    quat_normalize,
    quat_propagate,
    quat_to_dcm,
)
from sim.constants import ARCSEC_RAD as ARCSEC
from sim.fsw.ekf_measurements import (
    dss_residual,
    dss_sigma,
    scalar_update,
    star_tracker_residual,
)
from sim.fsw.ekf_propagation import propagate_covariance, transition_and_noise

# Options by ground command.
OPTION_STAR_TRACKER = 0                     # fly the selected tracker's quaternion
OPTION_IRU = 1                              # propagate with the IRU rates
OPTION_EKF = 2                              # the Kalman filter (seed 001: the default in Inertial mode)

ARCMIN = np.pi / 180.0 / 60.0

# work_66 slots
W_PHI, W_QD, W_PRODUCT = 0, 1, 2


class EkfParams(NamedTuple):
    dt: float                        # control cycle, s
    sigma_v: float                   # gyro angle random walk, rad/s^0.5
    sigma_u: float                   # gyro bias random walk, rad/s^1.5
    st_q_BS: np.ndarray              # (n_st, 4) each tracker's mounting (attitude of S in B)
    st_sigma_S: np.ndarray           # (n_st, 3) 1-sigma, rad, about S's X, Y (transverse) and Z (boresight)
    dss_dcm_DB: np.ndarray           # (3, 3) body to DSS frame (boresight +X)
    dss_inner_half_angle_rad: float  # best accuracy inside this off-boresight angle
    dss_fov_half_width_rad: float    # edge of each tangent-plane angle
    dss_sigma_inner_rad: float       # 1-sigma per angle inside the inner cone
    dss_sigma_edge_rad: float        # 1-sigma per angle at the FOV edge
    sun_sigma_rad: float             # 1-sigma of the on-board Sun direction, per axis


class EkfState(NamedTuple):
    q_est_BN: np.ndarray       # (4,) attitude estimate
    bias_B: np.ndarray         # (3,) gyro drift-bias estimate, rad/s, subtracted from the IRU rate
    omega_est_B: np.ndarray    # (3,) bias-corrected body rate of the last propagation, rad/s
    P: np.ndarray              # (6, 6) covariance of [dtheta (rad), dbias (rad/s)]
    P_diag: np.ndarray         # (6,) its diagonal after the last cycle, for telemetry
    st_use: np.ndarray         # (n_st,) bool: trackers the filter may use (ground command / FDC)
    dss_use: np.ndarray        # (1,) bool: the filter may use the DSS
    st_innov: np.ndarray       # (n_st, 3) last innovations, rad, tracker axes X, Y, Z
    st_innov_var: np.ndarray   # (n_st, 3) their predicted variances, rad^2
    st_updated: np.ndarray     # (n_st,) bool: tracker used in the last cycle
    dss_innov: np.ndarray      # (2,) last innovations of alpha, beta, rad
    dss_innov_var: np.ndarray  # (2,) their predicted variances, rad^2
    dss_updated: np.ndarray    # (1,) bool: DSS used in the last cycle
    dx: np.ndarray             # (6,) work: correction accumulated over one sensor's components
    work_6: np.ndarray         # (6,) work: P h of a scalar update
    H_att: np.ndarray          # (3, 3) work: rows of H over dtheta
    work_66: np.ndarray        # (3, 6, 6) work: Phi, Qd, a product (no allocation per cycle)


def make_ekf_params(dt, arw_deg_per_sqrt_h, rrw_deg_h_per_sqrt_h, st_q_BS, st_noise_transverse_arcsec_3sigma,
                    st_noise_boresight_arcsec_3sigma, dss_q_BD=(1.0, 0.0, 0.0, 0.0), dss_inner_half_angle_deg=10.0,
                    dss_fov_half_width_deg=16.0, dss_accuracy_inner_arcmin_3sigma=0.24,
                    dss_accuracy_edge_arcmin_3sigma=3.0, sun_accuracy_arcsec_3sigma=2.0) -> EkfParams:
    """Parameters from data-sheet units (the spacecraft file's). Per-tracker
    noises may be scalars (same for all) or one value per tracker.
    Defaults: seed 001 "Hardware complement" (DSS) and "On-Board Ephemeris"
    (Sun better than 2 arcsec; assumption: read as 3-sigma)."""
    q_BS = np.atleast_2d(np.asarray(st_q_BS, float))
    n_st = q_BS.shape[0]
    trans = np.broadcast_to(np.asarray(st_noise_transverse_arcsec_3sigma, float), (n_st,))
    bore = np.broadcast_to(np.asarray(st_noise_boresight_arcsec_3sigma, float), (n_st,))
    sigma_S = np.stack([trans, trans, bore], axis=1) / 3.0 * ARCSEC
    dcm_DB = np.ascontiguousarray(quat_to_dcm(np.asarray(dss_q_BD, float)).T)
    deg = np.pi / 180.0
    return EkfParams(float(dt), float(arw_deg_per_sqrt_h) * deg / 60.0,
                     float(rrw_deg_h_per_sqrt_h) * deg / 3600.0 / 60.0,
                     np.ascontiguousarray(q_BS), np.ascontiguousarray(sigma_S), dcm_DB,
                     float(dss_inner_half_angle_deg) * deg, float(dss_fov_half_width_deg) * deg,
                     float(dss_accuracy_inner_arcmin_3sigma) / 3.0 * ARCMIN,
                     float(dss_accuracy_edge_arcmin_3sigma) / 3.0 * ARCMIN,
                     float(sun_accuracy_arcsec_3sigma) / 3.0 * ARCSEC)


def ekf_params_from_spacecraft(sc, sun_accuracy_arcsec_3sigma=2.0) -> EkfParams:
    """From a validated spacecraft definition (sim/spacecraft). The gyro noise
    is one channel's: the least-squares body rate averages two channels per
    axis while all are in use, so this over-bounds it by sqrt(2) then and is
    right after a unit is lost. A spacecraft without a DSS gets the defaults
    and must leave the state's dss_use False (ekf_initial_state does)."""
    iru = sc.sensors.iru_units
    st = sc.star_trackers
    kw = {}
    if sc.sensors.dss is not None:
        d = sc.sensors.dss
        kw = {"dss_q_BD": d.q_BD, "dss_inner_half_angle_deg": d.inner_half_angle_deg,
              "dss_fov_half_width_deg": d.fov_half_width_deg,
              "dss_accuracy_inner_arcmin_3sigma": d.accuracy_inner_arcmin_3sigma,
              "dss_accuracy_edge_arcmin_3sigma": d.accuracy_edge_arcmin_3sigma}
    return make_ekf_params(sc.timing.control_dt_s, iru.arw_deg_per_sqrt_h, iru.rrw_deg_h_per_sqrt_h,
                           [t.q_BS for t in st], [t.noise_transverse_arcsec_3sigma for t in st],
                           [t.noise_boresight_arcsec_3sigma for t in st],
                           sun_accuracy_arcsec_3sigma=sun_accuracy_arcsec_3sigma, **kw)


def ekf_initial_state(q_BN, n_star_trackers, sigma_attitude_rad, sigma_bias_rad_s, bias_B=(0.0, 0.0, 0.0),
                      use_dss=True) -> EkfState:
    """A filter started at q_BN and bias_B, with independent per-axis
    uncertainties sigma_attitude_rad and sigma_bias_rad_s (1-sigma)."""
    n = int(n_star_trackers)
    P = np.diag(np.r_[np.full(3, float(sigma_attitude_rad) ** 2), np.full(3, float(sigma_bias_rad_s) ** 2)])
    return EkfState(quat_normalize(np.asarray(q_BN, float)), np.array(bias_B, float), np.zeros(3), P,
                    np.diag(P).copy(), np.ones(n, dtype=np.bool_), np.array([bool(use_dss)]), np.zeros((n, 3)),
                    np.zeros((n, 3)), np.zeros(n, dtype=np.bool_), np.zeros(2), np.zeros(2),
                    np.zeros(1, dtype=np.bool_), np.zeros(6), np.zeros(6), np.zeros((3, 3)), np.zeros((3, 6, 6)))


@njit(cache=True)
def body_from_tracker(q_SN, q_BS):
    """q_BN = q_SN (x) q_BS^* : the tracker's attitude carried back to the body."""
    return quat_mul(q_SN, quat_conj(q_BS))


@njit(cache=True, inline="always")
def ekf_propagate(s, p, rate_meas_B):
    """Over one cycle with the IRU rate measured over it: the estimate by the
    bias-corrected rate (exact for a rate constant over the cycle), the
    covariance by the linearised error dynamics at that rate."""
    for i in range(3):
        s.omega_est_B[i] = rate_meas_B[i] - s.bias_B[i]
    s.q_est_BN[:] = quat_propagate(s.q_est_BN, s.omega_est_B, p.dt)
    Phi, Qd = s.work_66[W_PHI], s.work_66[W_QD]
    transition_and_noise(s.omega_est_B, p.dt, p.sigma_v, p.sigma_u, Phi, Qd)
    propagate_covariance(s.P, Phi, Qd, s.work_66[W_PRODUCT])


@njit(cache=True, inline="always")
def _reset(s):
    """Fold the accumulated error estimate into the quaternion and the bias
    (the multiplicative reset) and zero it. The reset's own effect on P is
    second order in dtheta and is neglected, as is usual for this filter."""
    s.q_est_BN[:] = quat_normalize(quat_mul(s.q_est_BN, quat_from_rotvec(s.dx[0:3])))
    for i in range(3):
        s.bias_B[i] += s.dx[3 + i]
    s.dx[:] = 0.0


@njit(cache=True, inline="always")
def ekf_update_star_tracker(s, p, k, q_SN):
    """Update with tracker k's measured attitude q_SN of its own frame."""
    z = star_tracker_residual(s.q_est_BN, q_SN, p.st_q_BS[k], s.H_att)
    s.dx[:] = 0.0
    for i in range(3):
        var = p.st_sigma_S[k, i] * p.st_sigma_S[k, i]
        r, v = scalar_update(s.P, s.dx, s.H_att[i], z[i], var, s.work_6)
        s.st_innov[k, i] = r
        s.st_innov_var[k, i] = v
    _reset(s)


@njit(cache=True, inline="always")
def ekf_update_dss(s, p, sun_N, angles):
    """Update with the DSS angles [alpha, beta] (rad), given the on-board Sun
    unit vector in GCI. Its variance adds the ephemeris error to the sensor's,
    both taken per angle."""
    z, off_boresight = dss_residual(s.q_est_BN, sun_N, angles, p.dss_dcm_DB, s.H_att)
    sig = dss_sigma(off_boresight, p.dss_inner_half_angle_rad, p.dss_fov_half_width_rad, p.dss_sigma_inner_rad,
                    p.dss_sigma_edge_rad)
    var = sig * sig + p.sun_sigma_rad * p.sun_sigma_rad
    s.dx[:] = 0.0
    for i in range(2):
        r, v = scalar_update(s.P, s.dx, s.H_att[i], z[i], var, s.work_6)
        s.dss_innov[i] = r
        s.dss_innov_var[i] = v
    _reset(s)


@njit(cache=True, inline="always")
def _clear_update_flags(st_updated, dss_updated):
    st_updated[:] = False
    dss_updated[0] = False


@njit(cache=True, inline="always")
def _store_diagonal(P, P_diag):
    for i in range(6):
        P_diag[i] = P[i, i]


@njit(cache=True, inline="always")
def ekf_cycle(s, p, rate_meas_B, st_q_SN, st_valid, sun_N, dss_angles, dss_valid):
    """One cycle of the filter: propagate, then every valid and enabled star
    tracker, then the DSS. Returns the number of sensors used; their
    innovations are in s.st_innov / s.dss_innov, P's diagonal in s.P_diag."""
    ekf_propagate(s, p, rate_meas_B)
    _clear_update_flags(s.st_updated, s.dss_updated)
    n_used = 0
    for k in range(st_q_SN.shape[0]):
        if st_valid[k] and s.st_use[k]:
            ekf_update_star_tracker(s, p, k, st_q_SN[k])
            s.st_updated[k] = True
            n_used += 1
    if dss_valid[0] and s.dss_use[0]:
        ekf_update_dss(s, p, sun_N, dss_angles)
        s.dss_updated[0] = True
        n_used += 1
    _store_diagonal(s.P, s.P_diag)
    return n_used


@njit(cache=True, inline="always")
def _tracker_covariance(P, st_q_BS, st_sigma_S, k):
    """After flying tracker k: the attitude block is that tracker's noise
    in body axes, dcm_BS diag(sigma_S^2) dcm_SB, uncorrelated with the bias,
    so a filter switched on next starts from what it actually knows."""
    dcm_BS = quat_to_dcm(st_q_BS[k])
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for m in range(3):
                acc += dcm_BS[i, m] * st_sigma_S[k, m] * st_sigma_S[k, m] * dcm_BS[j, m]
            P[i, j] = acc
            P[i, 3 + j] = 0.0
            P[3 + j, i] = 0.0


@njit(cache=True, inline="always")
def attitude_cycle(option, st_index, s, p, rate_meas_B, st_q_SN, st_valid, sun_N, dss_angles, dss_valid):
    """The attitude solution of one cycle under the ground-selected option.

    OPTION_EKF: ekf_cycle.
    OPTION_IRU: propagate with the IRU rate less the last bias estimate (held
      while the filter is off); the covariance keeps growing.
    OPTION_STAR_TRACKER: the selected tracker's quaternion carried to the body
      when it is valid, else IRU propagation as above.
    Returns the number of sensors used (0 or 1 with the filter off)."""
    if option == OPTION_EKF:
        return ekf_cycle(s, p, rate_meas_B, st_q_SN, st_valid, sun_N, dss_angles, dss_valid)
    _clear_update_flags(s.st_updated, s.dss_updated)
    if option == OPTION_STAR_TRACKER and st_valid[st_index]:
        # the tracker overwrites both the estimate and P: nothing to propagate
        for i in range(3):
            s.omega_est_B[i] = rate_meas_B[i] - s.bias_B[i]
        s.q_est_BN[:] = body_from_tracker(st_q_SN[st_index], p.st_q_BS[st_index])
        _tracker_covariance(s.P, p.st_q_BS, p.st_sigma_S, st_index)
        _store_diagonal(s.P, s.P_diag)
        return 1
    ekf_propagate(s, p, rate_meas_B)
    _store_diagonal(s.P, s.P_diag)
    return 0
