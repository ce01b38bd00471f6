"""The viser operations console: its own server and port beside uvicorn, in
the same process. Every client sees the shared scene and panels; each gets
its own operator panel, locked until it enters the token.

One updater thread feeds the scene (10 Hz) and the panels and plots (2 Hz)
from the service's hub; it never touches the Runner.
"""
from __future__ import annotations

import logging
import threading
import time

import viser

from web.operator import OperatorPanel
from web.panels import ModeHistory, Plots, alarms_markdown, commands_markdown, events_markdown, status_markdown
from web.replay import Replay
from web.scene import SpacecraftScene

log = logging.getLogger("acs.console")
SCENE_HZ = 10.0
PANEL_EVERY = 5          # panels and plots at SCENE_HZ / PANEL_EVERY


class Console:
    def __init__(self, service, token: str, host: str, port: int, scenario_dir):
        self.service, self.token, self.host, self.port = service, token, host, port
        self.scenario_dir = scenario_dir
        self.server: viser.ViserServer | None = None
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self.mode_history = ModeHistory()
        self._shown: dict[str, str] = {}
        self._run_id = None

    @property
    def url(self) -> str:
        host = "127.0.0.1" if self.host in ("0.0.0.0", "::") else self.host
        return f"http://{host}:{self.server.get_port() if self.server else self.port}"

    def start(self) -> None:
        self.server = viser.ViserServer(host=self.host, port=self.port, label="ACS console", verbose=False)
        self._build()
        self.server.on_client_connect(self._on_connect)
        self._thread = threading.Thread(target=self._updater, name="acs-console", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(5.0)
        if self.server is not None:
            self.server.stop()

    # -- layout -------------------------------------------------------------------------------
    def _build(self) -> None:
        gui = self.server.gui
        gui.configure_theme(control_width="large", dark_mode=False, show_logo=False)
        self.scene = SpacecraftScene(self.server, self.service.run.sc)
        with gui.add_folder("Status"):
            self.status_md = gui.add_markdown("**Starting…**")
        self.operator_folder = gui.add_folder("Operator")
        tabs = gui.add_tab_group()
        with tabs.add_tab("Plots"):
            self.plots = Plots(gui)
        with tabs.add_tab("Commands"):
            self.commands_md = gui.add_markdown("")
        with tabs.add_tab("Events"):
            self.events_md = gui.add_markdown("")
        with tabs.add_tab("Alarms"):
            self.alarms_md = gui.add_markdown("")
        with tabs.add_tab("Mode"):
            self.mode_md = gui.add_markdown("")
        self.replay_tab = tabs.add_tab("Replay")

    def _on_connect(self, client) -> None:
        client.camera.position = (8.0, -9.0, 5.5)
        client.camera.look_at = (0.0, 0.0, 0.0)
        OperatorPanel(client, self.service, self.token, self.operator_folder, self.scenario_dir)
        Replay(client, self.service, self.replay_tab)

    # -- updates ------------------------------------------------------------------------------------
    def _updater(self) -> None:
        tick = 0
        while not self._stop.is_set():
            t0 = time.monotonic()
            try:
                self._update(tick % PANEL_EVERY == 0)
            except Exception:   # a display glitch must not end the console
                log.exception("console update failed")
            tick += 1
            self._stop.wait(max(0.0, 1.0 / SCENE_HZ - (time.monotonic() - t0)))

    def _update(self, panels: bool) -> None:
        hub, frame = self.service.hub, self.service.hub.latest
        self.mode_history.update(frame)
        if not self.server.get_clients():
            return   # nobody watching: leave the CPU to the simulation
        if frame is not None:
            if frame["run_id"] != self._run_id:
                self._run_id = frame["run_id"]
                self.scene.reset()
            self.scene.update(frame)
        if not panels:
            return
        run = self.service.run
        self._set("status", self.status_md, status_markdown(frame, self.service.status(), run.info()))
        self._set("commands", self.commands_md, commands_markdown(run.commands()))
        self._set("events", self.events_md, events_markdown(hub.events.tail(12)))
        self._set("alarms", self.alarms_md, alarms_markdown(run.limits.alarms()))
        self._set("mode", self.mode_md, self.mode_history.markdown())
        self.plots.update(list(hub.window))

    def _set(self, key: str, handle, text: str) -> None:
        """Send markdown only when it changed: every update goes to every client."""
        if self._shown.get(key) != text:
            self._shown[key] = text
            handle.content = text
