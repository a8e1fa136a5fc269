"""Obstacles logged on ``/scene``, drawn over a playback as extra geoms.

The log's ``/scene`` channel (``foxglove.SceneUpdate``, see docs/log-format.md)
shows the fixtures at the start and then every obstacle as it is added, moved
(sent again with the same id) or removed (a deletion). Playback draws the
workcell model, which has the fixtures and the arm already, so entities whose
id names a geom of the model, or that are attached to a frame other than
``world`` (the arm's links), are skipped; the rest (the obstacles) are drawn as
boxes, cylinders and spheres in the colour they were logged with.

``/scene`` is protobuf (log format 2, see docs/log-format.md), decoded with
Foxglove's published protobuf schemas; logs of format 1 held it as JSON of the
same shape, and both are read.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import Any

import numpy as np

from cosmos.errors import CosmosError
from cosmos.runlog.foxglove import SCENE_TOPIC, WORLD_FRAME
from cosmos.runlog.limits import MAX_SCENE_MESSAGE_BYTES, MAX_TEXT_CHARS
from cosmos.runlog.scan import load_mcap
from cosmos.runlog.validate import Invalid, decode, number

MAX_SHOWN = 1_000_000
"""Most shapes :func:`scene_timeline` keeps, summed over the updates (each keeps all it shows)."""


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


def _rotation(quat_xyzw: np.ndarray) -> np.ndarray:
    x, y, z, w = quat_xyzw
    norm = np.sqrt(w * w + x * x + y * y + z * z) or 1.0
    w, x, y, z = w / norm, x / norm, y / norm, z / norm
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _object(value: Any, name: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise Invalid(f"{name} is not a JSON object")
    return value


def _list(parent: dict[str, Any], name: str) -> list[Any]:
    value = parent.get(name, [])
    if not isinstance(value, list):
        raise Invalid(f"{name} is not a list")
    return value


def _numbers(parent: dict[str, Any], name: str, keys: str) -> np.ndarray:
    """The finite numbers ``parent[name][k]`` for each key ``k`` of ``keys``."""
    values = _object(parent.get(name), name)
    try:
        return np.array([number(values, k) for k in keys])
    except Invalid as error:
        raise Invalid(f"{name}.{error}") from None


def _shapes(entity: dict[str, Any]) -> list[Shape]:
    shapes = []
    for kind in ShapeKind:
        for item in _list(entity, kind.value):
            item = _object(item, kind.value)
            pose = _object(item.get("pose"), "pose")
            extent = _numbers(item, "size", "xyz") / 2
            if kind is ShapeKind.CYLINDER:
                extent = np.array([extent[0], extent[0], extent[2]])
            shapes.append(
                Shape(
                    kind=kind,
                    position=_numbers(pose, "position", "xyz"),
                    rotation_to_world=_rotation(_numbers(pose, "orientation", "xyzw")),
                    half_sizes=extent,
                    rgba=_numbers(item, "color", "rgba"),
                )
            )
    return shapes


def _entity_id(item: Any, what: str) -> str:
    value = _object(item, what).get("id")
    if not isinstance(value, str) or len(value) > MAX_TEXT_CHARS:
        raise Invalid(f"{what} id is not a string of at most {MAX_TEXT_CHARS:,} characters")
    return value


def _apply(update: dict[str, Any], current: dict[str, list[Shape]], drawn_already: Collection[str]) -> None:
    """Apply one ``foxglove.SceneUpdate``: deletions first, then added or replaced entities."""
    for deletion in _list(update, "deletions"):
        current.pop(_entity_id(deletion, "deletion"), None)
    for entity in _list(update, "entities"):
        name = _entity_id(entity, "entity")
        if name not in drawn_already and entity.get("frame_id", WORLD_FRAME) == WORLD_FRAME:
            current[name] = _shapes(entity)


def _decode_update(data: bytes, encoding: str) -> dict[str, Any]:
    """One ``/scene`` message as a dict of the JSON shape, from protobuf (format 2) or JSON (format 1)."""
    if encoding == "json":
        return decode(data, MAX_SCENE_MESSAGE_BYTES)
    if encoding != "protobuf":
        raise Invalid(f"message encoding {encoding[:40]!r} is neither protobuf nor json")
    if len(data) > MAX_SCENE_MESSAGE_BYTES:
        raise Invalid(f"{len(data):,} bytes, more than the {MAX_SCENE_MESSAGE_BYTES:,} a message may have")
    from foxglove_schemas_protobuf.SceneUpdate_pb2 import SceneUpdate
    from google.protobuf.json_format import MessageToDict
    from google.protobuf.message import DecodeError

    try:
        message = SceneUpdate.FromString(data)
    except (DecodeError, RecursionError) as error:
        raise Invalid(f"not a protobuf foxglove.SceneUpdate ({str(error)[:80]})") from None
    return MessageToDict(message, preserving_proto_field_name=True, always_print_fields_with_no_presence=True)


def scene_timeline(path: Path, drawn_already: Collection[str]) -> SceneTimeline:
    """Read the obstacles of a log's ``/scene`` channel (read and checked like every message).

    Args:
        path: The MCAP log (a cut one is read up to the cut).
        drawn_already: Entity ids to skip: the model's own geoms (fixtures).

    Raises:
        CosmosError: If a ``/scene`` message is not a scene update cosmos can draw
            (one line naming it), or the scene holds more than ``MAX_SHOWN`` shapes.
    """
    contents = load_mcap(path)
    channels = {
        cid: channel.message_encoding
        for cid, channel in contents.channels.items()
        if channel.topic == SCENE_TOPIC
    }
    updates = [m for m in contents.messages if m.channel_id in channels]
    order = sorted(range(len(updates)), key=lambda i: updates[i].log_time)
    current: dict[str, list[Shape]] = {}
    times: list[float] = []
    shown: list[tuple[Shape, ...]] = []
    total = 0
    for i in order:
        message = updates[i]
        try:
            _apply(_decode_update(message.data, channels[message.channel_id]), current, drawn_already)
        except Invalid as error:
            raise CosmosError(f"{path}: {SCENE_TOPIC} message {i + 1}: {error}") from None
        times.append(message.log_time / 1e9)
        shown.append(tuple(shape for shapes in current.values() for shape in shapes))
        total += len(shown[-1])
        if total > MAX_SHOWN:
            raise CosmosError(f"{path}: {SCENE_TOPIC}: more than {MAX_SHOWN:,} shapes to draw over the run")
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
