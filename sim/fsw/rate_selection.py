"""Body rate from the IRU channels the flight software trusts (seed 001
"Hardware complement": three two-axis IRUs, single-fault tolerant; FDC
reconfigures rate selection after a unit fails).

Each channel k measures a_k . omega_BN_B; with the channels of any two units
the six-channel SDO layout still sees all three axes, and the least-squares
rate uses every trusted channel (the redundant ones average the noise).
"""
from numba import njit

from sim.fsw.masked_least_squares import masked_least_squares

RANK_TOL = 1e-9   # relative eigenvalue below which a direction counts as unseen


@njit(cache=True, inline="always")
def least_squares_rate(ch_rates, ch_axes_B, valid):
    """(omega_B rad/s, ok): ok is False when the trusted channels do not span
    all three axes; the unseen components are then zero."""
    omega_B, rank = masked_least_squares(ch_axes_B, ch_rates, valid, RANK_TOL)
    return omega_B, rank == 3
