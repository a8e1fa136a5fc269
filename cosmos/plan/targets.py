"""What a segment aims at and how it finishes: its kind, its target and its completion."""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


class SegmentKind(enum.Enum):
    """What a segment does; the statement it came from is in ``Segment.statement``."""

    MOVE = "move"
    """Goal-position motion (seed eq. 20-21) or a timed trajectory (eq. 19)."""
    CONTACT_APPROACH = "contact_approach"
    """Guarded move along a direction at low speed until the tool touches."""
    CONTACT_HOLD = "contact_hold"
    """Hold the contact force on the contact axis, position on the others."""
    SLIDE = "slide"
    """Motion along a direction while the held contact axis stays force-controlled."""
    INSERT = "insert"
    """Force control along the insertion axis, zero-force compliance laterally."""
    WAIT = "wait"
    """Hold (position, and any held contact force) for a time or until a condition."""


# ----------------------------------------------------------------- targets


@dataclass(frozen=True, eq=False)
class AbsoluteTarget:
    """A goal pose in the world.

    Attributes:
        position_world: Tool point position [m], shape (3,).
        rotation_world: Tool orientation (tool frame to world), shape (3, 3), or
            ``None`` to keep the orientation the tool has when the segment starts.
    """

    position_world: FloatArray
    rotation_world: FloatArray | None


@dataclass(frozen=True, eq=False)
class RelativeTarget:
    """A goal offset from the tool position measured when the segment starts.

    Attributes:
        offset_world: Displacement of the tool point [m], world axes, shape (3,).
            The orientation is kept as it is at the segment start.
    """

    offset_world: FloatArray


Target = AbsoluteTarget | RelativeTarget


# ------------------------------------------------------------- completions


class CompletionKind(enum.Enum):
    """How a segment finishes successfully when no stop condition fires first."""

    GOAL_REACHED = "goal_reached"
    CONTACT_TOUCH = "contact_touch"
    FORCE_SETTLED = "force_settled"
    DEPTH_REACHED = "depth_reached"
    DURATION = "duration"
    CONDITION = "condition"


@dataclass(frozen=True, eq=False)
class GoalReached:
    """Done when the motion axes are at the target and the tool is nearly at rest.

    Only motion-controlled axes are compared; force-controlled axes are ignored.

    Attributes:
        position_tolerance_m: Largest position error on the motion axes [m].
        orientation_tolerance_rad: Largest orientation error on the motion axes [rad].
        speed_tolerance_mps: Largest tool-point speed [m/s].
    """

    position_tolerance_m: float
    orientation_tolerance_rad: float
    speed_tolerance_mps: float
    kind: ClassVar[CompletionKind] = CompletionKind.GOAL_REACHED


TOUCH_THRESHOLD_N = 2.0
"""A CONTACT's or an INSERT's touch: a push of this much, or half its FORCE if less [N]
(docs/language.md); the compiler's default, and what a CONTACT's hold counts as still touching
(:mod:`cosmos.execution.lost_push`)."""


@dataclass(frozen=True, eq=False)
class ContactTouch:
    """Done when the tool touches.

    Touching: the force the tool applies along ``direction_world``
    (``wrench_force_world @ direction_world``) exceeds ``threshold_n``.

    Attributes:
        direction_world: Unit approach direction, world, shape (3,).
        threshold_n: Touch threshold [N].
        max_travel_m: The segment *fails* ("found no contact within 300 mm") when the tool has
            moved this far along the direction without touching [m]. The
            segment's target sits at this distance.
        force_n: The FORCE the CONTACT holds once touched [N] (its landing's speed is chosen
            for it: :mod:`cosmos.osc.landing`); 0 if not known.
    """

    direction_world: FloatArray
    threshold_n: float
    max_travel_m: float
    force_n: float = 0.0
    kind: ClassVar[CompletionKind] = CompletionKind.CONTACT_TOUCH


@dataclass(frozen=True, eq=False)
class ForceSettled:
    """Done when the force has settled on its setpoint.

    Settled: every force-controlled axis has been within ``tolerance_n`` of its
    setpoint (moments: ``tolerance_n`` read as N m) for ``settle_time_s``.

    Attributes:
        tolerance_n: Allowed force error [N].
        settle_time_s: How long the force must stay within tolerance [s].
        max_time_s: The segment fails ("force did not settle") after this long [s].
    """

    tolerance_n: float
    settle_time_s: float
    max_time_s: float
    kind: ClassVar[CompletionKind] = CompletionKind.FORCE_SETTLED


@dataclass(frozen=True, eq=False)
class DepthReached:
    """Done when the tool point has gone ``depth_m`` deep along ``direction_world``.

    Depth is measured since the statement started (its first segment):
    ``(x - x_start) @ direction_world >= depth_m``.

    Attributes:
        direction_world: Unit insertion direction, world, shape (3,).
        depth_m: Depth to reach [m].
        touch_n: None for the insertion itself. Set on an INSERT's approach (every axis
            held while it moves along the direction): done also when the force the tool
            applies exceeds this [N], in any direction (a peg that enters its hole without
            meeting the chamfer touches the bore's wall first); the insertion follows. Gone
            ``depth_m`` without that touch, it fails: nothing was inserted.
        force_n: The INSERT's FORCE [N], on its approach: the speed of its landing on a steel face
            square to it is chosen for it (:mod:`cosmos.runtime.landing_zone`); 0 if not known.
    """

    direction_world: FloatArray
    depth_m: float
    touch_n: float | None = None
    force_n: float = 0.0
    kind: ClassVar[CompletionKind] = CompletionKind.DEPTH_REACHED


@dataclass(frozen=True, eq=False)
class Elapsed:
    """Done after ``duration_s`` seconds in the segment (WAIT t)."""

    duration_s: float
    kind: ClassVar[CompletionKind] = CompletionKind.DURATION


@dataclass(frozen=True, eq=False)
class UntilOnly:
    """Never done by itself: only ``until`` ends it (``WAIT UNTIL ...``), or the timeout."""

    kind: ClassVar[CompletionKind] = CompletionKind.CONDITION


Completion = GoalReached | ContactTouch | ForceSettled | DepthReached | Elapsed | UntilOnly
