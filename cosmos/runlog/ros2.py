"""ROS 2 messages of the run log (``cosmos run --ros2``): CDR-encoded, with their ros2msg schemas.

Three channels, for ``ros2 bag play``, PlotJuggler and rviz (docs/log-format.md):

- ``/joint_states``: ``sensor_msgs/msg/JointState``, with every state sample:
  the arm's joint names, positions [rad], velocities [rad/s] and torques [N m].
- ``/wrench``: ``geometry_msgs/msg/WrenchStamped``, with every state sample:
  the wrist sensor's wrench as on ``/cosmos/state`` (what the tool applies to
  the environment, world axes, ``frame_id`` ``world``).
- ``/tf_ros``: ``tf2_msgs/msg/TFMessage``, with every ``/tf`` sample: the same
  link and tool poses, each child of ``world``.

The encoding is OMG CDR, little endian (encapsulation ``00 01 00 00``), as
ROS 2's rmw writes it: each primitive aligned to its size from the start of
the payload, strings as a ``uint32`` length counting the final NUL, sequences
as a ``uint32`` count. Stamps are ``{sec, nanosec}`` of simulated time.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from typing import Final

import numpy as np

JOINT_STATE_TOPIC: Final = "/joint_states"
WRENCH_TOPIC: Final = "/wrench"
TF_TOPIC: Final = "/tf_ros"

_HEADER_DEFS: Final = """\
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
"""
_VECTOR_DEFS: Final = """\
================================================================================
MSG: geometry_msgs/Vector3
float64 x
float64 y
float64 z
"""

SCHEMAS: Final = {
    "sensor_msgs/msg/JointState": (
        "std_msgs/Header header\nstring[] name\nfloat64[] position\nfloat64[] velocity\n"
        "float64[] effort\n" + _HEADER_DEFS
    ),
    "geometry_msgs/msg/WrenchStamped": (
        "std_msgs/Header header\ngeometry_msgs/Wrench wrench\n"
        + _HEADER_DEFS
        + "================================================================================\n"
        "MSG: geometry_msgs/Wrench\ngeometry_msgs/Vector3 force\ngeometry_msgs/Vector3 torque\n"
        + _VECTOR_DEFS
    ),
    "tf2_msgs/msg/TFMessage": (
        "geometry_msgs/TransformStamped[] transforms\n"
        "================================================================================\n"
        "MSG: geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\n"
        "geometry_msgs/Transform transform\n"
        "================================================================================\n"
        "MSG: geometry_msgs/Transform\ngeometry_msgs/Vector3 translation\n"
        "geometry_msgs/Quaternion rotation\n"
        "================================================================================\n"
        "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w\n"
        + _HEADER_DEFS
        + _VECTOR_DEFS
    ),
}
"""ros2msg schema text per message type: the type's fields, then each nested type once."""

_ENCAPSULATION: Final = b"\x00\x01\x00\x00"  # CDR, little endian


class _Cdr:
    """A CDR payload being written (alignment counted from after the encapsulation header)."""

    def __init__(self) -> None:
        self.parts: list[bytes] = []
        self.size = 0

    def _put(self, data: bytes, align: int) -> None:
        pad = -self.size % align
        if pad:
            self.parts.append(b"\x00" * pad)
        self.parts.append(data)
        self.size += pad + len(data)

    def uint32(self, value: int) -> None:
        self._put(struct.pack("<I", value), 4)

    def stamp(self, t_ns: int) -> None:
        sec, nanosec = divmod(t_ns, 1_000_000_000)
        self._put(struct.pack("<iI", sec, nanosec), 4)

    def string(self, text: str) -> None:
        data = text.encode() + b"\x00"
        self._put(struct.pack("<I", len(data)) + data, 4)

    def doubles(self, values: Sequence[float]) -> None:
        self._put(struct.pack(f"<{len(values)}d", *values), 8)

    def double_sequence(self, values: Sequence[float]) -> None:
        self.uint32(len(values))
        if len(values):
            self.doubles(values)

    def bytes(self) -> bytes:
        return _ENCAPSULATION + b"".join(self.parts)


def joint_state(t_ns: int, names: Sequence[str], q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> bytes:
    """A ``sensor_msgs/msg/JointState`` (``frame_id`` empty, as for joint states)."""
    cdr = _Cdr()
    cdr.stamp(t_ns)
    cdr.string("")
    cdr.uint32(len(names))
    for name in names:
        cdr.string(name)
    for values in (q, qd, tau):
        cdr.double_sequence(values.tolist())
    return cdr.bytes()


def wrench_stamped(t_ns: int, frame: str, wrench: np.ndarray) -> bytes:
    """A ``geometry_msgs/msg/WrenchStamped``: force [N] then torque [N m]."""
    cdr = _Cdr()
    cdr.stamp(t_ns)
    cdr.string(frame)
    cdr.doubles(wrench.tolist())
    return cdr.bytes()


def tf_message(t_ns: int, parent: str, children: Sequence[str], poses: np.ndarray) -> bytes:
    """A ``tf2_msgs/msg/TFMessage``.

    Args:
        t_ns: Time of the poses [ns].
        parent: Frame the poses are in.
        children: The frames.
        poses: Per frame, translation x y z [m] and rotation x y z w. # (n, 7)
    """
    cdr = _Cdr()
    cdr.uint32(len(children))
    for child, pose in zip(children, poses.tolist(), strict=True):
        cdr.stamp(t_ns)
        cdr.string(parent)
        cdr.string(child)
        cdr.doubles(pose)
    return cdr.bytes()
