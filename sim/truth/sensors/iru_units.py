"""The three two-axis IRUs of SDO as six rate channels (seed 001 "Hardware
complement": three Kearfott TARA units, each sensing rate in two orthogonal
directions, 0.5 arcsec/bit; single-fault tolerant; the sensor "maintains the
correct rate polarity up to 10 deg/sec").

Each channel senses the integral of the body rate along its own axis,
a_k . theta_int_B, and is counted and differenced exactly as the single-unit
model in sim/truth/sensors/iru.py (quantisation error carried to the next
sample, per-channel bias, bias random walk, angle random walk): this module
feeds that counter two triplets of channel angles rather than copying it.

High rates (assumption; the seed gives only the polarity limit): the
rebalance loop cannot follow more than rate_max_rad_s, so over a sample the
channel angle advances at most rate_max * dt. Above the limit the channel
reports +-rate_max with the true sign and flags itself not valid.

Faults, fault[k, slot] for channel k (a silent fault keeps valid True: the
unit does not know, failure detection must find it):
  FAULT_STUCK       > 0.5: the output holds the last value it had before.
  FAULT_EXCESS_BIAS rad/s added to the channel's rate (integrated into its
                    angle, so it is quantised like the rest).
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.truth.sensors import iru

N_CHANNELS = 6
# seed 001: three two-axis units; assumption: unit 1 senses X, Y; unit 2 Y, Z;
# unit 3 Z, X, so any two units still sense all three body axes.
UNIT_OF_CHANNEL = (0, 0, 1, 1, 2, 2)
N_NOISE = 2 * iru.N_NOISE          # 12: per triplet of channels, ARW (3) then bias walk (3)
FAULT_STUCK, FAULT_EXCESS_BIAS = 0, 1
N_FAULT_SLOTS = 2

# state layout: two iru.py counter states (channels 0-2, 3-5), then per channel
COUNTER_A, COUNTER_B = 0, iru.STATE_SIZE
SENSED = 2 * iru.STATE_SIZE        # angle the rebalance loop has followed (rad)
TRUE_PREV = SENSED + N_CHANNELS    # true channel angle at the previous sample (rad)
FAULT_ANGLE = TRUE_PREV + N_CHANNELS  # integral of the excess-bias fault (rad)
LAST = FAULT_ANGLE + N_CHANNELS    # last rate output (rad/s), for the stuck fault
STATE_SIZE = LAST + N_CHANNELS


class IruUnitsParams(NamedTuple):
    ch_axes_B: np.ndarray      # (6, 3) unit sensing axis of each channel
    counter: iru.IruParams     # lsb_rad, arw_rad_per_sqrt_s, rrw_rad_s_per_sqrt_s, dt
    rate_max_rad_s: float      # rebalance-loop limit; correct polarity up to here


def make_iru_units_params(channel_axes_B, lsb_arcsec, arw_deg_per_sqrt_h, rrw_deg_h_per_sqrt_h,
                          rate_max_deg_s, dt) -> IruUnitsParams:
    axes = np.array(channel_axes_B, float)
    if axes.shape != (N_CHANNELS, 3):
        raise ValueError(f"channel_axes_B must be {N_CHANNELS} vectors of 3, got shape {axes.shape}")
    counter = iru.IruParams(np.radians(lsb_arcsec / 3600.0), np.radians(arw_deg_per_sqrt_h) / 60.0,
                            np.radians(rrw_deg_h_per_sqrt_h) / 3600.0 / 60.0, float(dt))
    return IruUnitsParams(axes / np.linalg.norm(axes, axis=1)[:, None], counter, np.radians(rate_max_deg_s))


def iru_units_initial_state(bias_ch_rad_s, theta_int_B, omega_BN_B, p: IruUnitsParams) -> np.ndarray:
    """As if the body had turned at omega_BN_B over the sample before, so the
    first output is the initial rate (saturation included)."""
    theta_prev = p.ch_axes_B @ (np.asarray(theta_int_B, float) - np.asarray(omega_BN_B, float) * p.counter.dt)
    bias, still = np.asarray(bias_ch_rad_s, float), np.zeros(3)
    s = np.zeros(STATE_SIZE)
    s[COUNTER_A:COUNTER_B] = iru.iru_initial_state(bias[:3], theta_prev[:3], still, p.counter)
    s[COUNTER_B:SENSED] = iru.iru_initial_state(bias[3:], theta_prev[3:], still, p.counter)
    s[SENSED:TRUE_PREV] = theta_prev
    s[TRUE_PREV:FAULT_ANGLE] = theta_prev
    s[LAST:] = np.clip(p.ch_axes_B @ np.asarray(omega_BN_B, float), -p.rate_max_rad_s, p.rate_max_rad_s)
    return s


@njit(cache=True)
def _followed_angles(theta_int_B, state, p, fault, valid_out):
    """Channel angles as the rebalance loops follow them, faults added."""
    dt = p.counter.dt
    step_max = p.rate_max_rad_s * dt
    theta = np.empty(N_CHANNELS)
    for k in range(N_CHANNELS):
        a = p.ch_axes_B[k]
        true_k = a[0] * theta_int_B[0] + a[1] * theta_int_B[1] + a[2] * theta_int_B[2]
        step = true_k - state[TRUE_PREV + k]
        state[TRUE_PREV + k] = true_k
        valid_out[k] = abs(step) <= step_max
        if not valid_out[k]:
            step = np.copysign(step_max, step)
        state[SENSED + k] += step
        state[FAULT_ANGLE + k] += fault[k, FAULT_EXCESS_BIAS] * dt
        theta[k] = state[SENSED + k] + state[FAULT_ANGLE + k]
    return theta


@njit(cache=True, inline="always")
def iru_units_sample(theta_int_B, state, p, noise, fault, rate_ch_out, valid_out):
    """One sample at t_k: each channel's mean rate over [t_k-1, t_k] (rad/s)."""
    theta = _followed_angles(theta_int_B, state, p, fault, valid_out)
    n = iru.N_NOISE
    iru.iru_sample(state[COUNTER_A:COUNTER_B], p.counter, theta[0:3], noise[0:n], rate_ch_out[0:3])
    iru.iru_sample(state[COUNTER_B:SENSED], p.counter, theta[3:6], noise[n:2 * n], rate_ch_out[3:6])
    for k in range(N_CHANNELS):
        if fault[k, FAULT_STUCK] > 0.5:
            rate_ch_out[k] = state[LAST + k]
        else:
            state[LAST + k] = rate_ch_out[k]
