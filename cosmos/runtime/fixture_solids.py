"""The workcell's fixtures as solids: how deep a point lies inside one, and where its top is.

A fixture (the table, the block around the hole, the tilted plate, the floor) is a set of
MuJoCo geoms of the world body (``cosmos/models/<arm>/scene.xml``); each is a box, a
sphere, a cylinder or a capsule, kept here as its shape, pose and MuJoCo ``size``. A
point's signed distance to a solid is negative inside (the exact Euclidean distance to
its surface, as MuJoCo's collision of a point-sized sphere measures it:
``tests/check/test_goal_inside_fixture.py``). The hole's bore is no solid: its walls are
boxes around it, so a point in the bore is outside every one.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

import numpy as np

FloatArray = np.ndarray

UP = np.array([0.0, 0.0, 1.0])
"""The world's up direction (z)."""
EXIT_TOLERANCE_M = 1e-7
"""The top of a fixture is found to within this [m]."""
SEAM_STEP_M = 1e-4
"""Where two solids of a fixture meet face to face, the top is looked for this far above the seam [m]."""


class SolidShape(enum.Enum):
    """A geom's shape (MuJoCo's ``size`` reads per shape)."""

    BOX = "box"
    """``size``: the half lengths along its axes."""
    SPHERE = "sphere"
    """``size[0]``: the radius."""
    CYLINDER = "cylinder"
    """``size[0]``: the radius; ``size[1]``: half its length along its z axis."""
    CAPSULE = "capsule"
    """``size[0]``: the radius; ``size[1]``: half the length of its segment along its z axis."""


@dataclass(frozen=True)
class FixtureSolid:
    """One solid of a fixture.

    Attributes:
        fixture: The fixture it belongs to, by the language's frame on it (``table``, ``hole``,
            ``slope``), else the frame's or the geom's own name (``floor``).
        geom: The geom's name in the scene.
        shape: Its shape.
        center: Its centre, world [m], read-only. # (3,)
        rotation: Its axes in the world (solid to world), read-only. # (3, 3)
        size: MuJoCo's ``size`` [m] (:class:`SolidShape`), read-only. # (3,)
        obstacle: True for an obstacle a program adds (``OBSTACLE``; ``fixture`` is its name).
    """

    fixture: str
    geom: str
    shape: SolidShape
    center: FloatArray
    rotation: FloatArray
    size: FloatArray
    obstacle: bool = False


def signed_distances(solids: tuple[FixtureSolid, ...], points: FloatArray) -> FloatArray:
    """The distance from each point (world [m]) to each solid's surface [m]: negative inside.

    Args:
        solids: The solids.
        points: The points. # (m, 3)

    Returns:
        The signed distances. # (m, len(solids))
    """
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    distances = np.empty((len(points), len(solids)))
    for shape in SolidShape:
        chosen = [i for i, solid in enumerate(solids) if solid.shape is shape]
        if not chosen:
            continue
        centers = np.array([solids[i].center for i in chosen])  # (k, 3)
        rotations = np.array([solids[i].rotation for i in chosen])  # (k, 3, 3), solid to world
        sizes = np.array([solids[i].size for i in chosen])  # (k, 3)
        local = np.einsum("kji,mkj->mki", rotations, points[:, None, :] - centers[None])  # (m, k, 3)
        distances[:, chosen] = _in_shape(shape, local, sizes)
    return distances


def _in_shape(shape: SolidShape, local: FloatArray, sizes: FloatArray) -> FloatArray:
    """Signed distances of points in each solid's own frame (``local``, (m, k, 3)) [m]: (m, k)."""
    if shape is SolidShape.SPHERE:
        return np.linalg.norm(local, axis=-1) - sizes[:, 0]
    if shape is SolidShape.CAPSULE:
        nearest = np.clip(local[..., 2], -sizes[:, 1], sizes[:, 1])
        return np.hypot(np.hypot(local[..., 0], local[..., 1]), local[..., 2] - nearest) - sizes[:, 0]
    if shape is SolidShape.BOX:
        excess = np.abs(local) - sizes
    else:  # a cylinder: radially, then along its axis
        radial = np.hypot(local[..., 0], local[..., 1]) - sizes[:, 0]
        excess = np.stack((radial, np.abs(local[..., 2]) - sizes[:, 1]), axis=-1)
    outside = np.linalg.norm(np.maximum(excess, 0.0), axis=-1)
    return outside + np.minimum(excess.max(axis=-1), 0.0)


def bounds(solids: tuple[FixtureSolid, ...]) -> tuple[FloatArray, FloatArray]:
    """Each solid's bounding box along the world's axes: lower and upper corners [m], (k, 3) each."""
    if not solids:
        return np.empty((0, 3)), np.empty((0, 3))
    half = []
    for solid in solids:
        radius, length = float(solid.size[0]), float(solid.size[1])
        if solid.shape is SolidShape.BOX:
            extent = solid.size
        elif solid.shape is SolidShape.SPHERE:
            extent = np.full(3, radius)
        else:  # a cylinder or a capsule along its z axis
            extent = np.array(
                (radius, radius, length + (radius if solid.shape is SolidShape.CAPSULE else 0.0))
            )
        half.append(np.abs(solid.rotation) @ extent)
    centers = np.array([solid.center for solid in solids])
    return centers - np.array(half), centers + np.array(half)


def depth_inside(solids: tuple[FixtureSolid, ...], point: FloatArray) -> float:
    """How deep ``point`` lies inside the deepest of ``solids`` [m]: 0 if it is inside none."""
    if not solids:
        return 0.0
    return max(0.0, float(-signed_distances(solids, point).min()))


def top_above(solids: tuple[FixtureSolid, ...], point: FloatArray) -> float:
    """Where the vertical line up from ``point`` (inside the solids) leaves them: z, world [m].

    Sphere tracing upwards: a point at depth d inside one solid is inside their union within
    d of it in every direction, so the line may step d at a time without passing the top (at
    least :data:`SEAM_STEP_M`, which also steps over a seam where two solids meet face to face,
    a leg under the table's top); the last step is halved back to the top.
    """
    inside = np.array(point, dtype=float)
    while True:
        step = max(depth_inside(solids, inside), SEAM_STEP_M)
        ahead = inside + step * UP
        if depth_inside(solids, ahead) > 0.0:
            inside = ahead
        elif depth_inside(solids, ahead + SEAM_STEP_M * UP) > 0.0:  # on a seam: solid beyond it
            inside = ahead + SEAM_STEP_M * UP
        else:
            break
    while step > EXIT_TOLERANCE_M:  # the top is within (inside, inside + step]
        step /= 2.0
        if depth_inside(solids, inside + step * UP) > 0.0:
            inside = inside + step * UP
    return float(inside[2] + step)
