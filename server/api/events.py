"""Events (the simulation log), limits, alarms with acknowledge, and the
WebSocket feeds of events and command lifecycles."""
from __future__ import annotations

import asyncio
from typing import Literal

from fastapi import APIRouter, HTTPException, Query, WebSocket, WebSocketDisconnect, status
from starlette.concurrency import run_in_threadpool

from server.api.deps import Operator, Reader, Service
from server.api.models import AckRequest
from server.hub import Feed
from server.service import SimService

router = APIRouter(prefix="/api", tags=["events and alarms"])
Severity = Literal["info", "warning", "error"]
_RANK = {"info": 0, "warning": 1, "error": 2}


@router.get("/events")
async def events(service: Service, archive: Reader,
                 run_id: int | None = Query(None, description="a past run; the live run when absent"),
                 severity: Severity = Query("info", description="this severity and worse"),
                 since_s: float = Query(float("-inf"), description="sim s"),
                 limit: int = Query(500, ge=1, le=100_000)) -> list[dict]:
    """Events, oldest first: severity, source, kind, sim time t_s and UTC (ISO 8601).
    The live run answers from memory (its last 2000 events); past runs from the archive."""
    if run_id is None or run_id == service.run.run_id:
        rows = [e for e in service.hub.events.tail(2000) if e["run_id"] == service.run.run_id]
    else:
        cols = ("t_s", "utc", "severity", "source", "kind", "message")
        found = await run_in_threadpool(archive.events, run_id)
        rows = [dict(zip(cols, r), run_id=run_id) for r in found]
    rows = [e for e in rows if _RANK[e["severity"]] >= _RANK[severity] and e["t_s"] >= since_s]
    return rows[-limit:]


@router.get("/limits")
async def limits(service: Service) -> list[dict]:
    """Each limited channel: its yellow and red bands (on |value|), unit, source, current level."""
    return service.run.limits.table()


@router.get("/alarms")
async def alarms(service: Service) -> list[dict]:
    """Alarms raised by limit violations: they stay until acknowledged, even after the value returns."""
    return service.run.limits.alarms()


@router.post("/alarms/{alarm_id}/ack", responses={404: {"description": "no such alarm"}})
async def acknowledge(alarm_id: int, who: Operator, service: Service, body: AckRequest | None = None) -> dict:
    operator = body.operator if body else "operator"
    found = await run_in_threadpool(service.acknowledge, alarm_id, f"{who}:{operator}")
    if found is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no alarm {alarm_id}")
    return found


async def _until_disconnect(ws: WebSocket) -> None:
    """Reads (and ignores) what the client sends, so that a disconnect is seen
    even while nothing is being sent to it."""
    while (await ws.receive())["type"] != "websocket.disconnect":
        pass


async def _follow(ws: WebSocket, feed: Feed, service: SimService) -> None:
    """Send every item of a feed as it is appended (after the last `backlog` ones)."""
    await ws.accept()
    try:
        backlog = max(0, int(ws.query_params.get("backlog", "0") or 0))
    except ValueError:
        backlog = 0
    seq = max(0, feed.seq - backlog)
    watcher = asyncio.create_task(_until_disconnect(ws))
    try:
        while not watcher.done():
            items, dropped = feed.since(seq)
            if dropped:
                await ws.send_json({"type": "gap", "dropped": dropped})
            for s, item in items:
                await ws.send_json({"type": "item", "seq": s, "item": item})
                seq = s
            if not items:
                await service.hub.wait_change(1.0)
    except (WebSocketDisconnect, RuntimeError):
        pass
    finally:
        watcher.cancel()


@router.websocket("/commands/stream")
async def commands_stream(ws: WebSocket):
    """Each command's snapshot every time its lifecycle advances (?backlog=N replays the last N)."""
    await _follow(ws, ws.app.state.service.hub.commands, ws.app.state.service)


@router.websocket("/events/stream")
async def events_stream(ws: WebSocket):
    """Every event as it happens (?backlog=N replays the last N)."""
    await _follow(ws, ws.app.state.service.hub.events, ws.app.state.service)
