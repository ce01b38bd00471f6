"""Telemetry frames as they travel: the recorded fields of a run (Layout), one
sample (Frame), columns for expectations, and the CSV writer. The fields
themselves are defined and computed in sim/telemetry_fields.py."""
from __future__ import annotations

from typing import IO

import numpy as np


class Layout:
    """The fields a run records and where they sit among a sample's numbers.
    Recorded fields keep field_names() order, so they open with t_s, mode."""

    def __init__(self, fields: list[str], all_fields: tuple[str, ...]):
        numeric = [n for n in all_fields if n != "mode"]
        if list(fields[:2]) != ["t_s", "mode"]:
            raise ValueError(f"recorded fields must open with t_s, mode; found {fields[:2]}")
        self.fields = list(fields)
        self.numeric_fields = [f for f in fields if f != "mode"]
        self.index = np.array([numeric.index(f) for f in self.numeric_fields], dtype=np.int64)


class Frame:
    """One recorded sample: the mode and the recorded numeric fields, in order."""
    __slots__ = ("mode", "values", "layout")

    def __init__(self, mode: str, values: np.ndarray, layout: Layout):
        self.mode, self.values, self.layout = mode, values, layout

    @property
    def t_s(self) -> float:
        return float(self.values[0])

    def as_dict(self) -> dict:
        out = dict(zip(self.layout.numeric_fields, self.values.tolist()))
        out["mode"] = self.mode
        return {f: out[f] for f in self.layout.fields}


def columns(frames: list[Frame], layout: Layout) -> dict[str, list]:
    """Recorded samples as one list per field."""
    table = np.array([f.values for f in frames]).reshape(len(frames), len(layout.numeric_fields))
    out = {f: table[:, i].tolist() for i, f in enumerate(layout.numeric_fields)}
    out["mode"] = [f.mode for f in frames]
    return {f: out[f] for f in layout.fields}


class CsvTelemetryWriter:
    """Writes frames to CSV with a header row. Floats are written with repr(),
    the shortest string that reads back to the same double: exact, and
    byte-identical from run to run."""

    def __init__(self, stream: IO[str], layout: Layout):
        self._stream = stream
        stream.write(",".join(layout.fields) + "\n")

    def write(self, frame: Frame) -> None:
        v = frame.values.tolist()
        self._stream.write(f"{v[0]!r},{frame.mode}," + ",".join(map(repr, v[1:])) + "\n")
