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
from sim.truth.ephemeris import earth_velocity_bary_N, sun_position_N
from sim.truth.rigid_body import IH, IQ, IW
from sim.truth.sensors import iru, star_tracker
from sim.truth.thrusters import N_FAULT_SLOTS as N_THRUSTER_FAULT_SLOTS
from sim.truth.thrusters import on_fraction

ARCSEC = np.pi / 180.0 / 3600.0


class TruthParams(NamedTuple):
    dyn: DynamicsParams
    iru: iru.IruParams
    st: star_tracker.StarTrackerParams
    truth_dt: float
    substeps: int


class TruthState(NamedTuple):
    x: np.ndarray              # dynamics state vector
    iru: np.ndarray            # IRU counter state
    inputs: StepInputs         # what acts over the current RK4 step (also read by telemetry)
    thruster_faults: np.ndarray  # (n_thrusters, N_THRUSTER_FAULT_SLOTS)
    held: dynamics.Held        # loads held over the current RK4 step
    work: np.ndarray           # (5, len(x)) RK4 scratch


def noise_per_cycle(n_star_trackers: int) -> int:
    return iru.N_NOISE + star_tracker.N_NOISE * n_star_trackers


def make_truth_state(x: np.ndarray, iru_state: np.ndarray, n_wheels: int, n_thrusters: int) -> TruthState:
    return TruthState(x, iru_state, dynamics.make_inputs(n_wheels, n_thrusters), np.zeros((n_thrusters, N_THRUSTER_FAULT_SLOTS)), dynamics.make_held(),
                      np.empty((5, x.shape[0])))


@njit(cache=True)
def set_environment(ts, p, t_s):
    """Fix the Sun's position and the lit fraction for the cycle starting at t_s."""
    n = p.dyn.wheels.axes_B.shape[0]
    ir = IH + n + 3
    sun = sun_position_N(p.dyn.ephem, t_s)
    ts.inputs.sun_N_m[:] = sun
    ts.inputs.lit_fraction[0] = lit_fraction(ts.x[ir:ir + 3], sun)
    ts.inputs.t_s[0] = t_s


@njit(cache=True)
def apparent_sun_N(ts, p):
    """Unit vector from the spacecraft to the Sun as its sensors see it (aberration included)."""
    n = p.dyn.wheels.axes_B.shape[0]
    ir = IH + n + 3
    x = ts.x
    return sun_vector_apparent_N(x[ir:ir + 3], x[ir + 3:ir + 6], ts.inputs.sun_N_m,
                                 earth_velocity_bary_N(p.dyn.ephem, ts.inputs.t_s[0]))


@njit(cache=True)
def sense(ts, p, noise, rec):
    n = p.dyn.wheels.axes_B.shape[0]
    x = ts.x
    iru.iru_sample(ts.iru, p.iru, x[IH + n:IH + n + 3], noise[:iru.N_NOISE], rec.iru_rate_B_rad_s)
    star_tracker.star_tracker_sample(x[IQ:IQ + 4], p.st, noise[iru.N_NOISE:], rec.st_q_SN, rec.st_valid)


@njit(cache=True)
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
