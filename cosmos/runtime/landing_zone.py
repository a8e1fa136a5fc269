"""Where a CONTACT's approach meets a stiff surface of its workcell model (:mod:`cosmos.osc.landing`).

The controller's workcell model is the scene file at its nominal poses: the fixtures' solids
(:attr:`cosmos.runtime.foresight_cache.Workcell.solids`, as the checker sees them, not where a
sweep's drawn variation put them in the plant) and their contact materials (the geoms'
``solimp`` and ``solmix`` in the scene file, mixed with the tool's as MuJoCo mixes them). From
the tool (its tool point and the rims of its sections) the approach's line is traced
into the solids (sphere tracing on their exact signed distances, as
:func:`cosmos.runtime.fixture_solids.top_above` does upward); the nearest surface hit sets the
landing: for the CONTACT's FORCE if its contact is stiff (:data:`cosmos.osc.landing.STIFF_RAMP_M`),
at :data:`cosmos.osc.landing.CUSHIONED_LANDING_MPS` if it cushions.

An INSERT's approach lands so on a stiff face square to it (:func:`square_face`: the flat around
the hole, a part placed beyond the chamfers), its cruise integral on as a CONTACT's approach has
it, and at its SPEED on the hole's chamfer, where its insertion is tuned to that landing
(:mod:`cosmos.osc.push_speed`): ``INSERT DOWN DEPTH 25 mm FORCE 15 N SEARCH LISSAJOUS RADIUS 10 mm
PITCH 3 mm`` from ``hole + (6 mm, -5 mm, 10 mm)`` met the top face at 17-20 mm/s and MuJoCo's
contact force peaked at 65-80 N (PUMA, realistic seeds 0-4 and ideal), 20-47 N on the Panda; landed
so, 17.6-19.7 N and 16.1-17.2 N (the bar for 15 N: 22.5 N).

A push held at a surface (a CONTACT's hold, a WAIT in contact) lands the same way where it loses
that surface (:func:`cosmos.osc.held_push.held_push_cap`): from the tool point alone, along the
push, to the stiff surface beyond the one it touches (a cushioned one gives a hold no landing: a
hold's landing also says that its push is on steel, :func:`cosmos.osc.held_push.held_gains`). A peg
on the hole's chamfer touches with its rim while its tool point is over the bore: traced from the
rim, the landing would be on the chamfer it stands on; from the tool point it is on the bore's
bottom, where the peg goes once it slides in.
"""

from __future__ import annotations

import functools
import math
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from cosmos.model_facts import kept
from cosmos.osc.landing import (
    CUSHIONED_LANDING_MPS,
    LANDING_DECELERATION_MPS2,
    LANDING_ZONE_M,
    STIFF_RAMP_M,
    landing_speed,
)
from cosmos.plan import ContactTouch, DepthReached, Segment, SegmentKind
from cosmos.plan.conditions import has_force_term
from cosmos.robots import ROBOTS
from cosmos.runtime.fixture_solids import FixtureSolid, bounds, signed_distances
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

if TYPE_CHECKING:
    from cosmos.runtime.loop import Runtime

FloatArray = np.ndarray

RIM_POINTS = 16
"""Points on each ring of a tool's section traced besides the tool point (:func:`tool_points`)."""
RING_SPACING_M = 0.01
"""The rings along a section are at most this far apart [m]: a fixture's edge thinner than that
between two may be missed."""
TRACE_TOLERANCE_M = 1e-5
"""A traced point this close to a solid has met it [m]."""
TRACE_STEPS = 200
"""A trace's steps at most."""
INSERT_TRACE_STEPS = 8
"""An INSERT's approach traces this many steps at most: a face square to it is met in a few
(each point jumps its distance to the face), while a peg over its hole steps down the bore's
0.12 mm clearance (200 steps: 60 ms at every ``peg_in_hole.cos`` INSERT) and meets only the
chamfer or the bottom, where it keeps its SPEED anyway (:func:`with_landing`)."""


def surface_ahead(
    solids: tuple[FixtureSolid, ...],
    points: FloatArray,
    direction: FloatArray,
    travel_m: float,
    steps: int = TRACE_STEPS,
) -> tuple[float, int]:
    """How far ``points`` move along ``direction`` before the first of them meets a solid.

    Sphere tracing: a point at distance d outside every solid may move d along any line
    without entering one.

    Args:
        solids: The workcell's solids.
        points: The tool's points, world [m]. # (m, 3)
        direction: The unit approach direction, world. # (3,)
        travel_m: How far to look [m].
        steps: The trace's steps at most (each point moves by its distance to the solids a step).

    Returns:
        ``(distance [m], solid index)``; ``(inf, -1)`` if none is met within ``travel_m`` and ``steps``.
    """
    if not solids:
        return math.inf, -1
    # Only the solids whose boxes the points' sweep reaches can be met (2-5 of the cell's 56:
    # 9-11 ms a trace of 417 points before, on a calm machine).
    low, high = _bounds(solids)
    # The sweep's box: the points' box and that box moved (a sum rounds monotonically, so the moved
    # box's corners are the moved points' least and greatest, exactly).
    lowest, highest, shift = points.min(axis=0), points.max(axis=0), travel_m * direction
    reach = (
        np.minimum(lowest, lowest + shift) - TRACE_TOLERANCE_M,
        np.maximum(highest, highest + shift) + TRACE_TOLERANCE_M,
    )
    near = np.flatnonzero(np.all(low <= reach[1], axis=1) & np.all(high >= reach[0], axis=1))
    if not near.size:
        return math.inf, -1
    distance, which = _trace(tuple(solids[i] for i in near), points, direction, travel_m, steps)
    return distance, -1 if which < 0 else int(near[which])


_BOUNDS: dict[int, tuple[tuple[FixtureSolid, ...], FloatArray, FloatArray]] = {}
""":func:`cosmos.runtime.fixture_solids.bounds` of a workcell's solids, by the tuple's identity."""


def _bounds(solids: tuple[FixtureSolid, ...]) -> tuple[FloatArray, FloatArray]:
    kept_solids, low, high = _BOUNDS.get(id(solids), ((), np.empty(0), np.empty(0)))
    if kept_solids is not solids:
        low, high = bounds(solids)
        _BOUNDS[id(solids)] = (solids, low, high)
    return low, high


def _trace(
    solids: tuple[FixtureSolid, ...],
    points: FloatArray,
    direction: FloatArray,
    travel_m: float,
    steps: int = TRACE_STEPS,
) -> tuple[float, int]:
    """:func:`surface_ahead`'s sphere tracing among ``solids``.

    Each point steps by its distance to the solids until it meets one (within
    :data:`TRACE_TOLERANCE_M`) or passes ``travel_m``; the answer is the least distance along at
    which a point met one (the first in order of those that met there, at the earliest step). A
    point farther along than that cannot better it and stops. At each step the points the least far
    along step first: if one of them meets a solid, all the others are farther along and stop
    unstepped (a CONTACT straight down met the table with its lowest ring at the second step, where
    the 400 points above it were stepped for nothing: 416 -> 216 us a trace; 7.5 -> 3.9 ms for
    search_insert.cos's INSERT over the hole's 50 solids, warm).
    """
    at = np.zeros(len(points))
    moving = np.ones(len(points), dtype=bool)
    best, which = math.inf, -1
    for _ in range(steps):
        index = np.flatnonzero(moving)
        if not index.size:
            break
        ahead = at[index]
        least = ahead == ahead.min()
        if least.all():
            met = _step(solids, points, direction, at, moving, index)
        elif not (met := _step(solids, points, direction, at, moving, index[least]))[0] < best:
            met = _step(solids, points, direction, at, moving, index[~least])  # none of them met one
        if met[0] < best:
            best, which = met
        moving &= at <= min(travel_m, best)
    return best, which


def _step(
    solids: tuple[FixtureSolid, ...],
    points: FloatArray,
    direction: FloatArray,
    at: FloatArray,
    moving: FloatArray,
    index: FloatArray,
) -> tuple[float, int]:
    """One step of :func:`_trace`'s points ``index``: ``at`` moves on, ``moving`` drops those that met.

    Returns:
        How far along the first of those met nearest met a solid, and that solid's index;
        ``(inf, -1)`` if none met one.
    """
    distances = signed_distances(solids, points[index] + at[index, None] * direction)
    nearest = distances.min(axis=1)
    met = nearest < TRACE_TOLERANCE_M
    found = math.inf, -1
    if met.any():  # the first of the least far along: argmin's first (a point by point scan: 140 us)
        first = np.flatnonzero(met)[at[index[met]].argmin()]
        found = float(at[index[first]]), int(distances[first].argmin())
    at[index] += np.where(met, 0.0, np.maximum(nearest, TRACE_TOLERANCE_M))
    moving[index[met]] = False
    return found


def tool_points(
    position: FloatArray, rotation: FloatArray, sections: tuple[tuple[float, float, float], ...]
) -> FloatArray:
    """The tool point and rims of the tool's sections, world [m]. # (m, 3).

    Rings of :data:`RIM_POINTS` at each section's radius, at its two ends and every
    :data:`RING_SPACING_M` between: a CONTACT down meets a face with the rim of the tool's end, one
    across meets a wall with the side of the tool's widest section there. Traced from the end's
    rim alone (the peg's tip, 8.4 mm in radius, chamfered), ``CONTACT -X`` onto the hole fixture's
    outer wall found the wall 1.6 mm beyond where the peg's shank (9.9 mm) met it, and the approach
    met it at its SPEED before it had slowed.
    """
    origin = np.asarray(position, dtype=float)
    to_world = np.asarray(rotation, dtype=float).T
    # Ring by ring, as each ring's own product (one product of all the rings may round otherwise).
    return np.concatenate([origin[None, :], *(origin + local.dot(to_world) for local in _rings(sections))])


@functools.cache
def _rings(sections: tuple[tuple[float, float, float], ...]) -> tuple[FloatArray, ...]:
    """:func:`tool_points`' rings in tool axes [m], built once per tool: each (RIM_POINTS, 3).

    Built at each call they were 70 % of its 52 us (warm; 130-200 us in the executor's cold caches).
    """
    angles = np.linspace(0.0, 2.0 * math.pi, RIM_POINTS, endpoint=False)
    ring = np.stack((np.cos(angles), np.sin(angles), np.zeros(RIM_POINTS)), axis=1)  # (RIM_POINTS, 3)
    rings = []
    for start, end, radius in sections:
        count = max(2, int(math.ceil((end - start) / RING_SPACING_M)) + 1)
        for back in np.linspace(max(start, 0.0), max(end, 0.0), count):
            local = radius * ring - np.array((0.0, 0.0, back))  # z along the tool, away from the flange
            local.setflags(write=False)
            rings.append(local)
    return tuple(rings)


@functools.cache
def contact_ramps(robot_name: str) -> dict[str, float]:
    """:func:`contact_ramps_from_scene`, kept with the model's facts (:mod:`cosmos.model_facts`)."""
    scene_xml = ROBOTS[robot_name].scene_xml
    return kept(
        scene_xml.parent, f"contact_ramps:{scene_xml.name}", lambda: contact_ramps_from_scene(robot_name)
    )


def contact_ramps_from_scene(robot_name: str) -> dict[str, float]:
    """Each world geom's contact impedance width against the tool, by geom name [m] (the scene file's)."""
    import mujoco

    model = mujoco.MjModel.from_xml_path(str(ROBOTS[robot_name].scene_xml))
    tool_body = model.body("tool").id
    tool = next(g for g in range(model.ngeom) if model.geom_bodyid[g] == tool_body and model.geom_contype[g])
    ramps = {}
    for g in range(model.ngeom):
        if model.geom_bodyid[g] == 0 and model.geom(g).name:
            mix_tool, mix_geom = float(model.geom_solmix[tool]), float(model.geom_solmix[g])
            share = mix_tool / (mix_tool + mix_geom) if mix_tool + mix_geom > 0.0 else 0.5
            width = share * model.geom_solimp[tool, 2] + (1.0 - share) * model.geom_solimp[g, 2]
            ramps[model.geom(g).name] = float(width)
    return ramps


HELD_PUSH_LOOK_M = 0.3
"""How far along a held push the surface it would land on is looked for [m]: a CONTACT's reach."""


def held_push(setpoint: ServoSetpoint) -> bool:
    """A push held at a surface with its landing (:func:`cosmos.osc.held_push.held_push_cap`).

    A hold (a CONTACT's, a WAIT in contact) whose translation is force-controlled and not held to a
    speed (an INSERT's push is); a SLIDE's tool moves across the surface, away from where the
    landing was traced, and keeps the SPEED alone.
    """
    forced = not all(setpoint.motion_axes[:3]) and bool(np.any(setpoint.force_world[:3]))
    return forced and setpoint.mode is MotionMode.HOLD and not setpoint.limit_push_speed


def guarded_approach(segment: Segment, setpoint: ServoSetpoint) -> bool:
    """A guarded MOVE (UNTIL on a force or moment) by goal motion: it lands as a CONTACT's approach.

    Its UNTIL ends it at the touch, and the arm brakes from there (cosmos.execution.holding): the
    impact is the momentum it meets the surface with. ``MOVE BY (0, 0, -100 mm) UNTIL FORCE > 5 N``
    from 50 mm over the table at the default 100 mm/s peaked at 174-195 N, 4 ms after the stop
    (its limit 2 x 5 + 30 N, the sensor's rating 130 N); landing at the CONTACT's speeds, 20-24 N.
    A timed move (``IN t``) keeps its time.
    """
    guarded = segment.kind is SegmentKind.MOVE and has_force_term(segment.until)[0]
    return guarded and setpoint.mode is MotionMode.GOAL and setpoint.trajectory is None


def fast_insert(segment: Segment, setpoint: ServoSetpoint) -> bool:
    """An INSERT's approach over :data:`~cosmos.osc.landing.CUSHIONED_LANDING_MPS`: it lands at that speed.

    An INSERT's approach onto the hole's chamfer lands at its SPEED up to 30 mm/s
    (:mod:`cosmos.osc.push_speed`: slower, the insertion after it stalled); faster, it met the
    hole's mouth at its SPEED: SPEED 100 mm/s stopped at 111.7 N (issue 14). So above 30 mm/s it
    lands at 30 mm/s on the surface its model foresees (on a steel face square to it, slower:
    :func:`with_landing`).
    """
    inserting = segment.kind is SegmentKind.CONTACT_APPROACH and isinstance(segment.completion, DepthReached)
    speed = segment.speed_limit_mps  # the SPEED (the approach's own limit runs 3 mm/s under 1.1 times it)
    return inserting and speed is not None and speed > CUSHIONED_LANDING_MPS


SQUARE_FACE_COS = math.cos(math.radians(15.0))
"""A face whose outward normal is within 15 deg of the approach's reverse is square to it
(:func:`square_face`); the hole's chamfers are at 45 deg."""
MET_M = 1e-4
"""A tool point this close to a solid where the trace stopped is on the surface met [m]."""


def insert_approach(segment: Segment) -> bool:
    """An INSERT's approach: every axis held until its touch (:class:`cosmos.plan.DepthReached`)."""
    completion = segment.completion
    inserting = isinstance(completion, DepthReached) and completion.touch_n is not None
    return segment.kind is SegmentKind.CONTACT_APPROACH and inserting


def square_face(
    solids: tuple[FixtureSolid, ...], points: FloatArray, direction: FloatArray, distance_m: float
) -> bool:
    """Whether the tool's points, moved ``distance_m`` along ``direction``, meet a face square to it.

    The outward normal is the gradient of the solids' signed distance (central differences) at
    each point then within :data:`MET_M` of them: the flat around a hole is square to an INSERT
    down, the hole's 45 deg chamfer is not.
    """
    moved = np.asarray(points, dtype=float) + distance_m * np.asarray(direction, dtype=float)
    met = moved[signed_distances(solids, moved).min(axis=1) < MET_M]
    if not met.size:
        return False
    step = TRACE_TOLERANCE_M
    gradient = np.stack(
        [
            signed_distances(solids, met + step * axis).min(axis=1)
            - signed_distances(solids, met - step * axis).min(axis=1)
            for axis in np.eye(3)
        ],
        axis=1,
    )  # (m, 3)
    lengths = np.linalg.norm(gradient, axis=1)
    facing = -gradient.dot(direction)[lengths > 0.0] / lengths[lengths > 0.0]
    return bool(np.any(facing >= SQUARE_FACE_COS))


def with_landing(
    setpoint: ServoSetpoint, segment: Segment, runtime: Runtime, rotation: FloatArray, tool: str
) -> ServoSetpoint:
    """A CONTACT approach's setpoint with its landing on the stiff surface ahead, if its model knows one.

    A held push (:func:`held_push`) gets the landing where it loses its surface:
    :func:`cosmos.osc.held_push.held_push_cap` reads ``s_l`` from its ``x_d`` along the push.

    Args:
        setpoint: The segment's setpoint (a CONTACT's approach: a goal motion toward its far goal).
        segment: The segment: any but a CONTACT's or an INSERT's approach or a held push gets
            ``setpoint`` back as it is (an INSERT's approach onto the hole's chamfer too, below
            30 mm/s: :func:`fast_insert`).
        runtime: The runtime: the tool point now, Lambda, the arm's name.
        rotation: The tool's orientation now (tool to world). # (3, 3)
        tool: The tool on its flange (``peg``, ``gripper``).
    """
    from cosmos.runtime.foresight_cache import workcell

    holds = held_push(setpoint)
    approaches = segment.kind is SegmentKind.CONTACT_APPROACH and isinstance(segment.completion, ContactTouch)
    guarded = guarded_approach(segment, setpoint)
    inserts = insert_approach(segment)
    if not (holds or approaches or guarded or inserts):
        return setpoint
    evaluation, robot_name = runtime.evaluation, runtime.robot.description.name
    start, lambda_ = np.asarray(evaluation.position, dtype=float), evaluation.lambda_
    cell = workcell(robot_name, tool)
    if holds:  # from the tool point along the push, as far as a CONTACT's approach looks
        direction = setpoint.force_world[:3] / float(np.linalg.norm(setpoint.force_world[:3]))
        travel = float(direction.dot(np.asarray(setpoint.position, dtype=float) - start))  # n^T (x_d - x)
        points, reach = start[None, :], HELD_PUSH_LOOK_M
    else:
        line = np.asarray(setpoint.position, dtype=float) - start
        travel = reach = float(np.linalg.norm(line))
        if not travel > 0.0:
            return setpoint
        direction, points = line / travel, tool_points(start, rotation, cell.tool_sections)
    distance, solid = surface_ahead(
        cell.solids, points, direction, reach, INSERT_TRACE_STEPS if inserts else TRACE_STEPS
    )
    if solid < 0 or guarded and distance <= LANDING_ZONE_M:  # a guarded MOVE from a touch: no landing
        return setpoint
    stiff = contact_ramps(robot_name).get(cell.solids[solid].geom, 0.0) < STIFF_RAMP_M
    at = travel - distance + LANDING_ZONE_M  # from the goal (a hold's x_d), along the line
    if inserts and not (stiff and square_face(cell.solids, points, direction, distance)):
        if not fast_insert(segment, setpoint):  # on the hole's chamfer at its SPEED (push_speed)
            return setpoint
        return replace(setpoint, landing=(at, CUSHIONED_LANDING_MPS, LANDING_DECELERATION_MPS2))
    if not stiff:
        if holds or not CUSHIONED_LANDING_MPS < setpoint.max_speed:
            return setpoint
        return replace(setpoint, landing=(at, CUSHIONED_LANDING_MPS, LANDING_DECELERATION_MPS2))
    mass = float(direction.dot(np.asarray(lambda_)[:3, :3]).dot(direction))  # Lambda_n
    force = float(np.linalg.norm(setpoint.force_world[:3]))  # a hold's; an approach's is its CONTACT's
    if isinstance(segment.completion, (ContactTouch, DepthReached)):  # a CONTACT's FORCE, an INSERT's
        force = segment.completion.force_n
    elif segment.kind is SegmentKind.MOVE:  # a guarded motion's: its UNTIL's threshold
        force = has_force_term(segment.until)[1]
    speed = landing_speed(mass, setpoint.max_speed, force)
    # An INSERT's approach onto a flat steel face lands as a CONTACT's does, its cruise integral on.
    integral = setpoint.cruise_integral or inserts
    return replace(setpoint, landing=(at, speed, LANDING_DECELERATION_MPS2), cruise_integral=integral)
