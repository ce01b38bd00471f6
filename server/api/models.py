"""Request and response models of the API. Commands themselves are the
discriminated union from sim.commands: nothing here lists command types, so
a command added to the engine appears in the API (and its OpenAPI schema)
without console code."""
from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from sim.commands import Command

Warp = Literal[0, 1, 10, 100, 1000, "max"]


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class CommandRequest(Strict):
    command: Command = Field(description="the command: one of the engine's command models, chosen by `type`")
    confirm: bool = Field(False, description="required true for hazardous commands")
    t_s: float | None = Field(None, ge=0, description="time tag (sim s); the next control cycle when absent")
    operator: str = Field("operator", min_length=1, max_length=40, pattern=r"^[A-Za-z0-9_.-]+$",
                          description="who sends it, for the command history")


class StageView(BaseModel):
    name: str
    t_s: float
    utc: str
    reason: str = ""


class CommandView(BaseModel):
    id: int
    run_id: int
    type: str
    args: dict[str, Any]
    source: str = Field(description="who sent it: scenario, rest:<operator>, console:<client>")
    due_s: float
    submitted_utc: str = Field(description="wall-clock UTC when the service queued it")
    hazardous: bool
    state: str = Field(description="queued | accepted | rejected | executing | completed | failed")
    stages: list[StageView]


class PacingRequest(Strict):
    warp: Warp = Field(description="0 pauses; 'max' runs as fast as the machine allows")


class StepRequest(Strict):
    cycles: int = Field(1, ge=1, le=3000, description="control cycles to run (only while paused)")


class PacingView(BaseModel):
    warp: Warp
    paused: bool
    resume_warp: Warp
    warps: list[Warp]
    t_s: float
    lag_s: float
    run_id: int
    finished: bool
    realtime_ratio: float = Field(description="sim s per wall s achieved over the last ~2 s")
    capacity_ratio: float = Field(description="sim s per wall s while stepping long slices: what max warp can "
                                              "reach (0 until measured at a high warp)")


class RunRequest(Strict):
    scenario: str = Field(pattern=r"^[A-Za-z0-9_.-]+$",
                          description="name of a scenario file in scenarios/ (without .yaml)")
    seed: int | None = Field(None, ge=0)
    live: bool = Field(True, description="extend the run to a year of sim time (false: run the file as written, "
                                         "and check its expectations at its end)")


class RunInfo(BaseModel):
    run_id: int
    name: str
    spacecraft: str
    seed: int
    epoch_utc: str
    duration_s: float
    finished: bool
    fields: list[str]


class AckRequest(Strict):
    operator: str = Field("operator", min_length=1, max_length=40, pattern=r"^[A-Za-z0-9_.-]+$")
