"""Wheel-speed bias in the null space of the wheel array: keeps the wheels away
from zero speed without putting any torque on the body.

Seed 001 "Attitude control modes": "In the case of RWA-actuated modes, the RWA
torques are then passed through logic that distributes the RWA momentum to
minimize passing through zero wheel speed." This module is that logic.

Geometry (parameter-build time, Python). G (3 x N) holds the spin axes as
columns; a motor torque u on the rotors changes the wheel momenta at +u and
puts -G u on the body (sim/fsw/distribution.py). With four wheels G has a
one-dimensional null space n (unit, G n = 0): adding c n to the wheel momenta,
or commanding u along n, changes no body momentum. The distribution's
minimum-norm torques have no component along n, so the bias is the only thing
that moves the wheels along it. For the SDO pyramid (seed 001: four wheels,
symmetric about X, 30 deg from the YZ plane) n = [1, -1, 1, -1] / 2. With three
independent wheels (a failed one) the null space is empty: n = 0 and the logic
does nothing.

Why it is needed here: wheel drag pulls the wheel momenta along n toward the
minimum-norm (least-drag) pattern h with n . h = 0, and seed 000's
[-36.95, 0, 36.95, 0] N m s is exactly that pattern, two wheels parked at zero.

Algorithm (each 0.2 s control cycle, small fixed N, three small arrays, 0.3 us).
The reachable wheel momenta are the line h(c) = h + c n. Let

    g(c) = min(h_target, min_i |h_i + c n_i|)     (wheels with n_i = 0 left out:
                                                   the shift cannot help them)

and C the shifts that push no wheel above max(h_cap, |h_i|) (so C holds c = 0:
the bias never pulls a wheel past the capacity, nor acts because of it). The
wanted shift c* maximises g over C -- the largest floor on |h_i| the null space
can give, capped at h_target -- and among the maximisers (within TIE_NMS) it is
the one of smallest |c|, then c > 0: the least momentum moved, and no action
at all while every wheel is already at or above h_target - TIE_NMS (a deadband).
g is piecewise linear, so c* is exactly one of a few candidates, evaluated by
brute force (no sort):
0, the ends of C, the level crossings |h_i + c n_i| = h_target and the pairwise
crossings |h_i + c n_i| = |h_j + c n_j| (1 + 2 + 2N + N(N-1) = 23 for N = 4).
This is the max-min over all sign patterns, so the shift may take one wheel
through zero once, deliberately, to reach a pattern that stays clear of zero.
The command is proportional, u = k c* n (the rotors gain momentum at +u, so the
shift decays as exp(-k t): a slow drift, not a step), limited to |u_i| <=
limit_Nm (scaled along n, so still no body torque). `add_wheel_bias` then adds
it to the distributed attitude torques, scaling only the bias to fit the
headroom under the software limit: the attitude torque has priority.

The tie tolerance TIE_NMS is hysteresis: when two far-apart shifts give nearly
the same floor, tachometer quantisation could flip the choice each cycle; with
the tolerance the nearer one wins, and moving toward it keeps it nearer.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

# Defaults (assumptions, justified against sim/spacecraft/sdo.yaml and seed 001):
H_MIN_NMS = 5.0
"""Floor on |h_i| the bias keeps (assumption): 5 N m s = 45 rad/s = 430 rpm at
J_s = 0.1114 kg m^2, 7 % of the 70 N m s capacity (seed 001); well clear of the
Coulomb sign flip and of one tachometer count (0.49 rad/s at 64 pulses/rev)."""
H_TARGET_NMS = 6.0
"""Level the shift aims at (assumption): above H_MIN_NMS by more than the
proportional law's steady-state lag under sdo.yaml drag (about 0.5 N m s), so
the floor is reached in finite time and held."""
GAIN_PER_S = 0.02
"""Proportional gain (assumption): a 50 s time constant, 250 control cycles
(k dt = 0.004), a slow drift next to the attitude loop."""
LIMIT_NM = 0.02
"""Bias torque budget per wheel (assumption): 10 % of the 0.2 N m software
limit (seed 001). Drag pulls the null component back at |n . d|; holding
seed 000's wheels 2 and 4 at 5.5 N m s against sdo.yaml drag (viscous
1.67e-4 N m/(rad/s), Coulomb 0.002 N m) takes |n_i| |n . d| <= 0.0015 h + 0.001
= 0.009 N m per wheel (0.008 in the closed-loop test), so 0.01 N m would leave
no margin. Those wheels reach 5 N m s from zero in 5/0.02 = 250 s without
drag, 335 s with it."""
TIE_NMS = 0.1
"""Floors within this of the best count as equal (hysteresis, see above):
about two tachometer counts, J_s 2 pi/64/0.2 s = 0.055 N m s."""

_COMPONENT_EPS = 1e-12   # null-vector components below this are exact zeros
_SV_RTOL = 1e-9          # singular values below this x the largest: rank-deficient


class WheelBiasParams(NamedTuple):
    null_B: np.ndarray        # (N,) unit null vector of G in wheel space (zeros: no null space)
    gain_per_s: float         # proportional gain k, 1/s
    limit_Nm: float           # bias torque budget per wheel, N m
    h_min_Nms: float          # floor on |h_i| the design holds (documentation, telemetry, tests)
    h_target_Nms: float       # level the shift aims at, > h_min_Nms
    h_cap_Nms: float          # the shift pushes no wheel above this (wheel capacity)
    spin_inertia_kgm2: float  # J_s: h_i = J_s omega_i from the tachometers


def null_vector(axes_B, in_use=None) -> np.ndarray:
    """(N,) unit vector n with G n = 0, G = axes_B.T (3 x N), n_i = 0 for the
    wheels not in use (in_use False, or a zero axis). Sign fixed: the first
    nonzero component is positive. Zeros when the null space is empty (three
    independent wheels); ValueError when it has more than one dimension (five
    or more wheels, or a degenerate array), which this logic does not handle."""
    axes = np.atleast_2d(np.asarray(axes_B, float))
    n_wheels = axes.shape[0]
    use = np.ones(n_wheels, bool) if in_use is None else np.asarray(in_use, bool).copy()
    use &= np.linalg.norm(axes, axis=1) > 0.0
    idx = np.flatnonzero(use)
    out = np.zeros(n_wheels)
    if idx.size == 0:
        return out
    g = axes[idx].T  # 3 x M
    _, sv, vt = np.linalg.svd(g)
    rank = int(np.sum(sv > _SV_RTOL * sv[0])) if sv.size and sv[0] > 0.0 else 0
    dim = idx.size - rank
    if dim == 0:
        return out
    if dim > 1:
        raise ValueError(f"wheel null space has {dim} dimensions; the bias logic handles one")
    v = vt[-1].copy()
    v[np.abs(v) < _COMPONENT_EPS] = 0.0
    v /= np.linalg.norm(v)
    if v[np.flatnonzero(v)[0]] < 0.0:
        v = -v
    out[idx] = v
    return out


def make_wheel_bias_params(axes_B, spin_inertia_kgm2, h_cap_Nms, in_use=None, h_min_Nms=H_MIN_NMS,
                           h_target_Nms=H_TARGET_NMS, gain_per_s=GAIN_PER_S, limit_Nm=LIMIT_NM) -> WheelBiasParams:
    """Parameters for the SDO wheels: make_wheel_bias_params(sc.wheels.axes_B,
    sc.wheels.spin_inertia_kgm2, sc.wheels.h_max_Nms)."""
    if not 0.0 <= h_min_Nms <= h_target_Nms < h_cap_Nms:
        raise ValueError("need 0 <= h_min_Nms <= h_target_Nms < h_cap_Nms")
    if gain_per_s < 0.0 or limit_Nm < 0.0 or spin_inertia_kgm2 <= 0.0:
        raise ValueError("gain, limit must be >= 0 and the spin inertia > 0")
    return WheelBiasParams(null_vector(axes_B, in_use), float(gain_per_s), float(limit_Nm), float(h_min_Nms),
                           float(h_target_Nms), float(h_cap_Nms), float(spin_inertia_kgm2))


@njit(cache=True)
def null_level(h, n, c, level):
    """g(c) = min(level, min over wheels with n_i != 0 of |h_i + c n_i|)."""
    g = level
    for i in range(h.shape[0]):
        if n[i] != 0.0:
            g = min(g, abs(h[i] + c * n[i]))
    return g


@njit(cache=True)
def null_shift(h, n, h_target, h_cap):
    """The null-space shift c* (N m s along n) of the module docstring: the
    largest floor min(h_target, min_i |h_i + c n_i|) over the admissible
    shifts, then the smallest |c|, then c > 0. Zero when n is zero."""
    m = h.shape[0]
    lo = -np.inf
    hi = np.inf
    active = 0
    for i in range(m):
        if n[i] != 0.0:
            active += 1
            cap = max(h_cap, abs(h[i]))
            a = (-cap - h[i]) / n[i]
            b = (cap - h[i]) / n[i]
            if a > b:
                a, b = b, a
            lo = max(lo, a)
            hi = min(hi, b)
    if active == 0:
        return 0.0
    cand = np.empty(3 + 2 * m + m * (m - 1))
    k = 0
    cand[k] = 0.0
    cand[k + 1] = lo
    cand[k + 2] = hi
    k += 3
    for i in range(m):
        if n[i] != 0.0:
            cand[k] = (h_target - h[i]) / n[i]
            cand[k + 1] = (-h_target - h[i]) / n[i]
            k += 2
    for i in range(m):
        if n[i] == 0.0:
            continue
        for j in range(i + 1, m):
            if n[j] == 0.0:
                continue
            d = n[i] - n[j]          # h_i + c n_i = h_j + c n_j
            if abs(d) > _COMPONENT_EPS:
                cand[k] = (h[j] - h[i]) / d
                k += 1
            d = n[i] + n[j]          # h_i + c n_i = -(h_j + c n_j)
            if abs(d) > _COMPONENT_EPS:
                cand[k] = -(h[i] + h[j]) / d
                k += 1
    best = -1.0
    for q in range(k):
        cand[q] = min(max(cand[q], lo), hi)
        best = max(best, null_level(h, n, cand[q], h_target))
    c_star = 0.0
    found = False
    for q in range(k):
        c = cand[q]
        if null_level(h, n, c, h_target) < best - TIE_NMS:
            continue
        if not found or abs(c) < abs(c_star) - 1e-12 or (abs(c) <= abs(c_star) + 1e-12 and c > c_star):
            c_star = c
            found = True
    return c_star


@njit(cache=True)
def wheel_bias_torque(h_wheels_Nms, valid, n, gain_per_s, limit_Nm, h_target_Nms, h_cap_Nms, out_u):
    """Write the bias motor torques (N,) N m to out_u, u = k c* n with
    |u_i| <= limit_Nm; G u = 0. Zero if n is zero or the tachometer of any
    wheel the bias moves (n_i != 0) is invalid. Returns c*, N m s (0 then)."""
    out_u[:] = 0.0
    nmax = 0.0
    for i in range(n.shape[0]):
        if n[i] != 0.0:
            if not valid[i]:
                return 0.0
            nmax = max(nmax, abs(n[i]))
    if nmax == 0.0:
        return 0.0
    c_star = null_shift(h_wheels_Nms, n, h_target_Nms, h_cap_Nms)
    a = gain_per_s * c_star
    a_max = limit_Nm / nmax
    a = min(max(a, -a_max), a_max)
    for i in range(n.shape[0]):
        out_u[i] = a * n[i]
    return c_star


@njit(cache=True)
def add_wheel_bias(u_att, u_bias, limit_Nm, out_u):
    """out_u = u_att + s u_bias with the largest s in [0, 1] that keeps every
    |out_u_i| <= limit_Nm: the attitude torques (already within the limit, from
    distribute) are untouched, and one scale for the whole bias keeps it along
    n (no body torque). Returns s."""
    s = 1.0
    for i in range(u_att.shape[0]):
        b = u_bias[i]
        if b > 0.0:
            s = min(s, (limit_Nm - u_att[i]) / b)
        elif b < 0.0:
            s = min(s, (limit_Nm + u_att[i]) / -b)
    s = max(s, 0.0)
    for i in range(u_att.shape[0]):
        out_u[i] = u_att[i] + s * u_bias[i]
    return s


@njit(cache=True, inline="always")
def wheel_bias_cycle(tach_rad_s, tach_valid, p, torque_limit_Nm, u_inout, out_bias):
    """One control cycle: wheel momenta J_s omega from the tachometers, the
    bias torque, added to the distributed wheel torques u_inout in place within
    the software limit; out_bias gets the part added (for telemetry). Returns
    c*, the null-space shift still wanted, N m s."""
    m = tach_rad_s.shape[0]
    h = np.empty(m)
    for i in range(m):
        h[i] = p.spin_inertia_kgm2 * tach_rad_s[i]
    c_star = wheel_bias_torque(h, tach_valid, p.null_B, p.gain_per_s, p.limit_Nm, p.h_target_Nms, p.h_cap_Nms,
                               out_bias)
    scale = add_wheel_bias(u_inout, out_bias, torque_limit_Nm, u_inout)
    for i in range(m):
        out_bias[i] *= scale
    return c_star
