"""Star tracker model: the attitude of the sensor frame S (boresight +Z),
rotated by a small random error drawn in S axes with separate transverse
(X, Y) and boresight (Z) sigmas (seed 001 "Hardware complement")."""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.attitude import quat_from_rotvec, quat_mul

N_NOISE = 3  # normals per tracker per sample


class StarTrackerParams(NamedTuple):
    q_BS: np.ndarray    # (n_st, 4) mounting
    sigma_S: np.ndarray  # (n_st, 3) 1-sigma error about S's X, Y (transverse) and Z (boresight), rad


@njit(cache=True)
def star_tracker_sample(q_BN, p, noise, q_out, valid_out):
    for k in range(p.q_BS.shape[0]):
        q_SN = quat_mul(q_BN, p.q_BS[k])
        err = quat_from_rotvec(p.sigma_S[k] * noise[3 * k:3 * k + 3])
        q_out[k] = quat_mul(q_SN, err)
        valid_out[k] = True
