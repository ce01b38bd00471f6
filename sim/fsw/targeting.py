"""The on-board ephemeris task and the attitude target, run from the control
cycle (seed 001 "On-Board Ephemeris" and "SNR Target").

The task samples every p.eph_every control cycles (1 s at SDO's 0.2 s cycle);
each sample refreshes the apparent Sun direction (the DSS's reference in the
Kalman filter) and the SNR frame, and so the target q_RN. Between samples the
target is held: the Sun moves 0.04 arcsec per second across the sky.
"""
from numba import njit

from sim.attitude import dcm_to_quat
from sim.fsw.ephemeris_task import SPACECRAFT, SUN, ephemeris_task_step, observer_bary_velocity_N
from sim.fsw.snr import apparent_sun_unit_N, snr_dcm_NS, target_quat


@njit(cache=True, inline="always")
def update_target(s, p):
    """From the task's latest sample: the apparent Sun, SNR frame and target."""
    e = s.eph
    sun = apparent_sun_unit_N(e.pos_N_m[SUN], e.pos_N_m[SPACECRAFT], observer_bary_velocity_N(e))
    s.sun_N[:] = sun
    s.q_SN[:] = dcm_to_quat(snr_dcm_NS(sun, p.pole_N))
    s.q_RN[:] = target_quat(s.target[0], s.q_SN, s.dq_RS, s.q_RN_cmd)


@njit(cache=True, inline="always")
def ephemeris_tick(s, p):
    """On a sample cycle (cycle k at t = k dt, k a positive multiple of
    eph_every; sample 0 is the task's initial state), run the task and refresh
    the target; then count the cycle."""
    k = s.cycle[0]
    if k > 0 and k % p.eph_every == 0:
        ephemeris_task_step(p.eph, s.eph)
        update_target(s, p)
    s.cycle[0] = k + 1
