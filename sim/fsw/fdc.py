"""Failure detection and correction (FDC), the compiled checks.

Each check can be disabled by command (FdcState.enabled). A check that fires
records what it found in FdcState.last = [check, unit] and the cycle returns
EVENT_FDC; the response that needs the mode machine (a transition, a new
distribution matrix) is taken on the Python side (flight_software.py).

* CHECK_LIMITS: the mode's attitude error or body rate beyond its limit for
  the persistence time; the response is the mode's (spacecraft file
  fsw.fdc.limit_response: Inertial, SunAcq or Safehold).
* CHECK_IRU: a failed IRU channel (fdc_iru.py); the response, here and at
  once: rate selection drops the channel (seed 001 "Hardware complement":
  FDC "is capable of reconfiguring rate selection autonomously").
* CHECK_WHEEL: a failed wheel (fdc_wheel.py); response: distribute on three.
* CHECK_STAR_TRACKER: a tracker invalid for the persistence time; the
  Kalman filter already skips invalid measurements and "continues on the
  remaining sensors": the check reports it.
The main processor's own loss is the ACE's to notice (safehold.py).
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.fsw.fdc_iru import IruFdcParams, IruFdcState, iru_fdc_cycle
from sim.fsw.fdc_wheel import WheelFdcParams, WheelFdcState, wheel_fdc_cycle

CHECK_LIMITS, CHECK_IRU, CHECK_WHEEL, CHECK_STAR_TRACKER = 0, 1, 2, 3
CHECK_NAMES = ("limits", "iru", "wheel", "star_tracker")
N_CHECKS = 4
NO_LIMIT = 1e30


class FdcParams(NamedTuple):
    att_limit_rad: np.ndarray     # (6,) per mode (sim.modes.Mode); NO_LIMIT: none
    rate_limit_rad_s: np.ndarray  # (6,)
    limit_cycles: int
    st_cycles: int
    acted_row: int            # row of cmd_hist that acted over the last interval: 0 with a one-cycle actuator delay
    iru: IruFdcParams
    wheel: WheelFdcParams


class FdcState(NamedTuple):
    enabled: np.ndarray       # (N_CHECKS,) bool
    limit_count: np.ndarray   # (1,) int64
    st_count: np.ndarray      # (n_st,) int64: cycles invalid in a row
    last: np.ndarray          # (2,) int64: [check, unit] of the last detection
    cmd_hist: np.ndarray      # (2, N) wheel commands of the last two cycles (the older acted last interval)
    wheel_ok: np.ndarray      # (N,) bool: wheels in use
    iru: IruFdcState
    wheel: WheelFdcState


@njit(cache=True, inline="always")
def limits_exceeded(mode, att_err_rad, rate_B, p, s):
    over = att_err_rad > p.att_limit_rad[mode] or np.sqrt(np.sum(rate_B * rate_B)) > p.rate_limit_rad_s[mode]
    s.limit_count[0] = s.limit_count[0] + 1 if over else 0
    return s.limit_count[0] >= p.limit_cycles


@njit(cache=True, inline="always")
def _fired(s, check, unit):
    s.last[0] = check
    s.last[1] = unit
    return True


@njit(cache=True, inline="always")
def fdc_cycle(mode, att_err_rad, rate_B, iru_rate_ch, iru_ch_valid, iru_ch_use, q_ref_BN, ref_ok, st_valid,
              tach_speed_rad_s, tach_valid, wheel_cmd_Nm, p, s):
    """All enabled checks for one cycle; True when one fired (s.last says which)."""
    fired = False
    en = s.enabled
    if en[CHECK_IRU]:
        k = iru_fdc_cycle(iru_rate_ch, iru_ch_valid, iru_ch_use, q_ref_BN, ref_ok, p.iru, s.iru)
        if k >= 0:
            iru_ch_use[k] = False
            fired = _fired(s, CHECK_IRU, k)
    if en[CHECK_WHEEL] and not fired:
        w = wheel_fdc_cycle(tach_speed_rad_s, tach_valid, s.cmd_hist[p.acted_row], p.wheel, s.wheel)
        if w >= 0 and s.wheel_ok[w]:
            s.wheel_ok[w] = False
            fired = _fired(s, CHECK_WHEEL, w)
    s.cmd_hist[0, :] = s.cmd_hist[1]
    s.cmd_hist[1, :] = wheel_cmd_Nm
    for i in range(st_valid.shape[0]):
        s.st_count[i] = 0 if st_valid[i] else s.st_count[i] + 1
        if en[CHECK_STAR_TRACKER] and s.st_count[i] == p.st_cycles and not fired:
            fired = _fired(s, CHECK_STAR_TRACKER, i)
    if en[CHECK_LIMITS] and not fired and limits_exceeded(mode, att_err_rad, rate_B, p, s):
        s.limit_count[0] = 0
        fired = _fired(s, CHECK_LIMITS, mode)
    return fired
