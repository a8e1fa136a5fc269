"""Rotation helpers for the language and the plan, on top of :mod:`cosmos.osc.orientation`.

Rotation matrices map frame coordinates to world coordinates: the columns of
``rotation_frame_to_world`` are the frame's x, y, z axes expressed in the world.
The plan holds read-only arrays, so these helpers return read-only copies.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from cosmos.osc import orientation

FloatArray = NDArray[np.float64]


def readonly(values: object) -> FloatArray:
    """A float64 copy of ``values`` that cannot be written to (-0.0 becomes 0.0)."""
    array: FloatArray = np.add(values, 0.0, dtype=np.float64)  # type: ignore[call-overload]  # -0.0 + 0.0 is 0.0
    array.flags.writeable = False
    return array


IDENTITY = readonly(np.eye(3))


def rpy_to_matrix(roll_rad: float, pitch_rad: float, yaw_rad: float) -> FloatArray:
    """Roll, pitch, yaw about the fixed world axes x, then y, then z (read-only).

    R = Rz(yaw) @ Ry(pitch) @ Rx(roll); ``RPY (180 deg, 0, 0)`` turns z down.
    """
    return readonly(orientation.rpy_to_matrix(roll_rad, pitch_rad, yaw_rad))


def signed_column(rotation: FloatArray, column: int, sign: int) -> tuple[FloatArray, tuple[float, ...]]:
    """``rotation[:, column] * sign`` as a read-only (3,) array and as a tuple of floats."""
    array = readonly(rotation[:, column] * sign)
    return array, tuple(array.tolist())


def matrix_to_quaternion(rotation: FloatArray) -> tuple[float, float, float, float]:
    """Unit quaternion (w, x, y, z) of a rotation matrix, with w >= 0, as floats."""
    w, x, y, z = orientation.matrix_to_quat(np.asarray(rotation, dtype=np.float64))
    return (float(w), float(x), float(y), float(z))
