"""The FastAPI application. Its lifespan owns the three parts of the live
service: the simulation thread, the viser console and (through uvicorn) the
API itself; it starts them together and stops them cleanly."""
from __future__ import annotations

import asyncio
import contextlib
import logging
from concurrent.futures import TimeoutError as FutureTimeout
from dataclasses import dataclass
from pathlib import Path

from fastapi import FastAPI, Request, status
from fastapi.encoders import jsonable_encoder
from fastapi.exceptions import RequestValidationError
from fastapi.responses import HTMLResponse, JSONResponse

from server.api import commands, events, runs, telemetry
from server.service import SimService, load_live_scenario
from sim.commands import COMMAND_TYPES

log = logging.getLogger("acs.app")
REPO = Path(__file__).resolve().parent.parent
STARTUP_TIMEOUT_S = 900.0     # the first start on a machine compiles every kernel


@dataclass
class ServeConfig:
    scenario: Path = REPO / "scenarios" / "live_sdo.yaml"
    archive: Path = Path("runs") / "archive.sqlite"
    token: str = ""
    host: str = "127.0.0.1"
    viser_port: int | None = 8080       # None: no viser console (API only, e.g. in API tests)
    warp: object = 1
    seed: int | None = None
    live: bool = True                   # extend the scenario to a year of sim time
    scenario_dir: Path = REPO / "scenarios"


def field_path(loc) -> str:
    """A pydantic error location as the user wrote it: no 'body', no union tag."""
    return ".".join(str(p) for p in loc if p != "body" and p not in COMMAND_TYPES)


async def validation_error(request: Request, exc: RequestValidationError) -> JSONResponse:
    detail = []
    for e in jsonable_encoder(exc.errors()):
        e.pop("url", None)
        e["field"] = field_path(e.get("loc", ()))
        detail.append(e)
    return JSONResponse({"detail": detail}, status_code=status.HTTP_422_UNPROCESSABLE_CONTENT)


async def service_unavailable(request: Request, exc: Exception) -> JSONResponse:
    return JSONResponse({"detail": "the simulation did not answer in time; try again"},
                        status_code=status.HTTP_503_SERVICE_UNAVAILABLE, headers={"Retry-After": "1"})


def api_surface(schema: dict) -> dict:
    """The OpenAPI schema without the command models: those belong to sim/ and
    grow with each flight-software issue; the API around them is what
    tests/openapi.json pins. The command union becomes a marker, and only the
    component schemas still referenced from the rest are kept."""

    def strip(node):
        if isinstance(node, dict):
            if node.get("discriminator", {}).get("propertyName") == "type":
                return {"description": node.get("description", ""), "x-command-union": "sim.commands.Command"}
            return {k: strip(v) for k, v in node.items()}
        if isinstance(node, list):
            return [strip(v) for v in node]
        return node

    def refs(node, found: set) -> set:
        if isinstance(node, dict):
            ref = node.get("$ref", "")
            if ref.startswith("#/components/schemas/") and ref.rsplit("/", 1)[1] not in found:
                found.add(ref.rsplit("/", 1)[1])
                refs(components.get(ref.rsplit("/", 1)[1], {}), found)
            for v in node.values():
                refs(v, found)
        elif isinstance(node, list):
            for v in node:
                refs(v, found)
        return found

    out = strip(schema)
    components = out.get("components", {}).get("schemas", {})
    used = refs(out.get("paths", {}), set())
    out["components"]["schemas"] = {k: v for k, v in components.items() if k in used}
    return out


def create_app(config: ServeConfig) -> FastAPI:
    @contextlib.asynccontextmanager
    async def lifespan(app: FastAPI):
        scenario, sc = load_live_scenario(config.scenario, config.live)
        service = SimService(config.archive, scenario, sc, config.seed, config.warp, keep_frames=not config.live)
        service.hub.attach_loop(asyncio.get_running_loop())
        app.state.service = service
        console = None
        service.start()
        try:
            announce = getattr(app.state, "on_starting", None)
            if announce is not None:
                announce()
            if not await asyncio.to_thread(service.ready.wait, STARTUP_TIMEOUT_S):
                raise RuntimeError(f"the simulation did not start within {STARTUP_TIMEOUT_S:g} s")
            if service.startup_error is not None:
                raise RuntimeError(f"the simulation could not start: {service.startup_error}")
            if config.viser_port is not None:
                from web.console import Console

                console = Console(service, config.token, config.host, config.viser_port, config.scenario_dir)
                console.start()
                app.state.console_url = console.url
            on_ready = getattr(app.state, "on_ready", None)
            if on_ready is not None:
                on_ready()
            yield
        finally:
            if console is not None:
                console.stop()
            service.stop()

    app = FastAPI(title="ACS operations console API", version="0.1.0", lifespan=lifespan,
                  description="Command and watch the live attitude-control simulation. Viewing needs no token; "
                              "anything that commands needs `Authorization: Bearer <operator token>`.")
    app.state.token = config.token
    app.state.scenario_dir = config.scenario_dir
    app.state.console_url = None
    app.add_exception_handler(RequestValidationError, validation_error)
    app.add_exception_handler(FutureTimeout, service_unavailable)
    for module in (commands, telemetry, events, runs):
        app.include_router(module.router)

    @app.get("/", response_class=HTMLResponse, include_in_schema=False)
    async def home(request: Request):
        url = request.app.state.console_url
        console = f'<a href="{url}">{url}</a>' if url else "not running"
        return (f"<html><body><h1>ACS operations console</h1><p>3D console: {console}</p>"
                f'<p>API: <a href="/docs">/docs</a> (OpenAPI at <a href="/openapi.json">/openapi.json</a>)</p>'
                "</body></html>")

    return app


if __name__ == "__main__":
    import json
    import sys

    if sys.argv[1:] == ["--openapi"]:
        print(json.dumps(api_surface(create_app(ServeConfig(viser_port=None)).openapi()), indent=1, sort_keys=True))
