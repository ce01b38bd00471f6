"""Science mode's attitude errors (seed 001 "Science mode", eq. 4) and the
guide-telescope side of the autonomous Inertial -> Science transition.

    theta_e,y = S_z,   theta_e,z = -S_y                                  (4)

"where S_y and S_z are the CGT errors rotated into the body frame", each GT
measurement with a bias added "such that when the GT measurement plus bias is
zero, the spacecraft points at the SRB". Roll comes from the quaternion error
as in Inertial mode (EKF), rates from the IRU.

The biases are a ground calibration (build time, `gt_biases`). Assumption
(docs/fsw.md): post-launch alignment makes the SRB the body X axis, so the
bias of each telescope is minus its reading with X on the Sun centre, and the
identity target of the SNR frame and the GT zero agree.

A commanded SNR delta target (calibration steps small enough to keep the Sun
in the CGT's fine range, seed 000 "Introduction") offsets the GT errors by
its pitch and yaw: with target R and attitude B, both small rotations from
SNR, theta_e ~ phi_R - phi_B, and the GT reads -phi_B.
"""
import numpy as np
from numba import njit

from sim.attitude import mounting_dcm_XB, small_angle_error
from sim.constants import ARCSEC_RAD as ARCSEC
from sim.fsw.snr import TARGET_SNR_DELTA


def gt_biases(q_BG_list, misalignment_arcsec_list) -> np.ndarray:
    """(n_gt, 2) biases [b_y, b_z], rad: minus each telescope's [S_y, S_z]
    with the body X axis on the Sun (S_y = -atan2(s_y, s_x), S_z likewise,
    s the Sun in the telescope frame)."""
    out = np.empty((len(q_BG_list), 2))
    for k, (q, mis) in enumerate(zip(q_BG_list, misalignment_arcsec_list)):
        s = mounting_dcm_XB(q, np.asarray(mis, float) * ARCSEC)[:, 0]
        out[k] = np.arctan2(s[1], s[0]), np.arctan2(s[2], s[0])
    return out


# The kernels below take arrays, not the state and parameter records: every
# record handed to a function, inlined or not, costs a reference count per
# array it holds (docs/architecture.md "Inlined kernels"), and the records
# hold dozens.

@njit(cache=True, inline="always")
def cgt_errors_B(rec, k, sci, out_err_B):
    """CGT k's eq. (4) pitch and yaw errors [theta_y, theta_z] (rad) into
    out_err_B, and whether it is usable (valid and in its fine range)."""
    if k >= rec.gt_valid.shape[0]:
        return False    # a spacecraft without guide telescopes
    ok = rec.gt_valid[k] and rec.gt_in_range[k]
    ey = rec.gt_offset_G_rad[k, 0] + sci.gt_bias_G[k, 0]
    ez = rec.gt_offset_G_rad[k, 1] + sci.gt_bias_G[k, 1]
    d = sci.dcm_BG[k]
    sy = d[1, 1] * ey + d[1, 2] * ez     # [0, ey, ez] carried into body axes
    sz = d[2, 1] * ey + d[2, 2] * ez
    out_err_B[0] = sz
    out_err_B[1] = -sy
    return ok


@njit(cache=True, inline="always")
def commanded_offset_yz(target, dq_RS):
    """Pitch and yaw of the commanded SNR delta target, rad (zero otherwise)."""
    if target == TARGET_SNR_DELTA:
        phi = small_angle_error(dq_RS)
        return phi[1], phi[2]
    return 0.0, 0.0


@njit(cache=True, inline="always")
def science_errors(cgt_err_B, offset_y, offset_z, theta_quat, out_theta_e):
    """Seed 001 eq. (4) from the CGT errors plus the commanded offset, with
    roll from the quaternion error theta_quat."""
    out_theta_e[0] = theta_quat[0]
    out_theta_e[1] = cgt_err_B[0] + offset_y
    out_theta_e[2] = cgt_err_B[1] + offset_z


@njit(cache=True, inline="always")
def science_acquired(autonomy, target, cgt_ok, cgt_err_B, offset_y, offset_z, acq_range_rad):
    """Inertial's hand-over test: autonomy on, a Sun-referenced target, and
    the CGT usable with both errors (less the commanded offset) inside the
    acquisition range."""
    if not (autonomy and cgt_ok) or target > TARGET_SNR_DELTA:
        return False
    return abs(cgt_err_B[0] + offset_y) < acq_range_rad and abs(cgt_err_B[1] + offset_z) < acq_range_rad
