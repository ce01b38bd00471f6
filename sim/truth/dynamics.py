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
from sim.truth.gravity import GravityParams, gravity_accel_N
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
    j_prime: np.ndarray       # (3, 3) inertia less the rotors' spin inertia
    j_prime_inv: np.ndarray   # (3, 3)
    j_prime_dot: np.ndarray   # (3, 3)
    scalars: np.ndarray       # (2,) [1 / mass kg^-1, propellant flow kg/s]


def make_held() -> Held:
    return Held(np.zeros(3), np.zeros(3), np.eye(3), np.eye(3), np.zeros((3, 3)), np.zeros(2))


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


@njit(cache=True)
def loads(x, p, inp):
    n = p.wheels.axes_B.shape[0]
    ir = IH + n + 3
    q = x[IQ:IQ + 4]
    m_prop = x[ir + 6]
    cm = massmod.centre_of_mass_B(m_prop, p.mass)
    r_N = x[ir:ir + 3]
    to_sun_N = inp.sun_N_m - r_N
    d_sun = np.sqrt(np.sum(to_sun_N * to_sun_N))
    f_srp, t_srp = srp_force_torque_B(quat_rotate_inv(q, to_sun_N / d_sun), d_sun, inp.lit_fraction[0], cm, p.srp)
    t_gg = gravity_gradient_torque_B(quat_rotate_inv(q, r_N), massmod.inertia_B(m_prop, p.mass), p.gravity.mu_m3_s2)
    on, engine = inp.thruster_on, inp.engine_on[0]
    if m_prop <= 0.0:  # dry tanks: nothing fires
        on, engine = on * 0.0, 0.0
    f_thr, t_thr, flow, t_eng = thrust_force_torque_B(on, engine, cm, p.thrusters, p.engine)
    s = p.switches
    return Loads(s[SW_SRP] * t_srp, s[SW_GRAVITY_GRADIENT] * t_gg, t_thr - t_eng, s[SW_ENGINE_TORQUE] * t_eng,
                 s[SW_SRP] * f_srp + f_thr, flow)


@njit(cache=True)
def hold_loads(x, p, inp, held):
    """Evaluate the slowly varying loads and mass properties into `held`."""
    n = p.wheels.axes_B.shape[0]
    m_prop = x[IH + n + 3 + 6]
    ld = loads(x, p, inp)
    held.torque_B[:] = ld.torque_srp_B + ld.torque_gg_B + ld.torque_thrusters_B + ld.torque_engine_B
    held.torque_B[:] += inp.torque_extra_B
    held.force_N[:] = quat_rotate(x[IQ:IQ + 4], ld.force_B)
    held.j_prime[:] = massmod.inertia_B(m_prop, p.mass) - p.wheels.spin_inertia_B
    held.j_prime_inv[:] = inv3(held.j_prime)
    held.j_prime_dot[:] = massmod.inertia_rate_per_kg(p.mass) * (-ld.flow_kg_s)
    held.scalars[0] = 1.0 / massmod.total_mass_kg(m_prop, p.mass)
    held.scalars[1] = ld.flow_kg_s


@njit(cache=True)
def derivatives(x, p, inp, held, dx):
    n = p.wheels.axes_B.shape[0]
    ir = IH + n + 3
    body_derivatives(x, held.j_prime, held.j_prime_inv, held.j_prime_dot, p.wheels, inp.wheel_faults,
                     inp.wheel_cmd_Nm, held.torque_B, dx)
    accel = gravity_accel_N(x[ir:ir + 3], inp.t_s[0], p.gravity, p.ephem)
    inv_mass = held.scalars[0]
    for k in range(3):
        dx[ir + k] = x[ir + 3 + k]
        dx[ir + 3 + k] = accel[k] + held.force_N[k] * inv_mass
    dx[ir + 6] = -held.scalars[1]


@njit(cache=True)
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
