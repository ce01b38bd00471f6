"""Runs (archive listing, loading another scenario), pacing (pause, resume,
warp, step) and CSV export of telemetry, commands and events."""
from __future__ import annotations

import csv
import io
import json
from pathlib import Path

from fastapi import APIRouter, HTTPException, Query, Request, status
from fastapi.responses import Response
from starlette.concurrency import run_in_threadpool

from server.api.commands import archived_commands
from server.api.deps import Operator, Reader, Service
from server.api.models import PacingRequest, PacingView, RunInfo, RunRequest, StepRequest
from server.api.telemetry import split_fields
from server.service import load_live_scenario
from sim.scenario import ScenarioError

router = APIRouter(prefix="/api", tags=["runs and pacing"])


@router.get("/runs")
async def runs(service: Service, archive: Reader) -> dict:
    """Every run in the archive (this and earlier service sessions) and which one is live."""
    return {"live": service.run.info(), "runs": await run_in_threadpool(archive.runs)}


@router.get("/scenarios")
async def scenarios(request: Request) -> list[str]:
    """The scenario names POST /api/runs accepts."""
    return sorted(p.stem for p in Path(request.app.state.scenario_dir).glob("*.yaml"))


@router.post("/runs", status_code=status.HTTP_201_CREATED, response_model=RunInfo)
async def load_run(req: RunRequest, request: Request, who: Operator,
                   service: Service):
    """Stop the live run (archived as 'stopped') and start another scenario in its place."""
    path = Path(request.app.state.scenario_dir) / f"{req.scenario}.yaml"
    if not path.is_file():
        names = sorted(p.stem for p in path.parent.glob("*.yaml"))
        raise HTTPException(status.HTTP_422_UNPROCESSABLE_CONTENT, [
            {"loc": ["body", "scenario"], "msg": f"unknown scenario {req.scenario!r}; allowed: {', '.join(names)}",
             "type": "value_error"}])
    try:
        scenario, sc = await run_in_threadpool(load_live_scenario, path, req.live)
    except ScenarioError as err:
        raise HTTPException(status.HTTP_422_UNPROCESSABLE_CONTENT,
                            [{"loc": ["body", "scenario"], "msg": str(err), "type": "value_error"}]) from None
    return await run_in_threadpool(service.load, scenario, sc, req.seed, who, not req.live)


@router.get("/pacing", response_model=PacingView)
async def pacing(service: Service):
    return service.status()


@router.post("/pacing", response_model=PacingView)
async def set_warp(req: PacingRequest, who: Operator, service: Service):
    """Set the warp: sim time runs at real time x warp (0 pauses)."""
    return await run_in_threadpool(service.set_warp, req.warp, who)


@router.post("/pacing/pause", response_model=PacingView)
async def pause(who: Operator, service: Service):
    return await run_in_threadpool(service.set_warp, 0, who)


@router.post("/pacing/resume", response_model=PacingView)
async def resume(who: Operator, service: Service):
    """Resume at the warp in force before the pause."""
    return await run_in_threadpool(service.resume, who)


@router.post("/pacing/step", response_model=PacingView, responses={409: {"description": "not paused"}})
async def step(who: Operator, service: Service, req: StepRequest | None = None):
    """Run whole control cycles while paused (one by default)."""
    try:
        return await run_in_threadpool(service.step, (req or StepRequest()).cycles, who)
    except ValueError as err:
        raise HTTPException(status.HTTP_409_CONFLICT, str(err)) from None


def _csv(header: list[str], rows) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    w.writerows(rows)
    return buf.getvalue()


def _csv_response(text: str, name: str) -> Response:
    return Response(text, media_type="text/csv", headers={"Content-Disposition": f'attachment; filename="{name}"'})


@router.get("/export/{what}.csv", response_class=Response,
            responses={200: {"content": {"text/csv": {}}}, 404: {"description": "no such run or table"}})
async def export(what: str, service: Service, archive: Reader,
                 run_id: int | None = Query(None, description="the live run when absent"),
                 start: float = Query(float("-inf"), description="sim s"),
                 end: float = Query(float("inf"), description="sim s"),
                 fields: str = Query("", description="telemetry only: comma-separated fields (all when empty)")):
    """CSV of a run's telemetry, commands (one row per lifecycle stage) or events, for a sim-time range."""
    run_id = service.run.run_id if run_id is None else run_id
    if run_id == service.run.run_id:
        await run_in_threadpool(service.flush_archive)
    known = {r["id"]: r for r in await run_in_threadpool(archive.runs)}
    if run_id not in known:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no run {run_id} in the archive")
    if what == "telemetry":
        text = await run_in_threadpool(_telemetry_csv, archive, run_id, split_fields(fields), start, end)
    elif what == "events":
        rows = [r for r in await run_in_threadpool(archive.events, run_id) if start <= r[0] <= end]
        text = _csv(["t_s", "utc", "severity", "source", "kind", "message"], rows)
    elif what == "commands":
        cmds = await run_in_threadpool(archived_commands, archive, run_id)
        rows = [[c["id"], c["type"], c["source"], json.dumps(c["args"]), s["name"], s["t_s"], s["utc"], s["reason"]]
                for c in cmds for s in c["stages"] if start <= s["t_s"] <= end]
        text = _csv(["id", "type", "source", "args", "stage", "t_s", "utc", "reason"], rows)
    else:
        raise HTTPException(status.HTTP_404_NOT_FOUND, "export telemetry.csv, commands.csv or events.csv")
    return _csv_response(text, f"run{run_id}_{what}.csv")


def _telemetry_csv(archive, run_id: int, fields: list[str], start: float, end: float) -> str:
    recorded = json.loads(archive.db.execute("SELECT fields_json FROM runs WHERE id = ?", (run_id,)).fetchone()[0])
    names = recorded if not fields else ["t_s", *[f for f in fields if f != "t_s"]]
    try:
        cols = archive.telemetry(run_id, names, start, end)
    except KeyError as err:
        raise HTTPException(status.HTTP_422_UNPROCESSABLE_CONTENT,
                            [{"loc": ["query", "fields"], "msg": err.args[0], "type": "value_error"}]) from None
    return _csv(names, zip(*(cols[f] for f in names)))
