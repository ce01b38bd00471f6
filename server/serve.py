"""`acs serve`: the operations console as one process (uvicorn + FastAPI,
the viser console, the simulation thread)."""
from __future__ import annotations

import os
import secrets
import sys
from pathlib import Path

EXIT_BAD_INPUT = 2


def operator_token(token_file: Path | None) -> tuple[str, bool]:
    """The operator token: ACS_TOKEN, else the token file, else a new one.
    Returns (token, generated)."""
    token = os.environ.get("ACS_TOKEN", "").strip()
    if not token and token_file is not None:
        token = token_file.read_text().strip()
    if token:
        return token, False
    return secrets.token_urlsafe(18), True


def main(args) -> int:
    import uvicorn

    from server.app import ServeConfig, create_app
    from server.archive import Archive, ArchiveError
    from server.pacing import WARPS
    from server.service import load_live_scenario
    from sim.scenario import ScenarioError

    try:
        load_live_scenario(args.scenario)            # fail fast, before any port is taken
        Archive(args.archive).close()
    except (ScenarioError, ArchiveError) as err:
        print(f"error: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT
    warp = "max" if args.warp == "max" else int(args.warp)
    if warp not in WARPS:
        print(f"error: --warp must be one of {', '.join(map(str, WARPS))}", file=sys.stderr)
        return EXIT_BAD_INPUT
    token, generated = operator_token(args.token_file)
    config = ServeConfig(scenario=Path(args.scenario), archive=Path(args.archive), token=token, host=args.host,
                         viser_port=args.viser_port, warp=warp, seed=args.seed)
    app = create_app(config)

    def announce() -> None:
        print(f"ACS console (3D):  {app.state.console_url}", flush=True)
        print(f"ACS API:           http://{args.host}:{args.port}/docs", flush=True)
        print(f"archive:           {Path(args.archive).resolve()}", flush=True)
        if generated:
            # Printed once on the terminal, never logged or archived. Set ACS_TOKEN to choose it.
            print(f"operator token:    {token}   (generated; set ACS_TOKEN to choose your own)", flush=True)

    app.state.on_ready = announce
    app.state.on_starting = lambda: print("starting the simulation (the first start on a machine compiles its "
                                          "kernels: about a minute)...", flush=True)
    uvicorn.run(app, host=args.host, port=args.port, log_level="warning" if args.quiet else "info")
    return 0


REPO = Path(__file__).resolve().parent.parent


def add_arguments(s) -> None:
    # no import of the console stack here: `acs run` builds this parser too
    s.add_argument("--scenario", default=str(REPO / "scenarios" / "live_sdo.yaml"),
                   help="scenario to run live (extended to a year of sim time)")
    s.add_argument("--host", default="127.0.0.1", help="address to bind (default: this machine only)")
    s.add_argument("--port", type=int, default=8000, help="REST/WebSocket API port")
    s.add_argument("--viser-port", type=int, default=8080, help="3D console port")
    s.add_argument("--archive", type=Path, default=Path("runs") / "archive.sqlite", help="SQLite archive")
    s.add_argument("--token-file", type=Path, help="file holding the operator token (when ACS_TOKEN is unset)")
    s.add_argument("--warp", default="1", help="initial warp: 0, 1, 10, 100, 1000 or max")
    s.add_argument("--seed", type=int, help="override the scenario's seed")
    s.add_argument("--quiet", action="store_true", help="log warnings only")
