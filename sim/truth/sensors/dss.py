"""Digital Sun sensor (seed 001 "Hardware complement": one Adcole DSS, "32-deg
square FOV ... boresight along the spacecraft X axis"; "the accuracy is 0.24
arcminutes within 10 deg of the boresight, and diminishes to 3 arcminutes as
the Sun moves towards the edges of its FOV").

Output: the two tangent-plane angles of the Sun in the sensor frame D (see
sensor_geometry.tangent_angles): alpha = atan2(s_y, s_x), toward +Y, a turn
about +Z; beta = atan2(s_z, s_x), toward +Z, a turn about -Y. The square FOV
is |alpha| <= 16 deg and |beta| <= 16 deg.

Noise (assumptions: the seed's accuracies are per-angle 3-sigma; the sigma
depends on the off-boresight angle theta): constant inside 10 deg, rising
linearly to the edge value at the FOV half-width (16 deg, the middle of an
edge), and held there out to the corners (22.1 deg).

Invalid outside the FOV, or while the lit fraction of the disk is below a
threshold (assumption: the detector needs that much light), or failed.

Faults, fault[0, slot]:
  FAULT_FAILED     > 0.5: no output (valid False, angles zero).
  FAULT_BIAS_ALPHA rad added to alpha while valid.
  FAULT_BIAS_BETA  rad added to beta while valid.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.attitude import mounting_dcm_XB
from sim.truth.sensors.sensor_geometry import (
    direction_in_sensor,
    off_boresight_angle,
    tangent_angles,
)

N_NOISE = 2                        # alpha, beta
FAULT_FAILED, FAULT_BIAS_ALPHA, FAULT_BIAS_BETA = 0, 1, 2
N_FAULT_SLOTS = 3
ARCMIN = np.pi / 180.0 / 60.0


class DssParams(NamedTuple):
    dcm_DB: np.ndarray             # (3, 3) body to sensor frame; boresight +X
    fov_half_width_rad: float      # limit of each tangent-plane angle
    inner_half_angle_rad: float    # best accuracy inside this off-boresight angle
    sigma_inner_rad: float         # 1-sigma per angle inside it
    sigma_edge_rad: float          # 1-sigma per angle at the FOV half-width and beyond
    lit_fraction_min: float


def make_dss_params(q_BD, fov_half_width_deg, inner_half_angle_deg, accuracy_inner_arcmin_3sigma,
                    accuracy_edge_arcmin_3sigma, lit_fraction_min) -> DssParams:
    return DssParams(mounting_dcm_XB(q_BD), np.radians(fov_half_width_deg), np.radians(inner_half_angle_deg),
                     accuracy_inner_arcmin_3sigma / 3.0 * ARCMIN, accuracy_edge_arcmin_3sigma / 3.0 * ARCMIN,
                     float(lit_fraction_min))


@njit(cache=True)
def dss_sigma(theta_rad, p):
    """1-sigma noise per angle (rad) at off-boresight angle theta."""
    if theta_rad <= p.inner_half_angle_rad:
        return p.sigma_inner_rad
    x = min((theta_rad - p.inner_half_angle_rad) / (p.fov_half_width_rad - p.inner_half_angle_rad), 1.0)
    return p.sigma_inner_rad + x * (p.sigma_edge_rad - p.sigma_inner_rad)


@njit(cache=True, inline="always")
def dss_sample(q_BN, sun_N, lit_fraction, p, noise, fault, angles_out, valid_out):
    """[alpha, beta] (rad) into angles_out, valid_out[0]."""
    s_D = direction_in_sensor(q_BN, sun_N, p.dcm_DB)
    alpha, beta = tangent_angles(s_D)
    in_fov = abs(alpha) <= p.fov_half_width_rad and abs(beta) <= p.fov_half_width_rad
    valid = in_fov and lit_fraction >= p.lit_fraction_min and fault[0, FAULT_FAILED] <= 0.5
    valid_out[0] = valid
    if not valid:
        angles_out[0] = 0.0
        angles_out[1] = 0.0
        return
    sigma = dss_sigma(off_boresight_angle(s_D), p)
    angles_out[0] = alpha + sigma * noise[0] + fault[0, FAULT_BIAS_ALPHA]
    angles_out[1] = beta + sigma * noise[1] + fault[0, FAULT_BIAS_BETA]
