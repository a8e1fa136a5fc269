"""Foxglove well-known messages (protobuf) of the run log: frames, scene, log.

Foxglove, rerun and other viewers recognise a channel by its schema name
(``foxglove.FrameTransforms``, ``foxglove.SceneUpdate``, ``foxglove.Log``).
cosmos writes these channels through foxglove-sdk's typed channels, which
encode protobuf and store Foxglove's own ``.proto`` schemas (a
``FileDescriptorSet``) in the log: the messages match the official schemas by
construction. Logs written before (log format 1) held the same content as JSON.

Times in these messages are ``{sec, nsec}`` of simulated time since the start
of the run, the same clock as the MCAP log time.
"""

from __future__ import annotations

from collections.abc import Sequence
from enum import IntEnum
from typing import Final

import numpy as np
from foxglove import messages as fm

TRANSFORMS_TOPIC: Final = "/tf"
SCENE_TOPIC: Final = "/scene"
LOG_TOPIC: Final = "/cosmos/log"

FRAME_TRANSFORMS_SCHEMA_NAME: Final = "foxglove.FrameTransforms"
SCENE_UPDATE_SCHEMA_NAME: Final = "foxglove.SceneUpdate"
LOG_SCHEMA_NAME: Final = "foxglove.Log"

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


_SDK_LEVELS: Final = {
    LogLevel.UNKNOWN: fm.LogLevel.Unknown,
    LogLevel.DEBUG: fm.LogLevel.Debug,
    LogLevel.INFO: fm.LogLevel.Info,
    LogLevel.WARNING: fm.LogLevel.Warning,
    LogLevel.ERROR: fm.LogLevel.Error,
    LogLevel.FATAL: fm.LogLevel.Fatal,
}


def stamp(t_ns: int) -> fm.Timestamp:
    """Foxglove time ``{sec, nsec}`` of a log time in integer nanoseconds."""
    sec, nsec = divmod(t_ns, 1_000_000_000)
    return fm.Timestamp(sec, nsec)


def frame_transforms(
    t_ns: int, child_frames: Sequence[str], poses: np.ndarray, parent_frame: str = WORLD_FRAME
) -> fm.FrameTransforms:
    """A ``foxglove.FrameTransforms`` message: the pose of each child frame in the parent.

    Args:
        t_ns: Time of the poses [ns].
        child_frames: Names of the frames, in the order of ``poses``.
        poses: Per frame, translation x y z [m] and rotation x y z w. # (frames, 7)
        parent_frame: Frame the poses are expressed in.
    """
    time = stamp(t_ns)
    return fm.FrameTransforms(
        transforms=[
            fm.FrameTransform(
                timestamp=time,
                parent_frame_id=parent_frame,
                child_frame_id=name,
                translation=fm.Vector3(x=x, y=y, z=z),
                rotation=fm.Quaternion(x=qx, y=qy, z=qz, w=qw),
            )
            for name, (x, y, z, qx, qy, qz, qw) in zip(child_frames, poses.tolist(), strict=True)
        ]
    )


def scene_update(
    t_ns: int, entities: Sequence[fm.SceneEntity], removed: Sequence[str] = ()
) -> fm.SceneUpdate:
    """A ``foxglove.SceneUpdate`` message that deletes, then adds or replaces entities."""
    deletions = [
        fm.SceneEntityDeletion(timestamp=stamp(t_ns), type=fm.SceneEntityDeletionType.MatchingId, id=i)
        for i in removed
    ]
    return fm.SceneUpdate(deletions=deletions, entities=list(entities))


def log_message(t_ns: int, level: LogLevel, message: str, file: str, line: int) -> fm.Log:
    """A ``foxglove.Log`` message from cosmos about a source line."""
    return fm.Log(
        timestamp=stamp(t_ns),
        level=_SDK_LEVELS[level],
        message=message,
        name="cosmos",
        file=file,
        line=line,
    )
