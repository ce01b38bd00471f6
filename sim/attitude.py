"""Attitude math: the one quaternion convention of the whole code base.

Convention (checked against ``scipy.spatial.transform.Rotation`` in
tests/test_attitude.py):

* Quaternions are Hamilton, scalar-first ``[w, x, y, z]`` (viser's order;
  scipy's ``scalar_first=True``), unit norm.
* ``q_BN`` is the attitude of frame B relative to frame N. Its rotation
  matrix ``quat_to_dcm(q_BN)`` maps B components to N components:
  ``v_N = quat_to_dcm(q_BN) @ v_B``; i.e. it is ``dcm_NB``, and
  ``dcm_BN = dcm_NB.T`` (Basilisk's ``[BN]``). This is scipy's
  ``Rotation.from_quat(q_BN, scalar_first=True).apply(v_B) == v_N`` and
  viser's local-to-parent ``wxyz``.
* Composition: ``q_CN = quat_mul(q_BN, q_CB)`` (attitude of C relative to N
  is that of B relative to N followed by C relative to B), scipy's ``r1 * r2``.
* Kinematics with body rates: ``dq_BN/dt = 0.5 * q_BN (x) [0, omega_BN_B]``.

Error quaternion, seed 001 eq. (1): the paper writes ``q_e = +-q_c^-1 (x) q_hat``
in the GSFC product convention and feeds ``theta_e = 2 vec(q_e)`` to eq. (3)
beside eq. (2)'s ``omega_e = -omega``: both errors are "desired minus actual".
In this convention that is the rotation from the body to the commanded frame,
``q_e = +-(q_BN^* (x) q_RN)``, with the sign chosen so the scalar part is
non-negative (the shortest rotation), and ``theta_e`` is in body axes.

Every function is compiled with numba and is plain Python when read.
"""
import numpy as np
from numba import njit

ARCSEC_PER_RAD = 180.0 / np.pi * 3600.0


@njit(cache=True)
def quat_mul(p, q):
    """Hamilton product p (x) q."""
    out = np.empty(4)
    out[0] = p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3]
    out[1] = p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2]
    out[2] = p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1]
    out[3] = p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0]
    return out


@njit(cache=True)
def quat_conj(q):
    """Conjugate; the inverse of a unit quaternion (q_NB from q_BN)."""
    return np.array([q[0], -q[1], -q[2], -q[3]])


@njit(cache=True)
def quat_normalize(q):
    return q / np.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])


@njit(cache=True)
def quat_to_dcm(q):
    """Rotation matrix of q_BN: maps B components to N components (dcm_NB)."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    m = np.empty((3, 3))
    m[0, 0] = w * w + x * x - y * y - z * z
    m[0, 1] = 2.0 * (x * y - w * z)
    m[0, 2] = 2.0 * (x * z + w * y)
    m[1, 0] = 2.0 * (x * y + w * z)
    m[1, 1] = w * w - x * x + y * y - z * z
    m[1, 2] = 2.0 * (y * z - w * x)
    m[2, 0] = 2.0 * (x * z - w * y)
    m[2, 1] = 2.0 * (y * z + w * x)
    m[2, 2] = w * w - x * x - y * y + z * z
    return m


@njit(cache=True)
def dcm_to_quat(m):
    """Inverse of quat_to_dcm (Shepperd's method: pivot on the largest term
    so that no branch divides by a small number). Scalar part >= 0."""
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    q = np.empty(4)
    if tr >= m[0, 0] and tr >= m[1, 1] and tr >= m[2, 2]:
        s = 2.0 * np.sqrt(1.0 + tr)
        q[0] = 0.25 * s
        q[1] = (m[2, 1] - m[1, 2]) / s
        q[2] = (m[0, 2] - m[2, 0]) / s
        q[3] = (m[1, 0] - m[0, 1]) / s
    elif m[0, 0] >= m[1, 1] and m[0, 0] >= m[2, 2]:
        s = 2.0 * np.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q[0] = (m[2, 1] - m[1, 2]) / s
        q[1] = 0.25 * s
        q[2] = (m[0, 1] + m[1, 0]) / s
        q[3] = (m[0, 2] + m[2, 0]) / s
    elif m[1, 1] >= m[2, 2]:
        s = 2.0 * np.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q[0] = (m[0, 2] - m[2, 0]) / s
        q[1] = (m[0, 1] + m[1, 0]) / s
        q[2] = 0.25 * s
        q[3] = (m[1, 2] + m[2, 1]) / s
    else:
        s = 2.0 * np.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q[0] = (m[1, 0] - m[0, 1]) / s
        q[1] = (m[0, 2] + m[2, 0]) / s
        q[2] = (m[1, 2] + m[2, 1]) / s
        q[3] = 0.25 * s
    if q[0] < 0.0:
        q = -q
    return quat_normalize(q)


@njit(cache=True)
def quat_rotate(q, v):
    """Components in the parent frame of a vector given in the child frame:
    v_N = quat_rotate(q_BN, v_B)."""
    # v + 2w (u x v) + 2 u x (u x v), u the vector part: no matrix built.
    ux, uy, uz, w = q[1], q[2], q[3], q[0]
    tx = 2.0 * (uy * v[2] - uz * v[1])
    ty = 2.0 * (uz * v[0] - ux * v[2])
    tz = 2.0 * (ux * v[1] - uy * v[0])
    out = np.empty(3)
    out[0] = v[0] + w * tx + (uy * tz - uz * ty)
    out[1] = v[1] + w * ty + (uz * tx - ux * tz)
    out[2] = v[2] + w * tz + (ux * ty - uy * tx)
    return out


@njit(cache=True)
def quat_rotate_inv(q, v):
    """Components in the child frame of a vector given in the parent frame:
    v_B = quat_rotate_inv(q_BN, v_N)."""
    return quat_rotate(quat_conj(q), v)


@njit(cache=True)
def quat_from_rotvec(phi):
    """Quaternion of a rotation vector (axis times angle, rad)."""
    angle = np.sqrt(phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2])
    q = np.empty(4)
    q[0] = np.cos(0.5 * angle)
    # sin(a/2)/a -> 1/2 as a -> 0; the series keeps small rotations exact.
    if angle < 1e-8:
        k = 0.5 - angle * angle / 48.0
    else:
        k = np.sin(0.5 * angle) / angle
    q[1] = k * phi[0]
    q[2] = k * phi[1]
    q[3] = k * phi[2]
    return q


@njit(cache=True)
def error_quat(q_RN, q_BN):
    """Seed 001 eq. (1): rotation from the body B to the commanded frame R,
    in body axes, sign chosen so the scalar part is >= 0 (shortest way)."""
    q_e = quat_mul(quat_conj(q_BN), q_RN)
    if q_e[0] < 0.0:
        q_e = -q_e
    return q_e


@njit(cache=True)
def small_angle_error(q_e):
    """Seed 001 eq. (1): theta_e = 2 * vec(q_e), rad, body axes."""
    return 2.0 * q_e[1:4]


@njit(cache=True)
def rotation_angle(q_e):
    """Principal rotation angle (rad, in [0, pi]) of a quaternion; exact at
    both small and large angles, unlike acos(w)."""
    v = np.sqrt(q_e[1] * q_e[1] + q_e[2] * q_e[2] + q_e[3] * q_e[3])
    return 2.0 * np.arctan2(v, abs(q_e[0]))


@njit(cache=True)
def quat_derivative(q_BN, omega_BN_B, out):
    """dq_BN/dt = 0.5 q_BN (x) [0, omega_BN_B], written into out (the RK4
    loop calls this 16 times a cycle: no allocation)."""
    w, x, y, z = q_BN[0], q_BN[1], q_BN[2], q_BN[3]
    p, r, s = omega_BN_B[0], omega_BN_B[1], omega_BN_B[2]
    out[0] = 0.5 * (-x * p - y * r - z * s)
    out[1] = 0.5 * (w * p + y * s - z * r)
    out[2] = 0.5 * (w * r - x * s + z * p)
    out[3] = 0.5 * (w * s + x * r - y * p)


@njit(cache=True)
def quat_propagate(q_BN, omega_BN_B, dt):
    """Integrate body rates held constant over dt (exact for constant rate):
    q(t+dt) = q(t) (x) exp(omega dt / 2)."""
    return quat_normalize(quat_mul(q_BN, quat_from_rotvec(omega_BN_B * dt)))


@njit(cache=True)
def quat_from_mrp(sigma):
    """Modified Rodrigues parameters to quaternion (Schaub & Junkins eq. 3.130)."""
    s2 = sigma[0] * sigma[0] + sigma[1] * sigma[1] + sigma[2] * sigma[2]
    q = np.empty(4)
    q[0] = (1.0 - s2) / (1.0 + s2)
    q[1:4] = 2.0 * sigma / (1.0 + s2)
    return q


def angle_between_arcsec(q_a, q_b) -> float:
    """Angle (arcsec) of the rotation between two attitudes; for telemetry."""
    return float(rotation_angle(quat_mul(quat_conj(np.asarray(q_a, float)), np.asarray(q_b, float)))) * ARCSEC_PER_RAD


def mounting_dcm_XB(q_BX, misalignment_rad=(0.0, 0.0, 0.0)) -> np.ndarray:
    """dcm_XB of a sensor frame X mounted at q_BX (attitude of X in B, as the
    star trackers' q_BS) and then turned by a small misalignment rotation
    vector given in X axes: q_BX_true = q_BX (x) exp(misalignment)."""
    q = quat_mul(np.asarray(q_BX, float), quat_from_rotvec(np.asarray(misalignment_rad, float)))
    return np.ascontiguousarray(quat_to_dcm(q).T)
