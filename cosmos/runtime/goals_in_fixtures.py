"""Goals inside a fixture, foreseen from a program's text.

``MOVE TO table + (0, 0, -30 mm)`` (a frame plus a vector moves along the world's axes, while
the table's frame points its z down into the table: ``-30 mm`` is down, into it) is an easy
slip, as is a goal below the plate; the run finds it only when the tool meets the fixture, as a
protective stop. Where a motion's goal is known from
the text, the checker says so at the statement:

    MOVE TO: the goal is 30.0 mm inside the fixture 'table' (below its top at z = 200.0 mm);
    the run will stop at the touch

A goal is known for a ``MOVE TO`` (and each VIA point), and for a ``MOVE BY`` from a pose
the program fixes (from home through MOVEs that end where they were sent, as
:mod:`cosmos.runtime.foresight` follows them). The goal is inside when the tool point, or a
point of the tool's axis back to the flange where the goal's orientation is known, lies
inside a fixture's solid (:mod:`cosmos.runtime.fixture_solids`) by more than
:data:`DEEPER_THAN_M`, or the tool's side reaches into one that far (a ball inscribed in one of
its round sections meets the solid: a peg off the bore's axis by more than the clearance): a
MOVE that touches a fixture is stopped. A VIA point is inside when it
is deeper than the distance at which it counts as passed: the tool must then touch. Statements
meant to touch are not judged (CONTACT, SLIDE, INSERT, a MOVE with an UNTIL or with axes under
force control), nor is the hole's bore, which is no solid.

An obstacle the program adds (``OBSTACLE``, not MOVING, not a PLANE) is a solid too from its
statement on (until ``OBSTACLE REMOVE``; one added in a block only within it): a goal inside it
is warned the same way, ending "the run will stop short of it" (its field holds the tool off:
the MOVE fails "stuck in a local minimum of the potential field", or at the touch).
"""

from __future__ import annotations

import functools
from collections.abc import Iterator
from dataclasses import dataclass, replace

import numpy as np

from cosmos import plan
from cosmos.runtime.fixture_solids import FixtureSolid, SolidShape, bounds, signed_distances, top_above

AXIS_STEP_M = 0.005
"""Spacing of the points of the tool's axis that are tested [m]."""
DEEPER_THAN_M = 1e-4
"""A goal deeper than this inside a fixture is warned of [m]. Any touch of a fixture stops a
MOVE (a protective stop: ``MOVE TO table + (0, 0, -0.5 mm)`` stops at 0.1 N); a goal on the
surface (``MOVE TO table``) arrives."""


@dataclass(frozen=True)
class ToolShape:
    """The tool along its axis, back from the tool point (its z axis points away from the flange).

    Attributes:
        length_m: From the tool point back to the flange [m].
        sections: Its round parts on the axis (the peg, its collar, the sensor's housing): from
            and to how far back from the tool point, and radius, each [m].
        ahead_m: How far it reaches past the tool point (the gripper's fingertips) [m].
    """

    length_m: float
    sections: tuple[tuple[float, float, float], ...] = ()
    ahead_m: float = 0.0


POINT = ToolShape(0.0)
"""A point: a VIA point's test."""


@dataclass(frozen=True)
class Pose:
    """Where the program leaves the tool, as far as its text says.

    Attributes:
        position: The tool point, world [m], or None if not known. # (3,)
        rotation: The tool's orientation (tool to world), or None if not known. # (3, 3)
    """

    position: np.ndarray | None
    rotation: np.ndarray | None


UNKNOWN = Pose(None, None)


@dataclass(frozen=True)
class Solids:
    """The workcell's solids with their bounding boxes (:func:`bounds`), for a quick first look.

    Attributes:
        all: The solids.
        lower: Lower corners of their boxes, world [m]. # (k, 3)
        upper: Upper corners. # (k, 3)
    """

    all: tuple[FixtureSolid, ...]
    lower: np.ndarray
    upper: np.ndarray


@dataclass(frozen=True)
class Inside:
    """A point found inside a fixture.

    Attributes:
        fixture: The fixture's (or obstacle's) name.
        obstacle: True for an obstacle the program added (``OBSTACLE``).
        depth_m: How far the point lies below the fixture's top, straight above it; for the
            tool's side, how far a ball inside the tool reaches into the fixture [m].
        top_z_m: The z of that top [m]; None for the tool's side.
        along_axis_m: 0 for the tool point; else how far back along the tool's axis the
            point is [m].
    """

    fixture: str
    obstacle: bool
    depth_m: float
    top_z_m: float | None
    along_axis_m: float


@dataclass(frozen=True)
class Approach:
    """A CONTACT's approach, the pose the text fixes for its start, and the solids then in the cell."""

    step: plan.Segment
    pose: Pose
    solids: tuple[FixtureSolid, ...]


def goals_inside_fixtures(
    steps: tuple[plan.Step, ...],
    solids: tuple[FixtureSolid, ...],
    home: Pose,
    tool: ToolShape,
    approaches: list[Approach] | None = None,
) -> list[plan.Diagnostic]:
    """Warnings for the motions whose goal the text fixes inside a fixture.

    Args:
        steps: The compiled plan's steps.
        solids: The workcell's fixture solids.
        home: The tool's pose at home, where the program starts.
        tool: The tool's shape along its axis.
        approaches: If given, each CONTACT's approach is added to it with the pose it starts from
            (:mod:`cosmos.runtime.approach_time` judges its TIMEOUT).

    Returns:
        One diagnostic per such goal (each statement once), at its statement.
    """
    found: dict[tuple[int, int], plan.Diagnostic] = {}
    for diagnostic in _walk(steps, packed(solids), home, tool, approaches):
        found.setdefault((diagnostic.span.line, diagnostic.span.column), diagnostic)
    return list(found.values())


def packed(solids: tuple[FixtureSolid, ...]) -> Solids:
    """``solids`` with their bounding boxes."""
    return Solids(solids, *bounds(solids))


def obstacle_solid(step: plan.AddObstacle) -> FixtureSolid | None:
    """The solid an ``OBSTACLE`` adds, if it stays where it is put and has an inside (not a PLANE).

    MuJoCo's ``size`` of it: a box's half edges, a cylinder's radius and half height (its
    ``position_world`` is the middle of its axis), a sphere's radius.
    """
    if np.any(np.asarray(step.velocity_world_mps) != 0.0):
        return None
    radius, height, edges = step.radius_m, step.height_m, step.size_m
    if step.shape is plan.ObstacleShape.SPHERE and radius is not None:
        shape, size = SolidShape.SPHERE, np.array((radius, 0.0, 0.0))
    elif step.shape is plan.ObstacleShape.CYLINDER and radius is not None and height is not None:
        shape, size = SolidShape.CYLINDER, np.array((radius, height / 2.0, 0.0))
    elif step.shape is plan.ObstacleShape.BOX and edges is not None:
        shape, size = SolidShape.BOX, np.asarray(edges, dtype=float) / 2.0
    else:
        return None
    center = np.asarray(step.position_world, dtype=float)
    rotation = np.asarray(step.rotation_world, dtype=float)
    return FixtureSolid(step.name, step.name, shape, center, rotation, size, obstacle=True)


def _walk(
    steps: tuple[plan.Step, ...],
    solids: Solids,
    pose: Pose,
    tool: ToolShape,
    approaches: list[Approach] | None = None,
) -> Iterator[plan.Diagnostic]:
    """The warnings of ``steps``, run from ``pose``.

    A block's first steps start where the program is when it is reached; after a block
    (which may or may not run, or stop anywhere) the pose is not known.
    """
    empty = tool
    for step in steps:
        if isinstance(step, plan.HandStep):  # held, the object is the tool: its tip is not known
            tool = empty if step.action is plan.HandAction.RELEASE else replace(empty, ahead_m=0.0)
        elif isinstance(step, plan.AddObstacle | plan.RemoveObstacle):  # in a block: only there
            kept = tuple(s for s in solids.all if not (s.obstacle and s.fixture == step.name))
            added = obstacle_solid(step) if isinstance(step, plan.AddObstacle) else None
            solids = packed(kept if added is None else (*kept, added))
        elif isinstance(step, plan.Branch):
            yield from _walk(step.then_steps, solids, pose, tool, approaches)
            yield from _walk(step.else_steps, solids, pose, tool, approaches)
            pose = UNKNOWN
        elif isinstance(step, plan.Loop | plan.Attempt):
            yield from _walk(step.body, solids, pose, tool, approaches)
            if isinstance(step, plan.Attempt):
                yield from _walk(step.handler, solids, UNKNOWN, tool, approaches)
            pose = UNKNOWN
        if _holds_hand_steps(step):  # a block that grasps or lets go: after it, not known either
            tool = replace(empty, ahead_m=0.0)
        elif isinstance(step, plan.Segment):
            diagnostic, pose = _segment(step, solids, pose, tool, approaches)
            if diagnostic is not None:
                yield diagnostic


def _blocks(step: plan.Step) -> tuple[plan.Step, ...]:
    """The steps of a block (both branches, a body and its handler); () for any other step."""
    if isinstance(step, plan.Branch):
        return (*step.then_steps, *step.else_steps)
    if isinstance(step, plan.Attempt):
        return (*step.body, *step.handler)
    return step.body if isinstance(step, plan.Loop) else ()


def _holds_hand_steps(step: plan.Step) -> bool:
    """Whether a block has a GRASP or RELEASE in it, however deep."""
    return any(isinstance(s, plan.HandStep) or _holds_hand_steps(s) for s in _blocks(step))


def _segment(
    step: plan.Segment, solids: Solids, pose: Pose, tool: ToolShape, approaches: list[Approach] | None
) -> tuple[plan.Diagnostic | None, Pose]:
    """The warning for one segment, if any, and the pose it leaves."""
    if step.tool_end is plan.ToolEnd.STAYS:
        return None, pose
    target = step.target
    if step.tool_end is not plan.ToolEnd.AT_TARGET or target is None:
        if approaches is not None and step.kind is plan.SegmentKind.CONTACT_APPROACH:
            approaches.append(Approach(step, pose, solids.all))
        return None, UNKNOWN  # meant to touch, or stopped by a condition: its end is not known
    if isinstance(target, plan.AbsoluteTarget):
        position: np.ndarray | None = np.asarray(target.position_world, dtype=float)
        rotation = pose.rotation if target.rotation_world is None else np.asarray(target.rotation_world)
    else:
        position = None if pose.position is None else pose.position + np.asarray(target.offset_world)
        rotation = pose.rotation
    end = Pose(position, None if step.orientation_free else rotation)
    keyword = "MOVE TO" if isinstance(target, plan.AbsoluteTarget) else "MOVE BY"
    for number, via in enumerate(step.via, start=1):
        via_point = np.asarray(via.position_world, dtype=float)
        hit = point_inside(solids, via_point, None, POINT, step.via_radius_m or DEEPER_THAN_M)
        if hit is not None:
            return plan.Diagnostic(_said(keyword, step, hit, f"VIA point {number}"), step.span), UNKNOWN
    if position is None:
        return None, end
    hit = point_inside(solids, position, end.rotation, tool, DEEPER_THAN_M)
    if hit is None:
        return None, end
    return plan.Diagnostic(_said(keyword, step, hit, "goal"), step.span), UNKNOWN  # the run stops there


def point_inside(
    solids: Solids,
    position: np.ndarray,
    rotation: np.ndarray | None,
    tool: ToolShape,
    tolerance_m: float,
) -> Inside | None:
    """Where the tool at this pose lies inside a fixture deeper than ``tolerance_m``, or None.

    The tool point is tested, then (when ``rotation`` is known) the points of the tool's axis
    back to the flange every :data:`AXIS_STEP_M` (the axis's point deepest below its fixture's
    top is said), then the tool's round sections: a ball inscribed in one (its radius, or half its
    length if shorter) lies in the tool, so a ball that meets a solid is the tool's side in it.
    """
    count = int(tool.length_m / AXIS_STEP_M) if rotation is not None else 0
    backs = np.arange(count + 1) * AXIS_STEP_M
    if rotation is not None and tool.ahead_m > DEEPER_THAN_M:  # its tip past the tool point (fingertips)
        backs = np.concatenate(([-tool.ahead_m], backs))
    axis = np.zeros(3) if rotation is None else rotation[:, 2]
    points = position[None, :] - backs[:, None] * axis[None, :]  # (count + 1, 3)
    sides = rotation is not None and bool(tool.sections)
    centres_back, radii = _balls(tool) if sides else (np.zeros(0), np.zeros(0))
    # The balls' centres are on the axis, within its points' reach.
    candidates = _near(solids, points, float(radii.max(initial=0.0)))
    if not candidates:
        return None
    found = _deepest_point(solids, candidates, points, backs, tolerance_m)
    if found is not None or not sides:
        return found
    centres = position[None, :] - centres_back[:, None] * axis[None, :]  # (n, 3)
    into = radii[:, None] - signed_distances(candidates, centres)  # (n, len(candidates))
    ball, solid = np.unravel_index(int(np.argmax(into)), into.shape)
    if into[ball, solid] <= tolerance_m:
        return None
    hit = candidates[solid]
    return Inside(hit.fixture, hit.obstacle, float(into[ball, solid]), None, float(centres_back[ball]))


def _near(solids: Solids, points: np.ndarray, margin_m: float) -> tuple[FixtureSolid, ...]:
    """The solids whose bounding boxes come within ``margin_m`` of the points' bounding box."""
    low, high = points.min(axis=0) - margin_m, points.max(axis=0) + margin_m
    near = np.all((solids.lower <= high) & (solids.upper >= low), axis=1)
    return tuple(solid for solid, close in zip(solids.all, near, strict=True) if close)


def _deepest_point(
    solids: Solids,
    candidates: tuple[FixtureSolid, ...],
    points: np.ndarray,
    backs: np.ndarray,
    tolerance_m: float,
) -> Inside | None:
    """The tool point if it is inside, else the axis's point deepest below its fixture's top."""
    distances = signed_distances(candidates, points)  # (len(points), len(candidates))
    found: Inside | None = None
    for k in range(len(points)):
        deepest = int(np.argmin(distances[k]))
        if -distances[k, deepest] <= tolerance_m:
            continue
        hit = candidates[deepest]
        same = tuple(s for s in solids.all if (s.fixture, s.obstacle) == (hit.fixture, hit.obstacle))
        top = top_above(same, points[k])
        if found is None or top - points[k, 2] > found.depth_m:
            found = Inside(hit.fixture, hit.obstacle, top - float(points[k, 2]), top, float(backs[k]))
        if k == 0:
            break  # the tool point itself: its goal is what the statement says
    return found


@functools.cache
def _balls(tool: ToolShape) -> tuple[np.ndarray, np.ndarray]:
    """Centres (how far back from the tool point [m]) and radii [m] of balls inside the tool."""
    backs, radii = [], []
    for start, end, radius in tool.sections:
        inscribed = min(radius, (end - start) / 2.0)
        first, last = start + inscribed, end - inscribed
        centres = np.append(np.arange(first, last, AXIS_STEP_M), last)
        backs.append(centres)
        radii.append(np.full(len(centres), inscribed))
    return _read_only(np.concatenate(backs)), _read_only(np.concatenate(radii))


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


def _said(keyword: str, step: plan.Segment, hit: Inside, what: str) -> str:
    """``MOVE TO: the goal is 30.0 mm inside the fixture 'table' (below its top at z = 200.0 mm); ...``.

    A statement of a procedure or a loop says which call or pass (its context) first.
    """
    keyword += f": in {step.context}," if step.context else ":"
    named = f"{'obstacle' if hit.obstacle else 'fixture'} '{hit.fixture}'"
    ending = "the run will stop " + ("short of it" if hit.obstacle else "at the touch")
    back_mm = hit.along_axis_m * 1e3
    if hit.top_z_m is None:
        return (
            f"{keyword} at the {what} the tool's side, {back_mm:.0f} mm back from the tool point, is "
            f"{hit.depth_m * 1e3:.1f} mm into the {named}; {ending}"
        )
    if hit.along_axis_m == 0.0:
        subject = f"the {what} is"
    elif hit.along_axis_m < 0.0:
        subject = f"at the {what} the tool's tip, {-back_mm:.1f} mm past the tool point, is"
    else:
        subject = f"at the {what} the tool's axis, {back_mm:.0f} mm back from the tool point, is"
    return (
        f"{keyword} {subject} {hit.depth_m * 1e3:.1f} mm inside the {named} "
        f"(below its top at z = {hit.top_z_m * 1e3:.1f} mm); {ending}"
    )
