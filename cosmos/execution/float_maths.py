"""Small vector sums the monitor and the executor do every tick, in Python floats (no array's overhead)."""

from __future__ import annotations

import math

import numpy as np

from cosmos.osc.orientation import _log_rows

FloatArray = np.ndarray


def norm3(v: FloatArray) -> float:
    """The length of a 3-vector."""
    x, y, z = v.tolist()
    return math.sqrt(x * x + y * y + z * z)


def length(v: FloatArray) -> float:
    """``np.linalg.norm`` of a vector, to the last bit (its very sum), without its checks (microseconds)."""
    return math.sqrt(v.dot(v))


def distance_to_point(position: FloatArray, point: tuple[float, ...]) -> float:
    """The distance from ``position`` (3,) to ``point``, in floats (cheaper than an array's norm)."""
    x, y, z = position.tolist()
    return math.sqrt((x - point[0]) ** 2 + (y - point[1]) ** 2 + (z - point[2]) ** 2)


def length_along(rows: list[tuple[float, ...]], x: float, y: float, z: float) -> float:
    """The length of the vector ``(x, y, z)`` along the orthonormal ``rows``."""
    total = 0.0
    for ax, ay, az in rows:
        component = ax * x + ay * y + az * z
        total += component * component
    return math.sqrt(total)


def pose_error(
    position: list[float],
    rotation: list[list[float]],
    goal: tuple[float, ...],
    goal_rows: tuple[tuple[float, ...], ...],
) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """The tool point minus the goal's, and the rotation vector of ``R R_goal^T`` (world axes).

    :func:`cosmos.execution.arrival.goal_error` in floats (3 us where its arrays cost 10-25 us);
    ``rotation`` and ``goal_rows`` are the two orientations' rows.
    """
    (a0, a1, a2), (b0, b1, b2), (c0, c1, c2) = rotation
    (u0, u1, u2), (v0, v1, v2), (w0, w1, w2) = goal_rows
    turned = _log_rows(
        (
            (a0 * u0 + a1 * u1 + a2 * u2, a0 * v0 + a1 * v1 + a2 * v2, a0 * w0 + a1 * w1 + a2 * w2),
            (b0 * u0 + b1 * u1 + b2 * u2, b0 * v0 + b1 * v1 + b2 * v2, b0 * w0 + b1 * w1 + b2 * w2),
            (c0 * u0 + c1 * u1 + c2 * u2, c0 * v0 + c1 * v1 + c2 * v2, c0 * w0 + c1 * w1 + c2 * w2),
        )
    )
    return (position[0] - goal[0], position[1] - goal[1], position[2] - goal[2]), turned
