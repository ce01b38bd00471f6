"""One live run: the Runner, its archive recorder, its limits and the
console's thread-safe view of it (command history, events).

Everything here that touches the Runner runs on the simulation thread; the
snapshot readers (`commands`, `command`) may run on any thread.
"""
from __future__ import annotations

import threading
from datetime import UTC, datetime

import numpy as np

from server.archive import Archive, ArchiveRecorder
from server.hub import Hub
from server.limits import NOMINAL, RED, LimitChecker, default_limits
from sim.commands import FAILED, CommandRecord, Stage
from sim.events import ERROR, INFO, WARNING, Event, utc_iso
from sim.runner import Listener, Runner

LAG_FIELD = "lag_s"


def wall_utc() -> str:
    return datetime.now(UTC).isoformat(timespec="milliseconds").replace("+00:00", "Z")


class LiveRecorder(ArchiveRecorder):
    """The archive recorder, with the service's lag appended to each frame
    (the run's fields list it last, see LiveRun)."""

    def __init__(self, base: ArchiveRecorder, lag):
        super().__init__(base.archive, base.run_id, base.epoch, base.fields)
        self._lag = lag

    def on_telemetry(self, frame) -> None:
        values = np.append(frame.values, self._lag())
        self.archive.db.execute("INSERT INTO telemetry VALUES (?, ?, ?, ?)",
                                (self.run_id, frame.t_s, frame.mode, values.tobytes()))
        self.archive.maybe_commit()


class LiveRun(Listener):
    def __init__(self, scenario, sc, seed: int | None, archive: Archive, hub: Hub, keep_frames: bool):
        self.scenario, self.sc, self.hub = scenario, sc, hub
        self.epoch = scenario.epoch_utc
        self.lag_s = 0.0
        self.keep_frames = keep_frames
        self._lock = threading.Lock()
        self._commands: dict[int, dict] = {}
        self.limits = LimitChecker(default_limits(sc, sc.n_wheels))
        fields = scenario.recorded_fields(sc)
        seed = scenario.seed if seed is None else seed
        self.recorder = LiveRecorder(archive.start_run(scenario, seed, fields + [LAG_FIELD]), lambda: self.lag_s)
        self.run_id = self.recorder.run_id
        # Listeners are called in order: this object first, so the snapshot
        # exists before the archive and the feeds are told.
        # A live run of a year cannot keep every frame in memory; the archive has them.
        self.runner = Runner(scenario, sc, seed, listeners=[self, self.recorder], keep_frames=keep_frames)
        self.seed = self.runner.seed
        self.fields = fields + [LAG_FIELD]
        numeric = self.runner.layout.numeric_fields
        self._limit_index = {lim.channel: numeric.index(lim.channel) for lim in self.limits.limits
                             if lim.channel in numeric}
        self.finished = False

    # -- Listener (simulation thread) ------------------------------------------
    def on_command(self, rec: CommandRecord, st: Stage) -> None:
        stage = {"name": st.name, "t_s": st.t_s, "utc": utc_iso(self.epoch, st.t_s), "reason": st.reason}
        with self._lock:
            snap = self._commands.get(rec.id)
            if snap is None:
                snap = {"id": rec.id, "run_id": self.run_id, "type": rec.command.type, "args": rec.args(),
                        "source": rec.source, "due_s": rec.due_s, "submitted_utc": wall_utc(),
                        "hazardous": type(rec.command).hazardous, "stages": []}
                self._commands[rec.id] = snap
            snap = dict(snap, stages=snap["stages"] + [stage], state=st.name)
            self._commands[rec.id] = snap
        self.hub.publish_command(snap)

    def on_event(self, e: Event) -> None:
        self.hub.publish_event(self.event_dict(e))

    def on_telemetry(self, frame) -> None:
        values = frame.values
        sample = {ch: float(values[i]) for ch, i in self._limit_index.items()}
        sample[LAG_FIELD] = self.lag_s
        sample["t_s"] = frame.t_s
        for old, lim, new, value in self.limits.check(sample, utc_iso(self.epoch, frame.t_s)):
            sev = ERROR if new == RED else INFO if new == NOMINAL else WARNING
            self.emit(Event(frame.t_s, sev, "limits", "limit",
                            f"{lim.channel} {old} -> {new}: {value:.6g} {lim.unit} "
                            f"(yellow {lim.yellow:.6g}, red {lim.red:.6g})", {"channel": lim.channel}))

    # -- the service's own events go to every listener (archive, feeds) ---------
    def emit(self, e: Event) -> None:
        for listener in self.runner.listeners:
            listener.on_event(e)

    def event_dict(self, e: Event) -> dict:
        return {"run_id": self.run_id, "t_s": e.t_s, "utc": e.utc(self.epoch), "severity": e.severity,
                "source": e.source, "kind": e.kind, "message": e.message}

    # -- stepping (simulation thread) --------------------------------------------
    def advance_to(self, cycle: int) -> None:
        self.runner.advance_to(cycle)
        if self.runner.cycle >= self.runner.end_cycle and not self.finished:
            self.finish_at_end()

    def finish_at_end(self) -> None:
        result = self.runner.run()   # at the end already: delivers, records, evaluates
        self.finished = True
        self.recorder.finish("passed" if result.passed else "failed")

    def stop(self, why: str) -> None:
        """End the run early (another run replaces it, or the service stops)."""
        if self.finished:
            return
        for rec in self.runner.queue.records:
            if not rec.done:
                self.runner.queue.stamp(rec, FAILED, self.runner.t_s, why)
        self.emit(Event(self.runner.t_s, INFO, "runner", "run", f"run stopped: {why}"))
        self.finished = True
        self.recorder.finish("stopped")

    def live_frame(self, extra: dict) -> dict:
        frame = self.runner.frame().as_dict()
        frame[LAG_FIELD] = self.lag_s
        frame["utc"] = utc_iso(self.epoch, frame["t_s"])
        frame["run_id"] = self.run_id
        frame.update(extra)
        return frame

    # -- readers (any thread) -------------------------------------------------------
    def commands(self) -> list[dict]:
        with self._lock:
            return list(self._commands.values())

    def command(self, cmd_id: int) -> dict | None:
        with self._lock:
            return self._commands.get(cmd_id)

    def info(self) -> dict:
        return {"run_id": self.run_id, "name": self.scenario.name, "spacecraft": self.scenario.spacecraft,
                "seed": self.seed, "epoch_utc": self.epoch.isoformat(), "duration_s": self.scenario.duration_s,
                "finished": self.finished, "fields": self.fields}
