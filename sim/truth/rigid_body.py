"""Rigid body with N reaction wheels: the rotational equations of motion.

On the attitude part of the truth state, [q_BN (4), omega_BN_B (3),
h_wheels (N), theta_int_B (3)]: attitude, body rate, each rotor's axial
momentum, and the integral of the body rate (what a rate-integrating gyro
senses). The rest of the state (orbit, propellant) is sim/truth/dynamics.py's.

    H_B        = J' omega + G h                              (total angular momentum, B axes)
    J' domega  = tau_ext - G dh/dt - omega x H_B - J'dot omega
    dh/dt      = motor + drag                                (sim/truth/wheels.py)
    dq/dt      = 0.5 q (x) [0, omega]

with J' the inertia less each rotor's spin-axis inertia, J' = J - sum J_s g g^T,
and G the 3 x N matrix of spin axes (Markley & Crassidis 2014, eq. 3.147-3.150).
The J'dot term makes dH/dt = tau_ext - omega x H hold while propellant leaves
(sim/truth/mass.py).
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.attitude import quat_derivative
from sim.linalg import matvec, matvec_t
from sim.truth.wheels import rotor_torque_Nm

IQ, IW, IH = 0, 4, 7  # offsets of q, omega and h in the state vector

# wheel fault slots: motor disabled (0/1), extra viscous drag N m/(rad/s)
W_MOTOR_OFF, W_EXTRA_VISCOUS = 0, 1
N_WHEEL_FAULT_SLOTS = 2


class WheelParams(NamedTuple):
    axes_B: np.ndarray        # G^T, (N, 3): row i is wheel i's spin axis
    spin_inertia: float
    torque_max: float
    h_max: float
    viscous: float
    coulomb: float
    coulomb_speed: float
    spin_inertia_B: np.ndarray  # sum J_s g g^T, (3, 3): what J' leaves out of J


def make_wheel_params(axes_B, spin_inertia, torque_max, h_max, viscous, coulomb, coulomb_speed) -> WheelParams:
    axes = np.ascontiguousarray(axes_B, dtype=float)
    return WheelParams(axes, float(spin_inertia), float(torque_max), float(h_max), float(viscous), float(coulomb),
                       float(coulomb_speed), spin_inertia * axes.T @ axes)


def attitude_state_size(n_wheels: int) -> int:
    return IH + n_wheels + 3


@njit(cache=True, inline="always")
def body_derivatives(x, j_prime, j_prime_inv, j_prime_dot, w, wheel_faults, u_cmd_Nm, torque_ext_B, dx):
    """d/dt of the attitude part of x, written into dx. Scalar code: it runs
    four times per RK4 step."""
    n = w.axes_B.shape[0]
    w0, w1, w2 = x[IW], x[IW + 1], x[IW + 2]
    gh0 = gh1 = gh2 = 0.0      # G h: rotor momentum in B
    ghd0 = ghd1 = ghd2 = 0.0   # G dh/dt: torque the rotors take from the body
    for i in range(n):
        a0, a1, a2 = w.axes_B[i, 0], w.axes_B[i, 1], w.axes_B[i, 2]
        h = x[IH + i]
        speed = h / w.spin_inertia - (a0 * w0 + a1 * w1 + a2 * w2)
        u = 0.0 if wheel_faults[i, W_MOTOR_OFF] > 0.0 else u_cmd_Nm[i]
        hd = rotor_torque_Nm(speed, u, w) - wheel_faults[i, W_EXTRA_VISCOUS] * speed
        dx[IH + i] = hd
        gh0 += a0 * h
        gh1 += a1 * h
        gh2 += a2 * h
        ghd0 += a0 * hd
        ghd1 += a1 * hd
        ghd2 += a2 * hd
    J, Jd = j_prime, j_prime_dot
    H0 = J[0, 0] * w0 + J[0, 1] * w1 + J[0, 2] * w2 + gh0
    H1 = J[1, 0] * w0 + J[1, 1] * w1 + J[1, 2] * w2 + gh1
    H2 = J[2, 0] * w0 + J[2, 1] * w1 + J[2, 2] * w2 + gh2
    r0 = torque_ext_B[0] - ghd0 - (w1 * H2 - w2 * H1) - (Jd[0, 0] * w0 + Jd[0, 1] * w1 + Jd[0, 2] * w2)
    r1 = torque_ext_B[1] - ghd1 - (w2 * H0 - w0 * H2) - (Jd[1, 0] * w0 + Jd[1, 1] * w1 + Jd[1, 2] * w2)
    r2 = torque_ext_B[2] - ghd2 - (w0 * H1 - w1 * H0) - (Jd[2, 0] * w0 + Jd[2, 1] * w1 + Jd[2, 2] * w2)
    Ji = j_prime_inv
    dx[IW] = Ji[0, 0] * r0 + Ji[0, 1] * r1 + Ji[0, 2] * r2
    dx[IW + 1] = Ji[1, 0] * r0 + Ji[1, 1] * r1 + Ji[1, 2] * r2
    dx[IW + 2] = Ji[2, 0] * r0 + Ji[2, 1] * r1 + Ji[2, 2] * r2
    quat_derivative(x[IQ:IQ + 4], x[IW:IW + 3], dx[IQ:IQ + 4])
    dx[IH + n] = w0
    dx[IH + n + 1] = w1
    dx[IH + n + 2] = w2


@njit(cache=True)
def angular_momentum_B(x, j_prime, w):
    """Total angular momentum of body and rotors about the centre of mass, B axes."""
    n = w.axes_B.shape[0]
    return matvec(j_prime, x[IW:IW + 3]) + matvec_t(w.axes_B, x[IH:IH + n])


@njit(cache=True)
def kinetic_energy(x, j_prime, w):
    """Rotational kinetic energy of body and rotors, J."""
    n = w.axes_B.shape[0]
    omega = x[IW:IW + 3]
    h = x[IH:IH + n]
    return 0.5 * np.sum(omega * matvec(j_prime, omega)) + 0.5 * np.sum(h * h) / w.spin_inertia
