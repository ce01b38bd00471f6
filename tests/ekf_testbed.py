"""A compiled closed loop for the EKF tests: synthetic truth, sensor data from
the truth sensor models (sim/truth/sensors), the flight software's filter, and
the estimation errors recorded each cycle.

Truth: the body turns at omega(t) = omega_const_B + omega_amp_B sin(2 pi t /
period) (no controller: the tests are about knowledge, not control), the
attitude integrated in four substeps per cycle, the gyro's integrated angle
exactly. Gyro data come from one of two models:

* GYRO_SYNTHETIC: body-axis rates from the filter's own continuous model
  (bias random walk plus angle random walk), sampled as a rate-integrating
  gyro averages them over the cycle (Crassidis & Junkins, "Optimal
  Estimation of Dynamic Systems", 2nd ed., the attitude chapter's gyro
  simulation:
  omega_meas = mean omega + (b_k + b_k+1) / 2 + sqrt(sv^2/dt + su^2 dt/12) N,
  b_k+1 = b_k + su sqrt(dt) N). With it the filter's model is right, so its
  NEES must follow the chi-square distribution.
* GYRO_IRU_UNITS: SDO's six IRU channels (sim/truth/sensors/iru_units.py:
  quantised counts, per-channel bias, noise) through the flight software's
  least-squares rate selection (sim/fsw/rate_selection.py).

Star trackers and DSS are the truth models (star_tracker.py, dss.py). A
schedule switches trackers off and selects the attitude option per cycle.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.attitude import quat_conj, quat_mul, quat_propagate
from sim.fsw.ekf import attitude_cycle
from sim.fsw.ekf_measurements import rotvec_of
from sim.fsw.rate_selection import least_squares_rate
from sim.truth.sensors import dss, iru, iru_units, star_tracker

GYRO_SYNTHETIC, GYRO_IRU_UNITS = 0, 1
N_SUB = 4


class Truth(NamedTuple):
    q0_BN: np.ndarray          # (4,) true attitude at t = 0
    omega_const_B: np.ndarray  # (3,) rad/s
    omega_amp_B: np.ndarray    # (3,) rad/s, amplitude of the sinusoidal part
    period_s: float
    sun_N: np.ndarray          # (3,) unit vector to the Sun (also the flight software's)
    gyro_model: int
    bias0_B: np.ndarray        # (3,) GYRO_SYNTHETIC: true body bias at t = 0, rad/s
    sigma_v: float             # GYRO_SYNTHETIC: rad/s^0.5
    sigma_u: float             # GYRO_SYNTHETIC: rad/s^1.5


class Record(NamedTuple):
    err_B: np.ndarray       # (T, 3) attitude error, rad, body axes: q_true = q_est (x) exp(err / 2)
    bias_err: np.ndarray    # (T, 3) true body bias minus estimate, rad/s
    P_diag: np.ndarray      # (T, 6)
    nees: np.ndarray        # (T,) e^T P^-1 e with e = [err_B, bias_err]
    st_nis: np.ndarray      # (T, n_st) sum over X, Y, Z of r^2 / var (0 when not used)
    dss_nis: np.ndarray     # (T,) sum over alpha, beta of r^2 / var (0 when not used)
    n_used: np.ndarray      # (T,) sensors the estimate used
    q_est: np.ndarray       # (T, 4)
    q_true: np.ndarray      # (T, 4)


def make_record(T, n_st):
    return Record(np.zeros((T, 3)), np.zeros((T, 3)), np.zeros((T, 6)), np.zeros(T), np.zeros((T, n_st)),
                  np.zeros(T), np.zeros(T, np.int64), np.zeros((T, 4)), np.zeros((T, 4)))


@njit(cache=True)
def _omega(tr, t):
    return tr.omega_const_B + tr.omega_amp_B * np.sin(2.0 * np.pi * t / tr.period_s)


@njit(cache=True)
def _omega_integral(tr, t0, t1):
    """Exact integral of omega over [t0, t1]."""
    w = 2.0 * np.pi / tr.period_s
    return tr.omega_const_B * (t1 - t0) + tr.omega_amp_B * (np.cos(w * t0) - np.cos(w * t1)) / w


@njit(cache=True)
def run(tr, ekf_s, ekf_p, options, st_index, st_on, st_p, dss_p, iru_p, iru_state, noise_gyro, noise_st, noise_dss,
        out):
    """Run len(options) cycles; options[k] is the attitude option of cycle k,
    st_on[k, j] whether tracker j delivers at cycle k. Noise arrays: (T, 6)
    for the synthetic gyro (ARW 3, bias walk 3) or (T, 12) for the IRU units,
    (T, 3 n_st), (T, 2). Fills out (a Record)."""
    T = options.shape[0]
    n_st = st_p.q_BS.shape[0]
    dt = ekf_p.dt
    q = tr.q0_BN.copy()
    bias = tr.bias0_B.copy()
    theta_int = np.zeros(3)
    st_q = np.zeros((n_st, 4))
    st_valid = np.zeros(n_st, np.bool_)
    angles = np.zeros(2)
    dss_valid = np.zeros(1, np.bool_)
    dss_fault = np.zeros((1, dss.N_FAULT_SLOTS))
    iru_fault = np.zeros((iru_units.N_CHANNELS, iru_units.N_FAULT_SLOTS))
    rate_ch = np.zeros(iru_units.N_CHANNELS)
    ch_valid = np.zeros(iru_units.N_CHANNELS, np.bool_)
    bias_ch = np.zeros(iru_units.N_CHANNELS)
    e = np.zeros(6)
    h = dt / N_SUB
    for k in range(T):
        t0 = k * dt
        for j in range(N_SUB):                     # truth from t0 to t0 + dt
            q = quat_propagate(q, _omega(tr, t0 + (j + 0.5) * h), h)
        dtheta = _omega_integral(tr, t0, t0 + dt)
        theta_int += dtheta
        if tr.gyro_model == GYRO_SYNTHETIC:
            bias_next = bias + tr.sigma_u * np.sqrt(dt) * noise_gyro[k, 3:6]
            sd = np.sqrt(tr.sigma_v ** 2 / dt + tr.sigma_u ** 2 * dt / 12.0)
            rate = dtheta / dt + 0.5 * (bias + bias_next) + sd * noise_gyro[k, 0:3]
            bias = bias_next
        else:
            iru_units.iru_units_sample(theta_int, iru_state, iru_p, noise_gyro[k], iru_fault, rate_ch, ch_valid)
            rate, _ = least_squares_rate(rate_ch, iru_p.ch_axes_B, ch_valid)
            # the true body bias: the channels' (drifting) biases through the same least squares
            for i in range(3):
                bias_ch[i] = iru_state[iru_units.COUNTER_A + iru.BIAS + i]
                bias_ch[3 + i] = iru_state[iru_units.COUNTER_B + iru.BIAS + i]
            bias, _ = least_squares_rate(bias_ch, iru_p.ch_axes_B, ch_valid)
        star_tracker.star_tracker_sample(q, st_p, noise_st[k], st_q, st_valid)
        for j in range(n_st):
            st_valid[j] = st_on[k, j]
        dss.dss_sample(q, tr.sun_N, 1.0, dss_p, noise_dss[k], dss_fault, angles, dss_valid)
        out.n_used[k] = attitude_cycle(options[k], st_index, ekf_s, ekf_p, rate, st_q, st_valid, tr.sun_N, angles,
                                       dss_valid)
        err = rotvec_of(quat_mul(quat_conj(ekf_s.q_est_BN), q))
        for i in range(3):
            out.err_B[k, i] = err[i]
            out.bias_err[k, i] = bias[i] - ekf_s.bias_B[i]
            e[i] = err[i]
            e[3 + i] = bias[i] - ekf_s.bias_B[i]
        out.P_diag[k] = ekf_s.P_diag
        out.nees[k] = e @ np.linalg.solve(ekf_s.P, e)
        for j in range(n_st):
            if ekf_s.st_updated[j]:
                out.st_nis[k, j] = np.sum(ekf_s.st_innov[j] ** 2 / ekf_s.st_innov_var[j])
        if ekf_s.dss_updated[0]:
            out.dss_nis[k] = np.sum(ekf_s.dss_innov ** 2 / ekf_s.dss_innov_var)
        out.q_est[k] = ekf_s.q_est_BN
        out.q_true[k] = q


# ---- Python-side set-up shared by the EKF tests ----------------------------

ARCSEC = np.pi / 180.0 / 3600.0
DEG_H = np.pi / 180.0 / 3600.0      # deg/h in rad/s
SUN_N = np.array([0.2, 0.9, 0.39]) / np.linalg.norm([0.2, 0.9, 0.39])   # any direction; ecliptic-ish


def sun_pointing_q(sun_N):
    """q_BN with body X on the Sun (SDO's science attitude, seed 001 "SNR
    Target": identity target in the SNR frame) and body Z toward celestial north."""
    from scipy.spatial.transform import Rotation
    x = np.asarray(sun_N, float)
    y = np.cross([0.0, 0.0, 1.0], x)
    y /= np.linalg.norm(y)
    z = np.cross(x, y)
    return Rotation.from_matrix(np.column_stack([x, y, z])).as_quat(scalar_first=True)


def sdo_sensors():
    """(spacecraft, truth sensor params) of SDO from sim/spacecraft/sdo.yaml."""
    from sim.spacecraft import load_spacecraft
    from sim.truth.build import make_sensor_params
    sc = load_spacecraft("sdo")
    return sc, make_sensor_params(sc)


def iru_units_state(sc, sp):
    """SDO's IRU channels at rest with the spacecraft file's channel biases."""
    bias = np.radians(np.array(sc.sensors.iru_units.bias_deg_h)) / 3600.0
    return iru_units.iru_units_initial_state(bias, np.zeros(3), np.zeros(3), sp.iru)


def draw_noise(rng, T, n_st, gyro_model):
    n_gyro = 6 if gyro_model == GYRO_SYNTHETIC else iru_units.N_NOISE
    return rng.standard_normal((T, n_gyro)), rng.standard_normal((T, 3 * n_st)), rng.standard_normal((T, 2))
