"""Whether a goal motion still gets closer to its goal: the stall rule every goal is held to.

A MOVE's target (:meth:`cosmos.execution.monitor.SegmentMonitor._stalled`) and each of its VIA
points (:mod:`cosmos.execution.via_legs`): a motion that gets no closer by
:data:`STALL_PROGRESS_M` for :data:`STALL_TIME_S` has stalled, and without the rule it would
push for ever (a MOVE into the table, a leg a post's field holds back).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

STALL_TIME_S = 2.0
"""A goal motion that gets no closer by STALL_PROGRESS_M for this long has stalled [s]."""
STALL_PROGRESS_M = 0.0005


@dataclass(slots=True)
class Closing:
    """The closest a motion has come to its goal, and when it came that close."""

    closest_m: float = math.inf
    since_s: float = 0.0

    def stalled(self, distance_m: float, t_s: float) -> bool:
        """Whether, at ``distance_m`` from the goal now, the motion has got no closer for the stall's time."""
        if distance_m < self.closest_m - STALL_PROGRESS_M:
            self.closest_m, self.since_s = distance_m, t_s
            return False
        return t_s - self.since_s >= STALL_TIME_S


def stall_reason(error_text: str, speed_mps: float, rest_mps: float, cause: Callable[[], str]) -> str:
    """Why a goal motion stalled: stopped short (and what holds it), or still moving about its goal.

    An arm that oscillates about its goal (a model error past the controller's margins:
    ``--vary model_error=0.5``, the tool swinging 2.5 mm either side at 90 mm/s) gets no closer
    either; it has not stopped, and the message says so.

    Args:
        error_text: The measured error, ``0.2 mm and 0.0 deg from its goal``.
        speed_mps: The tool point's speed now [m/s].
        rest_mps: The speed under which it is at rest (the goal's speed tolerance) [m/s].
        cause: Says what holds a motion back (:func:`cosmos.execution.arrival.stall_cause`).
    """
    if speed_mps > rest_mps:
        return (
            f"cannot settle at its goal: {error_text} and still moving at {speed_mps * 1e3:.0f} mm/s, "
            f"no closer for {STALL_TIME_S:g} s (swinging about it)"
        )
    return f"cannot reach its goal: stopped {error_text} for {STALL_TIME_S:g} s; {cause()}"
