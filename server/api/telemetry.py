"""Telemetry: the latest live frame, archived telemetry by time, and the
live stream (subscribe to fields at a rate)."""
from __future__ import annotations

import asyncio
import json
import time

from fastapi import APIRouter, HTTPException, Query, WebSocket, WebSocketDisconnect, status
from starlette.concurrency import run_in_threadpool

from server.api.deps import Reader, Service
from server.service import SimService

router = APIRouter(prefix="/api/telemetry", tags=["telemetry"])
MAX_ROWS = 20_000
MAX_RATE_HZ = 50.0


@router.get("/latest")
async def latest(service: Service) -> dict:
    """The newest live frame: every recorded field, plus lag_s, utc, run_id and warp."""
    frame = service.hub.latest
    if frame is None:
        raise HTTPException(status.HTTP_503_SERVICE_UNAVAILABLE, "no telemetry yet (the simulation is starting)",
                            headers={"Retry-After": "1"})
    return frame


def split_fields(fields: str) -> list[str]:
    return [f.strip() for f in fields.split(",") if f.strip()]


@router.get("")
async def archived(service: Service, archive: Reader,
                   fields: str = Query(..., description="comma-separated field names", examples=["att_err_arcsec"]),
                   start: float = Query(float("-inf"), description="sim s"),
                   end: float = Query(float("inf"), description="sim s"),
                   run_id: int | None = Query(None, description="the live run when absent")) -> dict:
    """Telemetry from the archive at the recorded rate, one list per field (t_s
    always included). Long ranges are thinned to at most 20000 rows; `stride`
    says by how much."""
    run_id = service.run.run_id if run_id is None else run_id
    names = ["t_s"] + [f for f in split_fields(fields) if f != "t_s"]
    if run_id == service.run.run_id:
        await run_in_threadpool(service.flush_archive)
    try:
        cols = await run_in_threadpool(archive.telemetry, run_id, names, start, end)
    except KeyError as err:
        raise HTTPException(status.HTTP_422_UNPROCESSABLE_CONTENT,
                            [{"loc": ["query", "fields"], "msg": err.args[0], "type": "value_error"}]) from None
    except TypeError:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no run {run_id} in the archive") from None
    n = len(cols["t_s"])
    stride = max(1, -(-n // MAX_ROWS))
    return {"run_id": run_id, "stride": stride, "rows": len(range(0, n, stride)),
            "columns": {f: v[::stride] for f, v in cols.items()}}


class Subscription:
    """What one stream client asked for: fields (all when empty) and a rate."""

    def __init__(self, fields: list[str], rate_hz: float):
        self.fields, self.rate_hz = fields, rate_hz

    def update(self, msg: dict) -> None:
        if "fields" in msg:
            if not isinstance(msg["fields"], list) or not all(isinstance(f, str) for f in msg["fields"]):
                raise ValueError("fields: expected a list of field names")
            self.fields = msg["fields"]
        if "rate_hz" in msg:
            rate = msg["rate_hz"]
            if not isinstance(rate, (int, float)) or not 0 < rate <= MAX_RATE_HZ:
                raise ValueError(f"rate_hz: expected a number in (0, {MAX_RATE_HZ:g}]")
            self.rate_hz = float(rate)

    def pick(self, frame: dict) -> tuple[dict, list[str]]:
        if not self.fields:
            return frame, []
        missing = [f for f in self.fields if f not in frame]
        return {f: frame[f] for f in ["t_s", *self.fields] if f in frame}, missing


async def _receive(ws: WebSocket, sub: Subscription) -> None:
    """Subscription changes from the client: {"fields": [...], "rate_hz": 10}."""
    while True:
        text = await ws.receive_text()
        try:
            msg = json.loads(text)
            if not isinstance(msg, dict):
                raise ValueError("expected a JSON object such as {\"fields\": [\"att_err_arcsec\"], \"rate_hz\": 10}")
            sub.update(msg)
            await ws.send_json({"type": "subscribed", "fields": sub.fields, "rate_hz": sub.rate_hz})
        except ValueError as err:   # json.JSONDecodeError is a ValueError
            await ws.send_json({"type": "error", "message": str(err)})


@router.websocket("/stream")
async def stream(ws: WebSocket, fields: str = "", rate_hz: float = 10.0):
    """Live frames at up to `rate_hz` (each new frame once). Change the
    subscription at any time by sending {"fields": [...], "rate_hz": r}."""
    service: SimService = ws.app.state.service
    await ws.accept()
    sub = Subscription(split_fields(fields), min(max(rate_hz, 0.1), MAX_RATE_HZ))
    receiver = asyncio.create_task(_receive(ws, sub))
    try:
        await _send_frames(ws, service, sub, receiver)
    except (WebSocketDisconnect, RuntimeError):
        pass   # the client went away
    finally:
        receiver.cancel()


async def _send_frames(ws: WebSocket, service: SimService, sub: Subscription, receiver: asyncio.Task) -> None:
    hub, last_seq, warned = service.hub, -1, set()
    await ws.send_json({"type": "subscribed", "fields": sub.fields, "rate_hz": sub.rate_hz})
    while not receiver.done():
        if hub.frame_seq == last_seq or hub.latest is None:
            await hub.wait_change(1.0)
            continue
        last_seq, t0 = hub.frame_seq, time.monotonic()
        frame, missing = sub.pick(hub.latest)
        new_missing = set(missing) - warned
        if new_missing:
            warned |= new_missing
            await ws.send_json({"type": "error", "message": f"not in telemetry: {', '.join(sorted(new_missing))}"})
        await ws.send_json({"type": "telemetry", "seq": last_seq, "frame": frame})
        await asyncio.sleep(max(0.0, 1.0 / sub.rate_hz - (time.monotonic() - t0)))
