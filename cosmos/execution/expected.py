"""What the running statement expects: whether it touches, how hard, along which line.

The protective stops (:mod:`cosmos.execution.supervision`) compare the arm with
these expectations every tick; they are pure functions of the segment and of
positions, documented in docs/language.md ("Protective stops").
"""

from __future__ import annotations

import numpy as np

from cosmos.execution.float_maths import length_along
from cosmos.plan import Segment, SegmentKind
from cosmos.plan.conditions import has_force_term
from cosmos.workcell import WRIST_SENSOR

FloatArray = np.ndarray

FREE_MOTION_FORCE_N = 20.0
"""Force limit in free motion [N], unless a program sets its own with ``LIMIT FORCE``.

Above what the tool's own inertia gives the wrist sensor at the arm's
accelerations (a 50 mm reversal at 100 mm/s reads about 6 N)."""
CONTACT_FORCE_MARGIN_N = 30.0
"""A contact statement's force range: twice its FORCE (or UNTIL threshold) plus this [N]
(impacts on touching, a force loop's overshoot)."""


def expects_contact(segment: Segment) -> bool:
    """Whether the statement holds or seeks the tool's contact with the fixtures."""
    if segment.kind in (SegmentKind.CONTACT_APPROACH, SegmentKind.CONTACT_HOLD):
        return True
    if segment.kind in (SegmentKind.SLIDE, SegmentKind.INSERT):
        return True
    if not bool(np.all(segment.motion_axes)):
        return True  # a contact held (force-controlled axes)
    return any(s is not None and s > 0.0 for s in segment.stiffness)  # a COMPLY spring


def spring_press_n(segment: Segment, start: FloatArray, goal: FloatArray) -> float:
    """The hardest a COMPLY spring of the segment can press [N].

    Its stiffness times its anchor's travel along its axis (the MOVE from ``start`` to ``goal``,
    world [m]), the largest axis's: ``COMPLY Z STIFFNESS 4000 N/m`` moved 25 mm down, 15 mm to the
    table, presses 40 N, which the 30 N of a statement without FORCE stopped.
    """
    travel = segment.frame_rotation.T @ (np.asarray(goal, dtype=float) - start)
    presses = [k * abs(float(d)) for k, d in zip(segment.stiffness[:3], travel, strict=True) if k]
    return max(presses, default=0.0)


def free_limit_n(segment: Segment) -> float:
    """The free-motion force limit in force for ``segment``: its ``LIMIT FORCE``, else the default [N]."""
    return segment.force_limit_n or FREE_MOTION_FORCE_N


def force_limit_n(segment: Segment, free_limit_n: float, spring_press: float = 0.0) -> float:
    """The largest force the statement may see at the wrist [N] (module docstring).

    Args:
        segment: The running segment.
        free_limit_n: The free-motion limit in force (default or ``LIMIT FORCE``).
        spring_press: :func:`spring_press_n`: a spring's press counts as a FORCE [N].
    """
    limit = free_limit_n
    guarded, threshold = has_force_term(segment.until)
    if guarded:
        limit = max(limit, 2.0 * threshold + CONTACT_FORCE_MARGIN_N)
    if expects_contact(segment):
        setpoint = max(float(np.max(np.abs(segment.force_setpoint[:3]))), spring_press)
        limit = max(limit, 2.0 * setpoint + CONTACT_FORCE_MARGIN_N)
    return min(limit, WRIST_SENSOR.force_n)


def braked_over_limit(segment: Segment, braked: tuple[float, float], until_reason: str) -> str:
    """A protective stop's message if the wrist's peak while the arm braked after an UNTIL exceeds the limit.

    A guarded motion's impact comes after its UNTIL fired, while the arm brakes
    (:func:`cosmos.execution.holding.brake_to_rest`): at 100 mm/s onto the table, UNTIL FORCE > 5 N
    fired at 5.7 N and the wrist read 174 N 4 ms later. Over the statement's limit
    (:func:`force_limit_n`) that is a protective stop, not a stop on the condition.

    Args:
        segment: The segment its UNTIL stopped.
        braked: ``(peak [N], when [s])``: the largest wrist force while the arm braked.
        until_reason: The stop's reason (``UNTIL FORCE > 5 N: 5.7 N at 3.16 s``).

    Returns:
        ``protective stop: 174.2 N at the wrist at 3.17 s while braking after UNTIL FORCE > 5 N:
        5.7 N at 3.16 s; over this statement's limit of 40 N``; "" within the limit.
    """
    limit, (peak_n, peak_s) = force_limit_n(segment, free_limit_n(segment)), braked
    if peak_n <= limit:
        return ""
    return (
        f"protective stop: {peak_n:.1f} N at the wrist at {peak_s:.2f} s while braking after "
        f"{until_reason}; over this statement's limit of {limit:.0f} N"
    )


def off_line(
    p: list[float],
    a: tuple[float, ...],
    d: tuple[float, ...],
    length2: float,
    axes: list[tuple[float, ...]],
) -> float:
    """:func:`path_deviation` on floats (it runs every tick): ``a`` the start, ``d`` the line."""
    rx, ry, rz = p[0] - a[0], p[1] - a[1], p[2] - a[2]
    if length2 > 1e-12:
        along = min(1.0, max(0.0, (rx * d[0] + ry * d[1] + rz * d[2]) / length2))
        rx, ry, rz = rx - along * d[0], ry - along * d[1], rz - along * d[2]
    return length_along(axes, rx, ry, rz)


def path_deviation(position: FloatArray, start: FloatArray, end: FloatArray, axes: FloatArray) -> float:
    """Distance of ``position`` from the segment ``start``-``end`` along the rows of ``axes`` [m].

    Args:
        position: The measured tool point, world [m]. # (3,)
        start: The line's start, world [m]. # (3,)
        end: Its end, world [m]. # (3,)
        axes: Orthonormal world directions the distance is measured along. # (k, 3)
    """
    line = end - start
    length2 = float(line.dot(line))
    along = 0.0 if length2 < 1e-12 else min(1.0, max(0.0, float((position - start).dot(line)) / length2))
    off = position - (start + along * line)
    return float(np.linalg.norm(axes.dot(off)))
