"""Distance from the arm's capsules to an obstacle: a cheap lower bound and the exact closest point.

The exact closest approach of one capsule to one primitive comes from
:mod:`cosmos.osc.firas` (a golden-section search for boxes and finite
cylinders). Before it, :func:`distance_lower_bounds` rules out, for all
capsules at once, those that cannot be within the influence distance: the
obstacle's signed distance function is 1-Lipschitz, so a capsule held in a
sphere of radius ``bound`` about the point ``c`` is at least
``sdf(c) - bound`` from the obstacle.
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


def distance_lower_bounds(
    midpoints: FloatArray, bounds_m: FloatArray, obstacle: Obstacle, center: FloatArray
) -> FloatArray:
    """A lower bound of each capsule's surface distance to the obstacle, in [m].

    Args:
        midpoints: Segment midpoints, world, in [m]. # (n, 3)
        bounds_m: Radii of spheres about the midpoints holding the capsules, in [m]. # (n,)
        obstacle: The primitive.
        center: The obstacle's centre now, world, in [m]. # (3,)

    Returns:
        ``sdf(midpoint) - bound`` per capsule, in [m]. # (n,)
    """
    return signed_distances(midpoints, obstacle, center) - bounds_m


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
