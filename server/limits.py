"""Limits with yellow and red bands on key telemetry channels, and the alarms
they raise (latched until an operator acknowledges them, as in YAMCS/COSMOS).

Bands come from the spacecraft definition and the seeds where they can; the
rest are marked as assumptions. A channel absent from telemetry (Sun angle,
until the truth model reports it) is simply not checked.
"""
from __future__ import annotations

import math
import threading
from dataclasses import dataclass, field

NOMINAL, YELLOW, RED = "nominal", "yellow", "red"
_RANK = {NOMINAL: 0, YELLOW: 1, RED: 2}
HYSTERESIS = 0.95


@dataclass(frozen=True)
class Limit:
    channel: str       # telemetry field; the absolute value is compared
    yellow: float
    red: float
    unit: str
    source: str        # where the numbers come from

    def level(self, value: float, previous: str = NOMINAL) -> str:
        """The band of |value|. Leaving a band needs a 5% margin, so that a
        value dithering on a threshold (sensor noise) does not flood the log."""
        v = abs(value)
        red = self.red * (HYSTERESIS if previous == RED else 1.0)
        yellow = self.yellow * (HYSTERESIS if previous in (YELLOW, RED) else 1.0)
        return RED if v >= red else YELLOW if v >= yellow else NOMINAL


def default_limits(sc, n_wheels: int) -> list[Limit]:
    """The console's limit table for a spacecraft definition."""
    g = sc.fsw.inertial
    box_arcsec = math.degrees(g.box_theta_lim_rad) * 3600.0
    att_limit_arcsec = math.degrees(g.attitude_limit_rad) * 3600.0
    rpm_max = sc.wheels.h_max_Nms / sc.wheels.spin_inertia_kgm2 * 60.0 / (2.0 * math.pi)
    limits = [
        Limit("att_err_arcsec", box_arcsec, att_limit_arcsec, "arcsec",
              "yellow: integral torque box (seed 000); red: the controller's attitude limit (spacecraft file)"),
        Limit("h_total_Nms", 60.0, 100.0, "N m s",
              "assumption: about half and 80% of the pyramid's smallest axis capacity (2 x 70 cos 30 = 121 N m s)"),
        Limit("sun_angle_deg", 15.0, 45.0, "deg",
              "seed 001 Safehold: +X within 15 deg of the Sun; 45 deg eclipse-exit discharge risk"),
        Limit("lag_s", 0.5, 2.0, "s", "assumption: the console's own real-time budget"),
    ]
    for i in range(1, n_wheels + 1):
        limits.append(Limit(f"wheel_speed_{i}_rpm", 0.8 * rpm_max, 0.95 * rpm_max, "rpm",
                            f"assumption: 80% / 95% of {rpm_max:.0f} rpm, the speed at the 70 N m s capacity"))
    return limits


@dataclass
class Alarm:
    id: int
    channel: str
    level: str
    value: float
    t_s: float
    utc: str
    active: bool = True          # the channel is still outside its nominal band
    acknowledged: bool = False
    acknowledged_by: str = ""
    worst: str = field(default="")

    def as_dict(self) -> dict:
        return dict(self.__dict__)


class LimitChecker:
    """Checks frames against the limits; raises, escalates and clears alarms.

    `check` runs on the simulation thread; `alarms` and `acknowledge` on API
    threads: the lock keeps them consistent."""

    def __init__(self, limits: list[Limit]):
        self.limits = limits
        self.levels: dict[str, str] = {}
        self._alarms: dict[int, Alarm] = {}
        self._open: dict[str, Alarm] = {}   # channel -> its active alarm
        self._next_id = 1
        self._lock = threading.Lock()

    def check(self, frame: dict, utc: str) -> list[tuple[str, Limit, str, float]]:
        """Returns the transitions (old level, limit, new level, value) of this frame."""
        changes = []
        with self._lock:
            for lim in self.limits:
                value = frame.get(lim.channel)
                if not isinstance(value, (int, float)) or math.isnan(value):
                    continue
                old = self.levels.get(lim.channel, NOMINAL)
                new = lim.level(value, old)
                self.levels[lim.channel] = new
                if new != old:
                    changes.append((old, lim, new, float(value)))
                    self._update_alarm(lim.channel, old, new, float(value), frame.get("t_s", 0.0), utc)
        return changes

    def _update_alarm(self, channel: str, old: str, new: str, value: float, t_s: float, utc: str) -> None:
        alarm = self._open.get(channel)
        if new == NOMINAL:
            if alarm is not None:
                alarm.active = False
                del self._open[channel]
                self._drop_if_done(alarm)
            return
        if alarm is None or _RANK[new] > _RANK[alarm.worst]:
            # a new alarm, or an escalation that needs a fresh acknowledgement
            if alarm is not None:
                alarm.active = False
                self._drop_if_done(alarm)
            alarm = Alarm(self._next_id, channel, new, value, t_s, utc, worst=new)
            self._next_id += 1
            self._alarms[alarm.id] = alarm
            self._open[channel] = alarm
        else:
            alarm.level = new

    def _drop_if_done(self, alarm: Alarm) -> None:
        if alarm.acknowledged and not alarm.active:
            self._alarms.pop(alarm.id, None)

    def alarms(self) -> list[dict]:
        with self._lock:
            return [a.as_dict() for a in self._alarms.values()]

    def acknowledge(self, alarm_id: int, who: str) -> dict | None:
        with self._lock:
            alarm = self._alarms.get(alarm_id)
            if alarm is None:
                return None
            alarm.acknowledged, alarm.acknowledged_by = True, who
            out = alarm.as_dict()
            self._drop_if_done(alarm)
            return out

    def table(self) -> list[dict]:
        with self._lock:
            return [dict(lim.__dict__, level=self.levels.get(lim.channel)) for lim in self.limits]
