"""A run shown as it happens: foxglove-sdk's WebSocket server on the log's channels, paced in real time.

:class:`Pacer` holds the run to the wall clock (``rate`` times real time) and,
when live, hands the pending samples to the channels every :data:`SEND_EVERY_S`
of simulated time, so a viewer sees the arm move smoothly rather than in
batches. The server (:func:`serve`) is bound to 127.0.0.1 and streams every
channel of the log (the same messages the file gets); a viewer that connects
after the start still sees the arm and the workcell because the live log
repeats the whole scene every :data:`SCENE_EVERY_S` (those repeats are in the
file too: the same entities, replaced by themselves).

The pacer is called from the run log's state sampling, in the loop's thread.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Final

import foxglove
from foxglove import Capability, Context, WebSocketServer

SEND_EVERY_S: Final = 0.02
"""Simulated time between hand-overs of the pending samples to a live viewer [s] (50 Hz)."""
SCENE_EVERY_S: Final = 1.0
"""Simulated time between repeats of the whole scene for viewers that connect late [s]."""
LIVE_HOST: Final = "127.0.0.1"
DEFAULT_PORT: Final = 8765
"""Foxglove's usual WebSocket port."""
MAX_LAG_S: Final = 0.1
"""A run more than this behind the wall clock (a REPL waiting at its prompt, a slow step) is not
hurried to catch up: the pace restarts from where it is [s]."""


class Pacer:
    """Holds a run to ``rate`` times real time; when live, also sends and repeats on schedule.

    Args:
        rate: Simulated seconds per wall-clock second (1: real time; 0.5: half speed).
        send: Hands the pending samples to the channels (None: not live).
        repeat_scene: Sends the whole scene again at a simulated time [s] (None: not live).
        clock: Wall clock [s] (for tests).
        sleep: Sleeps [s] (for tests).
    """

    def __init__(
        self,
        rate: float,
        send: Callable[[], None] | None = None,
        repeat_scene: Callable[[float], None] | None = None,
        clock: Callable[[], float] = time.perf_counter,
        sleep: Callable[[float], None] = time.sleep,
    ):
        if not rate > 0:
            raise ValueError(f"the pace rate must be positive, not {rate}")
        self._rate = rate
        self._send = send
        self._repeat_scene = repeat_scene
        self._clock = clock
        self._sleep = sleep
        self._start: float | None = None
        self._send_due = 0.0
        self._scene_due = SCENE_EVERY_S
        self.on_time: Callable[[int], None] | None = None
        """Called with each hand-over's simulated time [ns] (the server's clock)."""

    def tick(self, t: float) -> None:
        """At a state sample of simulated time ``t`` [s]: send if due, then wait for the wall clock."""
        now = self._clock()
        if self._start is None:
            self._start = now - t / self._rate
        if self._send is not None and t >= self._send_due:
            self._send_due = t + SEND_EVERY_S
            if self._repeat_scene is not None and t >= self._scene_due:
                self._scene_due = t + SCENE_EVERY_S
                self._repeat_scene(t)
            self._send()
            if self.on_time is not None:
                self.on_time(round(t * 1e9))
        ahead = self._start + t / self._rate - now
        if ahead > 0:
            self._sleep(ahead)
        elif ahead < -MAX_LAG_S:
            self._start = now - t / self._rate


def serve(context: Context, port: int, name: str) -> WebSocketServer:
    """Start foxglove-sdk's WebSocket server on 127.0.0.1 for ``context``'s channels.

    Args:
        context: The run log's context.
        port: TCP port; 0 for one the system picks (``server.port`` tells which).
        name: Server name shown by the viewer.
    """
    return foxglove.start_server(
        name=name, host=LIVE_HOST, port=port, context=context, capabilities=[Capability.Time]
    )
