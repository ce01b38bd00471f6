"""Attitude estimate without the Kalman filter (seed 001 "Attitude
determination and targeting": with the EKF disabled the solution is a star
tracker's quaternion or the IRU-propagated attitude)."""
from numba import njit

from sim.attitude import quat_conj, quat_mul, quat_propagate

SOURCE_STAR_TRACKER = 0
SOURCE_IRU = 1


@njit(cache=True)
def body_from_tracker(q_SN, q_BS):
    """q_BN = q_SN (x) q_BS^* : the tracker's attitude carried back to the body."""
    return quat_mul(q_SN, quat_conj(q_BS))


@njit(cache=True, inline="always")
def estimate_attitude(source, q_est_BN, rate_B, q_SN, st_valid, q_BS, dt):
    """Fly the tracker when it is valid and selected, else propagate with the
    IRU rates measured over the last cycle."""
    if source == SOURCE_STAR_TRACKER and st_valid:
        return body_from_tracker(q_SN, q_BS)
    return quat_propagate(q_est_BN, rate_B, dt)
