"""DeltaH, seed 001 "DeltaH": momentum unloading with thrusters and wheels at once.

* Wheels: "a command torque to drive the reaction wheels to a desired wheel
  speed", here u_i = g (h_target,i - h_i) per wheel (h_i from the
  tachometers), scaled as a vector so the largest stays within the software
  limit (the wheel modes' direction-keeping rule).
* Thrusters: the PD of thruster_modes.py on the IRU-propagated attitude
  against the attitude at entry, on-pulsing; for the tip-off contingency
  K_p / 10 ("so that rapid rate damping is the only effect").
* Exit: "when the wheel momentum plus the body momentum is within 3 Nms of
  the target momentum, the mode exits to the mode from which it was entered".
"""
import numpy as np
from numba import njit


@njit(cache=True)
def deltah_wheel_torque(tach_speed_rad_s, h_target_Nms, spin_inertia, gain_per_s, limit_Nm, u_out):
    n = tach_speed_rad_s.shape[0]
    peak = 0.0
    for i in range(n):
        u_out[i] = gain_per_s * (h_target_Nms[i] - spin_inertia * tach_speed_rad_s[i])
        peak = max(peak, abs(u_out[i]))
    if peak > limit_Nm:
        u_out[:] *= limit_Nm / peak


@njit(cache=True)
def system_momentum_error_Nms(tach_speed_rad_s, h_target_Nms, rate_B, inertia_diag, wheel_axes_B, spin_inertia):
    """|H_wheels + H_body - H_target|, body frame, N m s."""
    e = inertia_diag * rate_B
    for i in range(tach_speed_rad_s.shape[0]):
        e += wheel_axes_B[i] * (spin_inertia * tach_speed_rad_s[i] - h_target_Nms[i])
    return np.sqrt(np.sum(e * e))
