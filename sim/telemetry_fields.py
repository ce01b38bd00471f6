"""The telemetry fields: their names, and one compiled function that computes
them all at an instant.

The runner owns both sides of the wall, so a frame may hold truth values
beside flight-software values; names say which (q_BN and sun_B are truth,
q_est_BN the flight software's estimate). Flight-software values are those of
the last completed control cycle. sun_B is the apparent Sun direction (with
aberration), as the sensors see it.
"""
from __future__ import annotations

import functools

import numpy as np
from numba import njit

from sim.attitude import (
    ARCSEC_PER_RAD,
    error_quat,
    quat_conj,
    quat_mul,
    quat_rotate,
    quat_rotate_inv,
    rotation_angle,
    small_angle_error,
)
from sim.fsw.cycle import is_thruster_mode
from sim.fsw.state import F_CGT_OK
from sim.modes import Mode
from sim.truth import mass as massmod
from sim.truth.dynamics import loads
from sim.truth.plant import apparent_sun_N
from sim.truth.rigid_body import IH, IQ, IW, angular_momentum_B
from sim.truth.sensors.sensor_geometry import angle_between
from sim.truth.wheels import wheel_speeds_rad_s

RPM_PER_RAD_S = 60.0 / (2.0 * np.pi)
DEG_H_PER_RAD_S = 180.0 / np.pi * 3600.0
XYZ = ("x", "y", "z")
WXYZ = ("w", "x", "y", "z")


def _vec(prefix: str, unit: str = "", axes=XYZ) -> list[str]:
    return [f"{prefix}_{a}{unit}" for a in axes]


def _numbered(prefix: str, unit: str, n: int) -> list[str]:
    return [f"{prefix}_{i + 1}{unit}" for i in range(n)]


def always_fields(n_wheels: int = 4) -> list[str]:
    """The columns every telemetry file has."""
    return (["t_s", "mode"] + _vec("q_BN", axes=WXYZ) + _vec("omega_BN_B", "_rad_s")
            + _numbered("h_wheel", "_Nms", n_wheels) + _vec("h_total_N", "_Nms") + ["att_err_arcsec"])


def sensor_fields(n_star_trackers: int, n_wheels: int, n_css: int, n_gt: int) -> list[str]:
    """Each sensor's outputs, named after the sensor (sim/records.py SensorRecord);
    an absent DSS or tachometer set keeps its columns, never valid."""
    return (_numbered("iru_rate_ch", "_rad_s", 6) + _numbered("iru_ch_valid", "", 6)
            + _numbered("st_valid", "", n_star_trackers) + _numbered("css_current", "_A", n_css)
            + ["dss_alpha_rad", "dss_beta_rad", "dss_valid"]
            + [f"gt_{i + 1}_{a}_arcsec" for i in range(n_gt) for a in ("y", "z")]
            + _numbered("gt_valid", "", n_gt) + _numbered("gt_in_range", "", n_gt)
            + _numbered("tach_speed", "_rpm", n_wheels) + _numbered("tach_valid", "", n_wheels))


@functools.cache
def field_names(n_wheels: int = 4, n_thrusters: int = 8, n_star_trackers: int = 2, n_css: int = 16,
                n_gt: int = 4) -> tuple[str, ...]:
    return tuple(always_fields(n_wheels) + (
        ["h_total_Nms", "est_err_arcsec"] + _vec("q_est_BN", axes=WXYZ) + _vec("q_RN", axes=WXYZ)
        + _vec("theta_e_B", "_arcsec") + _vec("iru_rate_B", "_rad_s")
        + _vec("torque_pid_B", "_Nm") + _vec("torque_cmd_B", "_Nm") + _vec("torque_undelivered_B", "_Nm")
        + ["integrator_active"] + _vec("integrator_active") + _vec("integral_B", "_rad_s")
        + _vec("torque_int_B", "_Nm")
        + _numbered("wheel_speed", "_rpm", n_wheels) + _numbered("wheel_cmd", "_Nm", n_wheels)
        + _vec("sun_B") + ["sun_angle_deg", "eclipse_lit_fraction"]
        + _vec("torque_srp_B", "_Nm") + _vec("torque_gg_B", "_Nm") + _vec("torque_engine_B", "_Nm")
        + _vec("torque_thrusters_B", "_Nm") + ["mass_kg", "propellant_kg"]
        + _vec("r_N", "_m") + _vec("v_N", "_m_s")
        + _numbered("thr_pulses", "", n_thrusters) + ["engine_on"]
        + fsw_fields(n_star_trackers, n_wheels)
        + sensor_fields(n_star_trackers, n_wheels, n_css, n_gt)))


def fsw_fields(n_star_trackers: int, n_wheels: int) -> list[str]:
    """Targeting, attitude determination and Science mode (sim/fsw/state.py);
    knowledge_err_B is the estimate's error against the truth, point_err and
    roll_err the truth attitude's against the flight software's target, and
    sun_fsw_err the on-board apparent Sun's against the truth's."""
    return (["target_kind", "attitude_option", "star_tracker_flown", "cgt", "science_autonomy", "cgt_ok",
             "cgt_err_y_arcsec", "cgt_err_z_arcsec"] + _vec("q_SN", axes=WXYZ)
            + _vec("ekf_bias_B", "_deg_h") + _vec("ekf_sigma_att_B", "_arcsec") + _vec("ekf_sigma_bias_B", "_deg_h")
            + [f"st_{k + 1}_innov_{a}_arcsec" for k in range(n_star_trackers) for a in XYZ]
            + _numbered("st_used", "", n_star_trackers) + ["dss_innov_alpha_arcsec", "dss_innov_beta_arcsec", "dss_used"]
            + _vec("knowledge_err_B", "_arcsec") + ["point_err_arcsec", "roll_err_arcsec", "sun_fsw_err_arcsec"]
            + _numbered("wheel_bias", "_Nm", n_wheels) + mode_fields(n_wheels))


def mode_fields(n_wheels: int) -> list[str]:
    """The mode machine and the modes of flight software II: mode_prev is the
    previous mode's number (sim.modes.Mode), mode_cause the last transition's
    cause (0 ground, 1 FDC, 2 autonomous; -1 none yet); torque_demand and
    torque_delivered are the control law's torque and what the actuators were
    commanded to give (wheel modes: after the distribution's scaling;
    thruster modes: from the pulse counts); the rest are on-board estimates
    and the FDC's view of the hardware."""
    return (["mode_prev", "mode_cause", "h_sys_err_Nms", "deltav_est_m_s", "propellant_est_kg", "css_sun_ok"]
            + _vec("torque_demand_B", "_Nm") + _vec("torque_delivered_B", "_Nm")
            + _numbered("wheel_ok", "", n_wheels) + _numbered("iru_ch_use", "", 6))


def sensor_counts(sc) -> tuple[int, int]:
    """(CSS eyes, guide telescopes) of a spacecraft: zero when it has none."""
    s = sc.sensors
    return (16 if s.css else 0), (len(s.guide_telescopes.units) if s.guide_telescopes else 0)


def names_for(sc) -> tuple[str, ...]:
    return field_names(sc.n_wheels, len(sc.thrusters.units), len(sc.star_trackers), *sensor_counts(sc))


@njit(cache=True)
def _sensor_numbers(rec):
    return np.concatenate((rec.iru_rate_ch_rad_s, rec.iru_ch_valid.astype(np.float64),
                           rec.st_valid.astype(np.float64), rec.css_current_A, rec.dss_angles_rad,
                           rec.dss_valid.astype(np.float64), rec.gt_offset_G_rad.ravel() * ARCSEC_PER_RAD,
                           rec.gt_valid.astype(np.float64), rec.gt_in_range.astype(np.float64),
                           rec.tach_speed_rad_s * RPM_PER_RAD_S, rec.tach_valid.astype(np.float64)))


@njit(cache=True)
def _fsw_numbers(s, q_BN, sun_N):
    e = s.ekf
    sig = np.sqrt(e.P_diag)
    know = small_angle_error(error_quat(s.q_est_BN, q_BN))
    point = small_angle_error(error_quat(s.q_RN, q_BN))
    return np.concatenate((
        np.array([float(s.target[0]), float(s.att_option[0]), float(s.st_select[0] + 1), float(s.cgt[0] + 1),
                  1.0 if s.autonomy[0] else 0.0, s.flags[F_CGT_OK]]), s.cgt_err_B * ARCSEC_PER_RAD, s.q_SN,
        e.bias_B * DEG_H_PER_RAD_S, sig[0:3] * ARCSEC_PER_RAD, sig[3:6] * DEG_H_PER_RAD_S,
        e.st_innov.ravel() * ARCSEC_PER_RAD, e.st_updated.astype(np.float64), e.dss_innov * ARCSEC_PER_RAD,
        e.dss_updated.astype(np.float64), know * ARCSEC_PER_RAD,
        np.array([np.sqrt(point[1] ** 2 + point[2] ** 2) * ARCSEC_PER_RAD, point[0] * ARCSEC_PER_RAD,
                  angle_between(s.sun_N, sun_N) * ARCSEC_PER_RAD]), s.wheel_bias_Nm, _mode_numbers(s)))


@njit(cache=True)
def _mode_numbers(s):
    t = s.thr
    # every mode leaves its demand in torque_cmd_B and what it could not give in
    # torque_undelivered_B (the thruster modes: by the pulse counts)
    demand = s.torque_cmd_B
    delivered = s.torque_cmd_B - s.torque_undelivered_B
    return np.concatenate((
        np.array([float(s.mode_info[0]), float(s.mode_info[1]), t.h_sys_err_Nms[0],
                  np.sqrt(np.sum(t.dv_N * t.dv_N)), t.propellant_kg[0], 1.0 if s.sun_ok[0] else 0.0]),
        demand, delivered, s.fdc.wheel_ok.astype(np.float64), s.iru_ch_use.astype(np.float64)))


@njit(cache=True)
def target_in_use(s):
    """The attitude the current mode holds: the thruster modes' own target, else q_RN."""
    mode = s.mode[0]
    return s.thr.q_hold_BN if is_thruster_mode(mode) else s.q_RN


@njit(cache=True)
def _numbers(t_s, ts, tp, s, rec, act):
    """The numeric fields in field_names() order (mode left out), compiled:
    telemetry is sampled often enough that Python-level math would dominate."""
    x = ts.x
    w = tp.dyn.wheels
    n = w.axes_B.shape[0]
    ir = IH + n + 3
    q_BN = x[IQ:IQ + 4]
    omega = x[IW:IW + 3]
    h = x[IH:IH + n]
    m_prop = x[ir + 6]
    j_prime = massmod.inertia_B(m_prop, tp.dyn.mass) - w.spin_inertia_B
    h_total_N = quat_rotate(q_BN, angular_momentum_B(x, j_prime, w))
    sun_N = apparent_sun_N(ts, tp)
    sun_B = quat_rotate_inv(q_BN, sun_N)
    ld = loads(x, tp.dyn, ts.inputs)
    # two concatenations: a tuple of more than 30 non-constant items compiles to
    # an op-code numba does not support (CPython 3.11's LIST_TO_TUPLE)
    head = np.concatenate((
        np.array([t_s]), q_BN, omega, h, h_total_N,
        np.array([rotation_angle(quat_mul(quat_conj(target_in_use(s)), q_BN)) * ARCSEC_PER_RAD,
                  np.sqrt(np.sum(h_total_N * h_total_N)),
                  rotation_angle(quat_mul(quat_conj(s.q_est_BN), q_BN)) * ARCSEC_PER_RAD]),
        s.q_est_BN, s.q_RN, s.theta_e * ARCSEC_PER_RAD, s.rate_B, s.torque_pid_B, s.torque_cmd_B,
        s.torque_undelivered_B,
        np.array([1.0 if s.int_active.all() else 0.0]), s.int_active.astype(np.float64), s.integral,
        s.torque_int_B,
        wheel_speeds_rad_s(h, omega, w.axes_B, w.spin_inertia) * RPM_PER_RAD_S, act.wheel_torque_Nm))
    return np.concatenate((
        head, sun_B, np.array([np.degrees(np.arccos(min(max(sun_B[0], -1.0), 1.0))), ts.inputs.lit_fraction[0]]),
        ld.torque_srp_B, ld.torque_gg_B, ld.torque_engine_B, ld.torque_thrusters_B,
        np.array([massmod.total_mass_kg(m_prop, tp.dyn.mass), m_prop]), x[ir:ir + 6],
        act.thruster_pulses, act.engine_on, _fsw_numbers(s, q_BN, sun_N), _sensor_numbers(rec)))


def sample(t_s: float, ts, tp, fsw_state, sensors, act) -> tuple[str, np.ndarray]:
    """Every field at one instant: the mode's name and the numeric fields."""
    return Mode(int(fsw_state.mode[0])).name, _numbers(t_s, ts, tp, fsw_state, sensors, act)
