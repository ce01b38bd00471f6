"""sim/truth/rigid_body.py, sim/truth/dynamics.py and sim/truth/wheels.py checked
from outside: conservation laws, the closed-form torque-free axisymmetric
nutation, an independent scipy solve_ivp integration of the textbook equations
of motion (Markley & Crassidis 2014, eq. 3.147-3.150), hand-computed wheel
torques, the first-order spin-down of a seized wheel, and Kepler's circular
orbit for the translational part of the state.

The physics checks run the whole-spacecraft integrator (dynamics.rk4_step) on
build.make_free_body_params: constant mass, no surface, no thrusters, no
disturbance torque, point-mass gravity only, so the attitude part is exactly
the torque-free rigid body with wheels and the orbit part is the two-body
problem.

Units: rad, rad/s, N m, N m s, kg m^2, J, s, m. 1 arcsec = 4.848e-6 rad.
"""
from datetime import UTC, datetime
from pathlib import Path

import numpy as np
import pytest
import yaml
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from sim.truth import dynamics
from sim.truth.build import make_free_body_params
from sim.truth.rigid_body import (
    IH,
    IQ,
    IW,
    N_WHEEL_FAULT_SLOTS,
    W_EXTRA_VISCOUS,
    W_MOTOR_OFF,
    angular_momentum_B,
    attitude_state_size,
    body_derivatives,
    kinetic_energy,
    make_wheel_params,
)
from sim.truth.wheels import rotor_torque_Nm

ARCSEC = np.pi / 180.0 / 3600.0   # rad per arcsec (definition)

# SDO numbers read straight from the YAML (not through sim.spacecraft.model).
_SDO = yaml.safe_load((Path(__file__).resolve().parents[1] / "sim" / "spacecraft" / "sdo.yaml").read_text())
SDO_INERTIA = np.diag([2211.0, 3963.0, 3268.0])    # sdo.yaml inertia_B_kgm2 (seed 000 K_p / k_p)
SDO_AXES = np.array(_SDO["wheels"]["axes_B"])       # sdo.yaml: 4-wheel pyramid, 30 deg to the YZ plane
SDO_JS = _SDO["wheels"]["spin_inertia_kgm2"]        # 0.1114 kg m^2
SDO_HMAX = _SDO["wheels"]["h_max_Nms"]              # 70 N m s
SDO_TMAX = _SDO["wheels"]["torque_max_Nm"]          # 0.25 N m
SDO_VISC = _SDO["wheels"]["viscous_Nm_per_rad_s"]   # 1.67e-4 N m / (rad/s)
SDO_COUL = _SDO["wheels"]["coulomb_Nm"]             # 0.002 N m
COULOMB_SPEED = 0.1                                  # rad/s, model.py default of coulomb_smoothing_rad_s
# J' = J - J_s G G^T (M&C eq. 3.147), computed here, independently of make_wheel_params
SDO_J_PRIME = SDO_INERTIA - SDO_JS * SDO_AXES.T @ SDO_AXES

MU_EARTH = 3.986004418e14   # m^3/s^2, WGS84 GM incl. atmosphere (NIMA TR8350.2, 3rd ed., Table 3.1)
EPOCH = datetime(2026, 3, 20, 12, 0, 0, tzinfo=UTC)   # point-mass gravity does not depend on it
R_GEO = np.array([42164e3, 0.0, 0.0])    # m
V_GEO = np.array([0.0, 3074.66, 0.0])    # m/s, sqrt(mu / r) = 3074.666: circular to 2e-6


def sdo_wheels(viscous=0.0, coulomb=0.0, coulomb_speed=COULOMB_SPEED):
    return make_wheel_params(SDO_AXES, SDO_JS, SDO_TMAX, SDO_HMAX, viscous, coulomb, coulomb_speed)


def free_body(inertia, wheels, duration_s=3600.0):
    """The whole-spacecraft parameters of a torque-free body with wheels in a
    point-mass gravity field (build.make_free_body_params)."""
    return make_free_body_params(inertia, wheels, EPOCH, duration_s=duration_s, zonal=False)


def sdo_params(viscous=0.0, coulomb=0.0, coulomb_speed=COULOMB_SPEED):
    return free_body(SDO_INERTIA, sdo_wheels(viscous, coulomb, coulomb_speed))


def make_state(q_BN, omega, h, r_N=R_GEO, v_N=V_GEO):
    """Whole state on the near-circular orbit, propellant 0, theta_int 0."""
    n = len(h)
    x = dynamics.initial_state(q_BN, omega, h, r_N, v_N, 0.0)
    ir, _, im = dynamics.offsets(n)
    assert x.shape == (dynamics.state_size(n),) and x[IH + n:ir].tolist() == [0.0, 0.0, 0.0]
    assert x[im] == 0.0
    return x


class Integrator:
    """dynamics.rk4_step with its step inputs, held loads and scratch. Each
    step holds the wheel commands u and the extra torque tau (zero-order hold)
    and starts at the running time t."""

    def __init__(self, p, x):
        self.p = p
        self.inp = dynamics.make_inputs(p.wheels.axes_B.shape[0], 0)
        self.held = dynamics.make_held()
        self.work = np.empty((5, len(x)))
        self.t = 0.0

    def step(self, x, u, tau, dt):
        self.inp.wheel_cmd_Nm[:] = u
        self.inp.torque_extra_B[:] = tau
        self.inp.t_s[0] = self.t
        dynamics.rk4_step(x, self.p, self.inp, self.held, dt, self.work)
        self.t += dt


def full_derivatives(x, p, u, tau, faults=None):
    """dx/dt of the whole state: dynamics.hold_loads then dynamics.derivatives."""
    n = p.wheels.axes_B.shape[0]
    inp = dynamics.make_inputs(n, 0)
    inp.wheel_cmd_Nm[:] = u
    inp.torque_extra_B[:] = tau
    if faults is not None:
        inp.wheel_faults[:] = faults
    held = dynamics.make_held()
    dynamics.hold_loads(x, p, inp, held)
    dx = np.full(len(x), np.nan)
    dynamics.derivatives(x, p, inp, held, dx)
    return dx, held


def h_from_speeds(speeds, omega, axes, js):
    """Wheel state from relative speeds: h_i = J_s (Omega_i + g_i . omega)
    (sim/truth/wheels.py module docstring; Markley & Crassidis sec. 3.3.5.3)."""
    return js * (np.asarray(speeds, float) + np.asarray(axes) @ np.asarray(omega, float))


def speeds_from_h(x, axes, js):
    """The inverse: Omega_i = h_i / J_s - g_i . omega."""
    axes = np.asarray(axes)
    return x[IH:IH + len(axes)] / js - axes @ x[IW:IW + 3]


def random_unit_quat(rng):
    q = rng.standard_normal(4)
    return q / np.linalg.norm(q)


def H_inertial(x, j_prime, wheels):
    """H_N = dcm_NB H_B, with scipy's matrix of q_BN (sim/attitude.py convention)."""
    return Rotation.from_quat(x[IQ:IQ + 4], scalar_first=True).apply(angular_momentum_B(x, j_prime, wheels))


# --- state layout ---------------------------------------------------------------

def test_state_size_layout():
    """Attitude part x = [q (4), omega (3), h (N), theta_int (3)]: 4 + 3 + N + 3;
    the whole state appends r_N (3), v_N (3), m_propellant (1)."""
    assert (IQ, IW, IH) == (0, 4, 7)
    assert attitude_state_size(4) == 14
    assert attitude_state_size(3) == 13
    assert attitude_state_size(6) == 16
    assert dynamics.state_size(4) == 21
    assert dynamics.state_size(3) == 20
    assert dynamics.state_size(6) == 23
    assert dynamics.offsets(4) == (14, 17, 20)
    assert dynamics.offsets(3) == (13, 16, 19)
    x = dynamics.initial_state([0.5, 0.5, -0.5, 0.5], [1.0, 2.0, 3.0], [4.0, 5.0, 6.0, 7.0],
                               [8.0, 9.0, 10.0], [11.0, 12.0, 13.0], 14.0)
    np.testing.assert_array_equal(x, [0.5, 0.5, -0.5, 0.5, 1, 2, 3, 4, 5, 6, 7, 0, 0, 0,
                                      8, 9, 10, 11, 12, 13, 14])


# --- make_wheel_params / J' -------------------------------------------------------

def test_inertia_prime_by_hand():
    """J' = J - J_s sum g g^T (M&C eq. 3.147). For the SDO pyramid
    g = [1/2, cos30 cos phi, cos30 sin phi], phi = 0, 90, 180, 270 deg:
    sum g g^T = diag(4/4, 2*3/4, 2*3/4) = diag(1, 1.5, 1.5), off-diagonals cancel,
    so J_s sum g g^T = diag(0.1114, 0.1671, 0.1671) and
    J' = diag(2211 - 0.1114, 3963 - 0.1671, 3268 - 0.1671). The free body holds
    this J' (and its inverse) over every step, with constant mass (J'dot = 0) and
    no external load."""
    wheels = sdo_wheels()
    np.testing.assert_allclose(wheels.spin_inertia_B, np.diag([0.1114, 0.1671, 0.1671]), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(wheels.axes_B, SDO_AXES)
    assert wheels.axes_B.flags.c_contiguous
    assert (wheels.spin_inertia, wheels.torque_max, wheels.h_max) == (0.1114, 0.25, 70.0)
    assert (wheels.viscous, wheels.coulomb, wheels.coulomb_speed) == (0.0, 0.0, COULOMB_SPEED)

    p = free_body(SDO_INERTIA, wheels)
    x = make_state([0.5, 0.5, -0.5, 0.5], [0.01, -0.02, 0.03], [10.0, -5.0, 3.0, 1.0])
    _, held = full_derivatives(x, p, np.zeros(4), np.zeros(3))
    want = np.diag([2210.8886, 3962.8329, 3267.8329])
    np.testing.assert_allclose(held.j_prime, want, rtol=0, atol=1e-11)   # kg m^2
    np.testing.assert_allclose(held.j_prime_inv, np.diag(1.0 / np.diag(want)), rtol=1e-14, atol=1e-19)
    np.testing.assert_allclose(SDO_J_PRIME, want, rtol=0, atol=1e-11)   # the test's own J'
    np.testing.assert_array_equal(held.j_prime_dot, 0.0)     # constant mass
    np.testing.assert_array_equal(held.torque_B, 0.0)        # no SRP, gravity gradient, thrust
    np.testing.assert_array_equal(held.force_N, 0.0)
    assert held.scalars[1] == 0.0                            # no propellant flow


def test_inertia_prime_full_inertia_with_products():
    """Non-diagonal J and a skewed wheel: J' = J - J_s g g^T computed by hand for
    g = [0, 0.6, 0.8]: g g^T = [[0,0,0],[0,.36,.48],[0,.48,.64]], J_s = 0.5."""
    J = np.array([[100.0, 2.0, -3.0], [2.0, 150.0, 4.0], [-3.0, 4.0, 120.0]])
    wheels = make_wheel_params([[0.0, 0.6, 0.8]], 0.5, 0.1, 10.0, 0.0, 0.0, 0.1)
    np.testing.assert_allclose(wheels.spin_inertia_B, [[0, 0, 0], [0, 0.18, 0.24], [0, 0.24, 0.32]],
                               rtol=0, atol=1e-15)
    p = free_body(J, wheels)
    x = make_state([1.0, 0, 0, 0], [0.0, 0.0, 0.0], [0.0])
    _, held = full_derivatives(x, p, np.zeros(1), np.zeros(3))
    want = np.array([[100.0, 2.0, -3.0], [2.0, 149.82, 3.76], [-3.0, 3.76, 119.68]])
    np.testing.assert_allclose(held.j_prime, want, rtol=0, atol=1e-12)
    np.testing.assert_allclose(held.j_prime_inv @ want, np.eye(3), rtol=0, atol=1e-14)


# --- angular_momentum_B / kinetic_energy -------------------------------------

def test_angular_momentum_and_energy_textbook_forms():
    """In terms of the full inertia J and relative wheel speeds Omega:
    H_B = J omega + J_s sum Omega_i g_i,
    T = 1/2 omega^T J omega + J_s sum Omega_i (g_i . omega) + 1/2 J_s sum Omega_i^2
    (body incl. rotors' transverse inertia plus each rotor's spin energy
    1/2 J_s (Omega_i + g_i . omega)^2, expanded). J' = J - J_s G G^T (eq. 3.147)
    is computed in this file."""
    wheels = sdo_wheels()
    omega = np.array([0.012, -0.034, 0.021])          # rad/s
    speeds = np.array([300.0, -150.0, 45.0, -600.0])  # rad/s
    x = make_state([1.0, 0, 0, 0], omega, h_from_speeds(speeds, omega, SDO_AXES, SDO_JS))
    H_want = SDO_INERTIA @ omega + SDO_JS * SDO_AXES.T @ speeds
    np.testing.assert_allclose(angular_momentum_B(x, SDO_J_PRIME, wheels), H_want, rtol=0, atol=1e-12)   # N m s
    g_dot_w = SDO_AXES @ omega
    T_want = 0.5 * omega @ SDO_INERTIA @ omega + SDO_JS * np.sum(speeds * g_dot_w) + 0.5 * SDO_JS * np.sum(speeds ** 2)
    assert kinetic_energy(x, SDO_J_PRIME, wheels) == pytest.approx(T_want, rel=1e-13, abs=0)               # J
    # hand number, body only: omega = [0.1, 0, 0], h = 0: H = J'_xx * 0.1, T = J'_xx * 0.01 / 2
    J_prime_hand = np.diag([2210.8886, 3962.8329, 3267.8329])
    x0 = make_state([1.0, 0, 0, 0], [0.1, 0.0, 0.0], np.zeros(4))
    np.testing.assert_allclose(angular_momentum_B(x0, J_prime_hand, wheels), [221.08886, 0.0, 0.0], rtol=0, atol=1e-12)
    assert kinetic_energy(x0, J_prime_hand, wheels) == pytest.approx(11.054443, rel=1e-14)


# --- derivatives --------------------------------------------------------------

def test_derivatives_hand_values_at_rest():
    """Body at rest, wheels at rest, wheel 1 commanded 0.1 N m, no drag:
    dh = [0.1, 0, 0, 0] N m; the body takes -0.1 g_1 = [-0.05, +0.0866025, 0] N m,
    so domega = that / diag(J') = [-0.05/2210.8886, 0.08660254/3962.8329, 0] rad/s^2;
    dq = 0, dtheta_int = omega = 0. Orbit part: dr = v, dv = -mu r / |r|^3 =
    [-mu / 42164e3^2, 0, 0] = [-0.2242096, 0, 0] m/s^2 (point mass, WGS84 mu),
    dm_propellant = 0."""
    p = sdo_params()
    q = np.array([0.5, 0.5, -0.5, 0.5])
    x = make_state(q, np.zeros(3), np.zeros(4))
    dx, _ = full_derivatives(x, p, np.array([0.1, 0.0, 0.0, 0.0]), np.zeros(3))
    np.testing.assert_allclose(dx[IH:IH + 4], [0.1, 0, 0, 0], rtol=0, atol=1e-17)
    np.testing.assert_allclose(dx[IW:IW + 3], [-0.05 / 2210.8886, 0.08660254037844386 / 3962.8329, 0.0],
                               rtol=1e-13, atol=1e-20)
    np.testing.assert_array_equal(dx[IQ:IQ + 4], 0.0)
    np.testing.assert_array_equal(dx[IH + 4:IH + 7], 0.0)
    ir, iv, im = dynamics.offsets(4)
    np.testing.assert_array_equal(dx[ir:ir + 3], V_GEO)                                   # m/s
    np.testing.assert_allclose(dx[iv:iv + 3], [-MU_EARTH / 42164e3 ** 2, 0.0, 0.0], rtol=1e-14, atol=1e-20)
    assert dx[iv] == pytest.approx(-0.2242096, abs=1e-7)                                 # m/s^2
    assert dx[im] == 0.0                                                                  # kg/s


def test_derivatives_external_torque_and_gyroscopic_hand_values():
    """Spin about z at 0.1 rad/s with wheel momentum h = 5 N m s in a single
    wheel along x (no wheel torque, no drag) and tau_ext = [0, 0, 0.3] N m:
    three wheels along the body axes, J_s = 0.2, so J' = diag(2210.8, 3962.8, 3267.8);
    H_B = J' omega + G h = [5, 0, 326.78], omega x H = [0, 0.1 * 5, 0] = [0, 0.5, 0],
    J' domega = tau - omega x H = [0, -0.5, 0.3].
    Checked twice: rigid_body.body_derivatives on the attitude state with J' by
    hand, and the whole-spacecraft path (hold_loads, derivatives) with the
    torque as StepInputs.torque_extra_B."""
    J = np.diag([2211.0, 3963.0, 3268.0])
    wheels = make_wheel_params([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], 0.2, 0.25, 70.0, 0.0, 0.0, 0.1)
    np.testing.assert_allclose(wheels.spin_inertia_B, 0.2 * np.eye(3), rtol=0, atol=1e-16)
    tau = np.array([0.0, 0.0, 0.3])

    j_prime = np.diag([2210.8, 3962.8, 3267.8])     # by hand
    xa = np.zeros(attitude_state_size(3))
    xa[IQ] = 1.0
    xa[IW + 2] = 0.1
    xa[IH] = 5.0
    dxa = np.full(len(xa), np.nan)
    body_derivatives(xa, j_prime, np.linalg.inv(j_prime), np.zeros((3, 3)), wheels,
                     np.zeros((3, N_WHEEL_FAULT_SLOTS)), np.zeros(3), tau, dxa)

    x = make_state([1.0, 0, 0, 0], [0.0, 0.0, 0.1], [5.0, 0.0, 0.0])
    np.testing.assert_array_equal(x[:attitude_state_size(3)], xa)
    dx, _ = full_derivatives(x, free_body(J, wheels), np.zeros(3), tau)

    for d in (dxa, dx):
        np.testing.assert_allclose(d[IW:IW + 3], [0.0, -0.5 / 3962.8, 0.3 / 3267.8], rtol=1e-13, atol=1e-20)
        np.testing.assert_array_equal(d[IH:IH + 3], 0.0)
        # dq = 0.5 [1,0,0,0] (x) [0, 0, 0, 0.1] = [0, 0, 0, 0.05]; dtheta_int = omega
        np.testing.assert_allclose(d[IQ:IQ + 4], [0, 0, 0, 0.05], rtol=0, atol=1e-17)
        np.testing.assert_allclose(d[IH + 3:IH + 6], [0, 0, 0.1], rtol=0, atol=1e-17)


def test_derivatives_drag_uses_speed_relative_to_body():
    """dh_i = -viscous * Omega_i with Omega_i = h_i / J_s - g_i . omega
    (sim/truth/wheels.py): the rotor speed relative to the body, not inertial."""
    p = sdo_params(viscous=1e-3)
    omega = np.array([0.01, 0.02, -0.03])
    speeds = np.array([100.0, -50.0, 0.0, 20.0])
    x = make_state([1.0, 0, 0, 0], omega, h_from_speeds(speeds, omega, SDO_AXES, SDO_JS))
    dx, _ = full_derivatives(x, p, np.zeros(4), np.zeros(3))
    np.testing.assert_allclose(dx[IH:IH + 4], -1e-3 * speeds, rtol=0, atol=1e-15)   # N m


def test_wheel_fault_slots_hand_values():
    """Per-wheel fault slots (rigid_body.W_MOTOR_OFF, W_EXTRA_VISCOUS): a motor
    that is off ignores its command; extra viscous drag c adds -c Omega_i to the
    wheel's own drag, Omega_i relative to the body. All four wheels commanded
    0.1 N m, own drag 1e-3 N m/(rad/s), speeds [100, -50, 20, 10] rad/s:
    wheel 1 motor off:              dh = -1e-3 * 100              = -0.1
    wheel 2 extra drag 1.0:         dh = 0.1 - (1e-3 + 1.0) * -50 = 50.15
    wheel 3 motor off + drag 1.0:   dh = -(1e-3 + 1.0) * 20       = -20.02
    wheel 4 healthy:                dh = 0.1 - 1e-3 * 10          = 0.09
    The torque is internal: the body takes -G dh, J' domega = -G dh - omega x H
    (M&C eq. 3.147-3.149, evaluated here with numpy)."""
    wheels = sdo_wheels(viscous=1e-3)
    omega = np.array([0.01, 0.02, -0.03])
    speeds = np.array([100.0, -50.0, 20.0, 10.0])
    x = make_state([1.0, 0, 0, 0], omega, h_from_speeds(speeds, omega, SDO_AXES, SDO_JS))
    faults = np.zeros((4, N_WHEEL_FAULT_SLOTS))
    faults[0, W_MOTOR_OFF] = 1.0
    faults[1, W_EXTRA_VISCOUS] = 1.0
    faults[2, W_MOTOR_OFF] = 1.0
    faults[2, W_EXTRA_VISCOUS] = 1.0
    u = np.full(4, 0.1)
    dh_want = np.array([-0.1, 50.15, -20.02, 0.09])
    dx, _ = full_derivatives(x, free_body(SDO_INERTIA, wheels), u, np.zeros(3), faults)
    np.testing.assert_allclose(dx[IH:IH + 4], dh_want, rtol=0, atol=1e-12)   # N m

    xa = x[:attitude_state_size(4)].copy()
    dxa = np.full(len(xa), np.nan)
    body_derivatives(xa, SDO_J_PRIME, np.linalg.inv(SDO_J_PRIME), np.zeros((3, 3)), wheels, faults, u,
                     np.zeros(3), dxa)
    np.testing.assert_allclose(dxa[IH:IH + 4], dh_want, rtol=0, atol=1e-12)
    H = SDO_J_PRIME @ omega + SDO_AXES.T @ x[IH:IH + 4]
    dw_want = np.linalg.solve(SDO_J_PRIME, -SDO_AXES.T @ dh_want - np.cross(omega, H))
    for d in (dx, dxa):
        np.testing.assert_allclose(d[IW:IW + 3], dw_want, rtol=1e-12, atol=1e-18)   # rad/s^2


# --- rotor_torque_Nm (hand numbers) -------------------------------------------

@pytest.mark.parametrize("speed, u, want", [
    # no drag: the motor command, clipped at +-0.25 N m (sdo.yaml torque_max_Nm)
    (0.0, 0.1, 0.1),
    (0.0, 0.4, 0.25),
    (0.0, -1.0, -0.25),
    (100.0, 0.25, 0.25),
    # h_rel = 0.1114 * speed; h_max = 70 N m s <=> speed 628.366 rad/s
    (69.99 / 0.1114, 0.1, 0.1),       # just below capacity: passes
    (70.01 / 0.1114, 0.1, 0.0),       # past +capacity, torque would add: cut
    (70.01 / 0.1114, -0.1, -0.1),     # past +capacity, torque unloads: passes
    (700.0, 5.0, 0.0),                # past +capacity, clipped then cut
    (-70.01 / 0.1114, -0.1, 0.0),     # past -capacity, torque would add: cut
    (-70.01 / 0.1114, 0.2, 0.2),      # past -capacity, unloading: passes
    (-69.99 / 0.1114, -0.3, -0.25),   # just inside: clipped only
])
def test_rotor_torque_limits(speed, u, want):
    p = sdo_wheels()
    assert rotor_torque_Nm(speed, u, p) == pytest.approx(want, abs=1e-15)   # N m


@pytest.mark.parametrize("speed, u, want", [
    # drag = -(viscous * speed + coulomb * tanh(speed / 0.1)), viscous 1.67e-4, coulomb 0.002
    (332.0, 0.0, -(0.055444 + 0.002)),                          # tanh(3320) = 1
    (-332.0, 0.0, +(0.055444 + 0.002)),
    (0.05, 0.0, -(8.35e-6 + 0.002 * 0.46211715726000974)),      # tanh(0.5)
    (-0.05, 0.0, +(8.35e-6 + 0.002 * 0.46211715726000974)),
    (0.0, 0.0, 0.0),
    (100.0, 0.1, 0.1 - 0.0167 - 0.002),                         # motor plus drag = 0.0813
    (100.0, 1.0, 0.25 - 0.0167 - 0.002),                        # clipped motor plus drag
    (700.0, 0.2, -(0.1169 + 0.002)),                            # motor cut (h_rel 77.98), drag stays
    (-700.0, -0.2, +(0.1169 + 0.002)),
])
def test_rotor_torque_drag(speed, u, want):
    p = sdo_wheels(viscous=SDO_VISC, coulomb=SDO_COUL)
    assert rotor_torque_Nm(speed, u, p) == pytest.approx(want, abs=1e-15)   # N m


# --- conservation laws ---------------------------------------------------------

DT = 0.05  # s, sdo.yaml timing.truth_dt_s


def test_inertial_momentum_conserved_with_wheel_exchange():
    """No external torque: H_N = dcm_NB (J' omega + G h) is constant (Euler).
    SDO inertia and pyramid, tumbling body, four wheels driven by sinusoidal
    motor torques (zero-order hold per step), no drag, 1 h at dt 0.05 s.
    RK4 truncation at omega dt ~ 2e-3 rad and round-off over 72000 steps stay
    far below the 1e-9 relative tolerance (~1e-7 N m s here)."""
    rng = np.random.default_rng(7)
    wheels = sdo_wheels()
    x = make_state(random_unit_quat(rng), [0.02, -0.015, 0.03], [10.0, -20.0, 5.0, 15.0])
    ig = Integrator(free_body(SDO_INERTIA, wheels), x)
    H0 = H_inertial(x, SDO_J_PRIME, wheels)
    h0 = x[IH:IH + 4].copy()
    tau = np.zeros(3)
    amp = 0.2                                           # N m, below torque_max 0.25
    # periods 300..1000 s: each wheel's momentum swings by up to 2 * amp * T / (2 pi) = 19..64 N m s
    freq = 2 * np.pi / np.array([300.0, 450.0, 650.0, 1000.0])   # rad/s
    phase = np.array([0.0, 1.0, 2.0, 3.0])
    worst = 0.0
    h_swing = h_peak = 0.0
    for k in range(72000):
        ig.step(x, amp * np.sin(freq * (k * DT) + phase), tau, DT)
        h_peak = max(h_peak, np.max(np.abs(x[IH:IH + 4])))
        if k % 50 == 0:
            worst = max(worst, np.linalg.norm(H_inertial(x, SDO_J_PRIME, wheels) - H0))
            h_swing = max(h_swing, np.max(np.abs(x[IH:IH + 4] - h0)))
    worst = max(worst, np.linalg.norm(H_inertial(x, SDO_J_PRIME, wheels) - H0))
    assert h_swing > 10.0                               # N m s: the wheels did exchange momentum
    assert h_peak < 0.95 * SDO_HMAX                     # and never neared the 70 N m s cut-off
    assert worst / np.linalg.norm(H0) < 1e-9, worst / np.linalg.norm(H0)


def test_inertial_momentum_conserved_with_wheel_drag():
    """Wheel drag is internal (rotor on body): H_N stays constant with the SDO
    viscous and Coulomb drag on, wheels spinning down over 10 min (1e-9 relative)."""
    rng = np.random.default_rng(8)
    wheels = sdo_wheels(viscous=SDO_VISC, coulomb=SDO_COUL)
    x = make_state(random_unit_quat(rng), [0.01, 0.02, -0.01], [40.0, -30.0, 25.0, -35.0])
    ig = Integrator(free_body(SDO_INERTIA, wheels), x)
    H0 = H_inertial(x, SDO_J_PRIME, wheels)
    h0 = x[IH:IH + 4].copy()
    u, tau = np.zeros(4), np.zeros(3)
    worst = 0.0
    for k in range(12000):
        ig.step(x, u, tau, DT)
        if k % 50 == 0:
            worst = max(worst, np.linalg.norm(H_inertial(x, SDO_J_PRIME, wheels) - H0))
    assert np.max(np.abs(x[IH:IH + 4] - h0)) > 1.0     # N m s of drag actually acted
    assert worst / np.linalg.norm(H0) < 1e-9


def test_kinetic_energy_conserved_torque_free():
    """No motor torque, no drag, no external torque: h constant, and
    dT/dt = omega . (-omega x H) = 0. Tumbling SDO with non-zero wheel momenta,
    1 h at dt 0.05 s; relative drift below 1e-9. Also |H_B| is constant.
    The rotors' spin energy sum h^2 / (2 J_s) (~1.5e4 J) dwarfs the body's
    (~8 J) and is constant by itself here, so the body part 1/2 omega^T J' omega
    (J' by hand, see test_inertia_prime_by_hand) is held to
    1e-9 relative on its own: otherwise the test could not see a drift."""
    rng = np.random.default_rng(9)
    wheels = sdo_wheels()
    x = make_state(random_unit_quat(rng), [0.03, -0.04, 0.05], [30.0, -12.0, 18.0, 45.0])
    ig = Integrator(free_body(SDO_INERTIA, wheels), x)
    J_prime = np.diag([2210.8886, 3962.8329, 3267.8329])   # kg m^2, by hand
    T0 = kinetic_energy(x, J_prime, wheels)
    Hn0 = np.linalg.norm(angular_momentum_B(x, J_prime, wheels))
    h0 = x[IH:IH + 4].copy()
    w0 = x[IW:IW + 3].copy()
    u, tau = np.zeros(4), np.zeros(3)
    Tb0 = 0.5 * w0 @ J_prime @ w0
    worst_T = worst_H = worst_Tb = 0.0
    w_change = 0.0
    for k in range(72000):
        ig.step(x, u, tau, DT)
        if k % 50 == 0:
            w = x[IW:IW + 3]
            worst_Tb = max(worst_Tb, abs(0.5 * w @ J_prime @ w - Tb0))
            worst_T = max(worst_T, abs(kinetic_energy(x, J_prime, wheels) - T0))
            worst_H = max(worst_H, abs(np.linalg.norm(angular_momentum_B(x, J_prime, wheels)) - Hn0))
            w_change = max(w_change, np.linalg.norm(x[IW:IW + 3] - w0))
    np.testing.assert_array_equal(x[IH:IH + 4], h0)      # dh/dt = 0 exactly
    assert w_change > 1e-2                                # rad/s: the body really tumbles
    assert worst_T / T0 < 1e-9, worst_T / T0
    assert worst_Tb / Tb0 < 1e-9, worst_Tb / Tb0
    assert worst_H / Hn0 < 1e-9, worst_H / Hn0


# --- seized wheel (wheel fault slots) ----------------------------------------------

SEIZE_C = 1.0   # N m/(rad/s), W_EXTRA_VISCOUS of a seized bearing


def test_seized_wheel_spin_down_closed_form():
    """One wheel along the body z axis, a principal axis, body at rest, rotor
    at Omega_0 = 300 rad/s relative to the body; at t = 0 it seizes: motor off
    (W_MOTOR_OFF = 1, its 0.2 N m command ignored) and a bearing drag
    c = 1.0 N m/(rad/s) (W_EXTRA_VISCOUS), no other drag. omega and H stay on z,
    omega x H = 0, and the rotor-body pair is two coaxial inertias coupled by a
    viscous damper: with J'_z = J_z - J_s,
        J'_z domega/dt = c Omega,  dh/dt = -c Omega,  Omega = h / J_s - omega
    so dOmega/dt = -c (1/J_s + 1/J'_z) Omega:
        Omega(t) = Omega_0 exp(-t / tau),  tau = 1 / (c (1/J_s + 1/J'_z)) = 0.111396 s
    (the time constant J_s / c = 0.1114 s, less 3.4e-5 for the body's recoil), and
    angular momentum H_z = J_z omega + J_s Omega = J_s Omega_0 conserved, ending as J_z omega_f:
        omega_f = J_s Omega_0 / J_z,  T_f = (J_s Omega_0)^2 / (2 J_z)   (from T_0 = J_s Omega_0^2 / 2).
    dt = tau / 50: the RK4 error of a decaying exponential, ~ k (dt/tau)^5 / 120
    relative after k steps, stays below 3e-8 of Omega_0 over the 20 tau run."""
    J = np.diag([2211.0, 3963.0, 3268.0])
    js, omega0 = SDO_JS, 300.0
    wheels = make_wheel_params([[0.0, 0.0, 1.0]], js, SDO_TMAX, SDO_HMAX, 0.0, 0.0, COULOMB_SPEED)
    tau_c = 1.0 / (SEIZE_C * (1.0 / js + 1.0 / (3268.0 - js)))
    assert tau_c == pytest.approx(0.111396, abs=1e-6)
    x = make_state([1.0, 0, 0, 0], np.zeros(3), [js * omega0])
    ig = Integrator(free_body(J, wheels), x)
    ig.inp.wheel_faults[0, W_MOTOR_OFF] = 1.0
    ig.inp.wheel_faults[0, W_EXTRA_VISCOUS] = SEIZE_C
    u, tau = np.array([0.2]), np.zeros(3)
    T0 = kinetic_energy(x, J - js * np.diag([0.0, 0.0, 1.0]), wheels)
    assert T0 == pytest.approx(0.5 * js * omega0 ** 2, rel=1e-15)
    dt = tau_c / 50
    worst = worst_H = 0.0
    for k in range(1, 1001):
        ig.step(x, u, tau, dt)
        Omega = x[IH] / js - x[IW + 2]
        worst = max(worst, abs(Omega - omega0 * np.exp(-k * dt / tau_c)))
        worst_H = max(worst_H, abs(3268.0 * x[IW + 2] + js * Omega - js * omega0))   # H_z = J_z omega + J_s Omega
    assert worst < 3e-8 * omega0, worst / omega0                        # rad/s
    assert worst_H < 1e-12 * js * omega0, worst_H / (js * omega0)       # N m s
    assert abs(x[IH] / js - x[IW + 2]) < 1e-6                           # stopped: 300 * exp(-20) = 6e-7
    w_f = js * omega0 / 3268.0
    np.testing.assert_allclose(x[IW:IW + 3], [0.0, 0.0, w_f], rtol=0, atol=1e-8 * w_f)   # exp(-20) = 2e-9
    T_f = (js * omega0) ** 2 / (2 * 3268.0)                             # J, 1.7e-1 of the initial 5013 J
    assert kinetic_energy(x, J - js * np.diag([0.0, 0.0, 1.0]), wheels) == pytest.approx(T_f, rel=1e-6)


def test_seized_wheel_stops_and_momentum_is_conserved():
    """SDO body tumbling, wheel 1 (at 300 rad/s relative to the body) seizes at
    t = 0 (W_MOTOR_OFF = 1, W_EXTRA_VISCOUS = 1.0 N m/(rad/s)) while the other
    three keep their momentum (no command, no drag), 10 min.
    The seized rotor stops relative to the body within a few time constants
    tau ~ J_s / c = 0.1114 s (exp(-5) = 6.7e-3 at 5 tau); afterwards gyroscopic
    forcing g . J'^-1 (omega x H) ~ 1e-3 rad/s^2 keeps only |Omega| ~ tau * 1e-3
    ~ 1e-4 rad/s. The bearing torque is internal: H_N constant to 1e-9 relative
    through the transient and after.
    Steps: the first second at dt = 0.0125 s (tau / 9), then the truth dt of
    0.05 s. At 0.05 s throughout (dt / tau = 0.45, inside RK4's stability
    region |z| < 2.78) the fast mode's truncation error during the transient
    alone costs 6.1e-10 of |H_N| (measured; 3.3e-11 at 0.025 s, 1.9e-12 at
    0.0125 s: the dt^4 of RK4), too close to the 1e-9 bound to test a conservation
    law with; resolving tau keeps it at ~2e-12."""
    rng = np.random.default_rng(12)
    wheels = sdo_wheels()
    omega0 = 300.0
    w0 = np.array([0.02, -0.015, 0.03])
    x = make_state(random_unit_quat(rng), w0, h_from_speeds([omega0, -150.0, 100.0, 200.0], w0, SDO_AXES, SDO_JS))
    ig = Integrator(free_body(SDO_INERTIA, wheels), x)
    ig.inp.wheel_faults[0, W_MOTOR_OFF] = 1.0
    ig.inp.wheel_faults[0, W_EXTRA_VISCOUS] = SEIZE_C
    u, tau = np.array([0.2, 0.0, 0.0, 0.0]), np.zeros(3)   # the seized wheel's command is ignored
    tau_c = SDO_JS / SEIZE_C
    H0 = H_inertial(x, SDO_J_PRIME, wheels)
    h0 = x[IH + 1:IH + 4].copy()
    T0 = kinetic_energy(x, SDO_J_PRIME, wheels)
    worst = 0.0
    Omega_5tau = None
    Omega_late = 0.0
    dts = [DT / 4] * 80 + [DT] * 11980      # 1 s + 599 s
    for k, dt in enumerate(dts):
        ig.step(x, u, tau, dt)
        t = ig.t
        Omega = speeds_from_h(x, SDO_AXES, SDO_JS)[0]
        if Omega_5tau is None and t >= 5 * tau_c:
            Omega_5tau = abs(Omega)
        if t >= 20 * tau_c:
            Omega_late = max(Omega_late, abs(Omega))
        if k % 50 == 0 or k <= 200:
            worst = max(worst, np.linalg.norm(H_inertial(x, SDO_J_PRIME, wheels) - H0))
    assert ig.t == pytest.approx(600.0, abs=1e-9)
    assert Omega_5tau < 1e-2 * omega0, Omega_5tau         # rad/s: stopped within a few time constants
    assert Omega_late < 1e-3, Omega_late                   # rad/s, and stays stopped
    np.testing.assert_array_equal(x[IH + 1:IH + 4], h0)   # healthy wheels: dh/dt = 0 exactly
    assert kinetic_energy(x, SDO_J_PRIME, wheels) < T0 - 0.9 * 0.5 * SDO_JS * omega0 ** 2   # J dissipated
    assert worst / np.linalg.norm(H0) < 1e-9, worst / np.linalg.norm(H0)


# --- closed form: torque-free axisymmetric nutation ---------------------------

@pytest.mark.parametrize("h3", [0.0, 8.0])
def test_axisymmetric_nutation_closed_form(h3):
    """J' = diag(It, It, I3), torque free. Euler: It dw1/dt = -lambda It w2,
    It dw2/dt = lambda It w1, w3 constant, with
    lambda = ((I3 - It) w3 + h3) / It (Markley & Crassidis sec. 3.3; h3 = 0 is
    the rigid body's lambda = (I3 - It)/It w3, h3 a constant wheel momentum along
    the symmetry axis, the gyrostat). So w1 + i w2 = (w1_0 + i w2_0) exp(i lambda t).
    Three wheels along the body axes, J_s = 0.2, J = J' + J_s I so that J' is
    axisymmetric; no motor torque, no drag (h constant).
    RK4 phase error ~ (lambda dt)^4 lambda t / 120 ~ 1e-12 rad: tolerance 1e-10 rad/s
    on rates of ~0.03 rad/s, over 5 nutation periods."""
    It, I3, js = 3000.0, 4500.0, 0.2
    wheels = make_wheel_params(np.eye(3), js, 0.25, 70.0, 0.0, 0.0, 0.1)
    w0 = np.array([0.02, -0.01, 0.2])
    lam = ((I3 - It) * w0[2] + h3) / It          # 0.1 rad/s (h3 = 0) or 0.10267 rad/s
    x = make_state([1.0, 0, 0, 0], w0, [0.0, 0.0, h3])
    ig = Integrator(free_body(np.diag([It, It, I3]) + js * np.eye(3), wheels), x)
    u, tau = np.zeros(3), np.zeros(3)
    n_steps = round(5 * 2 * np.pi / lam / DT)
    worst = 0.0
    c0 = w0[0] + 1j * w0[1]
    for k in range(1, n_steps + 1):
        ig.step(x, u, tau, DT)
        if k % 20 == 0 or k == n_steps:
            c = c0 * np.exp(1j * lam * k * DT)
            worst = max(worst, abs(x[IW] - c.real), abs(x[IW + 1] - c.imag), abs(x[IW + 2] - w0[2]))
    assert worst < 1e-10, worst                  # rad/s


# --- independent integration: scipy solve_ivp of the textbook equations --------

def _textbook_rhs(J_prime, G, tau_ext, u):
    """M&C 2014 eq. 3.147-3.150 with constant motor torque and no drag:
    H_B = J' w + G h; dh/dt = u; J' dw/dt = tau_ext - G dh/dt - w x H_B;
    dq/dt = 0.5 q (x) [0, w] (Hamilton, scalar first); dtheta/dt = w."""
    J_inv = np.linalg.inv(J_prime)
    n = G.shape[1]

    def rhs(t, y):
        q, w, h = y[0:4], y[4:7], y[7:7 + n]
        H = J_prime @ w + G @ h
        dh = u
        dw = J_inv @ (tau_ext - G @ dh - np.cross(w, H))
        wx, wy, wz = w
        # right multiplication by the pure quaternion [0, w]: q (x) [0, w]
        Omega = np.array([[0.0, -wx, -wy, -wz],
                          [wx, 0.0, wz, -wy],
                          [wy, -wz, 0.0, wx],
                          [wz, wy, -wx, 0.0]])
        dq = 0.5 * Omega @ q
        return np.concatenate([dq, dw, dh, w])

    return rhs


def test_trajectory_matches_solve_ivp():
    """600 s, SDO body and pyramid, tumbling at ~0.03 rad/s, constant motor torques
    below the 0.25 N m limit, a constant external torque, no drag, momenta well
    inside 70 N m s. Reference: DOP853, rtol 1e-12, atol 1e-14, of the equations
    written above (J' computed here as J - J_s G G^T, eq. 3.147).
    Tolerances: attitude 1e-4 arcsec, rates 1e-12 rad/s, wheel momenta 1e-10 N m s,
    rate integral 1e-4 arcsec; RK4 at dt 0.05 s with omega dt ~ 2e-3 rad has a
    global error orders of magnitude smaller, and the reference is ~1e-12 relative.
    The external torque enters the integrator as StepInputs.torque_extra_B."""
    rng = np.random.default_rng(11)
    q0 = random_unit_quat(rng)
    w0 = np.array([0.02, -0.03, 0.015])
    h0 = np.array([10.0, -20.0, 5.0, 15.0])
    u = np.array([0.05, -0.03, 0.04, -0.02])     # N m, |u| < 0.25: no clipping
    tau_ext = np.array([1e-3, -2e-3, 5e-4])       # N m
    G = SDO_AXES.T                                # 3 x 4
    J_prime = SDO_INERTIA - SDO_JS * G @ G.T
    T_END, N_OUT = 600.0, 60
    t_eval = np.linspace(0.0, T_END, N_OUT + 1)
    y0 = np.concatenate([q0, w0, h0, np.zeros(3)])
    sol = solve_ivp(_textbook_rhs(J_prime, G, tau_ext, u), (0.0, T_END), y0, method="DOP853",
                    t_eval=t_eval, rtol=1e-12, atol=1e-14)
    assert sol.success

    x = make_state(q0, w0, h0)
    ig = Integrator(sdo_params(), x)
    steps_per_out = round(T_END / N_OUT / DT)
    err_att = err_w = err_h = err_th = 0.0
    for j in range(1, N_OUT + 1):
        for _ in range(steps_per_out):
            ig.step(x, u, tau_ext, DT)
        ref = sol.y[:, j]
        q_ref = ref[0:4] / np.linalg.norm(ref[0:4])
        err_att = max(err_att, (Rotation.from_quat(q_ref, scalar_first=True).inv()
                                * Rotation.from_quat(x[IQ:IQ + 4], scalar_first=True)).magnitude() / ARCSEC)
        err_w = max(err_w, np.max(np.abs(x[IW:IW + 3] - ref[4:7])))
        err_h = max(err_h, np.max(np.abs(x[IH:IH + 4] - ref[7:11])))
        err_th = max(err_th, np.max(np.abs(x[IH + 4:IH + 7] - ref[11:14])) / ARCSEC)
    # the reference really went somewhere: wheels moved 18-30 N m s, body turned > 30 deg
    assert np.max(np.abs(sol.y[7:11, -1] - h0)) > 10.0
    assert (Rotation.from_quat(q0, scalar_first=True).inv()
            * Rotation.from_quat(sol.y[0:4, -1], scalar_first=True)).magnitude() > np.radians(30)
    assert np.max(np.abs(x[IH:IH + 4])) < SDO_HMAX
    assert err_att < 1e-4, err_att        # arcsec
    assert err_w < 1e-12, err_w           # rad/s
    assert err_h < 1e-10, err_h           # N m s
    assert err_th < 1e-4, err_th          # arcsec


# --- the orbit part of the state: Kepler's circular orbit ---------------------------

def test_circular_orbit_closes_after_one_kepler_period():
    """Point-mass gravity only (make_free_body_params, zonal=False): a circular
    orbit of radius a = 42164 km, v = sqrt(mu / a), has the period
    T = 2 pi sqrt(a^3 / mu) = 86163.57 s (Kepler's third law, WGS84 mu). Over
    one period at dt = T / 28800 = 2.99 s the specific orbital energy
    v^2 / 2 - mu / r = -mu / (2 a) is conserved to 1e-9 relative, the position is
    at -r_0 at T / 2 and back at r_0 at T, each within 1 m. RK4 at n dt = 2.2e-4 rad
    has a truncation error ~ a (n dt)^5 / 120 per step ~ 1e-10 m, round-off
    ~ 1e-16 a per step: both far below 1 m. The free body at rest with idle wheels
    feels no torque from the orbit (gravity gradient off): omega stays exactly 0."""
    a = 42164e3
    v_c = np.sqrt(MU_EARTH / a)                              # 3074.666 m/s
    period = 2 * np.pi * np.sqrt(a ** 3 / MU_EARTH)         # s
    assert period == pytest.approx(86163.57, abs=0.01)
    n_steps = 28800
    dt = period / n_steps
    p = free_body(SDO_INERTIA, sdo_wheels(), duration_s=period + 600.0)
    assert p.gravity.mu_m3_s2 == MU_EARTH
    r0 = np.array([a, 0.0, 0.0])
    x = make_state([1.0, 0, 0, 0], np.zeros(3), np.zeros(4), r0, [0.0, v_c, 0.0])
    ir, iv, im = dynamics.offsets(4)
    ig = Integrator(p, x)
    u, tau = np.zeros(4), np.zeros(3)

    def energy(x):
        return 0.5 * x[iv:iv + 3] @ x[iv:iv + 3] - MU_EARTH / np.linalg.norm(x[ir:ir + 3])

    E0 = energy(x)
    assert E0 == pytest.approx(-MU_EARTH / (2 * a), rel=1e-15)   # J/kg
    worst_E = 0.0
    for k in range(1, n_steps + 1):
        ig.step(x, u, tau, dt)
        if k % 100 == 0:
            worst_E = max(worst_E, abs(energy(x) - E0))
        if k == n_steps // 2:
            assert np.linalg.norm(x[ir:ir + 3] + r0) < 1.0, x[ir:ir + 3] + r0   # m, half way round
    worst_E = max(worst_E, abs(energy(x) - E0))
    assert worst_E / abs(E0) < 1e-9, worst_E / abs(E0)
    assert np.linalg.norm(x[ir:ir + 3] - r0) < 1.0, x[ir:ir + 3] - r0            # m
    np.testing.assert_allclose(x[iv:iv + 3], [0.0, v_c, 0.0], rtol=0, atol=1e-3)  # m/s
    assert x[im] == 0.0
    np.testing.assert_array_equal(x[IW:IW + 3], 0.0)
    np.testing.assert_array_equal(x[IQ:IQ + 4], [1.0, 0.0, 0.0, 0.0])
