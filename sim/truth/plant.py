"""The truth model assembled: dynamics, environment and sensors, built from a
Spacecraft and a scenario's environment.

Once per control cycle `sense` samples every sensor into a SensorRecord and
`propagate` integrates the plant over the cycle with the actuator command
held: the environment (Sun position, lit fraction) is fixed at the top of the
cycle and RK4 steps at the pulse resolution, each with its thrusters' on-time.
Both are compiled and called from the runner's cycle loop (sim/loop.py).
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.truth import dynamics
from sim.truth.dynamics import DynamicsParams, StepInputs  # noqa: F401 (StepInputs: the type of TruthState.inputs)
from sim.truth.eclipse import lit_fraction, sun_vector_apparent_N
from sim.truth.ephemeris import earth_velocity_bary_N, moon_position_N, sun_position_N
from sim.truth.rigid_body import IH, IQ, IW
from sim.truth.sensor_suite import SensorFaults, SensorParams, SensorStates, sample_all
from sim.truth.sensor_suite import make_faults as make_sensor_faults
from sim.truth.wheels import wheel_speeds_rad_s
from sim.truth.thrusters import N_FAULT_SLOTS as N_THRUSTER_FAULT_SLOTS
from sim.truth.thrusters import on_fraction

class TruthParams(NamedTuple):
    dyn: DynamicsParams
    sensors: SensorParams
    truth_dt: float
    substeps: int


class TruthState(NamedTuple):
    x: np.ndarray                # dynamics state vector
    sensors: SensorStates        # sensor internal states (gyro counters, tachometer pulses)
    sensor_faults: SensorFaults
    inputs: StepInputs           # what acts over the current RK4 step (also read by telemetry)
    thruster_faults: np.ndarray  # (n_thrusters, N_THRUSTER_FAULT_SLOTS)
    held: dynamics.Held          # loads held over the current RK4 step
    work: np.ndarray             # (5, len(x)) RK4 scratch


def make_truth_state(x: np.ndarray, sensors: SensorStates, sensor_params: SensorParams, n_wheels: int,
                     n_thrusters: int) -> TruthState:
    return TruthState(x, sensors, make_sensor_faults(sensor_params, n_wheels),
                      dynamics.make_inputs(n_wheels, n_thrusters), np.zeros((n_thrusters, N_THRUSTER_FAULT_SLOTS)), dynamics.make_held(),
                      np.empty((5, x.shape[0])))


@njit(cache=True, inline="always")
def set_environment(ts, p, t_s):
    """Fix the Sun's position and the lit fraction for the cycle starting at t_s."""
    n = p.dyn.wheels.axes_B.shape[0]
    ir = IH + n + 3
    sun = sun_position_N(p.dyn.ephem, t_s)
    ts.inputs.sun_N_m[:] = sun
    ts.inputs.lit_fraction[0] = lit_fraction(ts.x[ir:ir + 3], sun)
    ts.inputs.t_s[0] = t_s


@njit(cache=True, inline="always")
def apparent_sun_N(ts, p):
    """Unit vector from the spacecraft to the Sun as its sensors see it (aberration included)."""
    n = p.dyn.wheels.axes_B.shape[0]
    ir = IH + n + 3
    x = ts.x
    return sun_vector_apparent_N(x[ir:ir + 3], x[ir + 3:ir + 6], ts.inputs.sun_N_m,
                                 earth_velocity_bary_N(p.dyn.ephem, ts.inputs.t_s[0]))


@njit(cache=True, inline="always")
def sense(ts, p, noise, rec):
    w = p.dyn.wheels
    n = w.axes_B.shape[0]
    ir = IH + n + 3
    x = ts.x
    speeds = wheel_speeds_rad_s(x[IH:IH + n], x[IW:IW + 3], w.axes_B, w.spin_inertia)
    sample_all(x[IQ:IQ + 4], x[IH + n:IH + n + 3], speeds, apparent_sun_N(ts, p), ts.inputs.lit_fraction[0],
               x[ir:ir + 3], moon_position_N(p.dyn.ephem, ts.inputs.t_s[0]), ts.sensors, p.sensors,
               ts.sensor_faults, noise, rec)


@njit(cache=True, inline="always")
def propagate(ts, p, act):
    """Integrate over one control cycle with the actuator command `act` held."""
    inp = ts.inputs
    inp.wheel_cmd_Nm[:] = act.wheel_torque_Nm
    inp.engine_on[0] = act.engine_on[0]
    t0 = inp.t_s[0]
    for j in range(p.substeps):
        on_fraction(act.thruster_pulses, j, p.truth_dt, p.dyn.thrusters.pulse_s, ts.thruster_faults,
                    inp.thruster_on)
        inp.t_s[0] = t0 + j * p.truth_dt
        dynamics.rk4_step(ts.x, p.dyn, inp, ts.held, p.truth_dt, ts.work)
    inp.t_s[0] = t0


def omega_of(ts: TruthState) -> np.ndarray:
    return ts.x[IW:IW + 3]
