"""Star trackers with their exclusion zones and a dropout fault (seed 001
"Hardware complement": two A-STRs; "bright light sources are well outside
the 55-deg Sun exclusion zone provided by the A-STR shade").

The measurement itself is the existing model, sim/truth/sensors/star_tracker.py
(same noise, N_NOISE normals per tracker). This module decides whether each
tracker has a solution:
  * Sun: excluded while the angle between the boresight and the Sun is below
    the Sun half-angle (seed 001: 55 deg) and any of the disk is lit (in
    eclipse the Earth hides the Sun, and the Earth zone applies instead);
  * Earth, Moon: excluded while the angle to the body's centre is below the
    half-angle beyond the limb (assumption) plus the body's angular radius.
An invalid tracker writes the zero quaternion: it has no solution, and a
zero quaternion cannot be mistaken for an attitude.

Faults, fault[k, slot] for tracker k:
  FAULT_DROPOUT > 0.5: no output (valid False, zero quaternion).
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.attitude import quat_rotate
from sim.truth.sensors import star_tracker
from sim.truth.sensors.sensor_geometry import angle_between

N_NOISE = star_tracker.N_NOISE     # per tracker, as the base model
FAULT_DROPOUT = 0
N_FAULT_SLOTS = 1


class StarTrackerExclusionParams(NamedTuple):
    st: star_tracker.StarTrackerParams   # mounting and noise (existing model)
    boresight_B: np.ndarray              # (n_st, 3) each tracker's +Z in B
    sun_half_angle_rad: float
    earth_half_angle_rad: float          # beyond the limb
    moon_half_angle_rad: float           # beyond the limb


def make_star_tracker_exclusion_params(st: star_tracker.StarTrackerParams, sun_half_angle_deg,
                                       earth_limb_half_angle_deg, moon_limb_half_angle_deg
                                       ) -> StarTrackerExclusionParams:
    z = np.array([0.0, 0.0, 1.0])
    boresight_B = np.array([quat_rotate(np.asarray(q, float), z) for q in st.q_BS])
    return StarTrackerExclusionParams(st, boresight_B, np.radians(sun_half_angle_deg),
                                      np.radians(earth_limb_half_angle_deg), np.radians(moon_limb_half_angle_deg))


@njit(cache=True)
def excluded(boresight_N, sun_N, lit_fraction, earth_N, earth_radius_rad, moon_N, moon_radius_rad, p):
    """True while a bright body is inside the tracker's exclusion zone."""
    if lit_fraction > 0.0 and angle_between(boresight_N, sun_N) < p.sun_half_angle_rad:
        return True
    if angle_between(boresight_N, earth_N) < p.earth_half_angle_rad + earth_radius_rad:
        return True
    return angle_between(boresight_N, moon_N) < p.moon_half_angle_rad + moon_radius_rad


@njit(cache=True, inline="always")
def star_tracker_exclusion_sample(q_BN, sun_N, lit_fraction, earth_N, earth_radius_rad, moon_N, moon_radius_rad,
                                  p, noise, fault, q_out, valid_out):
    """Measure every tracker (fixed noise use), then blank those without a solution."""
    star_tracker.star_tracker_sample(q_BN, p.st, noise, q_out, valid_out)
    for k in range(q_out.shape[0]):
        boresight_N = quat_rotate(q_BN, p.boresight_B[k])
        blind = excluded(boresight_N, sun_N, lit_fraction, earth_N, earth_radius_rad, moon_N, moon_radius_rad, p)
        if blind or fault[k, FAULT_DROPOUT] > 0.5:
            valid_out[k] = False
            q_out[k, :] = 0.0
