"""Commands: submit (one queue with the scenario's time-tagged commands) and
history with every lifecycle stage."""
from __future__ import annotations

import json

from fastapi import APIRouter, HTTPException, Query, status
from starlette.concurrency import run_in_threadpool

from server.api.deps import Operator, Reader, Service
from server.api.models import CommandRequest, CommandView

router = APIRouter(prefix="/api/commands", tags=["commands"])


@router.post("", status_code=status.HTTP_202_ACCEPTED, response_model=CommandView,
             responses={401: {"description": "no operator token"}, 403: {"description": "wrong operator token"},
                        409: {"description": "the run has ended"},
                        428: {"description": "hazardous command sent without confirm: true"}})
async def submit_command(req: CommandRequest, who: Operator,
                         service: Service):
    """Queue a command. It is checked by the flight software at the next control
    cycle (or at its time tag): follow its lifecycle in the answer's `stages`,
    at GET /api/commands/{id} or on the WebSocket /api/commands/stream."""
    if type(req.command).hazardous and not req.confirm:
        raise HTTPException(status.HTTP_428_PRECONDITION_REQUIRED,
                            f"{req.command.type} is hazardous: send it again with \"confirm\": true")
    try:
        return await run_in_threadpool(service.submit, req.command, f"{who}:{req.operator}", req.t_s)
    except RuntimeError as err:
        raise HTTPException(status.HTTP_409_CONFLICT, str(err)) from None


@router.get("", response_model=list[CommandView])
async def command_history(service: Service, archive: Reader,
                          run_id: int | None = Query(None, description="a past run; the live run when absent")):
    """Every command of a run: who sent it, when, its arguments and the time of each stage."""
    if run_id is None or run_id == service.run.run_id:
        return service.run.commands()
    return await run_in_threadpool(archived_commands, archive, run_id)


@router.get("/{cmd_id}", response_model=CommandView)
async def command(cmd_id: int, service: Service):
    snap = service.run.command(cmd_id)
    if snap is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no command {cmd_id} in the live run")
    return snap


def archived_commands(archive, run_id: int) -> list[dict]:
    """Command snapshots rebuilt from the archive (commands + command_stages)."""
    rows = archive.db.execute(
        "SELECT c.cmd_id, c.type, c.args_json, c.source, c.due_s, s.stage, s.t_s, s.utc, s.reason FROM commands c"
        " JOIN command_stages s USING (run_id, cmd_id) WHERE run_id = ? ORDER BY s.rowid", (run_id,)).fetchall()
    out: dict[int, dict] = {}
    for cmd_id, typ, args_json, source, due_s, stage, t_s, utc, reason in rows:
        snap = out.setdefault(cmd_id, {"id": cmd_id, "run_id": run_id, "type": typ, "args": json.loads(args_json),
                                       "source": source, "due_s": due_s, "submitted_utc": "",
                                       "hazardous": False, "stages": [], "state": stage})
        snap["stages"].append({"name": stage, "t_s": t_s, "utc": utc, "reason": reason})
        snap["state"] = stage
    return list(out.values())

