"""The compiled closed-form distances (cosmos.obstacles.kernels.distance) against MuJoCo and the NumPy SDF."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from cosmos.obstacles.kernels import distance as dk
from cosmos.obstacles.obstacle import Obstacle, box, cylinder, sphere
from cosmos.obstacles.proximity import capsule_proximity, signed_distances
from cosmos.osc import firas
from cosmos.plan import ObstacleShape

_KIND = {
    ObstacleShape.SPHERE: dk.KIND_SPHERE,
    ObstacleShape.CYLINDER: dk.KIND_CYLINDER,
    ObstacleShape.BOX: dk.KIND_BOX,
    ObstacleShape.PLANE: dk.KIND_PLANE,
}


def _random_rotation(rng: np.random.Generator) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def _capsule_and(kind: mujoco.mjtGeom, size: list[float]) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """A model with a capsule (geom 0) and one other geom (geom 1), poses written directly."""
    spec = mujoco.MjSpec()
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_CAPSULE, size=[0.05, 0.1, 0.0])
    spec.worldbody.add_geom(type=kind, size=size)
    model = spec.compile()
    return model, mujoco.MjData(model)


def _place_capsule(
    model: mujoco.MjModel, data: mujoco.MjData, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray, float, float]:
    """A random capsule pose and size, written as geom 0. Returns midpoint, unit axis, half length, radius."""
    rotation = _random_rotation(rng)
    mid = rng.uniform(-0.3, 0.3, 3)
    half, radius = float(rng.uniform(0.02, 0.2)), float(rng.uniform(0.01, 0.06))
    model.geom_size[0, :2] = (radius, half)
    data.geom_xpos[0] = mid
    data.geom_xmat[0] = rotation.reshape(9)
    return mid, rotation[:, 2].copy(), half, radius


def test_capsule_sphere_is_mujocos_answer() -> None:
    """Distance and closest points equal ``mj_geomDistance`` (capped at distmax, zeros beyond).

    Catches the projection clamped to the wrong parameter range, the points on
    the wrong surfaces, the segment written obstacle-first, or no cap.
    """
    model, data = _capsule_and(mujoco.mjtGeom.mjGEOM_SPHERE, [0.05, 0.0, 0.0])
    rng = np.random.default_rng(4)
    fromto, expected = np.zeros(6), np.zeros(6)
    for _ in range(200):
        mid, axis, half, radius = _place_capsule(model, data, rng)
        sphere_radius = float(rng.uniform(0.02, 0.1))
        model.geom_size[1, 0] = sphere_radius
        center = rng.uniform(-0.4, 0.4, 3)
        data.geom_xpos[1] = center
        distmax = float(rng.uniform(0.05, 0.3))
        got = dk.capsule_sphere(fromto, mid, axis, half, radius, center, sphere_radius, distmax)
        want = mujoco.mj_geomDistance(model, data, 0, 1, distmax, expected)
        assert got == pytest.approx(want, abs=1e-12)
        if want > 0.0:  # MuJoCo's points for a penetration sit at the contact midpoint
            np.testing.assert_allclose(fromto, expected, atol=1e-12)


def test_capsule_plane_is_mujocos_answer() -> None:
    """Height of the lower end minus the radius, and its points, equal ``mj_geomDistance``.

    Catches the upper end taken, the radius added instead of subtracted, or the
    point projected along the wrong normal.
    """
    model, data = _capsule_and(mujoco.mjtGeom.mjGEOM_PLANE, [1.0, 1.0, 0.05])
    rng = np.random.default_rng(5)
    fromto, expected = np.zeros(6), np.zeros(6)
    for _ in range(200):
        mid, axis, half, radius = _place_capsule(model, data, rng)
        rotation = _random_rotation(rng)
        point = rng.uniform(-0.3, 0.3, 3)
        data.geom_xpos[1] = point
        data.geom_xmat[1] = rotation.reshape(9)
        distmax = float(rng.uniform(0.05, 0.3))
        got = dk.capsule_plane(fromto, mid, axis, half, radius, point, rotation[:, 2].copy(), distmax)
        want = mujoco.mj_geomDistance(model, data, 0, 1, distmax, expected)
        assert got == pytest.approx(want, abs=1e-12)
        if want > 0.0:
            np.testing.assert_allclose(fromto, expected, atol=1e-12)


def test_capsule_sphere_and_plane_are_the_firas_reference() -> None:
    """Within distmax the closed forms give :mod:`cosmos.osc.firas`' distance and capsule point.

    Catches the kernel drifting from its readable reference (a capsule end taken for
    the other, the radius on the wrong side, the sphere's radius left out).
    """
    rng = np.random.default_rng(6)
    fromto = np.zeros(6)
    distmax = 10.0  # no cap: every answer is the reference's
    for _ in range(200):
        axis = _random_rotation(rng)[:, 2].copy()
        mid = rng.uniform(-0.3, 0.3, 3)
        half, radius = float(rng.uniform(0.02, 0.2)), float(rng.uniform(0.01, 0.06))
        a, b = mid - half * axis, mid + half * axis
        center, sphere_radius = rng.uniform(-0.4, 0.4, 3), float(rng.uniform(0.02, 0.1))
        got = dk.capsule_sphere(fromto, mid, axis, half, radius, center, sphere_radius, distmax)
        want = firas.capsule_sphere(a, b, radius, center, sphere_radius)
        assert got == pytest.approx(want.distance, abs=1e-12)
        if want.distance > 0.0:
            np.testing.assert_allclose(fromto[:3], want.point, atol=1e-12)
        point, normal = rng.uniform(-0.3, 0.3, 3), _random_rotation(rng)[:, 2].copy()
        got = dk.capsule_plane(fromto, mid, axis, half, radius, point, normal, distmax)
        want = firas.capsule_plane(a, b, radius, point, normal)
        assert got == pytest.approx(want.distance, abs=1e-12)
        np.testing.assert_allclose(fromto[:3], want.point, atol=1e-12)


def _turned(obstacle: Obstacle, rotation: np.ndarray) -> Obstacle:
    return Obstacle(
        obstacle.name,
        obstacle.shape,
        obstacle.position_world,
        rotation,
        obstacle.half_extents_m,
        obstacle.velocity_world_mps,
    )


PLANE = Obstacle(
    "floor", ObstacleShape.PLANE, np.zeros(3), np.eye(3), np.array((np.inf, np.inf, 0.0)), np.zeros(3)
)


@pytest.mark.parametrize(
    "shape",
    [
        sphere("s", (0.1, 0.0, 0.2), 0.07),
        box("b", (0.0, 0.1, 0.2), (0.3, 0.1, 0.2)),
        cylinder("c", (0.05, 0, 0.1), 0.05, 0.3),
        PLANE,
    ],
    ids=["sphere", "box", "cylinder", "plane"],
)
def test_point_signed_distance_is_the_numpy_one(shape: Obstacle) -> None:
    """The compiled signed distance of a point equals ``proximity.signed_distances``, inside and out.

    Catches ``R p`` for ``R^T p`` (turned shapes), a wrong sign inside, or a
    cylinder's axis taken along the wrong shape axis.
    """
    rng = np.random.default_rng(6)
    inside = 0
    for _ in range(10):
        obstacle = _turned(shape, _random_rotation(rng))
        center = obstacle.position_world + rng.normal(scale=0.05, size=3)
        row = np.zeros(dk.SHAPE)
        row[dk.SHAPE_KIND] = _KIND[obstacle.shape]
        row[dk.SHAPE_ROTATION : dk.SHAPE_ROTATION + 9] = obstacle.rotation_world.reshape(9)
        row[dk.SHAPE_HALF : dk.SHAPE_HALF + 3] = obstacle.half_extents_m
        points = center + np.concatenate((rng.uniform(-0.4, 0.4, (20, 3)), rng.uniform(-0.04, 0.04, (10, 3))))
        expected = signed_distances(points, obstacle, center)
        got = [dk.signed_distance(x, y, z, row, *center.tolist()) for x, y, z in points.tolist()]
        np.testing.assert_allclose(got, expected, atol=1e-12)
        inside += int((expected < 0.0).sum())
    assert inside > 20  # points inside the shape were tested too


@pytest.mark.parametrize(
    "shape",
    [
        box("b", (0.0, 0.1, 0.2), (0.3, 0.02, 0.2)),
        cylinder("c", (0.05, 0, 0.1), 0.05, 0.3),
        sphere("s", (0, 0, 0), 0.1),
    ],
    ids=["box", "cylinder", "sphere"],
)
def test_segment_lower_bound_never_exceeds_the_distance(shape: Obstacle) -> None:
    """The separating-axis bound is at most the segment's firas distance, and exact for a face-parallel one.

    Catches ``R`` for ``R^T``, a segment extent without its absolute value, or a
    cylinder's radial gap taken from the midpoint only: any of them drops pairs
    that are within rho_0.
    """
    rng = np.random.default_rng(9)
    separated = 0
    for _ in range(150):
        obstacle = _turned(shape, _random_rotation(rng))
        center = obstacle.position_world
        row = np.zeros(dk.SHAPE)
        row[dk.SHAPE_KIND] = _KIND[obstacle.shape]
        row[dk.SHAPE_ROTATION : dk.SHAPE_ROTATION + 9] = obstacle.rotation_world.reshape(9)
        row[dk.SHAPE_HALF : dk.SHAPE_HALF + 3] = obstacle.half_extents_m
        mid = center + rng.uniform(-0.4, 0.4, 3)
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        half = float(rng.uniform(0.0, 0.2))
        exact = capsule_proximity(mid - half * axis, mid + half * axis, 0.0, obstacle, center).distance
        bound = dk.segment_lower_bound(mid, axis, half, row, *center.tolist())
        assert bound <= exact + 1e-6
        separated += bound > 0.0
    assert separated > 50  # the bound is not trivially low
    # A segment parallel to the box's large face, 5 cm off it: the bound is the distance.
    if shape.shape is ObstacleShape.BOX:
        row = np.zeros(dk.SHAPE)
        row[dk.SHAPE_KIND] = dk.KIND_BOX
        row[dk.SHAPE_ROTATION : dk.SHAPE_ROTATION + 9] = np.eye(3).reshape(9)
        row[dk.SHAPE_HALF : dk.SHAPE_HALF + 3] = shape.half_extents_m
        mid = shape.position_world + np.array((0.0, 0.01 + 0.05, 0.0))
        bound = dk.segment_lower_bound(
            mid, np.array((0.0, 0.0, 1.0)), 0.1, row, *shape.position_world.tolist()
        )
        assert bound == pytest.approx(0.05)
