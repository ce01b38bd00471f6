"""Reaction wheel tachometers (seed 001 "Safehold": the mode uses "the RWA
tachometers", and the X rate "is derived from the RWA tachometers").

Each wheel's tachometer counts pulses, pulses_per_rev of them per turn
(assumption), and the measured speed is the count over the sample times the
pulse angle over dt: the mean speed over [t_k-1, t_k], quantised to one pulse
per sample. As in the IRU (sim/truth/sensors/iru.py) the count is of an
accumulated angle, so the fraction of a pulse not counted in one sample is
counted in a later one and the long-run mean is exact. The wheel angle is not
a truth input; it is integrated here from the sampled speeds by the
trapezoidal rule (exact for a constant wheel acceleration over the sample).
No noise: counting pulses is exact.

Faults, fault[j, slot] for wheel j:
  FAULT_FAILED > 0.5: no output (valid False, speed zero).
"""
from typing import NamedTuple

import numpy as np
from numba import njit

N_NOISE = 0
FAULT_FAILED = 0
N_FAULT_SLOTS = 1
ANGLE, PREV_COUNT, PREV_SPEED = 0, 1, 2   # per-wheel state: rad, pulses, rad/s
STATE_PER_WHEEL = 3


def state_size(n_wheels: int) -> int:
    return STATE_PER_WHEEL * n_wheels


class TachometerParams(NamedTuple):
    pulse_rad: float    # wheel angle per pulse
    dt: float           # sample time (the control cycle)


def make_tachometer_params(pulses_per_rev, dt) -> TachometerParams:
    return TachometerParams(2.0 * np.pi / pulses_per_rev, float(dt))


def tachometer_initial_state(wheel_speed_rad_s) -> np.ndarray:
    """As if each wheel had turned at its initial speed over the sample before,
    so the first output is the initial speed (to one pulse)."""
    w = np.asarray(wheel_speed_rad_s, float)
    s = np.zeros(state_size(len(w)))
    s[PREV_SPEED::STATE_PER_WHEEL] = w
    return s


@njit(cache=True, inline="always")
def tachometer_sample(wheel_speed_rad_s, state, p, fault, speed_out, valid_out):
    """Measured speed of each wheel relative to the body (rad/s) at t_k."""
    for j in range(wheel_speed_rad_s.shape[0]):
        o = STATE_PER_WHEEL * j
        state[o + ANGLE] += 0.5 * (state[o + PREV_SPEED] + wheel_speed_rad_s[j]) * p.dt
        state[o + PREV_SPEED] = wheel_speed_rad_s[j]
        count = np.floor(state[o + ANGLE] / p.pulse_rad)
        speed_out[j] = (count - state[o + PREV_COUNT]) * p.pulse_rad / p.dt
        state[o + PREV_COUNT] = count
        valid_out[j] = fault[j, FAULT_FAILED] <= 0.5
        if not valid_out[j]:
            speed_out[j] = 0.0
