"""Sun vector from coarse Sun sensor currents (seed 001 "Hardware complement":
each CSS "outputs a current proportional to the cosine of the sun angle
relative to the boresight"; "each set of eight eyes" suffices to calculate a
sun vector; "Sun Acquisition", "Safehold": the proportional law uses the CSS
Sun vector, and in eclipse only the rates are controlled).

An eye that sees the Sun reads i_k = c b_k . sun_B, c unknown (distance, lit
fraction, calibration): least squares over the lit eyes gives c sun_B, and
normalising removes c. Dark eyes say only b_k . sun_B < cos(85 deg), which is
not a linear measurement, so they are left out. With the cube-diagonal layout
at least two eyes of a set always see the Sun; when only two do (the Sun
within ~8.5 deg of a plane through two diagonals), the component along
their normal is unseen and the minimum-norm solution drops it, which costs
at most asin(sqrt(3/2) cos 85 deg) = 6.1 deg.

The minimum-norm solution is also the fall-back when the lit eyes do not span
3-D, rather than the current-weighted sum of boresights sum_k i_k b_k: for two
lit eyes it is the exact projection of the Sun on their plane, while the
weighted sum multiplies by sum_k b_k b_k^T, not the identity on that plane (two
cube diagonals are 70.5 deg apart, not 90), adding up to 4.2 deg within it.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.fsw.masked_least_squares import masked_least_squares

RANK_TOL = 1e-6
# Assumption (flight-software design): below this summed signal of a set's lit
# eyes, in full-Sun currents, the Sun is taken as eclipsed. A set in full Sun
# sums 1.61 (Sun near the midpoint of two diagonals) to 2.31 (Sun on an axis), so
# the cut is at a lit fraction of 13-19 %, where the 1.5 % 3-sigma noise still keeps
# the Sun vector within 9 deg (tests/test_css_sun.py); at 10 % it reaches 19 deg.
ECLIPSE_FRACTION = 0.3
# Assumption: two lit eyes alone are trusted while they cannot miss the Sun by
# more than this: above the 6.1-deg band with its noise, below the 15-deg need.
MAX_UNSEEN_DEG = 12.0
COS_MAX_UNSEEN = np.cos(np.radians(MAX_UNSEEN_DEG))


class CssSunParams(NamedTuple):
    boresight_B: np.ndarray   # (16, 3) unit boresights, primary 0-7 then backup 8-15 (from the spacecraft file)
    full_sun_current_A: float
    lit_threshold_A: float    # an eye reading at or below this is taken as dark
    eclipse_fraction: float   # summed lit-eye signal per set / full-Sun current below this: no Sun (eclipse)


def make_css_sun_params(sc) -> CssSunParams:
    """From sim.spacecraft.definition.Spacecraft. A spacecraft without CSS gets
    zero eyes (docs/architecture.md "Optional sensors"): never a Sun vector.
    The lit threshold is half an eye's current at its cone edge in full Sun
    (a lit eye reads at least cos(fov) of full scale; for SDO 8.7 sigma of the
    noise), raised to 5 sigma if that is higher: noise is not taken for light."""
    c = sc.sensors.css
    if c is None:
        return CssSunParams(np.zeros((0, 3)), 1.0, 1.0, ECLIPSE_FRACTION)
    b = np.vstack([np.asarray(c.boresights_primary_B, float), np.asarray(c.boresights_backup_B, float)])
    edge_A = c.full_sun_current_A * np.cos(np.radians(c.fov_half_angle_deg))
    threshold = max(0.5 * edge_A, 5.0 * c.noise_A_3sigma / 3.0, c.lsb_A)
    return CssSunParams(b / np.linalg.norm(b, axis=1)[:, None], float(c.full_sun_current_A), float(threshold),
                        ECLIPSE_FRACTION)


@njit(cache=True, inline="always")
def lit_least_squares(currents, valid, boresights_B, lit_threshold):
    """(v, rank): least squares over the valid eyes reading above lit_threshold."""
    use = np.empty(currents.shape[0], dtype=np.bool_)
    for k in range(currents.shape[0]):
        use[k] = valid[k] and currents[k] > lit_threshold
    return masked_least_squares(boresights_B, currents, use, RANK_TOL)


@njit(cache=True)
def css_sun_vector(currents, valid, boresights_B, lit_threshold):
    """(sun_B unit, ok). Eyes are used when valid (trusted by the flight
    software) and reading above lit_threshold (same unit as currents); ok is
    False with fewer than two such eyes (one eye gives only a cone)."""
    v, rank = lit_least_squares(currents, valid, boresights_B, lit_threshold)
    norm = np.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    if rank < 2 or norm <= 0.0:
        return np.zeros(3), False
    return v / norm, True


@njit(cache=True)
def css_sun_vector_B(current_A, use_set, p, sun_out_B):
    """Sun unit vector in B from the CSS currents (A, primary 0-7 then backup
    8-15) of use_set: 0 primary, 1 backup, 2 both (each ACE reads one set).
    Writes sun_out_B and returns True; returns False, leaving sun_out_B as it
    was, when there is no usable Sun: eclipse (too little signal), fewer than
    two lit eyes, or two lit eyes that may miss the Sun by over MAX_UNSEEN_DEG."""
    n = p.boresight_B.shape[0]
    half = n // 2
    lo = half if use_set == 1 else 0
    hi = half if use_set == 0 else n
    valid = np.zeros(n, dtype=np.bool_)
    total_A = 0.0
    for k in range(lo, hi):
        valid[k] = True
        if current_A[k] > p.lit_threshold_A:
            total_A += current_A[k]
    n_sets = 2.0 if hi - lo > half else 1.0
    if n == 0 or total_A < p.eclipse_fraction * p.full_sun_current_A * n_sets:
        return False
    v, rank = lit_least_squares(current_A, valid, p.boresight_B, p.lit_threshold_A)
    norm = np.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    # Lit eyes in one plane see only the Sun's projection on it, f cos(unseen
    # angle) full-Sun currents long with lit fraction f <= 1: a short projection
    # means the plane may hide a large angle (a failed eye reads as dark and can
    # leave two eyes 40-50 deg off the Sun; a partial Sun is refused too).
    if rank < 2 or norm <= 0.0 or (rank == 2 and norm < COS_MAX_UNSEEN * p.full_sun_current_A):
        return False
    for i in range(3):
        sun_out_B[i] = v[i] / norm
    return True
