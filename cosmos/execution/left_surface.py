"""A SLIDE that leaves its surface: it fails then, with what was measured, not at its goal.

A SLIDE carries the tool along a surface while its push holds it there. Over a fixture's edge
the push follows the tool down at its SPEED (:func:`cosmos.osc.held_push.held_push_cap`) while
the motion axes go on to their goal: ``SLIDE +Y BY 150 mm SPEED 20 mm/s`` off the hole
fixture's top face fell 60 mm onto the table at 21 mm/s (a 47 N spike at the edge) and then
arrived 0.5 mm from its goal, "done". Off the table's edge it found nothing below and failed
at its goal's time. Either way the SLIDE did not do what it says. So every tick (a few float
products) the SLIDE's push is watched from where it started pressing:

- **dropped**: the tool point has moved more than
  :data:`~cosmos.execution.lost_push.LOST_SURFACE_M` along the push (into where the surface
  was: less than any fixture's step, the hole fixture's top face stands 60 mm over the table);
- **push lost**: the push along its axis, once it has reached :data:`LOST_PUSH_SHARE` of its
  setpoint, has stayed under it for :data:`LOST_PUSH_S` in a row.

Either fails the statement with the measured figures (docs/language.md, SLIDE).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TypeVar

import numpy as np

from cosmos.execution.lost_push import LOST_SURFACE_M, segment_push
from cosmos.plan import Segment, SegmentKind

FloatArray = np.ndarray
S = TypeVar("S")
T = TypeVar("T")
V = TypeVar("V")

LOST_PUSH_SHARE = 0.1
"""A SLIDE's push under this share of its setpoint is lost (while it lasts :data:`LOST_PUSH_S`)."""

LOST_PUSH_S = 0.25
"""A push under :data:`LOST_PUSH_SHARE` of its setpoint for this long in a row is lost [s]: off the
hole fixture's edge at 20 mm/s the push read under 0.5 N of its 5 N from 0.1 s before the tool
began to drop; on the surface the slide grid's pushes never fall under half their setpoint."""


@dataclass(slots=True)
class SurfaceWatch:
    """A SLIDE's push, watched from where it started pressing.

    Attributes:
        push: The push's unit direction, world. # (3,)
        setpoint_n: The push's setpoint [N].
        start: The tool point where the SLIDE started, world [m]. # (3,)
        weak_since_s: Since when the push has been under its share (None: it is not).
        pressed: Whether the push has reached its share yet (only then can it be lost).
    """

    push: tuple[float, float, float]
    setpoint_n: float
    start: tuple[float, float, float]
    weak_since_s: float | None = None
    pressed: bool = False

    @classmethod
    def of(cls, segment: Segment, start: tuple[float, ...]) -> SurfaceWatch | None:
        """The watch of a segment's push (its force setpoint's translation); None if it pushes nothing."""
        unit, size = segment_push(segment)
        if not size > 0.0:
            return None
        x, y, z = start
        return cls(unit, size, (x, y, z))

    def left(self, position: FloatArray, wrench: FloatArray, t_s: float) -> str:
        """Why the tool has left its surface at this tick (the failure's reason), or "" if it has not.

        Args:
            position: The measured tool point, world [m]. # (3,)
            wrench: The wrench the tool applies, world [N, N m]. # (6,)
            t_s: Simulated time [s].
        """
        x, y, z = position.tolist()
        fx, fy, fz = wrench[:3].tolist()
        (nx, ny, nz), (x0, y0, z0) = self.push, self.start
        dropped = (x - x0) * nx + (y - y0) * ny + (z - z0) * nz
        push = fx * nx + fy * ny + fz * nz
        if dropped > LOST_SURFACE_M:
            slid = self._slid(position, dropped)
            return (
                f"left its surface at {t_s:.2f} s: the tool dropped {dropped * 1e3:.1f} mm along its push "
                f"after {slid * 1e3:.1f} mm of its slide "
                f"(push {round(push, 1) + 0.0:.1f} N of {self.setpoint_n:g} N)"
            )
        if push >= LOST_PUSH_SHARE * self.setpoint_n:
            self.weak_since_s, self.pressed = None, True
            return ""
        if not self.pressed:  # a SLIDE's own FORCE over the contact's: still ramping up to it
            return ""
        if self.weak_since_s is None:
            self.weak_since_s = t_s
        if t_s - self.weak_since_s < LOST_PUSH_S - 1e-9:
            return ""
        slid, weak = self._slid(position, dropped), LOST_PUSH_SHARE * self.setpoint_n
        return (
            f"lost its surface at {t_s:.2f} s: the push stayed under {weak:.1f} N "
            f"of its {self.setpoint_n:g} N for {LOST_PUSH_S:g} s, after {slid * 1e3:.1f} mm of its slide"
        )

    def _slid(self, position: FloatArray, dropped_m: float) -> float:
        """How far the tool point has moved across its push since the start [m]."""
        moved = np.asarray(position, dtype=float) - np.array(self.start)
        return float(np.linalg.norm(moved - dropped_m * np.array(self.push)))


def watched(
    segment: Segment,
    start: tuple[float, ...],
    reached: Callable[[S], T | None],
    failed: V,
    outcome: Callable[[V, str], T],
) -> Callable[[S], T | None]:
    """A SLIDE's goal judge ``reached`` with its surface watched first; any other segment's as it is.

    Args:
        segment: The segment.
        start: The tool point where it starts, world [m].
        reached: Its judge of arrival, one snapshot (``position``, ``wrench``, ``t_s``) a tick.
        failed: The failed verdict.
        outcome: Makes an outcome of a verdict and a reason.
    """
    watch = SurfaceWatch.of(segment, start) if segment.kind is SegmentKind.SLIDE else None
    if watch is None:
        return reached
    left = watch.left

    def judge(snap: S) -> T | None:
        why = left(snap.position, snap.wrench, snap.t_s)  # type: ignore[attr-defined]
        return outcome(failed, why) if why else reached(snap)

    return judge
