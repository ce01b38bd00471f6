"""The four AIA guide telescopes (seed 001 "Science mode": "Each GT measures
the offset from the center of the solar disk along the Y and Z axes", within
"the 0.5-deg field-of-view for each GT"; seed 000 "Introduction": "a fine
pointing range of approximately +-95 arcsec").

Output, per telescope G (boresight +X of G), rad: S = [S_y, S_z], the offset
of the boresight from the Sun-disk centre along G's Y and Z axes,
S_y = -atan2(s_y, s_x), S_z = -atan2(s_z, s_x) with s the Sun in G. That is
the sign seed 001 eq. (4) takes: for a telescope aligned with the body,
theta_e,y = S_z and theta_e,z = -S_y are the attitude errors "desired minus
actual" of sim/attitude.py (checked in tests/test_sensors_sdo_sun.py). The
SRB biases of eq. (4) are flight software and are not added here.

Each telescope carries its own misalignment (assumption: a few to tens of
arcsec, state values), so its zero is not the body X axis. Noise: assumption,
sub-arcsec. Beyond the fine range each offset saturates at +-fine_range and
in_range is False; outside the FOV (assumption: a 0.5-deg diameter cone), in
eclipse (lit fraction below a threshold: with the limb cut the disk centre
is wrong) or failed, valid is False and the offsets are zero.

Faults, fault[k, slot] for telescope k:
  FAULT_FAILED > 0.5: no output.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.attitude import mounting_dcm_XB
from sim.constants import ARCSEC_RAD as ARCSEC
from sim.truth.sensors.sensor_geometry import (
    direction_in_sensor,
    off_boresight_angle,
    tangent_angles,
)

N_TELESCOPES = 4
N_NOISE = 2 * N_TELESCOPES         # S_y, S_z per telescope
FAULT_FAILED = 0
N_FAULT_SLOTS = 1


class GuideTelescopeParams(NamedTuple):
    dcm_GB: np.ndarray             # (4, 3, 3) body to each telescope frame, misalignment included
    fov_half_angle_rad: float
    fine_range_rad: float          # saturation of each offset
    noise_rad: float               # 1-sigma per offset
    lit_fraction_min: float


def make_guide_telescope_params(units, fov_half_angle_deg, fine_range_arcsec, noise_arcsec_3sigma,
                                lit_fraction_min) -> GuideTelescopeParams:
    """units: one mapping per telescope with q_BG (nominal mounting) and
    misalignment_arcsec (small rotation vector in G axes)."""
    dcm = np.array([mounting_dcm_XB(u["q_BG"], np.asarray(u["misalignment_arcsec"], float) * ARCSEC)
                    for u in units])
    if dcm.shape != (N_TELESCOPES, 3, 3):
        raise ValueError(f"expected {N_TELESCOPES} guide telescopes, got {len(units)}")
    return GuideTelescopeParams(dcm, np.radians(fov_half_angle_deg), fine_range_arcsec * ARCSEC,
                                noise_arcsec_3sigma / 3.0 * ARCSEC, float(lit_fraction_min))


@njit(cache=True, inline="always")
def guide_telescope_sample(q_BN, sun_N, lit_fraction, p, noise, fault, offset_out, valid_out, in_range_out):
    """offset_out (4, 2) rad, valid_out (4,), in_range_out (4,)."""
    r = p.fine_range_rad
    for k in range(p.dcm_GB.shape[0]):
        s_G = direction_in_sensor(q_BN, sun_N, p.dcm_GB[k])
        seen = off_boresight_angle(s_G) <= p.fov_half_angle_rad
        valid_out[k] = seen and lit_fraction >= p.lit_fraction_min and fault[k, FAULT_FAILED] <= 0.5
        if not valid_out[k]:
            offset_out[k, :] = 0.0
            in_range_out[k] = False
            continue
        alpha, beta = tangent_angles(s_G)
        s_y = -alpha + p.noise_rad * noise[2 * k]
        s_z = -beta + p.noise_rad * noise[2 * k + 1]
        in_range_out[k] = abs(s_y) <= r and abs(s_z) <= r
        offset_out[k, 0] = min(max(s_y, -r), r)
        offset_out[k, 1] = min(max(s_z, -r), r)
