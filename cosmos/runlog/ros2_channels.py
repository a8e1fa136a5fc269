"""The ROS 2 channels of a run log (``--ros2``), fed from the staged state and /tf samples."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from foxglove import Channel, Context, Schema

from cosmos.runlog import ros2
from cosmos.runlog.foxglove import WORLD_FRAME
from cosmos.runlog.schemas import state_vectors


def _slices(joints: int) -> tuple[slice, slice, slice, slice]:
    """Where q, qd, tau and the wrench are in a state row of an arm of ``joints`` joints."""
    vectors = state_vectors(joints)
    starts = dict(
        zip((name for name, _ in vectors), np.cumsum([0] + [n for _, n in vectors]).tolist(), strict=False)
    )
    sizes = dict(vectors)
    q, qd, tau, wrench = (slice(starts[k], starts[k] + sizes[k]) for k in ("q", "qd", "tau", "wrench"))
    return q, qd, tau, wrench


def _channel(context: Context, topic: str, type_name: str) -> Channel:
    schema = Schema(name=type_name, encoding="ros2msg", data=ros2.SCHEMAS[type_name].encode())
    return Channel(topic, message_encoding="cdr", schema=schema, context=context)


class Ros2Channels:
    """``/joint_states``, ``/wrench`` and ``/tf_ros`` in ``context`` (see :mod:`cosmos.runlog.ros2`).

    Args:
        context: The log's foxglove-sdk context.
        joint_names: The arm's joint names, in the order of ``q``.
    """

    def __init__(self, context: Context, joint_names: Sequence[str]):
        self._names = tuple(joint_names)
        self._q, self._qd, self._tau, self._wrench_at = _slices(len(self._names))
        self._joints = _channel(context, ros2.JOINT_STATE_TOPIC, "sensor_msgs/msg/JointState")
        self._wrench = _channel(context, ros2.WRENCH_TOPIC, "geometry_msgs/msg/WrenchStamped")
        self._tf = _channel(context, ros2.TF_TOPIC, "tf2_msgs/msg/TFMessage")

    def state(self, t_ns: int, row: np.ndarray) -> None:
        """Joint state and wrench of one state row (the vectors of ``cosmos.State`` in order)."""
        message = ros2.joint_state(t_ns, self._names, row[self._q], row[self._qd], row[self._tau])
        self._joints.log(message, log_time=t_ns)
        self._wrench.log(ros2.wrench_stamped(t_ns, WORLD_FRAME, row[self._wrench_at]), log_time=t_ns)

    def transforms(self, t_ns: int, frames: Sequence[str], poses: np.ndarray) -> None:
        """The frames' poses in ``world``: translation [m], rotation x y z w. ``poses``: (frames, 7)."""
        self._tf.log(ros2.tf_message(t_ns, WORLD_FRAME, frames, poses), log_time=t_ns)

    def close(self) -> None:
        """Close the channels."""
        for channel in (self._joints, self._wrench, self._tf):
            channel.close()
