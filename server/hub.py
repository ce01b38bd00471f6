"""Hand-over from the simulation thread to any number of readers (WebSocket
clients, the viser console) without ever blocking the simulation.

The simulation thread only replaces references and appends to bounded
deques; readers copy what they need. Memory stays flat whatever the number of
clients and however slow they are: a reader that falls behind a feed's window
is told how many items it missed instead of holding them back.
"""
from __future__ import annotations

import asyncio
import collections
import threading
from typing import Any


class Feed:
    """A bounded, numbered log (command stages, events, alarms)."""

    def __init__(self, maxlen: int = 2000):
        self._items: collections.deque[tuple[int, Any]] = collections.deque(maxlen=maxlen)
        self._seq = 0
        self._lock = threading.Lock()

    def append(self, item: Any) -> int:
        with self._lock:
            self._seq += 1
            self._items.append((self._seq, item))
            return self._seq

    @property
    def seq(self) -> int:
        return self._seq

    def since(self, seq: int) -> tuple[list[tuple[int, Any]], int]:
        """Items after `seq`, and how many between were already dropped."""
        with self._lock:
            items = [(s, it) for s, it in self._items if s > seq]
            first = items[0][0] if items else self._seq + 1
            return items, max(0, first - seq - 1)

    def tail(self, n: int) -> list[Any]:
        with self._lock:
            return [it for _, it in list(self._items)[-n:]]


class Hub:
    """The latest live frame, a rolling window of frames, and the feeds,
    with wake-ups for asyncio readers on one event loop."""

    def __init__(self, window: int = 1200):
        self.latest: dict | None = None
        self.frame_seq = 0
        self.window: collections.deque[dict] = collections.deque(maxlen=window)
        self.commands = Feed()
        self.events = Feed()
        self._loop: asyncio.AbstractEventLoop | None = None
        self._changed: asyncio.Event | None = None

    # -- writer side (simulation thread) --------------------------------------
    def publish_frame(self, frame: dict) -> None:
        self.window.append(frame)
        self.latest = frame
        self.frame_seq += 1
        self._wake()

    def publish_command(self, item: dict) -> None:
        self.commands.append(item)
        self._wake()

    def publish_event(self, item: dict) -> None:
        self.events.append(item)
        self._wake()

    def reset_window(self) -> None:
        self.window.clear()
        self.latest = None

    def _wake(self) -> None:
        loop = self._loop
        if loop is not None and not loop.is_closed():
            try:
                loop.call_soon_threadsafe(self._set_changed)
            except RuntimeError:
                pass  # the loop closed between the check and the call: nobody is waiting

    # -- reader side ------------------------------------------------------------
    def attach_loop(self, loop: asyncio.AbstractEventLoop) -> None:
        self._loop = loop
        self._changed = asyncio.Event()

    def _set_changed(self) -> None:
        # Replace the event so each wake-up releases the current waiters once.
        ev, self._changed = self._changed, asyncio.Event()
        ev.set()

    async def wait_change(self, timeout: float) -> None:
        """Returns on the next publication, or after `timeout` seconds."""
        ev = self._changed
        try:
            await asyncio.wait_for(ev.wait(), timeout)
        except TimeoutError:
            pass
