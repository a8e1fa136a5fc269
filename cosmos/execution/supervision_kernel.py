"""The protective stops' slower looks (every 4th tick), compiled (numba): the drives and the path in one call.

In Python floats the drives' look (a torque as large as the lowest limit?) and the path's
(:func:`cosmos.execution.expected.off_line`) cost 2 to 3 us every 4th tick, most of the
supervision's cost per tick; here one call, with the same arithmetic in the same order.
"""

from __future__ import annotations

import math

import numpy as np
from numba.core import types

from cosmos.jit import kernel

FloatArray = np.ndarray

LINE_START, LINE_DIRECTION, LINE_LENGTH2, LINE_SIZE = 0, 3, 6, 7
"""The commanded line's layout in its array: its start, its direction (end - start), the
direction's squared length."""


_VECTOR = types.Array(types.float64, 1, "A", readonly=True)


@kernel(
    types.Tuple((types.boolean, types.float64))(
        _VECTOR,
        types.float64,
        _VECTOR,
        _VECTOR,
        types.Array(types.float64, 2, "A", readonly=True),
        types.boolean,
    )
)
def slow_look(
    torque: FloatArray,
    lowest_limit: float,
    position: FloatArray,
    line: FloatArray,
    axes: FloatArray,
    look_at_path: bool,
) -> tuple[bool, float]:
    """Whether a drive's torque is as large as ``lowest_limit``, and the tool's distance from its line.

    Args:
        torque: The drives' torques [N m]. # (n,)
        lowest_limit: The lowest of the drives' limits (at the saturation fraction) [N m].
        position: The measured tool point, world [m]. # (3,)
        line: The commanded line (:data:`LINE_START` ...). # (7,)
        axes: The world directions the distance is measured along, one a row. # (k, 3)
        look_at_path: Whether to measure it (else the distance is 0).

    Returns:
        ``(at_lowest, off_m)``: some ``|tau| >= lowest_limit``; the distance from the line
        on ``axes`` as :func:`cosmos.execution.expected.off_line` computes it [m].
    """
    at_lowest = False
    for i in range(torque.shape[0]):
        tau = torque[i]
        if tau >= lowest_limit or -tau >= lowest_limit:
            at_lowest = True
            break
    if not look_at_path:
        return at_lowest, 0.0
    dx, dy, dz = line[LINE_DIRECTION], line[LINE_DIRECTION + 1], line[LINE_DIRECTION + 2]
    rx = position[0] - line[LINE_START]
    ry = position[1] - line[LINE_START + 1]
    rz = position[2] - line[LINE_START + 2]
    length2 = line[LINE_LENGTH2]
    if length2 > 1e-12:
        along = (rx * dx + ry * dy + rz * dz) / length2
        along = 0.0 if along < 0.0 else along  # max(0.0, along), as Python's max takes it
        along = along if along < 1.0 else 1.0  # min(1.0, along)
        rx, ry, rz = rx - along * dx, ry - along * dy, rz - along * dz
    total = 0.0
    for k in range(axes.shape[0]):
        component = rx * axes[k, 0] + ry * axes[k, 1] + rz * axes[k, 2]
        total += component * component
    return at_lowest, math.sqrt(total)
