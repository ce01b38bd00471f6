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
    SelectThrusterSet,
    SetAttitudeOption,
    SetDeltaVTarget,
    SetFdcCheck,
    SetMode,
    SetTargetQuaternion,
    SetTargetSnr,
    StartDeltaH,
    StartDeltaV,
)
from sim.fsw import state as st
from sim.fsw.build import ATTITUDE_OPTIONS, make_fsw_params, make_fsw_state, target_kind
from sim.fsw.build_modes import ace_params, forget_fdc_history, thruster_set_index
from sim.fsw.ephemeris_task import ephemeris_task_run
from sim.fsw.fdc import CHECK_NAMES
from sim.fsw.mode_machine import FdcAction, ModeMachine, Transition
from sim.fsw.safehold import make_ace_state
from sim.fsw.snr import TARGET_GCI
from sim.fsw.targeting import update_target
from sim.modes import GROUND, Mode
from sim.spacecraft.definition import Spacecraft


@dataclass
class Outcome:
    """What the flight software made of a command at its cycle."""
    accepted: bool
    reason: str = ""
    completed: bool = False   # done within the cycle (else: executing)
    watch_slew: bool = False  # a slew started: complete once inside the integral torque box


class FlightSoftware:
    def __init__(self, sc: Spacecraft, uplink, mode: Mode, q_est_BN, q_RN_gci=None,
                 dq_RS=(1.0, 0.0, 0.0, 0.0), propellant_kg=None):
        self.sc = sc
        self.params = make_fsw_params(sc, uplink)
        self.state = make_fsw_state(sc, self.params, uplink, mode, q_est_BN, q_RN_gci, dq_RS, propellant_kg)
        # the ACE: its own unit, beside the main processor (safehold.py)
        self.ace_params = ace_params(sc)
        self.ace = make_ace_state()
        self.ace.in_control[0] = mode == Mode.SAFEHOLD
        self.machine = ModeMachine(sc, self.params, self.state, self.ace)
        g = sc.fsw.inertial
        self.slew_rate_rad_s = g.kp_per_s2 / g.kd_per_s * g.attitude_limit_rad   # the limiter's steady slew rate
        self.slew_allowance_s = sc.fsw.slew_allowance_s

    @property
    def mode(self) -> Mode:
        return Mode(int(self.state.mode[0]))

    # -- mode machine (mode_machine.py) ------------------------------------------
    def transition(self, new: Mode, cause: str, why: str, setup=None) -> str:
        return self.machine.transition(new, cause, why, setup)

    def on_event(self, code: int) -> None:
        self.machine.on_event(code)

    @property
    def transitions(self) -> list[Transition]:
        return self.machine.transitions

    @property
    def fdc_actions(self) -> list[FdcAction]:
        return self.machine.fdc_actions

    # -- commands --------------------------------------------------------------
    def check(self, cmd: CommandBase) -> str:
        """Why the command is illegal now, or "" when it is legal."""
        if not self.state.proc_up[0]:
            return "the main processor is down: the ACE holds Safehold until it is back"
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
        return self._check_thruster_args(cmd)

    def _check_thruster_args(self, cmd) -> str:
        sets = [x.set for x in self.sc.thrusters.units]
        args = cmd.deltav if isinstance(cmd, SetMode) else cmd
        name = getattr(args, "thruster_set", None)
        if name is not None and name not in sets:
            return f"thruster_set {name}: this spacecraft has {', '.join(sorted(set(sets)))}"
        args = cmd.deltah if isinstance(cmd, SetMode) else cmd
        for field in ("wheel_momentum_Nms", "wheel_speed_rpm"):
            v = getattr(args, field, None)
            if v is not None and len(v) != self.sc.n_wheels:
                return f"{field}: {len(v)} values given, this spacecraft has {self.sc.n_wheels} wheels"
        h = self._deltah_targets_Nms(args)
        if np.abs(h).max() > self.sc.wheels.h_max_Nms:
            return f"wheel targets beyond the wheels' {self.sc.wheels.h_max_Nms:g} N m s capacity"
        if isinstance(cmd, SetDeltaVTarget):
            return self._check_retarget(cmd)
        return ""

    def _check_retarget(self, cmd) -> str:
        """A retarget the DeltaV attitude limit would take for a failure is refused."""
        limits = self.sc.fsw.fdc.attitude_limit_deg if self.sc.fsw.fdc else {}
        angle = np.degrees(rotation_angle(error_quat(np.array(cmd.q_RN, float), self.state.thr.q_hold_BN)))
        if "DELTAV" in limits and angle >= limits["DELTAV"]:
            return (f"q_RN is {angle:.1f} deg from the current burn target, beyond the DeltaV attitude limit "
                    f"{limits['DELTAV']:g} deg (FDC would abandon the burn); retarget in smaller steps")
        return ""

    def execute(self, cmd: CommandBase) -> Outcome:
        reason = self.check(cmd)
        if reason:
            return Outcome(False, reason)
        s = self.state
        if isinstance(cmd, (SetMode, StartDeltaH, StartDeltaV)):
            return self._mode_command(cmd)
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
        elif isinstance(cmd, SetDeltaVTarget):
            s.thr.q_hold_BN[:] = cmd.q_RN
            s.fdc.limit_count[0] = 0
        elif isinstance(cmd, SelectThrusterSet):
            s.thr.thr_set[0] = thruster_set_index(self.sc, cmd.thruster_set)
            s.thr.carry[:] = 0.0
        elif isinstance(cmd, SetFdcCheck):
            s.fdc.enabled[CHECK_NAMES.index(cmd.check)] = cmd.enabled
        else:
            raise TypeError(f"flight software has no handler for {cmd.type}")  # a programming error, not client input
        return Outcome(True, completed=True)

    def _mode_command(self, cmd) -> Outcome:
        """set_mode, start_deltah, start_deltav: one path into the mode machine."""
        if isinstance(cmd, StartDeltaH):
            new, args = Mode.DELTAH, cmd
        elif isinstance(cmd, StartDeltaV):
            new, args = Mode.DELTAV, cmd
        else:
            new, args = Mode[cmd.mode], cmd.deltav or cmd.deltah
        setup = None
        if new == Mode.DELTAH:
            setup = self._deltah_setup(args)
        elif new == Mode.DELTAV:
            setup = self._deltav_setup(args)
        reason = self.transition(new, GROUND, f"command {cmd.type}", setup)
        return Outcome(not reason, reason, completed=not reason)

    def _deltah_targets_Nms(self, args) -> np.ndarray:
        """DeltaH's wheel momentum targets from start_deltah / set_mode deltah (zero when not given)."""
        if getattr(args, "wheel_momentum_Nms", None) is not None:
            return np.array(args.wheel_momentum_Nms, float)
        if getattr(args, "wheel_speed_rpm", None) is not None:
            return np.array(args.wheel_speed_rpm, float) * (np.pi / 30.0) * self.sc.wheels.spin_inertia_kgm2
        return np.zeros(self.sc.n_wheels)

    def _deltah_setup(self, args):
        h = self._deltah_targets_Nms(args)
        tipoff = bool(args.tipoff) if args is not None else False
        t = self.state.thr

        def setup():
            t.h_target_Nms[:] = h
            t.tipoff[0] = tipoff
        return setup

    def _deltav_setup(self, args):
        t, dt = self.state.thr, self.sc.timing.control_dt_s
        set_index = thruster_set_index(self.sc, args.thruster_set)

        def setup():
            t.q_hold_BN[:] = args.target_q_RN
            t.burn_cycles[0] = round(args.duration_s / dt)
            t.burn_k[0] = 0
            t.main_engine[0] = args.main_engine
            t.thr_set[0] = set_index
            t.carry[:] = 0.0
        return setup

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

    def resume(self, cycle: int) -> None:
        """The main processor is back after an outage up to `cycle`: its clock
        and ephemeris catch up (the spacecraft clock kept time), its checks
        forget what they saw before. The ACE keeps Safehold if it took over."""
        s, p = self.state, self.params
        if p.eph_every > 0:
            k0 = int(s.cycle[0])
            first = (k0 // p.eph_every + 1) * p.eph_every   # the first sample cycle the processor missed
            n = max(0, (cycle - 1 - first) // p.eph_every + 1) if cycle > first else 0
            ephemeris_task_run(p.eph, s.eph, n)
            update_target(s, p)
        s.cycle[0] = cycle
        forget_fdc_history(s.fdc)

    def slew_time_allowed_s(self) -> float:
        """For the slew just commanded: its angle at the limited rate plus the allowance."""
        angle = rotation_angle(error_quat(self.state.q_RN, self.state.q_est_BN))
        return angle / self.slew_rate_rad_s + self.slew_allowance_s

    def stop_watching_slew(self) -> None:
        self.state.flags[st.F_WATCH_SLEW] = 0.0
