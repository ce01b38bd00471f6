"""The shared panels every client sees: status (mode, sim UTC, warp, lag),
live plots with rolling windows, mode history, command history with
lifecycle, events and alarms. They read the service's hub, never the Runner.
"""
from __future__ import annotations

import collections

import numpy as np

PLOT_POINTS = 600
COLORS = ("#e6194b", "#3cb44b", "#4363d8", "#f58231", "#911eb4", "#42d4f4")
SEVERITY_MARK = {"info": "", "warning": "**WARN**", "error": "**ERROR**"}
ARCSEC_PER_RAD = 206264.80624709636

# (title, [(label, telemetry field)], display unit, factor from the field's SI unit)
PLOTS = [
    ("Attitude error", [("att_err", "att_err_arcsec"), ("est_err", "est_err_arcsec")], "arcsec", 1.0),
    ("Body rates", [(a, f"omega_BN_B_{a}_rad_s") for a in "xyz"], "arcsec/s", ARCSEC_PER_RAD),
    ("Wheel speeds", [(f"W{i}", f"wheel_speed_{i}_rpm") for i in range(1, 5)], "rpm", 1.0),
    ("System momentum", [("|H|", "h_total_Nms")] + [(a, f"h_total_N_{a}_Nms") for a in "xyz"], "N m s", 1.0),
    # the PID's integral torque is K_i times this integral of the attitude error
    ("Integral of attitude error (integral torque / K_i)", [(a, f"integral_B_{a}_rad_s") for a in "xyz"],
     "arcsec s", ARCSEC_PER_RAD),
    ("Sun angle", [("sun", "sun_angle_deg")], "deg", 1.0),
]


def _series(labels: list[str], unit: str) -> tuple:
    return ({"label": "t (s)"},) + tuple(
        {"label": lab, "stroke": COLORS[i % len(COLORS)], "width": 1.5} for i, lab in enumerate(labels))


class Plots:
    def __init__(self, gui):
        self.handles = []
        for title, series, unit, factor in PLOTS:
            empty = tuple(np.zeros(1) for _ in range(len(series) + 1))
            h = gui.add_uplot(empty, _series([s[0] for s in series], unit), title=f"{title} [{unit}]", aspect=2.0,
                              scales={"x": {"time": False}}, axes=({}, {"size": 64}), visible=False)
            self.handles.append((h, series, factor))

    def update(self, window: list[dict]) -> None:
        frames = window[-PLOT_POINTS:]
        if len(frames) < 2:
            return
        t = np.array([f["t_s"] for f in frames], float)
        for handle, series, factor in self.handles:
            fields = [s[1] for s in series]
            present = all(f in frames[-1] for f in fields)
            handle.visible = present
            if present:
                handle.data = (t,) + tuple(factor * np.array([f.get(name, np.nan) for f in frames], float)
                                           for name in fields)


def status_markdown(frame: dict | None, status: dict, run: dict) -> str:
    if frame is None:
        return "**Starting the simulation…**"
    warp = "paused" if status["paused"] else f"× {status['warp']}"
    lag = frame.get("lag_s", 0.0)
    ended = "  \n**Run ended** — load another run." if run["finished"] else ""
    return (f"### {frame['mode']}\n"
            f"**Sim UTC** {frame['utc']}  \n**t** {frame['t_s']:.1f} s   **warp** {warp}   "
            f"**lag** {lag:.3f} s  \n**running at** {status['realtime_ratio']:.1f}× real time  \n"
            f"{pointing_line(frame)}  \n"
            f"run {run['run_id']}: {run['name']} (seed {run['seed']}){ended}")


CAUSES = {0.0: "ground", 1.0: "FDC", 2.0: "autonomous"}   # telemetry mode_cause (sim/telemetry_fields.py)


def pointing_line(frame: dict) -> str:
    """What the mode points by: the CSS modes hold the Sun (the attitude target
    means nothing there), the others their target attitude."""
    if frame["mode"] in ("SUNACQ", "SAFEHOLD"):
        return f"**Sun angle** {frame.get('sun_angle_deg', float('nan')):.2f} deg"
    return f"**att err** {frame.get('att_err_arcsec', float('nan')):.1f} arcsec"


class ModeHistory:
    """Mode transitions seen in the live frames (the engine's own mode events
    also appear in the event log)."""

    def __init__(self):
        self.entries: collections.deque = collections.deque(maxlen=15)
        self._last = None

    def update(self, frame: dict | None) -> None:
        if frame is None:
            return
        key = (frame["run_id"], frame["mode"])
        if key != self._last:
            change = frame["mode"]
            if self._last is not None and self._last[0] == key[0]:
                cause = CAUSES.get(frame.get("mode_cause"), "")
                change = f"{self._last[1]} -> {frame['mode']}" + (f" ({cause})" if cause else "")
            self._last = key
            self.entries.appendleft(f"- {frame['utc']} (t = {frame['t_s']:.1f} s): **{change}**")

    def markdown(self) -> str:
        return "\n".join(self.entries) or "—"


def commands_markdown(commands: list[dict], n: int = 8) -> str:
    if not commands:
        return "No commands yet."
    lines = ["| id | command | from | lifecycle (sim s) |", "|---|---|---|---|"]
    for c in reversed(commands[-n:]):
        stages = " → ".join(f"{s['name']} {s['t_s']:.1f}" + (f" ({s['reason']})" if s["reason"] else "")
                            for s in c["stages"])
        lines.append(f"| {c['id']} | {c['type']} | {c['source']} | {stages} |")
    return "\n".join(lines)


def events_markdown(events: list[dict], n: int = 12) -> str:
    if not events:
        return "No events yet."
    return "\n".join(f"- {SEVERITY_MARK.get(e['severity'], '')} `{e['utc'][11:23]}` t={e['t_s']:.1f} "
                     f"[{e['source']}] {e['message']}" for e in reversed(events[-n:]))


def alarms_markdown(alarms: list[dict]) -> str:
    if not alarms:
        return "No alarms."
    lines = ["| id | channel | worst | now | t (s) | ack |", "|---|---|---|---|---|---|"]
    for a in reversed(alarms):
        now = a["level"] if a["active"] else "cleared"
        ack = f"✔ {a['acknowledged_by']}" if a["acknowledged"] else "**unacknowledged**"
        lines.append(f"| {a['id']} | {a['channel']} | {a['worst'].upper()} | {now} | {a['t_s']:.1f} | {ack} |")
    return "\n".join(lines)

