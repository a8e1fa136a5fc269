"""An obstacle as both the simulator and the controller know it: a primitive with a motion.

An :class:`Obstacle` is built from the compiler's :class:`cosmos.plan.AddObstacle`
when the step runs (the time it was added is its epoch). Its pose at time ``t``
is the declared pose moved by ``velocity (t - added)``: a ``MOVING`` obstacle
translates at constant velocity and never turns.

Shape frame conventions (as in :class:`~cosmos.plan.AddObstacle`): the position
is the shape's centre (a cylinder's mid-axis, a plane's point); a cylinder's
axis and a plane's outward normal are the shape frame's z axis; a box's edges
are its x, y, z axes.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from cosmos.errors import CosmosError, Span
from cosmos.plan import AddObstacle, ObstacleShape

FloatArray = np.ndarray


def _frozen(array: object, shape: tuple[int, ...]) -> FloatArray:
    out = np.array(array, dtype=float).reshape(shape)
    out.setflags(write=False)
    return out


def _positive(value: float | None, what: str, name: str, span: Span | None) -> float:
    if value is None or not math.isfinite(value) or value <= 0.0:
        raise CosmosError(f"obstacle '{name}': {what} must be a positive length, got {value}", span)
    return float(value)


@dataclass(frozen=True, eq=False)
class Obstacle:
    """A primitive obstacle (seed section 6) with a constant velocity.

    Attributes:
        name: The obstacle's name in the program.
        shape: Its primitive.
        position_world: Shape centre at ``added_s``, in [m]. # (3,)
        rotation_world: Shape frame to world. # (3, 3)
        half_extents_m: Sphere ``(r, r, r)``; cylinder ``(r, r, h/2)``; box half
            its edges; plane ``(inf, inf, 0)``, in [m]. # (3,)
        velocity_world_mps: Constant velocity, in [m/s]. # (3,)
        influence_m: rho_0 for this obstacle, or None for the field's default.
        gain_scale: Factor on the field's default gain eta.
        added_s: Simulated time at which it was added, in [s].
    """

    name: str
    shape: ObstacleShape
    position_world: FloatArray
    rotation_world: FloatArray
    half_extents_m: FloatArray
    velocity_world_mps: FloatArray
    influence_m: float | None = None
    gain_scale: float = 1.0
    added_s: float = 0.0

    @property
    def radius_m(self) -> float:
        """Sphere or cylinder radius, in [m] (the first half extent)."""
        return float(self.half_extents_m[0])

    @functools.cached_property
    def moving(self) -> bool:
        """True when the obstacle has a non-zero velocity (its velocity is read-only: worked out once).

        Asked at every draw of the scene and every position: NumPy's answer cost 3-14 us a time.
        """
        return bool(np.any(self.velocity_world_mps != 0.0))

    def position_at(self, t_s: float) -> FloatArray:
        """Shape centre at simulated time ``t_s``, in [m]. # (3,)."""
        if not self.moving:
            return self.position_world
        return self.position_world + (t_s - self.added_s) * self.velocity_world_mps

    @property
    def bounding_radius_m(self) -> float:
        """Radius of a sphere about the centre that contains the shape (inf for a plane), in [m]."""
        if self.shape is ObstacleShape.PLANE:
            return math.inf
        if self.shape is ObstacleShape.SPHERE:
            return self.radius_m
        if self.shape is ObstacleShape.CYLINDER:
            return math.hypot(self.radius_m, float(self.half_extents_m[2]))
        return float(np.linalg.norm(self.half_extents_m))


def sphere(name: str, center: object, radius_m: float, velocity_mps: object = (0.0, 0.0, 0.0)) -> Obstacle:
    """A sphere of radius ``radius_m`` centred on ``center`` [m] (a convenience for tests and tools)."""
    r = _positive(radius_m, "the radius", name, None)
    return Obstacle(
        name,
        ObstacleShape.SPHERE,
        _frozen(center, (3,)),
        _frozen(np.eye(3), (3, 3)),
        _frozen((r, r, r), (3,)),
        _frozen(velocity_mps, (3,)),
    )


def box(name: str, center: object, size_m: object, velocity_mps: object = (0.0, 0.0, 0.0)) -> Obstacle:
    """An axis-aligned box with edge lengths ``size_m`` centred on ``center`` [m]."""
    size = np.asarray(size_m, dtype=float).reshape(3)
    for edge in size:
        _positive(float(edge), "every edge", name, None)
    return Obstacle(
        name,
        ObstacleShape.BOX,
        _frozen(center, (3,)),
        _frozen(np.eye(3), (3, 3)),
        _frozen(0.5 * size, (3,)),
        _frozen(velocity_mps, (3,)),
    )


def cylinder(name: str, center: object, radius_m: float, height_m: float) -> Obstacle:
    """A vertical cylinder (a post) whose axis' midpoint is ``center`` [m]."""
    r = _positive(radius_m, "the radius", name, None)
    h = _positive(height_m, "the height", name, None)
    return Obstacle(
        name,
        ObstacleShape.CYLINDER,
        _frozen(center, (3,)),
        _frozen(np.eye(3), (3, 3)),
        _frozen((r, r, 0.5 * h), (3,)),
        _frozen((0.0, 0.0, 0.0), (3,)),
    )


def from_step(step: AddObstacle, t_s: float) -> Obstacle:
    """The obstacle an ``OBSTACLE`` statement adds at simulated time ``t_s``.

    Args:
        step: The compiled statement.
        t_s: Simulated time of the step, in [s]: the epoch of a ``MOVING`` obstacle.

    Returns:
        The obstacle.

    Raises:
        CosmosError: If a dimension the shape needs is missing or not positive.
    """
    name, span = step.name, step.span
    half: tuple[float, ...]
    if step.shape is ObstacleShape.SPHERE:
        r = _positive(step.radius_m, "RADIUS", name, span)
        half = (r, r, r)
    elif step.shape is ObstacleShape.CYLINDER:
        r = _positive(step.radius_m, "RADIUS", name, span)
        half = (r, r, 0.5 * _positive(step.height_m, "HEIGHT", name, span))
    elif step.shape is ObstacleShape.BOX:
        if step.size_m is None:
            raise CosmosError(f"obstacle '{name}': a BOX needs a SIZE", span)
        half = tuple(0.5 * _positive(float(s), "every SIZE edge", name, span) for s in step.size_m)
    else:
        half = (math.inf, math.inf, 0.0)
    if step.influence_m is not None:
        _positive(step.influence_m, "the influence distance", name, span)
    if not math.isfinite(step.gain_scale) or step.gain_scale < 0.0:
        raise CosmosError(f"obstacle '{name}': the gain factor must be >= 0, got {step.gain_scale}", span)
    return Obstacle(
        name=name,
        shape=step.shape,
        position_world=_frozen(step.position_world, (3,)),
        rotation_world=_frozen(step.rotation_world, (3, 3)),
        half_extents_m=_frozen(half, (3,)),
        velocity_world_mps=_frozen(step.velocity_world_mps, (3,)),
        influence_m=step.influence_m,
        gain_scale=float(step.gain_scale),
        added_s=float(t_s),
    )
