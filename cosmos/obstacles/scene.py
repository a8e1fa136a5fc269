"""Obstacles as real bodies of the MuJoCo workcell, so a collision is a contact MuJoCo reports.

MuJoCo compiles a model once, so the workcell is built with a fixed number of
obstacle *slots* (:func:`add_obstacle_slots`): mocap bodies named
``obstacle_slot<i>``, each with one geom, parked far below the floor. Adding an
obstacle takes a free slot and sets its geom's type and size (and the bounding
volumes the collision broad phase uses: ``geom_rbound``, ``geom_aabb`` and the
body's ``bvh_aabb``) and its mocap pose; removing it parks the slot again. A
``MOVING`` obstacle is a mocap body moved by :meth:`ObstacleScene.update`, which
the executor calls every servo tick (the mocap pose is held over the physics
steps of one tick).

Contact filtering: the slot geoms have ``contype 0`` and ``conaffinity 6``, so
they touch the arm's links (``contype 2``) and the tool (``contype 4``) but not
the fixtures (``contype 1``) nor each other; being mocap bodies they are welded
to the world, so MuJoCo never collides them with world geoms either.

:meth:`cosmos.plant.Plant.reset` restores the keyframe, which parks every slot:
call :meth:`ObstacleScene.restore` after a reset.
"""

from __future__ import annotations

import functools
import tempfile
from pathlib import Path
from xml.etree import ElementTree

import mujoco
import numpy as np

from cosmos.errors import CosmosError
from cosmos.obstacles.obstacle import Obstacle
from cosmos.plan import ObstacleShape
from cosmos.plant import Plant
from cosmos.workcell import SCENE_XML

DEFAULT_SLOTS = 12
"""Obstacles the workcell can hold at once."""
SLOT_PREFIX = "obstacle_slot"
OBSTACLE_CONTYPE = 0
OBSTACLE_CONAFFINITY = 6  # arm links (contype 2) and tool (contype 4)
OBSTACLE_RGBA = (0.90, 0.35, 0.20, 0.6)
_PARKED_Z_M = -50.0
_PLANE_AABB = (0.0, 0.0, -5e9, 1e10, 1e10, 5e9)  # what MuJoCo's compiler gives a plane
_GEOM_TYPE = {
    ObstacleShape.SPHERE: mujoco.mjtGeom.mjGEOM_SPHERE,
    ObstacleShape.CYLINDER: mujoco.mjtGeom.mjGEOM_CYLINDER,
    ObstacleShape.BOX: mujoco.mjtGeom.mjGEOM_BOX,
    ObstacleShape.PLANE: mujoco.mjtGeom.mjGEOM_PLANE,
}


def parked_position(slot: int) -> tuple[float, float, float]:
    """Where slot ``slot`` waits when free, in [m]: far below the floor, out of reach."""
    return (3.0 * slot, 0.0, _PARKED_Z_M)


def add_obstacle_slots(worldbody: ElementTree.Element, count: int = DEFAULT_SLOTS) -> None:
    """Append ``count`` parked obstacle slots (mocap bodies, one geom each) to an MJCF ``worldbody``."""
    rgba = " ".join(str(c) for c in OBSTACLE_RGBA)
    for slot in range(count):
        name = f"{SLOT_PREFIX}{slot}"
        pos = " ".join(str(c) for c in parked_position(slot))
        body = ElementTree.SubElement(worldbody, "body", name=name, mocap="true", pos=pos)
        ElementTree.SubElement(
            body,
            "geom",
            name=name,
            type="sphere",
            size="0.01",
            contype=str(OBSTACLE_CONTYPE),
            conaffinity=str(OBSTACLE_CONAFFINITY),
            rgba=rgba,
        )


@functools.cache
def _scene_dir() -> tempfile.TemporaryDirectory[str]:
    return tempfile.TemporaryDirectory(prefix="cosmos-obstacles-")


@functools.cache
def obstacle_scene_xml(slots: int = DEFAULT_SLOTS) -> Path:
    """The workcell (``scene.xml``) with ``slots`` obstacle slots, as an MJCF file for :class:`Plant`.

    The slots are appended to the scene's text, so every number of the workcell
    is kept as written; the file is written once per process into a temporary
    directory (the workcell has no file assets, so the copy compiles anywhere).
    """
    tree = ElementTree.parse(SCENE_XML)
    worldbody = tree.getroot().find("worldbody")
    if worldbody is None:  # pragma: no cover - guards the shipped model file
        raise CosmosError(f"{SCENE_XML}: no worldbody")
    add_obstacle_slots(worldbody, slots)
    path = Path(_scene_dir().name) / f"scene_with_{slots}_obstacle_slots.xml"
    tree.write(path, encoding="unicode")
    return path


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
        self._slot_body: list[int] = []
        for body in range(model.nbody):
            if model.body(body).name.startswith(SLOT_PREFIX) and model.body_mocapid[body] >= 0:
                self._slot_body.append(body)
        if not self._slot_body:
            raise CosmosError(
                "the plant's scene has no obstacle slots: build it with "
                "Plant(cosmos.obstacles.obstacle_scene_xml())"
            )
        self._slot_geom = [int(model.body_geomadr[b]) for b in self._slot_body]
        self._slot_name = [model.body(b).name for b in self._slot_body]
        self._by_name: dict[str, tuple[int, Obstacle]] = {}
        self._moving: list[tuple[np.ndarray, float, float, float, float, float, float, float]] = []

    @property
    def capacity(self) -> int:
        """How many obstacles the scene can hold at once."""
        return len(self._slot_body)

    @property
    def obstacles(self) -> tuple[Obstacle, ...]:
        """The obstacles in the scene, in the order they were added."""
        return tuple(obstacle for _, obstacle in self._by_name.values())

    def body_names(self) -> dict[str, str]:
        """MuJoCo body name of each occupied slot -> the obstacle's name."""
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
        geom, body = self._slot_geom[slot], self._slot_body[slot]
        size, rbound, aabb = geom_size_and_bounds(obstacle)
        model.geom_type[geom] = _GEOM_TYPE[obstacle.shape]
        model.geom_size[geom] = size
        model.geom_rbound[geom] = rbound
        model.geom_aabb[geom] = aabb
        model.bvh_aabb[model.body_bvhadr[body]] = aabb
        self._by_name[obstacle.name] = (slot, obstacle)
        self._orient(slot, obstacle)
        self._place(slot, obstacle.position_at(self._plant.time_s))
        self._track_moving()

    def remove(self, name: str) -> Obstacle:
        """Take the obstacle ``name`` out of the workcell (its slot is parked) and return it.

        Raises:
            CosmosError: If there is no obstacle of that name.
        """
        if name not in self._by_name:
            present = ", ".join(self._by_name) or "none"
            raise CosmosError(f"no obstacle '{name}' in the scene (present: {present})")
        slot, obstacle = self._by_name.pop(name)
        self._place(slot, np.array(parked_position(slot)))
        self._track_moving()
        return obstacle

    def update(self, t_s: float) -> None:
        """Move the ``MOVING`` obstacles to their positions at simulated time ``t_s`` (each servo tick)."""
        for position, x, y, z, vx, vy, vz, added_s in self._moving:
            dt = t_s - added_s
            position[0] = x + vx * dt
            position[1] = y + vy * dt
            position[2] = z + vz * dt

    def _track_moving(self) -> None:
        """Cache what :meth:`update` needs per tick: the mocap body's row of ``mocap_pos``, plain floats."""
        body_mocapid, mocap_pos = self._plant.model.body_mocapid, self._plant.data.mocap_pos
        self._moving = [
            (
                mocap_pos[int(body_mocapid[self._slot_body[slot]])],  # a view: writes reach MuJoCo
                *obstacle.position_world.tolist(),
                *obstacle.velocity_world_mps.tolist(),
                obstacle.added_s,
            )
            for slot, obstacle in self._by_name.values()
            if obstacle.moving
        ]

    def restore(self, t_s: float) -> None:
        """Put every obstacle back at its pose at ``t_s`` (after :meth:`Plant.reset` parked them)."""
        for slot, obstacle in self._by_name.values():
            self._orient(slot, obstacle)
            self._place(slot, obstacle.position_at(t_s))

    def _orient(self, slot: int, obstacle: Obstacle) -> None:
        quat = np.empty(4)
        mujoco.mju_mat2Quat(quat, np.ascontiguousarray(obstacle.rotation_world).reshape(9))
        self._plant.data.mocap_quat[self._plant.model.body_mocapid[self._slot_body[slot]]] = quat

    def _place(self, slot: int, position: np.ndarray) -> None:
        mocap = self._plant.model.body_mocapid[self._slot_body[slot]]
        self._plant.data.mocap_pos[mocap] = position
