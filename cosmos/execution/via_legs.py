"""A MOVE's VIA legs judged as its last leg is: a leg that stops getting closer to its point fails.

The monitor judges a goal motion's arrival, and its stall, on the last leg (the target):
:meth:`cosmos.execution.monitor.SegmentMonitor._stalled`. Before it the tool is on its way to
a VIA point, which counts as passed within the segment's VIA radius; a leg that something stops
short of that (an obstacle's field on the links, a joint limit, a fixture) would push for ever:
``MOVE TO (0.55, -0.15, 0.35) VIA (0.65, 0, 0.4)`` on the Panda, a post's field holding its
link 5 back, stood 31 mm from the VIA point for 4265 s of simulated time, until interrupted.
The same rule as the last leg's holds on every leg (:class:`cosmos.execution.closing.Closing`),
and it fails with the measured distance and the cause.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from cosmos.execution.closing import STALL_TIME_S, Closing
from cosmos.execution.float_maths import distance_to_point
from cosmos.execution.monitor import Outcome, Verdict
from cosmos.osc._types import FloatArray


class ViaProgress:
    """How close the tool has come to the VIA point it is on its way to, and since when (a Closing)."""

    def __init__(self, points: Sequence[tuple[float, ...]], cause: Callable[[], str]) -> None:
        """Watch a MOVE's legs.

        Args:
            points: The MOVE's goal points, its VIA points then its target, world [m]. # (legs, 3)
            cause: Why the arm stopped (the monitor's stall cause: a joint limit, a field, ...).
        """
        self._points, self._cause = points, cause
        self._leg, self._closing = -1, Closing()

    def stalled(self, t_s: float, position: FloatArray, leg: int) -> Outcome | None:
        """The failure of a leg that got no closer to its VIA point for ``STALL_TIME_S``, else None.

        Args:
            t_s: Now [s].
            position: The measured tool point, world [m]. # (3,)
            leg: The index of the VIA point the tool is on its way to (0 for the first).
        """
        point = self._points[leg]
        distance = distance_to_point(position, point)
        if leg != self._leg:  # a new leg: judged from here
            self._leg, self._closing = leg, Closing(distance, t_s)
            return None
        if not self._closing.stalled(distance, t_s):
            return None
        x, y, z = (1e3 * coordinate for coordinate in point)
        return Outcome(
            Verdict.FAILED,
            f"cannot reach its VIA point {leg + 1} at ({x:.0f}, {y:.0f}, {z:.0f}) mm: stopped "
            f"{distance * 1e3:.1f} mm from it for {STALL_TIME_S:g} s; {self._cause()}",
        )
