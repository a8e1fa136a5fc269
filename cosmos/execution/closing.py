"""Whether a goal motion still gets closer to its goal: the stall rule every goal is held to.

A MOVE's target (:meth:`cosmos.execution.monitor.SegmentMonitor._stalled`) and each of its VIA
points (:mod:`cosmos.execution.via_legs`): a motion that gets no closer by
:data:`STALL_PROGRESS_M` for :data:`STALL_TIME_S` has stalled, and without the rule it would
push for ever (a MOVE into the table, a leg a post's field holds back).
"""

from __future__ import annotations

import math
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
