"""Where a direction falls in a sensor's frame: the geometry the Sun sensors
(DSS, guide telescopes) and the star-tracker exclusion zones share.

A sensor frame X is given by dcm_XB (B components to X components); its
boresight is its +X axis (seed 001 "Hardware complement": the DSS boresight
and, through the SRB, the guide telescopes point along the spacecraft X axis).
"""
import numpy as np
from numba import njit

from sim.attitude import quat_rotate_inv
from sim.linalg import matvec


@njit(cache=True)
def direction_in_sensor(q_BN, v_N, dcm_XB):
    """Components in the sensor frame of a direction given in N."""
    return matvec(dcm_XB, quat_rotate_inv(q_BN, v_N))


@njit(cache=True)
def tangent_angles(v_X):
    """The two tangent-plane angles of v about the +X boresight (rad):
    alpha = atan2(v_y, v_x), the angle of v's projection on the X-Y plane,
    positive toward +Y (a right-hand turn of the boresight about +Z);
    beta = atan2(v_z, v_x), the angle of its projection on the X-Z plane,
    positive toward +Z (a turn about -Y)."""
    return np.arctan2(v_X[1], v_X[0]), np.arctan2(v_X[2], v_X[0])


@njit(cache=True)
def angle_between(a, b):
    """Angle (rad, 0..pi) between two vectors; atan2 keeps it exact near 0
    and pi, where acos of the dot product loses half its digits."""
    cx = a[1] * b[2] - a[2] * b[1]
    cy = a[2] * b[0] - a[0] * b[2]
    cz = a[0] * b[1] - a[1] * b[0]
    dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    return np.arctan2(np.sqrt(cx * cx + cy * cy + cz * cz), dot)


@njit(cache=True)
def off_boresight_angle(v_X):
    """Angle (rad) between v and the +X boresight."""
    return np.arctan2(np.sqrt(v_X[1] * v_X[1] + v_X[2] * v_X[2]), v_X[0])
