"""The controller's own geometric model of the arm's capsules and the obstacles, for fast distances.

The field needs, at the parameter rate, the closest points between each link's
capsules and each obstacle near it. :mod:`cosmos.osc.firas` computes them in
Python (closed form for spheres and planes, a golden-section search for boxes
and finite cylinders: about 0.2 ms per capsule-box pair on the 2-core target,
too slow for ten obstacles). This module keeps a small MuJoCo model of its own
(not the plant's: the controller never reads the simulator) holding one geom
per capsule and one per obstacle, writes their world poses into it directly
(``geom_xpos``, ``geom_xmat``; no kinematics is run) and asks MuJoCo's
``mj_geomDistance`` (about 2 us a pair) for the distance and the two closest
points. :func:`cosmos.obstacles.proximity.capsule_proximity` (firas) remains the
reference, checked against it in the tests, and is used when the capsule
penetrates the obstacle, where MuJoCo returns a penetration depth rather than
the signed distance and its points do not define a normal.
"""

from __future__ import annotations

from typing import NamedTuple

import mujoco
import numpy as np

from cosmos.obstacles.capsules import LinkCapsules
from cosmos.obstacles.obstacle import Obstacle
from cosmos.obstacles.proximity import capsule_proximity
from cosmos.obstacles.scene import geom_size_and_bounds
from cosmos.plan import ObstacleShape

FloatArray = np.ndarray

_GEOM_TYPE = {
    ObstacleShape.SPHERE: mujoco.mjtGeom.mjGEOM_SPHERE,
    ObstacleShape.CYLINDER: mujoco.mjtGeom.mjGEOM_CYLINDER,
    ObstacleShape.BOX: mujoco.mjtGeom.mjGEOM_BOX,
    ObstacleShape.PLANE: mujoco.mjtGeom.mjGEOM_PLANE,
}


def _frame_with_z(direction: FloatArray) -> FloatArray:
    """A rotation whose z axis is ``direction`` (unit), columns x, y, z. # (3, 3)."""
    z = direction / np.linalg.norm(direction)
    helper = np.array((1.0, 0.0, 0.0)) if abs(z[0]) < 0.9 else np.array((0.0, 1.0, 0.0))
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack((x, np.cross(z, x), z))


_NORMAL_FROM_POINTS_M = 1e-4  # below this distance the normal comes from firas, not the two points
CANDIDATE_MARGIN_M = 0.03
"""Slack of the candidate list: it is rebuilt once the arm and obstacles may have moved this much."""


class Nearest(NamedTuple):
    """A link's closest approach to an obstacle within the obstacle's influence distance."""

    link: int  # joint index 0..5 of the link
    obstacle: int  # index in the model's obstacles
    capsule: int  # index in the capsules
    distance: float  # [m], MuJoCo's: a penetration depth (<= 0) when touching
    fromto: list[float]  # the capsule's point then the obstacle's, world, [m]


_Vec = tuple[float, float, float]


def _triple(vector: FloatArray) -> _Vec:
    x, y, z = vector.tolist()
    return (x, y, z)


class Approach(NamedTuple):
    """Where and how close one link comes to one obstacle (inside its rho_0)."""

    link: int  # joint index 0..5 of the link
    obstacle: int  # index in the model's obstacles
    distance: float  # [m] between the surfaces, negative when penetrating
    point: tuple[float, float, float]  # the link's closest point, world, [m]
    normal: tuple[float, float, float]  # unit, world, pointing away from the obstacle


class ProximityModel:
    """Capsules and obstacles as geoms of a private MuJoCo model; their near pairs.

    Args:
        capsules: The arm's capsules (in joint frames).
        obstacles: The obstacles, in the order their indices refer to.
        influence_m: rho_0 of each obstacle, in [m].
    """

    def __init__(
        self, capsules: LinkCapsules, obstacles: tuple[Obstacle, ...], influence_m: list[float]
    ) -> None:
        spec = mujoco.MjSpec()
        axes = capsules.b_in_joint - capsules.a_in_joint  # (n, 3)
        half_lengths = 0.5 * np.linalg.norm(axes, axis=1)
        for radius, half in zip(capsules.radius_m.tolist(), half_lengths.tolist(), strict=True):
            if half > 1e-9:
                spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_CAPSULE, size=[radius, half, 0.0])
            else:
                spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[radius, 0.0, 0.0])
        for obstacle in obstacles:
            size, _, _ = geom_size_and_bounds(obstacle)
            spec.worldbody.add_geom(type=_GEOM_TYPE[obstacle.shape], size=size)
        self._model = spec.compile()
        self._data = mujoco.MjData(self._model)
        self._n = len(capsules)
        self.obstacles = obstacles
        self.influence_m = list(influence_m)
        # Capsule frames in their joint's frame: z along the segment, origin at the midpoint.
        self._rotation_in_joint = np.array(
            [_frame_with_z(a) if h > 1e-9 else np.eye(3) for a, h in zip(axes, half_lengths, strict=True)]
        )  # (n, 3, 3)
        self._mid_in_joint = 0.5 * (capsules.a_in_joint + capsules.b_in_joint)  # (n, 3)
        self._joint = capsules.joint
        self._joint_list = capsules.joint.tolist()
        self._capsule_bounds = capsules.bound_m
        self._centers = np.array([o.position_world for o in obstacles]).reshape(-1, 3)  # (k, 3)
        self._velocities = np.array([o.velocity_world_mps for o in obstacles]).reshape(-1, 3)  # (k, 3)
        self._added_s = np.array([o.added_s for o in obstacles])  # (k,)
        self._obstacle_bounds = np.array(
            [0.0 if o.shape is ObstacleShape.PLANE else o.bounding_radius_m for o in obstacles]
        )
        self._planes = [
            (j, o.rotation_world[:, 2]) for j, o in enumerate(obstacles) if o.shape is ObstacleShape.PLANE
        ]
        self._moving = [j for j, o in enumerate(obstacles) if o.moving]
        self._rho_0 = np.array(self.influence_m)
        xmat, xpos = self._data.geom_xmat, self._data.geom_xpos
        for j, obstacle in enumerate(obstacles):
            xmat[self._n + j] = np.ascontiguousarray(obstacle.rotation_world).reshape(9)
            xpos[self._n + j] = obstacle.position_world
        self._fromto = np.zeros(6)
        self._candidates: list[list] | None = None  # [capsule, obstacle, distance, travel then]
        self._travel_m = 0.0
        self._last_s: float | None = None
        self._capsules = capsules
        # Per approach: link, obstacle, the link's point, the obstacle's point, normal, time; world.
        self._held: list[tuple[int, int, _Vec, _Vec, _Vec, float]] = []
        self.velocities = [_triple(o.velocity_world_mps) for o in obstacles]
        """Each obstacle's velocity, world, in [m/s]."""

    def centers(self, t_s: float) -> FloatArray:
        """The obstacles' centres at simulated time ``t_s``, world, in [m]. # (k, 3)."""
        if not self._moving:
            return self._centers
        return self._centers + (t_s - self._added_s)[:, None] * self._velocities

    def estimate(self, twists: list[list[float]], t_s: float) -> list[Approach]:
        """The approaches of the last :meth:`measure`, carried forward to ``t_s`` to first order.

        As the seed's servo level estimates the end effector between two
        evaluations of the model, each held closest point moves with its link's
        current twist, the obstacle's point with the obstacle's velocity, and
        the distance is their separation along the held normal.

        Args:
            twists: Per link k, ``(v, w)`` of its body at the world origin (J qd over
                joints 0..k), world, in [m/s, rad/s]. # 6 x (6,)
            t_s: Simulated time, in [s].
        """
        out = []
        for k, j, (px, py, pz), (ox, oy, oz), (nx, ny, nz), held_s in self._held:
            dt = t_s - held_s
            vx, vy, vz, wx, wy, wz = twists[k]
            px, py, pz = (
                px + (vx + wy * pz - wz * py) * dt,
                py + (vy + wz * px - wx * pz) * dt,
                pz + (vz + wx * py - wy * px) * dt,
            )
            ux, uy, uz = self.velocities[j]
            distance = nx * (px - ox - ux * dt) + ny * (py - oy - uy * dt) + nz * (pz - oz - uz * dt)
            if distance < self.influence_m[j]:
                out.append(Approach(k, j, distance, (px, py, pz), (nx, ny, nz)))
        return out

    def measure(
        self, rotations: FloatArray, origins: FloatArray, t_s: float, speed_mps: float
    ) -> list[Approach]:
        """Each link's closest approach to each obstacle within rho_0 (firas where the link touches).

        Args:
            rotations: Rotation of each joint's frame to world. # (6, 3, 3)
            origins: Origin of each joint's frame, world, in [m]. # (6, 3)
            t_s: Simulated time, in [s].
            speed_mps: Bound on the relative speed of arm and obstacles since the last call, in [m/s].
        """
        caps, out, self._held = self._capsules, [], []
        for pair in self.nearest(rotations, origins, t_s, speed_mps):
            k, j, i, distance = pair.link, pair.obstacle, pair.capsule, pair.distance
            px, py, pz, ox, oy, oz = pair.fromto
            if distance > _NORMAL_FROM_POINTS_M:
                point, other = (px, py, pz), (ox, oy, oz)
                normal = ((px - ox) / distance, (py - oy) / distance, (pz - oz) / distance)
            else:  # touching or penetrating: the signed distance and normal of firas
                a = rotations[k].dot(caps.a_in_joint[i]) + origins[k]
                b = rotations[k].dot(caps.b_in_joint[i]) + origins[k]
                center = self.centers(t_s)[j]
                exact = capsule_proximity(a, b, float(caps.radius_m[i]), self.obstacles[j], center)
                distance, point, normal = exact.distance, _triple(exact.point), _triple(exact.normal)
                other = _triple(exact.point - exact.distance * exact.normal)
            self._held.append((k, j, point, other, normal, t_s))
            out.append(Approach(k, j, distance, point, normal))
        return out

    def nearest(
        self, rotations: FloatArray, origins: FloatArray, t_s: float, speed_mps: float
    ) -> list[Nearest]:
        """For each (link, obstacle) within the obstacle's rho_0, the link's closest capsule.

        The (capsule, obstacle) pairs worth a distance query are those within
        ``rho_0 + CANDIDATE_MARGIN_M`` of each other (bounding spheres first, then
        the exact distance); the list is kept until the surfaces may have closed
        that margin (``speed_mps`` bounds how fast any point of the arm
        approaches any obstacle), then rebuilt. A listed pair is queried again
        only once it may have come within rho_0 since its last query.

        Args:
            rotations: Rotation of each joint's frame to world. # (6, 3, 3)
            origins: Origin of each joint's frame, world, in [m]. # (6, 3)
            t_s: Simulated time, in [s] (moving obstacles).
            speed_mps: Bound on the relative speed of arm and obstacles since the last call, in [m/s].

        Returns:
            The near pairs, in no particular order.
        """
        joint, n, data = self._joint, self._n, self._data
        rotation = rotations[joint]  # (n, 3, 3)
        midpoints = np.matmul(rotation, self._mid_in_joint[:, :, None])[:, :, 0] + origins[joint]
        data.geom_xmat[:n] = np.matmul(rotation, self._rotation_in_joint).reshape(n, 9)
        data.geom_xpos[:n] = midpoints
        if self._moving:
            centers = self.centers(t_s)
            for j in self._moving:
                data.geom_xpos[n + j] = centers[j]
        if self._last_s is not None:
            self._travel_m += speed_mps * abs(t_s - self._last_s)
        self._last_s = t_s
        if self._candidates is None or self._travel_m >= CANDIDATE_MARGIN_M:
            self._candidates = self._candidate_pairs(midpoints, self.centers(t_s))
            self._travel_m = 0.0
        rho_0, links, travel = self.influence_m, self._joint_list, self._travel_m
        model, fromto, distance_of = self._model, self._fromto, mujoco.mj_geomDistance
        best: dict[tuple[int, int], Nearest] = {}
        for candidate in self._candidates:
            i, j, last_m, travel_then_m = candidate
            limit = rho_0[j]
            if last_m - (travel - travel_then_m) >= limit:
                continue  # it was farther than it can have come since
            distance = distance_of(model, data, i, n + j, limit + CANDIDATE_MARGIN_M, fromto)
            candidate[2], candidate[3] = distance, travel
            if distance >= limit:
                continue
            key = (links[i], j)
            seen = best.get(key)
            if seen is None or distance < seen.distance:
                best[key] = Nearest(links[i], j, i, distance, fromto.tolist())
        return list(best.values())

    def _candidate_pairs(self, midpoints: FloatArray, centers: FloatArray) -> list[list]:
        """``[capsule, obstacle, distance, travel]`` of the pairs within rho_0 + margin (spheres first)."""
        offsets = midpoints[:, None, :] - centers[None]  # (n, k, 3)
        gaps = np.sqrt(np.einsum("ijk,ijk->ij", offsets, offsets)) - self._obstacle_bounds[None]
        for j, normal in self._planes:
            gaps[:, j] = offsets[:, j].dot(normal)
        gaps -= self._capsule_bounds[:, None]
        n, model, data, fromto = self._n, self._model, self._data, self._fromto
        pairs = []
        for i, j in np.argwhere(gaps < self._rho_0[None] + CANDIDATE_MARGIN_M).tolist():
            reach = self.influence_m[j] + CANDIDATE_MARGIN_M
            distance = mujoco.mj_geomDistance(model, data, i, n + j, reach, fromto)
            if distance < reach:
                pairs.append([i, j, -np.inf, 0.0])  # measured again right away
        return pairs
