"""Propagation of the six-state attitude EKF over one control cycle: the state
transition matrix and the process-noise covariance of the error state, in
closed form for a body rate held constant over the cycle.

Error state (Lefferts, Markley & Shuster 1982; Markley & Crassidis 2014,
sec. 6.2): x = [dtheta (3), dbias (3)], with the true attitude
q_BN = q_est_BN (x) exp(dtheta / 2) (dtheta a small rotation in body axes,
sim/attitude.py's convention) and dbias = bias_true - bias_est. The gyro model
is omega_meas = omega + bias + eta_v, d(bias)/dt = eta_u, white eta_v, eta_u
with spectral densities sigma_v^2 (rad^2/s) and sigma_u^2 (rad^2/s^3). With
omega_est = omega_meas - bias_est the linearised error dynamics are

    d(dtheta)/dt = -[omega_est x] dtheta - dbias - eta_v
    d(dbias)/dt  = eta_u

i.e. F = [[-[w x], -I], [0, 0]], G = [[-I, 0], [0, I]], Q = diag(sigma_v^2 I,
sigma_u^2 I). For constant omega_est, Phi = exp(F dt) and
Qd = int_0^dt Phi(t) G Q G^T Phi(t)^T dt have the closed forms below (the
discrete model of Markley & Crassidis sec. 6.2; Farrenkopf's gyro model).
tests/test_ekf_propagation.py checks both against scipy's matrix exponential
of the continuous system (Van Loan's method), so the formulas here are not
taken on trust.

Written with W = [omega x] dt (dimensionless) and x = |omega| dt:

    Phi11 = I - a W + b W^2
    Phi12 = -dt (I - b W + c W^2)
    Qd11  = sigma_v^2 dt I + sigma_u^2 dt^3 (I / 3 + d W^2)
    Qd12  = -sigma_u^2 dt^2 (I / 2 - c W + e W^2)
    Qd22  = sigma_u^2 dt I

    a = sin x / x, b = (1 - cos x) / x^2, c = (x - sin x) / x^3,
    d = (x^3 / 3 + 2 sin x - 2 x) / x^5, e = (x^2 / 2 + cos x - 1) / x^4.
"""
import numpy as np
from numba import njit

# Below this x the coefficients come from their Taylor series: the closed
# forms cancel catastrophically (d loses ~x^-5 of its digits), and SDO's rates
# (<= 10 deg/s, x <= 0.035) are always here. At 0.2 the first dropped series
# term is < 1e-12 relative, and the closed forms above it keep ~1e-11.
SERIES_X_MAX = 0.2


@njit(cache=True)
def transition_coefficients(x):
    """(a, b, c, d, e) of the module docstring at x = |omega| dt."""
    if x < SERIES_X_MAX:
        x2 = x * x
        x4 = x2 * x2
        x6 = x4 * x2
        a = 1.0 - x2 / 6.0 + x4 / 120.0 - x6 / 5040.0
        b = 0.5 - x2 / 24.0 + x4 / 720.0 - x6 / 40320.0
        c = 1.0 / 6.0 - x2 / 120.0 + x4 / 5040.0 - x6 / 362880.0
        d = 1.0 / 60.0 - x2 / 2520.0 + x4 / 181440.0 - x6 / 19958400.0
        e = 1.0 / 24.0 - x2 / 720.0 + x4 / 40320.0 - x6 / 3628800.0
        return a, b, c, d, e
    s, co = np.sin(x), np.cos(x)
    return (s / x, (1.0 - co) / x ** 2, (x - s) / x ** 3, (x ** 3 / 3.0 + 2.0 * s - 2.0 * x) / x ** 5,
            (x * x / 2.0 + co - 1.0) / x ** 4)


@njit(cache=True)
def transition_and_noise(omega_est_B, dt, sigma_v, sigma_u, Phi, Qd):
    """Write Phi (6, 6) and Qd (6, 6) of one step of length dt (s) at the
    bias-corrected body rate omega_est_B (rad/s), held constant over it."""
    wx, wy, wz = omega_est_B[0] * dt, omega_est_B[1] * dt, omega_est_B[2] * dt
    x = np.sqrt(wx * wx + wy * wy + wz * wz)
    a, b, c, d, e = transition_coefficients(x)
    # W = [omega x] dt and W^2 = w w^T - |w|^2 I, element by element.
    W = np.empty((3, 3))
    W[0, 0], W[0, 1], W[0, 2] = 0.0, -wz, wy
    W[1, 0], W[1, 1], W[1, 2] = wz, 0.0, -wx
    W[2, 0], W[2, 1], W[2, 2] = -wy, wx, 0.0
    w = (wx, wy, wz)
    qv = sigma_v * sigma_v * dt
    qu = sigma_u * sigma_u
    Phi[:, :] = 0.0
    Qd[:, :] = 0.0
    for i in range(3):
        for j in range(3):
            eye = 1.0 if i == j else 0.0
            W2 = w[i] * w[j] - x * x * eye
            Phi[i, j] = eye - a * W[i, j] + b * W2
            Phi[i, 3 + j] = -dt * (eye - b * W[i, j] + c * W2)
            Qd[i, j] = qv * eye + qu * dt ** 3 * (eye / 3.0 + d * W2)
            Qd[i, 3 + j] = -qu * dt * dt * (0.5 * eye - c * W[i, j] + e * W2)
            Qd[3 + j, i] = Qd[i, 3 + j]   # Qd is symmetric: Qd21 = Qd12^T
        Phi[3 + i, 3 + i] = 1.0
        Qd[3 + i, 3 + i] = qu * dt


@njit(cache=True)
def propagate_covariance(P, Phi, Qd, work):
    """P <- Phi P Phi^T + Qd in place, with a (6, 6) work array (no
    allocation: this runs every cycle). The result is made exactly symmetric,
    so rounding cannot grow an antisymmetric part over millions of cycles."""
    n = P.shape[0]
    for i in range(n):            # work = Phi P
        for j in range(n):
            acc = 0.0
            for k in range(n):
                acc += Phi[i, k] * P[k, j]
            work[i, j] = acc
    for i in range(n):            # P = work Phi^T + Qd, upper triangle mirrored
        for j in range(i, n):
            acc = Qd[i, j]
            for k in range(n):
                acc += work[i, k] * Phi[j, k]
            P[i, j] = acc
            P[j, i] = acc
