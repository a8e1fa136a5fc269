"""Where a CONTACT's approach meets a stiff surface of its workcell model (:mod:`cosmos.osc.landing`).

The controller's workcell model is the scene file at its nominal poses: the fixtures' solids
(:attr:`cosmos.runtime.foresight_cache.Workcell.solids`, as the checker sees them, not where a
sweep's drawn variation put them in the plant) and their contact materials (the geoms'
``solimp`` and ``solmix`` in the scene file, mixed with the tool's as MuJoCo mixes them). From
the tool's end (its tool point and the rim of its end section) the approach's line is traced
into the solids (sphere tracing on their exact signed distances, as
:func:`cosmos.runtime.fixture_solids.top_above` does upward); the nearest surface hit sets the
landing if its contact is stiff (:data:`cosmos.osc.landing.STIFF_RAMP_M`).
"""

from __future__ import annotations

import functools
import math
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from cosmos.model_facts import kept
from cosmos.osc.landing import (
    LANDING_DECELERATION_MPS2,
    LANDING_ZONE_M,
    STIFF_RAMP_M,
    landing_speed,
)
from cosmos.plan import ContactTouch, Segment, SegmentKind
from cosmos.robots import ROBOTS
from cosmos.runtime.fixture_solids import FixtureSolid, signed_distances
from cosmos.runtime.setpoint import ServoSetpoint

if TYPE_CHECKING:
    from cosmos.runtime.loop import Runtime

FloatArray = np.ndarray

RIM_POINTS = 16
"""Points on the rim of the tool's end section traced besides the tool point."""
TRACE_TOLERANCE_M = 1e-5
"""A traced point this close to a solid has met it [m]."""


def surface_ahead(
    solids: tuple[FixtureSolid, ...], points: FloatArray, direction: FloatArray, travel_m: float
) -> tuple[float, int]:
    """How far ``points`` move along ``direction`` before the first of them meets a solid.

    Sphere tracing: a point at distance d outside every solid may move d along any line
    without entering one.

    Args:
        solids: The workcell's solids.
        points: The tool's points, world [m]. # (m, 3)
        direction: The unit approach direction, world. # (3,)
        travel_m: How far to look [m].

    Returns:
        ``(distance [m], solid index)``; ``(inf, -1)`` if none is met within ``travel_m``.
    """
    if not solids:
        return math.inf, -1
    at = np.zeros(len(points))
    moving = np.ones(len(points), dtype=bool)
    best, which = math.inf, -1
    for _ in range(200):
        if not moving.any():
            break
        distances = signed_distances(solids, points[moving] + at[moving, None] * direction)
        nearest = distances.min(axis=1)
        index = np.flatnonzero(moving)
        met = nearest < TRACE_TOLERANCE_M
        for k in np.flatnonzero(met):
            if at[index[k]] < best:
                best, which = float(at[index[k]]), int(distances[k].argmin())
        at[index] += np.where(met, 0.0, np.maximum(nearest, TRACE_TOLERANCE_M))
        moving[index[met]] = False
        moving &= at <= min(travel_m, best)
    return best, which


def tool_end_points(
    position: FloatArray, rotation: FloatArray, sections: tuple[tuple[float, float, float], ...]
) -> FloatArray:
    """The tool point and the rim of the tool's section at its end, world [m]. # (1 + RIM_POINTS, 3)."""
    points = [np.asarray(position, dtype=float)]
    ends = [s for s in sections if s[0] <= 1e-9]
    if ends:
        radius = max(s[2] for s in ends)
        for angle in np.linspace(0.0, 2.0 * math.pi, RIM_POINTS, endpoint=False):
            local = np.array((radius * math.cos(angle), radius * math.sin(angle), 0.0))
            points.append(points[0] + np.asarray(rotation).dot(local))
    return np.array(points)


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


def with_landing(
    setpoint: ServoSetpoint, segment: Segment, runtime: Runtime, rotation: FloatArray, tool: str
) -> ServoSetpoint:
    """A CONTACT approach's setpoint with its landing on the stiff surface ahead, if its model knows one.

    Args:
        setpoint: The segment's setpoint (a CONTACT's approach: a goal motion toward its far goal).
        segment: The segment: any but a CONTACT's approach (an INSERT's too, tuned to its own
            landing: cosmos.osc.push_speed) gets ``setpoint`` back as it is.
        runtime: The runtime: the tool point now, Lambda, the arm's name.
        rotation: The tool's orientation now (tool to world). # (3, 3)
        tool: The tool on its flange (``peg``, ``gripper``).
    """
    from cosmos.runtime.foresight_cache import workcell

    if segment.kind is not SegmentKind.CONTACT_APPROACH or not isinstance(segment.completion, ContactTouch):
        return setpoint
    evaluation, robot_name = runtime.evaluation, runtime.robot.description.name
    start, lambda_ = evaluation.position, evaluation.dynamics.lambda_
    line = np.asarray(setpoint.position, dtype=float) - np.asarray(start, dtype=float)
    travel = float(np.linalg.norm(line))
    if not travel > 0.0:
        return setpoint
    direction = line / travel
    cell = workcell(robot_name, tool)
    points = tool_end_points(start, rotation, cell.tool_sections)
    distance, solid = surface_ahead(cell.solids, points, direction, travel)
    if solid < 0 or contact_ramps(robot_name).get(cell.solids[solid].geom, 0.0) >= STIFF_RAMP_M:
        return setpoint
    mass = float(direction.dot(np.asarray(lambda_)[:3, :3]).dot(direction))  # Lambda_n
    speed = landing_speed(mass, setpoint.max_speed)
    at = travel - distance + LANDING_ZONE_M  # from the goal, along the line
    return replace(setpoint, landing=(at, speed, LANDING_DECELERATION_MPS2))
