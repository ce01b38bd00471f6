"""The flight software's Python side: its state and parameters, the mode, and
ground-command handling (legality, execution, completion).

The per-cycle math is in cycle.py; this class touches it only through the
FswState arrays, between cycles.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sim.commands import CommandBase, ResetIntegrator, SetTargetQuaternion
from sim.fsw import cycle
from sim.fsw.distribution import distribution_matrix
from sim.fsw.estimation import SOURCE_IRU, SOURCE_STAR_TRACKER
from sim.fsw.pid import DISABLE_METHODS, PidParams
from sim.modes import Mode
from sim.spacecraft.definition import Spacecraft


@dataclass
class Outcome:
    """What the flight software made of a command at its cycle."""
    accepted: bool
    reason: str = ""
    completed: bool = False   # done within the cycle (else: executing)


def make_fsw_params(sc: Spacecraft) -> cycle.FswParams:
    g = sc.fsw.inertial
    pid = PidParams(np.array(sc.inertia_B_kgm2, float), g.kp_per_s2, g.kd_per_s, g.ki_per_s3,
                    g.integrator_limit_rad_s, g.box_theta_lim_rad, g.box_omega_lim_rad_s,
                    g.attitude_limit_rad, sc.timing.control_dt_s, g.box_option, g.box_per_axis,
                    DISABLE_METHODS[g.disable], g.torque_sat_Nm)
    source = SOURCE_STAR_TRACKER if sc.fsw.attitude_source == "star_tracker" else SOURCE_IRU
    k = sc.fsw.star_tracker
    return cycle.FswParams(pid, distribution_matrix(sc.wheels.axes_B), sc.wheels.torque_limit_sw_Nm, source, k,
                           np.array(sc.star_trackers[k].q_BS, float),
                           np.array(sc.sensors.iru_units.channel_axes_B, float), sc.timing.control_dt_s)


def make_fsw_state(mode: Mode, q_est_BN, q_RN) -> cycle.FswState:
    return cycle.FswState(
        mode=np.array([int(mode)], np.int64), q_est_BN=np.array(q_est_BN, float), q_RN=np.array(q_RN, float),
        integral=np.zeros(3), theta_e=np.zeros(3), omega_e=np.zeros(3), torque_cmd_B=np.zeros(3),
        torque_undelivered_B=np.zeros(3), flags=np.zeros(cycle.N_FLAGS), rate_B=np.zeros(3),
        int_active=np.zeros(3, dtype=np.bool_), torque_int_B=np.zeros(3), iru_ch_use=np.ones(6, dtype=np.bool_))


class FlightSoftware:
    def __init__(self, sc: Spacecraft, mode: Mode, q_est_BN, q_RN):
        self.params = make_fsw_params(sc)
        self.state = make_fsw_state(mode, q_est_BN, q_RN)
        self.slew_timeout_s = sc.fsw.slew_timeout_s

    @property
    def mode(self) -> Mode:
        return Mode(int(self.state.mode[0]))

    def check(self, cmd: CommandBase) -> str:
        """Why the command is illegal now, or "" when it is legal."""
        if self.mode not in cmd.legal_modes:
            legal = ", ".join(m.name for m in cmd.legal_modes)
            return f"{cmd.type} is not legal in {self.mode.name}; legal in: {legal}"
        return ""

    def execute(self, cmd: CommandBase) -> Outcome:
        reason = self.check(cmd)
        if reason:
            return Outcome(False, reason)
        if isinstance(cmd, SetTargetQuaternion):
            self.state.q_RN[:] = cmd.q_RN
            self.state.flags[cycle.F_WATCH_SLEW] = 1.0
            return Outcome(True)
        if isinstance(cmd, ResetIntegrator):
            self.state.integral[:] = 0.0
            return Outcome(True, completed=True)
        raise TypeError(f"flight software has no handler for {cmd.type}")  # a programming error, not client input

    def stop_watching_slew(self) -> None:
        self.state.flags[cycle.F_WATCH_SLEW] = 0.0
