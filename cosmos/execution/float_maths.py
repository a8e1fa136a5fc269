"""Small vector sums the monitor and the executor do every tick, in Python floats (no array's overhead)."""

from __future__ import annotations

import math

import numpy as np

FloatArray = np.ndarray


def norm3(v: FloatArray) -> float:
    """The length of a 3-vector."""
    x, y, z = v.tolist()
    return math.sqrt(x * x + y * y + z * z)


def length(v: FloatArray) -> float:
    """``np.linalg.norm`` of a vector, to the last bit (its very sum), without its checks (microseconds)."""
    return math.sqrt(v.dot(v))


def block_diagonal(rotation: FloatArray) -> FloatArray:
    """``np.kron(np.eye(2), rotation)`` (bit for bit, its zeros' signs too) without its 30 us. # (6, 6)."""
    out = np.empty((6, 6))
    out[:3, :3] = out[3:, 3:] = rotation
    out[:3, 3:] = out[3:, :3] = 0.0 * rotation
    return out


def distance_to_point(position: FloatArray, point: tuple[float, ...]) -> float:
    """The distance from ``position`` (3,) to ``point``, in floats (cheaper than an array's norm)."""
    x, y, z = position.tolist()
    return math.sqrt((x - point[0]) ** 2 + (y - point[1]) ** 2 + (z - point[2]) ** 2)
