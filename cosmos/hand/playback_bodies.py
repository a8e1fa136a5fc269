"""A gripper run's video: the workcell it ran in, and where its fingers and objects were.

``cosmos replay LOG --video`` poses the arm from the logged joint angles; a ``TOOL GRIPPER``
run also had the gripper and free objects, whose state is not in ``/cosmos/state``. They
are read back from the log: the objects' body poses from ``/tf`` (MuJoCo's, every 5th
state sample) and the fingers' opening from ``/cosmos/hand``, interpolated (linearly, the
quaternions renormalised) at the video's frame times. The objects themselves come from the
program stored in the log, compiled again.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence

import mujoco
import numpy as np

from cosmos.errors import CosmosError
from cosmos.hand.gripper_scene import FINGERS, mount_gripper
from cosmos.hand.hand_log import HAND_TOPIC
from cosmos.hand.holder_scene import add_holder
from cosmos.hand.object_scene import add_objects
from cosmos.hand.work_object import WorkObject
from cosmos.runlog.reader import RunRecord
from cosmos.runlog.scan import load_mcap

TF_TOPIC = "/tf"


def gripper_workcell(
    record: RunRecord,
) -> tuple[Callable[[mujoco.MjSpec], None], tuple[WorkObject, ...]] | None:
    """The spec edit that rebuilds a gripper run's workcell, and its objects; None for a peg run."""
    if record.metadata.get("tool", "peg") != "gripper":
        return None
    from cosmos.lang import compile_program
    from cosmos.workcell import fixture_frames

    robot = record.metadata.get("robot", "puma560")
    try:
        objects = compile_program(
            record.source or "", record.source_name or "program", fixture_frames()
        ).objects
    except CosmosError as error:
        raise CosmosError(f"{record.path}: the program stored in the log does not compile: {error}") from None

    def edit(spec: mujoco.MjSpec) -> None:
        mount_gripper(spec, robot)
        add_holder(spec)
        add_objects(spec, objects)

    return edit, objects


class BodyTimeline:
    """The objects' poses and the fingers' opening of a gripper run, at any time.

    Args:
        record: The run's log.
        objects: Its objects (their names are ``/tf`` frames).
    """

    def __init__(self, record: RunRecord, objects: Sequence[WorkObject]) -> None:
        from foxglove_schemas_protobuf.FrameTransforms_pb2 import FrameTransforms

        names = {item.name for item in objects}
        contents = load_mcap(record.path)
        topics = {cid: c for cid, c in contents.channels.items() if c.topic in (TF_TOPIC, HAND_TOPIC)}
        poses: dict[str, list[tuple[float, np.ndarray]]] = {name: [] for name in names}
        openings: list[tuple[float, float]] = []
        for message in contents.messages:
            channel = topics.get(message.channel_id)
            if channel is None:
                continue
            t_s = message.log_time / 1e9
            if channel.topic == HAND_TOPIC:
                openings.append((t_s, float(json.loads(message.data)["opening"])))
                continue
            for transform in FrameTransforms.FromString(message.data).transforms:
                if transform.child_frame_id in poses:
                    p, r = transform.translation, transform.rotation
                    pose = np.array([p.x, p.y, p.z, r.w, r.x, r.y, r.z])
                    poses[transform.child_frame_id].append((t_s, pose))
        self._poses = {name: _columns(samples) for name, samples in poses.items() if samples}
        self._openings = _columns([(t, np.array([o])) for t, o in openings]) if openings else None

    def apply(self, model: mujoco.MjModel, data: mujoco.MjData, t_s: float) -> None:
        """Set the objects' free joints and the fingers' slides to where they were at ``t_s``."""
        for name, (times, rows) in self._poses.items():
            pose = np.array([np.interp(t_s, times, rows[:, k]) for k in range(7)])
            pose[3:] /= np.linalg.norm(pose[3:]) or 1.0
            joint = model.body(name).jntadr[0]
            data.qpos[model.jnt_qposadr[joint] : model.jnt_qposadr[joint] + 7] = pose
        if self._openings is not None:
            times, rows = self._openings
            half = 0.5 * float(np.interp(t_s, times, rows[:, 0]))
            for finger in FINGERS:
                data.qpos[model.jnt_qposadr[model.joint(finger).id]] = half


def _columns(samples: list[tuple[float, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    samples.sort(key=lambda s: s[0])
    return np.array([t for t, _ in samples]), np.vstack([row for _, row in samples])
