"""Thruster command logic: a body torque demand -> pulse counts per control cycle.

Seed 001 "Hardware complement" and "DeltaV": eight 5 lbf ACS thrusters, four
primary and four redundant, one set in use at a time. "The outputs of the
controller are thruster count commands, equivalent to the number of thruster
pulses in a given control cycle. Each thruster is capable of delivering up to
four 50-msec pulses during each 200-msec control cycle." In main-engine burns
("DeltaV") and in every momentum unload ("DeltaH") the thrusters on-pulse for
control; in burns without the main engine they give the delta-V and off-pulse.

Laid out like PX4's control allocation: geometry, algorithm, status.

Geometry (`make_thruster_logic_params`, numpy, build time): each thruster's
torque and force when firing continuously, and for each set the
pseudo-inverse M+ of its (3, 4) torque matrix M and its null vector n
(M n = 0). Four thrusters on three torque axes leave one free direction:
every duty vector d = M+ T + alpha n gives the mean torque T. With all n_i > 0
(SDO's four aft corners balance each other) alpha is a throttle: raising it
adds thrust along X and no torque. Null-space balancing chooses alpha:
  * on-pulsing: the smallest alpha with all d >= 0 -- the least propellant;
  * off-pulsing: the largest alpha with all d <= 1 -- the most delta-V.
Both are feasible exactly when the on-pulse duties are all <= 1 (the on-pulse
alpha, a = max_j(-x_j/n_j) with x = M+ T, fits under min_i (1 - x_i)/n_i
iff x_i + a n_i <= 1 for all i), so a torque beyond authority is scaled by
1 / max(d_on) in either case. d is positively homogeneous in T, so the scaled
torque keeps its direction (seed 001 "Attitude control modes": commands are
scaled so "the direction of the torque vector remains constant").

Algorithm (`thruster_pulses`, compiled, per cycle): duties, then whole pulses
with error feedback: each thruster's rounding remainder is carried to the next
cycle, so the delivered impulse follows the demand over cycles.

Status (`delivered_torque_B`, `delivered_force_B`, `propellant_used_kg`): what
the pulses give over one cycle; the caller takes the undelivered torque as the
demand minus the delivered torque.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.constants import G0_M_S2
from sim.linalg import matvec

SET_NAMES = ("primary", "redundant")  # row order of ThrusterLogicParams.sets (those present)
SET_SIZE = 4  # seed 001 "DeltaV": "only one set of four is used"


class ThrusterLogicParams(NamedTuple):
    torque_B: np.ndarray   # (n_thr, 3) N m: each thruster firing continuously, about the FSW's nominal cm
    force_B: np.ndarray    # (n_thr, 3) N: each thruster firing continuously
    flow_kg_s: np.ndarray  # (n_thr,) propellant flow while firing, thrust / (Isp g0)
    sets: np.ndarray       # (n_sets, 4) int64 thruster indices of each set (SET_NAMES order)
    pinv: np.ndarray       # (n_sets, 4, 3) pseudo-inverse of each set's (3, 4) torque matrix
    null: np.ndarray       # (n_sets, 4) each set's torque null vector, largest entry 1, all > 0
    max_pulses: int        # pulses per thruster per cycle at most
    pulse_s: float         # length of one pulse
    cycle_s: float         # control cycle


def _set_geometry(name, torque_B, members):
    """Pseudo-inverse (4, 3) and positive null vector (4,) of one set's torque matrix."""
    m = torque_B[members].T
    _, sv, vt = np.linalg.svd(m)
    if sv[2] <= 1e-9 * sv[0]:
        raise ValueError(f"thruster set {name!r}: the torque matrix has rank < 3, "
                         "the set cannot produce every torque direction")
    null = vt[3] / vt[3][np.argmax(np.abs(vt[3]))]
    if np.min(null) <= 1e-9:
        raise ValueError(f"thruster set {name!r}: the torque null vector {np.round(null, 6).tolist()} "
                         "does not have all entries of one sign, so on-pulsing cannot produce every "
                         "torque direction")
    return np.linalg.pinv(m), null


def make_thruster_logic_params(position_B_m, direction_B, thrust_N, isp_s, set_names, cm_B_m,
                               max_pulses, pulse_s, cycle_s) -> ThrusterLogicParams:
    """Geometry of the thruster suite about the centre of mass cm_B_m (structure frame)."""
    thrust_N = np.asarray(thrust_N, float)
    force_B = np.asarray(direction_B, float).reshape(-1, 3) * thrust_N[:, None]
    arm_B_m = np.asarray(position_B_m, float).reshape(-1, 3) - np.asarray(cm_B_m, float)
    torque_B = np.cross(arm_B_m, force_B)
    if max_pulses * pulse_s > cycle_s * (1.0 + 1e-12):
        raise ValueError(f"{max_pulses} pulses of {pulse_s} s do not fit in a {cycle_s} s cycle")
    names = np.asarray(list(set_names))
    unknown = sorted(set(names.tolist()) - set(SET_NAMES))
    if unknown or len(names) != len(force_B):
        raise ValueError(f"set_names must name each thruster's set, one of {SET_NAMES}; got {names.tolist()}")
    sets = [np.flatnonzero(names == s) for s in SET_NAMES if s in names]
    for s, members in zip(SET_NAMES, sets):
        if len(members) != SET_SIZE:
            raise ValueError(f"thruster set {s!r} has {len(members)} thrusters, needs {SET_SIZE}")
    geometry = [_set_geometry(s, torque_B, m) for s, m in zip(SET_NAMES, sets)]
    return ThrusterLogicParams(
        torque_B, force_B, thrust_N / (np.asarray(isp_s, float) * G0_M_S2),
        np.array(sets, dtype=np.int64), np.array([g[0] for g in geometry]),
        np.array([g[1] for g in geometry]), int(max_pulses), float(pulse_s), float(cycle_s))


@njit(cache=True)
def set_duty(torque_B, off_pulse, pinv, null, duty_out):
    """Duties (4,) in [0, 1] of one set (pinv (4, 3), null (4,)) whose mean torque,
    sum duty_i * torque_i, is k * torque_B; writes duty_out and returns k: 1 within
    authority, else the factor that scales the whole vector onto the boundary."""
    x = matvec(pinv, torque_B)
    alpha_on = np.max(-x / null)
    peak = np.max(x + alpha_on * null)
    k = 1.0 if peak <= 1.0 else 1.0 / peak
    alpha = np.min((1.0 - k * x) / null) if off_pulse else k * alpha_on
    duty_out[:] = np.minimum(np.maximum(k * x + alpha * null, 0.0), 1.0)
    return k


@njit(cache=True, inline="always")
def thruster_pulses(torque_B, off_pulse, set_index, p, carry, pulses_out):
    """Pulse counts (whole numbers as floats) for the demanded mean torque torque_B
    (N m, B) with set `set_index`; writes pulses_out (n_thr,) and updates the
    rounding carry (n_thr,) in place. Thrusters outside the set get 0, carry 0."""
    on_fraction = p.max_pulses * p.pulse_s / p.cycle_s  # duty 1 = max_pulses pulses
    duty = np.empty(SET_SIZE)
    set_duty(torque_B / on_fraction, off_pulse, p.pinv[set_index], p.null[set_index], duty)
    pulses_out[:] = 0.0
    kept = carry[p.sets[set_index]]
    carry[:] = 0.0
    for i in range(SET_SIZE):
        j = p.sets[set_index, i]
        desired = duty[i] * p.max_pulses + kept[i]
        n = min(max(np.floor(desired + 0.5), 0.0), float(p.max_pulses))
        pulses_out[j] = n
        carry[j] = min(max(desired - n, -1.0), 1.0)


@njit(cache=True)
def _pulse_sum(pulses, per_thruster, scale):
    """sum_i pulses_i * scale * per_thruster[i] for per_thruster (n_thr, 3)."""
    out = np.zeros(3)
    for i in range(pulses.shape[0]):
        out += (pulses[i] * scale) * per_thruster[i]
    return out


@njit(cache=True)
def delivered_torque_B(pulses, p):
    """Mean body torque (3,) N m over the cycle from the pulse counts."""
    return _pulse_sum(pulses, p.torque_B, p.pulse_s / p.cycle_s)


@njit(cache=True)
def delivered_force_B(pulses, p):
    """Mean body force (3,) N over the cycle from the pulse counts."""
    return _pulse_sum(pulses, p.force_B, p.pulse_s / p.cycle_s)


@njit(cache=True)
def propellant_used_kg(pulses, p):
    """Propellant the pulse counts use in one cycle."""
    return np.sum(pulses * p.flow_kg_s) * p.pulse_s
