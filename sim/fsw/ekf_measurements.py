"""Measurement models of the attitude EKF (residual and sensitivity to the
error state) and the scalar Kalman update they feed.

Error state and attitude convention as in ekf_propagation.py: the true
attitude is q_BN = q_est_BN (x) exp(dtheta / 2), dtheta in body axes. Each
sensor gives a residual z (measured minus predicted at q_est_BN) and the rows
of H over dtheta; no measurement sees the gyro bias directly, so H's bias
columns are zero and are left out here.

The noises of one sensor are independent per component (R diagonal), so the
update processes one component at a time (scalar updates; no matrix
inversion). Within a sensor the components share one linearisation point:
each later component's residual is corrected by the part of the state
correction already taken (z_i - h_i . dx, Markley & Crassidis 2014 sec. 6.2's
sequential processing), and the correction is folded into the quaternion once
per sensor (the multiplicative reset, ekf.py).
"""
import numpy as np
from numba import njit

from sim.attitude import quat_conj, quat_mul, quat_rotate_inv, quat_to_dcm
from sim.linalg import matvec


@njit(cache=True)
def rotvec_of(q):
    """Rotation vector (axis times angle, rad) of a unit quaternion, the
    shortest way; exact at all angles (2 vec(q) is only first order)."""
    v = np.sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    w = q[0]
    if w < 0.0:          # q and -q are the same rotation: take the short way
        w, v_sign = -w, -1.0
    else:
        v_sign = 1.0
    if v < 1e-12:
        k = 2.0 / w      # 2 atan2(v, w) / v -> 2 / w
    else:
        k = 2.0 * np.arctan2(v, w) / v
    out = np.empty(3)
    out[0] = v_sign * k * q[1]
    out[1] = v_sign * k * q[2]
    out[2] = v_sign * k * q[3]
    return out


@njit(cache=True)
def star_tracker_residual(q_est_BN, q_SN_meas, q_BS, H_att):
    """Residual (3,) rad in the tracker frame S and H_att (3, 3) written in place.

    The tracker reports q_SN = q_BN (x) q_BS (x) exp(v_S / 2), v_S its error
    in its own axes (sim/truth/sensors/star_tracker.py; seed 001: 30 arcsec
    transverse, 90 arcsec about the boresight). Against the prediction
    q_est_BN (x) q_BS, the rotation q_est_SN^* (x) q_SN is, to first order,
    dcm_SB dtheta + v_S: the residual is that rotation's vector, with H_att =
    dcm_SB, and the tracker's anisotropic noise is diagonal in these axes."""
    q_pred_SN = quat_mul(q_est_BN, q_BS)
    z = rotvec_of(quat_mul(quat_conj(q_pred_SN), q_SN_meas))
    dcm_BS = quat_to_dcm(q_BS)     # S components to B components
    for i in range(3):
        for j in range(3):
            H_att[i, j] = dcm_BS[j, i]
    return z


@njit(cache=True)
def wrap_pi(a):
    """Angle in [-pi, pi): an estimate far off (the Sun behind it) must not
    turn a small measured angle into a residual near 2 pi."""
    return (a + np.pi) % (2.0 * np.pi) - np.pi


@njit(cache=True)
def dss_residual(q_est_BN, sun_N, angles_meas, dcm_DB, H_att):
    """Residual (2,) rad of the DSS tangent-plane angles and H_att (2, 3)
    written in place; also returns the predicted off-boresight angle (rad),
    on which the sensor's accuracy depends.

    The DSS (seed 001: boresight along body X) reports alpha = atan2(s_y, s_x)
    and beta = atan2(s_z, s_x) of the Sun unit vector s in its frame D
    (sim/truth/sensors/dss.py). The body-frame Sun vector seen at the true
    attitude is s_B = exp(dtheta)^T s_est_B = s_est_B + [s_est_B x] dtheta to
    first order, so H_att = J dcm_DB [s_est_B x], J the angles' gradient."""
    s_B = quat_rotate_inv(q_est_BN, sun_N)
    s_D = matvec(dcm_DB, s_B)
    sx, sy, sz = s_D[0], s_D[1], s_D[2]
    z = np.empty(2)
    z[0] = wrap_pi(angles_meas[0] - np.arctan2(sy, sx))
    z[1] = wrap_pi(angles_meas[1] - np.arctan2(sz, sx))
    # Gradients of alpha and beta over s_D ...
    na, nb = sx * sx + sy * sy, sx * sx + sz * sz
    ga = (-sy / na, sx / na, 0.0)
    gb = (-sz / nb, 0.0, sx / nb)
    # ... carried back to body axes (g_B = dcm_DB^T g_D); then the row of H is
    # g_B^T [s_B x], and g . (s x dtheta) = (g x s) . dtheta.
    for i in range(2):
        g = ga if i == 0 else gb
        gx = dcm_DB[0, 0] * g[0] + dcm_DB[1, 0] * g[1] + dcm_DB[2, 0] * g[2]
        gy = dcm_DB[0, 1] * g[0] + dcm_DB[1, 1] * g[1] + dcm_DB[2, 1] * g[2]
        gz = dcm_DB[0, 2] * g[0] + dcm_DB[1, 2] * g[1] + dcm_DB[2, 2] * g[2]
        H_att[i, 0] = gy * s_B[2] - gz * s_B[1]
        H_att[i, 1] = gz * s_B[0] - gx * s_B[2]
        H_att[i, 2] = gx * s_B[1] - gy * s_B[0]
    off_boresight = np.arctan2(np.sqrt(sy * sy + sz * sz), sx)
    return z, off_boresight


@njit(cache=True)
def dss_sigma(off_boresight_rad, inner_half_angle_rad, fov_half_width_rad, sigma_inner_rad, sigma_edge_rad):
    """1-sigma per angle (rad) from the sensor's data sheet, as the flight
    software's database holds it (seed 001: 0.24 arcmin within 10 deg of the
    boresight, 3 arcmin toward the FOV edges; read as 3-sigma per angle and
    rising linearly from 10 deg to the 16-deg half-width, as the truth model
    assumes)."""
    if off_boresight_rad <= inner_half_angle_rad:
        return sigma_inner_rad
    f = min((off_boresight_rad - inner_half_angle_rad) / (fov_half_width_rad - inner_half_angle_rad), 1.0)
    return sigma_inner_rad + f * (sigma_edge_rad - sigma_inner_rad)


@njit(cache=True)
def scalar_update(P, dx, h_att, z, var_R, ph):
    """One scalar measurement z = h . x + noise (variance var_R), with h's
    bias part zero. Updates dx (the correction accumulated for this sensor)
    and P in place; ph is a (6,) work array. Returns (innovation, its
    predicted variance) for telemetry and consistency checks.

    Joseph form: P+ = (I - k h^T) P (I - k h^T)^T + var_R k k^T. For a scalar
    measurement it expands to P - k ph^T - ph k^T + s k k^T (ph = P h,
    s = h^T P h + var_R), which holds for any gain k, so rounding in k
    cannot make P lose positive definiteness as the short form P - s k k^T
    can."""
    n = P.shape[0]
    for i in range(n):
        ph[i] = P[i, 0] * h_att[0] + P[i, 1] * h_att[1] + P[i, 2] * h_att[2]
    s = h_att[0] * ph[0] + h_att[1] * ph[1] + h_att[2] * ph[2] + var_R
    r = z - (h_att[0] * dx[0] + h_att[1] * dx[1] + h_att[2] * dx[2])
    for i in range(n):
        dx[i] += ph[i] / s * r
    for i in range(n):            # upper triangle, mirrored: exactly symmetric
        ki = ph[i] / s
        for j in range(i, n):
            kj = ph[j] / s
            P[i, j] = P[i, j] - ki * ph[j] - ph[i] * kj + s * ki * kj
            P[j, i] = P[i, j]
    return r, s
