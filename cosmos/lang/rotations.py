"""Rotation helpers for the compiler, on top of :mod:`cosmos.osc.orientation`.

Rotation matrices map frame coordinates to world coordinates: the columns of
``rotation_frame_to_world`` are the frame's x, y, z axes expressed in the world.
The plan holds read-only arrays, so these helpers return read-only copies.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from cosmos.osc import orientation

FloatArray = NDArray[np.float64]


_add = np.add
_FLOAT64 = np.float64


def readonly(values: object) -> FloatArray:
    """A float64 copy of ``values`` that cannot be written to."""
    array: FloatArray = _add(values, 0.0, dtype=_FLOAT64)  # type: ignore[call-overload]  # new; -0.0 + 0.0 is 0.0
    array.flags.writeable = False
    return array


IDENTITY = readonly(np.eye(3))

_SHARED: dict[tuple[float, ...], FloatArray] = {}
"""Read-only arrays made from tuples of numbers, by the tuple (equal tuples, equal arrays)."""


def readonly_of(values: tuple[float, ...]) -> FloatArray:
    """``readonly(values)``, one array shared by equal tuples (it cannot be written to).

    A long program repeats its vectors (offsets, setpoints); each array is made once.
    """
    array = _SHARED.get(values)
    if array is None:
        array = readonly(values)
        if len(_SHARED) < 4096:
            _SHARED[values] = array
    return array


_RPY_SEEN: dict[tuple[float, float, float], FloatArray] = {}
"""Rotations made so far, by their angle triple [rad] (each read-only, so shared)."""


def rpy_to_matrix(roll_rad: float, pitch_rad: float, yaw_rad: float) -> FloatArray:
    """Roll, pitch, yaw about the fixed world axes x, then y, then z (read-only).

    R = Rz(yaw) @ Ry(pitch) @ Rx(roll); ``RPY (180 deg, 0, 0)`` turns z down.
    Equal angle triples share one array.
    """
    key = (roll_rad, pitch_rad, yaw_rad)
    rotation = _RPY_SEEN.get(key)
    if rotation is None:
        rotation = readonly(orientation.rpy_to_matrix(roll_rad, pitch_rad, yaw_rad))
        if len(_RPY_SEEN) < 1024:
            _RPY_SEEN[key] = rotation
    return rotation


_COLUMNS_SEEN: dict[tuple[bytes, int, int], tuple[FloatArray, tuple[float, ...]]] = {}
"""Signed rotation columns made so far, by (rotation bytes, column, sign)."""


def signed_column(rotation: FloatArray, column: int, sign: int) -> tuple[FloatArray, tuple[float, ...]]:
    """``rotation[:, column] * sign`` as a read-only (3,) array and as a tuple of floats.

    Equal rotations share the result (a program reads a few frames' axes again and again).
    """
    key = (rotation.tobytes(), column, sign)
    found = _COLUMNS_SEEN.get(key)
    if found is None:
        array = readonly(rotation[:, column] * sign)
        found = (array, tuple(array.tolist()))
        if len(_COLUMNS_SEEN) < 1024:
            _COLUMNS_SEEN[key] = found
    return found


def matrix_to_quaternion(rotation: FloatArray) -> tuple[float, float, float, float]:
    """Unit quaternion (w, x, y, z) of a rotation matrix, with w >= 0, as floats."""
    w, x, y, z = orientation.matrix_to_quat(np.asarray(rotation, dtype=np.float64))
    return (float(w), float(x), float(y), float(z))
