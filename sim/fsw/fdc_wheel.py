"""Reaction wheel failure detection (seed 001: four wheels in a pyramid; after
a wheel failure the software continues on three, the distribution recomputed
by the caller). This module only detects.

Physics. A wheel's tachometer speed changes by the motor torque over the spin
inertia: J_s dOmega/dt = u - drag (the body's angular acceleration adds
J_s g . domega_BN_B/dt, below 1e-5 N m for SDO's body inertia). So the torque
residual

    r = J_s (Omega_k - Omega_k-1) / dt - u                         [N m]

is minus the drag: 0.002 + 1.67e-4 |Omega| N m nominally (sdo.yaml; unknown
to the flight software), 0.12 N m at the 700 rad/s of seed 000's worst case.
A seized rotor locks to the body within ~0.1 s (an impulse of J_s Omega,
33 N m s from 300 rad/s) and then answers no command (r = -u); an extra viscous
drag c adds c |Omega| (0.3 N m for c = 1e-3 N m/(rad/s) at 300 rad/s).

Tachometer timing (sim/truth/sensors/tachometer.py). The tachometer at t_k
reads the *mean* speed over [t_k-1, t_k] (pulse count over the sample), so for
torques held over each cycle the difference of two readings is driven by the
mean of the torques over the last two intervals:
Omega_k - Omega_k-1 = (a[k-1, k] + a[k-2, k-1]) dt / 2. The caller passes the
command that acted over the last interval [t_k-1, t_k]; the state keeps the one
before it. With the one-cycle actuator delay (sim/loop.py) the command acting
over [t_k-1, t_k] is the one computed at cycle k-2; without delay, at k-1.

Quantisation. One pulse per sample is 2 pi / 64 / 0.2 s = 0.49 rad/s, so a
single-cycle residual carries up to 2 J_s 0.49 / 0.2 = 0.55 N m of counting
error: far above the threshold. But the count is of an accumulated angle, so
that error is a second difference of a bounded sequence, and a first-order
low-pass with gain alpha leaves about 2 alpha J_s pulse / dt^2 = 0.022 N m
with alpha = 1/25 (0.035 N m measured, a value frozen by the capacity hold
below included). The low-pass time constant is the persistence
time (alpha = 1 / persistence_cycles, tau = persistence_cycles dt = 5 s): the
filter averages over the same span the persistence then confirms.

Decision. A wheel is failed when |filtered r| > torque_threshold_Nm for
persistence_cycles consecutive cycles, or its tachometer is invalid for that
long (a cycle of either counts toward the same run). One new failure per call;
a failed wheel stays failed (its slots are no longer updated) until the
caller clears state.failed.

Momentum capacity. The truth motor cuts out where it would drive the rotor
past h_max (sim/truth/wheels.py), so a wheel at capacity commanded further out
shows r = -u (up to 0.2 N m, above the threshold) without being failed: while
|Omega| is within CAPACITY_MARGIN of speed_max_rad_s and the command pushes
outward, the wheel's filter and count are held.

What is detected with the defaults (sdo.yaml wheels, 0.2 s cycle), measured in
tests/test_fdc_detectors.py:
* a wheel seizing from |Omega| > 25 rad/s: the impulse alone lifts the
  filtered residual to J_s |Omega| / tau, still above the threshold a
  persistence later if J_s |Omega| e^-1 / tau > 0.2 N m; declared 5.0 s
  after the seizure from 50 and 300 rad/s (the wheel-bias floor is 45 rad/s).
* extra drag c |Omega| well over the threshold less the nominal drag:
  c = 1e-3 N m/(rad/s) from 400 rad/s in 7.0 s, from 300 in 8.4 s, from
  200 in 13 s (the wheel slows meanwhile).
* a dead tachometer: 5.0 s (exactly the persistence).
Not detected: a seizure below ~25 rad/s unless the loop goes on commanding
more than 0.2 N m to the dead wheel, or an extra drag under ~0.1 N m (below
the threshold; the attitude loop compensates it like nominal drag).
"""
from typing import NamedTuple

import numpy as np
from numba import njit

TORQUE_THRESHOLD_NM = 0.2
"""Residual torque threshold (assumption): above the worst nominal drag of
sdo.yaml, 0.002 + 1.67e-4 * 700 = 0.12 N m (seed 000's two wheels at ~700 rad/s),
plus the filtered quantisation, 0.035 N m, by 1.3x (0.139 N m is the worst
measured at 628 rad/s, the capacity); below a 1e-3 N m/(rad/s)
extra drag at 300 rad/s, 0.3 + 0.052 = 0.35 N m, by 1.75x. 0.2 N m is near the
geometric mean of 0.12 and 0.35, and equals the software torque limit: a wheel
that loses more than it can be commanded to make up is failed."""
PERSISTENCE_CYCLES = 25
"""Consecutive cycles over the threshold (assumption): 5 s at 0.2 s, long
against the attitude loop's torque transients but short against seed 001's
30-s slew-settling scales. Also sets the low-pass time constant (5 s)."""
CAPACITY_MARGIN = 0.01
"""Fraction of speed_max_rad_s (1 %, 6 rad/s at 628 rad/s, about 13 tachometer
pulses per sample) within which a wheel counts as at capacity."""


class WheelFdcParams(NamedTuple):
    spin_inertia_kgm2: float      # J_s of every wheel, kg m^2
    torque_threshold_Nm: float    # |filtered residual| above this counts toward a failure
    persistence_cycles: int       # consecutive cycles that declare a failure; filter tau = this x dt
    dt: float                     # control cycle, s
    speed_max_rad_s: float        # momentum capacity h_max / J_s (inf: no capacity hold)


class WheelFdcState(NamedTuple):
    speed_prev: np.ndarray    # (n,) rad/s, the last valid tachometer reading
    residual_Nm: np.ndarray   # (n,) low-pass filtered torque residual (minus the drag), N m
    count: np.ndarray         # (n,) int64, consecutive cycles over the threshold or invalid
    failed: np.ndarray        # (n,) bool, declared failed (stays so)
    u_before_Nm: np.ndarray   # (n,) the command that acted over the interval before the last
    prev_ok: np.ndarray       # (n,) bool: speed_prev is the reading of the previous cycle


def make_wheel_fdc_params(spin_inertia_kgm2, dt, h_max_Nms=np.inf, torque_threshold_Nm=TORQUE_THRESHOLD_NM,
                          persistence_cycles=PERSISTENCE_CYCLES) -> WheelFdcParams:
    """For SDO: make_wheel_fdc_params(sc.wheels.spin_inertia_kgm2,
    sc.timing.control_dt_s, sc.wheels.h_max_Nms)."""
    if spin_inertia_kgm2 <= 0.0 or dt <= 0.0 or torque_threshold_Nm <= 0.0 or h_max_Nms <= 0.0:
        raise ValueError("spin inertia, dt, threshold and h_max must be > 0")
    if int(persistence_cycles) < 1:
        raise ValueError("persistence_cycles must be >= 1")
    return WheelFdcParams(float(spin_inertia_kgm2), float(torque_threshold_Nm), int(persistence_cycles),
                          float(dt), float(h_max_Nms) / float(spin_inertia_kgm2))


def make_wheel_fdc_state(n_wheels: int) -> WheelFdcState:
    return WheelFdcState(np.zeros(n_wheels), np.zeros(n_wheels), np.zeros(n_wheels, np.int64),
                         np.zeros(n_wheels, np.bool_), np.zeros(n_wheels), np.zeros(n_wheels, np.bool_))


@njit(cache=True, inline="always")
def wheel_fdc_cycle(tach_speed_rad_s, tach_valid, cmd_torque_Nm_prev, p, s):
    """One control cycle at t_k. cmd_torque_Nm_prev: the motor torque commands
    (n,) N m that acted over the last interval [t_k-1, t_k] (module docstring:
    computed at cycle k-2 with the one-cycle actuator delay). Returns the index
    of a wheel newly declared failed this cycle, else -1 (one per call)."""
    alpha = 1.0 / p.persistence_cycles
    near_cap = (1.0 - CAPACITY_MARGIN) * p.speed_max_rad_s
    new = -1
    for j in range(tach_speed_rad_s.shape[0]):
        u = cmd_torque_Nm_prev[j]
        u_mean = 0.5 * (u + s.u_before_Nm[j])
        s.u_before_Nm[j] = u
        if s.failed[j]:
            continue
        w = tach_speed_rad_s[j]
        if not tach_valid[j]:
            s.prev_ok[j] = False
            s.count[j] += 1
        else:
            held = abs(w) >= near_cap and u_mean * w > 0.0
            if s.prev_ok[j] and not held:
                r = p.spin_inertia_kgm2 * (w - s.speed_prev[j]) / p.dt - u_mean
                s.residual_Nm[j] += alpha * (r - s.residual_Nm[j])
                if abs(s.residual_Nm[j]) > p.torque_threshold_Nm:
                    s.count[j] += 1
                else:
                    s.count[j] = 0
            s.speed_prev[j] = w
            s.prev_ok[j] = True
        if new < 0 and s.count[j] >= p.persistence_cycles:
            s.failed[j] = True
            new = j
    return new
