"""End to end in a real browser: `acs serve` as a user starts it, Debian's
Chromium driven by Playwright. It opens the console, unlocks the operator
panel with the token, commands a slew from the generated form, and sees the
flight software take it (status panel and plots update), then pauses. The
screenshot is kept as a test artifact (out/test-artifacts/console.png).
"""
from __future__ import annotations

import json
import os
import re
import shutil
import socket
import sqlite3
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

from sim.commands import COMMAND_TYPES

REPO = Path(__file__).resolve().parent.parent
ACS = Path(sys.executable).parent / "acs"
ARTIFACTS = REPO / "out" / "test-artifacts"
CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--no-first-run"]
TOKEN = "browser-test-token"
SLEW_Q = [0.9961946980917455, 0.023293352046538898, 0.046586704093077795, 0.0698800561396167]  # 10 deg

from playwright import sync_api as playwright  # a test dependency (pyproject): missing is an error
if not Path(CHROMIUM).exists():   # make test installs it: a missing browser is an error, never a skip
    raise RuntimeError(f"Chromium is missing at {CHROMIUM}: `make test` installs Debian's chromium")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _get(url: str):
    with urllib.request.urlopen(url, timeout=3) as r:
        return json.load(r)


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    api, gui = _free_port(), _free_port()
    archive = tmp_path_factory.mktemp("browser") / "archive.sqlite"
    proc = subprocess.Popen([str(ACS), "serve", "--archive", str(archive), "--port", str(api),
                             "--viser-port", str(gui), "--quiet"], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, env=dict(os.environ, ACS_TOKEN=TOKEN))
    base = f"http://127.0.0.1:{api}"
    try:
        deadline = time.monotonic() + 180
        while time.monotonic() < deadline:
            try:
                _get(f"{base}/api/telemetry/latest")
                break
            except OSError:
                assert proc.poll() is None, proc.stdout.read()
                time.sleep(0.2)
        yield base, f"http://127.0.0.1:{gui}"
    finally:
        proc.terminate()
        out, _ = proc.communicate(timeout=30)
    # SIGTERM: uvicorn ends the lifespan, which stops the console and the simulation
    # cleanly (the run is archived as stopped), then re-raises the signal
    assert proc.returncode in (0, -15), out
    assert TOKEN not in out, "the operator token appeared in the service's output"
    db = sqlite3.connect(archive)
    assert db.execute("SELECT status FROM runs").fetchall() == [("stopped",)]
    assert TOKEN.encode() not in archive.read_bytes()
    db.close()


def _field(page, label: str):
    """The input beside a viser label (viser's <label for> does not name the input's id)."""
    row = page.locator("div.mantine-Flex-root", has=page.locator(f"label:has-text('{label}')"))
    return row.locator("input, textarea").first


def _choose(page, label: str, option: str) -> None:
    """Pick an option of a viser dropdown."""
    _field(page, label).click()
    page.get_by_role("option", name=option, exact=True).click()


def _canvas_png(page, title: str) -> bytes:
    return page.locator("div.uplot", has_text=title).locator("canvas").first.screenshot()


def test_unlock_command_a_slew_and_watch_it(served):
    base, console = served
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    with playwright.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1600, "height": 1000})
        page.goto(console)
        unlock = page.get_by_role("button", name="Unlock")
        unlock.wait_for(timeout=60_000)
        assert page.get_by_role("button", name="Send").count() == 0       # locked: no command form
        page.get_by_text("SUNACQ").first.wait_for(timeout=30_000)        # the default run starts in SunAcq

        _field(page, "Operator token").fill("not-the-token")
        unlock.click()
        page.get_by_text("Wrong token").wait_for(timeout=10_000)
        assert page.get_by_role("button", name="Send").count() == 0
        _field(page, "Operator token").fill(TOKEN)
        unlock.click()
        send = page.get_by_role("button", name="Send")
        send.wait_for(timeout=10_000)

        # SunAcq -> Inertial: a forced mode change, confirmed in the modal; the mode
        # panel shows the transition once the flight software has taken it
        _choose(page, "Command", "set_mode")
        _choose(page, "mode", "INERTIAL")
        page.get_by_role("button", name="Send").click()
        page.get_by_text("Send hazardous command set_mode?").first.wait_for(timeout=10_000)
        page.get_by_role("button", name="Confirm").click()
        page.get_by_text("Command 1 queued").wait_for(timeout=10_000)
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline and _get(f"{base}/api/telemetry/latest")["mode"] != "INERTIAL":
            time.sleep(0.1)
        assert _get(f"{base}/api/telemetry/latest")["mode"] == "INERTIAL"
        page.get_by_role("tab", name="Mode").click()
        page.get_by_text("SUNACQ -> INERTIAL (ground)").first.wait_for(timeout=10_000)   # the mode history
        page.screenshot(path=str(ARTIFACTS / "console-mode.png"))
        page.get_by_role("tab", name="Plots").click()

        _choose(page, "Command", "set_target_quaternion")
        send = page.get_by_role("button", name="Send")
        before = _canvas_png(page, "Attitude error")
        _field(page, "q_RN").fill(json.dumps(SLEW_Q))
        send.click()
        page.get_by_text("Command 2 queued").wait_for(timeout=10_000)

        # the flight software took it at a control cycle: lifecycle and telemetry say so
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline:
            history = _get(f"{base}/api/commands")
            if history and "executing" in [s["name"] for s in history[-1]["stages"]]:
                break
            time.sleep(0.1)
        assert history[-1]["source"].startswith("console:") and history[-1]["args"]["q_RN"] == SLEW_Q
        latest = _get(f"{base}/api/telemetry/latest")
        assert latest["att_err_arcsec"] > 30_000          # 10 deg away from the new target

        page.get_by_role("button", name="10×", exact=True).click()
        page.get_by_text("warp × 10").wait_for(timeout=10_000)
        time.sleep(1.5)   # let the plots take a few rolling-window updates (2 Hz) for the picture
        assert _canvas_png(page, "Attitude error") != before
        page.get_by_role("tab", name="Commands").click()
        page.get_by_text("rest:").or_(page.get_by_text("console:")).first.wait_for(timeout=10_000)
        page.screenshot(path=str(ARTIFACTS / "console.png"))

        page.get_by_role("button", name="Pause", exact=True).click()
        page.get_by_text("warp paused").wait_for(timeout=10_000)
        assert _get(f"{base}/api/pacing")["paused"]

        # a hazardous command asks for confirmation in a modal; cancelling sends nothing
        hazardous = [name for name, model in COMMAND_TYPES.items() if model.hazardous]
        if hazardous:
            n_before = len(_get(f"{base}/api/commands"))
            _choose(page, "Command", hazardous[0])
            page.get_by_role("button", name="Send").click()
            page.get_by_text(f"Send hazardous command {hazardous[0]}?").first.wait_for(timeout=10_000)
            page.screenshot(path=str(ARTIFACTS / "console-confirm.png"))
            page.get_by_role("button", name="Cancel").click()
            time.sleep(0.5)   # what is tested is that nothing arrives
            assert len(_get(f"{base}/api/commands")) == n_before

        # the time conductor: this client replays the archived run, the others stay live
        page.get_by_role("tab", name="Replay").click()
        _field(page, "Time").click()
        page.get_by_role("option", name="historical").click()
        page.get_by_role("button", name="Load run").click()
        page.get_by_text("HISTORICAL").first.wait_for(timeout=10_000)
        assert page.get_by_text(re.compile("mode (SUNACQ|INERTIAL)")).count() >= 1
        browser.close()
