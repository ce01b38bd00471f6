"""sim/attitude.py against scipy.spatial.transform.Rotation (scalar_first=True).

scipy is the oracle for every function: the convention at the top of
sim/attitude.py says q_BN is scipy's ``Rotation.from_quat(q_BN,
scalar_first=True)``, composition is scipy's ``r1 * r2`` and ``quat_to_dcm`` is
``as_matrix()``. Random rotations are uniform on SO(3) (normalised 4-D Gaussian
draws) from a seeded numpy Generator, plus near-identity rotations (1e-9 to 1e-6
rad), rotations near 180 deg and antipodal pairs q, -q.

Tolerances: a unit-quaternion or DCM component error of e is a rotation error of
at most ~2e, so 1e-14 on components is ~2e-14 rad = 4e-9 arcsec, a few hundred
times float64 round-off (2.2e-16) on O(1) numbers.
"""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from sim.attitude import (
    ARCSEC_PER_RAD,
    angle_between_arcsec,
    dcm_to_quat,
    error_quat,
    quat_conj,
    quat_derivative,
    quat_from_mrp,
    quat_from_rotvec,
    quat_mul,
    quat_propagate,
    quat_rotate,
    quat_rotate_inv,
    quat_to_dcm,
    rotation_angle,
    small_angle_error,
)

N_DRAWS = 200
COMP_TOL = 1e-14   # quaternion / DCM component, ~2e-14 rad = 4e-9 arcsec
ARCSEC = np.pi / 180.0 / 3600.0  # rad per arcsec, by definition (1 deg = 3600 arcsec)


def R(q):
    return Rotation.from_quat(q, scalar_first=True)


def sq(r):
    return r.as_quat(scalar_first=True)


def random_quats(rng, n=N_DRAWS):
    """Uniform on SO(3): a normalised 4-D Gaussian (Shoemake). Signs random, so
    about half of them have a negative scalar part."""
    q = rng.standard_normal((n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def random_axes(rng, n=N_DRAWS):
    a = rng.standard_normal((n, 3))
    return a / np.linalg.norm(a, axis=1, keepdims=True)


def tiny_rotvecs(rng, n=N_DRAWS, lo=-9.0, hi=-6.0):
    """Rotation vectors with angles log-uniform in [1e-9, 1e-6] rad."""
    return random_axes(rng, n) * 10.0 ** rng.uniform(lo, hi, n)[:, None]


def near_identity_quats(rng, n=N_DRAWS):
    return np.array([sq(Rotation.from_rotvec(v)) for v in tiny_rotvecs(rng, n)])


def near_pi_quats(rng):
    """Rotations of pi - d (d from 0 to 1e-3 rad) about random axes and about the
    coordinate axes, so that every branch of Shepperd's method is taken (a pi
    rotation about x makes m[0,0] the largest diagonal term, etc.)."""
    axes = np.vstack([random_axes(rng, 60), np.eye(3), -np.eye(3),
                      # axes close to a coordinate axis and near ties between two
                      np.array([[1.0, 1e-7, 0.0], [0.0, 1.0, 1e-9], [1e-8, 0.0, 1.0],
                                [1.0, 1.0, 0.0], [0.0, 1.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0]])])
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    out = []
    for a in axes:
        for d in (0.0, 1e-12, 1e-9, 1e-6, 1e-3):
            out.append(sq(Rotation.from_rotvec(a * (np.pi - d))))
    return np.array(out)


@pytest.fixture
def rng():
    return np.random.default_rng(20240601)


def all_quats(rng):
    return np.vstack([random_quats(rng), near_identity_quats(rng), near_pi_quats(rng),
                      [[1.0, 0, 0, 0], [-1.0, 0, 0, 0]]])


# --- quat_mul -----------------------------------------------------------------

def test_quat_mul_is_scipy_composition(rng):
    """quat_mul(p, q) == (R(p) * R(q)) component for component (scipy does not
    canonicalise the sign of a product, so the Hamilton sign is checked too)."""
    P, Q = random_quats(rng), random_quats(rng)
    for p, q in zip(P, Q):
        np.testing.assert_allclose(quat_mul(p, q), sq(R(p) * R(q)), rtol=0, atol=COMP_TOL)
    # composition of tiny rotations with big ones
    for p, q in zip(near_identity_quats(rng), random_quats(rng)):
        np.testing.assert_allclose(quat_mul(p, q), sq(R(p) * R(q)), rtol=0, atol=COMP_TOL)
        np.testing.assert_allclose(quat_mul(q, p), sq(R(q) * R(p)), rtol=0, atol=COMP_TOL)


def test_quat_mul_hamilton_units():
    """Hamilton's rules i^2 = j^2 = k^2 = ijk = -1: ij = k, jk = i, ki = j, ji = -k."""
    one, i, j, k = np.eye(4)
    np.testing.assert_array_equal(quat_mul(i, j), k)
    np.testing.assert_array_equal(quat_mul(j, k), i)
    np.testing.assert_array_equal(quat_mul(k, i), j)
    np.testing.assert_array_equal(quat_mul(j, i), -k)
    for u in (i, j, k):
        np.testing.assert_array_equal(quat_mul(u, u), -one)
    np.testing.assert_array_equal(quat_mul(quat_mul(i, j), k), -one)


def test_quat_mul_composes_dcms(rng):
    """Convention (sim/attitude.py docstring): q_CN = q_BN (x) q_CB, so
    dcm_NC = dcm_NB @ dcm_BC, i.e. as_matrix() of the product is the matrix product."""
    for p, q in zip(random_quats(rng), random_quats(rng)):
        np.testing.assert_allclose(R(quat_mul(p, q)).as_matrix(), R(p).as_matrix() @ R(q).as_matrix(),
                                   rtol=0, atol=COMP_TOL)


# --- quat_conj ----------------------------------------------------------------

def test_quat_conj_is_scipy_inverse(rng):
    for q in all_quats(rng):
        c = quat_conj(q)
        np.testing.assert_allclose(c, sq(R(q).inv()), rtol=0, atol=COMP_TOL)
        # q (x) q^* is the identity quaternion [1, 0, 0, 0] exactly up to round-off
        np.testing.assert_allclose(quat_mul(q, c), [1.0, 0, 0, 0], rtol=0, atol=COMP_TOL)


# --- quat_to_dcm / dcm_to_quat ------------------------------------------------

def test_quat_to_dcm_is_scipy_as_matrix(rng):
    for q in all_quats(rng):
        m = quat_to_dcm(q)
        np.testing.assert_allclose(m, R(q).as_matrix(), rtol=0, atol=COMP_TOL)
        # orthonormal, det +1 (a proper rotation)
        np.testing.assert_allclose(m @ m.T, np.eye(3), rtol=0, atol=COMP_TOL)
        assert abs(np.linalg.det(m) - 1.0) < COMP_TOL


def test_quat_to_dcm_antipodal_pairs_agree(rng):
    """q and -q are the same attitude: identical DCMs (the formula is quadratic
    in q, so they agree to the last bit)."""
    for q in all_quats(rng):
        np.testing.assert_array_equal(quat_to_dcm(q), quat_to_dcm(-q))


def test_quat_to_dcm_maps_B_to_N(rng):
    """Convention: v_N = quat_to_dcm(q_BN) @ v_B, scipy's R(q_BN).apply(v_B)."""
    V = rng.standard_normal((N_DRAWS, 3))
    for q, v in zip(random_quats(rng), V):
        np.testing.assert_allclose(quat_to_dcm(q) @ v, R(q).apply(v), rtol=0, atol=COMP_TOL * 10)


def _same_rotation_up_to_sign(q_got, q_want, atol):
    d = min(np.max(np.abs(q_got - q_want)), np.max(np.abs(q_got + q_want)))
    return d <= atol


def test_dcm_to_quat_round_trip(rng):
    """dcm_to_quat(as_matrix(q)) == +-q with scalar part >= 0 (its docstring); on
    random, near-identity and near-180-deg rotations (Shepperd's four branches).
    Near 180 deg the scalar part is ~0 and its sign is free, so compare up to sign
    there; everywhere else the sign is fixed by w >= 0."""
    for q in all_quats(rng):
        m = R(q).as_matrix()                  # oracle matrix, not quat_to_dcm
        got = dcm_to_quat(m)
        assert got[0] >= 0.0
        assert abs(np.linalg.norm(got) - 1.0) < 1e-15 * 4
        assert _same_rotation_up_to_sign(got, q, 2 * COMP_TOL), (q, got)
        want = q if q[0] >= 0 else -q
        if abs(want[0]) > 1e-6:
            np.testing.assert_allclose(got, want, rtol=0, atol=2 * COMP_TOL)
        # and back: the rotation it gives is the matrix it was given
        np.testing.assert_allclose(R(got).as_matrix(), m, rtol=0, atol=4 * COMP_TOL)


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_dcm_to_quat_exact_half_turns(axis):
    """pi about x, y, z: hand result [0, e_axis] (up to sign), each a different
    Shepperd branch (diag of the DCM is +1 on the axis and -1 elsewhere)."""
    m = -np.eye(3)
    m[axis, axis] = 1.0
    q = dcm_to_quat(m)
    want = np.zeros(4)
    want[1 + axis] = 1.0
    assert _same_rotation_up_to_sign(q, want, 1e-15)


def test_dcm_to_quat_near_pi_accuracy(rng):
    """Rotation angle of q_oracle^* (x) dcm_to_quat(m) below 1e-6 arcsec
    (~5e-12 rad): Shepperd never divides by a small number, so accuracy does not
    degrade as the angle nears pi (where acos/trace methods lose ~1e-8 rad)."""
    for q in near_pi_quats(rng):
        got = dcm_to_quat(R(q).as_matrix())
        err = (R(q).inv() * R(got)).magnitude()
        assert err < 1e-6 * ARCSEC, err / ARCSEC


# --- quat_rotate / quat_rotate_inv --------------------------------------------

def test_quat_rotate_is_scipy_apply(rng):
    Q = all_quats(rng)
    V = rng.standard_normal((len(Q), 3)) * 10.0 ** rng.uniform(-3, 3, (len(Q), 1))
    for q, v in zip(Q, V):
        scale = np.linalg.norm(v)
        # 1e-14 relative to |v| is ~2e-14 rad of direction (4e-9 arcsec)
        np.testing.assert_allclose(quat_rotate(q, v), R(q).apply(v), rtol=0, atol=COMP_TOL * scale)
        np.testing.assert_allclose(quat_rotate_inv(q, v), R(q).inv().apply(v), rtol=0, atol=COMP_TOL * scale)
        # antipodal: -q rotates the same way
        np.testing.assert_allclose(quat_rotate(-q, v), R(q).apply(v), rtol=0, atol=COMP_TOL * scale)
        # inverse of each other
        np.testing.assert_allclose(quat_rotate_inv(q, quat_rotate(q, v)), v, rtol=0, atol=2 * COMP_TOL * scale)


# --- quat_from_rotvec ---------------------------------------------------------

def test_quat_from_rotvec_is_scipy(rng):
    """Angles 0..2pi (scipy's from_rotvec gives w = cos(angle/2), negative past
    pi, without canonicalising: compared component for component)."""
    phis = random_axes(rng) * rng.uniform(0.0, 2 * np.pi, N_DRAWS)[:, None]
    for phi in phis:
        np.testing.assert_allclose(quat_from_rotvec(phi), sq(Rotation.from_rotvec(phi)), rtol=0, atol=COMP_TOL)


def test_quat_from_rotvec_tiny_angles(rng):
    """Angles 1e-12..1e-6 rad, either side of the series switch at 1e-8 rad. The
    vector part is ~angle/2, so it is compared *relative* to the angle: 1e-13 of
    the angle (a 1e-6 rad rotation reproduced to 1e-19 rad). The scalar part is
    cos(angle/2) = 1 - angle^2/8 and compared absolutely (1e-16)."""
    phis = tiny_rotvecs(rng, N_DRAWS, -12.0, -6.0)
    phis = np.vstack([phis, [[0.0, 0.0, 0.0]],
                      random_axes(rng, 4) * np.array([[1e-8 * (1 - 1e-12)], [1e-8], [1e-8 * (1 + 1e-12)], [2e-8]])])
    for phi in phis:
        got = quat_from_rotvec(phi)
        want = sq(Rotation.from_rotvec(phi))
        angle = np.linalg.norm(phi)
        assert abs(got[0] - want[0]) <= 1.2e-16
        np.testing.assert_allclose(got[1:], want[1:], rtol=0, atol=1e-13 * angle + 1e-300)
        # and the exact relation vec = phi/2 * (1 - angle^2/24): relative 1e-13
        np.testing.assert_allclose(got[1:], 0.5 * phi * (1.0 - angle * angle / 24.0), rtol=1e-13, atol=0)


# --- error_quat / small_angle_error / rotation_angle --------------------------

def test_error_quat_is_scipy_relative_rotation(rng):
    """error_quat(q_RN, q_BN) = +-(q_BN^* (x) q_RN) with scalar >= 0, the rotation
    R(q_BN).inv() * R(q_RN) (module docstring), i.e. from B to R in B axes."""
    QR, QB = random_quats(rng), random_quats(rng)
    for q_RN, q_BN in zip(QR, QB):
        q_e = error_quat(q_RN, q_BN)
        assert q_e[0] >= 0.0
        want = sq(R(q_BN).inv() * R(q_RN))
        if want[0] < 0:
            want = -want
        np.testing.assert_allclose(q_e, want, rtol=0, atol=COMP_TOL)
        # B rotated by q_e is R: q_BN (x) q_e = +-q_RN
        assert _same_rotation_up_to_sign(quat_mul(q_BN, q_e), q_RN, 2 * COMP_TOL)
        # the sign of either input does not matter
        for a, b in ((-q_RN, q_BN), (q_RN, -q_BN), (-q_RN, -q_BN)):
            np.testing.assert_allclose(error_quat(a, b), q_e, rtol=0, atol=0)


def test_error_quat_antipodal_is_identity(rng):
    """error_quat(q, -q) and error_quat(-q, q): the same attitude, so identity
    [1, 0, 0, 0] with positive scalar part (not [-1, 0, 0, 0])."""
    for q in all_quats(rng):
        for a, b in ((q, -q), (-q, q), (q, q)):
            e = error_quat(a, b)
            assert e[0] > 0.0
            np.testing.assert_allclose(e, [1.0, 0, 0, 0], rtol=0, atol=COMP_TOL)


def test_error_quat_near_identity_pairs(rng):
    """Body 1e-9..1e-6 rad off the reference, either sign of either quaternion:
    the error's rotation vector is scipy's (R_B^-1 R_R).as_rotvec() to 1e-9 arcsec."""
    QR = random_quats(rng)
    for q_RN, dphi in zip(QR, tiny_rotvecs(rng)):
        q_BN = sq(R(q_RN) * Rotation.from_rotvec(dphi))
        want = (R(q_BN).inv() * R(q_RN)).as_rotvec()    # = -dphi
        for s in (1.0, -1.0):
            e = error_quat(s * q_RN, q_BN)
            assert e[0] > 0.0
            np.testing.assert_allclose(small_angle_error(e), want, rtol=0, atol=1e-9 * ARCSEC)
            np.testing.assert_allclose(small_angle_error(e), -dphi, rtol=0, atol=1e-9 * ARCSEC)


def test_small_angle_error_matches_rotvec(rng):
    """theta_e = 2 vec(q_e) vs the exact rotation vector of the error, errors up to
    1e-3 rad (206 arcsec): 2 sin(a/2) differs from a by a^3/24 <= 4.2e-11 rad
    = 8.6e-6 arcsec; tolerance 1e-5 arcsec."""
    QB = random_quats(rng)
    errs = random_axes(rng) * 10.0 ** rng.uniform(-9.0, -3.0, N_DRAWS)[:, None]
    for q_BN, phi in zip(QB, errs):
        q_RN = sq(R(q_BN) * Rotation.from_rotvec(phi))   # R is B rotated by phi (body axes)
        theta = small_angle_error(error_quat(q_RN, q_BN))
        want = (R(q_BN).inv() * R(q_RN)).as_rotvec()
        assert np.max(np.abs(theta - want)) / ARCSEC < 1e-5
        assert np.max(np.abs(theta - phi)) / ARCSEC < 1e-5
    # and it is exactly 2 * vec: hand value for a 90 deg turn about z, 2 sin 45 deg = sqrt 2
    np.testing.assert_allclose(small_angle_error(np.array([np.sqrt(0.5), 0, 0, np.sqrt(0.5)])),
                               [0, 0, np.sqrt(2.0)], rtol=1e-15)


def test_rotation_angle_is_scipy_magnitude(rng):
    """Angle in [0, pi] for q and -q; absolute 1e-14 rad (2e-9 arcsec) plus
    relative 1e-12 so that 1e-9-rad angles are held to 1e-21 rad."""
    for q in all_quats(rng):
        want = R(q).magnitude()
        for s in (1.0, -1.0):
            a = rotation_angle(s * q)
            assert 0.0 <= a <= np.pi
            assert abs(a - want) <= 1e-14 + 1e-12 * want, (q, a, want)
    # tiny angles: relative to the angle (acos(w) would give 0 here)
    for phi in tiny_rotvecs(rng):
        q = quat_from_rotvec(phi)
        assert abs(rotation_angle(q) - np.linalg.norm(phi)) <= 1e-13 * np.linalg.norm(phi)


# --- quat_propagate / quat_derivative -----------------------------------------

def test_quat_propagate_is_rotvec_composition(rng):
    """One step: q (x) exp(omega dt / 2) is scipy R(q) * from_rotvec(omega dt)."""
    Q = random_quats(rng)
    W = rng.standard_normal((N_DRAWS, 3)) * 10.0 ** rng.uniform(-6, 0, (N_DRAWS, 1))   # rad/s
    DT = 10.0 ** rng.uniform(-3, 1, N_DRAWS)                                          # s
    for q, w, dt in zip(Q, W, DT):
        want = sq(R(q) * Rotation.from_rotvec(w * dt))
        got = quat_propagate(q, w, dt)
        np.testing.assert_allclose(got, want, rtol=0, atol=COMP_TOL)


def test_quat_propagate_constant_rate_many_steps(rng):
    """Constant body rate: 1000 steps of dt equal one rotation of omega * 1000 dt
    (exact for constant rate, its docstring). Round-off grows ~sqrt(1000): 1e-6
    arcsec tolerance (5e-12 rad)."""
    for q0, w in zip(random_quats(rng, 10), rng.standard_normal((10, 3)) * 0.01):
        q = q0.copy()
        dt = 0.05
        for _ in range(1000):
            q = quat_propagate(q, w, dt)
        want = R(q0) * Rotation.from_rotvec(w * dt * 1000)
        err = (want.inv() * R(q)).magnitude()
        assert err < 1e-6 * ARCSEC, err / ARCSEC


def test_quat_derivative_vs_finite_difference(rng):
    """quat_derivative(q, omega, out) writes dq/dt into out; central difference of
    quat_propagate with h = 1e-4 s: truncation h^2 |omega|^3 / 24 <= 6e-10 /s for
    |omega| <= 3 rad/s, round-off eps/h ~ 2e-12 /s; tolerance 2e-9 /s."""
    Q = random_quats(rng)
    W = rng.standard_normal((N_DRAWS, 3)) * 10.0 ** rng.uniform(-4, 0, (N_DRAWS, 1))
    h = 1e-4
    for q, w in zip(Q, W):
        out = np.full(4, np.nan)
        ret = quat_derivative(q, w, out)
        assert ret is None
        fd = (quat_propagate(q, w, h) - quat_propagate(q, w, -h)) / (2 * h)
        np.testing.assert_allclose(out, fd, rtol=0, atol=2e-9)
        # and the kinematics 0.5 q (x) [0, w] with scipy's product (exact formula)
        want = 0.5 * sq(R(q) * Rotation.from_quat(np.r_[0.0, w] / np.linalg.norm(w), scalar_first=True)) \
            * np.linalg.norm(w)
        np.testing.assert_allclose(out, want, rtol=0, atol=COMP_TOL * np.linalg.norm(w))
        # dq/dt is orthogonal to a unit q (|q| = 1 is preserved)
        assert abs(np.dot(out, q)) < COMP_TOL * np.linalg.norm(w)


def test_quat_derivative_writes_into_slice():
    """The RK4 loop passes a view of the state-derivative vector: the values must
    land in the caller's array. Hand value: q = identity, omega = [2, 0, 0] gives
    0.5 [1,0,0,0] (x) [0,2,0,0] = [0, 1, 0, 0]."""
    buf = np.full(10, -7.0)
    quat_derivative(np.array([1.0, 0, 0, 0]), np.array([2.0, 0, 0]), buf[3:7])
    np.testing.assert_array_equal(buf, [-7, -7, -7, 0, 1, 0, 0, -7, -7, -7])


# --- quat_from_mrp ------------------------------------------------------------

def test_quat_from_mrp_is_scipy(rng):
    """|sigma| up to 1 (the principal set, w >= 0: compared component for
    component) and past 1 (the shadow set, same attitude: up to sign)."""
    sig = random_axes(rng) * rng.uniform(0.0, 1.0, N_DRAWS)[:, None]
    for s in sig:
        np.testing.assert_allclose(quat_from_mrp(s), sq(Rotation.from_mrp(s)), rtol=0, atol=COMP_TOL)
    sig = random_axes(rng) * rng.uniform(1.0, 50.0, N_DRAWS)[:, None]
    for s in sig:
        got = quat_from_mrp(s)
        assert abs(np.linalg.norm(got) - 1.0) < COMP_TOL
        assert _same_rotation_up_to_sign(got, sq(Rotation.from_mrp(s)), COMP_TOL)
    # sigma = tan(angle/4) * axis (Schaub & Junkins eq. 3.130): 90 deg about y
    np.testing.assert_allclose(quat_from_mrp(np.array([0.0, np.tan(np.pi / 8), 0.0])),
                               [np.cos(np.pi / 4), 0, np.sin(np.pi / 4), 0], rtol=0, atol=1e-15)


# --- angle_between_arcsec -----------------------------------------------------

def test_angle_between_arcsec_is_scipy(rng):
    """(R_a^-1 R_b).magnitude() in arcsec; 1e-9 arcsec plus 1e-12 relative."""
    assert ARCSEC_PER_RAD == pytest.approx(206264.80624709636, rel=1e-15)   # 180 * 3600 / pi
    QA, QB = random_quats(rng), random_quats(rng)
    for qa, qb in zip(QA, QB):
        want = (R(qa).inv() * R(qb)).magnitude() / ARCSEC
        for s in (1.0, -1.0):
            got = angle_between_arcsec(qa, s * qb)
            assert isinstance(got, float)
            assert abs(got - want) <= 1e-9 + 1e-12 * want
        assert abs(angle_between_arcsec(qb, qa) - want) <= 1e-9 + 1e-12 * want
    # near-identity: 1e-9..1e-6 rad = 2e-4..0.2 arcsec, held to 1e-9 arcsec
    for qa, dphi in zip(QA, tiny_rotvecs(rng)):
        qb = sq(R(qa) * Rotation.from_rotvec(dphi))
        want = np.linalg.norm(dphi) / ARCSEC
        assert abs(angle_between_arcsec(qa, qb) - want) <= 1e-9  # 5e-15 rad: round-off of qb
        # antipodal: the same attitude is 0 arcsec away; lists are accepted
        assert angle_between_arcsec(list(qa), list(-qa)) < 1e-9   # round-off only (5e-15 rad)
