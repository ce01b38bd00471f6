"""Attitude-control thrusters and the main engine: force, torque about the
moving centre of mass, and propellant flow.

Each thruster pushes the spacecraft along its unit direction from its position
in the structure frame; the torque is (r - r_cm) x F (seed 001 "Hardware
complement": four pairs at the aft corners, canted 10 deg about Z, 5 lbf; the
main engine, 110 lbf, in the centre of the suite). Flow is F / (Isp g0).

Pulses (seed 001 "DeltaV": up to four 50 ms pulses per 200 ms cycle) start at
the top of the cycle; the truth integrator steps at the pulse length, so a
thruster is either on or off for a whole RK4 step and `on_fraction` reports
the overlap for any other step length.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.constants import G0_M_S2 as G0_m_s2
from sim.constants import LBF_N  # noqa: F401 (re-exported: the truth's builders and tests use it from here)
from sim.linalg import cross


class ThrusterParams(NamedTuple):
    position_B: np.ndarray   # (n, 3) m, structure frame
    direction_B: np.ndarray  # (n, 3) unit direction of the force on the spacecraft
    thrust_N: np.ndarray     # (n,)
    isp_s: np.ndarray        # (n,)
    pulse_s: float


class EngineParams(NamedTuple):
    position_B: np.ndarray   # (3,) m
    direction_B: np.ndarray  # (3,) unit, misalignment included
    thrust_N: float
    isp_s: float


# fault slots per thruster
FAIL_OFF, STUCK_ON = 0, 1
N_FAULT_SLOTS = 2


@njit(cache=True, inline="always")
def on_fraction(pulses, step_index, step_s, pulse_s, faults, out):
    """Fraction of RK4 step `step_index` of the cycle during which each
    thruster fires: on from the top of the cycle for pulses * pulse_s."""
    t0 = step_index * step_s
    for i in range(pulses.shape[0]):
        on_s = pulses[i] * pulse_s
        f = min(max((on_s - t0) / step_s, 0.0), 1.0)
        if faults[i, STUCK_ON] > 0.0:
            f = 1.0
        if faults[i, FAIL_OFF] > 0.0:
            f = 0.0
        out[i] = f


@njit(cache=True)
def thrust_force_torque_B(on, engine_on, cm_B, tp, ep):
    """(force_B N, torque_B N m about the centre of mass, propellant flow kg/s,
    engine torque_B N m alone: the main-engine disturbance)."""
    force = np.zeros(3)
    torque = np.zeros(3)
    flow = 0.0
    for i in range(on.shape[0]):
        if on[i] <= 0.0:
            continue
        f = (on[i] * tp.thrust_N[i]) * tp.direction_B[i]
        force += f
        torque += cross(tp.position_B[i] - cm_B, f)
        flow += on[i] * tp.thrust_N[i] / (tp.isp_s[i] * G0_m_s2)
    engine_torque = np.zeros(3)
    if engine_on > 0.0:
        f = (engine_on * ep.thrust_N) * ep.direction_B
        force += f
        engine_torque = cross(ep.position_B - cm_B, f)
        torque += engine_torque
        flow += engine_on * ep.thrust_N / (ep.isp_s * G0_m_s2)
    return force, torque, flow, engine_torque
