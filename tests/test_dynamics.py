"""sim/truth/rigid_body.py and sim/truth/wheels.py checked from outside:
conservation laws, the closed-form torque-free axisymmetric nutation, an
independent scipy solve_ivp integration of the textbook equations of motion
(Markley & Crassidis 2014, eq. 3.147-3.150) and hand-computed wheel torques.

Units: rad, rad/s, N m, N m s, kg m^2, J, s. 1 arcsec = 4.848e-6 rad.
"""
from pathlib import Path

import numpy as np
import pytest
import yaml
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from sim.truth.rigid_body import (
    IH,
    IQ,
    IW,
    angular_momentum_B,
    derivatives,
    initial_state,
    kinetic_energy,
    make_body_params,
    rk4_step,
    state_size,
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


def sdo_params(viscous=0.0, coulomb=0.0, coulomb_speed=COULOMB_SPEED):
    return make_body_params(SDO_INERTIA, SDO_AXES, SDO_JS, SDO_TMAX, SDO_HMAX, viscous, coulomb, coulomb_speed)


def make_state(q_BN, omega, h):
    x = initial_state(q_BN, omega, h)
    assert x.shape == (state_size(len(h)),) and x[-3:].tolist() == [0.0, 0.0, 0.0]
    return x


def h_from_speeds(speeds, omega, axes, js):
    """Wheel state from relative speeds: h_i = J_s (Omega_i + g_i . omega)
    (sim/truth/wheels.py module docstring; Markley & Crassidis sec. 3.3.5.3)."""
    return js * (np.asarray(speeds, float) + np.asarray(axes) @ np.asarray(omega, float))


def random_unit_quat(rng):
    q = rng.standard_normal(4)
    return q / np.linalg.norm(q)


def H_inertial(x, p):
    """H_N = dcm_NB H_B, with scipy's matrix of q_BN (sim/attitude.py convention)."""
    return Rotation.from_quat(x[IQ:IQ + 4], scalar_first=True).apply(angular_momentum_B(x, p))


# --- make_body_params / state_size ------------------------------------------

def test_state_size_layout():
    """x = [q (4), omega (3), h (N), theta_int (3)]: 4 + 3 + N + 3."""
    assert (IQ, IW, IH) == (0, 4, 7)
    assert state_size(4) == 14
    assert state_size(3) == 13
    assert state_size(6) == 16


def test_make_body_params_inertia_prime_by_hand():
    """J' = J - J_s sum g g^T (M&C eq. 3.147). For the SDO pyramid
    g = [1/2, cos30 cos phi, cos30 sin phi], phi = 0, 90, 180, 270 deg:
    sum g g^T = diag(4/4, 2*3/4, 2*3/4) = diag(1, 1.5, 1.5), off-diagonals cancel.
    J' = diag(2211 - 0.1114, 3963 - 0.1671, 3268 - 0.1671)."""
    p = sdo_params()
    want = np.diag([2210.8886, 3962.8329, 3267.8329])
    np.testing.assert_allclose(p.inertia_prime_B, want, rtol=0, atol=1e-11)   # kg m^2
    np.testing.assert_allclose(p.inertia_prime_inv_B, np.diag(1.0 / np.diag(want)), rtol=1e-14, atol=1e-19)
    np.testing.assert_array_equal(p.axes_B, SDO_AXES)
    assert p.axes_B.flags.c_contiguous
    assert (p.spin_inertia, p.torque_max, p.h_max) == (0.1114, 0.25, 70.0)
    assert (p.viscous, p.coulomb, p.coulomb_speed) == (0.0, 0.0, COULOMB_SPEED)


def test_make_body_params_full_inertia_with_products():
    """Non-diagonal J and a skewed wheel: J' = J - J_s g g^T computed by hand for
    g = [0, 0.6, 0.8]: g g^T = [[0,0,0],[0,.36,.48],[0,.48,.64]], J_s = 0.5."""
    J = np.array([[100.0, 2.0, -3.0], [2.0, 150.0, 4.0], [-3.0, 4.0, 120.0]])
    p = make_body_params(J, [[0.0, 0.6, 0.8]], 0.5, 0.1, 10.0, 0.0, 0.0, 0.1)
    want = np.array([[100.0, 2.0, -3.0], [2.0, 149.82, 3.76], [-3.0, 3.76, 119.68]])
    np.testing.assert_allclose(p.inertia_prime_B, want, rtol=0, atol=1e-12)
    np.testing.assert_allclose(p.inertia_prime_inv_B @ want, np.eye(3), rtol=0, atol=1e-14)


# --- angular_momentum_B / kinetic_energy -------------------------------------

def test_angular_momentum_and_energy_textbook_forms():
    """In terms of the full inertia J and relative wheel speeds Omega:
    H_B = J omega + J_s sum Omega_i g_i,
    T = 1/2 omega^T J omega + J_s sum Omega_i (g_i . omega) + 1/2 J_s sum Omega_i^2
    (body incl. rotors' transverse inertia plus each rotor's spin energy
    1/2 J_s (Omega_i + g_i . omega)^2, expanded)."""
    p = sdo_params()
    omega = np.array([0.012, -0.034, 0.021])          # rad/s
    speeds = np.array([300.0, -150.0, 45.0, -600.0])  # rad/s
    x = make_state([1.0, 0, 0, 0], omega, h_from_speeds(speeds, omega, SDO_AXES, SDO_JS))
    H_want = SDO_INERTIA @ omega + SDO_JS * SDO_AXES.T @ speeds
    np.testing.assert_allclose(angular_momentum_B(x, p), H_want, rtol=0, atol=1e-12)   # N m s
    g_dot_w = SDO_AXES @ omega
    T_want = 0.5 * omega @ SDO_INERTIA @ omega + SDO_JS * np.sum(speeds * g_dot_w) + 0.5 * SDO_JS * np.sum(speeds ** 2)
    assert kinetic_energy(x, p) == pytest.approx(T_want, rel=1e-13, abs=0)               # J
    # hand number, body only: omega = [0.1, 0, 0], h = 0: H = J'_xx * 0.1, T = J'_xx * 0.01 / 2
    x0 = make_state([1.0, 0, 0, 0], [0.1, 0.0, 0.0], np.zeros(4))
    np.testing.assert_allclose(angular_momentum_B(x0, p), [221.08886, 0.0, 0.0], rtol=0, atol=1e-12)
    assert kinetic_energy(x0, p) == pytest.approx(11.054443, rel=1e-14)


# --- derivatives --------------------------------------------------------------

def test_derivatives_hand_values_at_rest():
    """Body at rest, wheels at rest, wheel 1 commanded 0.1 N m, no drag:
    dh = [0.1, 0, 0, 0] N m; the body takes -0.1 g_1 = [-0.05, +0.0866025, 0] N m,
    so domega = that / diag(J') = [-0.05/2210.8886, 0.08660254/3962.8329, 0] rad/s^2;
    dq = 0, dtheta_int = omega = 0."""
    p = sdo_params()
    q = np.array([0.5, 0.5, -0.5, 0.5])
    x = make_state(q, np.zeros(3), np.zeros(4))
    dx = np.full(len(x), np.nan)
    derivatives(x, p, np.array([0.1, 0.0, 0.0, 0.0]), np.zeros(3), dx)
    np.testing.assert_allclose(dx[IH:IH + 4], [0.1, 0, 0, 0], rtol=0, atol=1e-17)
    np.testing.assert_allclose(dx[IW:IW + 3], [-0.05 / 2210.8886, 0.08660254037844386 / 3962.8329, 0.0],
                               rtol=1e-13, atol=1e-20)
    np.testing.assert_array_equal(dx[IQ:IQ + 4], 0.0)
    np.testing.assert_array_equal(dx[IH + 4:], 0.0)


def test_derivatives_external_torque_and_gyroscopic_hand_values():
    """Spin about z at 0.1 rad/s with wheel momentum h = 5 N m s in a single
    wheel along x (no wheel torque, no drag) and tau_ext = [0, 0, 0.3] N m:
    three wheels along the body axes, J_s = 0.2, so J' = diag(2210.8, 3962.8, 3267.8);
    H_B = J' omega + G h = [5, 0, 326.78], omega x H = [0, 0.1 * 5, 0] = [0, 0.5, 0],
    J' domega = tau - omega x H = [0, -0.5, 0.3]."""
    J = np.diag([2211.0, 3963.0, 3268.0])
    p = make_body_params(J, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], 0.2, 0.25, 70.0, 0.0, 0.0, 0.1)
    x = make_state([1.0, 0, 0, 0], [0.0, 0.0, 0.1], [5.0, 0.0, 0.0])
    dx = np.empty(len(x))
    derivatives(x, p, np.zeros(3), np.array([0.0, 0.0, 0.3]), dx)
    np.testing.assert_allclose(dx[IW:IW + 3], [0.0, -0.5 / 3962.8, 0.3 / 3267.8], rtol=1e-13, atol=1e-20)
    np.testing.assert_array_equal(dx[IH:IH + 3], 0.0)
    # dq = 0.5 [1,0,0,0] (x) [0, 0, 0, 0.1] = [0, 0, 0, 0.05]; dtheta_int = omega
    np.testing.assert_allclose(dx[IQ:IQ + 4], [0, 0, 0, 0.05], rtol=0, atol=1e-17)
    np.testing.assert_allclose(dx[IH + 3:], [0, 0, 0.1], rtol=0, atol=1e-17)


def test_derivatives_drag_uses_speed_relative_to_body():
    """dh_i = -viscous * Omega_i with Omega_i = h_i / J_s - g_i . omega
    (sim/truth/wheels.py): the rotor speed relative to the body, not inertial."""
    p = sdo_params(viscous=1e-3)
    omega = np.array([0.01, 0.02, -0.03])
    speeds = np.array([100.0, -50.0, 0.0, 20.0])
    x = make_state([1.0, 0, 0, 0], omega, h_from_speeds(speeds, omega, SDO_AXES, SDO_JS))
    dx = np.empty(len(x))
    derivatives(x, p, np.zeros(4), np.zeros(3), dx)
    np.testing.assert_allclose(dx[IH:IH + 4], -1e-3 * speeds, rtol=0, atol=1e-15)   # N m


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
    p = sdo_params()
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
    p = sdo_params(viscous=SDO_VISC, coulomb=SDO_COUL)
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
    p = sdo_params()
    x = make_state(random_unit_quat(rng), [0.02, -0.015, 0.03], [10.0, -20.0, 5.0, 15.0])
    H0 = H_inertial(x, p)
    h0 = x[IH:IH + 4].copy()
    work = np.empty((5, len(x)))
    tau = np.zeros(3)
    amp = 0.2                                           # N m, below torque_max 0.25
    # periods 300..1000 s: each wheel's momentum swings by up to 2 * amp * T / (2 pi) = 19..64 N m s
    freq = 2 * np.pi / np.array([300.0, 450.0, 650.0, 1000.0])   # rad/s
    phase = np.array([0.0, 1.0, 2.0, 3.0])
    u = np.empty(4)
    worst = 0.0
    h_swing = h_peak = 0.0
    for k in range(72000):
        u[:] = amp * np.sin(freq * (k * DT) + phase)
        rk4_step(x, p, u, tau, DT, work)
        h_peak = max(h_peak, np.max(np.abs(x[IH:IH + 4])))
        if k % 50 == 0:
            worst = max(worst, np.linalg.norm(H_inertial(x, p) - H0))
            h_swing = max(h_swing, np.max(np.abs(x[IH:IH + 4] - h0)))
    worst = max(worst, np.linalg.norm(H_inertial(x, p) - H0))
    assert h_swing > 10.0                               # N m s: the wheels did exchange momentum
    assert h_peak < 0.95 * SDO_HMAX                     # and never neared the 70 N m s cut-off
    assert worst / np.linalg.norm(H0) < 1e-9, worst / np.linalg.norm(H0)


def test_inertial_momentum_conserved_with_wheel_drag():
    """Wheel drag is internal (rotor on body): H_N stays constant with the SDO
    viscous and Coulomb drag on, wheels spinning down over 10 min (1e-9 relative)."""
    rng = np.random.default_rng(8)
    p = sdo_params(viscous=SDO_VISC, coulomb=SDO_COUL)
    x = make_state(random_unit_quat(rng), [0.01, 0.02, -0.01], [40.0, -30.0, 25.0, -35.0])
    H0 = H_inertial(x, p)
    h0 = x[IH:IH + 4].copy()
    work = np.empty((5, len(x)))
    u, tau = np.zeros(4), np.zeros(3)
    worst = 0.0
    for k in range(12000):
        rk4_step(x, p, u, tau, DT, work)
        if k % 50 == 0:
            worst = max(worst, np.linalg.norm(H_inertial(x, p) - H0))
    assert np.max(np.abs(x[IH:IH + 4] - h0)) > 1.0     # N m s of drag actually acted
    assert worst / np.linalg.norm(H0) < 1e-9


def test_kinetic_energy_conserved_torque_free():
    """No motor torque, no drag, no external torque: h constant, and
    dT/dt = omega . (-omega x H) = 0. Tumbling SDO with non-zero wheel momenta,
    1 h at dt 0.05 s; relative drift below 1e-9. Also |H_B| is constant.
    The rotors' spin energy sum h^2 / (2 J_s) (~1.5e4 J) dwarfs the body's
    (~8 J) and is constant by itself here, so the body part 1/2 omega^T J' omega
    (J' by hand, see test_make_body_params_inertia_prime_by_hand) is held to
    1e-9 relative on its own: otherwise the test could not see a drift."""
    rng = np.random.default_rng(9)
    p = sdo_params()
    x = make_state(random_unit_quat(rng), [0.03, -0.04, 0.05], [30.0, -12.0, 18.0, 45.0])
    T0 = kinetic_energy(x, p)
    Hn0 = np.linalg.norm(angular_momentum_B(x, p))
    h0 = x[IH:IH + 4].copy()
    w0 = x[IW:IW + 3].copy()
    work = np.empty((5, len(x)))
    u, tau = np.zeros(4), np.zeros(3)
    J_prime = np.diag([2210.8886, 3962.8329, 3267.8329])   # kg m^2, by hand
    Tb0 = 0.5 * w0 @ J_prime @ w0
    worst_T = worst_H = worst_Tb = 0.0
    w_change = 0.0
    for k in range(72000):
        rk4_step(x, p, u, tau, DT, work)
        if k % 50 == 0:
            w = x[IW:IW + 3]
            worst_Tb = max(worst_Tb, abs(0.5 * w @ J_prime @ w - Tb0))
            worst_T = max(worst_T, abs(kinetic_energy(x, p) - T0))
            worst_H = max(worst_H, abs(np.linalg.norm(angular_momentum_B(x, p)) - Hn0))
            w_change = max(w_change, np.linalg.norm(x[IW:IW + 3] - w0))
    np.testing.assert_array_equal(x[IH:IH + 4], h0)      # dh/dt = 0 exactly
    assert w_change > 1e-2                                # rad/s: the body really tumbles
    assert worst_T / T0 < 1e-9, worst_T / T0
    assert worst_Tb / Tb0 < 1e-9, worst_Tb / Tb0
    assert worst_H / Hn0 < 1e-9, worst_H / Hn0


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
    p = make_body_params(np.diag([It, It, I3]) + js * np.eye(3), np.eye(3), js, 0.25, 70.0, 0.0, 0.0, 0.1)
    w0 = np.array([0.02, -0.01, 0.2])
    lam = ((I3 - It) * w0[2] + h3) / It          # 0.1 rad/s (h3 = 0) or 0.10267 rad/s
    x = make_state([1.0, 0, 0, 0], w0, [0.0, 0.0, h3])
    work = np.empty((5, len(x)))
    u, tau = np.zeros(3), np.zeros(3)
    n_steps = int(round(5 * 2 * np.pi / lam / DT))
    worst = 0.0
    c0 = w0[0] + 1j * w0[1]
    for k in range(1, n_steps + 1):
        rk4_step(x, p, u, tau, DT, work)
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
    global error orders of magnitude smaller, and the reference is ~1e-12 relative."""
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

    p = sdo_params()
    x = make_state(q0, w0, h0)
    work = np.empty((5, len(x)))
    steps_per_out = int(round(T_END / N_OUT / DT))
    err_att = err_w = err_h = err_th = 0.0
    for j in range(1, N_OUT + 1):
        for _ in range(steps_per_out):
            rk4_step(x, p, u, tau_ext, DT, work)
        ref = sol.y[:, j]
        q_ref = ref[0:4] / np.linalg.norm(ref[0:4])
        err_att = max(err_att, (Rotation.from_quat(q_ref, scalar_first=True).inv()
                                * Rotation.from_quat(x[IQ:IQ + 4], scalar_first=True)).magnitude() / ARCSEC)
        err_w = max(err_w, np.max(np.abs(x[IW:IW + 3] - ref[4:7])))
        err_h = max(err_h, np.max(np.abs(x[IH:IH + 4] - ref[7:11])))
        err_th = max(err_th, np.max(np.abs(x[IH + 4:] - ref[11:14])) / ARCSEC)
    # the reference really went somewhere: wheels moved 18-30 N m s, body turned > 30 deg
    assert np.max(np.abs(sol.y[7:11, -1] - h0)) > 10.0
    assert (Rotation.from_quat(q0, scalar_first=True).inv()
            * Rotation.from_quat(sol.y[0:4, -1], scalar_first=True)).magnitude() > np.radians(30)
    assert np.max(np.abs(x[IH:IH + 4])) < SDO_HMAX
    assert err_att < 1e-4, err_att        # arcsec
    assert err_w < 1e-12, err_w           # rad/s
    assert err_h < 1e-10, err_h           # N m s
    assert err_th < 1e-4, err_th          # arcsec
