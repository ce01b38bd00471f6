"""Coarse Sun sensors (seed 001 "Hardware complement": sixteen Adcole CSSs in
primary and backup sets of eight; "each CSS outputs a current proportional to
the cosine of the sun angle relative to the boresight"; boresights "parallel
to the diagonals of a cube aligned with the spacecraft axes"; "each eye
covering a 170-degree cone field of view").

current_k = full_sun_current * lit_fraction * cos(angle_k) while the Sun is
inside the eye's cone (angle_k <= 85 deg), zero outside; plus electronic
noise, clipped at zero (a photodiode does not source current backwards) and
rounded to the converter's step (noise and step: assumptions).

Not modelled, and said so: Earth albedo (at geosynchronous distance the
full Earth adds 0.3 x (R_E / r)^2 = 0.7 % of the Sun's signal), the
Sun's 0.27-deg radius at the cone edge, shadowing by the spacecraft, and the
eyes' positions on the solar panels (the Sun is at infinity for a CSS).

Faults, fault[k, slot] for eye k:
  FAULT_FAILED > 0.5: the eye reads zero. There is no valid flag: a dead eye
                      looks like a dark one, which failure detection must sort out.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.attitude import quat_rotate_inv

N_EYES = 16
N_NOISE = N_EYES                   # one normal per eye per sample
FAULT_FAILED = 0
N_FAULT_SLOTS = 1


class CssParams(NamedTuple):
    boresight_B: np.ndarray    # (16, 3) unit boresights: primary set 0-7, backup set 8-15
    cos_fov: float             # cosine of the cone half-angle
    full_sun_current_A: float  # output at normal incidence, whole disk lit
    noise_A: float             # 1-sigma electronic noise
    lsb_A: float               # converter step; 0 for none


def make_css_params(boresights_primary_B, boresights_backup_B, fov_half_angle_deg, full_sun_current_A,
                    noise_A_3sigma, lsb_A) -> CssParams:
    b = np.vstack([np.asarray(boresights_primary_B, float), np.asarray(boresights_backup_B, float)])
    if b.shape != (N_EYES, 3):
        raise ValueError(f"expected two sets of 8 boresights (16 x 3), got shape {b.shape}")
    return CssParams(b / np.linalg.norm(b, axis=1)[:, None], np.cos(np.radians(fov_half_angle_deg)),
                     float(full_sun_current_A), noise_A_3sigma / 3.0, float(lsb_A))


@njit(cache=True, inline="always")
def css_sample(q_BN, sun_N, lit_fraction, p, noise, fault, current_out):
    """Every eye's current (A) at t_k."""
    sun_B = quat_rotate_inv(q_BN, sun_N)
    for k in range(p.boresight_B.shape[0]):
        b = p.boresight_B[k]
        cos_k = b[0] * sun_B[0] + b[1] * sun_B[1] + b[2] * sun_B[2]
        i = p.full_sun_current_A * lit_fraction * cos_k if cos_k >= p.cos_fov else 0.0
        i = max(i + p.noise_A * noise[k], 0.0)
        if fault[k, FAULT_FAILED] > 0.5:
            i = 0.0
        if p.lsb_A > 0.0:
            i = np.floor(i / p.lsb_A + 0.5) * p.lsb_A
        current_out[k] = i
