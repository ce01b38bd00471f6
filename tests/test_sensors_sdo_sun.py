"""SDO Sun sensors against seed 001 "Hardware complement" and "Science mode"
and seed 000 "Introduction": coarse Sun sensors, digital Sun sensor, guide
telescopes; and the flight-software CSS Sun vector."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from sdo_sensor_setup import (
    ARCMIN,
    ARCSEC,
    Q_IDENTITY,
    SUITE,
    no_faults,
    quat,
    random_unit_vectors,
    rotated_toward,
)

from sim.attitude import error_quat, small_angle_error
from sim.fsw.css_sun import css_sun_vector
from sim.truth.sensors import css, dss
from sim.truth.sensors import guide_telescope as gt

CSS_P = css.make_css_params(**SUITE.css.model_dump())
DSS_P = dss.make_dss_params(**SUITE.dss.model_dump())
GT_CFG = SUITE.guide_telescopes.model_dump()
GT_P = gt.make_guide_telescope_params(**GT_CFG)
GT_ALIGNED = gt.make_guide_telescope_params(**{**GT_CFG, "units": [
    {"q_BG": [1, 0, 0, 0], "misalignment_arcsec": [0, 0, 0]}] * 4, "noise_arcsec_3sigma": 0.0})
X = np.array([1.0, 0.0, 0.0])
I_FULL = SUITE.css.full_sun_current_A
LIT_THRESHOLD = 0.04   # fraction of full scale: above the 1.5 % 3-sigma noise, below cos(85 deg) = 0.087


def css_currents(q_BN, sun_N, lit=1.0, noise=None, fault=None):
    out = np.zeros(css.N_EYES)
    css.css_sample(q_BN, sun_N, lit, CSS_P, np.zeros(css.N_NOISE) if noise is None else noise,
                   no_faults(css.N_EYES, css.N_FAULT_SLOTS) if fault is None else fault, out)
    return out


def dss_measure(sun_N, lit=1.0, noise=None, fault=None, q_BN=Q_IDENTITY):
    angles, valid = np.zeros(2), np.zeros(1, dtype=np.bool_)
    noise = np.zeros(dss.N_NOISE) if noise is None else noise
    fault = no_faults(1, dss.N_FAULT_SLOTS) if fault is None else fault
    dss.dss_sample(q_BN, sun_N, lit, DSS_P, noise, fault, angles, valid)
    return angles, bool(valid[0])


def gt_measure(sun_N, p=GT_P, lit=1.0, noise=None, fault=None, q_BN=Q_IDENTITY):
    offset = np.zeros((gt.N_TELESCOPES, 2))
    valid, in_range = np.zeros(gt.N_TELESCOPES, dtype=np.bool_), np.zeros(gt.N_TELESCOPES, dtype=np.bool_)
    gt.guide_telescope_sample(q_BN, sun_N, lit, p, np.zeros(gt.N_NOISE) if noise is None else noise,
                              no_faults(gt.N_TELESCOPES, gt.N_FAULT_SLOTS) if fault is None else fault,
                              offset, valid, in_range)
    return offset, valid, in_range


def sun_at_tangent_angles(alpha, beta):
    v = np.array([1.0, np.tan(alpha), np.tan(beta)])
    return v / np.linalg.norm(v)


# ---------------------------------------------------------------- CSS

def test_css_each_set_of_eight_covers_every_sun_direction():
    # seed 001: "each set of eight eyes provides full 4-pi-steradian coverage"
    rng = np.random.default_rng(1)
    q_BN = quat(Rotation.from_rotvec([0.4, -1.1, 0.7]))
    lit_counts = np.array([[np.count_nonzero(c[:8]), np.count_nonzero(c[8:])]
                           for c in (css_currents(q_BN, s) for s in random_unit_vectors(rng, 5000))])
    assert lit_counts.min() >= 1
    # the cube-diagonal layout does better: two eyes of a set always see the Sun
    # (css_sun_vector relies on it); four at most
    assert lit_counts.min() == 2 and lit_counts.max() == 4


def test_css_current_is_cosine_law_inside_170_deg_cone_and_zero_outside():
    eye = 0
    b_B = CSS_P.boresight_B[eye]
    lsb = SUITE.css.lsb_A
    for angle_deg in (0.0, 30.0, 60.0, 84.9):   # seed 001: current proportional to the cosine
        sun = rotated_toward(b_B, [0, 0, -1], np.radians(angle_deg))
        assert css_currents(Q_IDENTITY, sun)[eye] == pytest.approx(I_FULL * np.cos(np.radians(angle_deg)), abs=lsb / 2)
    # seed 001: 170-degree cone field of view; just outside the eye reads nothing
    assert css_currents(Q_IDENTITY, rotated_toward(b_B, [0, 0, -1], np.radians(85.1)))[eye] == 0.0
    # partial eclipse: proportional to the lit fraction of the disk
    assert css_currents(Q_IDENTITY, b_B, lit=0.3)[eye] == pytest.approx(0.3 * I_FULL, abs=lsb / 2)
    assert not css_currents(Q_IDENTITY, b_B, lit=0.0).any()


def test_css_noise_and_quantisation_match_assumed_values():
    rng = np.random.default_rng(2)
    samples = np.array([css_currents(Q_IDENTITY, X, noise=rng.standard_normal(css.N_NOISE)) for _ in range(4000)])
    lit_eyes = CSS_P.boresight_B[:, 0] > 0          # Sun on +X: the eight eyes with a +X component
    lsb = SUITE.css.lsb_A
    # the sensors section of sim/spacecraft/sdo.yaml (assumption): 1.5e-5 A 3-sigma, 12-bit step 2.44e-7 A
    assert 3 * samples[:, lit_eyes].std(axis=0) == pytest.approx(np.full(8, 1.5e-5), rel=0.06)
    assert samples[:, lit_eyes].mean(axis=0) == pytest.approx(np.full(8, I_FULL / np.sqrt(3)), abs=lsb)
    assert samples / lsb == pytest.approx(np.round(samples / lsb), abs=1e-6)
    assert samples.min() >= 0.0                    # clipped: a dark eye never reads negative


def test_css_failed_eye_reads_zero_and_no_other_eye_changes():
    noise = np.random.default_rng(3).standard_normal(css.N_NOISE)
    fault = no_faults(css.N_EYES, css.N_FAULT_SLOTS)
    fault[5, css.FAULT_FAILED] = 1.0
    sun = np.array([-0.2, 0.7, 0.3]) / np.linalg.norm([-0.2, 0.7, 0.3])
    healthy = css_currents(Q_IDENTITY, sun, noise=noise)
    faulty = css_currents(Q_IDENTITY, sun, noise=noise, fault=fault)
    assert healthy[5] > 0.3 * I_FULL and faulty[5] == 0.0
    assert np.array_equal(np.flatnonzero(healthy != faulty), [5])


def css_sun_errors_deg(rng, n, eyes):
    valid = np.zeros(css.N_EYES, dtype=np.bool_)
    valid[eyes] = True
    errors = []
    for sun_N in random_unit_vectors(rng, n):
        q_BN = quat(Rotation.random(random_state=rng))
        cur = css_currents(q_BN, sun_N, noise=rng.standard_normal(css.N_NOISE))
        sun_B, ok = css_sun_vector(cur / I_FULL, valid, CSS_P.boresight_B, LIT_THRESHOLD)
        assert ok
        truth_B = Rotation.from_quat(q_BN, scalar_first=True).inv().apply(sun_N)
        errors.append(np.degrees(np.arccos(np.clip(sun_B @ truth_B, -1, 1))))
    return np.array(errors)


@pytest.mark.parametrize("eyes", [slice(0, 8), slice(8, 16), slice(0, 16)], ids=["primary", "backup", "both"])
def test_css_sun_vector_recovers_sun_direction_from_either_set(eyes):
    errors = css_sun_errors_deg(np.random.default_rng(4), 1500, eyes)
    # Measured with the assumed noise (1500 directions, one set): median 0.33 deg, 95th
    # percentile 0.8 deg, 99th 2.1 deg, worst 5.5 deg (20000 directions: 5.9 deg), in the
    # band where only two eyes of a set see the Sun. Analytic bound of that band: the dark
    # eyes' cone edge cos(85 deg) allows a component asin(sqrt(3/2) cos 85 deg) = 6.13 deg
    # off the lit eyes' plane. Safehold needs 15 deg (seed 001 "Safehold").
    assert np.median(errors) < 0.6
    assert np.percentile(errors, 95) < 1.5
    assert errors.max() < 6.13 + 0.5


def test_css_sun_vector_needs_two_lit_eyes():
    cur = css_currents(Q_IDENTITY, X, lit=0.0)   # eclipse
    assert not css_sun_vector(cur / I_FULL, np.ones(16, dtype=np.bool_), CSS_P.boresight_B, LIT_THRESHOLD)[1]
    one_eye = np.zeros(16, dtype=np.bool_)
    one_eye[0] = True
    cur = css_currents(Q_IDENTITY, CSS_P.boresight_B[0])
    assert not css_sun_vector(cur / I_FULL, one_eye, CSS_P.boresight_B, LIT_THRESHOLD)[1]


# ---------------------------------------------------------------- DSS

def test_dss_angles_are_the_tangent_plane_angles_of_the_sun():
    rng = np.random.default_rng(5)
    for _ in range(200):
        alpha, beta = rng.uniform(-0.27, 0.27, 2)           # inside +-16 deg
        rot = Rotation.random(random_state=rng)
        sun_N = rot.apply(sun_at_tangent_angles(alpha, beta))  # seen from a body at attitude rot
        angles, valid = dss_measure(sun_N, q_BN=quat(rot))
        assert valid
        assert angles == pytest.approx([alpha, beta], abs=1e-9)


@pytest.mark.parametrize("alpha_deg, beta_deg, seen", [
    (15.99, 0.0, True), (16.01, 0.0, False), (0.0, -15.99, True), (0.0, -16.01, False),
    (15.99, 15.99, True), (-16.01, 15.99, False)])
def test_dss_square_field_of_view_32_deg(alpha_deg, beta_deg, seen):
    # seed 001: 32-deg square FOV about +X
    assert dss_measure(sun_at_tangent_angles(np.radians(alpha_deg), np.radians(beta_deg)))[1] is seen


def test_dss_sees_nothing_behind_it_or_in_eclipse():
    assert not dss_measure(-X)[1]
    # assumption (the sensors section of sim/spacecraft/sdo.yaml): needs half the disk lit
    assert not dss_measure(X, lit=0.49)[1] and dss_measure(X, lit=0.51)[1]


def dss_three_sigma_arcmin(alpha_deg, rng, n=3000):
    sun = sun_at_tangent_angles(np.radians(alpha_deg), 0.0)
    a = np.array([dss_measure(sun, noise=rng.standard_normal(2))[0] for _ in range(n)])
    return 3 * a.std(axis=0) / ARCMIN


def test_dss_accuracy_vs_off_boresight_angle():
    rng = np.random.default_rng(6)
    # seed 001: 0.24 arcmin within 10 deg of the boresight (read as 3-sigma per angle)
    for alpha_deg in (0.0, 5.0, 9.9):
        assert dss_three_sigma_arcmin(alpha_deg, rng) == pytest.approx([0.24, 0.24], rel=0.06)
    # seed 001: "diminishes to 3 arcminutes as the Sun moves towards the edges of its FOV"
    assert dss_three_sigma_arcmin(15.95, rng) == pytest.approx([3.0, 3.0], rel=0.06)
    between = dss_three_sigma_arcmin(13.0, rng)
    assert (0.3 < between).all() and (between < 2.9).all()


def test_dss_faults_change_only_what_they_name():
    sun, noise = sun_at_tangent_angles(0.05, -0.03), np.array([0.3, -1.2])
    base, _ = dss_measure(sun, noise=noise)
    for slot, expect in ((dss.FAULT_BIAS_ALPHA, [1e-3, 0.0]), (dss.FAULT_BIAS_BETA, [0.0, 1e-3])):
        fault = no_faults(1, dss.N_FAULT_SLOTS)
        fault[0, slot] = 1e-3
        angles, valid = dss_measure(sun, noise=noise, fault=fault)
        assert valid and angles - base == pytest.approx(expect, abs=1e-15)
    fault = no_faults(1, dss.N_FAULT_SLOTS)
    fault[0, dss.FAULT_FAILED] = 1.0
    assert dss_measure(sun, noise=noise, fault=fault)[1] is False


# ---------------------------------------------------------------- guide telescopes

def test_gt_offsets_give_seed001_eq4_attitude_errors():
    # seed 001 eq. (4): theta_e,y = S_z, theta_e,z = -S_y for a telescope aligned with B,
    # theta_e the error to the Sun-pointing target (sim/attitude.py error_quat).
    rng = np.random.default_rng(7)
    for _ in range(300):
        q_BN = quat(Rotation.from_rotvec(rng.uniform(-60, 60, 3) * ARCSEC))
        offset, valid, in_range = gt_measure(X, p=GT_ALIGNED, q_BN=q_BN)
        theta_e = small_angle_error(error_quat(Q_IDENTITY, q_BN))   # target: X on the Sun (sun_N = X)
        assert valid.all() and in_range.all()
        # second-order terms of 85 arcsec: < 0.04 arcsec
        assert offset[:, 1] == pytest.approx(np.full(4, theta_e[1]), abs=0.05 * ARCSEC)
        assert offset[:, 0] == pytest.approx(np.full(4, -theta_e[2]), abs=0.05 * ARCSEC)


def test_gt_offsets_in_each_misaligned_frame_match_scipy_geometry():
    rng = np.random.default_rng(8)
    p = gt.make_guide_telescope_params(**{**GT_CFG, "noise_arcsec_3sigma": 0.0})
    for _ in range(200):
        rot = Rotation.from_rotvec(rng.uniform(-300, 300, 3) * ARCSEC)
        offset, valid, _ = gt_measure(X, p=p, q_BN=quat(rot))
        for k, unit in enumerate(SUITE.guide_telescopes.units):
            r_BG = Rotation.from_quat(unit.q_BG, scalar_first=True) * Rotation.from_rotvec(
                np.array(unit.misalignment_arcsec) * ARCSEC)
            s_G = (rot * r_BG).inv().apply(X)
            expect = np.clip(-np.arctan2(s_G[1:], s_G[0]), -95 * ARCSEC, 95 * ARCSEC)
            assert valid[k] and offset[k] == pytest.approx(expect, abs=1e-6 * ARCSEC)


def test_gt_misalignment_shifts_the_zero():
    # Sun exactly on the body X axis: each telescope reads its own misalignment phi
    # (small rotation in G): S = (phi_z, -phi_y) to first order; the roll part phi_x
    # enters only at second order, |phi|^2 ~ (70 arcsec)^2 = 0.024 arcsec.
    offset, valid, _ = gt_measure(X, p=gt.make_guide_telescope_params(**{**GT_CFG, "noise_arcsec_3sigma": 0.0}))
    phi = np.array([u.misalignment_arcsec for u in SUITE.guide_telescopes.units])
    assert valid.all()
    assert offset / ARCSEC == pytest.approx(np.column_stack([phi[:, 2], -phi[:, 1]]), abs=0.03)


def test_gt_saturates_at_the_95_arcsec_fine_range():
    # seed 000 "Introduction": fine pointing range of approximately +-95 arcsec
    for off_arcsec, in_fine in ((94.0, True), (96.0, False), (300.0, False)):
        offset, valid, in_range = gt_measure(sun_at_tangent_angles(off_arcsec * ARCSEC, 0.0), p=GT_ALIGNED)
        assert valid.all() and (in_range == in_fine).all()
        assert offset[:, 0] / ARCSEC == pytest.approx(np.full(4, -min(off_arcsec, 95.0)), abs=1e-6)


def test_gt_field_of_view_is_half_a_degree():
    # seed 001 "Science mode": 0.5-deg field of view (assumption: a cone of that diameter)
    assert gt_measure(sun_at_tangent_angles(0.0, np.radians(0.249)), p=GT_ALIGNED)[1].all()
    assert not gt_measure(sun_at_tangent_angles(0.0, np.radians(0.251)), p=GT_ALIGNED)[1].any()


def test_gt_noise_is_sub_arcsec():
    rng = np.random.default_rng(9)
    offsets = np.array([gt_measure(X, p=GT_P, noise=rng.standard_normal(gt.N_NOISE))[0] for _ in range(3000)])
    # assumption (the sensors section of sim/spacecraft/sdo.yaml): 0.5 arcsec 3-sigma per offset
    assert 3 * offsets.std(axis=0) / ARCSEC == pytest.approx(np.full((4, 2), 0.5), rel=0.06)


def test_gt_eclipse_and_failure():
    assert not gt_measure(X, lit=0.98)[1].any()      # assumption: a cut limb spoils the centre
    fault = no_faults(gt.N_TELESCOPES, gt.N_FAULT_SLOTS)
    fault[2, gt.FAULT_FAILED] = 1.0
    noise = np.random.default_rng(10).standard_normal(gt.N_NOISE)
    healthy, faulty = gt_measure(X, noise=noise), gt_measure(X, noise=noise, fault=fault)
    assert list(faulty[1]) == [True, True, False, True] and not faulty[0][2].any()
    others = [0, 1, 3]
    assert np.array_equal(healthy[0][others], faulty[0][others])
