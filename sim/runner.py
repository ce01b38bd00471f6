"""The runner: one run of a scenario, as a pure function of (scenario, seed).

It owns the truth model, the flight software, the command queue and the run's
single random generator, carries sensor records and actuator commands across
the wall (sim/loop.py), stamps command lifecycles, samples telemetry and hands
everything to its listeners. Time is an integer count of control cycles
(cycle_ns each), so rates never drift against each other.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from sim import fault_injection, telemetry, telemetry_fields
from sim.attitude import quat_mul
from sim.calibration import duration_s, expand
from sim.command_queue import CommandQueue
from sim.commands import (
    ACCEPTED,
    COMPLETED,
    EXECUTING,
    FAILED,
    GROUND_PROCEDURES,
    REJECTED,
    WORLD_COMMANDS,
    CommandBase,
    CommandRecord,
    InjectFault,
    Stage,
)
from sim.events import ERROR, INFO, WARNING, Event
from sim.expectations import evaluate
from sim.faults import PROCESSOR_FAULTS, ProcessorReset
from sim.faults import describe as describe_fault
from sim.fsw.flight_software import FlightSoftware
from sim.fsw.snr import SOLAR_POLE_N, snr_quat_from_sun
from sim.fsw.state import EVENT_SLEW_SETTLED
from sim.loop import advance
from sim.modes import Mode
from sim.records import empty_actuator_command, empty_sensor_record
from sim.scenario import Scenario, initial_mode
from sim.spacecraft.definition import Spacecraft
from sim.truth import build, sensor_suite
from sim.truth.plant import apparent_sun_N, set_environment
from sim.uplink import make_uplink

NOISE_BLOCK_CYCLES = 4096  # rows drawn at once; fixed, so draws never depend on segmenting


def truth_snr_quat(ts, tp) -> np.ndarray:
    """The SNR frame at t = 0 from the truth's apparent Sun (for initial
    attitudes given relative to it)."""
    set_environment(ts, tp, 0.0)
    return snr_quat_from_sun(apparent_sun_N(ts, tp), SOLAR_POLE_N)


class Listener:
    """What a run tells the outside world; override what you need."""

    def on_event(self, event: Event) -> None:
        pass

    def on_command(self, rec: CommandRecord, stage: Stage) -> None:
        pass

    def on_telemetry(self, frame: telemetry.Frame) -> None:
        pass


@dataclass
class ExpectationResult:
    description: str
    ok: bool
    measured: str


@dataclass
class RunResult:
    telemetry: dict[str, list] = field(default_factory=dict)
    events: list[Event] = field(default_factory=list)
    commands: list[CommandRecord] = field(default_factory=list)
    expectations: list[ExpectationResult] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return all(e.ok for e in self.expectations)


class Runner:
    def __init__(self, scenario: Scenario, sc: Spacecraft, seed: int | None = None,
                 listeners: list[Listener] | None = None, keep_frames: bool = True):
        """keep_frames: keep every recorded frame for the end-of-run
        expectations (headless runs); a long live run leaves it off and relies
        on its listeners (the archive)."""
        self.scenario, self.sc = scenario, sc
        self.seed = scenario.seed if seed is None else seed
        self.rng = np.random.default_rng(self.seed)
        self.listeners = list(listeners or [])
        self.layout = telemetry.Layout(scenario.recorded_fields(sc), telemetry_fields.names_for(sc))
        self.result = RunResult()
        self._frames: list[telemetry.Frame] = []
        self.keep_frames = keep_frames

        self.cycle_ns = round(sc.timing.control_dt_s * 1e9)
        self.cycle = 0
        self.end_cycle = math.floor(scenario.duration_s * 1e9 / self.cycle_ns + 1e-9)
        self.tlm_every = round(scenario.output.period_s * 1e9 / self.cycle_ns)
        self.delay = sc.timing.actuator_delay_cycles

        init = scenario.initial
        h0 = init.h_wheels_Nms or [0.0] * sc.n_wheels
        world = build.World(scenario.epoch_utc, scenario.duration_s, **scenario.environment.model_dump())
        self.truth_params = build.make_truth_params(sc, world)
        orbit = scenario.orbit or build.default_orbit(sc.name, scenario.epoch_utc)
        r0, v0 = orbit.to_rv()
        propellant = sc.mass.propellant_kg if init.propellant_kg is None else init.propellant_kg

        def truth_state(q_BN):
            return build.make_truth_state(sc, self.truth_params, q_BN, init.omega_BN_B_rad_s, h0, r0, v0, propellant)

        self.truth = truth_state(init.q_BN)
        q_BN = np.array(init.q_BN, float)
        if init.q_BN_frame == "snr":
            q_BN = quat_mul(truth_snr_quat(self.truth, self.truth_params), q_BN)
            self.truth = truth_state(q_BN)
        self.sensors = empty_sensor_record(len(sc.star_trackers), sc.n_wheels, *telemetry_fields.sensor_counts(sc))
        n_thr = len(sc.thrusters.units)
        self.act_applied = empty_actuator_command(sc.n_wheels, n_thr)
        self.act_new = empty_actuator_command(sc.n_wheels, n_thr)
        # The flight software starts knowing the initial attitude and orbit (as if uplinked).
        gci_target = None if init.target == "snr" else (init.target_q_RN or q_BN)
        self.fsw = FlightSoftware(sc, make_uplink(scenario.epoch_utc, r0, v0), initial_mode(scenario), q_BN,
                                  gci_target, propellant_kg=propellant)

        # telemetry samples computed inside a segment by the compiled loop (sim/loop.py)
        n_numbers = len(telemetry_fields.names_for(sc)) - 1   # every field but mode
        self._tlm_rows = np.empty((NOISE_BLOCK_CYCLES // self.tlm_every + 2, n_numbers))
        self._tlm_mode = np.empty(self._tlm_rows.shape[0], np.int64)
        self.n_noise = sensor_suite.noise_per_cycle(self.truth_params.sensors)
        self._noise = np.empty((0, self.n_noise))
        self._noise_row = 0
        self._slew: tuple[CommandRecord, int, float] | None = None  # executing slew, deadline cycle, s allowed
        self._n_transitions = 0
        self._n_fdc = 0
        self._processor_up_cycle: int | None = None   # a processor reset ends here

        self.queue = CommandQueue(self._on_stage)
        self.emit(Event(0.0, INFO, "runner", "run", f"run start: {scenario.name} seed {self.seed}"))
        for t_s, command in scenario.scheduled_commands():
            self.submit(command, "scenario", t_s)

    # -- time ----------------------------------------------------------------
    @property
    def t_s(self) -> float:
        return self.cycle * self.cycle_ns / 1e9

    def cycle_at(self, t_s: float) -> int:
        """First control cycle at or after t_s."""
        return math.ceil(round(t_s * 1e9) / self.cycle_ns)

    # -- commands ------------------------------------------------------------
    def submit(self, command: CommandBase, source: str, t_s: float | None = None) -> CommandRecord:
        due = self.t_s if t_s is None else t_s
        return self.queue.submit(command, source, due, max(self.cycle_at(due), self.cycle), self.t_s)

    def _on_stage(self, rec: CommandRecord, st: Stage) -> None:
        for listener in self.listeners:
            listener.on_command(rec, st)
        severity = WARNING if st.name in (REJECTED, FAILED) else INFO
        msg = f"{rec.describe()} {st.name}" + (f": {st.reason}" if st.reason else "")
        handler = ("simulator" if isinstance(rec.command, WORLD_COMMANDS)
                   else "ground" if isinstance(rec.command, GROUND_PROCEDURES) else "fsw")
        self.emit(Event(st.t_s, severity, "ground" if st.name == "queued" else handler, "command", msg,
                        {"id": rec.id, "stage": st.name}))

    def _processor_fault(self, f, inject: bool) -> None:
        """The main processor is flight hardware, not truth: the runner, which
        holds both sides, switches it (always possible: nothing to refuse)."""
        up = self.fsw.state.proc_up
        if inject:
            up[0] = False
            self._processor_up_cycle = (self.cycle + self.cycle_at(f.duration_s) if isinstance(f, ProcessorReset)
                                        else None)
        elif not up[0]:
            self._processor_up_cycle = None
            self._processor_up()

    def _apply_fault(self, rec: CommandRecord) -> None:
        cmd = rec.command
        inject = isinstance(cmd, InjectFault)
        if isinstance(cmd.fault, PROCESSOR_FAULTS):
            self._processor_fault(cmd.fault, inject)
            reason = ""
        else:
            reason = fault_injection.apply(cmd.fault, self.truth, active=inject)
        if reason:
            self.queue.stamp(rec, REJECTED, self.t_s, reason)
            return
        for stage in (ACCEPTED, EXECUTING, COMPLETED):
            self.queue.stamp(rec, stage, self.t_s)
        verb = "injected" if inject else "cleared"
        self.emit(Event(self.t_s, WARNING if inject else INFO, "ground", "fault",
                        f"fault {verb}: {describe_fault(cmd.fault)}", {"command": rec.id}))

    def _start_procedure(self, rec: CommandRecord) -> None:
        """A ground procedure (a calibration): legal now, it becomes its
        time-tagged commands from this cycle, each with its own lifecycle."""
        reason = self.fsw.check(rec.command)
        if reason:
            self.queue.stamp(rec, REJECTED, self.t_s, reason)
            return
        steps = expand(rec.command.maneuver, self.t_s)
        for stage in (ACCEPTED, EXECUTING):
            self.queue.stamp(rec, stage, self.t_s)
        for t_s, command in steps:
            self.submit(command, f"calibration:{rec.id}", t_s)
        self.queue.stamp(rec, COMPLETED, self.t_s)
        m = rec.command.maneuver
        self.emit(Event(self.t_s, INFO, "ground", "calibration",
                        f"calibration {m.maneuver}: {len(steps)} commands queued, {duration_s(m):.0f} s",
                        {"command": rec.id, "n_commands": len(steps)}))

    def _deliver_due_commands(self) -> None:
        for rec in self.queue.pop_due(self.cycle):
            if isinstance(rec.command, WORLD_COMMANDS):
                self._apply_fault(rec)
                continue
            if isinstance(rec.command, GROUND_PROCEDURES):
                self._start_procedure(rec)
                continue
            outcome = self.fsw.execute(rec.command)
            if not outcome.accepted:
                self.queue.stamp(rec, REJECTED, self.t_s, outcome.reason)
                continue
            self.queue.stamp(rec, ACCEPTED, self.t_s)
            self.queue.stamp(rec, EXECUTING, self.t_s)
            self._emit_transitions()
            if outcome.completed:
                self.queue.stamp(rec, COMPLETED, self.t_s)
            elif outcome.watch_slew:
                self._start_slew(rec)

    def _start_slew(self, rec: CommandRecord) -> None:
        if self._slew is not None:
            self.queue.stamp(self._slew[0], FAILED, self.t_s, f"superseded by command {rec.id}")
        allowed_s = self.fsw.slew_time_allowed_s()
        self._slew = (rec, self.cycle + self.cycle_at(allowed_s), allowed_s)

    def _on_fsw_event(self, code: int) -> None:
        if code == EVENT_SLEW_SETTLED:
            if self._slew is not None:
                self.queue.stamp(self._slew[0], COMPLETED, self.t_s)
                self._slew = None
            return
        self.fsw.on_event(code)
        self._emit_transitions()

    def _emit_transitions(self) -> None:
        while self._n_transitions < len(self.fsw.transitions):
            tr = self.fsw.transitions[self._n_transitions]
            self._n_transitions += 1
            self.emit(Event(self.t_s, WARNING if tr.cause == "fdc" else INFO, "fsw", "mode", tr.describe(),
                            {"from": tr.old.name, "to": tr.new.name, "cause": tr.cause}))
        while self._n_fdc < len(self.fsw.fdc_actions):
            a = self.fsw.fdc_actions[self._n_fdc]
            self._n_fdc += 1
            self.emit(Event(self.t_s, WARNING, "fdc", "fdc", f"FDC {a.check}: {a.trigger}; response: {a.response}",
                            {"check": a.check, "trigger": a.trigger, "response": a.response}))

    def _processor_return(self) -> None:
        """A reset ends: before this cycle's commands, so they find the processor up."""
        if self._processor_up_cycle is not None and self.cycle >= self._processor_up_cycle:
            self._processor_up_cycle = None
            self._processor_up()

    def _processor_up(self) -> None:
        self.fsw.resume(self.cycle)
        self.fsw.state.proc_up[0] = True
        self.emit(Event(self.t_s, WARNING, "fsw", "fault",
                        f"main processor back up; mode {self.fsw.mode.name}"))

    def _check_deadlines(self) -> None:
        if self._slew is not None and self.cycle >= self._slew[1]:
            self.fsw.stop_watching_slew()
            self.queue.stamp(self._slew[0], FAILED, self.t_s,
                             f"not inside the integral torque box within {self._slew[2]:.0f} s")
            self._slew = None

    # -- output --------------------------------------------------------------
    def emit(self, event: Event) -> None:
        self.result.events.append(event)
        for listener in self.listeners:
            listener.on_event(event)

    def frame(self) -> telemetry.Frame:
        """The recorded fields now."""
        mode, numbers = telemetry_fields.sample(self.t_s, self.truth, self.truth_params, self.fsw.state, self.sensors,
                                         self.act_applied)
        return telemetry.Frame(mode, numbers[self.layout.index], self.layout)

    def _record(self) -> None:
        self._emit_frame(self.frame())

    def _emit_frame(self, frame: telemetry.Frame) -> None:
        if self.keep_frames:
            self._frames.append(frame)
        for listener in self.listeners:
            listener.on_telemetry(frame)

    # -- stepping ------------------------------------------------------------
    def _noise_rows(self) -> int:
        if self._noise_row == self._noise.shape[0]:
            self._noise = self.rng.standard_normal((NOISE_BLOCK_CYCLES, self.n_noise))
            self._noise_row = 0
        return self._noise.shape[0] - self._noise_row

    def _next_stop(self, limit: int) -> int:
        stops = [limit]
        due = self.queue.next_due_cycle()
        if due is not None:
            stops.append(due)
        if self._slew is not None:
            stops.append(self._slew[1])
        if self._processor_up_cycle is not None:
            stops.append(self._processor_up_cycle)
        return max(min(stops), self.cycle + 1)

    def advance_to(self, target_cycle: int) -> None:
        """Run control cycles until `target_cycle` (capped at the run's end)."""
        target_cycle = min(target_cycle, self.end_cycle)
        while self.cycle < target_cycle:
            self._processor_return()
            self._deliver_due_commands()
            self._check_deadlines()
            if self.cycle % self.tlm_every == 0:
                self._record()
            n = min(self._next_stop(target_cycle) - self.cycle, self._noise_rows())
            ran, code, rows = advance(n, self.cycle, self.cycle_ns / 1e9, self.truth, self.truth_params, self._noise,
                                self._noise_row, self.sensors, self.fsw.state, self.fsw.params, self.fsw.ace,
                                self.fsw.ace_params, self.act_applied, self.act_new, self.delay, self.cycle_ns,
                                self.tlm_every, self._tlm_rows, self._tlm_mode)
            for i in range(rows):
                self._emit_frame(telemetry.Frame(Mode(int(self._tlm_mode[i])).name,
                                                 self._tlm_rows[i][self.layout.index], self.layout))
            self.cycle += ran
            self._noise_row += ran
            if code:
                self._on_fsw_event(code)

    def run(self, progress: Callable[[float], None] | None = None) -> RunResult:
        chunk = max(self.tlm_every, self.end_cycle // 200)
        while self.cycle < self.end_cycle:
            self.advance_to(self.cycle + chunk)
            if progress:
                progress(self.t_s)
        self._deliver_due_commands()  # commands tagged at the very end still get their answer
        if self.cycle % self.tlm_every == 0:
            self._record()
        self._finish()
        return self.result

    def _finish(self) -> None:
        for rec in self.queue.records:
            if not rec.done:
                self.queue.stamp(rec, FAILED, self.t_s, "run ended before completion")
        self.result.telemetry = telemetry.columns(self._frames, self.layout)
        t = np.asarray(self.result.telemetry["t_s"], float)
        for e in self.scenario.expect:
            ok, measured = evaluate(e, t, self.result.telemetry[e.field])
            self.result.expectations.append(ExpectationResult(e.describe(), ok, measured))
            self.emit(Event(self.t_s, INFO if ok else ERROR, "runner", "expectation",
                            f"{'PASS' if ok else 'FAIL'} {e.describe()}: {measured}"))
        self.result.commands = list(self.queue.records)
        self.emit(Event(self.t_s, INFO, "runner", "run", f"run end: {self.scenario.name}"))
