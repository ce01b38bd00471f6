"""Speed and load of the live console (issue 7), against a real `acs serve`
started here on 127.0.0.1 only. Every loop is bounded in count and time.

    python -m server.loadtest latency [--trials 40]           command-to-telemetry latency at warp 1
    python -m server.loadtest warp [--clients 5] [--seconds 30] [--ws]
                                                              real-time ratio at max warp with 5 browsers
    python -m server.loadtest soak [--clients 20] [--seconds 600]
                                                              memory and lag with 20 WebSocket clients

`warp` opens real browser pages (Debian's chromium via Playwright) on the 3D
console and each also subscribes to the telemetry stream at 10 Hz; --ws uses
plain WebSocket clients instead of browsers.
"""
from __future__ import annotations

import argparse
import contextlib
import json
import os
import random
import socket
import statistics
import subprocess
import sys
import threading
import time
import urllib.request
from pathlib import Path

from websockets.sync.client import connect

TOKEN = "loadtest-token"
ACS = Path(sys.executable).parent / "acs"
# slews are the load: the run starts in Inertial (the default console run starts in SunAcq)
INERTIAL_SCENARIO = Path(__file__).resolve().parent.parent / "scenarios" / "live_sdo_inertial.yaml"
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--no-first-run"]
# two unit quaternions 1 deg apart about Z: the latency probe alternates between them
TARGETS = ([1.0, 0.0, 0.0, 0.0], [0.9999619230641713, 0.0, 0.0, 0.008726535498373935])


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Served:
    """An `acs serve` subprocess on free loopback ports, with a small REST client."""

    def __init__(self, archive: Path):
        self.api, self.gui = _free_port(), _free_port()
        self.proc = subprocess.Popen([str(ACS), "serve", "--scenario", str(INERTIAL_SCENARIO), "--archive", str(archive),
                                      "--port", str(self.api),
                                      "--viser-port", str(self.gui), "--quiet"], stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL, env=dict(os.environ, ACS_TOKEN=TOKEN))
        self.base, self.console = f"http://127.0.0.1:{self.api}", f"http://127.0.0.1:{self.gui}"
        self.ws = f"ws://127.0.0.1:{self.api}"
        deadline = time.monotonic() + 180
        while time.monotonic() < deadline:
            with contextlib.suppress(OSError):
                self.get("/api/telemetry/latest")
                return
            time.sleep(0.2)
        self.stop()
        raise RuntimeError("acs serve did not come up within 180 s")

    def get(self, path: str):
        with urllib.request.urlopen(self.base + path, timeout=5) as r:
            return json.load(r)

    def post(self, path: str, body: dict | None = None):
        req = urllib.request.Request(self.base + path, data=json.dumps(body or {}).encode(), method="POST",
                                     headers={"Authorization": f"Bearer {TOKEN}", "Content-Type": "application/json"})
        with urllib.request.urlopen(req, timeout=10) as r:
            return json.load(r)

    def rss_mib(self) -> float:
        for line in Path(f"/proc/{self.proc.pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
        return float("nan")

    def stop(self) -> None:
        self.proc.terminate()
        try:
            self.proc.wait(20)
        except subprocess.TimeoutExpired:
            self.proc.kill()


# -- latency ---------------------------------------------------------------------------------

def latency(served: Served, trials: int) -> dict:
    """Wall time from POST /api/commands to the first telemetry frame on the
    stream whose target q_RN is the commanded one."""
    fields = ",".join(f"q_RN_{a}" for a in "wxyz")
    samples, rng = [], random.Random(7)
    with connect(f"{served.ws}/api/telemetry/stream?fields={fields}&rate_hz=50") as ws:
        ws.recv(timeout=10)
        for i in range(trials):
            target = TARGETS[(i + 1) % 2]
            time.sleep(rng.uniform(0.3, 0.7))   # random phase against the 200 ms control cycle
            t0 = time.monotonic()
            served.post("/api/commands", {"command": {"type": "set_target_quaternion", "q_RN": target}})
            while time.monotonic() - t0 < 5.0:
                msg = json.loads(ws.recv(timeout=5))
                frame = msg.get("frame", {})
                if msg["type"] == "telemetry" and abs(frame.get("q_RN_z", -1) - target[3]) < 1e-12:
                    samples.append(time.monotonic() - t0)
                    break
    samples.sort()
    return {"trials": len(samples), "median_ms": 1e3 * statistics.median(samples),
            "p90_ms": 1e3 * samples[int(0.9 * (len(samples) - 1))], "max_ms": 1e3 * samples[-1]}


# -- clients ---------------------------------------------------------------------------------------

class StreamClients:
    """n WebSocket clients on /api/telemetry/stream, each in its own thread."""

    def __init__(self, served: Served, n: int, rate_hz: float, fields: str = ""):
        self.counts = [0] * n
        self.errors: list[str] = []
        self._stop = threading.Event()
        url = f"{served.ws}/api/telemetry/stream?rate_hz={rate_hz}&fields={fields}"
        self.threads = [threading.Thread(target=self._run, args=(url, i), daemon=True) for i in range(n)]
        for t in self.threads:
            t.start()

    def _run(self, url: str, i: int) -> None:
        try:
            with connect(url, max_size=None) as ws:
                while not self._stop.is_set():
                    with contextlib.suppress(TimeoutError):
                        ws.recv(timeout=1)
                        self.counts[i] += 1
        except Exception as err:   # reported, not raised: one client's failure is a result
            self.errors.append(f"client {i}: {err}")

    def stop(self) -> None:
        self._stop.set()
        for t in self.threads:
            t.join(5)


@contextlib.contextmanager
def browsers(url: str, n: int):
    """n real browser pages on the 3D console (one Chromium, one context each)."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path="/usr/bin/chromium", args=CHROMIUM_ARGS)
        pages = []
        for _ in range(n):
            page = browser.new_context().new_page()
            page.goto(url)
            pages.append(page)
        for page in pages:
            page.get_by_text("Sim UTC").first.wait_for(timeout=60_000)
        try:
            yield pages
        finally:
            browser.close()


def _ratio_over(served: Served, seconds: float) -> tuple[float, float]:
    """(sim s per wall s over the window, worst lag_s seen)."""
    a, w0 = served.get("/api/pacing"), time.monotonic()
    worst = 0.0
    while time.monotonic() - w0 < seconds:
        time.sleep(1.0)
        worst = max(worst, served.get("/api/pacing")["lag_s"])
    b, w1 = served.get("/api/pacing"), time.monotonic()
    return (b["t_s"] - a["t_s"]) / (w1 - w0), worst


def warp(served: Served, clients: int, seconds: float, real_browsers: bool) -> dict:
    served.post("/api/pacing", {"warp": "max"})
    time.sleep(2.0)
    alone, _ = _ratio_over(served, seconds / 3)
    streams = StreamClients(served, clients, 10.0)
    pages = browsers(served.console, clients) if real_browsers else contextlib.nullcontext()
    with pages:
        before = list(streams.counts)
        loaded, _ = _ratio_over(served, seconds)
        received = [b - a for a, b in zip(before, streams.counts)]
    streams.stop()
    served.post("/api/pacing", {"warp": 1})
    return {"clients": clients, "browsers": real_browsers, "ratio_alone": alone, "ratio_loaded": loaded,
            "stream_frames_per_client_s": [round(c / seconds, 1) for c in received], "errors": streams.errors}


def soak(served: Served, clients: int, seconds: float) -> dict:
    streams = StreamClients(served, clients, 10.0)
    time.sleep(2.0)
    base, t0, rows = list(streams.counts), time.monotonic(), []
    while time.monotonic() - t0 < seconds:
        time.sleep(min(10.0, seconds / 12))
        p = served.get("/api/pacing")
        rows.append((round(time.monotonic() - t0, 1), round(served.rss_mib(), 1), p["lag_s"], p["realtime_ratio"]))
        print(f"  t={rows[-1][0]:7.1f} s  rss={rows[-1][1]:7.1f} MiB  lag={rows[-1][2]:.4f} s  "
              f"ratio={rows[-1][3]:.3f}", flush=True)
    streams.stop()
    # the live window (1200 frames) fills in 240 s at warp 1: compare the second half only
    first, last = rows[len(rows) // 2], rows[-1]
    return {"clients": clients, "seconds": seconds, "rss_mib_half_time": first[1], "rss_mib_end": last[1],
            "max_lag_s": max(r[2] for r in rows), "lag_end_s": last[2],
            "stream_frames_per_client_s": [round((c - b) / seconds, 2) for b, c in zip(base, streams.counts)],
            "errors": streams.errors}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m server.loadtest", description=__doc__.split("\n\n")[0])
    ap.add_argument("what", choices=["latency", "warp", "soak"])
    ap.add_argument("--trials", type=int, default=40)
    ap.add_argument("--clients", type=int)
    ap.add_argument("--seconds", type=float)
    ap.add_argument("--ws", action="store_true", help="warp: WebSocket clients instead of browser pages")
    ap.add_argument("--archive", type=Path, default=Path("out") / "loadtest" / "archive.sqlite")
    args = ap.parse_args(argv)
    args.archive.parent.mkdir(parents=True, exist_ok=True)
    args.archive.unlink(missing_ok=True)
    served = Served(args.archive)
    try:
        if args.what == "latency":
            result = latency(served, args.trials)
        elif args.what == "warp":
            result = warp(served, args.clients or 5, args.seconds or 30.0, not args.ws)
        else:
            result = soak(served, args.clients or 20, args.seconds or 600.0)
    finally:
        served.stop()
    print(json.dumps({args.what: result}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
