"""FIRAS repulsion (Khatib 1986; seed section 6) and capsule-to-obstacle proximity.

Each link of the arm is a capsule (segment ``a``-``b`` swollen by a radius);
obstacles are composed of primitives (sphere, vertical cylinder, oriented box,
plane). The link's point closest to an obstacle is pushed along the surface
normal by the FIRAS force, the negative gradient of::

    U(rho) = eta/2 (1/rho - 1/rho_0)^2   for rho < rho_0, else 0
    |F|    = eta (1/rho - 1/rho_0) / rho^2

with ``rho`` the distance between the surfaces. The force is capped so that it
stays finite as ``rho -> 0`` and on contact (``rho <= 0``).

Every proximity function returns :class:`Proximity`: the signed surface
distance (negative when penetrating), the point of the capsule's surface
closest to the obstacle (where the force applies) and the unit normal pointing
away from the obstacle (the force's direction). Sphere, infinite cylinder and
plane are closed form. For the finite cylinder and the box the signed distance
of the obstacle, convex along the segment (the signed distance to a convex set
is convex), is minimised by golden-section search over the segment parameter;
24 steps locate the point to 1e-5 of the segment length.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple, overload

import numpy as np

from cosmos.osc._types import FloatArray

_GOLDEN = 0.5 * (math.sqrt(5.0) - 1.0)
_GOLDEN_STEPS = 24
_TINY = 1e-12

_Vec = tuple[float, float, float]


class Proximity(NamedTuple):
    """Closest approach of a capsule to an obstacle."""

    distance: float  # [m] between the surfaces; negative when penetrating
    point: FloatArray  # (3,) on the capsule's surface, world, [m]
    normal: FloatArray  # (3,) unit, world, pointing away from the obstacle


@overload
def firas_magnitude(rho: float, rho_0: float, eta: float, cap: float) -> float: ...
@overload
def firas_magnitude(rho: FloatArray, rho_0: float, eta: float, cap: float) -> FloatArray: ...
def firas_magnitude(rho: FloatArray | float, rho_0: float, eta: float, cap: float) -> FloatArray | float:
    """FIRAS force magnitude ``eta (1/rho - 1/rho_0) / rho^2`` for ``rho < rho_0``, capped.

    Args:
        rho: Distance to the obstacle surface, in [m] (or [rad] for joint limits): a float
            (plain arithmetic, the per-link case) or an array.
        rho_0: Influence distance: no force at or beyond it.
        eta: Gain, in [N m^3] (or [N m rad^3] for joint limits).
        cap: Largest magnitude; also the value for ``rho <= 0``.

    Returns:
        The magnitude, a float or shaped like ``rho``.
    """
    if isinstance(rho, float):
        if rho >= rho_0:
            return 0.0
        return cap if rho <= 0.0 else min(eta * (1.0 / rho - 1.0 / rho_0) / (rho * rho), cap)
    rho = np.asarray(rho, dtype=float)
    safe = np.maximum(rho, _TINY)
    magnitude = np.minimum(eta * (1.0 / safe - 1.0 / rho_0) / (safe * safe), cap)
    return np.where(rho < rho_0, magnitude, 0.0)


def repulsion_magnitude(
    distance_m: float, rho_0_m: float, eta: float, damping_ns_per_m: float, cap_n: float, approach_mps: float
) -> float:
    """|F| of the obstacle field on one link's point: FIRAS plus approach damping, capped, in [N].

    Section 6's FIRAS magnitude (:func:`firas_magnitude`) with a damping term on the
    approach speed that fades out toward rho_0; the compiled field
    (:func:`cosmos.obstacles.kernels.field.repulsion_magnitude`) mirrors it.

    Args:
        distance_m: rho, the point's distance to the obstacle's surface, in [m].
        rho_0_m: Influence distance, in [m].
        eta: FIRAS gain, in [N m^3].
        damping_ns_per_m: c, in [N s/m].
        cap_n: Largest magnitude, in [N].
        approach_mps: Speed of the point toward the obstacle along the normal, in [m/s].

    Returns:
        ``eta (1/rho - 1/rho_0)/rho^2 + c (1 - rho/rho_0) max(0, approach)``, capped;
        0 at and beyond rho_0.
    """
    if distance_m >= rho_0_m:
        return 0.0
    magnitude = firas_magnitude(distance_m, rho_0_m, eta, cap_n)
    if approach_mps > 0.0:
        magnitude += damping_ns_per_m * min(1.0, 1.0 - distance_m / rho_0_m) * approach_mps
    return min(magnitude, cap_n)


def firas_potential(rho: FloatArray | float, rho_0: float, eta: float) -> FloatArray:
    """The uncapped FIRAS potential ``eta/2 (1/rho - 1/rho_0)^2`` inside ``rho_0``, else 0.

    Args:
        rho: Distance to the obstacle surface, > 0, in [m].
        rho_0: Influence distance, in [m].
        eta: Gain, in [N m^3].

    Returns:
        U, in [J], shaped like ``rho``.
    """
    rho = np.asarray(rho, dtype=float)
    return np.where(rho < rho_0, 0.5 * eta * (1.0 / rho - 1.0 / rho_0) ** 2, 0.0)


def _result(seg: _Vec, normal: _Vec, distance: float, radius: float) -> Proximity:
    """Move from the segment to the capsule surface along -normal."""
    nx, ny, nz = normal
    point = (seg[0] - radius * nx, seg[1] - radius * ny, seg[2] - radius * nz)
    return Proximity(distance - radius, np.array(point), np.array(normal))


def _perpendicular(dx: float, dy: float, dz: float) -> _Vec:
    """Some unit vector perpendicular to d (any unit vector if d is zero)."""
    ax, ay, az = abs(dx), abs(dy), abs(dz)
    # Cross d with the axis of its smallest component.
    if ax <= ay and ax <= az:
        v = (0.0, dz, -dy)
    elif ay <= az:
        v = (-dz, 0.0, dx)
    else:
        v = (dy, -dx, 0.0)
    n = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return (1.0, 0.0, 0.0) if n < _TINY else (v[0] / n, v[1] / n, v[2] / n)


def capsule_sphere(
    a: FloatArray, b: FloatArray, radius: float, center: FloatArray, sphere_radius: float
) -> Proximity:
    """Capsule ``a``-``b`` (radius ``radius``) against a sphere, closed form.

    Args:
        a: Segment start, world, in [m]. # (3,)
        b: Segment end, world, in [m]. # (3,)
        radius: Capsule radius, in [m].
        center: Sphere centre, world, in [m]. # (3,)
        sphere_radius: In [m].

    Returns:
        The closest approach.
    """
    ax, ay, az = a.tolist()
    dx, dy, dz = (b - a).tolist()
    cx, cy, cz = center.tolist()
    dd = dx * dx + dy * dy + dz * dz
    t = 0.0 if dd < _TINY else min(1.0, max(0.0, ((cx - ax) * dx + (cy - ay) * dy + (cz - az) * dz) / dd))
    px, py, pz = ax + t * dx, ay + t * dy, az + t * dz
    vx, vy, vz = px - cx, py - cy, pz - cz
    dist = math.sqrt(vx * vx + vy * vy + vz * vz)
    normal = _perpendicular(dx, dy, dz) if dist < _TINY else (vx / dist, vy / dist, vz / dist)
    return _result((px, py, pz), normal, dist - sphere_radius, radius)


def capsule_plane(
    a: FloatArray, b: FloatArray, radius: float, plane_point: FloatArray, plane_normal: FloatArray
) -> Proximity:
    """Capsule against a half-space bounded by a plane (e.g. the table), closed form.

    Args:
        a: Segment start, world, in [m]. # (3,)
        b: Segment end, world, in [m]. # (3,)
        radius: Capsule radius, in [m].
        plane_point: A point of the plane, world, in [m]. # (3,)
        plane_normal: The plane's normal, pointing out of the solid side (need not be unit). # (3,)

    Returns:
        The closest approach (the deeper end when the segment crosses the plane).
    """
    nx, ny, nz = plane_normal.tolist()
    norm = math.sqrt(nx * nx + ny * ny + nz * nz)
    normal = (nx / norm, ny / norm, nz / norm)
    offset = float(plane_point.dot(plane_normal)) / norm
    da = float(a.dot(plane_normal)) / norm - offset
    db = float(b.dot(plane_normal)) / norm - offset
    ex, ey, ez = (a if da <= db else b).tolist()
    return _result((ex, ey, ez), normal, min(da, db), radius)


def capsule_cylinder(
    a: FloatArray,
    b: FloatArray,
    radius: float,
    base_center: FloatArray,
    cylinder_radius: float,
    height: float = math.inf,
) -> Proximity:
    """Capsule against a vertical (world z) solid cylinder standing on ``base_center``.

    Args:
        a: Segment start, world, in [m]. # (3,)
        b: Segment end, world, in [m]. # (3,)
        radius: Capsule radius, in [m].
        base_center: Centre of the bottom face, world, in [m]. # (3,)
        cylinder_radius: In [m].
        height: In [m]; ``math.inf`` for an infinite vertical post (closed form).

    Returns:
        The closest approach.
    """
    ox, oy, oz = base_center.tolist()
    ax, ay, az = a.tolist()
    bx, by, bz = b.tolist()
    ax, ay, az, bx, by, bz = ax - ox, ay - oy, az - oz, bx - ox, by - oy, bz - oz
    dx, dy, dz = bx - ax, by - ay, bz - az
    if math.isinf(height):
        # Distance to a vertical line: the 2-D point-to-segment problem in the xy plane.
        dd = dx * dx + dy * dy
        t = 0.5 if dd < _TINY else min(1.0, max(0.0, -(ax * dx + ay * dy) / dd))
    else:
        half = 0.5 * height  # the cylinder's centre is at height `half` above the base
        t = _golden(
            lambda s: _cylinder_sdf(ax + s * dx, ay + s * dy, az + s * dz - half, cylinder_radius, half)
        )
    px, py, pz = ax + t * dx, ay + t * dy, az + t * dz
    if math.isinf(height):
        rho = math.hypot(px, py)
        normal = (px / rho, py / rho, 0.0) if rho > _TINY else _perpendicular(0.0, 0.0, 1.0)
        distance = rho - cylinder_radius
    else:
        distance, normal = _cylinder_sdf_normal(px, py, pz - half, cylinder_radius, half)
    return _result((px + ox, py + oy, pz + oz), normal, distance, radius)


def _cylinder_sdf(x: float, y: float, z: float, r: float, half: float) -> float:
    """Signed distance to a z-axis cylinder centred at the origin (radius r, half-height half)."""
    qr = math.hypot(x, y) - r
    qz = abs(z) - half
    return math.hypot(max(qr, 0.0), max(qz, 0.0)) + min(max(qr, qz), 0.0)


def _cylinder_sdf_normal(x: float, y: float, z: float, r: float, half: float) -> tuple[float, _Vec]:
    rho = math.hypot(x, y)
    ux, uy = (x / rho, y / rho) if rho > _TINY else (1.0, 0.0)
    sz = 1.0 if z >= 0.0 else -1.0
    qr, qz = rho - r, abs(z) - half
    if qr > 0.0 or qz > 0.0:  # outside: along the vector from the closest surface point
        er, ez = max(qr, 0.0), max(qz, 0.0)
        n = math.hypot(er, ez)
        return n, (er * ux / n, er * uy / n, ez * sz / n)
    if qr > qz:  # inside, nearer the side
        return qr, (ux, uy, 0.0)
    return qz, (0.0, 0.0, sz)


def capsule_box(
    a: FloatArray,
    b: FloatArray,
    radius: float,
    center: FloatArray,
    rotation_box_to_world: FloatArray,
    half_extents: FloatArray,
) -> Proximity:
    """Capsule against an oriented solid box.

    Args:
        a: Segment start, world, in [m]. # (3,)
        b: Segment end, world, in [m]. # (3,)
        radius: Capsule radius, in [m].
        center: Box centre, world, in [m]. # (3,)
        rotation_box_to_world: The box's axes in world, as columns. # (3, 3)
        half_extents: Half the box's size along its axes, in [m]. # (3,)

    Returns:
        The closest approach.
    """
    r_t = rotation_box_to_world.T
    ax, ay, az = r_t.dot(a - center).tolist()
    bx, by, bz = r_t.dot(b - center).tolist()
    hx, hy, hz = half_extents.tolist()
    dx, dy, dz = bx - ax, by - ay, bz - az

    def sdf(s: float) -> float:
        qx, qy, qz = abs(ax + s * dx) - hx, abs(ay + s * dy) - hy, abs(az + s * dz) - hz
        ox, oy, oz = max(qx, 0.0), max(qy, 0.0), max(qz, 0.0)
        return math.sqrt(ox * ox + oy * oy + oz * oz) + min(max(qx, qy, qz), 0.0)

    t = _golden(sdf)
    p = (ax + t * dx, ay + t * dy, az + t * dz)
    q = (abs(p[0]) - hx, abs(p[1]) - hy, abs(p[2]) - hz)
    sign = tuple(1.0 if c >= 0.0 else -1.0 for c in p)
    if max(q) > 0.0:  # outside: from the clamped point to p
        e = [max(c, 0.0) * s for c, s in zip(q, sign, strict=True)]
        distance = math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
        local = [c / distance for c in e]
    else:  # inside: out through the nearest face
        k = max(range(3), key=q.__getitem__)
        distance = q[k]
        local = [0.0, 0.0, 0.0]
        local[k] = sign[k]
    nx, ny, nz = rotation_box_to_world.dot(np.array(local)).tolist()
    px, py, pz = (rotation_box_to_world.dot(np.array(p)) + center).tolist()
    return _result((px, py, pz), (nx, ny, nz), distance, radius)


def _golden(f: Callable[[float], float]) -> float:
    """Minimiser over [0, 1] of a convex f, by golden-section search (endpoints included)."""
    lo, hi = 0.0, 1.0
    x1, x2 = hi - _GOLDEN * (hi - lo), lo + _GOLDEN * (hi - lo)
    f1, f2 = f(x1), f(x2)
    for _ in range(_GOLDEN_STEPS):
        if f1 <= f2:
            hi, x2, f2 = x2, x1, f1
            x1 = hi - _GOLDEN * (hi - lo)
            f1 = f(x1)
        else:
            lo, x1, f1 = x1, x2, f2
            x2 = lo + _GOLDEN * (hi - lo)
            f2 = f(x2)
    return min((f(0.0), 0.0), (f(1.0), 1.0), (f1, x1), (f2, x2))[1]
