"""The on-board ephemeris task and the attitude target, run from the control
cycle (seed 001 "On-Board Ephemeris" and "SNR Target").

The task samples every p.eph_every control cycles (1 s at SDO's 0.2 s cycle);
each sample refreshes the apparent Sun direction (the DSS's reference in the
Kalman filter) and the SNR frame, and so the target q_RN. Between samples the
target is held: the Sun moves 0.04 arcsec per second across the sky.
"""
from numba import njit

from sim.fsw.ephemeris_task import SPACECRAFT, SUN, ephemeris_task_step, observer_bary_velocity_N
from sim.fsw.snr import apparent_sun_unit_N, snr_quat_from_sun, target_quat


@njit(cache=True, inline="always")
def update_target(s, p):
    """From the task's latest sample: the apparent Sun, SNR frame and target."""
    e = s.eph
    sun = apparent_sun_unit_N(e.pos_N_m[SUN], e.pos_N_m[SPACECRAFT], observer_bary_velocity_N(e))
    s.sun_N[:] = sun
    s.q_SN[:] = snr_quat_from_sun(sun, p.pole_N)
    s.q_RN[:] = target_quat(s.target[0], s.q_SN, s.dq_RS, s.q_RN_cmd)


@njit(cache=True)
def ephemeris_sample(s, p):
    """One sample of the task, then the target. Out of line on purpose: it
    runs once a second, and a call that takes the records costs a reference
    count per array only when it is made."""
    ephemeris_task_step(p.eph, s.eph)
    update_target(s, p)


@njit(cache=True, inline="always")
def is_sample_cycle(k, eph_every):
    """Cycle k (t = k dt) samples the task when k is a positive multiple of
    eph_every (sample 0 is the task's initial state); eph_every = 0: no
    on-board ephemeris, the target and Sun direction stay those of t = 0."""
    return eph_every > 0 and k > 0 and k % eph_every == 0
