"""The event log: the Princeton paper's planned "simulation log file"
(seed 002 "User Interface"): commands, failures and mode transitions,
time-stamped in sim seconds and UTC."""
from __future__ import annotations

import csv
from dataclasses import dataclass, field
from datetime import datetime, timedelta
from typing import IO

INFO, WARNING, ERROR = "info", "warning", "error"


@dataclass(frozen=True)
class Event:
    t_s: float
    severity: str   # info | warning | error
    source: str     # ground | fsw | runner | truth
    kind: str       # command | mode | fault | expectation | run
    message: str
    data: dict = field(default_factory=dict)

    def utc(self, epoch: datetime) -> str:
        return utc_iso(epoch, self.t_s)


def utc_iso(epoch: datetime, t_s: float) -> str:
    """ISO 8601 UTC with millisecond resolution, e.g. 2026-03-20T12:00:01.200Z."""
    t = epoch + timedelta(microseconds=round(t_s * 1e6))
    return t.strftime("%Y-%m-%dT%H:%M:%S.") + f"{t.microsecond // 1000:03d}Z"


class CsvEventWriter:
    HEADER = ("t_s", "utc", "severity", "source", "kind", "message")

    def __init__(self, stream: IO[str], epoch: datetime):
        self.epoch = epoch
        self._w = csv.writer(stream, lineterminator="\n")
        self._w.writerow(self.HEADER)

    def write(self, e: Event) -> None:
        self._w.writerow([repr(float(e.t_s)), e.utc(self.epoch), e.severity, e.source, e.kind, e.message])
