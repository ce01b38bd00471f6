"""Expectations: what turns a scenario into a test.

Each names a telemetry field, a statistic over a time window, and a bound:

    {field: att_err_arcsec, from_s: 600, below: 5}                       # every sample
    {field: att_err_arcsec, stat: three_sigma, from_s: 1200, below: 2}   # |mean| + 3 std
    {field: mode, stat: any, to_s: 900, equals: SCIENCE}                 # reached by t
"""
from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, model_validator

Stat = Literal["all", "any", "final", "max", "min", "mean", "rms", "max_abs", "three_sigma"]
SAMPLEWISE = ("all", "any", "final")


class Expectation(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)
    field: str
    stat: Stat = "all"
    from_s: float = 0.0
    to_s: float | None = None
    below: float | None = None
    above: float | None = None
    equals: str | float | None = None

    @model_validator(mode="after")
    def _one_bound(self) -> "Expectation":
        given = [k for k in ("below", "above", "equals") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(f"give exactly one of below, above, equals (found: {', '.join(given) or 'none'})")
        if self.equals is not None and self.stat not in SAMPLEWISE:
            raise ValueError(f"equals works with stat {', '.join(SAMPLEWISE)}; found stat {self.stat!r}")
        if self.to_s is not None and self.to_s < self.from_s:
            raise ValueError(f"to_s ({self.to_s:g}) is before from_s ({self.from_s:g})")
        return self

    def describe(self) -> str:
        window = f"[{self.from_s:g}, {'end' if self.to_s is None else f'{self.to_s:g}'}] s"
        bound = next(f"{k} {getattr(self, k)}" for k in ("below", "above", "equals") if getattr(self, k) is not None)
        return f"{self.stat}({self.field}) over {window} {bound}"


def _holds(values, e: Expectation):
    if e.equals is not None:
        return np.array([v == e.equals for v in values])
    v = np.asarray(values, float)
    return v < e.below if e.below is not None else v > e.above


def evaluate(e: Expectation, t_s: np.ndarray, values: list) -> tuple[bool, str]:
    """(holds, measured) for one expectation over recorded telemetry."""
    end = np.inf if e.to_s is None else e.to_s + 1e-9
    idx = np.nonzero((t_s >= e.from_s - 1e-9) & (t_s <= end))[0]
    if idx.size == 0:
        return False, "no telemetry samples in the window"
    window = [values[i] for i in idx]
    if e.stat in SAMPLEWISE:
        ok = _holds(window, e)
        if e.stat == "all":
            bad = np.nonzero(~ok)[0]
            return (True, f"{len(window)} samples hold") if bad.size == 0 else (
                False, f"{window[bad[0]]} at t = {t_s[idx[bad[0]]]:g} s ({bad.size} of {len(window)} samples fail)")
        if e.stat == "any":
            good = np.nonzero(ok)[0]
            return (True, f"first at t = {t_s[idx[good[0]]]:g} s") if good.size else (
                False, f"never; last value {window[-1]}")
        return bool(ok[-1]), f"{window[-1]}"
    v = np.asarray(window, float)
    stat = {"max": np.max, "min": np.min, "mean": np.mean, "rms": lambda a: np.sqrt(np.mean(a * a)),
            "max_abs": lambda a: np.max(np.abs(a)),
            "three_sigma": lambda a: abs(np.mean(a)) + 3.0 * np.std(a)}[e.stat](v)
    return bool(_holds([stat], e)[0]), f"{stat:.6g}"
