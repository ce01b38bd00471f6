"""One main-processor control cycle, compiled: rates, ephemeris and target,
attitude determination, the control law of the current mode (SunAcq,
Inertial, Science: wheels; DeltaH, DeltaV: thrusters, and wheels in DeltaH),
the torque filter, distribution to the actuators, the FDC checks. Safehold
is the ACE's (safehold.py), run after this by the loop.

The mode machine and command handling stay in Python (flight_software.py);
this kernel returns an event code (state.EVENT_*) when something needs their
attention. Records: sim/fsw/state.py.
"""
import numpy as np
from numba import njit

from sim.attitude import error_quat, rotation_angle, small_angle_error
from sim.fsw.css_sun import css_sun_vector_B
from sim.fsw.distribution import distribute
from sim.fsw.ekf import OPTION_IRU, attitude_cycle, body_from_tracker
from sim.fsw.fdc import fdc_cycle
from sim.fsw.integral_enable import inside_box
from sim.fsw.pid import pid_torque
from sim.fsw.rate_selection import least_squares_rate
from sim.fsw.science import (
    cgt_errors_B,
    commanded_offset_yz,
    science_acquired,
    science_errors,
)
from sim.fsw.state import (
    EVENT_CGT_LOST,
    EVENT_FDC,
    EVENT_NONE,
    EVENT_SCIENCE_ACQUIRED,
    EVENT_SLEW_SETTLED,
    F_CGT_OK,
    F_WATCH_SLEW,
)
from sim.fsw.sunacq import sunacq_torque_B
from sim.fsw.targeting import ephemeris_sample, is_sample_cycle
from sim.fsw.thruster_modes import thruster_mode_cycle
from sim.fsw.torque_filter import BANK_INERTIAL, BANK_SCIENCE, filter_torque
from sim.fsw.wheel_bias import wheel_bias_cycle
from sim.modes import Mode

SUNACQ = int(Mode.SUNACQ)
INERTIAL = int(Mode.INERTIAL)
SCIENCE = int(Mode.SCIENCE)
DELTAH = int(Mode.DELTAH)
DELTAV = int(Mode.DELTAV)
SAFEHOLD = int(Mode.SAFEHOLD)


@njit(cache=True)
def mode_uses_wheels(mode):
    """The wheel-based modes, whose wheel torques pass the zero-speed logic (seed 001)."""
    return mode == INERTIAL or mode == SCIENCE


@njit(cache=True)
def is_thruster_mode(mode):
    """DeltaH and DeltaV: thrusters, on the IRU-propagated attitude (seed 001)."""
    return mode == DELTAH or mode == DELTAV


@njit(cache=True)
def torque_scale(torque_cmd_B, torque_undelivered_B):
    """Delivered over desired torque of the last cycle, k_t of seed 000 eq. (1)
    (the distribution scales the whole vector, so one number says it). Takes
    arrays, not the state record: a call LLVM leaves out of line pays a
    reference count on every array of a record it is given."""
    cmd = np.sqrt(np.sum(torque_cmd_B * torque_cmd_B))
    if cmd == 0.0:
        return 1.0
    return 1.0 - np.sqrt(np.sum(torque_undelivered_B * torque_undelivered_B)) / cmd


@njit(cache=True, inline="always")
def pid_mode_law(rec, s, p):
    """Inertial (seed 001 eq. 1-3) and Science (eq. 4-5): errors, the PID with
    the integral torque box, the mode's torque filter. Returns an event."""
    theta_q = small_angle_error(error_quat(s.q_RN, s.q_est_BN))
    cgt_err = s.cgt_err_B
    cgt_ok = cgt_errors_B(rec, s.cgt[0], p.sci, cgt_err)
    flags = s.flags
    flags[F_CGT_OK] = 1.0 if cgt_ok else 0.0
    oy, oz = commanded_offset_yz(s.target[0], s.dq_RS)
    theta_e, omega_e, mode = s.theta_e, s.omega_e, s.mode[0]
    event = EVENT_NONE
    bank = BANK_INERTIAL
    if mode == SCIENCE and cgt_ok:
        science_errors(cgt_err, oy, oz, theta_q, theta_e)
        bank = BANK_SCIENCE
    else:
        theta_e[:] = theta_q
        if mode == SCIENCE:
            event = EVENT_CGT_LOST      # flown on the quaternion this cycle; the mode machine leaves Science
        elif science_acquired(s.autonomy[0], s.target[0], cgt_ok, cgt_err, oy, oz, p.sci.acq_range_rad):
            event = EVENT_SCIENCE_ACQUIRED
    omega_e[:] = -s.ekf.omega_est_B   # eq. (2), (5): the IRU rate less the estimated bias
    pid = p.pid
    torque, torque_int = pid_torque(theta_e, omega_e, s.integral, s.int_active,
                                    torque_scale(s.torque_cmd_B, s.torque_undelivered_B), pid)
    s.torque_pid_B[:] = torque
    s.torque_int_B[:] = torque_int
    filter_torque(torque, p.tf, s.tf, bank, s.torque_cmd_B)
    if event == EVENT_NONE and flags[F_WATCH_SLEW] > 0.0 and inside_box(theta_e, omega_e, pid, np.zeros(3)):
        flags[F_WATCH_SLEW] = 0.0
        event = EVENT_SLEW_SETTLED
    return event


@njit(cache=True, inline="always")
def tracker_attitude(st_q_SN, st_valid, st_q_BS):
    """(q_BN, ok) from the lowest-numbered valid star tracker: a reference
    independent of the IRU, for the IRU failure check."""
    for i in range(st_valid.shape[0]):
        if st_valid[i]:
            return body_from_tracker(st_q_SN[i], st_q_BS[i]), True
    return np.array([1.0, 0.0, 0.0, 0.0]), False


@njit(cache=True)
def sunacq_cycle(rec, s, p):
    """SunAcq, eq. (6): CSS Sun vector, IRU rate, no torque filter."""
    s.sun_ok[0] = css_sun_vector_B(rec.css_current_A, p.css_set, p.css, s.sun_B)
    t = sunacq_torque_B(s.sun_B, s.sun_ok[0], s.rate_B, np.diag(p.pid.inertia_B), p.sun)
    s.torque_pid_B[:] = t
    s.torque_cmd_B[:] = t
    if not s.sun_ok[0]:
        return 0.0
    return np.arccos(min(max(np.sum(s.sun_B * p.sun.sun_desired_B), -1.0), 1.0))


@njit(cache=True, inline="always")
def fsw_cycle(rec, s, p, act):
    """The main processor's cycle (nothing while it is down: the ACE notices)."""
    if not s.proc_up[0]:
        return EVENT_NONE
    rate, _ = least_squares_rate(rec.iru_rate_ch_rad_s, p.iru_ch_axes_B, rec.iru_ch_valid & s.iru_ch_use)
    s.rate_B[:] = rate
    k = s.cycle[0]
    if is_sample_cycle(k, p.eph_every):
        ephemeris_sample(s, p)
    s.cycle[0] = k + 1
    mode = s.mode[0]
    thruster_mode = is_thruster_mode(mode)
    # the thruster modes fly the IRU-propagated attitude (seed 001 "DeltaV", "DeltaH")
    attitude_cycle(OPTION_IRU if thruster_mode else s.att_option[0], s.st_select[0], s.ekf, p.ekf, s.rate_B,
                   rec.st_q_SN, rec.st_valid, s.sun_N, rec.dss_angles_rad, rec.dss_valid)
    event = EVENT_NONE
    att_err = 0.0
    if thruster_mode:
        event = thruster_mode_cycle(mode == DELTAV, s.q_est_BN, s.ekf.omega_est_B, rec.tach_speed_rad_s, s.thr,
                                    p.thr, act.wheel_torque_Nm, act.thruster_pulses, act.engine_on)
        att_err = rotation_angle(error_quat(s.thr.q_hold_BN, s.q_est_BN))
        s.torque_pid_B[:] = s.thr.torque_demand_B
        s.torque_cmd_B[:] = s.thr.torque_demand_B
        s.torque_undelivered_B[:] = s.thr.torque_demand_B - s.thr.torque_delivered_B
    else:
        act.thruster_pulses[:] = 0.0
        act.engine_on[0] = 0.0
        if mode_uses_wheels(mode):
            event = pid_mode_law(rec, s, p)
            att_err = np.sqrt(np.sum(s.theta_e * s.theta_e))
        elif mode == SUNACQ:
            att_err = sunacq_cycle(rec, s, p)
        else:   # Safehold: the ACE drives the wheels
            s.torque_pid_B[:] = 0.0
            s.torque_cmd_B[:] = 0.0
        s.torque_undelivered_B[:] = distribute(s.torque_cmd_B, p.dist, p.torque_limit, act.wheel_torque_Nm)
        if mode_uses_wheels(mode) and p.wb.limit_Nm > 0.0 and s.fdc.wheel_ok.all():
            wheel_bias_cycle(rec.tach_speed_rad_s, rec.tach_valid, p.wb, p.torque_limit, act.wheel_torque_Nm,
                             s.wheel_bias_Nm)
    if mode != SAFEHOLD and s.fdc.enabled.any():
        q_ref, ref_ok = tracker_attitude(rec.st_q_SN, rec.st_valid, p.ekf.st_q_BS)
        if fdc_cycle(mode, att_err, s.rate_B, rec.iru_rate_ch_rad_s, rec.iru_ch_valid, s.iru_ch_use, q_ref, ref_ok,
                     rec.st_valid, rec.tach_speed_rad_s, rec.tach_valid, act.wheel_torque_Nm, p.fdc,
                     s.fdc) and event == EVENT_NONE:
            event = EVENT_FDC
    return event
