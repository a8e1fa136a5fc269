"""The ``MOVING`` obstacles carried to where they are, every servo tick, compiled (numba).

:meth:`cosmos.obstacles.scene.ObstacleScene.update` puts each moving obstacle's
geom at ``p(t) = p_0 + v (t - t_added)`` (its straight-line motion, as the field
takes it: :meth:`cosmos.obstacles.obstacle.Obstacle.position_at`) in the plant's
``geom_pos``, which MuJoCo places world geoms from every step. One call for all
of them, where a Python loop cost the tick about half a microsecond; called through its declared
signature's entry point (:func:`entry`), without numba's dispatch, which types every argument
(0.13 us of the 0.29 us a call).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numba.core import types

from cosmos.jit import kernel

FloatArray = np.ndarray

# ``motions`` (k, MOTION): per moving obstacle its geom's id, its position when added [m], its
# velocity [m/s] and the time it was added [s].
MOTION_GEOM, MOTION_POSITION, MOTION_VELOCITY, MOTION_ADDED_S = 0, 1, 4, 7
MOTION = 8


_ROWS = types.Array(types.float64, 2, "C")


@kernel(types.void(_ROWS, _ROWS, types.float64))
def move_into(geom_pos: FloatArray, motions: FloatArray, t_s: float) -> None:
    """Each moving obstacle's geom to where it is at simulated time ``t_s`` [s] (``geom_pos`` rows)."""
    for k in range(motions.shape[0]):
        motion = motions[k]
        row = geom_pos[int(motion[MOTION_GEOM])]
        dt = t_s - motion[MOTION_ADDED_S]
        for i in range(3):
            row[i] = motion[MOTION_POSITION + i] + motion[MOTION_VELOCITY + i] * dt


def entry() -> Callable[[FloatArray, FloatArray, float], None]:
    """:func:`move_into` compiled (or loaded) for its declared types, called without numba's dispatch.

    Its arguments must be of those types: C-contiguous float64 matrices (MuJoCo's ``geom_pos``
    and the packed motions) and a float.
    """
    move_into.compile_declared()
    (declared,) = move_into.signatures
    return move_into.overloads[declared].entry_point
