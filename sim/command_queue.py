"""The one queue that time-tagged (scenario) and live commands share.

It owns the command records and stamps each lifecycle stage, telling the
listeners (telemetry writers, the archive, the live service) as it goes.
"""
from __future__ import annotations

import bisect
from typing import Callable

from sim.commands import QUEUED, CommandBase, CommandRecord, Stage

Listener = Callable[[CommandRecord, Stage], None]


def _order(entry):
    return entry[0], entry[1]


class CommandQueue:
    def __init__(self, listener: Listener | None = None):
        self.records: list[CommandRecord] = []
        self._pending: list[tuple[int, int, CommandRecord]] = []  # (due cycle, id, record), sorted
        self._listener = listener

    def submit(self, command: CommandBase, source: str, due_s: float, due_cycle: int, now_s: float) -> CommandRecord:
        rec = CommandRecord(len(self.records) + 1, command, source, due_s)
        self.records.append(rec)
        bisect.insort(self._pending, (due_cycle, rec.id, rec), key=_order)
        self.stamp(rec, QUEUED, now_s)
        return rec

    def next_due_cycle(self) -> int | None:
        return self._pending[0][0] if self._pending else None

    def pop_due(self, cycle: int) -> list[CommandRecord]:
        n = bisect.bisect_right(self._pending, (cycle, float("inf")), key=_order)
        due, self._pending = self._pending[:n], self._pending[n:]
        return [r for _, _, r in due]

    def stamp(self, rec: CommandRecord, stage: str, t_s: float, reason: str = "") -> None:
        st = Stage(stage, t_s, reason)
        rec.stages.append(st)
        if self._listener is not None:
            self._listener(rec, st)
