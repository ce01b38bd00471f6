"""The flight software's Python side: ground commands (legality, execution)
and the mode machine (transitions and what each resets).

The per-cycle math is in cycle.py; this class touches it only through the
FswState arrays, between cycles.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sim.attitude import error_quat, rotation_angle
from sim.commands import (
    CommandBase,
    EnableScienceAutonomy,
    ResetIntegrator,
    SelectCgt,
    SetAttitudeOption,
    SetMode,
    SetTargetQuaternion,
    SetTargetSnr,
)
from sim.fsw import state as st
from sim.fsw.build import ATTITUDE_OPTIONS, make_fsw_params, make_fsw_state, target_kind
from sim.fsw.snr import TARGET_GCI
from sim.fsw.targeting import update_target
from sim.fsw.torque_filter import BANK_INERTIAL, BANK_SCIENCE, preload_torque_filter
from sim.modes import AUTONOMOUS, FDC, GROUND, Mode, refusal
from sim.spacecraft.definition import Spacecraft


@dataclass
class Outcome:
    """What the flight software made of a command at its cycle."""
    accepted: bool
    reason: str = ""
    completed: bool = False   # done within the cycle (else: executing)
    watch_slew: bool = False  # a slew started: complete once inside the integral torque box


@dataclass
class Transition:
    old: Mode
    new: Mode
    cause: str      # modes.GROUND | FDC | AUTONOMOUS
    why: str

    def describe(self) -> str:
        return f"mode {self.old.name} -> {self.new.name} ({self.cause}: {self.why})"


class FlightSoftware:
    def __init__(self, sc: Spacecraft, uplink, mode: Mode, q_est_BN, q_RN_gci=None,
                 dq_RS=(1.0, 0.0, 0.0, 0.0)):
        self.sc = sc
        self.params = make_fsw_params(sc, uplink)
        self.state = make_fsw_state(sc, self.params, uplink, mode, q_est_BN, q_RN_gci, dq_RS)
        g = sc.fsw.inertial
        self.slew_rate_rad_s = g.kp_per_s2 / g.kd_per_s * g.attitude_limit_rad   # the limiter's steady slew rate
        self.slew_allowance_s = sc.fsw.slew_allowance_s
        self.transitions: list[Transition] = []

    @property
    def mode(self) -> Mode:
        return Mode(int(self.state.mode[0]))

    # -- mode machine ----------------------------------------------------------
    def transition(self, new: Mode, cause: str, why: str) -> str:
        """Take the transition, or return why it is refused."""
        reason = refusal(self.mode, new, cause)
        if reason:
            return reason
        if new == Mode.SCIENCE and self.state.flags[st.F_CGT_OK] == 0.0:
            return f"the controlling guide telescope {int(self.state.cgt[0]) + 1} is not valid and in its fine range"
        s = self.state
        old = self.mode
        # The integral carries across Inertial <-> Science (seed 000); the new
        # bank starts from the steady state of the held integral torque, so the
        # switch of filters puts no step into the torque command.
        if new == Mode.INERTIAL:
            s.autonomy[0] = False   # seed 001: "disabled on entry into Inertial mode to prevent ... switching back and forth"
            preload_torque_filter(s.tf, self.params.tf, BANK_INERTIAL, s.torque_int_B)
        elif new == Mode.SCIENCE:
            preload_torque_filter(s.tf, self.params.tf, BANK_SCIENCE, s.torque_int_B)
        s.mode[0] = int(new)
        self.transitions.append(Transition(old, new, cause, why))
        return ""

    def on_event(self, code: int) -> Transition | None:
        """The mode machine's answer to a cycle event (other codes: the runner's)."""
        if code == st.EVENT_SCIENCE_ACQUIRED and not self.transition(
                Mode.SCIENCE, AUTONOMOUS, "controlling guide telescope in its acquisition range"):
            return self.transitions[-1]
        if code == st.EVENT_CGT_LOST and not self.transition(
                Mode.INERTIAL, FDC, "controlling guide telescope invalid or out of its fine range"):
            return self.transitions[-1]
        return None

    # -- commands --------------------------------------------------------------
    def check(self, cmd: CommandBase) -> str:
        """Why the command is illegal now, or "" when it is legal."""
        if self.mode not in cmd.legal_modes:
            legal = ", ".join(m.name for m in cmd.legal_modes)
            return f"{cmd.type} is not legal in {self.mode.name}; legal in: {legal}"
        if isinstance(cmd, SetAttitudeOption) and cmd.star_tracker > len(self.sc.star_trackers):
            return f"star_tracker {cmd.star_tracker}: this spacecraft has {len(self.sc.star_trackers)} tracker(s)"
        if isinstance(cmd, SetTargetSnr) and self.sc.fsw.ephemeris is None:
            return "set_target_snr needs the on-board ephemeris, and this spacecraft has none (fsw.ephemeris)"
        n_gt = len(self.sc.sensors.guide_telescopes.units) if self.sc.sensors.guide_telescopes else 0
        if isinstance(cmd, SelectCgt) and cmd.cgt > n_gt:
            return f"cgt {cmd.cgt}: this spacecraft has {n_gt} guide telescope(s)"
        return ""

    def execute(self, cmd: CommandBase) -> Outcome:
        reason = self.check(cmd)
        if reason:
            return Outcome(False, reason)
        s = self.state
        if isinstance(cmd, SetMode):
            reason = self.transition(Mode[cmd.mode], GROUND, f"command {cmd.type}")
            return Outcome(not reason, reason, completed=not reason)
        if isinstance(cmd, (SetTargetQuaternion, SetTargetSnr)):
            self._set_target(cmd)
            return Outcome(True, watch_slew=True)
        if isinstance(cmd, ResetIntegrator):
            s.integral[:] = 0.0
        elif isinstance(cmd, SetAttitudeOption):
            s.att_option[0] = ATTITUDE_OPTIONS[cmd.option]
            s.st_select[0] = cmd.star_tracker - 1
        elif isinstance(cmd, EnableScienceAutonomy):
            s.autonomy[0] = cmd.enabled
        elif isinstance(cmd, SelectCgt):
            s.cgt[0] = cmd.cgt - 1
        else:
            raise TypeError(f"flight software has no handler for {cmd.type}")  # a programming error, not client input
        return Outcome(True, completed=True)

    def _set_target(self, cmd) -> None:
        s = self.state
        if isinstance(cmd, SetTargetQuaternion):
            s.q_RN_cmd[:] = cmd.q_RN
            s.target[0] = TARGET_GCI
        else:
            dq = np.array(cmd.delta_q, float)
            s.dq_RS[:] = dq if dq[0] >= 0.0 else -dq
            s.target[0] = target_kind(s.dq_RS)
        update_target(s, self.params)
        s.flags[st.F_WATCH_SLEW] = 1.0

    def slew_time_allowed_s(self) -> float:
        """For the slew just commanded: its angle at the limited rate plus the allowance."""
        angle = rotation_angle(error_quat(self.state.q_RN, self.state.q_est_BN))
        return angle / self.slew_rate_rad_s + self.slew_allowance_s

    def stop_watching_slew(self) -> None:
        self.state.flags[st.F_WATCH_SLEW] = 0.0
