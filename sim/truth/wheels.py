"""Reaction wheel model: motor torque limits, momentum (speed) limit, drag.

Each wheel's state is its axial angular momentum h_i = J_s,i (Omega_i + g_i . omega_BN_B),
with Omega_i the speed relative to the body; dh_i/dt is then exactly the torque
acting on the rotor (motor plus drag), which keeps the rigid-body equations
decoupled (Markley & Crassidis, "Fundamentals of Spacecraft Attitude
Determination and Control", 2014, sec. 3.3.5.3).
"""
import numpy as np
from numba import njit

from sim.linalg import matvec


@njit(cache=True)
def wheel_speeds_rad_s(h_wheels, omega_BN_B, axes_B, spin_inertia):
    """Speed of each rotor relative to the body, rad/s."""
    return h_wheels / spin_inertia - matvec(axes_B, omega_BN_B)


@njit(cache=True)
def rotor_torque_Nm(speed_rad_s, u_cmd_Nm, p):
    """dh/dt of one rotor spinning at speed_rad_s relative to the body: the
    commanded motor torque clipped to the hardware limit and cut where it would
    drive the rotor past its momentum capacity, plus viscous and Coulomb drag
    (tanh keeps the Coulomb force smooth for RK4). p: WheelParams."""
    motor = min(max(u_cmd_Nm, -p.torque_max), p.torque_max)
    h_rel = speed_rad_s * p.spin_inertia
    if (h_rel >= p.h_max and motor > 0.0) or (h_rel <= -p.h_max and motor < 0.0):
        motor = 0.0
    return motor - p.viscous * speed_rad_s - p.coulomb * np.tanh(speed_rad_s / p.coulomb_speed)
