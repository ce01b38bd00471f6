"""Rate-integrating gyro (IRU) model.

The gyro senses the integral of the body rate (theta_int_B in the truth state)
plus bias and angle random walk, quantised to whole counts of lsb (seed 001
"Hardware complement": 0.5 arcsec/bit). The rate output is the difference of
successive counts over the sample time, so quantisation error is carried to the
next sample rather than lost; at 0.2 s this gives the seed 000 "Option three"
rate resolution of 0.5 arcsec / 0.2 s = 1.2e-5 rad/s.

State (per axis): [accumulated error angle (rad), previous count, bias (rad/s)].
"""
from typing import NamedTuple

import numpy as np
from numba import njit

ERR, PREV, BIAS = 0, 3, 6
STATE_SIZE = 9
N_NOISE = 6  # normals per sample: ARW (3), bias random walk (3)


class IruParams(NamedTuple):
    lsb_rad: float
    arw_rad_per_sqrt_s: float
    rrw_rad_s_per_sqrt_s: float
    dt: float


@njit(cache=True)
def iru_sample(state, p, theta_int_B, noise, rate_out):
    """One sample: advance bias and noise, count, and write the rate (rad/s)."""
    sq = np.sqrt(p.dt)
    for i in range(3):
        state[BIAS + i] += p.rrw_rad_s_per_sqrt_s * sq * noise[3 + i]
        state[ERR + i] += state[BIAS + i] * p.dt + p.arw_rad_per_sqrt_s * sq * noise[i]
        count = np.floor((theta_int_B[i] + state[ERR + i]) / p.lsb_rad)
        rate_out[i] = (count - state[PREV + i]) * p.lsb_rad / p.dt
        state[PREV + i] = count


def iru_initial_state(bias_rad_s, theta_int_B, omega_BN_B, p: IruParams) -> np.ndarray:
    """Prime the counter one sample back so the first output is the initial rate."""
    s = np.zeros(STATE_SIZE)
    s[BIAS:BIAS + 3] = bias_rad_s
    s[PREV:PREV + 3] = np.floor((np.asarray(theta_int_B) - np.asarray(omega_BN_B) * p.dt) / p.lsb_rad)
    return s
