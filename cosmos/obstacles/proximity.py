"""Distances to an obstacle in pure Python/numpy: of points, and of a capsule with its closest point.

:func:`capsule_proximity` dispatches to :mod:`cosmos.osc.firas` (closed form
for spheres and planes, a golden-section search for boxes and finite
cylinders). It is the reference for the field's fast distances
(:mod:`cosmos.obstacles.geometry`) and what the field uses when a link touches
an obstacle. :func:`signed_distances` is the obstacle's signed distance
function, e.g. to tell whether a target lies inside an obstacle.
"""

from __future__ import annotations

import numpy as np

from cosmos.obstacles.obstacle import Obstacle
from cosmos.osc.firas import Proximity, capsule_box, capsule_cylinder, capsule_plane, capsule_sphere
from cosmos.plan import ObstacleShape

FloatArray = np.ndarray


def signed_distances(points: FloatArray, obstacle: Obstacle, center: FloatArray) -> FloatArray:
    """Signed distance from each point to the obstacle's surface (negative inside), in [m].

    Args:
        points: Points, world, in [m]. # (n, 3)
        obstacle: The primitive.
        center: The obstacle's centre now, world, in [m]. # (3,)

    Returns:
        The distances, in [m]. # (n,)
    """
    local = (points - center).dot(obstacle.rotation_world)  # (n, 3): rows R^T (p - c)
    half = obstacle.half_extents_m
    if obstacle.shape is ObstacleShape.SPHERE:
        return np.sqrt(np.einsum("ij,ij->i", local, local)) - half[0]
    if obstacle.shape is ObstacleShape.PLANE:
        return local[:, 2].copy()
    if obstacle.shape is ObstacleShape.CYLINDER:
        radial = np.hypot(local[:, 0], local[:, 1]) - half[0]
        axial = np.abs(local[:, 2]) - half[2]
        outside = np.hypot(np.maximum(radial, 0.0), np.maximum(axial, 0.0))
        return outside + np.minimum(np.maximum(radial, axial), 0.0)
    q = np.abs(local) - half  # (n, 3)
    outside = np.sqrt(np.einsum("ij,ij->i", np.maximum(q, 0.0), np.maximum(q, 0.0)))
    return outside + np.minimum(q.max(axis=1), 0.0)


def capsule_proximity(
    a: FloatArray, b: FloatArray, radius_m: float, obstacle: Obstacle, center: FloatArray
) -> Proximity:
    """Closest approach of the capsule ``a``-``b`` (radius ``radius_m``) to the obstacle.

    Args:
        a: Segment start, world, in [m]. # (3,)
        b: Segment end, world, in [m]. # (3,)
        radius_m: Capsule radius, in [m].
        obstacle: The primitive.
        center: The obstacle's centre now, world, in [m]. # (3,)

    Returns:
        Surface distance (negative when penetrating), the capsule's surface point
        closest to the obstacle and the unit normal pointing away from it, world.
    """
    shape, rotation, half = obstacle.shape, obstacle.rotation_world, obstacle.half_extents_m
    if shape is ObstacleShape.SPHERE:
        return capsule_sphere(a, b, radius_m, center, float(half[0]))
    if shape is ObstacleShape.BOX:
        return capsule_box(a, b, radius_m, center, rotation, half)
    if shape is ObstacleShape.PLANE:
        return capsule_plane(a, b, radius_m, center, rotation[:, 2])
    # Cylinder: firas works with a vertical one standing on its base; go to the shape frame.
    base = np.array((0.0, 0.0, -float(half[2])))
    local = capsule_cylinder(
        rotation.T.dot(a - center), rotation.T.dot(b - center), radius_m, base, float(half[0]), 2.0 * half[2]
    )
    return Proximity(local.distance, rotation.dot(local.point) + center, rotation.dot(local.normal))
