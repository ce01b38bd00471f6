"""Pacing of the live run: sim time = real time x warp.

The schedule is anchored (wall time, sim time) at every warp change and
computed from the wall clock, never accumulated from sleeps, so the loop
cannot drift: a late wake-up is caught up on the next slice and shows as lag,
not as a slower clock.
"""
from __future__ import annotations

import time

MAX = "max"
WARPS: tuple = (0, 1, 10, 100, 1000, MAX)


class Pacer:
    def __init__(self, warp=1, clock=time.monotonic):
        self.clock = clock
        self.warp = warp
        self.resume_warp = warp if warp != 0 else 1
        self.anchor_wall = clock()
        self.anchor_sim = 0.0

    @property
    def paused(self) -> bool:
        return self.warp == 0

    @property
    def unlimited(self) -> bool:
        return self.warp == MAX

    def set(self, warp, sim_t: float) -> None:
        if warp not in WARPS:
            raise ValueError(f"warp must be one of {WARPS}, found {warp!r}")
        if warp != 0:
            self.resume_warp = warp
        self.warp = warp
        self.reanchor(sim_t)

    def reanchor(self, sim_t: float) -> None:
        """Start the schedule afresh from sim_t now (warp change, resume, new run)."""
        self.anchor_wall, self.anchor_sim = self.clock(), sim_t

    def target_sim(self, now: float) -> float:
        """Where sim time should be at wall time `now` (finite, nonzero warp)."""
        return self.anchor_sim + (now - self.anchor_wall) * self.warp

    def due_wall(self, sim_t: float) -> float:
        """The wall time at which sim time `sim_t` is due."""
        return self.anchor_wall + (sim_t - self.anchor_sim) / self.warp

    def as_dict(self) -> dict:
        return {"warp": self.warp, "paused": self.paused, "resume_warp": self.resume_warp, "warps": list(WARPS)}
