"""Rigid body with N reaction wheels: equations of motion and the RK4 step.

State x = [q_BN (4), omega_BN_B (3), h_wheels (N), theta_int_B (3)]:
attitude, body rate, each rotor's axial momentum, and the integral of the body
rate (what a rate-integrating gyro senses).

    H_B        = J' omega + G h                    (total angular momentum, B axes)
    J' domega  = tau_ext - G dh/dt - omega x H_B   (Euler's equation, wheels inside)
    dh/dt      = motor + drag                      (sim/truth/wheels.py)
    dq/dt      = 0.5 q (x) [0, omega]

with J' the inertia less each rotor's spin-axis inertia, J' = J - sum J_s g g^T,
and G the 3 x N matrix of spin axes (Markley & Crassidis 2014, eq. 3.147-3.150).
Fixed-step RK4, quaternion renormalised after each step.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.attitude import quat_derivative
from sim.linalg import matvec, matvec_t
from sim.truth.wheels import rotor_torque_Nm

IQ, IW, IH = 0, 4, 7  # offsets of q, omega and h in the state vector


class BodyParams(NamedTuple):
    inertia_prime_B: np.ndarray      # J' (3, 3), kg m^2
    inertia_prime_inv_B: np.ndarray  # J'^-1
    axes_B: np.ndarray               # G^T, (N, 3): row i is wheel i's spin axis
    spin_inertia: float
    torque_max: float
    h_max: float
    viscous: float
    coulomb: float
    coulomb_speed: float


def make_body_params(inertia_B, axes_B, spin_inertia, torque_max, h_max, viscous, coulomb, coulomb_speed):
    axes = np.ascontiguousarray(axes_B, dtype=float)
    j_prime = np.asarray(inertia_B, float) - spin_inertia * axes.T @ axes
    return BodyParams(j_prime, np.linalg.inv(j_prime), axes, float(spin_inertia), float(torque_max),
                      float(h_max), float(viscous), float(coulomb), float(coulomb_speed))


def state_size(n_wheels: int) -> int:
    return IH + n_wheels + 3


def initial_state(q_BN, omega_BN_B_rad_s, h_wheels_Nms) -> np.ndarray:
    """A state vector (theta_int starts at zero)."""
    n = len(h_wheels_Nms)
    x = np.zeros(state_size(n))
    x[IQ:IQ + 4] = q_BN
    x[IW:IW + 3] = omega_BN_B_rad_s
    x[IH:IH + n] = h_wheels_Nms
    return x


@njit(cache=True)
def derivatives(x, p, u_cmd_Nm, torque_ext_B, dx):
    """dx/dt written into dx. Scalar code: it runs 4 times per RK4 step."""
    n = p.axes_B.shape[0]
    w0, w1, w2 = x[IW], x[IW + 1], x[IW + 2]
    gh0 = gh1 = gh2 = 0.0      # G h: rotor momentum in B
    ghd0 = ghd1 = ghd2 = 0.0   # G dh/dt: torque the rotors take from the body
    for i in range(n):
        a0, a1, a2 = p.axes_B[i, 0], p.axes_B[i, 1], p.axes_B[i, 2]
        h = x[IH + i]
        hd = rotor_torque_Nm(h / p.spin_inertia - (a0 * w0 + a1 * w1 + a2 * w2), u_cmd_Nm[i], p)
        dx[IH + i] = hd
        gh0 += a0 * h
        gh1 += a1 * h
        gh2 += a2 * h
        ghd0 += a0 * hd
        ghd1 += a1 * hd
        ghd2 += a2 * hd
    J = p.inertia_prime_B
    H0 = J[0, 0] * w0 + J[0, 1] * w1 + J[0, 2] * w2 + gh0
    H1 = J[1, 0] * w0 + J[1, 1] * w1 + J[1, 2] * w2 + gh1
    H2 = J[2, 0] * w0 + J[2, 1] * w1 + J[2, 2] * w2 + gh2
    r0 = torque_ext_B[0] - ghd0 - (w1 * H2 - w2 * H1)
    r1 = torque_ext_B[1] - ghd1 - (w2 * H0 - w0 * H2)
    r2 = torque_ext_B[2] - ghd2 - (w0 * H1 - w1 * H0)
    Ji = p.inertia_prime_inv_B
    dx[IW] = Ji[0, 0] * r0 + Ji[0, 1] * r1 + Ji[0, 2] * r2
    dx[IW + 1] = Ji[1, 0] * r0 + Ji[1, 1] * r1 + Ji[1, 2] * r2
    dx[IW + 2] = Ji[2, 0] * r0 + Ji[2, 1] * r1 + Ji[2, 2] * r2
    quat_derivative(x[IQ:IQ + 4], x[IW:IW + 3], dx[IQ:IQ + 4])
    dx[IH + n] = w0
    dx[IH + n + 1] = w1
    dx[IH + n + 2] = w2


@njit(cache=True)
def rk4_step(x, p, u_cmd_Nm, torque_ext_B, dt, work):
    """One fixed RK4 step in place; inputs held over the step (zero-order hold).
    work: (5, len(x)) scratch, so that the step allocates nothing."""
    k1, k2, k3, k4, xt = work[0], work[1], work[2], work[3], work[4]
    m = x.shape[0]
    derivatives(x, p, u_cmd_Nm, torque_ext_B, k1)
    for i in range(m):
        xt[i] = x[i] + 0.5 * dt * k1[i]
    derivatives(xt, p, u_cmd_Nm, torque_ext_B, k2)
    for i in range(m):
        xt[i] = x[i] + 0.5 * dt * k2[i]
    derivatives(xt, p, u_cmd_Nm, torque_ext_B, k3)
    for i in range(m):
        xt[i] = x[i] + dt * k3[i]
    derivatives(xt, p, u_cmd_Nm, torque_ext_B, k4)
    for i in range(m):
        x[i] += (dt / 6.0) * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
    norm = np.sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + x[3] * x[3])
    for i in range(4):
        x[IQ + i] /= norm


@njit(cache=True)
def angular_momentum_B(x, p):
    n = p.axes_B.shape[0]
    return matvec(p.inertia_prime_B, x[IW:IW + 3]) + matvec_t(p.axes_B, x[IH:IH + n])


@njit(cache=True)
def kinetic_energy(x, p):
    """Rotational kinetic energy of body and rotors, J."""
    n = p.axes_B.shape[0]
    omega = x[IW:IW + 3]
    h = x[IH:IH + n]
    return 0.5 * np.sum(omega * matvec(p.inertia_prime_B, omega)) + 0.5 * np.sum(h * h) / p.spin_inertia
