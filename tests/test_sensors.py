"""Sensor models against their specifications (seed 001 "Hardware complement")."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from sim.scenario import DEFAULT_EPOCH
from sim.spacecraft import load_spacecraft
from sim.truth import build
from sim.truth.sensors.iru import IruParams, iru_initial_state, iru_sample
from sim.truth.sensors.star_tracker import star_tracker_sample

ARCSEC = np.pi / 180 / 3600
SC = load_spacecraft("sdo")
TP = build.make_truth_params(SC, build.World(DEFAULT_EPOCH, 60.0))


def test_iru_rate_resolution_is_lsb_over_cycle():
    # seed 001: 0.5 arcsec/bit; seed 000 "Option three": rate resolution ~1.2e-5 rad/s at 0.2 s
    p = IruParams(0.5 * ARCSEC, 0.0, 0.0, 0.2)
    omega = np.array([3.3e-5, -7.7e-6, 1.0e-3])
    state = iru_initial_state(np.zeros(3), np.zeros(3), omega, p)
    out, theta, rates = np.zeros(3), np.zeros(3), []
    for _ in range(500):  # sample at t_k, then the body turns until t_k+1 (as the runner does)
        iru_sample(state, p, theta, np.zeros(6), out)
        rates.append(out.copy())
        theta += omega * 0.2
    rates = np.array(rates)
    step = 0.5 * ARCSEC / 0.2
    assert step == pytest.approx(1.2e-5, rel=0.02)
    assert rates / step == pytest.approx(np.round(rates / step), abs=1e-9)
    # quantisation error is carried, not lost: the mean over 100 s is the true rate within one count / 100 s
    assert rates.mean(axis=0) == pytest.approx(omega, abs=step / 500 * 1.01)


def test_iru_bias_and_angle_random_walk():
    arw_deg_rt_h = 0.05
    p = IruParams(1e-12, np.radians(arw_deg_rt_h) / 60.0, 0.0, 0.2)
    bias = np.array([1e-6, -2e-6, 3e-6])
    state = iru_initial_state(bias, np.zeros(3), np.zeros(3), p)
    rng = np.random.default_rng(3)
    out, n, runs = np.zeros(3), 900, []
    for _ in range(200):
        s = state.copy()
        acc = np.zeros(3)
        for _ in range(n):
            iru_sample(s, p, np.zeros(3), rng.standard_normal(6), out)
            acc += out * 0.2
        runs.append(acc)
    runs = np.array(runs)
    t = n * 0.2
    # random walk: the angle error after t has sigma ARW * sqrt(t) (IEEE Std 952 definition)
    sigma = np.radians(arw_deg_rt_h) / 60.0 * np.sqrt(t)
    assert runs.std(axis=0) == pytest.approx(np.full(3, sigma), rel=0.15)
    assert runs.mean(axis=0) == pytest.approx(bias * t, abs=4 * sigma / np.sqrt(200))


def test_star_tracker_noise_matches_seed001_accuracy():
    # seed 001: 90 arcsec about the boresight, 30 arcsec transverse (read as 3 sigma)
    rng = np.random.default_rng(11)
    q_BN = Rotation.from_rotvec([0.3, -0.2, 1.0]).as_quat(scalar_first=True)
    n_st = TP.sensors.st.st.q_BS.shape[0]
    q_out, valid = np.zeros((n_st, 4)), np.zeros(n_st, dtype=np.bool_)
    errs = []
    for _ in range(20000):
        star_tracker_sample(q_BN, TP.sensors.st.st, rng.standard_normal(3 * n_st), q_out, valid)
        q_SN_true = Rotation.from_quat(q_BN, scalar_first=True) * Rotation.from_quat(TP.sensors.st.st.q_BS[0], scalar_first=True)
        err = q_SN_true.inv() * Rotation.from_quat(q_out[0], scalar_first=True)
        errs.append(err.as_rotvec())
    three_sigma_arcsec = 3 * np.array(errs).std(axis=0) / ARCSEC
    assert three_sigma_arcsec == pytest.approx([30, 30, 90], rel=0.03)
    assert valid.all()


def test_star_tracker_boresights_76_deg_apart_in_yz_plane():
    # seed 001: "boresights are 76 deg apart and approximately parallel to the YZ plane"
    b = [Rotation.from_quat(q, scalar_first=True).apply([0, 0, 1]) for q in TP.sensors.st.st.q_BS]
    assert np.degrees(np.arccos(b[0] @ b[1])) == pytest.approx(76.0, abs=1e-6)
    assert abs(b[0][0]) < 1e-12 and abs(b[1][0]) < 1e-12
