"""Foxglove well-known schemas (JSON) and their messages: frames, scene, log.

Foxglove recognises a channel by its schema name (``foxglove.FrameTransforms``,
``foxglove.SceneUpdate``, ``foxglove.Log``) and reads JSON messages of the
documented shape. The schema texts below describe the subset of each message
that cosmos writes; Foxglove fills in what a message leaves out.

Times in these messages are ``{sec, nsec}`` of simulated time since the start
of the run, the same clock as the MCAP log time.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from enum import IntEnum
from typing import Any, Final

TRANSFORMS_TOPIC: Final = "/tf"
SCENE_TOPIC: Final = "/scene"
LOG_TOPIC: Final = "/cosmos/log"

FRAME_TRANSFORMS_SCHEMA_NAME: Final = "foxglove.FrameTransforms"
SCENE_UPDATE_SCHEMA_NAME: Final = "foxglove.SceneUpdate"
LOG_SCHEMA_NAME: Final = "foxglove.Log"

Entity = dict[str, Any]
"""A ``foxglove.SceneEntity`` as JSON."""

WORLD_FRAME: Final = "world"
ARM_FRAMES: Final = ("link1", "link2", "link3", "link4", "link5", "link6", "tool")
"""Child frames published on ``/tf`` by default, each relative to ``world``."""


class LogLevel(IntEnum):
    """Levels of ``foxglove.Log``."""

    UNKNOWN = 0
    DEBUG = 1
    INFO = 2
    WARNING = 3
    ERROR = 4
    FATAL = 5


def _time(description: str) -> dict[str, Any]:
    return {
        "type": "object",
        "title": "time",
        "description": description,
        "properties": {
            "sec": {"type": "integer", "minimum": 0},
            "nsec": {"type": "integer", "minimum": 0, "maximum": 999_999_999},
        },
    }


def _xyz(title: str, description: str, names: str = "xyz") -> dict[str, Any]:
    return {
        "title": title,
        "description": description,
        "type": "object",
        "properties": {axis: {"type": "number"} for axis in names},
    }


def _pose(description: str) -> dict[str, Any]:
    return {
        "title": "foxglove.Pose",
        "description": description,
        "type": "object",
        "properties": {
            "position": _xyz("foxglove.Vector3", "position [m]"),
            "orientation": _xyz("foxglove.Quaternion", "orientation", "xyzw"),
        },
    }


def _color() -> dict[str, Any]:
    return _xyz("foxglove.Color", "colour, each component in [0, 1]", "rgba")


def _primitive(title: str, size: str, extra: dict[str, Any] | None = None) -> dict[str, Any]:
    return {
        "type": "array",
        "items": {
            "title": title,
            "type": "object",
            "properties": {
                "pose": _pose("pose of the centre of the primitive"),
                "size": _xyz("foxglove.Vector3", size),
                **(extra or {}),
                "color": _color(),
            },
        },
    }


FRAME_TRANSFORMS_SCHEMA: Final = {
    "title": FRAME_TRANSFORMS_SCHEMA_NAME,
    "description": "An array of FrameTransform messages",
    "type": "object",
    "properties": {
        "transforms": {
            "type": "array",
            "items": {
                "title": "foxglove.FrameTransform",
                "description": "pose of the child frame in the parent frame",
                "type": "object",
                "properties": {
                    "timestamp": _time("time of the transform"),
                    "parent_frame_id": {"type": "string"},
                    "child_frame_id": {"type": "string"},
                    "translation": _xyz("foxglove.Vector3", "child origin in the parent [m]"),
                    "rotation": _xyz("foxglove.Quaternion", "child orientation", "xyzw"),
                },
            },
        }
    },
}

SCENE_UPDATE_SCHEMA: Final = {
    "title": SCENE_UPDATE_SCHEMA_NAME,
    "description": "An update to the entities displayed in a 3D scene",
    "type": "object",
    "properties": {
        "deletions": {
            "type": "array",
            "items": {
                "title": "foxglove.SceneEntityDeletion",
                "type": "object",
                "properties": {
                    "timestamp": _time("entities older than this are deleted"),
                    "type": {
                        "title": "foxglove.SceneEntityDeletionType",
                        "oneOf": [
                            {"title": "MATCHING_ID", "const": 0},
                            {"title": "ALL", "const": 1},
                        ],
                    },
                    "id": {"type": "string"},
                },
            },
        },
        "entities": {
            "type": "array",
            "items": {
                "title": "foxglove.SceneEntity",
                "type": "object",
                "properties": {
                    "timestamp": _time("time of the entity"),
                    "frame_id": {"type": "string"},
                    "id": {"type": "string"},
                    "lifetime": _time("zero: until replaced or deleted") | {"title": "duration"},
                    "frame_locked": {"type": "boolean"},
                    "cubes": _primitive("foxglove.CubePrimitive", "edge lengths [m]"),
                    "spheres": _primitive("foxglove.SpherePrimitive", "diameters [m]"),
                    "cylinders": _primitive(
                        "foxglove.CylinderPrimitive",
                        "diameters in x and y, height along the axis z [m]",
                        {
                            "bottom_scale": {"type": "number"},
                            "top_scale": {"type": "number"},
                        },
                    ),
                },
            },
        },
    },
}

LOG_SCHEMA: Final = {
    "title": LOG_SCHEMA_NAME,
    "description": "A log message",
    "type": "object",
    "properties": {
        "timestamp": _time("time of the message"),
        "level": {
            "title": "foxglove.LogLevel",
            "oneOf": [{"title": level.name, "const": level.value} for level in LogLevel],
        },
        "message": {"type": "string"},
        "name": {"type": "string"},
        "file": {"type": "string"},
        "line": {"type": "integer", "minimum": 0},
    },
}


def stamp(t_ns: int) -> dict[str, int]:
    """Foxglove ``{sec, nsec}`` of a log time in integer nanoseconds."""
    sec, nsec = divmod(t_ns, 1_000_000_000)
    return {"sec": sec, "nsec": nsec}


def frame_transforms_format(child_frames: Sequence[str], parent_frame: str = WORLD_FRAME) -> str:
    """The ``foxglove.FrameTransforms`` JSON text for a fixed list of frames, as a ``%``-format.

    Per frame, nine ``%d`` holes: the time's ``sec`` and ``nsec``, the
    translation x y z [m] and the rotation x y z w, both in micro-units (the
    text ``125730e-6`` is 0.125730). The run log's compiled kernel fills it
    (:mod:`cosmos.runlog.text_kernel`).

    Args:
        child_frames: Names of the frames, in the order their poses are given.
        parent_frame: Frame the poses are expressed in.
    """
    item = (
        '{"timestamp":{"sec":%d,"nsec":%d},'
        f'"parent_frame_id":{json.dumps(parent_frame).replace("%", "%%")},'
        '"child_frame_id":%s,'
        '"translation":{"x":%de-6,"y":%de-6,"z":%de-6},'
        '"rotation":{"x":%de-6,"y":%de-6,"z":%de-6,"w":%de-6}}'
    )
    items = ",".join(item.replace("%s", json.dumps(name).replace("%", "%%")) for name in child_frames)
    return '{"transforms":[' + items + "]}"


def scene_update(t_ns: int, entities: Sequence[Entity], removed: Sequence[str] = ()) -> bytes:
    """A ``foxglove.SceneUpdate`` message that deletes, then adds or replaces entities."""
    message = {
        "deletions": [{"timestamp": stamp(t_ns), "type": 0, "id": i} for i in removed],
        "entities": list(entities),
    }
    return json.dumps(message, separators=(",", ":")).encode()


def log_message(t_ns: int, level: LogLevel, message: str, file: str, line: int) -> bytes:
    """A ``foxglove.Log`` message from cosmos about a source line."""
    record = {
        "timestamp": stamp(t_ns),
        "level": int(level),
        "message": message,
        "name": "cosmos",
        "file": file,
        "line": line,
    }
    return json.dumps(record, separators=(",", ":")).encode()
