"""The flight software's parameters and initial state, from a validated
spacecraft definition and the ground's uplink (sim/uplink.py gives the
numbers; this module takes them as plain values, so sim.fsw still never sees
the truth model).
"""
from __future__ import annotations

import numpy as np

from sim.attitude import quat_to_dcm
from sim.fsw import build_modes as bm
from sim.fsw import ekf as ekfmod
from sim.fsw.css_sun import make_css_sun_params
from sim.fsw.distribution import distribution_matrix
from sim.fsw.ephemeris_task import EphemerisTaskParams, init_task
from sim.fsw.filter_design import make_torque_filter_params
from sim.fsw.ground_station import white_sands_E_m
from sim.fsw.orbit_propagator import make_orbit_params
from sim.fsw.pid import DISABLE_METHODS, PidParams
from sim.fsw.science import ARCSEC, gt_biases
from sim.fsw.snr import SOLAR_POLE_N, TARGET_GCI, TARGET_SNR, TARGET_SNR_DELTA
from sim.fsw.state import N_FLAGS, FswParams, FswState, ScienceParams
from sim.fsw.targeting import update_target
from sim.fsw.thruster_modes import make_thruster_mode_state
from sim.fsw.torque_filter import make_torque_filter_state
from sim.fsw.wheel_bias import WheelBiasParams, make_wheel_bias_params
from sim.modes import Mode
from sim.spacecraft.fsw_models import OnboardEphemeris

ATTITUDE_OPTIONS = {"ekf": ekfmod.OPTION_EKF, "star_tracker": ekfmod.OPTION_STAR_TRACKER, "iru": ekfmod.OPTION_IRU}
DEG_H = np.pi / 180.0 / 3600.0   # rad/s per deg/h


def pid_params(sc) -> PidParams:
    g = sc.fsw.inertial
    return PidParams(np.array(sc.inertia_B_kgm2, float), g.kp_per_s2, g.kd_per_s, g.ki_per_s3,
                     g.integrator_limit_rad_s, g.box_theta_lim_rad, g.box_omega_lim_rad_s, g.attitude_limit_rad,
                     sc.timing.control_dt_s, g.box_option, g.box_per_axis, DISABLE_METHODS[g.disable],
                     g.torque_sat_Nm)


def _science_params(sc) -> ScienceParams:
    gts = sc.sensors.guide_telescopes
    acq = sc.fsw.science.acquisition_range_arcsec * ARCSEC
    if gts is None:   # no telescopes: one dummy slot, never valid (cycle checks the record's size)
        return ScienceParams(np.eye(3)[None].copy(), np.zeros((1, 2)), acq)
    q = [u.q_BG for u in gts.units]
    dcm_BG = np.ascontiguousarray(np.stack([quat_to_dcm(np.asarray(x, float)) for x in q]))
    return ScienceParams(dcm_BG, gt_biases(q, [u.misalignment_arcsec for u in gts.units]), acq)


def _wheel_bias_params(sc) -> WheelBiasParams:
    w, wb = sc.wheels, sc.fsw.wheel_bias
    if wb is None:   # gain and budget zero: the logic adds nothing
        return make_wheel_bias_params(w.axes_B, w.spin_inertia_kgm2, w.h_max_Nms, gain_per_s=0.0, limit_Nm=0.0)
    return make_wheel_bias_params(w.axes_B, w.spin_inertia_kgm2, w.h_max_Nms, h_min_Nms=wb.h_min_Nms,
                                  h_target_Nms=wb.h_target_Nms, gain_per_s=wb.gain_per_s, limit_Nm=wb.limit_Nm)


def make_fsw_params(sc, uplink) -> FswParams:
    dt = sc.timing.control_dt_s
    e = sc.fsw.ephemeris or OnboardEphemeris(srp_area_m2=0.0, cr=1.0)   # absent: built once, never stepped
    every = round(e.sample_s / dt) if sc.fsw.ephemeris else 0
    if sc.fsw.ephemeris and (every < 1 or abs(every * dt - e.sample_s) > 1e-9):
        raise ValueError(f"fsw.ephemeris.sample_s = {e.sample_s:g} s must be a whole number of control cycles "
                         f"({dt:g} s)")
    orbit = make_orbit_params(uplink.clock, uplink.dcm_CN, e.srp_area_m2, sc.mass_kg, e.cr)
    return FswParams(
        pid=pid_params(sc), dist=distribution_matrix(sc.wheels.axes_B), torque_limit=sc.wheels.torque_limit_sw_Nm,
        iru_ch_axes_B=np.array(sc.sensors.iru_units.channel_axes_B, float), dt=dt,
        ekf=ekfmod.ekf_params_from_spacecraft(sc, sc.fsw.ekf.sun_accuracy_arcsec_3sigma),
        eph=EphemerisTaskParams(orbit, white_sands_E_m(), e.sample_s), eph_every=every, pole_N=SOLAR_POLE_N.copy(),
        tf=make_torque_filter_params(sc.fsw.torque_filters, dt), sci=_science_params(sc), wb=_wheel_bias_params(sc),
        sun=bm.sun_law_params(sc), css=make_css_sun_params(sc), css_set=bm.css_set(sc), thr=bm.thruster_mode_params(sc),
        fdc=bm.fdc_params(sc))


def target_kind(dq_RS) -> int:
    return TARGET_SNR if np.allclose(dq_RS, (1.0, 0.0, 0.0, 0.0), rtol=0.0, atol=1e-15) else TARGET_SNR_DELTA


def make_fsw_state(sc, p: FswParams, uplink, mode: Mode, q_est_BN, q_RN_gci=None,
                   dq_RS=(1.0, 0.0, 0.0, 0.0), propellant_kg=None) -> FswState:
    """The state at t = 0: the filter at the uplinked attitude q_est_BN, the
    ephemeris task at the uplinked orbit, the target GCI q_RN_gci when given,
    else the SNR frame times dq_RS."""
    f = sc.fsw
    ekf = ekfmod.ekf_initial_state(q_est_BN, len(sc.star_trackers), f.ekf.initial_sigma_attitude_arcsec * ARCSEC,
                                   f.ekf.initial_sigma_bias_deg_h * DEG_H, use_dss=sc.sensors.dss is not None)
    dq = np.array(dq_RS, float) * (1.0 if dq_RS[0] >= 0.0 else -1.0)
    kind = TARGET_GCI if q_RN_gci is not None else target_kind(dq)
    q_cmd = np.array(q_RN_gci if q_RN_gci is not None else (1.0, 0.0, 0.0, 0.0), float)
    n_gt = len(sc.sensors.guide_telescopes.units) if sc.sensors.guide_telescopes else 0

    def flag(value):
        return np.array([value], dtype=np.bool_)

    def index(value):
        return np.array([value], np.int64)

    s = FswState(
        mode=index(int(mode)), cycle=index(0), q_est_BN=ekf.q_est_BN, q_RN=q_cmd.copy(), target=index(kind),
        dq_RS=dq, q_RN_cmd=q_cmd, q_SN=np.zeros(4), sun_N=np.zeros(3), att_option=index(ATTITUDE_OPTIONS[f.attitude_option]),
        st_select=index(f.star_tracker), cgt=index(f.science.cgt - 1), autonomy=flag(f.science.autonomy and n_gt > 0),
        cgt_err_B=np.zeros(2), integral=np.zeros(3), theta_e=np.zeros(3), omega_e=np.zeros(3),
        torque_pid_B=np.zeros(3), torque_cmd_B=np.zeros(3), torque_undelivered_B=np.zeros(3),
        flags=np.zeros(N_FLAGS), rate_B=np.zeros(3), int_active=np.zeros(3, dtype=np.bool_), torque_int_B=np.zeros(3),
        iru_ch_use=np.ones(6, dtype=np.bool_), wheel_bias_Nm=np.zeros(sc.n_wheels),
        ekf=ekf, eph=init_task(p.eph, uplink.x_sc_N, 0.0), tf=make_torque_filter_state(),
        mode_info=np.array([int(mode), -1], np.int64), sun_B=np.array([1.0, 0.0, 0.0]), sun_ok=flag(False),
        proc_up=flag(True),
        thr=make_thruster_mode_state(sc.n_wheels, len(sc.thrusters.units),
                                     sc.mass.propellant_kg if propellant_kg is None else propellant_kg,
                                     bm.thruster_set_index(sc, f.thruster_control.thruster_set
                                                           if f.thruster_control else "primary")),
        fdc=bm.fdc_state(sc, enabled=True))
    update_target(s, p)
    return s
