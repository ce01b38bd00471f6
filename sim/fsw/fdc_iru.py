"""IRU channel failure detection and isolation (seed 001 "Hardware
complement": "With three units, the rate sensing capability of the IRUs is
single-fault tolerant, and the failure detection and correction (FDC) system
is capable of reconfiguring rate selection autonomously in the event of an IRU
failure"). This module finds the failed channel; the caller clears its
ch_use slot and rate selection (sim/fsw/rate_selection.py) goes on without it.

Geometry. Every body axis is sensed by two channels of different units
(sdo.yaml: X by channels 0 and 5, Y by 1 and 2, Z by 3 and 4); params.pair
lists them, and each channel's rate along its axis is r_k a_k[i] (a_k = +-e_i).

Detection. A channel in use whose valid flag is False for persistence_cycles
is failed (not counted while its partner on the same axis is invalid too: both
at once is the rate beyond the range, seed 001's 10 deg/s, not a channel). On
each axis with both channels in use and valid, the difference of their rates
is low-pass filtered (first order, tau = persistence_cycles dt) and the axis
is *detected* when |filtered difference| > disagree_rad_s for persistence_cycles
consecutive cycles. A silent fault (stuck output, excess bias) shows only so.

Isolation. Two channels cannot tell which of them is wrong; an independent
attitude reference q_BN_ref (a star tracker's body quaternion,
sim/fsw/ekf.py body_from_tracker) can. Over consecutive windows of
window_cycles, started at a cycle with a valid reference, the detector
propagates the attitude q_prop from q_BN_ref(start) with the rate of the
channels in use (the mean of each axis pair) and tracks, per channel, its
angle relative to that rate, delta_k = integral (r_k - omega_i) dt. The
reference sees the propagation error e = small_angle(q_prop^* (x) q_BN_ref),
body axes, which is integral (omega_true - omega_used); so
res_k = e_i - delta_k = integral (omega_true,i - r_k) dt is channel k's own
angle error, to first order in the (small) channel errors; the propagation
carries the slew's large rotation exactly, the split into per-channel errors
holds while the body turns little in a window (MAX_WINDOW_TURN_RAD). Its
least-squares slope over the window (a line fit against time with intercept,
at every cycle with a valid reference, so the start sample's noise drops out)
is the channel's rate error. A window counts for a channel if the channel was valid throughout and
the reference valid at least half of the window, and the body turned less
than MAX_WINDOW_TURN_RAD in it; otherwise (ref_valid False: those cycles
cannot be used) it gives no verdict.

On a detected axis the channel with the larger |slope| is failed when
|slope_bad| >= ISO_MIN_FRACTION disagree_rad_s and >= ISO_RATIO |slope_good|,
using the latest window that ended at most one window ago. Otherwise the
detector waits for the next window: it never guesses, so without a reference
an axis stays detected (state.detected) and nothing is isolated.

One new failure per call; a failed channel stays failed (state.failed) and
is ignored from then on, as are channels the caller has taken out of use
(ch_use False). An axis left with one channel has nothing to compare against
and is checked only by its valid flag.

What the defaults see (sdo.yaml IRU: 0.5 arcsec LSB at 0.2 s, i.e. 2.5 arcsec/s
per count; ARW 0.005 deg/sqrt(h); star tracker 10/30 arcsec 1-sigma), measured
in tests/test_fdc_detectors.py:
* Nominal filtered difference: quantisation is a first difference of a bounded
  angle error, filtered to <= 2 alpha LSB/dt = 0.2 arcsec/s; ARW 0.14 arcsec/s
  1-sigma; bias difference <= 0.04 deg/h = 0.04 arcsec/s (sdo.yaml), drifting.
  The 5 arcsec/s threshold is > 30 sigma of the noise.
* A stuck channel is invisible while the body rate equals the held value
  (to the held sample's quantisation and ARW, a few arcsec/s); once the rate
  changes by >= 0.01 deg/s (36 arcsec/s) it is detected in ~6 s and isolated
  at the end of the window in which the change happened, or of the next one
  if the change came late in it: 7-37 s after the change, 60 s at worst.
* An excess bias is detected in ~5 s at 0.05 deg/s, 8 s at 10 deg/h, 13 s at
  6 deg/h, and isolated at the next window end with a clear verdict (10-20 s
  at 0.05 deg/s and 10 deg/h, 40 s at 6 deg/h). 4 deg/h is not detected.
* An excess bias of ~1 deg/h (1 arcsec/s) is not detected: it is 7 sigma of
  the filtered ARW but also the size of the nominal bias drift over a long
  mission, and it is not a failure in practice (the EKF estimates it with the
  axis bias: 0.5 deg/h on the pair mean). Its angle error over a 30-s window,
  30 arcsec, is the star tracker's 1-sigma noise.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.attitude import error_quat, quat_propagate, small_angle_error

DISAGREE_RAD_S = np.radians(5.0 / 3600.0)
"""Axis disagreement threshold (assumption): 5 arcsec/s = 5 deg/h =
2.4e-5 rad/s: twice one count per cycle (0.5 arcsec / 0.2 s = 2.5 arcsec/s)
and > 30 sigma of the filtered nominal noise (module docstring; 0.09 arcsec/s
the largest measured over 15 min); a 0.01 deg/s rate change on a stuck
channel exceeds it 7x."""
PERSISTENCE_CYCLES = 25
"""Consecutive cycles (assumption): 5 s at 0.2 s; also the filter's time
constant (alpha = 1/25), so the ARW left on the filtered difference is
0.95 arcsec/s x sqrt(alpha / 2) = 0.14 arcsec/s."""
WINDOW_CYCLES = 150
"""Isolation window (assumption): 30 s at 0.2 s. The slope of 150 tracker
samples with 30 arcsec noise is good to 30 sqrt(12/150) / 30 s = 0.28 arcsec/s,
9x under the isolation floor; a fault is isolated at the end of the window it
shows in, so within 30-60 s of showing."""
ISO_MIN_FRACTION = 0.5
"""The failed channel's window rate error must reach this fraction of
disagree_rad_s (2.5 arcsec/s with the defaults, 9 sigma of the slope noise)."""
ISO_RATIO = 3.0
"""... and this multiple of its partner's: a clear margin, not a coin toss."""
MAX_WINDOW_TURN_RAD = np.radians(20.0)
"""A window in which the body turned more than this (integral of |omega| dt)
gives no verdict (assumption). The first-order split res_k = e_i - delta_k
adds the channel errors along fixed body axes; as the body turns by phi an
earlier error rotates out of its axis (cos 20 deg = 0.94) and the start
snapshot's tracker noise (30 arcsec) moves across the axes by up to
30 sin(20 deg) = 10 arcsec, a common-mode 0.35 arcsec/s over 30 s. 20 deg per
30-s window is 0.67 deg/s: every SDO slew (<= 0.4 deg/s), not the 1-3 deg/s
of sun acquisition, where the detector waits for the rates to come down."""
ALIGN_TOL = 1e-6   # channel axes must be within this of +-e_i


class IruFdcParams(NamedTuple):
    ch_axes_B: np.ndarray     # (6, 3) unit sensing axis of each channel, each +-e_i
    pair: np.ndarray          # (3, 2) int64, the channels sensing body axis i
    disagree_rad_s: float     # filtered axis disagreement threshold, rad/s
    persistence_cycles: int   # consecutive cycles (invalid, disagreeing); filter tau = this x dt
    window_cycles: int        # isolation window, cycles
    dt: float                 # control cycle, s


class IruFdcState(NamedTuple):
    diff_f: np.ndarray        # (3,) rad/s, filtered rate difference pair[i, 0] - pair[i, 1]
    count_dis: np.ndarray     # (3,) int64, consecutive cycles over disagree_rad_s
    detected: np.ndarray      # (3,) bool, axis disagreement confirmed, awaiting isolation
    count_inv: np.ndarray     # (6,) int64, consecutive invalid cycles
    failed: np.ndarray        # (6,) bool, declared failed by this detector (stays so)
    win_t: np.ndarray         # (1,) int64, cycles into the current window; -1: none open
    q_prop_BN: np.ndarray     # (4,) attitude propagated with the rates in use since the window start
    delta_rad: np.ndarray     # (6,) integral of (channel rate - axis rate used), rad
    ch_ok: np.ndarray         # (6,) bool, channel usable and valid throughout the window
    n_ref: np.ndarray         # (1,) int64, reference samples in the window
    turn_rad: np.ndarray      # (1,) integral of |omega| dt over the window, rad
    sums: np.ndarray          # (4, 6) line-fit sums per channel: t, t^2, res, t res (s, rad)
    slope_rad_s: np.ndarray   # (6,) rate error of the last completed window (reference minus channel)
    slope_ok: np.ndarray      # (6,) bool, that window gives a verdict for the channel
    slope_age: np.ndarray     # (1,) int64, cycles since that window ended


def axis_pairs(ch_axes_B) -> np.ndarray:
    """(3, 2) channels sensing each body axis, in channel order; ValueError
    unless every channel lies along a body axis and each axis has two."""
    axes = np.asarray(ch_axes_B, float)
    pair = np.full((3, 2), -1, np.int64)
    found = np.zeros(3, int)
    for k, a in enumerate(axes):
        i = int(np.argmax(np.abs(a)))
        if abs(abs(a[i]) - 1.0) > ALIGN_TOL or np.linalg.norm(np.delete(a, i)) > ALIGN_TOL:
            raise ValueError(f"IRU channel {k} axis {a} is not along a body axis")
        if found[i] == 2:
            raise ValueError(f"more than two IRU channels sense body axis {i}")
        pair[i, found[i]] = k
        found[i] += 1
    if np.any(found != 2):
        raise ValueError(f"each body axis needs two IRU channels, got {found.tolist()}")
    return pair


def make_iru_fdc_params(ch_axes_B, dt, disagree_rad_s=DISAGREE_RAD_S, persistence_cycles=PERSISTENCE_CYCLES,
                        window_cycles=WINDOW_CYCLES) -> IruFdcParams:
    """For SDO: make_iru_fdc_params(sc.sensors.iru_units.channel_axes_B, sc.timing.control_dt_s)."""
    axes = np.asarray(ch_axes_B, float)
    axes = axes / np.linalg.norm(axes, axis=1)[:, None]
    if dt <= 0.0 or disagree_rad_s <= 0.0 or int(persistence_cycles) < 1 or int(window_cycles) < 4:
        raise ValueError("need dt, disagree_rad_s > 0, persistence_cycles >= 1, window_cycles >= 4")
    return IruFdcParams(axes, axis_pairs(axes), float(disagree_rad_s), int(persistence_cycles),
                        int(window_cycles), float(dt))


def make_iru_fdc_state(n_channels: int = 6) -> IruFdcState:
    z = np.zeros
    return IruFdcState(z(3), z(3, np.int64), z(3, np.bool_), z(n_channels, np.int64), z(n_channels, np.bool_),
                       np.full(1, -1, np.int64), np.array([1.0, 0.0, 0.0, 0.0]), z(n_channels),
                       z(n_channels, np.bool_), z(1, np.int64), z(1), z((4, n_channels)), z(n_channels),
                       z(n_channels, np.bool_), np.full(1, np.iinfo(np.int64).max // 2, np.int64))


@njit(cache=True)
def _start_window(q_BN_ref, s):
    s.win_t[0] = 0
    s.q_prop_BN[:] = q_BN_ref
    s.delta_rad[:] = 0.0
    s.ch_ok[:] = True
    s.n_ref[0] = 0
    s.turn_rad[0] = 0.0
    s.sums[:, :] = 0.0


@njit(cache=True)
def _close_window(s, min_ref):
    """Line-fit slopes of res_k against time; a verdict only for channels
    valid throughout, with at least min_ref reference samples and a body turn
    under MAX_WINDOW_TURN_RAD."""
    n = s.n_ref[0]
    usable = n >= min_ref and s.turn_rad[0] <= MAX_WINDOW_TURN_RAD
    for k in range(s.slope_rad_s.shape[0]):
        st, stt, sr, str_ = s.sums[0, k], s.sums[1, k], s.sums[2, k], s.sums[3, k]
        den = n * stt - st * st
        s.slope_ok[k] = s.ch_ok[k] and usable and den > 0.0
        s.slope_rad_s[k] = (n * str_ - st * sr) / den if s.slope_ok[k] else 0.0
    s.slope_age[0] = 0
    s.win_t[0] = -1


@njit(cache=True)
def _window_step(rate_ch_rad_s, ch_valid, usable, q_BN_ref, ref_valid, p, s):
    """Advance the isolation window by one cycle (module docstring)."""
    s.slope_age[0] += 1
    if s.win_t[0] < 0:
        if ref_valid:
            _start_window(q_BN_ref, s)
        return
    omega_B = np.zeros(3)
    for i in range(3):
        m = 0
        for j in range(2):
            k = p.pair[i, j]
            if usable[k] and ch_valid[k]:
                omega_B[i] += rate_ch_rad_s[k] * p.ch_axes_B[k, i]
                m += 1
        if m == 0:          # an axis unseen this cycle: the propagation is lost
            s.win_t[0] = -1
            return
        omega_B[i] /= m
    s.q_prop_BN[:] = quat_propagate(s.q_prop_BN, omega_B, p.dt)
    s.turn_rad[0] += np.sqrt(omega_B[0] ** 2 + omega_B[1] ** 2 + omega_B[2] ** 2) * p.dt
    s.win_t[0] += 1
    t = s.win_t[0] * p.dt
    for i in range(3):
        for j in range(2):
            k = p.pair[i, j]
            if not (usable[k] and ch_valid[k]):
                s.ch_ok[k] = False
            s.delta_rad[k] += (rate_ch_rad_s[k] * p.ch_axes_B[k, i] - omega_B[i]) * p.dt
    if ref_valid:
        e_B = small_angle_error(error_quat(q_BN_ref, s.q_prop_BN))
        s.n_ref[0] += 1
        for i in range(3):
            for j in range(2):
                k = p.pair[i, j]
                res = e_B[i] - s.delta_rad[k]
                s.sums[0, k] += t
                s.sums[1, k] += t * t
                s.sums[2, k] += res
                s.sums[3, k] += t * res
    if s.win_t[0] >= p.window_cycles:
        _close_window(s, p.window_cycles // 2)
        if ref_valid:
            _start_window(q_BN_ref, s)


@njit(cache=True)
def _isolate(i, p, s):
    """The failed channel of detected axis i by the last window, else -1."""
    if s.slope_age[0] > p.window_cycles:
        return -1
    a, b = p.pair[i, 0], p.pair[i, 1]
    if not (s.slope_ok[a] and s.slope_ok[b]):
        return -1
    ea, eb = abs(s.slope_rad_s[a]), abs(s.slope_rad_s[b])
    bad, big, small = (a, ea, eb) if ea >= eb else (b, eb, ea)
    if big >= ISO_MIN_FRACTION * p.disagree_rad_s and big >= ISO_RATIO * small:
        return bad
    return -1


@njit(cache=True, inline="always")
def iru_fdc_cycle(rate_ch_rad_s, ch_valid, ch_use, q_BN_ref, ref_valid, p, s):
    """One control cycle: the six channel rates (rad/s) and valid flags of the
    samples at t_k, the caller's channels in use, and a reference body
    attitude q_BN_ref at t_k independent of the IRUs (ref_valid False: none).
    Returns the channel newly declared failed this cycle, else -1."""
    n_ch = rate_ch_rad_s.shape[0]
    usable = np.empty(n_ch, np.bool_)
    for k in range(n_ch):
        usable[k] = ch_use[k] and not s.failed[k]
    # the isolation windows run only once an axis disagrees: a healthy IRU
    # then costs the disagreement filter alone (the windows cost most of a
    # microsecond a cycle); isolation comes at the end of the first window
    # after detection
    if s.win_t[0] >= 0 or s.detected.any():
        _window_step(rate_ch_rad_s, ch_valid, usable, q_BN_ref, ref_valid, p, s)
    else:
        s.slope_age[0] += 1

    new = -1
    alpha = 1.0 / p.persistence_cycles
    for i in range(3):
        a, b = p.pair[i, 0], p.pair[i, 1]
        for j in range(2):
            k, partner = p.pair[i, j], p.pair[i, 1 - j]
            if not usable[k] or ch_valid[k]:
                s.count_inv[k] = 0
            elif not (usable[partner] and not ch_valid[partner]):
                s.count_inv[k] += 1     # both invalid at once: the rate, not the channel (held)
            if new < 0 and usable[k] and s.count_inv[k] >= p.persistence_cycles:
                new = k
        if not (usable[a] and usable[b]):
            s.diff_f[i] = 0.0
            s.count_dis[i] = 0
            s.detected[i] = False
            continue
        if ch_valid[a] and ch_valid[b]:
            d = rate_ch_rad_s[a] * p.ch_axes_B[a, i] - rate_ch_rad_s[b] * p.ch_axes_B[b, i]
            s.diff_f[i] += alpha * (d - s.diff_f[i])
            if abs(s.diff_f[i]) > p.disagree_rad_s:
                s.count_dis[i] += 1
            else:
                s.count_dis[i] = 0
            if s.count_dis[i] >= p.persistence_cycles:
                s.detected[i] = True
        if new < 0 and s.detected[i]:
            new = _isolate(i, p, s)

    if new >= 0:
        s.failed[new] = True
        s.count_inv[new] = 0
        for i in range(3):
            if p.pair[i, 0] == new or p.pair[i, 1] == new:
                s.diff_f[i] = 0.0
                s.count_dis[i] = 0
                s.detected[i] = False
    return new
