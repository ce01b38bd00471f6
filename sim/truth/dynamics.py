"""The whole spacecraft's equations of motion and the truth integrator.

State x = [q_BN (4), omega_BN_B (3), h_wheels (N), theta_int_B (3),
           r_N (3), v_N (3), m_propellant (1)]

Rotation: sim/truth/rigid_body.py, with the inertia and centre of mass of the
current propellant load (sim/truth/mass.py) and the external torque of solar
radiation pressure and gravity gradient (sim/truth/disturbances.py) and of the
thrusters and main engine (sim/truth/thrusters.py).
Translation: gravity (sim/truth/gravity.py) plus thrust and SRP force over the
current mass. Mass: minus the propellant flow.

Inputs are held over one RK4 step (zero-order hold), and so are the slowly
varying loads: SRP, gravity gradient, thrust and the mass properties are
evaluated once at the top of each step (`hold_loads`; in 0.05 s they change by
parts per million), while the rotational dynamics and the orbit's gravity are
evaluated at every RK4 stage. One fixed-step RK4 integrates it all; the
quaternion is renormalised after each step.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.attitude import quat_rotate, quat_rotate_inv
from sim.linalg import inv3
from sim.truth import mass as massmod
from sim.truth.disturbances import SrpParams, gravity_gradient_torque_B, srp_force_torque_B
from sim.truth.ephemeris import EphemerisTable
from sim.truth.gravity import GravityParams, gravity_accel3
from sim.truth.rigid_body import IH, IQ, IW, WheelParams, attitude_state_size, body_derivatives
from sim.truth.thrusters import EngineParams, ThrusterParams, thrust_force_torque_B

# switches[] slots: disturbance torques a scenario may turn off
SW_SRP, SW_GRAVITY_GRADIENT, SW_ENGINE_TORQUE = 0, 1, 2
N_SWITCHES = 3


class DynamicsParams(NamedTuple):
    wheels: WheelParams
    mass: massmod.MassParams
    srp: SrpParams
    thrusters: ThrusterParams
    engine: EngineParams
    gravity: GravityParams
    ephem: EphemerisTable
    switches: np.ndarray  # (N_SWITCHES,) 1.0 on, 0.0 off


class StepInputs(NamedTuple):
    """What acts on the plant over one RK4 step."""
    wheel_cmd_Nm: np.ndarray    # (N,)
    thruster_on: np.ndarray     # (n_thrusters,) fraction of the step each fires
    engine_on: np.ndarray       # (1,) 0..1
    sun_N_m: np.ndarray         # (3,) geocentric Sun
    lit_fraction: np.ndarray    # (1,)
    torque_extra_B: np.ndarray  # (3,) any other torque (tests, unmodelled effects)
    t_s: np.ndarray             # (1,) time at the start of the step
    wheel_faults: np.ndarray    # (N, N_WHEEL_FAULT_SLOTS)


def make_inputs(n_wheels: int, n_thrusters: int) -> StepInputs:
    from sim.truth.rigid_body import N_WHEEL_FAULT_SLOTS
    return StepInputs(np.zeros(n_wheels), np.zeros(n_thrusters), np.zeros(1), np.array([1.496e11, 0.0, 0.0]),
                      np.ones(1), np.zeros(3), np.zeros(1), np.zeros((n_wheels, N_WHEEL_FAULT_SLOTS)))


class Held(NamedTuple):
    """Loads and mass properties held over one RK4 step (preallocated)."""
    torque_B: np.ndarray      # (3,) total external torque
    force_N: np.ndarray       # (3,) non-gravitational force, inertial axes
    inertia_B: np.ndarray     # (3, 3) about the centre of mass
    j_prime: np.ndarray       # (3, 3) inertia less the rotors' spin inertia
    j_prime_inv: np.ndarray   # (3, 3)
    j_prime_dot: np.ndarray   # (3, 3)
    cm_B: np.ndarray          # (3,) centre of mass, structure frame
    scalars: np.ndarray       # (3,) [1 / mass kg^-1, propellant flow kg/s, propellant of the mass properties kg]


H_INV_MASS, H_FLOW, H_MASS_OF = 0, 1, 2


def make_held() -> Held:
    return Held(np.zeros(3), np.zeros(3), np.eye(3), np.eye(3), np.eye(3), np.zeros((3, 3)), np.zeros(3),
                np.array([0.0, 0.0, np.nan]))


class Loads(NamedTuple):
    """Forces and torques at one instant, for telemetry."""
    torque_srp_B: np.ndarray
    torque_gg_B: np.ndarray
    torque_thrusters_B: np.ndarray
    torque_engine_B: np.ndarray
    force_B: np.ndarray
    flow_kg_s: float


def offsets(n_wheels: int) -> tuple[int, int, int]:
    """(r_N, v_N, m_propellant) offsets in the state vector."""
    ir = attitude_state_size(n_wheels)
    return ir, ir + 3, ir + 6


def state_size(n_wheels: int) -> int:
    return offsets(n_wheels)[2] + 1


def initial_state(q_BN, omega_BN_B_rad_s, h_wheels_Nms, r_N_m, v_N_m_s, propellant_kg) -> np.ndarray:
    """A state vector (theta_int starts at zero)."""
    n = len(h_wheels_Nms)
    ir, iv, im = offsets(n)
    x = np.zeros(state_size(n))
    x[IQ:IQ + 4] = q_BN
    x[IW:IW + 3] = omega_BN_B_rad_s
    x[IH:IH + n] = h_wheels_Nms
    x[ir:ir + 3] = r_N_m
    x[iv:iv + 3] = v_N_m_s
    x[im] = propellant_kg
    return x


@njit(cache=True, inline="always")
def loads_at(x, p, inp, cm, inertia):
    """Forces and torques with the centre of mass and inertia given. A load
    that is switched off, or that has nothing to act (no thruster firing, Sun
    eclipsed), is skipped, not computed and multiplied by zero."""
    n = p.wheels.axes_B.shape[0]
    ir = IH + n + 3
    q = x[IQ:IQ + 4]
    r_N = x[ir:ir + 3]
    zero = np.zeros(3)
    f_srp, t_srp = zero, zero
    if p.switches[SW_SRP] > 0.0 and inp.lit_fraction[0] > 0.0:
        to_sun_N = inp.sun_N_m - r_N
        d_sun = np.sqrt(np.sum(to_sun_N * to_sun_N))
        f_srp, t_srp = srp_force_torque_B(quat_rotate_inv(q, to_sun_N / d_sun), d_sun, inp.lit_fraction[0], cm,
                                          p.srp)
    t_gg = zero
    if p.switches[SW_GRAVITY_GRADIENT] > 0.0:
        t_gg = gravity_gradient_torque_B(quat_rotate_inv(q, r_N), inertia, p.gravity.mu_m3_s2)
    f_thr, t_thr, t_eng, flow = zero, zero, zero, 0.0
    engine = inp.engine_on[0]
    if x[ir + 6] > 0.0 and (engine > 0.0 or np.any(inp.thruster_on > 0.0)):  # dry tanks: nothing fires
        f_thr, t_all, flow, t_eng = thrust_force_torque_B(inp.thruster_on, engine, cm, p.thrusters, p.engine)
        t_thr = t_all - t_eng
        t_eng = p.switches[SW_ENGINE_TORQUE] * t_eng
    return Loads(t_srp, t_gg, t_thr, t_eng, f_srp + f_thr, flow)


@njit(cache=True)
def loads(x, p, inp):
    """Forces and torques at one instant (telemetry)."""
    n = p.wheels.axes_B.shape[0]
    m_prop = x[IH + n + 3 + 6]
    return loads_at(x, p, inp, massmod.centre_of_mass_B(m_prop, p.mass), massmod.inertia_B(m_prop, p.mass))


@njit(cache=True)
def _update_mass_properties(m_prop, p, held):
    """Only when the propellant has changed: between burns this is skipped."""
    held.inertia_B[:] = massmod.inertia_B(m_prop, p.mass)
    held.j_prime[:] = held.inertia_B - p.wheels.spin_inertia_B
    held.j_prime_inv[:] = inv3(held.j_prime)
    held.cm_B[:] = massmod.centre_of_mass_B(m_prop, p.mass)
    held.scalars[H_INV_MASS] = 1.0 / massmod.total_mass_kg(m_prop, p.mass)
    held.scalars[H_MASS_OF] = m_prop


@njit(cache=True, inline="always")
def hold_loads(x, p, inp, held):
    """Evaluate the slowly varying loads and mass properties into `held`."""
    n = p.wheels.axes_B.shape[0]
    m_prop = x[IH + n + 3 + 6]
    if m_prop != held.scalars[H_MASS_OF]:
        _update_mass_properties(m_prop, p, held)
    ld = loads_at(x, p, inp, held.cm_B, held.inertia_B)
    for k in range(3):
        held.torque_B[k] = (ld.torque_srp_B[k] + ld.torque_gg_B[k] + ld.torque_thrusters_B[k]
                            + ld.torque_engine_B[k] + inp.torque_extra_B[k])
    held.force_N[:] = quat_rotate(x[IQ:IQ + 4], ld.force_B)
    held.j_prime_dot[:] = massmod.inertia_rate_per_kg(p.mass) * (-ld.flow_kg_s)
    held.scalars[H_FLOW] = ld.flow_kg_s


@njit(cache=True, inline="always")
def derivatives(x, p, inp, held, dx):
    n = p.wheels.axes_B.shape[0]
    ir = IH + n + 3
    body_derivatives(x, held.j_prime, held.j_prime_inv, held.j_prime_dot, p.wheels, inp.wheel_faults,
                     inp.wheel_cmd_Nm, held.torque_B, dx)
    ax, ay, az = gravity_accel3(x[ir], x[ir + 1], x[ir + 2], inp.t_s[0], p.gravity, p.ephem)
    inv_mass = held.scalars[H_INV_MASS]
    for k in range(3):
        dx[ir + k] = x[ir + 3 + k]
    dx[ir + 3] = ax + held.force_N[0] * inv_mass
    dx[ir + 4] = ay + held.force_N[1] * inv_mass
    dx[ir + 5] = az + held.force_N[2] * inv_mass
    dx[ir + 6] = -held.scalars[H_FLOW]


@njit(cache=True, inline="always")
def rk4_step(x, p, inp, held, dt, work):
    """One fixed RK4 step in place. work: (5, len(x)) scratch, so the step
    allocates no state-sized arrays."""
    k1, k2, k3, k4, xt = work[0], work[1], work[2], work[3], work[4]
    m = x.shape[0]
    hold_loads(x, p, inp, held)
    derivatives(x, p, inp, held, k1)
    for i in range(m):
        xt[i] = x[i] + 0.5 * dt * k1[i]
    derivatives(xt, p, inp, held, k2)
    for i in range(m):
        xt[i] = x[i] + 0.5 * dt * k2[i]
    derivatives(xt, p, inp, held, k3)
    for i in range(m):
        xt[i] = x[i] + dt * k3[i]
    derivatives(xt, p, inp, held, k4)
    for i in range(m):
        x[i] += (dt / 6.0) * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
    norm = np.sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + x[3] * x[3])
    for i in range(4):
        x[IQ + i] /= norm
