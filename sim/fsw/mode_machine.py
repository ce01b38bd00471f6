"""The mode machine: which transitions are taken, what each one resets, and
the answers to the cycle's events (autonomous exits, FDC responses).

The table of allowed edges is sim/modes.py (docs/modes.md quotes the seed
for each); this module adds what the table cannot say: whether the mode can
be flown at all (its spacecraft-file section), the CGT for Science, DeltaH's
return to the mode it came from, the processor being up to leave Safehold.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from sim.fsw import state as st
from sim.fsw.build_modes import forget_fdc_history
from sim.fsw.distribution import distribution_matrix
from sim.fsw.fdc import (
    CHECK_IRU,
    CHECK_LIMITS,
    CHECK_NAMES,
    CHECK_STAR_TRACKER,
    CHECK_WHEEL,
)
from sim.fsw.snr import TARGET_GCI, TARGET_SNR
from sim.fsw.targeting import update_target
from sim.fsw.torque_filter import BANK_INERTIAL, BANK_SCIENCE, preload_torque_filter
from sim.modes import AUTONOMOUS, CAUSES, FDC, Mode, refusal

PID_MODES = (Mode.INERTIAL, Mode.SCIENCE)
CAUSE_CODES = {c: i for i, c in enumerate(CAUSES)}
NEEDS_SECTION = {Mode.SUNACQ: "sun_acquisition", Mode.SAFEHOLD: "safehold", Mode.DELTAH: "thruster_control",
                 Mode.DELTAV: "thruster_control"}


@dataclass
class Transition:
    old: Mode
    new: Mode
    cause: str      # modes.GROUND | FDC | AUTONOMOUS
    why: str

    def describe(self) -> str:
        return f"mode {self.old.name} -> {self.new.name} ({self.cause}: {self.why})"


@dataclass
class FdcAction:
    check: str      # fdc.CHECK_NAMES
    trigger: str
    response: str


class ModeMachine:
    def __init__(self, sc, params, state, ace):
        self.sc, self.p, self.s, self.ace = sc, params, state, ace
        self.transitions: list[Transition] = []
        self.fdc_actions: list[FdcAction] = []
        self.deltah_entry: Mode | None = None

    @property
    def mode(self) -> Mode:
        return Mode(int(self.s.mode[0]))

    def refusal(self, new: Mode, cause: str) -> str:
        old = self.mode
        reason = refusal(old, new, cause)
        if reason:
            return reason
        section = NEEDS_SECTION.get(new)
        if section and getattr(self.sc.fsw, section) is None:
            return f"{new.name} needs fsw.{section} in the spacecraft file, and {self.sc.name} has none"
        if new == Mode.SCIENCE and self.s.flags[st.F_CGT_OK] == 0.0:
            return f"the controlling guide telescope {int(self.s.cgt[0]) + 1} is not valid and in its fine range"
        if old == Mode.DELTAH and cause == AUTONOMOUS and new != self.deltah_entry:
            return f"DELTAH returns to the mode it was entered from ({self.deltah_entry.name})"
        if old == Mode.SAFEHOLD and not self.s.proc_up[0]:
            return "the main processor is down: the ACE keeps Safehold"
        return ""

    def transition(self, new: Mode, cause: str, why: str, setup: Callable[[], None] | None = None) -> str:
        """Take the transition (running `setup` first, once it is legal), or
        return why it is refused; a refusal changes nothing."""
        reason = self.refusal(new, cause)
        if reason:
            return reason
        if setup:
            setup()
        self._switch(new, cause, why)
        return ""

    def _switch(self, new: Mode, cause: str, why: str) -> None:
        old = self.mode
        self._exit(old)
        self._enter(new, old)
        self.s.mode[0] = int(new)
        self.s.mode_info[:] = (int(old), CAUSE_CODES[cause])
        self.s.fdc.limit_count[0] = 0
        self.transitions.append(Transition(old, new, cause, why))

    def _exit(self, old: Mode) -> None:
        s = self.s
        if old == Mode.SAFEHOLD:
            self.ace.in_control[0] = False
            forget_fdc_history(s.fdc)   # the main processor's checks did not run: their memory is stale
        if old in (Mode.DELTAH, Mode.DELTAV):
            s.thr.carry[:] = 0.0

    def _enter(self, new: Mode, old: Mode) -> None:
        s, p = self.s, self.p
        if new == Mode.INERTIAL:
            s.autonomy[0] = False   # seed 001: "disabled on entry into Inertial mode to prevent ... switching back and forth"
            if old not in PID_MODES:
                self._fresh_pid(old)
            preload_torque_filter(s.tf, p.tf, BANK_INERTIAL, s.torque_int_B)
        elif new == Mode.SCIENCE:
            # The integral carries across Inertial <-> Science (seed 000); the new
            # bank starts from the steady state of the held integral torque.
            preload_torque_filter(s.tf, p.tf, BANK_SCIENCE, s.torque_int_B)
        elif new == Mode.DELTAH:
            s.thr.carry[:] = 0.0
            self.deltah_entry = old
            s.thr.q_hold_BN[:] = s.q_est_BN   # seed 001: "the estimated spacecraft attitude upon DeltaH mode entry"
        elif new == Mode.SAFEHOLD:
            self.ace.in_control[0] = True

    def _fresh_pid(self, old: Mode) -> None:
        """Into Inertial from a mode without the PID: no integral to carry (it
        belonged to another momentum state). From DeltaV: hold the burn
        attitude; from SunAcq or Safehold: the default SNR target (seed 001
        "Inertial mode": "by default, is the on-board calculated SNR frame")."""
        s = self.s
        s.integral[:] = 0.0
        s.int_active[:] = False
        s.torque_int_B[:] = 0.0
        s.torque_cmd_B[:] = 0.0          # the last mode's torques say nothing of the PID's
        s.torque_undelivered_B[:] = 0.0
        if old == Mode.DELTAV:
            s.q_RN_cmd[:] = s.thr.q_hold_BN
            s.target[0] = TARGET_GCI
        elif old in (Mode.SUNACQ, Mode.SAFEHOLD) and self.sc.fsw.ephemeris is not None:
            s.dq_RS[:] = (1.0, 0.0, 0.0, 0.0)
            s.target[0] = TARGET_SNR
        update_target(s, self.p)

    # -- events -----------------------------------------------------------------
    def on_event(self, code: int) -> None:
        handlers = {
            st.EVENT_SCIENCE_ACQUIRED: lambda: self.transition(
                Mode.SCIENCE, AUTONOMOUS, "controlling guide telescope in its acquisition range"),
            st.EVENT_CGT_LOST: lambda: self.transition(
                Mode.INERTIAL, FDC, "controlling guide telescope invalid or out of its fine range"),
            st.EVENT_BURN_DONE: lambda: self.transition(Mode.INERTIAL, AUTONOMOUS, "burn time reached"),
            st.EVENT_DELTAH_DONE: lambda: self.transition(
                self.deltah_entry, AUTONOMOUS,
                f"system momentum within {self.sc.fsw.thruster_control.h_exit_Nms:g} N m s of the target"),
            st.EVENT_FDC: self._on_fdc,
            st.EVENT_ACE_TAKEOVER: self._on_takeover,
        }
        if code in handlers:
            handlers[code]()
        if self.s.fdc.last[0] >= 0:   # an FDC check fired on the same cycle as another event
            self._on_fdc()

    def _on_takeover(self) -> None:
        if self.mode == Mode.SAFEHOLD:
            return
        # no refusal check: the ACE has the wheels already, whatever the table says
        self._switch(Mode.SAFEHOLD, FDC, "ACE: main processor heartbeat lost")
        self.fdc_actions.append(FdcAction("processor", "main processor heartbeat lost", "ACE Safehold"))

    def _on_fdc(self) -> None:
        check, unit = (int(x) for x in self.s.fdc.last)
        if check < 0:
            return
        self.s.fdc.last[:] = -1   # handled (the cycle sets it again when a check fires)
        name = CHECK_NAMES[check]
        if check == CHECK_IRU:
            self.fdc_actions.append(FdcAction(name, f"IRU channel {unit + 1} failed",
                                              f"rate selection without channel {unit + 1}"))
        elif check == CHECK_WHEEL:
            self._drop_wheel(unit)
        elif check == CHECK_STAR_TRACKER:
            self.fdc_actions.append(FdcAction(name, f"star tracker {unit + 1} lost",
                                              "Kalman filter continues on the remaining sensors"))
        elif check == CHECK_LIMITS:
            mode = Mode(unit)
            target = Mode[self.sc.fsw.fdc.limit_response[mode.name]]
            why = f"attitude or rate limit exceeded in {mode.name}"
            reason = self.transition(target, FDC, why)
            self.fdc_actions.append(FdcAction(name, why, f"to {target.name}" if not reason else f"none: {reason}"))

    def _drop_wheel(self, wheel: int) -> None:
        axes = np.array(self.sc.wheels.axes_B, float)
        ok = self.s.fdc.wheel_ok
        if np.count_nonzero(ok) < 3:   # two wheels cannot hold three axes: keep the last distribution
            self.fdc_actions.append(FdcAction("wheel", f"wheel {wheel + 1} failed",
                                              "none: fewer than three wheels left (command Safehold or DeltaH)"))
            return
        dist = np.zeros_like(self.p.dist)
        dist[ok] = distribution_matrix(axes[ok])
        self.p.dist[:] = dist
        self.fdc_actions.append(FdcAction("wheel", f"wheel {wheel + 1} failed",
                                          f"distribution recomputed for wheels "
                                          f"{', '.join(str(i + 1) for i in np.flatnonzero(ok))}"))
