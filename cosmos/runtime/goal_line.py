"""The line a goal motion keeps to, and when it gives it up for the obstacles' field.

Eq. 21 scales the whole desired velocity to its speed limit, so far from the goal a
deviation from the straight line is answered with a stiffness that vanishes with the
distance (:func:`cosmos.osc.motion.on_the_line`); the servo keeps the tool on the line
from where the motion began to its goal instead. Seed section 6 needs the opposite
where an obstacle's field pushes the tool: the arm goes round the obstacle, off the
line, and a line held stiffly would stop it in front of the obstacle (four of the five
avoidance scenes stalled 0.18-0.53 m short). So the line is given up, and eq. 21 is as
the seed writes it, while the field acts on the tool: on its own link, or on the other
links where the task's null space does not absorb their share
(:class:`cosmos.runtime.null_space.NullSpaceTerms`).
"""

from __future__ import annotations

import numpy as np

from cosmos.runtime.null_space import LinkField, NullSpaceTerms

FloatArray = np.ndarray

SHORTEST_LINE_M = 1e-6
"""A goal closer than this to the start has no line [m]."""


def goal_line(start_m: FloatArray | None, goal_m: FloatArray, is_goal_motion: bool) -> FloatArray:
    """The unit vector from the motion's start to its goal; zeros if none (not a goal motion). # (3,)."""
    if not is_goal_motion or start_m is None:
        return np.zeros(3)
    way = np.asarray(goal_m, dtype=float) - np.asarray(start_m, dtype=float)
    length = float(np.linalg.norm(way))
    return way / length if length > SHORTEST_LINE_M else np.zeros(3)


def field_pushes_tool(field: LinkField, null_space: NullSpaceTerms) -> bool:
    """Whether the obstacles' field acts on the tool: on its link, or on the others unabsorbed."""
    if field.tool.any():
        return True
    if not field.links.any():
        return False
    absorbed = (
        null_space.dimension >= null_space.policy.min_dimension and null_space.link_share_to_tool == 0.0
    )
    return not absorbed


def kept_line(line: FloatArray, field: LinkField, null_space: NullSpaceTerms) -> FloatArray:
    """The line the servo keeps to now: ``line``, or zeros while the field pushes the tool. # (3,)."""
    return np.zeros(3) if field_pushes_tool(field, null_space) else line
