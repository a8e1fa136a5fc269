"""Compiled closed-form distances: a capsule to a sphere or a plane, a point to any obstacle.

The proximity model (:mod:`cosmos.obstacles.geometry`) asks MuJoCo's
``mj_geomDistance`` for the distance between a capsule and a box or a finite
cylinder; for a sphere and a plane MuJoCo's own collision functions are
closed form (``mjc_SphereCapsule``, ``mjc_PlaneCapsule``), and these are the
same formulas, answered the same way (distance capped at ``distmax``, the
segment from the capsule's surface to the obstacle's), without a call from
Python per pair. ``tests/obstacles/test_obstacles_distance_kernel.py`` checks
them against ``mj_geomDistance`` and :func:`cosmos.obstacles.proximity.signed_distances`.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel

FloatArray = np.ndarray

# ``shapes`` (k, SHAPE): per obstacle, its primitive (KIND_*), shape frame to world (row-major) and
# half extents [m] (as :class:`cosmos.obstacles.obstacle.Obstacle`).
SHAPE_KIND, SHAPE_ROTATION, SHAPE_HALF = 0, 1, 10
SHAPE = 13
KIND_SPHERE, KIND_CYLINDER, KIND_BOX, KIND_PLANE = 0.0, 1.0, 2.0, 3.0

# ``capsules`` (n, CAPSULE): per capsule, the joint (= link) carrying it; its geom's frame in the
# joint's frame (origin at the segment's midpoint [m], rotation with z along the segment); half its
# segment's length and its radius [m] (as the private model's geom) and the radius of a sphere about
# the midpoint that holds it [m].
CAPSULE_JOINT, CAPSULE_MID, CAPSULE_ROTATION, CAPSULE_HALF, CAPSULE_RADIUS, CAPSULE_BOUND = (
    0,
    1,
    4,
    13,
    14,
    15,
)
CAPSULE = 16


@kernel
def signed_distance(
    x: float, y: float, z: float, shape: FloatArray, cx: float, cy: float, cz: float
) -> float:
    """:func:`cosmos.obstacles.proximity.signed_distances` of one point, the obstacle centred on c; [m]."""
    dx, dy, dz = x - cx, y - cy, z - cz
    r = SHAPE_ROTATION
    # The point in the shape's frame: R^T (p - c).
    lx = dx * shape[r] + dy * shape[r + 3] + dz * shape[r + 6]
    ly = dx * shape[r + 1] + dy * shape[r + 4] + dz * shape[r + 7]
    lz = dx * shape[r + 2] + dy * shape[r + 5] + dz * shape[r + 8]
    kind = shape[SHAPE_KIND]
    hx, hy, hz = shape[SHAPE_HALF], shape[SHAPE_HALF + 1], shape[SHAPE_HALF + 2]
    if kind == KIND_SPHERE:
        return math.sqrt(lx * lx + ly * ly + lz * lz) - hx
    if kind == KIND_PLANE:
        return lz
    if kind == KIND_CYLINDER:
        radial = math.hypot(lx, ly) - hx
        axial = abs(lz) - hz
        return math.hypot(max(radial, 0.0), max(axial, 0.0)) + min(max(radial, axial), 0.0)
    qx, qy, qz = abs(lx) - hx, abs(ly) - hy, abs(lz) - hz
    ox, oy, oz = max(qx, 0.0), max(qy, 0.0), max(qz, 0.0)
    return math.sqrt(ox * ox + oy * oy + oz * oz) + min(max(qx, max(qy, qz)), 0.0)


@kernel
def capsule_sphere(
    fromto: FloatArray,
    mid: FloatArray,
    axis: FloatArray,
    half_m: float,
    radius_m: float,
    center: FloatArray,
    sphere_radius_m: float,
    distmax_m: float,
) -> float:
    """Surface distance of a capsule and a sphere, as ``mj_geomDistance(capsule, sphere)``, in [m].

    Mirrors :func:`cosmos.osc.firas.capsule_sphere` (within ``distmax_m``).

    The sphere's centre is projected on the capsule's segment (``mid +- half_m
    axis``, ``axis`` unit); the two surface points lie on the line through the
    projection and the centre.

    Args:
        fromto: Written: the capsule's closest point, then the sphere's, world, in [m]
            (zeros when the distance is ``distmax_m`` or more). # (6,)
        mid: The segment's midpoint, world, in [m]. # (3,)
        axis: The segment's unit direction, world. # (3,)
        half_m: Half the segment's length, in [m].
        radius_m: The capsule's radius, in [m].
        center: The sphere's centre, world, in [m]. # (3,)
        sphere_radius_m: Its radius, in [m].
        distmax_m: The distance returned, capped, when the surfaces are this far apart or more.
    """
    ax, ay, az = axis[0] * half_m, axis[1] * half_m, axis[2] * half_m
    vx, vy, vz = center[0] - mid[0], center[1] - mid[1], center[2] - mid[2]
    length2 = ax * ax + ay * ay + az * az
    x = 0.0 if length2 <= 0.0 else min(1.0, max(-1.0, (ax * vx + ay * vy + az * vz) / length2))
    sx, sy, sz = mid[0] + x * ax, mid[1] + x * ay, mid[2] + x * az
    dx, dy, dz = center[0] - sx, center[1] - sy, center[2] - sz
    gap = math.sqrt(dx * dx + dy * dy + dz * dz)
    distance = gap - radius_m - sphere_radius_m
    fromto[:] = 0.0
    if distance >= distmax_m:
        return distmax_m
    if gap > 0.0:
        ux, uy, uz = dx / gap, dy / gap, dz / gap
    else:  # the centre on the segment: any direction
        ux, uy, uz = 1.0, 0.0, 0.0
    fromto[0], fromto[1], fromto[2] = sx + radius_m * ux, sy + radius_m * uy, sz + radius_m * uz
    fromto[3] = center[0] - sphere_radius_m * ux
    fromto[4] = center[1] - sphere_radius_m * uy
    fromto[5] = center[2] - sphere_radius_m * uz
    return distance


@kernel
def capsule_plane(
    fromto: FloatArray,
    mid: FloatArray,
    axis: FloatArray,
    half_m: float,
    radius_m: float,
    point: FloatArray,
    normal: FloatArray,
    distmax_m: float,
) -> float:
    """Height of a capsule above a plane, as ``mj_geomDistance(capsule, plane)``, in [m].

    Mirrors :func:`cosmos.osc.firas.capsule_plane` (within ``distmax_m``).

    The lower of the segment's two ends (the ``+axis`` end first on a tie, as
    MuJoCo's ``mjc_PlaneCapsule``) minus the radius.

    Args:
        fromto: Written: the capsule's lowest point, then its projection on the plane, world, in [m]
            (zeros when the distance is ``distmax_m`` or more). # (6,)
        mid: The segment's midpoint, world, in [m]. # (3,)
        axis: The segment's unit direction, world. # (3,)
        half_m: Half the segment's length, in [m].
        radius_m: The capsule's radius, in [m].
        point: A point of the plane, world, in [m]. # (3,)
        normal: The plane's unit outward normal, world. # (3,)
        distmax_m: The distance returned, capped, when the surfaces are this far apart or more.
    """
    nx, ny, nz = normal[0], normal[1], normal[2]
    fromto[:] = 0.0
    best = distmax_m
    for sign in (1.0, -1.0):
        ex = mid[0] + sign * half_m * axis[0]
        ey = mid[1] + sign * half_m * axis[1]
        ez = mid[2] + sign * half_m * axis[2]
        height = nx * (ex - point[0]) + ny * (ey - point[1]) + nz * (ez - point[2])
        distance = height - radius_m
        if distance < best:
            best = distance
            fromto[0], fromto[1], fromto[2] = ex - radius_m * nx, ey - radius_m * ny, ez - radius_m * nz
            fromto[3], fromto[4], fromto[5] = ex - height * nx, ey - height * ny, ez - height * nz
    return best


@kernel
def analytic_distance(
    fromto: FloatArray,
    geom_xpos: FloatArray,
    geom_xmat: FloatArray,
    capsules: FloatArray,
    i: int,
    shapes: FloatArray,
    j: int,
    distmax_m: float,
) -> float:
    """Capsule ``i`` to obstacle ``j`` (a sphere or a plane), closed form, as ``mj_geomDistance``; in [m].

    The geoms' poses are read from ``geom_xpos`` and ``geom_xmat`` (capsules
    first, then the obstacles), as MuJoCo would; ``fromto`` gets the segment
    from the capsule to the obstacle. # (6,)
    """
    n = capsules.shape[0]
    c, shape = capsules[i], shapes[j]
    axis = np.empty(3)
    axis[0], axis[1], axis[2] = geom_xmat[i, 2], geom_xmat[i, 5], geom_xmat[i, 8]
    if shape[SHAPE_KIND] == KIND_SPHERE:
        return capsule_sphere(
            fromto,
            geom_xpos[i],
            axis,
            c[CAPSULE_HALF],
            c[CAPSULE_RADIUS],
            geom_xpos[n + j],
            shape[SHAPE_HALF],
            distmax_m,
        )
    normal = np.empty(3)
    r = SHAPE_ROTATION
    normal[0], normal[1], normal[2] = shape[r + 2], shape[r + 5], shape[r + 8]
    return capsule_plane(
        fromto, geom_xpos[i], axis, c[CAPSULE_HALF], c[CAPSULE_RADIUS], geom_xpos[n + j], normal, distmax_m
    )


@kernel
def segment_lower_bound(
    mid: FloatArray, axis: FloatArray, half_m: float, shape: FloatArray, cx: float, cy: float, cz: float
) -> float:
    """A lower bound on the distance from a segment to a box or a cylinder centred on ``c``, in [m].

    Along each axis of a box, and along a cylinder's axis and across it, the
    segment's extent and the obstacle's are intervals: the gap between them
    bounds every distance between a point of one and a point of the other
    (a separating axis). The largest gap is returned (at most 0 when none
    separates); for a sphere or a plane, the midpoint's signed distance less
    ``half_m``.

    Args:
        mid: The segment's midpoint, world, in [m]. # (3,)
        axis: Its unit direction, world. # (3,)
        half_m: Half its length, in [m].
        shape: The obstacle's row of ``shapes`` (``SHAPE_*``). # (SHAPE,)
        cx: The obstacle's centre, world x, in [m].
        cy: Its y, in [m].
        cz: Its z, in [m].
    """
    kind = shape[SHAPE_KIND]
    if kind == KIND_SPHERE or kind == KIND_PLANE:
        return signed_distance(mid[0], mid[1], mid[2], shape, cx, cy, cz) - half_m
    r = SHAPE_ROTATION
    dx, dy, dz = mid[0] - cx, mid[1] - cy, mid[2] - cz
    # Midpoint and half-axis in the shape's frame: R^T (p - c), R^T a half.
    local = np.empty(3)
    extent = np.empty(3)
    for k in range(3):
        local[k] = dx * shape[r + k] + dy * shape[r + 3 + k] + dz * shape[r + 6 + k]
        extent[k] = half_m * (
            axis[0] * shape[r + k] + axis[1] * shape[r + 3 + k] + axis[2] * shape[r + 6 + k]
        )
    if kind == KIND_BOX:
        gap = -np.inf
        for k in range(3):
            gap = max(gap, abs(local[k]) - abs(extent[k]) - shape[SHAPE_HALF + k])
        return gap
    axial = abs(local[2]) - abs(extent[2]) - shape[SHAPE_HALF + 2]
    # Distance from the cylinder's axis to the segment's projection across it.
    ex, ey = extent[0], extent[1]
    length2 = ex * ex + ey * ey
    t = 0.0 if length2 <= 0.0 else min(1.0, max(-1.0, -(local[0] * ex + local[1] * ey) / length2))
    radial = math.hypot(local[0] + t * ex, local[1] + t * ey) - shape[SHAPE_HALF]
    return max(axial, radial)
