"""The run archive: SQLite (WAL), one database holding runs, commands with
every lifecycle stage, events and telemetry frames.

Telemetry frames are stored one row per sample: the mode, and the numeric
fields as a float64 blob in the order runs.fields_json lists them (the field
set differs between spacecraft and scenarios; a blob is exact and ~20 times
cheaper to write than JSON). `telemetry()` reads fields back by time.
Writes are batched and committed at least every `commit_every_s` of wall time,
so a killed process loses at most that much.
"""
from __future__ import annotations

import json
import sqlite3
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from sim.commands import CommandRecord, Stage
from sim.events import Event, utc_iso
from sim.runner import Listener
from sim.telemetry import Frame

SCHEMA_VERSION = 1


class ArchiveError(Exception):
    """An archive this version cannot use; the message says why and what to do."""


SCHEMA = """
CREATE TABLE IF NOT EXISTS runs (
    id INTEGER PRIMARY KEY, name TEXT NOT NULL, spacecraft TEXT NOT NULL, seed INTEGER NOT NULL,
    epoch_utc TEXT NOT NULL, duration_s REAL NOT NULL, started_wall_utc TEXT NOT NULL,
    status TEXT NOT NULL, fields_json TEXT NOT NULL, scenario_json TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS commands (
    run_id INTEGER NOT NULL, cmd_id INTEGER NOT NULL, type TEXT NOT NULL, args_json TEXT NOT NULL,
    source TEXT NOT NULL, due_s REAL NOT NULL, PRIMARY KEY (run_id, cmd_id));
CREATE TABLE IF NOT EXISTS command_stages (
    run_id INTEGER NOT NULL, cmd_id INTEGER NOT NULL, stage TEXT NOT NULL, t_s REAL NOT NULL,
    utc TEXT NOT NULL, reason TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS events (
    run_id INTEGER NOT NULL, t_s REAL NOT NULL, utc TEXT NOT NULL, severity TEXT NOT NULL,
    source TEXT NOT NULL, kind TEXT NOT NULL, message TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS telemetry (
    run_id INTEGER NOT NULL, t_s REAL NOT NULL, mode TEXT NOT NULL,
    value_blob BLOB NOT NULL);  -- float64 values of the run's numeric fields, in runs.fields_json order
CREATE INDEX IF NOT EXISTS telemetry_run_t ON telemetry (run_id, t_s);
CREATE INDEX IF NOT EXISTS events_run_t ON events (run_id, t_s);
"""


class Archive:
    def __init__(self, path: str | Path, commit_every_s: float = 1.0):
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.db = sqlite3.connect(self.path, check_same_thread=False)
        self._check_version()
        self.db.execute("PRAGMA journal_mode=WAL")
        self.db.execute("PRAGMA synchronous=NORMAL")
        self.db.executescript(SCHEMA)
        self.db.execute(f"PRAGMA user_version={SCHEMA_VERSION}")
        self.commit_every_s = commit_every_s
        self._last_commit = time.monotonic()

    def _check_version(self) -> None:
        version = self.db.execute("PRAGMA user_version").fetchone()[0]
        has_tables = self.db.execute("SELECT count(*) FROM sqlite_master WHERE type='table'").fetchone()[0]
        if has_tables and version != SCHEMA_VERSION:
            self.db.close()
            raise ArchiveError(f"{self.path}: archive schema version {version}, this program writes version "
                               f"{SCHEMA_VERSION}; choose another archive path or move this file away")

    def close(self) -> None:
        self.db.commit()
        self.db.close()

    def start_run(self, scenario, seed: int, fields: list[str]) -> "ArchiveRecorder":
        cur = self.db.execute(
            "INSERT INTO runs (name, spacecraft, seed, epoch_utc, duration_s, started_wall_utc, status,"
            " fields_json, scenario_json) VALUES (?, ?, ?, ?, ?, ?, 'running', ?, ?)",
            (scenario.name, scenario.spacecraft, seed, scenario.epoch_utc.isoformat(), scenario.duration_s,
             datetime.now(timezone.utc).isoformat(timespec="seconds"), json.dumps(fields),
             scenario.model_dump_json()))
        self.db.commit()
        return ArchiveRecorder(self, cur.lastrowid, scenario.epoch_utc, fields)

    def maybe_commit(self) -> None:
        now = time.monotonic()
        if now - self._last_commit >= self.commit_every_s:
            self.db.commit()
            self._last_commit = now

    # -- reading -------------------------------------------------------------
    def runs(self) -> list[dict]:
        cur = self.db.execute("SELECT id, name, spacecraft, seed, epoch_utc, duration_s, started_wall_utc, status"
                              " FROM runs ORDER BY id")
        cols = [c[0] for c in cur.description]
        return [dict(zip(cols, row)) for row in cur.fetchall()]

    def telemetry(self, run_id: int, fields: list[str], start_s: float = float("-inf"),
                  end_s: float = float("inf")) -> dict[str, list]:
        recorded = json.loads(self.db.execute("SELECT fields_json FROM runs WHERE id = ?", (run_id,)).fetchone()[0])
        unknown = [f for f in fields if f not in recorded]
        if unknown:
            raise KeyError(f"run {run_id} did not record {', '.join(unknown)}; recorded: {', '.join(recorded)}")
        numeric = [f for f in recorded if f != "mode"]
        rows = self.db.execute("SELECT mode, value_blob FROM telemetry WHERE run_id = ? AND t_s >= ? AND t_s <= ?"
                               " ORDER BY t_s", (run_id, start_s, end_s)).fetchall()
        table = np.array([np.frombuffer(r[1], dtype=np.float64) for r in rows]).reshape(len(rows), len(numeric))
        out = {f: table[:, i].tolist() for i, f in enumerate(numeric)}
        out["mode"] = [r[0] for r in rows]
        return {f: out[f] for f in fields}

    def events(self, run_id: int) -> list[tuple]:
        return self.db.execute("SELECT t_s, utc, severity, source, kind, message FROM events WHERE run_id = ?"
                               " ORDER BY rowid", (run_id,)).fetchall()

    def command_stages(self, run_id: int) -> list[tuple]:
        return self.db.execute(
            "SELECT c.cmd_id, c.type, c.args_json, c.source, s.stage, s.t_s, s.reason FROM commands c"
            " JOIN command_stages s USING (run_id, cmd_id) WHERE run_id = ? ORDER BY s.rowid", (run_id,)).fetchall()


class ArchiveRecorder(Listener):
    """A run's listener that writes into the archive."""

    def __init__(self, archive: Archive, run_id: int, epoch: datetime, fields: list[str]):
        self.archive, self.run_id, self.epoch, self.fields = archive, run_id, epoch, fields

    def on_event(self, e: Event) -> None:
        self.archive.db.execute("INSERT INTO events VALUES (?, ?, ?, ?, ?, ?, ?)",
                                (self.run_id, e.t_s, e.utc(self.epoch), e.severity, e.source, e.kind, e.message))
        self.archive.maybe_commit()

    def on_command(self, rec: CommandRecord, st: Stage) -> None:
        db = self.archive.db
        if len(rec.stages) == 1:
            db.execute("INSERT INTO commands VALUES (?, ?, ?, ?, ?, ?)",
                       (self.run_id, rec.id, rec.command.type, json.dumps(rec.args()), rec.source, rec.due_s))
        db.execute("INSERT INTO command_stages VALUES (?, ?, ?, ?, ?, ?)",
                   (self.run_id, rec.id, st.name, st.t_s, utc_iso(self.epoch, st.t_s), st.reason))

    def on_telemetry(self, frame: Frame) -> None:
        self.archive.db.execute("INSERT INTO telemetry VALUES (?, ?, ?, ?)",
                                (self.run_id, frame.t_s, frame.mode, frame.values.tobytes()))
        self.archive.maybe_commit()

    def finish(self, status: str) -> None:
        self.archive.db.execute("UPDATE runs SET status = ? WHERE id = ?", (status, self.run_id))
        self.archive.db.commit()
