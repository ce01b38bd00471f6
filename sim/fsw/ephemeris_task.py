"""The on-board ephemeris task: positions of the Sun, the Moon, the spacecraft
and the ground station each sample, velocities by differencing.

Seed 001 "On-Board Ephemeris": "Each object's velocity is derived from
differencing successive position vectors and dividing the result by the
ephemeris task sample time (nominally 1 second)":
    v_k = (r_k - r_{k-1}) / dt.
This is the central difference of the midpoint t_k - dt/2, so it equals the
true velocity at t_k - dt/2 to O(dt^2 |r'''| / 24) and lags the velocity at
t_k by |a| dt / 2 (at geosynchronous altitude 0.11 m/s at dt = 1 s: 4e-10 rad
of aberration; the Earth's orbital velocity: 3 mm/s).

The spacecraft is advanced one RK4 step of dt per sample
(sim/fsw/orbit_propagator.py), the Sun and Moon come from their series,
the station from sim/fsw/ground_station.py. ``init_task`` fills the
previous positions at t0 - dt (the spacecraft by a backward RK4 step), so
the first sample's velocities are already differences.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.fsw.ephemeris_moon import moon_position_N
from sim.fsw.ephemeris_sun import sun_position_N
from sim.fsw.ground_station import station_position_N
from sim.fsw.orbit_propagator import OrbitModelParams, rk4_step, rk4_step_given

SUN, MOON, SPACECRAFT, STATION = 0, 1, 2, 3
N_OBJECTS = 4
EPHEMERIS_DT_S = 1.0   # seed 001: "nominally 1 second"


class EphemerisTaskParams(NamedTuple):
    orbit: OrbitModelParams  # holds the clock and the uploaded dcm_CN
    station_E_m: np.ndarray  # (3,) ground station, Earth-fixed
    dt_s: float              # sample time


class EphemerisTaskState(NamedTuple):
    """Arrays updated in place by ``ephemeris_task_step``."""
    t_s: np.ndarray          # (1,) time of the latest sample
    x_sc: np.ndarray         # (6,) on-board orbit state [r_N_m, v_N_m_s] (the integrator's)
    pos_N_m: np.ndarray      # (4, 3) positions at t_s: SUN, MOON, SPACECRAFT, STATION
    prev_N_m: np.ndarray     # (4, 3) positions at t_s - dt_s
    vel_N_m_s: np.ndarray    # (4, 3) differenced velocities


@njit(cache=True)
def difference_velocity(r_now, r_prev, dt_s):
    """(r_now - r_prev) / dt_s."""
    return (r_now - r_prev) / dt_s


@njit(cache=True)
def _put(out, i, v):
    """out[i, :] = v[:3] as an element loop (numba's array setitem costs
    seconds of compile time per caller)."""
    for j in range(3):
        out[i, j] = v[j]


@njit(cache=True)
def _positions(x_sc, t_s, p, out):
    _put(out, SUN, sun_position_N(p.orbit.clock, t_s))
    _put(out, MOON, moon_position_N(p.orbit.clock, t_s))
    _put(out, SPACECRAFT, x_sc)
    _put(out, STATION, station_position_N(p.station_E_m, p.orbit.clock, p.orbit.dcm_CN, t_s))


@njit(cache=True)
def ephemeris_task_step(p, s):
    """Advance the task by one sample of p.dt_s. The Sun and Moon of the
    previous sample serve as the RK4's first stage, so each series is
    evaluated twice per sample (mid-step and end) instead of four times."""
    t0 = s.t_s[0]
    t_new = t0 + p.dt_s
    for i in range(N_OBJECTS):
        _put(s.prev_N_m, i, s.pos_N_m[i])
    sun_mid = sun_position_N(p.orbit.clock, t0 + 0.5 * p.dt_s)
    moon_mid = moon_position_N(p.orbit.clock, t0 + 0.5 * p.dt_s)
    _put(s.pos_N_m, SUN, sun_position_N(p.orbit.clock, t_new))
    _put(s.pos_N_m, MOON, moon_position_N(p.orbit.clock, t_new))
    x = rk4_step_given(s.x_sc, t0, p.dt_s, s.prev_N_m[SUN], s.prev_N_m[MOON], sun_mid, moon_mid,
                       s.pos_N_m[SUN], s.pos_N_m[MOON], p.orbit)
    for j in range(6):
        s.x_sc[j] = x[j]
    _put(s.pos_N_m, SPACECRAFT, x)
    _put(s.pos_N_m, STATION, station_position_N(p.station_E_m, p.orbit.clock, p.orbit.dcm_CN, t_new))
    for i in range(N_OBJECTS):
        for j in range(3):
            s.vel_N_m_s[i, j] = (s.pos_N_m[i, j] - s.prev_N_m[i, j]) / p.dt_s   # difference_velocity
    s.t_s[0] = t_new


@njit(cache=True)
def ephemeris_task_run(p, s, n_samples):
    """n_samples steps of the task (for segments of the run and for tests)."""
    for _ in range(n_samples):
        ephemeris_task_step(p, s)


def init_task(p: EphemerisTaskParams, x_sc0: np.ndarray, t0_s: float) -> EphemerisTaskState:
    """Task state at t0_s from the uploaded orbit state x_sc0 = [r_N_m, v_N_m_s]."""
    if not p.dt_s > 0.0:
        raise ValueError(f"EphemerisTaskParams.dt_s = {p.dt_s}: the sample time must be > 0 s (nominally 1 s)")
    x0 = np.ascontiguousarray(x_sc0, dtype=float)
    if x0.shape != (6,):
        raise ValueError(f"x_sc0 must be [r_N_m, v_N_m_s], shape (6,), got {x0.shape}")
    pos, prev = np.empty((N_OBJECTS, 3)), np.empty((N_OBJECTS, 3))
    _positions(x0, t0_s, p, pos)
    _positions(rk4_step(x0, t0_s, -p.dt_s, p.orbit), t0_s - p.dt_s, p, prev)
    vel = difference_velocity(pos, prev, p.dt_s)
    return EphemerisTaskState(np.array([float(t0_s)]), x0.copy(), pos, prev, vel)


@njit(cache=True)
def observer_bary_velocity_N(s):
    """The spacecraft's velocity relative to the solar-system barycentre, from
    the differenced velocities: the Earth's heliocentric velocity (minus that
    of the geocentric Sun) plus the spacecraft's geocentric velocity. The Sun's
    own ~13 m/s about the barycentre is left out (9 mas of aberration)."""
    return s.vel_N_m_s[SPACECRAFT] - s.vel_N_m_s[SUN]
