"""The background simulation service: one thread steps the live run, paced
against the wall clock; everything else talks to it through a thread-safe
inbox (commands, pacing, new runs), drained between slices so that a ground
command reaches the flight software at the next control cycle.

The Runner is not thread-safe, so only the simulation thread touches it. A
request that needs an answer (a command's id) carries a Future.
"""
from __future__ import annotations

import collections
import logging
import math
import queue
import threading
import time
from concurrent.futures import Future
from dataclasses import dataclass
from pathlib import Path

from server.archive import Archive
from server.hub import Hub
from server.live_run import LiveRun
from server.pacing import Pacer
from sim.commands import CommandBase
from sim.events import INFO, Event
from sim.scenario import load_scenario, parse_scenario

log = logging.getLogger("acs.service")

LIVE_DURATION_S = 365 * 86400.0   # a live run lasts a year of sim time (then it ends like any run)
LIVE_HZ = 20.0                    # live frames per wall second, at most
SLICE_WALL_S = 0.02               # longest stretch of stepping between inbox checks
IDLE_WAIT_S = 0.25                # paused or finished: how often to commit the archive


def load_live_scenario(path: str | Path, live: bool = True):
    """A scenario file as a live run: its duration extended to LIVE_DURATION_S."""
    scenario, sc = load_scenario(path)
    if live and scenario.duration_s < LIVE_DURATION_S:
        scenario, sc = parse_scenario(dict(scenario.model_dump(mode="json"), duration_s=LIVE_DURATION_S), str(path))
    return scenario, sc


@dataclass
class _Request:
    kind: str            # command | pace | step | load | call
    args: tuple
    future: Future


class SimService:
    def __init__(self, archive_path: str | Path, scenario, sc, seed: int | None = None, warp=1,
                 keep_frames: bool = False):
        self.archive_path = Path(archive_path)
        self.archive = Archive(self.archive_path)
        self._mark_interrupted_runs()
        self.hub = Hub()
        self.pacer = Pacer(warp)
        self.run = LiveRun(scenario, sc, seed, self.archive, self.hub, keep_frames)
        self._inbox: queue.Queue[_Request] = queue.Queue()
        self._stop = threading.Event()
        self.ready = threading.Event()     # set once the first cycle ran (kernels compiled)
        self.startup_error: Exception | None = None
        self._thread: threading.Thread | None = None
        self._slice_cycles = 50
        self._last_publish = 0.0
        self.cycles_per_s = 0.0      # stepping speed while stepping (what max warp can reach)
        self._progress: collections.deque = collections.deque(maxlen=40)   # (wall, sim t) at each publication

    def _mark_interrupted_runs(self) -> None:
        # A run still "running" in the archive belonged to a process that was
        # killed: say so rather than leave it looking alive.
        self.archive.db.execute("UPDATE runs SET status = 'interrupted' WHERE status = 'running'")
        self.archive.db.commit()

    # -- lifecycle ----------------------------------------------------------------
    def start(self) -> None:
        self.pacer.reanchor(self.run.runner.t_s)
        self._thread = threading.Thread(target=self._main, name="acs-sim", daemon=True)
        self._thread.start()

    def stop(self, timeout: float = 10.0) -> None:
        self._stop.set()
        self._inbox.put(_Request("wake", (), Future()))
        if self._thread is not None:
            self._thread.join(timeout)
        self.run.stop("service stopped")
        self.archive.close()

    @property
    def alive(self) -> bool:
        return self._thread is not None and self._thread.is_alive()

    # -- the API's side: requests answered by the simulation thread -------------------
    def _ask(self, kind: str, *args, timeout: float = 5.0):
        if not self.alive:
            raise RuntimeError("the simulation thread is not running")
        fut: Future = Future()
        self._inbox.put(_Request(kind, args, fut))
        return fut.result(timeout)

    def submit(self, command: CommandBase, source: str, t_s: float | None = None) -> dict:
        """Queue a command for the next control cycle (or its time tag); returns its snapshot."""
        return self._ask("command", command, source, t_s)

    def set_warp(self, warp, who: str) -> dict:
        return self._ask("pace", warp, who)

    def resume(self, who: str) -> dict:
        return self._ask("pace", self.pacer.resume_warp, who)

    def step(self, cycles: int, who: str) -> dict:
        return self._ask("step", cycles, who)

    def load(self, scenario, sc, seed: int | None, who: str, keep_frames: bool = False) -> dict:
        return self._ask("load", scenario, sc, seed, who, keep_frames, timeout=30.0)

    def acknowledge(self, alarm_id: int, who: str) -> dict | None:
        return self._ask("ack", alarm_id, who)

    def flush_archive(self) -> None:
        """Commit what the simulation thread has written, so readers see it all."""
        self._ask("flush")

    def status(self) -> dict:
        r = self.run
        return {**self.pacer.as_dict(), "t_s": r.runner.t_s, "lag_s": r.lag_s, "run_id": r.run_id,
                "finished": r.finished, "realtime_ratio": self.realtime_ratio(),
                "capacity_ratio": self.cycles_per_s * r.runner.cycle_ns / 1e9}

    def realtime_ratio(self) -> float:
        """Sim seconds per wall second over the last two seconds or so: the speed achieved."""
        samples = list(self._progress)
        if len(samples) < 2 or self.pacer.paused or self.run.finished:
            return 0.0
        (w0, t0), (w1, t1) = samples[0], samples[-1]
        return (t1 - t0) / (w1 - w0) if w1 > w0 else 0.0

    # -- the simulation thread ------------------------------------------------------------
    def _main(self) -> None:
        try:
            self._warm_up()
        except Exception as err:   # reported to whoever waits for `ready`
            log.exception("the simulation could not start")
            self.startup_error = err
            self.ready.set()
            return
        while not self._stop.is_set():
            try:
                wait = self._tick()
            except Exception:   # a bug must not end the live service silently
                log.exception("simulation step failed; pausing")
                self._emit(Event(self.run.runner.t_s, "error", "runner", "run", "simulation step failed; paused"))
                self.pacer.set(0, self.run.runner.t_s)
                wait = IDLE_WAIT_S
            self._drain(wait)
            self.archive.maybe_commit()

    def _warm_up(self) -> None:
        """One cycle before pacing starts: the first call compiles the kernels
        (a minute on a fresh machine), which must not count as lag."""
        runner = self.run.runner
        self.run.advance_to(runner.cycle + 1)
        self.pacer.reanchor(runner.t_s)
        self._publish(force=True)
        self.ready.set()

    def _drain(self, wait: float) -> None:
        try:
            req = self._inbox.get(timeout=wait) if wait > 0 else self._inbox.get_nowait()
        except queue.Empty:
            return
        while True:
            self._handle(req)
            try:
                req = self._inbox.get_nowait()
            except queue.Empty:
                return

    def _handle(self, req: _Request) -> None:
        if req.future.done():   # the asker gave up (timeout)
            return
        try:
            handler = {"command": self._do_command, "pace": self._do_pace, "step": self._do_step,
                       "load": self._do_load, "ack": self._do_ack, "flush": self.archive.db.commit,
                       "wake": lambda: None}[req.kind]
            req.future.set_result(handler(*req.args))
        except Exception as err:  # reported to the asker, never raised in this thread
            req.future.set_exception(err)

    def _tick(self) -> float:
        """Step as far as the schedule says; returns how long to wait for the next cycle."""
        r = self.run
        if r.finished or self.pacer.paused:
            r.lag_s = 0.0
            return IDLE_WAIT_S
        runner = r.runner
        if self.pacer.unlimited:
            r.lag_s = 0.0
            self._advance(runner.cycle + self._slice_cycles)
            return 0.0
        now = self.pacer.clock()
        # the last cycle whose sim time is due by now
        target = math.floor(self.pacer.target_sim(now) * 1e9 / runner.cycle_ns + 1e-9)
        if target > runner.cycle:
            self._advance(min(target, runner.cycle + self._slice_cycles))
            r.lag_s = max(0.0, self.pacer.clock() - self.pacer.due_wall(runner.t_s))
        next_due = self.pacer.due_wall((runner.cycle + 1) * runner.cycle_ns / 1e9)
        return max(0.0, next_due - self.pacer.clock())

    def _advance(self, cycle: int) -> None:
        runner = self.run.runner
        start_cycle, t0 = runner.cycle, time.perf_counter()
        self.run.advance_to(cycle)
        dt = time.perf_counter() - t0
        n = runner.cycle - start_cycle
        if n >= 50 and dt > 0:   # short slices measure call overhead, not stepping speed
            rate = n / dt
            self.cycles_per_s = rate if self.cycles_per_s == 0 else 0.8 * self.cycles_per_s + 0.2 * rate
            # size the next slice to SLICE_WALL_S of stepping
            self._slice_cycles = max(1, min(100_000, int(self.cycles_per_s * SLICE_WALL_S)))
        self._publish()

    def _publish(self, force: bool = False) -> None:
        now = time.monotonic()
        if force or now - self._last_publish >= 1.0 / LIVE_HZ:
            self._last_publish = now
            t_s = self.run.runner.t_s
            if self._progress and t_s < self._progress[-1][1]:
                self._progress.clear()      # a new run: sim time starts again
            while self._progress and now - self._progress[0][0] > 2.0:
                self._progress.popleft()
            self._progress.append((now, t_s))
            self.hub.publish_frame(self.run.live_frame({"warp": self.pacer.warp}))

    def _emit(self, e: Event) -> None:
        self.run.emit(e)

    # -- request handlers (simulation thread) ---------------------------------------------
    def _do_command(self, command: CommandBase, source: str, t_s: float | None) -> dict:
        if self.run.finished:
            raise RuntimeError("the run has ended; load a new run to command")
        rec = self.run.runner.submit(command, source, t_s)
        return self.run.command(rec.id)

    def _do_pace(self, warp, who: str) -> dict:
        t_s = self.run.runner.t_s
        old = self.pacer.warp
        self.pacer.set(warp, t_s)
        if warp != old:
            what = "paused" if warp == 0 else f"warp {old} -> {warp}" if old != 0 else f"resumed at warp {warp}"
            self._emit(Event(t_s, INFO, "ground", "pacing", f"{what} (by {who})"))
        self._publish(force=True)
        return self.status()

    def _do_step(self, cycles: int, who: str) -> dict:
        if not self.pacer.paused:
            raise ValueError("step works while paused; pause first (warp 0)")
        runner = self.run.runner
        self.run.advance_to(runner.cycle + cycles)
        self._emit(Event(runner.t_s, INFO, "ground", "pacing", f"stepped {cycles} cycle(s) (by {who})"))
        self._publish(force=True)
        return self.status()

    def _do_ack(self, alarm_id: int, who: str) -> dict | None:
        found = self.run.limits.acknowledge(alarm_id, who)
        if found is not None:
            self._emit(Event(self.run.runner.t_s, INFO, "ground", "alarm",
                             f"alarm {alarm_id} ({found['channel']} {found['worst']}) acknowledged by {who}"))
        return found

    def _do_load(self, scenario, sc, seed, who: str, keep_frames: bool) -> dict:
        new = LiveRun(scenario, sc, seed, self.archive, self.hub, keep_frames)
        self.run.stop(f"replaced by run {new.run_id} (by {who})")
        self.run = new
        self.hub.reset_window()
        self.pacer.reanchor(new.runner.t_s)
        self._emit(Event(0.0, INFO, "ground", "run", f"run {new.run_id} loaded: {scenario.name} (by {who})"))
        self._publish(force=True)
        return new.info()
