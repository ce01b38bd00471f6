"""The time conductor of one client (as in Open MCT): live, or historical
replay of an archived run. In historical mode the client's own scene nodes
shadow the shared spacecraft (viser: a client-scoped node under a server
node's name replaces it for that client only), so replaying never changes
what other operators see. Reads the archive on a read-only connection.
"""
from __future__ import annotations

import numpy as np

from server.api.deps import reader

QUATS = ("q_BN", "q_est_BN", "q_RN")
NODES = {"q_BN": "/sdo", "q_est_BN": "/estimate", "q_RN": "/target"}
MAX_POINTS = 2000


class Replay:
    def __init__(self, client, service, container):
        self.client, self.service = client, service
        self.data: dict | None = None
        self.shadows: dict = {}
        gui = client.gui
        with container:
            self.mode = gui.add_dropdown("Time", ["live", "historical"], initial_value="live")
            self.run_pick = gui.add_dropdown("Run", ["—"], visible=False)
            self.load = gui.add_button("Load run", visible=False)
            self.slider = gui.add_slider("t (s)", min=0.0, max=1.0, step=1.0, initial_value=0.0, visible=False)
            self.info = gui.add_markdown("Watching the live run.")
            self.plot = gui.add_uplot((np.zeros(1), np.zeros(1)), ({"label": "t (s)"},
                                      {"label": "att_err [arcsec]", "stroke": "#e6194b"}),
                                      title="Archived attitude error [arcsec]", aspect=2.0,
                                      scales={"x": {"time": False}}, visible=False)
        self.mode.on_update(lambda _: self._switch())
        self.load.on_click(lambda _: self._load())
        self.slider.on_update(lambda _: self._show(self.slider.value))

    def _switch(self) -> None:
        historical = self.mode.value == "historical"
        for h in (self.run_pick, self.load, self.slider):
            h.visible = historical
        if historical:
            runs = reader(self.service.archive_path).runs()
            self.run_pick.options = [f"{r['id']}: {r['name']} ({r['status']})" for r in reversed(runs)] or ["—"]
            self.info.content = "Pick a run and load it."
        else:
            self._clear()
            self.info.content = "Watching the live run."

    def _load(self) -> None:
        if self.run_pick.value == "—":
            return
        run_id = int(self.run_pick.value.split(":")[0])
        if run_id == self.service.run.run_id:
            self.service.flush_archive()
        archive = reader(self.service.archive_path)
        fields = ["t_s", "mode", "att_err_arcsec"] + [f"{q}_{a}" for q in QUATS for a in "wxyz"]
        cols = archive.telemetry(run_id, fields)
        n = len(cols["t_s"])
        if n == 0:
            self.info.content = f"Run {run_id} recorded no telemetry."
            return
        stride = max(1, -(-n // MAX_POINTS))
        self.data = {k: np.asarray(v[::stride]) if k != "mode" else v[::stride] for k, v in cols.items()}
        t = self.data["t_s"].astype(float)
        self.plot.data = (t, self.data["att_err_arcsec"].astype(float))
        self.plot.visible = True
        self.slider.max = float(t[-1]) if t[-1] > 0 else 1.0
        self.slider.step = max(float(t[1] - t[0]), 0.2) if len(t) > 1 else 1.0
        self.slider.value = float(t[-1])
        self._show(float(t[-1]))

    def _show(self, t_s: float) -> None:
        if self.data is None or self.mode.value != "historical":
            return
        t = self.data["t_s"].astype(float)
        i = int(np.clip(np.searchsorted(t, t_s), 0, len(t) - 1))
        for q in QUATS:
            wxyz = tuple(float(self.data[f"{q}_{a}"][i]) for a in "wxyz")
            node = self.shadows.get(q)
            if node is None:
                self.shadows[q] = self.client.scene.add_frame(NODES[q], show_axes=False, wxyz=wxyz)
            else:
                node.wxyz = wxyz
        self.info.content = (f"**HISTORICAL** run {self.run_pick.value}  \nt = {t[i]:.1f} s, "
                             f"mode {self.data['mode'][i]}, att err {float(self.data['att_err_arcsec'][i]):.1f} arcsec")

    def _clear(self) -> None:
        for node in self.shadows.values():
            node.remove()
        self.shadows.clear()
        self.plot.visible = False
        self.data = None
