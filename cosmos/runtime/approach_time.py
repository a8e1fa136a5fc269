"""A CONTACT whose TIMEOUT ends its approach before it can reach the surface ahead, foreseen from the text.

Where the program fixes the pose a ``CONTACT`` starts from (:mod:`cosmos.runtime.goals_in_fixtures`
follows it), the fixture the approach meets is traced along its direction from the tool's points, as
the run's landing traces it (:func:`cosmos.runtime.landing_zone.surface_ahead`). The approach needs
at least that distance over its SPEED (more with its landing's slowing), so a TIMEOUT shorter than
that fails for certain: ``MOVE TO table + (0, 0, 100 mm)`` then ``CONTACT DOWN FORCE 10 N TIMEOUT
2 s`` failed "found no contact within 2 s", 100 mm at 20 mm/s being 5 s.
"""

from __future__ import annotations

import numpy as np

from cosmos import plan
from cosmos.runtime.goals_in_fixtures import Approach
from cosmos.runtime.landing_zone import surface_ahead, tool_points


def approach_timeout(
    approach: Approach, sections: tuple[tuple[float, float, float], ...]
) -> plan.Diagnostic | None:
    """The warning for a CONTACT's approach whose TIMEOUT is shorter than its travel to a fixture needs.

    Args:
        approach: The approach, the pose the text fixes for its start (None: not known), the solids.
        sections: The tool's round parts along its axis (from, to, radius [m]).
    """
    step, solids = approach.step, approach.solids
    position, rotation = approach.pose.position, approach.pose.rotation
    timeout, speed, target = step.timeout_s, step.speed_limit_mps, step.target
    touching = isinstance(step.completion, plan.ContactTouch)
    approaching = step.kind is plan.SegmentKind.CONTACT_APPROACH and touching
    if not approaching or timeout is None or not speed or position is None or rotation is None:
        return None
    if not isinstance(target, plan.RelativeTarget):
        return None
    line = np.asarray(target.offset_world, dtype=float)
    travel = float(np.linalg.norm(line))
    if not travel > 0.0:
        return None
    points = tool_points(position, rotation, sections)
    distance, solid = surface_ahead(solids, points, line / travel, travel)
    needed = distance / speed
    if solid < 0 or timeout >= needed:
        return None
    return plan.Diagnostic(
        f"TIMEOUT {timeout:g} s ends this approach before it can reach '{solids[solid].fixture}' "
        f"{distance * 1e3:.1f} mm ahead, at least {needed:.2f} s at {speed * 1e3:g} mm/s",
        step.span,
    )
