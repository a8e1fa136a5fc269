"""Obstacles as real geoms of the MuJoCo workcell, so a collision is a contact MuJoCo reports.

MuJoCo compiles a model once, so the workcell is built with a fixed number of obstacle *slots*
(:func:`add_obstacle_slots`): geoms of the world body named ``obstacle_slot<i>``, parked far below the
floor. A slot is a geom, not a body: every body costs every physics step (kinematics, inertia, dynamics
run over bodies; twelve parked mocap bodies made a tick 1.2-1.3x dearer with no obstacle at all), while
a parked geom costs almost nothing, so the workcell holds :data:`CAPACITY` obstacles and a tick without
obstacles costs what the bare workcell's does.

Adding an obstacle takes a free slot and sets its geom's type, size, pose (``geom_pos``, ``geom_quat``;
MuJoCo places world geoms from them every step) and the bounding volumes the collision phases use:
``geom_rbound``, ``geom_aabb``, and the world body's bounding-volume hierarchy (``bvh_aabb``: the slot's
leaf and every node above it, refitted; the next :meth:`ObstacleScene.update` rebuilds the hierarchy's
shape for the obstacles, :mod:`cosmos.obstacles.hierarchy`). Removing it parks the slot again. A
``MOVING`` obstacle is moved by :meth:`ObstacleScene.update` (compiled:
:mod:`cosmos.obstacles.kernels.moving`), which the executor calls every servo tick; its leaf is refitted
every :data:`SWEEP_S` (or, if longer, as the fastest takes to go :data:`SWEEP_M`) to the box it sweeps
until the next refit, so the hierarchy always contains it without a refit per tick.

Contact filtering: the slot geoms have ``contype 0`` and ``conaffinity 6``, so they touch the arm's
links (``contype 2``) and the tool (``contype 4``) but not the fixtures (``contype 1``) nor each other;
being geoms of the world body, MuJoCo never collides them with other world geoms either.

The model's geoms are not part of the state: :meth:`cosmos.plant.Plant.reset` leaves the obstacles where
they are (:meth:`ObstacleScene.restore` puts the moving ones where they are at a given time).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from pathlib import Path
from xml.etree import ElementTree

import mujoco
import numpy as np

from cosmos.errors import CosmosError
from cosmos.lang.check.limits import MAX_OBSTACLES
from cosmos.obstacles.hierarchy import Group, install, layout, world_leaves
from cosmos.obstacles.kernels import moving as mk
from cosmos.obstacles.obstacle import Obstacle
from cosmos.obstacles.scene_file import kept_scene_file
from cosmos.plan import ObstacleShape
from cosmos.plant import Plant
from cosmos.workcell import SCENE_XML

CAPACITY = MAX_OBSTACLES
"""Obstacles the workcell can hold at once (the checker refuses a program that adds more)."""
DEFAULT_SLOTS = CAPACITY
"""The slots :func:`obstacle_scene_xml` makes unless told otherwise."""
SWEEP_S = 0.1
"""A moving obstacle's bounding volume covers its path for at least this long, then is refitted [s]."""
SWEEP_M = 0.02
"""... and over at least this much of its path [m]: a slow one is refitted less often (each refit
changes the world's tree, which makes the contact gate look at every body again)."""
SLOT_PREFIX = "obstacle_slot"
OBSTACLE_CONTYPE = 0
OBSTACLE_CONAFFINITY = 6  # arm links (contype 2) and tool (contype 4)
OBSTACLE_RGBA = (0.90, 0.35, 0.20, 0.6)
_PARKED_Z_M = -50.0
_IDENTITY_QUAT = (1.0, 0.0, 0.0, 0.0)
_SAME_AXES = mujoco.mjtSameFrame.mjSAMEFRAME_BODYROT  # a slot's geom has the world's axes
_PLANE_AABB = (0.0, 0.0, -5e9, 1e10, 1e10, 5e9)  # what MuJoCo's compiler gives a plane
_GEOM_TYPE = {
    ObstacleShape.SPHERE: mujoco.mjtGeom.mjGEOM_SPHERE,
    ObstacleShape.CYLINDER: mujoco.mjtGeom.mjGEOM_CYLINDER,
    ObstacleShape.BOX: mujoco.mjtGeom.mjGEOM_BOX,
    ObstacleShape.PLANE: mujoco.mjtGeom.mjGEOM_PLANE,
}


def parked_position(slot: int) -> tuple[float, float, float]:
    """Where slot ``slot`` waits when free, in [m]: far below the floor, out of reach, near the others."""
    return (0.05 * slot, 0.0, _PARKED_Z_M)


def add_obstacle_slots(worldbody: ElementTree.Element, count: int = DEFAULT_SLOTS) -> None:
    """Append ``count`` parked obstacle slots (world geoms, each in its frame) to an MJCF ``worldbody``."""
    rgba = " ".join(str(c) for c in OBSTACLE_RGBA)
    for slot in range(count):
        name = f"{SLOT_PREFIX}{slot}"
        # A frame of the slot's name: the plant names a world geom's owner by its frame
        # (:attr:`cosmos.plant.Plant.geom_owners`), so contacts name the slot, not "world".
        frame = ElementTree.SubElement(worldbody, "frame", name=name)
        ElementTree.SubElement(
            frame,
            "geom",
            name=name,
            type="sphere",
            size="0.01",
            pos=" ".join(str(c) for c in parked_position(slot)),
            contype=str(OBSTACLE_CONTYPE),
            conaffinity=str(OBSTACLE_CONAFFINITY),
            rgba=rgba,
        )


@functools.cache
def obstacle_scene_xml(slots: int = DEFAULT_SLOTS, scene_xml: Path = SCENE_XML) -> Path:
    """An arm's workcell (``scene.xml``) with ``slots`` obstacle slots, an MJCF file for :class:`Plant`.

    The slots are appended to the scene's text, so every number of the workcell
    is kept as written; the file is kept in the user cache
    (:func:`~cosmos.obstacles.scene_file.kept_scene_file`: the workcell has no file assets,
    so the copy compiles anywhere).
    """
    tree = ElementTree.parse(scene_xml)
    worldbody = tree.getroot().find("worldbody")
    if worldbody is None:  # pragma: no cover - guards the shipped model file
        raise CosmosError(f"{scene_xml}: no worldbody")
    add_obstacle_slots(worldbody, slots)
    text = ElementTree.tostring(tree.getroot(), encoding="unicode")
    return kept_scene_file(f"{scene_xml.parent.name}_scene_with_{slots}_obstacle_slots", text)


def geom_size_and_bounds(obstacle: Obstacle) -> tuple[np.ndarray, float, np.ndarray]:
    """MuJoCo ``geom_size``, ``geom_rbound`` and ``geom_aabb`` of the obstacle's geom.

    The bounds are those MuJoCo's compiler computes for a geom of that type and
    size at its body's origin (checked against the compiler in the tests).
    """
    half = obstacle.half_extents_m
    if obstacle.shape is ObstacleShape.SPHERE:
        r = float(half[0])
        return np.array((r, 0.0, 0.0)), r, np.array((0.0, 0.0, 0.0, r, r, r))
    if obstacle.shape is ObstacleShape.CYLINDER:
        r, h = float(half[0]), float(half[2])
        return np.array((r, h, 0.0)), float(np.hypot(r, h)), np.array((0.0, 0.0, 0.0, r, r, h))
    if obstacle.shape is ObstacleShape.BOX:
        return half.copy(), float(np.linalg.norm(half)), np.concatenate((np.zeros(3), half))
    return np.array((2.0, 2.0, 0.05)), 0.0, np.array(_PLANE_AABB)


class ObstacleScene:
    """The obstacles of a plant built from :func:`obstacle_scene_xml`: add, remove, move them.

    Args:
        plant: A plant whose model has obstacle slots.

    Raises:
        CosmosError: If the plant's model has no obstacle slots.
    """

    def __init__(self, plant: Plant) -> None:
        model = plant.model
        self._plant = plant
        first, count = int(model.body_geomadr[0]), int(model.body_geomnum[0])
        self._slot_geom = [
            g for g in range(first, first + count) if model.geom(g).name.startswith(SLOT_PREFIX)
        ]
        if not self._slot_geom:
            raise CosmosError(
                "the plant's scene has no obstacle slots: build it with "
                "Plant(cosmos.obstacles.obstacle_scene_xml())"
            )
        self._slot_name = [model.geom(g).name for g in self._slot_geom]
        self._leaf_geoms = world_leaves(model)  # the world tree's leaves (fixtures and slots)
        self._above: dict[int, tuple[list[int], list[int], list[int]]] = {}  # a slot's leaf -> the way up
        self._tree: tuple[int, list[int], list[list[int]]] = (0, [], [])  # root; each node's parent, children
        self._by_name: dict[str, tuple[int, Obstacle]] = {}
        self._moving: list[tuple[int, float, float, float, float, float, float, float]] = []
        self._motions = np.zeros((0, mk.MOTION))  # the same, packed for the tick (kernels.moving)
        self._move_into: Callable[[np.ndarray, np.ndarray, float], None] | None = None  # loaded for the first
        self._geom_pos = plant.model.geom_pos
        self._moving_slots: list[tuple[int, Obstacle]] = []
        self._extents: dict[int, tuple[list[float], list[float]]] = {}
        self._obstacles: tuple[Obstacle, ...] = ()
        self._refit_s = -np.inf
        self._sweep_s = SWEEP_S
        self._stale = False  # the hierarchy's shape is older than the obstacles (rebuilt by update)
        self.version = np.zeros(1)
        """Raised whenever a box of the world's tree changes (cosmos.obstacles.gate)."""
        self._index_tree()

    @property
    def capacity(self) -> int:
        """How many obstacles the scene can hold at once."""
        return len(self._slot_geom)

    @property
    def obstacles(self) -> tuple[Obstacle, ...]:
        """The obstacles in the scene, in the order they were added (kept: the executor asks every tick)."""
        return self._obstacles

    def body_names(self) -> dict[str, str]:
        """MuJoCo geom name of each occupied slot -> the obstacle's name (for :func:`collisions`)."""
        return {self._slot_name[slot]: obstacle.name for slot, obstacle in self._by_name.values()}

    def add(self, obstacle: Obstacle) -> None:
        """Put ``obstacle`` in the workcell at its pose for the plant's current time.

        Raises:
            CosmosError: If an obstacle of that name is present or every slot is taken.
        """
        if obstacle.name in self._by_name:
            raise CosmosError(f"obstacle '{obstacle.name}' is already in the scene; remove it first")
        used = {slot for slot, _ in self._by_name.values()}
        free = [slot for slot in range(self.capacity) if slot not in used]
        if not free:
            raise CosmosError(
                f"cannot add obstacle '{obstacle.name}': the workcell holds at most "
                f"{self.capacity} obstacles at once; remove one first"
            )
        slot = free[0]
        model = self._plant.model
        geom = self._slot_geom[slot]
        size, rbound, aabb = geom_size_and_bounds(obstacle)
        model.geom_type[geom] = _GEOM_TYPE[obstacle.shape]
        model.geom_size[geom] = size
        model.geom_rbound[geom] = rbound
        model.geom_aabb[geom] = aabb
        mujoco.mju_mat2Quat(model.geom_quat[geom], np.ascontiguousarray(obstacle.rotation_world).reshape(9))
        # Placed by its own pos and quat; one not turned keeps the world's axes, which MuJoCo then
        # copies instead of composing the quaternions (the same matrix, exactly: the identity).
        unturned = model.geom_quat[geom].tolist() == list(_IDENTITY_QUAT)  # (array_equal: 5-10 us)
        model.geom_sameframe[geom] = _SAME_AXES if unturned else mujoco.mjtSameFrame.mjSAMEFRAME_NONE
        self._by_name[obstacle.name] = (slot, obstacle)
        now = self._plant.time_s
        self._geom_pos[geom] = obstacle.position_at(now)
        self._track_moving()
        self._refit(slot, obstacle.position_at(now).tolist(), obstacle.position_at(now + SWEEP_S).tolist())
        self._stale = True

    def remove(self, name: str) -> Obstacle:
        """Take the obstacle ``name`` out of the workcell (its slot is parked) and return it.

        Raises:
            CosmosError: If there is no obstacle of that name.
        """
        if name not in self._by_name:
            present = ", ".join(self._by_name) or "none"
            raise CosmosError(f"no obstacle '{name}' in the scene (present: {present})")
        slot, obstacle = self._by_name.pop(name)
        parked = np.array(parked_position(slot))
        model = self._plant.model
        geom = self._slot_geom[slot]
        model.geom_quat[geom] = _IDENTITY_QUAT
        model.geom_sameframe[geom] = _SAME_AXES
        self._geom_pos[geom] = parked
        self._track_moving()
        self._refit(slot, parked.tolist(), parked.tolist())
        self._stale = True
        return obstacle

    def update(self, t_s: float) -> None:
        """Move the ``MOVING`` obstacles to their positions at simulated time ``t_s`` (each servo tick).

        The first update after obstacles were added or removed also rebuilds the world's
        hierarchy for them (once for a program's many ``OBSTACLE`` statements; until then
        the refitted one holds them: a refit keeps it valid, a rebuild makes it cheap).
        """
        if self._stale:
            self._rebuild()
        moving = self._moving
        if not moving:
            return
        self._move_into(self._geom_pos, self._motions, t_s)  # type: ignore[misc]  # loaded with _moving
        if t_s >= self._refit_s:  # in plain floats: the servo loop
            until = self._refit_s = t_s + self._sweep_s
            for slot, x, y, z, vx, vy, vz, added_s in moving:
                dt, later = t_s - added_s, until - added_s
                start = [x + vx * dt, y + vy * dt, z + vz * dt]
                self._refit(slot, start, [x + vx * later, y + vy * later, z + vz * later])

    def _track_moving(self) -> None:
        """Cache what :meth:`update` needs: the moving obstacles' motions, packed and as plain floats."""
        self._obstacles = tuple(obstacle for _, obstacle in self._by_name.values())
        self._moving_slots = [(slot, o) for slot, o in self._by_name.values() if o.moving]
        self._extents = {slot: self._extent(slot) for slot, _ in self._moving_slots}  # they never turn
        speeds = [float(np.linalg.norm(o.velocity_world_mps)) for _, o in self._moving_slots]
        self._sweep_s = max(SWEEP_S, SWEEP_M / max(speeds, default=np.inf))
        self._moving = [
            (slot, *obstacle.position_world.tolist(), *obstacle.velocity_world_mps.tolist(), obstacle.added_s)
            for slot, obstacle in self._moving_slots
        ]
        self._motions = np.array(
            [(self._slot_geom[slot], *rest) for slot, *rest in self._moving], dtype=float
        ).reshape(-1, mk.MOTION)
        if self._moving and self._move_into is None:
            self._move_into = mk.entry()
        self._refit_s = -np.inf

    def restore(self, t_s: float) -> None:
        """Put every moving obstacle where it is at ``t_s`` (after the plant's clock was set back)."""
        self._refit_s = -np.inf
        self.update(t_s)

    def _rebuild(self) -> None:
        """Rebuild the world's hierarchy for where its geoms are now (:mod:`cosmos.obstacles.hierarchy`)."""
        model = self._plant.model
        root, nodes = int(model.body_bvhadr[0]), int(model.body_bvhnum[0])
        ids = model.bvh_nodeid[root : root + nodes]
        leaves = np.flatnonzero((model.bvh_child[root : root + nodes] < 0).all(axis=1) & (ids >= 0))
        first = int(model.body_geomadr[0])
        # Each leaf's box, by its geom (the model's arrays read once: a read builds a view, 1-2 us)
        row_of = {first + node_id: row for row, node_id in enumerate(ids[leaves].tolist())}
        leaf_boxes = model.bvh_aabb[root : root + nodes][leaves]
        geoms = self._leaf_geoms
        group_of = dict.fromkeys(self._slot_geom, Group.PARKED)  # a geom not named: the workcell's
        for slot, obstacle in self._by_name.values():
            group_of[self._slot_geom[slot]] = Group.MOVING if obstacle.moving else Group.OBSTACLE
        groups = np.array([group_of.get(g, Group.FIXTURE) for g in geoms.tolist()])
        tree = layout(leaf_boxes[[row_of[g] for g in geoms.tolist()]], groups)
        install(model, geoms, tree)
        self.version[0] += 1.0
        self._stale = False
        self._index_tree()

    def _index_tree(self) -> None:
        """Each slot's leaf in the world's hierarchy, and the nodes above it (what :meth:`_refit` walks).

        Those are listed from the leaf's parent to the root, each with its two children.
        """
        model = self._plant.model
        root, nodes = int(model.body_bvhadr[0]), int(model.body_bvhnum[0])
        child = model.bvh_child[root : root + nodes]  # (nodes, 2), each node's own indices (-1: none)
        node_ids = model.bvh_nodeid[root : root + nodes]
        parent_of = np.full(nodes, -1, dtype=np.int64)  # absolute (-1: the root's)
        for side in (0, 1):
            has = np.flatnonzero(child[:, side] >= 0)
            parent_of[child[has, side]] = root + has
        parent = parent_of.tolist()
        leaves = np.flatnonzero((child < 0).all(axis=1) & (node_ids >= 0))
        first = int(model.body_geomadr[0])
        leaf_of = dict(zip((first + node_ids[leaves]).tolist(), (root + leaves).tolist(), strict=True))
        children = (child + root).tolist()  # absolute (-1 + root: none)
        self._leaf: list[int] = [leaf_of[g] for g in self._slot_geom]
        self._above = {}  # listed for a slot when it is first refitted (most stay parked)
        self._tree = (root, parent, children)

    def _nodes_above(self, leaf: int) -> tuple[list[int], list[int], list[int]]:
        """The way from ``leaf`` up to the root: its nodes, the child of each off the way, the way's side.

        The side of a node's child on the way: 0 its only child (then also listed as off it), 1 left, 2 right.
        """
        if leaf not in self._above:
            root, parent, children = self._tree
            nodes, others, sides, below, node = [], [], [], leaf, parent[leaf - root]
            while node >= 0:
                left, right = children[node - root]
                nodes.append(node)
                others.append(below if right < root else right if left == below else left)
                sides.append(0 if right < root else 1 if left == below else 2)
                below, node = node, parent[node - root]
            self._above[leaf] = (nodes, others, sides)
        return self._above[leaf]

    def _extent(self, slot: int) -> tuple[list[float], list[float]]:
        """Where the slot's geom box is centred from its origin, and its half-sizes, world axes [m]."""
        model = self._plant.model
        geom = self._slot_geom[slot]
        aabb = model.geom_aabb[geom]
        flat = np.empty(9)
        mujoco.mju_quat2Mat(flat, model.geom_quat[geom])
        rotation = flat.reshape(3, 3)
        return (rotation @ aabb[:3]).tolist(), (np.abs(rotation) @ aabb[3:]).tolist()

    def _refit(self, slot: int, start: list[float], end: list[float]) -> None:
        """Fit the slot's leaf of the world's hierarchy to its geom swept from ``start`` to ``end``.

        Then every node above it is refitted to its children (in plain floats: a moving
        obstacle's leaf is refitted every :data:`SWEEP_S`, in the servo loop).
        """
        model = self._plant.model
        offset, half = self._extents.get(slot) or self._extent(slot)
        low = [min(a, b) + o - h for a, b, o, h in zip(start, end, offset, half, strict=True)]
        high = [max(a, b) + o + h for a, b, o, h in zip(start, end, offset, half, strict=True)]
        bvh, leaf = model.bvh_aabb, self._leaf[slot]
        nodes, others, sides = self._nodes_above(leaf)
        off_way = bvh[others].tolist()  # read at once: the walk rewrites only the nodes on its way
        self.version[0] += 1.0
        boxes = [_box(low, high)]
        for side, other in zip(sides, off_way, strict=True):
            if side:  # the box of the left child, of the right child
                a, b = (boxes[-1], other) if side == 1 else (other, boxes[-1])
                low = [min(a[i] - a[i + 3], b[i] - b[i + 3]) for i in range(3)]
                high = [max(a[i] + a[i + 3], b[i] + b[i + 3]) for i in range(3)]
            boxes.append(_box(low, high) if side else boxes[-1])
        bvh[[leaf, *nodes]] = boxes


def _box(low: list[float], high: list[float]) -> list[float]:
    """Centre and half-sizes of the box from ``low`` to ``high`` corners."""
    return [
        (low[0] + high[0]) / 2.0, (low[1] + high[1]) / 2.0, (low[2] + high[2]) / 2.0,
        (high[0] - low[0]) / 2.0, (high[1] - low[1]) / 2.0, (high[2] - low[2]) / 2.0,
    ]  # fmt: skip
