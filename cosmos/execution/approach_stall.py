"""A CONTACT's approach that stops short of its touch: landed too softly to count, or held back.

The approach is eq. 20-21's goal motion toward a target 300 mm along its direction, done once
the tool pushes along it more than the touch threshold (2 N, or half the FORCE). Its command is
a velocity servo without an integral: met by a surface at a slant (a peg's end on the hole's
chamfer, 2.5 mm off the axis), at the landing's few mm/s it presses only what its damping
makes of that speed (1-1.5 N on the Panda), below the threshold, and stands there: with no
TIMEOUT one such CONTACT ran 1124 s of simulated time without an outcome. So an approach that
gets no further along its direction for :data:`~cosmos.execution.closing.STALL_TIME_S` has
stopped: pressing at least :data:`LANDED_N` along it, it has landed (the hold then pushes its
FORCE); pressing less, something else holds it, and it fails.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from cosmos.execution.closing import STALL_PROGRESS_M, STALL_TIME_S
from cosmos.plan import ContactTouch, Segment, SegmentKind

LANDED_N = 0.5
"""A stopped approach pressing this much along its direction has landed [N] (the push from which
the approach brakes: docs/language.md, CONTACT, "The landing")."""


@dataclass(slots=True)
class ApproachStall:
    """The furthest an approach has got along its direction, and when it got there.

    Attributes:
        max_travel_m: How far the approach goes before it fails "found no contact" [m].
        progress_m: What counts as getting further in :data:`STALL_TIME_S`: 0.5 mm, or a quarter
            of what the approach's SPEED covers in that time if less (SPEED may be 0.1 mm/s) [m].
        since_s: When the approach last got further [s].
        cause: Says what holds a motion back (:func:`cosmos.execution.arrival.stall_cause`).
        furthest_m: How far along it had got then [m].
    """

    max_travel_m: float
    progress_m: float
    since_s: float
    cause: Callable[[], str]
    furthest_m: float = 0.0

    @staticmethod
    def of(segment: Segment, start_s: float, cause: Callable[[], str]) -> ApproachStall:
        """The rule for a CONTACT's approach ``segment`` started at ``start_s``."""
        assert isinstance(segment.completion, ContactTouch)
        speed = segment.speed_limit_mps
        progress = STALL_PROGRESS_M if not speed else min(STALL_PROGRESS_M, 0.25 * speed * STALL_TIME_S)
        return ApproachStall(segment.completion.max_travel_m, progress, start_s, cause)

    def stopped(self, push_n: float, travel_m: float, t_s: float) -> tuple[bool, str] | None:
        """``(landed, reason)`` once the approach has ended without its touch, else None.

        Args:
            push_n: The push along the approach now [N].
            travel_m: How far along it the tool has come [m].
            t_s: Now [s].
        """
        if travel_m >= self.max_travel_m - 1e-3:
            return False, f"found no contact within {self.max_travel_m * 1e3:.0f} mm"
        if travel_m > self.furthest_m + self.progress_m:
            self.furthest_m, self.since_s = travel_m, t_s
            return None
        if t_s - self.since_s < STALL_TIME_S:
            return None
        if push_n >= LANDED_N:
            return (
                True,
                f"touched: stopped against it {push_n:.2f} N along the approach for {STALL_TIME_S:g} s",
            )
        return False, (
            f"stopped {max(travel_m, 0.0) * 1e3:.1f} mm along its approach without touching "
            f"({push_n:.2f} N along it for {STALL_TIME_S:g} s): {self.cause()}"
        )


def timeout_reason(kind: SegmentKind, timeout_s: float, depth_m: float) -> str:
    """What a segment of ``kind`` that ran out its statement's TIMEOUT [s] says; ``depth_m``: an INSERT's [m].

    A CONTACT's TIMEOUT bounds its search for the surface (docs/language.md).
    """
    if kind is SegmentKind.CONTACT_APPROACH:
        return f"found no contact within {timeout_s:g} s"
    if kind is SegmentKind.INSERT:
        return f"timed out after {timeout_s:g} s at depth {depth_m * 1e3:.1f} mm"
    return f"timed out after {timeout_s:g} s"
