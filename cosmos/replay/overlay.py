"""Obstacles logged on ``/scene``, drawn over a playback as extra geoms.

The log's ``/scene`` channel (``foxglove.SceneUpdate``, see docs/log-format.md)
shows the fixtures at the start and then every obstacle as it is added, moved
(sent again with the same id) or removed (a deletion). Playback draws the
workcell model, which has the fixtures already, so entities whose id names a
geom of the model are skipped; the rest (the obstacles) are drawn as boxes,
cylinders and spheres in the colour they were logged with.
"""

from __future__ import annotations

import json
from collections.abc import Collection, Sequence
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import Any

import numpy as np

from cosmos.errors import CosmosError
from cosmos.runlog.foxglove import SCENE_TOPIC
from cosmos.runlog.scan import load_mcap


class ShapeKind(Enum):
    """The primitives a Foxglove scene entity may hold that cosmos writes."""

    BOX = "cubes"
    CYLINDER = "cylinders"
    SPHERE = "spheres"


@dataclass(frozen=True)
class Shape:
    """One primitive to draw.

    Attributes:
        kind: Box, cylinder or sphere.
        position: Centre in the world frame [m]. # (3,)
        rotation_to_world: Orientation. # (3, 3)
        half_sizes: MuJoCo geom size: box half edges; cylinder radius, radius,
            half height; sphere radius (three times) [m]. # (3,)
        rgba: Colour. # (4,)
    """

    kind: ShapeKind
    position: np.ndarray
    rotation_to_world: np.ndarray
    half_sizes: np.ndarray
    rgba: np.ndarray


@dataclass(frozen=True)
class SceneTimeline:
    """The obstacles shown after each ``/scene`` update, in time order."""

    times_s: np.ndarray  # (updates,)
    shown: tuple[tuple[Shape, ...], ...]  # (updates,)

    def at(self, t_s: float) -> tuple[Shape, ...]:
        """The obstacles shown at simulated time ``t_s``."""
        index = int(np.searchsorted(self.times_s, t_s, side="right")) - 1
        return self.shown[index] if index >= 0 else ()


def _rotation(quat_xyzw: dict[str, float]) -> np.ndarray:
    x, y, z, w = (float(quat_xyzw[k]) for k in ("x", "y", "z", "w"))
    norm = np.sqrt(w * w + x * x + y * y + z * z) or 1.0
    w, x, y, z = w / norm, x / norm, y / norm, z / norm
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _shapes(entity: dict[str, Any]) -> list[Shape]:
    shapes = []
    for kind in ShapeKind:
        for item in entity.get(kind.value, []):
            pose, size, color = item["pose"], item["size"], item["color"]
            extent = np.array([size["x"], size["y"], size["z"]], dtype=float) / 2
            if kind is ShapeKind.CYLINDER:
                extent = np.array([extent[0], extent[0], extent[2]])
            shapes.append(
                Shape(
                    kind=kind,
                    position=np.array([pose["position"][k] for k in "xyz"], dtype=float),
                    rotation_to_world=_rotation(pose["orientation"]),
                    half_sizes=extent,
                    rgba=np.array([color[k] for k in "rgba"], dtype=float),
                )
            )
    return shapes


def scene_timeline(path: Path, drawn_already: Collection[str]) -> SceneTimeline:
    """Read the obstacles of a log's ``/scene`` channel.

    Args:
        path: The MCAP log (a cut one is read up to the cut).
        drawn_already: Entity ids to skip: the model's own geoms (fixtures).

    Raises:
        CosmosError: If a ``/scene`` message is not a scene update cosmos wrote.
    """
    contents = load_mcap(path)
    channels = {cid for cid, channel in contents.channels.items() if channel.topic == SCENE_TOPIC}
    updates = sorted((m for m in contents.messages if m.channel_id in channels), key=lambda m: m.log_time)
    current: dict[str, list[Shape]] = {}
    times: list[float] = []
    shown: list[tuple[Shape, ...]] = []
    for message in updates:
        try:
            update = json.loads(message.data)
            for deletion in update.get("deletions", []):
                current.pop(str(deletion["id"]), None)
            for entity in update.get("entities", []):
                if entity["id"] not in drawn_already:
                    current[str(entity["id"])] = _shapes(entity)
        except (ValueError, KeyError, TypeError) as error:
            raise CosmosError(f"{path}: a {SCENE_TOPIC} message is malformed: {error!r}") from None
        times.append(message.log_time / 1e9)
        shown.append(tuple(shape for shapes in current.values() for shape in shapes))
    return SceneTimeline(np.array(times, dtype=float), tuple(shown))


def draw(scene: Any, shapes: Sequence[Shape]) -> None:
    """Append ``shapes`` to a ``mujoco.MjvScene`` as visual-only geoms (as many as fit)."""
    import mujoco

    geom_types = {
        ShapeKind.BOX: mujoco.mjtGeom.mjGEOM_BOX,
        ShapeKind.CYLINDER: mujoco.mjtGeom.mjGEOM_CYLINDER,
        ShapeKind.SPHERE: mujoco.mjtGeom.mjGEOM_SPHERE,
    }
    for shape in shapes:
        if scene.ngeom >= scene.maxgeom:
            return
        mujoco.mjv_initGeom(
            scene.geoms[scene.ngeom],
            int(geom_types[shape.kind]),
            shape.half_sizes,
            shape.position,
            shape.rotation_to_world.reshape(-1),
            shape.rgba.astype(np.float32),
        )
        scene.ngeom += 1
