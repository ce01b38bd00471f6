"""`acs`: the command-line entry point.

    acs run SCENARIO [--seed N] [--out DIR]   headless run; exit 0 pass, 1 expectation failed, 2 bad input
    acs bench [NAME ...] [--reference PYTHON] speed, as real-time ratios
    acs serve [--scenario FILE] [--host H] [--port P] [--viser-port V] [--archive PATH]
                                              the live operations console
"""
from __future__ import annotations

import argparse
import os
import signal
import sys
from pathlib import Path

EXIT_OK, EXIT_EXPECTATION, EXIT_BAD_INPUT = 0, 1, 2
REPO = Path(__file__).resolve().parent.parent
DEFAULT_SCENARIO = REPO / "scenarios" / "sdo_inertial_slew.yaml"


def _progress_bar(total_s: float):
    """A progress bar on a terminal; nothing in CI or when piped."""
    if os.environ.get("CI") or not sys.stderr.isatty():
        return None, lambda: None
    from tqdm import tqdm

    bar = tqdm(total=round(total_s), unit="sim s", dynamic_ncols=True, leave=False)

    def update(t_s: float) -> None:
        bar.update(round(t_s) - bar.n)

    return update, bar.close


def run_headless(scenario_path: str | Path, seed: int | None, out_dir: str | Path) -> int:
    """Run a scenario file and write telemetry.csv, events.csv and archive.sqlite
    into out_dir. Returns the process exit code."""
    from server.archive import Archive, ArchiveError
    from sim.events import CsvEventWriter
    from sim.runner import Listener, Runner
    from sim.scenario import ScenarioError, load_scenario
    from sim.telemetry import CsvTelemetryWriter, Layout
    from sim.telemetry_fields import names_for

    try:
        scenario, sc = load_scenario(scenario_path)
    except ScenarioError as err:
        print(f"error: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    seed = scenario.seed if seed is None else seed
    layout = Layout(scenario.recorded_fields(sc), names_for(sc))
    try:
        archive = Archive(out / "archive.sqlite")
    except ArchiveError as err:
        print(f"error: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT

    with open(out / "telemetry.csv", "w", newline="") as tlm_file, \
            open(out / "events.csv", "w", newline="") as ev_file:
        tlm = CsvTelemetryWriter(tlm_file, layout)
        events = CsvEventWriter(ev_file, scenario.epoch_utc)

        class Files(Listener):
            def on_event(self, e):
                events.write(e)

            def on_telemetry(self, frame):
                tlm.write(frame)

        recorder = archive.start_run(scenario, seed, layout.fields)
        update, close = _progress_bar(scenario.duration_s)
        try:
            result = Runner(scenario, sc, seed, [Files(), recorder]).run(progress=update)
        finally:
            close()
        recorder.finish("passed" if result.passed else "failed")
        archive.close()

    for e in result.expectations:
        print(f"{'PASS' if e.ok else 'FAIL'}  {e.description}: {e.measured}")
    print(f"wrote {out / 'telemetry.csv'}, {out / 'events.csv'}, {out / 'archive.sqlite'}")
    return EXIT_OK if result.passed else EXIT_EXPECTATION


def _cmd_run(args) -> int:
    # `acs run ... | head`: when the reader leaves, end quietly as Unix tools do
    # (killed by SIGPIPE) rather than with a traceback. Only here: the server must
    # keep Python's default, or a client closing its socket would kill it.
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    out = args.out or Path("out") / Path(args.scenario).stem
    return run_headless(args.scenario, args.seed, out)


def _cmd_serve(args) -> int:
    from server.serve import main as serve_main

    return serve_main(args)


def _cmd_bench(args) -> int:
    from server.bench import main as bench_main

    return bench_main(args)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="acs", description="Spacecraft attitude-control simulator")
    sub = p.add_subparsers(dest="command", required=True)

    r = sub.add_parser("run", help="run a scenario file headless")
    r.add_argument("scenario", help="scenario YAML file")
    r.add_argument("--seed", type=int, help="override the scenario's seed")
    r.add_argument("--out", type=Path, help="output directory (default: out/<scenario name>)")
    r.set_defaults(func=_cmd_run)

    b = sub.add_parser("bench", help="speed benchmarks, as real-time ratios")
    b.add_argument("names", nargs="*", help="benchmarks to run (default: all)")
    b.add_argument("--reference", metavar="PYTHON",
                   help="python of a virtual environment with Basilisk (pip install bsk): run the reference "
                        "benchmark interleaved with ours and print the ratio")
    b.add_argument("--reference-script", type=Path,
                   default=REPO.parent / "shared" / "bench" / "basilisk_reference.py")
    b.add_argument("--repeat", type=int, default=3, help="runs of each; the median counts")
    b.add_argument("--startup", action="store_true", help="also time cold and warm starts of `acs run`")
    b.set_defaults(func=_cmd_bench)

    s = sub.add_parser("serve", help="run the live operations console (3D console + REST/WebSocket API)")
    from server.serve import add_arguments

    add_arguments(s)
    s.set_defaults(func=_cmd_serve)
    return p


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
