"""The thruster modes' shared cycle (seed 001 "DeltaV", "DeltaH"): PD on the
IRU-propagated attitude, thruster pulse counts, and the on-board book-keeping
of propellant and delta-V.

* Gains "built from the decoupled inertia, which changes with propellant":
  K = k * diag(I(m)), with I interpolated linearly between the full- and
  empty-tank inertias at the on-board propellant estimate (the truth model's
  own assumption, sim/truth/mass.py, made from the same spacecraft file).
* Propellant: the estimate starts at the uplinked load and is debited by the
  commanded pulses and engine time at the nominal flow.
* Delta-V: the commanded thrust (pulses and engine, nominal forces) rotated
  to GCI with the attitude estimate, over the estimated mass; the magnitude
  of the sum is `deltav_est_m_s`.
"""
from typing import NamedTuple

import numpy as np
from numba import njit

from sim.attitude import error_quat, quat_rotate, small_angle_error
from sim.fsw.deltah import deltah_wheel_torque, system_momentum_error_Nms
from sim.fsw.deltav import PHASE_DONE, PHASE_ENGINE, burn_phase
from sim.fsw.thruster_logic import (
    ThrusterLogicParams,
    delivered_force_B,
    delivered_torque_B,
    propellant_used_kg,
    thruster_pulses,
)

EVENT_BURN_DONE = 4
EVENT_DELTAH_DONE = 5


class ThrusterModeParams(NamedTuple):
    logic: ThrusterLogicParams
    deltav_kp_per_s2: float
    deltav_kd_per_s: float
    deltah_kp_per_s2: float
    deltah_kd_per_s: float
    tipoff_kp_factor: float
    wheel_gain_per_s: float
    h_exit_Nms: float
    settle_cycles: int
    inertia_full_diag: np.ndarray   # (3,) kg m^2
    inertia_empty_diag: np.ndarray  # (3,)
    propellant_full_kg: float
    dry_kg: float
    engine_force_B: np.ndarray      # (3,) N, nominal
    engine_flow_kg_s: float
    wheel_axes_B: np.ndarray        # (N, 3)
    spin_inertia: float
    torque_limit: float             # wheel software limit, N m
    dt: float


class ThrusterModeState(NamedTuple):
    q_hold_BN: np.ndarray           # (4,) DeltaH: attitude at entry; DeltaV: the burn target
    h_target_Nms: np.ndarray        # (N,) DeltaH wheel momentum targets
    tipoff: np.ndarray              # (1,) bool: DeltaH tip-off contingency (K_p / 10)
    burn_cycles: np.ndarray         # (1,) int64: DeltaV burn length incl. settling
    burn_k: np.ndarray              # (1,) int64: DeltaV cycles burnt
    main_engine: np.ndarray         # (1,) bool
    thr_set: np.ndarray             # (1,) int64: 0 primary, 1 redundant
    carry: np.ndarray               # (n_thr,) pulse quantisation carry
    torque_demand_B: np.ndarray     # (3,) N m, the PD's torque
    torque_delivered_B: np.ndarray  # (3,) N m, what the pulse counts give (nominal geometry)
    propellant_kg: np.ndarray       # (1,) on-board estimate
    dv_N: np.ndarray                # (3,) m/s, on-board delta-V estimate, GCI
    h_sys_err_Nms: np.ndarray       # (1,) DeltaH exit quantity


def make_thruster_mode_state(n_wheels, n_thr, propellant_kg, thr_set) -> ThrusterModeState:
    return ThrusterModeState(np.array([1.0, 0.0, 0.0, 0.0]), np.zeros(n_wheels), np.zeros(1, np.bool_),
                             np.zeros(1, np.int64), np.zeros(1, np.int64), np.zeros(1, np.bool_),
                             np.array([thr_set], np.int64), np.zeros(n_thr), np.zeros(3), np.zeros(3),
                             np.array([propellant_kg], float), np.zeros(3), np.zeros(1))


@njit(cache=True)
def inertia_diag_kgm2(propellant_kg, p):
    f = 0.0 if p.propellant_full_kg <= 0.0 else min(max(propellant_kg / p.propellant_full_kg, 0.0), 1.0)
    return p.inertia_empty_diag + f * (p.inertia_full_diag - p.inertia_empty_diag)


@njit(cache=True)
def pd_torque_B(q_hold_BN, q_est_BN, omega_B, inertia_diag, kp, kd):
    theta = small_angle_error(error_quat(q_hold_BN, q_est_BN))
    return inertia_diag * (kp * theta - kd * omega_B)


@njit(cache=True)
def book_keeping(pulses, engine_on, q_est_BN, t, p):
    """Debit the propellant, credit the delta-V estimate, for one cycle."""
    m = p.dry_kg + max(t.propellant_kg[0], 0.0)
    force_B = delivered_force_B(pulses, p.logic) + engine_on * p.engine_force_B
    t.dv_N[:] += quat_rotate(q_est_BN, force_B) * (p.dt / m)
    used = propellant_used_kg(pulses, p.logic) + engine_on * p.engine_flow_kg_s * p.dt
    t.propellant_kg[0] = max(t.propellant_kg[0] - used, 0.0)


@njit(cache=True)
def thruster_mode_cycle(is_deltav, q_est_BN, omega_B, tach_speed_rad_s, t, p, wheel_torque_Nm, pulses, engine_on):
    """One DeltaV or DeltaH cycle; writes the whole actuator command and
    returns an event code (0: none)."""
    I = inertia_diag_kgm2(t.propellant_kg[0], p)
    event = 0
    off_pulse = False
    engine_on[0] = 0.0
    wheel_torque_Nm[:] = 0.0   # DeltaV: the wheels "are allowed to run down due to drag"
    if is_deltav:
        phase = burn_phase(t.burn_k[0], t.burn_cycles[0], p.settle_cycles, t.main_engine[0])
        t.burn_k[0] += 1
        if phase == PHASE_DONE:
            pulses[:] = 0.0
            t.torque_demand_B[:] = 0.0
            t.torque_delivered_B[:] = 0.0
            return EVENT_BURN_DONE
        off_pulse = phase != PHASE_ENGINE
        if phase == PHASE_ENGINE:
            engine_on[0] = 1.0
        kp, kd = p.deltav_kp_per_s2, p.deltav_kd_per_s
    else:
        kp = p.deltah_kp_per_s2 * (p.tipoff_kp_factor if t.tipoff[0] else 1.0)
        kd = p.deltah_kd_per_s
        deltah_wheel_torque(tach_speed_rad_s, t.h_target_Nms, p.spin_inertia, p.wheel_gain_per_s, p.torque_limit,
                            wheel_torque_Nm)
        t.h_sys_err_Nms[0] = system_momentum_error_Nms(tach_speed_rad_s, t.h_target_Nms, omega_B, I,
                                                       p.wheel_axes_B, p.spin_inertia)
        if t.h_sys_err_Nms[0] < p.h_exit_Nms:
            event = EVENT_DELTAH_DONE
    t.torque_demand_B[:] = pd_torque_B(t.q_hold_BN, q_est_BN, omega_B, I, kp, kd)
    thruster_pulses(t.torque_demand_B, off_pulse, t.thr_set[0], p.logic, t.carry, pulses)
    t.torque_delivered_B[:] = delivered_torque_B(pulses, p.logic)
    book_keeping(pulses, engine_on[0], q_est_BN, t, p)
    return event
