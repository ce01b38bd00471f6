"""Parameters and initial state of the SunAcq, Safehold (ACE), DeltaV/DeltaH
and FDC parts of the flight software, from a validated spacecraft file.

A spacecraft without a section (fsw.sun_acquisition, fsw.safehold,
fsw.thruster_control, fsw.fdc) still gets well-formed records, and the mode
machine refuses the modes it cannot fly (flight_software.py)."""
from __future__ import annotations

import numpy as np

from sim.constants import G0_M_S2, LBF_N
from sim.fsw.css_sun import make_css_sun_params
from sim.fsw.distribution import distribution_matrix
from sim.fsw.fdc import CHECK_WHEEL, N_CHECKS, NO_LIMIT, FdcParams, FdcState
from sim.fsw.fdc_iru import make_iru_fdc_params, make_iru_fdc_state
from sim.fsw.fdc_wheel import make_wheel_fdc_params, make_wheel_fdc_state
from sim.fsw.safehold import AceParams
from sim.fsw.sunacq import SunLawParams
from sim.fsw.thruster_logic import SET_NAMES, make_thruster_logic_params
from sim.fsw.thruster_modes import ThrusterModeParams
from sim.modes import Mode

CSS_SETS = {"primary": 0, "backup": 1, "both": 2}
PLUS_X = np.array([1.0, 0.0, 0.0])   # seed 001: instruments, DSS and the Sun line along +X


def _sun_law(g) -> SunLawParams:
    """The Sun-pointing PD of a spacecraft-file section (SunAcq's or Safehold's); none: zero gains."""
    if g is None:
        return SunLawParams(0.0, 0.0, 1.0, PLUS_X.copy())
    return SunLawParams(g.kp_per_s2, g.kd_per_s, g.sun_error_limit, PLUS_X.copy())


def sun_law_params(sc) -> SunLawParams:
    return _sun_law(sc.fsw.sun_acquisition)


def css_set(sc) -> int:
    g = sc.fsw.sun_acquisition
    return CSS_SETS[g.css_set if g else "both"]


def ace_params(sc) -> AceParams:
    g = sc.fsw.safehold
    dt = sc.timing.control_dt_s
    w = sc.wheels
    tau = g.rate_filter_s if g else 1.0
    return AceParams(g is not None, _sun_law(g), g.k_perp if g else 1.0, g.k_sunline if g else 1.0, dt / (tau + dt),
                     g.h_sunline_ref_Nms if g else 0.0, np.diag(np.array(sc.inertia_B_kgm2, float)).copy(),
                     distribution_matrix(w.axes_B), w.torque_limit_sw_Nm, np.array(w.axes_B, float),
                     w.spin_inertia_kgm2, np.array(sc.sensors.iru_units.channel_axes_B, float),
                     make_css_sun_params(sc), CSS_SETS[g.css_set if g else "primary"],
                     g.heartbeat_cycles if g else 1 << 30, dt)


def thruster_mode_params(sc) -> ThrusterModeParams:
    t, e, dt = sc.thrusters, sc.main_engine, sc.timing.control_dt_s
    u = t.units
    logic = make_thruster_logic_params([x.position_B_m for x in u], [x.direction_B for x in u],
                                       [x.thrust_lbf * LBF_N for x in u], [x.isp_s for x in u], [x.set for x in u],
                                       sc.mass.cm_full_B_m, t.max_pulses_per_cycle, t.pulse_s, dt)
    g = sc.fsw.thruster_control
    gains = ((g.deltav_kp_per_s2, g.deltav_kd_per_s, g.deltah_kp_per_s2, g.deltah_kd_per_s, g.tipoff_kp_factor,
              g.wheel_gain_per_s, g.h_exit_Nms, round(g.settling_burn_s / dt)) if g
             else (0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0))
    f_engine = e.thrust_lbf * LBF_N
    return ThrusterModeParams(
        logic, *gains, np.diag(np.array(sc.inertia_B_kgm2, float)).copy(),
        np.diag(np.array(sc.mass.inertia_empty_B_kgm2, float)).copy(), sc.mass.propellant_kg,
        sc.mass_kg - sc.mass.propellant_kg, f_engine * np.array(e.direction_B, float), f_engine / (e.isp_s * G0_M_S2),
        np.array(sc.wheels.axes_B, float), sc.wheels.spin_inertia_kgm2, sc.wheels.torque_limit_sw_Nm, dt)


def thruster_set_index(sc, name: str) -> int:
    present = [s for s in SET_NAMES if any(u.set == s for u in sc.thrusters.units)]
    if name not in present:
        raise ValueError(f"thruster set {name!r}: this spacecraft's thrusters form the sets {', '.join(present)}")
    return present.index(name)


def fdc_params(sc) -> FdcParams:
    g, dt = sc.fsw.fdc, sc.timing.control_dt_s
    att = np.full(len(Mode), NO_LIMIT)
    rate = np.full(len(Mode), NO_LIMIT)
    if g is None:
        return FdcParams(att, rate, 1 << 30, 1 << 30, acted_row(sc), make_iru_fdc_params(sc.sensors.iru_units.channel_axes_B, dt),
                         make_wheel_fdc_params(sc.wheels.spin_inertia_kgm2, dt, sc.wheels.h_max_Nms))
    for name, v in g.attitude_limit_deg.items():
        att[Mode[name]] = np.radians(v)
    for name, v in g.rate_limit_deg_s.items():
        rate[Mode[name]] = np.radians(v)
    iru = make_iru_fdc_params(sc.sensors.iru_units.channel_axes_B, dt, disagree_rad_s=np.radians(g.iru_disagree_deg_s),
                              persistence_cycles=round(g.iru_persistence_s / dt),
                              window_cycles=round(g.iru_window_s / dt))
    wheel = make_wheel_fdc_params(sc.wheels.spin_inertia_kgm2, dt, sc.wheels.h_max_Nms,
                                  torque_threshold_Nm=g.wheel_torque_threshold_Nm,
                                  persistence_cycles=round(g.wheel_persistence_s / dt))
    return FdcParams(att, rate, max(round(g.limit_persistence_s / dt), 1), max(round(g.limit_persistence_s / dt), 1),
                     acted_row(sc), iru, wheel)


def acted_row(sc) -> int:
    """The command that drove the wheels between the last two samples was
    computed 1 + delay cycles before (sim/loop.py)."""
    return 0 if sc.timing.actuator_delay_cycles == 1 else 1


def forget_fdc_history(f: FdcState) -> None:
    """Clear what the checks remember of past cycles (after Safehold or a
    processor outage, when they did not run): the wheel residuals and last
    speeds, the IRU disagreement filters and isolation window, the limit and
    tracker counters. Failures already declared stay declared."""
    f.limit_count[:] = 0
    f.st_count[:] = 0
    f.cmd_hist[:] = 0.0
    w = f.wheel
    w.residual_Nm[:] = 0.0
    w.count[:] = 0
    w.prev_ok[:] = False
    w.u_before_Nm[:] = 0.0
    i = f.iru
    i.diff_f[:] = 0.0
    i.count_dis[:] = 0
    i.detected[:] = False
    i.count_inv[:] = 0
    i.win_t[:] = -1
    i.slope_age[:] = np.iinfo(np.int64).max // 2   # no verdict from before the gap


def fdc_state(sc, enabled: bool) -> FdcState:
    n = sc.n_wheels
    on = np.full(N_CHECKS, enabled and sc.fsw.fdc is not None, np.bool_)
    on[CHECK_WHEEL] &= sc.sensors.tachometers is not None   # the wheel check reads the tachometers
    return FdcState(on, np.zeros(1, np.int64),
                    np.zeros(len(sc.star_trackers), np.int64), np.full(2, -1, np.int64), np.zeros((2, n)),
                    np.ones(n, np.bool_), make_iru_fdc_state(), make_wheel_fdc_state(n))
