"""Sun vector from coarse Sun sensor currents (seed 001 "Hardware complement":
each CSS "outputs a current proportional to the cosine of the sun angle
relative to the boresight"; "each set of eight eyes" suffices to calculate a
sun vector; "Safehold": the proportional law uses the CSS Sun vector).

An eye that sees the Sun reads i_k = c b_k . sun_B, c unknown (distance, lit
fraction, calibration): least squares over the lit eyes gives c sun_B, and
normalising removes c. Dark eyes say only b_k . sun_B < cos(85 deg), which is
not a linear measurement, so they are left out. With the cube-diagonal layout
at least two eyes of a set always see the Sun; when only two do (the Sun
within ~8.5 deg of a plane through two diagonals), the component along
their normal is unseen and the minimum-norm solution drops it, which costs
at most asin(sqrt(3/2) cos 85 deg) = 6.1 deg (measured with noise in
tests/test_sensors_sdo_sun.py: median 0.33 deg, worst 5.9 deg).
"""
import numpy as np
from numba import njit

from sim.fsw.masked_least_squares import masked_least_squares

RANK_TOL = 1e-6


@njit(cache=True)
def css_sun_vector(currents, valid, boresights_B, lit_threshold):
    """(sun_B unit, ok). Eyes are used when valid (trusted by the flight
    software) and reading above lit_threshold (same unit as currents); ok is
    False with fewer than two such eyes (one eye gives only a cone)."""
    use = np.empty(currents.shape[0], dtype=np.bool_)
    for k in range(currents.shape[0]):
        use[k] = valid[k] and currents[k] > lit_threshold
    v, rank = masked_least_squares(boresights_B, currents, use, RANK_TOL)
    norm = np.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    if rank < 2 or norm <= 0.0:
        return np.zeros(3), False
    return v / norm, True
