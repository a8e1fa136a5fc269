"""The controller's own geometric model of the arm's capsules and the obstacles, for fast distances.

The field needs, at the parameter rate, the closest points between each link's
capsules and each obstacle near it. :mod:`cosmos.osc.firas` computes them in
Python (closed form for spheres and planes, a golden-section search for boxes
and finite cylinders: about 0.2 ms per capsule-box pair on the 2-core target,
too slow for ten obstacles). This module keeps a small MuJoCo model of its own
(not the plant's: the controller never reads the simulator) holding one geom
per capsule and one per obstacle, writes their world poses into it directly
(``geom_xpos``, ``geom_xmat``; no kinematics is run) and asks MuJoCo's
``mj_geomDistance`` (2 to 4 us a pair, called from Python) for the distance and
the two closest points of a capsule and a box or a cylinder; a sphere's and a
plane's are MuJoCo's closed forms, compiled (:mod:`cosmos.obstacles.kernels.distance`).
The candidate lists, the choice of each link's closest capsule and the
estimate between measurements are compiled too (:mod:`cosmos.obstacles.kernels.geometry`).
:func:`cosmos.obstacles.proximity.capsule_proximity` (firas) remains the
reference, checked against it in the tests, and is used when the capsule
penetrates the obstacle, where MuJoCo returns a penetration depth rather than
the signed distance and its points do not define a normal.
"""

from __future__ import annotations

import mujoco
import numpy as np

from cosmos.obstacles.capsules import LinkCapsules
from cosmos.obstacles.kernels import candidates as ck
from cosmos.obstacles.kernels import distance as dk
from cosmos.obstacles.kernels import field as fk
from cosmos.obstacles.kernels import geometry as gk
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

_KIND = {
    ObstacleShape.SPHERE: dk.KIND_SPHERE,
    ObstacleShape.CYLINDER: dk.KIND_CYLINDER,
    ObstacleShape.BOX: dk.KIND_BOX,
    ObstacleShape.PLANE: dk.KIND_PLANE,
}


def _frame_with_z(direction: FloatArray) -> FloatArray:
    """A rotation whose z axis is ``direction`` (unit), columns x, y, z. # (3, 3)."""
    z = direction / np.linalg.norm(direction)
    helper = np.array((1.0, 0.0, 0.0)) if abs(z[0]) < 0.9 else np.array((0.0, 1.0, 0.0))
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack((x, np.cross(z, x), z))


def capsule_table(capsules: LinkCapsules) -> FloatArray:
    """The capsules as the private model's geoms, in their joints' frames (``CAPSULE_*``). # (n, CAPSULE).

    A geom's frame has its origin at the segment's midpoint and its z axis along
    the segment; a segment of no length is a sphere geom (half length 0).
    """
    n = len(capsules)
    axes = capsules.b_in_joint - capsules.a_in_joint  # (n, 3)
    half_lengths = 0.5 * np.linalg.norm(axes, axis=1)
    rotations = [_frame_with_z(a) if h > 1e-9 else np.eye(3) for a, h in zip(axes, half_lengths, strict=True)]
    table = np.zeros((n, dk.CAPSULE))
    table[:, dk.CAPSULE_JOINT] = capsules.joint
    table[:, dk.CAPSULE_MID : dk.CAPSULE_MID + 3] = 0.5 * (capsules.a_in_joint + capsules.b_in_joint)
    table[:, dk.CAPSULE_ROTATION : dk.CAPSULE_ROTATION + 9] = np.array(rotations).reshape(n, 9)
    table[:, dk.CAPSULE_HALF] = np.where(half_lengths > 1e-9, half_lengths, 0.0)
    table[:, dk.CAPSULE_RADIUS] = capsules.radius_m
    table[:, dk.CAPSULE_BOUND] = capsules.bound_m
    return table


CANDIDATE_MARGIN_M = 0.03
"""Slack of the candidate list: it is rebuilt once the arm and obstacles may have moved this much."""


class ProximityModel:
    """Capsules and obstacles as geoms of a private MuJoCo model; their near pairs.

    The arithmetic is compiled (:mod:`cosmos.obstacles.kernels.geometry`); the
    results are packed arrays: :attr:`approaches` holds, after :meth:`measure`
    or :meth:`estimate`, one row per (link, obstacle) within that obstacle's
    rho_0 (layout ``APPROACH_*`` of :mod:`cosmos.obstacles.kernels.field`).

    Args:
        capsules: The arm's capsules (in joint frames).
        obstacles: The obstacles, in the order their indices refer to.
        table: Per obstacle its centre, velocity, time added, rho_0 and gain factor
            (layout ``OBSTACLE_*`` of :mod:`cosmos.obstacles.kernels.field`). # (k, OBSTACLE)
    """

    def __init__(self, capsules: LinkCapsules, obstacles: tuple[Obstacle, ...], table: FloatArray) -> None:
        spec = mujoco.MjSpec()
        self._capsule_table = capsule_table(capsules)
        for radius, half in self._capsule_table[:, [dk.CAPSULE_RADIUS, dk.CAPSULE_HALF]].tolist():
            if half > 0.0:
                spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_CAPSULE, size=[radius, half, 0.0])
            else:
                spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[radius, 0.0, 0.0])
        for obstacle in obstacles:
            size, _, _ = geom_size_and_bounds(obstacle)
            spec.worldbody.add_geom(type=_GEOM_TYPE[obstacle.shape], size=size)
        self._model = spec.compile()
        self._data = mujoco.MjData(self._model)
        self._n = n = len(capsules)
        self.obstacles = obstacles
        self.table = table
        """Per obstacle its centre, velocity, time added, rho_0 and gain factor. # (k, OBSTACLE)"""
        self._centers = table[:, fk.OBSTACLE_CENTER : fk.OBSTACLE_CENTER + 3]  # (k, 3)
        self._velocities = table[:, fk.OBSTACLE_VELOCITY : fk.OBSTACLE_VELOCITY + 3]  # (k, 3)
        self._added_s = table[:, fk.OBSTACLE_ADDED_S]  # (k,)
        self._rho_0 = table[:, fk.OBSTACLE_RHO_0]  # (k,)
        self._shapes = np.zeros((len(obstacles), dk.SHAPE))
        for j, o in enumerate(obstacles):
            self._shapes[j, dk.SHAPE_KIND] = _KIND[o.shape]
            self._shapes[j, dk.SHAPE_ROTATION : dk.SHAPE_ROTATION + 9] = o.rotation_world.reshape(9)
            self._shapes[j, dk.SHAPE_HALF : dk.SHAPE_HALF + 3] = o.half_extents_m
        self._moving = any(o.moving for o in obstacles)
        xmat, xpos = self._data.geom_xmat, self._data.geom_xpos
        for j, obstacle in enumerate(obstacles):
            xmat[n + j] = np.ascontiguousarray(obstacle.rotation_world).reshape(9)
            xpos[n + j] = obstacle.position_world
        # The candidate pairs (the first ``_count`` rows; -1: to be built), their last answers (the
        # distance, the segment from the capsule to the obstacle), and the lists of one measurement.
        pairs = n * len(obstacles)
        self._candidates = np.zeros((pairs, ck.CANDIDATE))
        self._count = -1
        self._distances = np.zeros(pairs)
        self._fromtos = np.zeros((pairs, 6))
        self._lists = np.zeros((pairs, ck.LISTS), dtype=np.int64)
        self._xpos, self._xmat = self._data.geom_xpos, self._data.geom_xmat  # views of MuJoCo's arrays
        # distmax of a query, by the obstacle's geom: rho_0 + margin.
        self._reach = [0.0] * n + [float(rho_0) + CANDIDATE_MARGIN_M for rho_0 in self._rho_0.tolist()]
        self._travel_m = 0.0
        self._last_s: float | None = None
        self._capsules = capsules
        joints = int(capsules.joint.max()) + 1 if len(capsules) else 0  # the links that carry capsules
        links = joints * len(obstacles)  # at most one approach per (link, obstacle)
        self._held = np.zeros((links, gk.HELD))
        self._held_count = 0
        self.approaches = np.zeros((links, fk.APPROACH))
        """One row per (link, obstacle) within rho_0, the first ``count`` rows valid. # (n k, APPROACH)"""

    def centers(self, t_s: float) -> FloatArray:
        """The obstacles' centres at simulated time ``t_s``, world, in [m]. # (k, 3)."""
        if not self._moving:
            return self._centers
        return self._centers + (t_s - self._added_s)[:, None] * self._velocities

    def estimate(self, frames: FloatArray, t_s: float) -> int:
        """The approaches of the last :meth:`measure`, carried forward to ``t_s`` to first order.

        As the seed's servo level estimates the end effector between two
        evaluations of the model, each held closest point moves with its link's
        current twist, the obstacle's point with the obstacle's velocity, and
        the distance is their separation along the held normal.

        Args:
            frames: The arm's joint frames and link twists now (``FRAME_*`` of
                :mod:`cosmos.obstacles.kernels.field`). # (n, FRAMES)
            t_s: Simulated time, in [s].

        Returns:
            How many rows of :attr:`approaches` are valid.
        """
        return int(gk.estimate_into(self.approaches, self._held, self._held_count, frames, self.table, t_s))

    def estimated_torque(
        self,
        torque: FloatArray,
        link_torque: FloatArray,
        nearest: FloatArray,
        acting: FloatArray,
        chain: FloatArray,
        q: FloatArray,
        qd: FloatArray,
        frames: FloatArray,
        parameters: FloatArray,
        t_s: float,
    ) -> float:
        """:meth:`estimate` and the field's torques from it, with the kinematics, in one compiled call.

        Args:
            torque: Written: the field's joint torques, in [N m]. # (n,)
            link_torque: Written: their part from every link but the tool's, in [N m]. # (n,)
            nearest: Written: those links' nearest approach (``NEAREST_*``). # (NEAREST,)
            acting: Written: per obstacle, whether and how it acted (``ACTING_*``). # (k, ACTING)
            chain: The arm's chain (``CHAIN_*`` of :mod:`cosmos.obstacles.kernels.field`). # (n, CHAIN)
            q: Joint angles, in [rad]. # (n,)
            qd: Joint velocities, in [rad/s]. # (n,)
            frames: Written: the joint frames and link twists (``FRAME_*``). # (n, FRAMES)
            parameters: eta, c, the cap and whether the field is enabled (``PARAMETER_*``). # (PARAMETERS,)
            t_s: Simulated time, in [s].

        Returns:
            ``sum_j |qd_j| reach_j``, in [m/s].
        """
        return float(
            gk.estimated_torque_into(
                torque,
                link_torque,
                nearest,
                acting,
                frames,
                chain,
                q,
                qd,
                self.approaches,
                self._held,
                self._held_count,
                self.table,
                parameters,
                t_s,
            )
        )

    def measure(self, frames: FloatArray, t_s: float, speed_mps: float) -> int:
        """Each link's closest approach to each obstacle within rho_0 (firas where the link touches).

        The (capsule, obstacle) pairs worth a distance query are those that may
        be within ``rho_0 + CANDIDATE_MARGIN_M`` of each other (the signed
        distance of the capsule's midpoint less its bounding radius is below);
        the list is kept until the surfaces may have closed that margin
        (``speed_mps`` bounds how fast any point of the arm approaches any
        obstacle), then rebuilt. A listed pair is queried only while it may be
        within rho_0 (at the rebuild, then once it may have come that close
        since its last query). Of a link's capsules near an obstacle, the
        closest one's point counts.

        Args:
            frames: The arm's joint frames (``FRAME_*``, :mod:`cosmos.obstacles.kernels.field`). # (n, FRAMES)
            t_s: Simulated time, in [s].
            speed_mps: Bound on the relative speed of arm and obstacles since the last call, in [m/s].

        Returns:
            How many rows of :attr:`approaches` are valid.
        """
        xpos, xmat = self._xpos, self._xmat
        if self._last_s is not None:
            self._travel_m += speed_mps * abs(t_s - self._last_s)
        self._last_s = t_s
        count = self._count
        if count < 0 or self._travel_m >= CANDIDATE_MARGIN_M:
            self._travel_m, count = 0.0, -1  # rebuild the candidates
        lists, distances, fromtos = self._lists, self._distances, self._fromtos
        self._count, queued, remotes = gk.place_and_select(
            lists,
            self._candidates,
            count,
            xpos,
            xmat,
            frames,
            self._capsule_table,
            self._shapes,
            self.table,
            t_s,
            self._travel_m,
            CANDIDATE_MARGIN_M,
        )
        self.query(remotes)
        count, touching = gk.nearest_into(
            self.approaches,
            self._held,
            self._candidates,
            distances,
            fromtos,
            lists,
            queued,
            xpos,
            xmat,
            self._capsule_table,
            self._shapes,
            self.table,
            CANDIDATE_MARGIN_M,
            self._travel_m,
            t_s,
        )
        self._held_count = count
        if touching:
            self.touching(count, frames, t_s)
        return count

    @property
    def arrays(self) -> tuple[np.ndarray, ...]:
        """Its arrays, in the order of ``ARRAY_APPROACHES`` .. ``ARRAY_SHAPES`` (kernels.evaluation)."""
        return (
            self.approaches,
            self._held,
            self.table,
            self._candidates,
            self._lists,
            self._distances,
            self._fromtos,
            self._xpos,
            self._xmat,
            self._capsule_table,
            self._shapes,
        )

    def query(self, remotes: int) -> None:
        """MuJoCo's distance and closest points for the first ``remotes`` pairs listed for it."""
        model, data, reach, distance_of = self._model, self._data, self._reach, mujoco.mj_geomDistance
        distances, fromtos = self._distances, self._fromtos
        for c, capsule, geom in self._lists[:remotes, ck.LIST_REMOTE :].tolist():
            distances[c] = distance_of(model, data, capsule, geom, reach[geom], fromtos[c])

    def touching(self, count: int, frames: FloatArray, t_s: float) -> None:
        """Of the first ``count`` approaches, those that touch get firas's distance, point and normal."""
        for s in range(count):
            if self.approaches[s, fk.APPROACH_DISTANCE] <= gk.NORMAL_FROM_POINTS_M:
                self._touching(s, frames, t_s)

    def _touching(self, s: int, frames: FloatArray, t_s: float) -> None:
        """Approach ``s`` touches or penetrates: the signed distance, point and normal of firas."""
        held, caps = self._held[s], self._capsules
        k, j, i = int(held[gk.HELD_LINK]), int(held[gk.HELD_OBSTACLE]), int(held[gk.HELD_CAPSULE])
        rotation = frames[k, fk.FRAME_ROTATION : fk.FRAME_ROTATION + 9].reshape(3, 3)
        origin = frames[k, fk.FRAME_ORIGIN : fk.FRAME_ORIGIN + 3]
        a = rotation.dot(caps.a_in_joint[i]) + origin
        b = rotation.dot(caps.b_in_joint[i]) + origin
        center = self.centers(t_s)[j]
        exact = capsule_proximity(a, b, float(caps.radius_m[i]), self.obstacles[j], center)
        held[gk.HELD_POINT : gk.HELD_POINT + 3] = exact.point
        held[gk.HELD_OTHER : gk.HELD_OTHER + 3] = exact.point - exact.distance * exact.normal
        held[gk.HELD_NORMAL : gk.HELD_NORMAL + 3] = exact.normal
        approach = self.approaches[s]
        approach[fk.APPROACH_DISTANCE] = exact.distance
        approach[fk.APPROACH_POINT : fk.APPROACH_POINT + 3] = exact.point
        approach[fk.APPROACH_NORMAL : fk.APPROACH_NORMAL + 3] = exact.normal
