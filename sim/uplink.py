"""What the ground uploads to the flight software before a run: the clock
(epoch, leap seconds), the Earth-orientation matrix dcm_CN at the epoch, and
the spacecraft's orbit state (seed 001 "On-Board Ephemeris": the on-board
orbit is propagated from an uplinked state).

This is ground software: it may use ERFA and the truth's initial state, as an
orbit-determination team would hand over their best estimate. The flight
software receives only the numbers.
"""
from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

import erfa
import numpy as np

from sim.fsw.onboard_time import OnboardClock, make_clock
from sim.truth.ephemeris import tt_jd, utc_jd


@dataclass(frozen=True)
class Uplink:
    clock: OnboardClock
    dcm_CN: np.ndarray   # (3, 3) GCI -> celestial intermediate at the epoch (IAU 2006/2000A)
    x_sc_N: np.ndarray   # (6,) orbit state [r_N_m, v_N_m_s] at t = 0


def make_uplink(epoch_utc: datetime, r0_N_m, v0_N_m_s) -> Uplink:
    u1, u2 = utc_jd(epoch_utc)
    leap_s = float(erfa.dat(epoch_utc.year, epoch_utc.month, epoch_utc.day, 0.0))
    return Uplink(make_clock(u1, leap_s, 0.0, u2), np.ascontiguousarray(erfa.c2i06a(*tt_jd(epoch_utc))),
                  np.concatenate([np.asarray(r0_N_m, float), np.asarray(v0_N_m_s, float)]))
