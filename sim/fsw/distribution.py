"""Wheel torque distribution: geometry, algorithm, and what could not be delivered.

Geometry: the pseudo-inverse of the spin-axis matrix G (3 x N). A motor torque
u on the rotors puts -G u on the body, so u = -G^+ T.
Algorithm: seed 001 "Attitude control modes": the commands are scaled so the
largest stays within the software limit *and the direction of the torque
vector remains constant*.
Status: the body torque that the scaling withheld.
"""
import numpy as np
from numba import njit

from sim.linalg import matvec


def distribution_matrix(axes_B) -> np.ndarray:
    """(N, 3) matrix D with u = D T, the minimum-norm wheel torques for T."""
    return -np.linalg.pinv(np.asarray(axes_B, float).T)


@njit(cache=True, inline="always")
def distribute(torque_B, dist, limit, u_out):
    """Write wheel motor torques to u_out; return the undelivered body torque."""
    u = matvec(dist, torque_B)
    peak = np.max(np.abs(u))
    scale = 1.0
    if peak > limit:
        scale = limit / peak
    u_out[:] = u * scale
    return torque_B * (1.0 - scale)
