"""A held push that loses its surface: a CONTACT's hold whose tool runs on along the push.

A peg held on the hole's chamfer may slide off it into the bore; the held push then runs on
at its SPEED (:func:`cosmos.osc.held_push.held_push_cap`) until it lands on the bore's bottom. Its
force is not settled meanwhile, whatever the wrist reads (the bore's wall rubbing the peg reads
3-6 N of an 8 N push), and its settling is bounded from where it lands again, not from the touch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cosmos.plan import TOUCH_THRESHOLD_N, Segment, SegmentKind

FloatArray = np.ndarray

LOST_PUSH_TRAVEL_M = 0.001
"""A held push that runs on this far along itself has lost its surface [m]. Pressing a surface
it moves under 0.1 mm (the table's 1.5 mm contact ramp, sensed through the encoders' noise)."""


@dataclass(slots=True)
class LostPush:
    """Where a held push last had its surface, and since when.

    Attributes:
        push: The push's unit direction, world. # (3,)
        at: The tool point where it last had its surface, world [m]. # (3,)
        since_s: When it was there [s].
        pressed_at: The tool point where it last touched something (:meth:`ran_free`), world [m]. # (3,)
        touching_n: The least force that touches something [N]: the touch's
            (:data:`~cosmos.plan.TOUCH_THRESHOLD_N`), or half the push if less.
        contact: The push is a CONTACT's hold: one running on touching nothing fails (:meth:`lost_contact`).
    """

    push: tuple[float, float, float]
    at: tuple[float, float, float]
    since_s: float
    pressed_at: tuple[float, float, float] = (0.0, 0.0, 0.0)
    touching_n: float = 0.0
    contact: bool = False

    @classmethod
    def of(cls, segment: Segment, start: tuple[float, ...], start_s: float) -> LostPush:
        """The watch of ``segment``'s push (its force setpoint's translation), from its start."""
        unit, size = segment_push(segment)
        x, y, z = start
        touching = min(TOUCH_THRESHOLD_N, 0.5 * size)
        held = segment.kind is SegmentKind.CONTACT_HOLD
        return cls(unit, (x, y, z), start_s, (x, y, z), touching, held)

    def ran_on(self, position: FloatArray, t_s: float) -> bool:
        """Whether the tool point ``position`` [m] ran on past :data:`LOST_PUSH_TRAVEL_M` (now its mark)."""
        x, y, z = position.tolist()
        (nx, ny, nz), (x0, y0, z0) = self.push, self.at
        if (x - x0) * nx + (y - y0) * ny + (z - z0) * nz <= LOST_PUSH_TRAVEL_M:
            return False
        self.at, self.since_s = (x, y, z), t_s
        return True

    def ran_free(self, position: FloatArray, force_n: float) -> float:
        """How far the tool point ``position`` [m] ran on along the push touching nothing [m] (0: it touches).

        Touching is a sensed force ``|f|`` [N] of at least :attr:`touching_n`, whatever its direction
        (the bore's wall rubbing a falling peg reads 4-7 N across the push and 1.5-3.6 N along it);
        the run is counted along the push from where the tool last touched.
        """
        x, y, z = position.tolist()
        if force_n >= self.touching_n:
            self.pressed_at = (x, y, z)
            return 0.0
        (nx, ny, nz), (x0, y0, z0) = self.push, self.pressed_at
        return (x - x0) * nx + (y - y0) * ny + (z - z0) * nz

    def lost_contact(self, position: FloatArray, wrench: FloatArray, t_s: float) -> str:
        """A CONTACT hold's failure once it ran :data:`LOST_CONTACT_M` touching nothing, else "".

        :meth:`ran_free`; "" for any other held push (:attr:`contact` False).
        """
        if not self.contact:
            return ""
        fx, fy, fz, _, _, _ = wrench.tolist()
        free = self.ran_free(position, math.sqrt(fx * fx + fy * fy + fz * fz))
        if free <= LOST_CONTACT_M:
            return ""
        return (
            f"lost contact: the tool ran on {free * 1e3:.1f} mm along its push touching nothing "
            f"(under {self.touching_n:g} N) at {t_s:.2f} s"
        )


LOST_CONTACT_M = 0.015
"""A CONTACT's hold whose tool runs on this far along its push touching nothing has lost its
contact and fails [m]. A peg sliding off the hole's chamfer falls into the bore rubbing its wall
(4-7 N sensed all the 43 mm down, realistic seed 1); a hold whose touch was the tool's own
inertia (issue 14: SPEED 100 mm/s, before the touch was judged without it) pushed the tool 606
mm through free air, 7.2 s, until the path deviation stopped it."""

LOST_SURFACE_M = 0.005
"""A motion statement's held push that ran on this far along itself has lost its surface, as its
failure says [m]: more than a tilted table's rise over a slide (2 deg over 100 mm is 3.5 mm)."""


def segment_push(segment: Segment) -> tuple[tuple[float, float, float], float]:
    """The segment's push, its force setpoint's translation in the world: unit direction, size [N].

    ``((0, 0, 0), 0)`` for a segment that pushes nothing.
    """
    push = np.asarray(segment.frame_rotation, dtype=float).dot(np.asarray(segment.force_setpoint[:3]))
    size = float(np.linalg.norm(push))
    if not size > 0.0:
        return (0.0, 0.0, 0.0), 0.0
    nx, ny, nz = (push / size).tolist()
    return (nx, ny, nz), size


def lost_surface(segment: Segment, start: tuple[float, ...], position: FloatArray) -> str:
    """What a failure adds when the segment's held push ran on along itself: its surface is gone.

    A SLIDE off a fixture's edge: the push follows the tool down at its SPEED
    (:func:`cosmos.osc.held_push.held_push_cap`) while the motion axes reach their goal, and the
    statement does not arrive; "18.3 mm from its goal" said nothing of why (17.7 mm of it was the
    fall along the push). Empty when the push is held, or the segment holds none.
    """
    watch = LostPush.of(segment, start, 0.0)
    ran = sum((p - s) * n for p, s, n in zip(position.tolist(), start, watch.push, strict=True))
    if not any(watch.push) or ran <= LOST_SURFACE_M:
        return ""
    return f"; it lost its surface: the tool ran on {ran * 1e3:.1f} mm along its push"
