"""Safehold, the attitude control electronics' (ACE) own flight software
(seed 001 "Safehold": "located in the ACE"; "Hardware complement": the ACE
"allows reaction wheels to be commanded by the Sun-pointing Safehold
independent of the Mil Std 1553 data bus").

Seed 001 eq. (7), as a body torque (the seed writes T with a wheel torque's
sign, as eq. (6); see sunacq.py):

    T_B = K_p (s_d x s) - K_d (K_perp diag(0,1,1) (ds/dt x s) + K_sunline w~_x e_x)

* s: the CSS Sun vector of this ACE's set of eyes; ds/dt x s = omega
  perpendicular to s (ds/dt = s x omega), differenced and low-passed: the
  CSS noise differenced at 5 Hz would otherwise dominate the rate.
* w~_x: the X rate "calculated from the RWAs": with the system momentum
  along the Sun line H_ref (constant while +X holds the Sun),
  I_xx w_x = H_ref - h_wheels,x. H_ref is an ACE table value (default 0);
  a residual shows up as a slow roll about the Sun line.
* Eclipse: rate-only on the IRU ("identical to the SunAcq eclipse controller").

The ACE watches the main processor's heartbeat; after heartbeat_cycles
without it, the ACE takes the wheels in Safehold (FDC: processor reset or
failure). It computes its own rate from the IRU channels and distributes
with its own matrix: nothing of the main processor's state is needed.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.fsw.css_sun import CssSunParams, css_sun_vector_B
from sim.fsw.distribution import distribute
from sim.fsw.rate_selection import least_squares_rate
from sim.fsw.sunacq import SunLawParams, sun_pointing_error_B
from sim.linalg import cross

EVENT_ACE_TAKEOVER = 10   # shares the event-code space of sim/fsw/state.py


class AceParams(NamedTuple):
    present: bool              # False: this spacecraft has no ACE Safehold (fsw.safehold absent)
    law: SunLawParams
    k_perp: float
    k_sunline: float
    rate_alpha: float          # low-pass weight per cycle, dt / (tau + dt)
    h_sunline_ref_Nms: float
    inertia_diag: np.ndarray   # (3,) kg m^2
    dist: np.ndarray           # (N, 3) the ACE's wheel distribution matrix
    torque_limit: float
    wheel_axes_B: np.ndarray   # (N, 3)
    spin_inertia: float
    iru_ch_axes_B: np.ndarray  # (6, 3)
    css: CssSunParams
    css_set: int
    heartbeat_cycles: int
    dt: float


class AceState(NamedTuple):
    in_control: np.ndarray     # (1,) bool: the ACE drives the wheels (Safehold)
    missed: np.ndarray         # (1,) int64: main-processor cycles missed in a row
    sun_B: np.ndarray          # (3,) last CSS Sun vector
    sun_ok: np.ndarray         # (1,) bool: the CSS saw the Sun last cycle
    rate_perp_B: np.ndarray    # (3,) low-passed ds/dt x s, rad/s
    torque_B: np.ndarray       # (3,) last body torque command, N m


def make_ace_state() -> AceState:
    return AceState(np.zeros(1, np.bool_), np.zeros(1, np.int64), np.array([1.0, 0.0, 0.0]),
                    np.zeros(1, np.bool_), np.zeros(3), np.zeros(3))


@njit(cache=True, inline="always")
def css_rates(sun_B, sun_ok, a, p):
    """Update the CSS-derived perpendicular rate from this cycle's Sun vector."""
    if sun_ok and a.sun_ok[0]:
        sdot = (sun_B - a.sun_B) / p.dt
        a.rate_perp_B[:] += p.rate_alpha * (cross(sdot, sun_B) - a.rate_perp_B)
    elif sun_ok:
        a.rate_perp_B[:] = 0.0   # first Sun after eclipse (or at entry): no difference yet
    a.sun_B[:] = sun_B
    a.sun_ok[0] = sun_ok


@njit(cache=True, inline="always")
def safehold_torque_B(tach_speed_rad_s, iru_rate_B, a, p):
    """Eq. (7), or the rate-only eclipse law."""
    t = np.empty(3)
    I = p.inertia_diag
    kd = p.law.kd_per_s
    if not a.sun_ok[0]:
        for i in range(3):
            t[i] = -I[i] * kd * iru_rate_B[i]
        return t
    h_x = 0.0
    for i in range(tach_speed_rad_s.shape[0]):
        h_x += p.wheel_axes_B[i, 0] * p.spin_inertia * tach_speed_rad_s[i]
    w_x = (p.h_sunline_ref_Nms - h_x) / I[0]
    e = sun_pointing_error_B(a.sun_B, p.law.sun_desired_B, p.law.error_limit)
    t[0] = I[0] * (p.law.kp_per_s2 * e[0] - kd * p.k_sunline * w_x)
    for i in (1, 2):
        t[i] = I[i] * (p.law.kp_per_s2 * e[i] - kd * p.k_perp * a.rate_perp_B[i])
    return t


@njit(cache=True, inline="always")
def ace_cycle(proc_up, css_current_A, iru_rate_ch, iru_ch_valid, tach_speed_rad_s, a, p, wheel_torque_Nm,
              thruster_pulses, engine_on):
    """One ACE cycle after the main processor's (whose output it overrides
    while in control). Returns EVENT_ACE_TAKEOVER on the cycle it takes over."""
    event = 0
    a.missed[0] = 0 if proc_up else a.missed[0] + 1
    if not a.in_control[0] and a.missed[0] >= p.heartbeat_cycles:
        a.in_control[0] = True
        event = EVENT_ACE_TAKEOVER
    if a.in_control[0]:
        # the Sun vector only while in control: out of it this would be work in
        # every cycle of every run; the rate filter starts afresh at takeover,
        # as after an eclipse
        sun = np.empty(3)
        ok = css_sun_vector_B(css_current_A, p.css_set, p.css, sun)
        css_rates(sun if ok else a.sun_B.copy(), ok, a, p)
        rate, _ = least_squares_rate(iru_rate_ch, p.iru_ch_axes_B, iru_ch_valid)
        a.torque_B[:] = safehold_torque_B(tach_speed_rad_s, rate, a, p)
        distribute(a.torque_B, p.dist, p.torque_limit, wheel_torque_Nm)
        thruster_pulses[:] = 0.0
        engine_on[0] = 0.0
    else:
        a.sun_ok[0] = False        # no Sun vector differenced across a spell out of control
        if not proc_up:   # between the processor's loss and the takeover nobody commands
            wheel_torque_Nm[:] = 0.0
            thruster_pulses[:] = 0.0
            engine_on[0] = 0.0
    return event
