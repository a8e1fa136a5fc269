"""The generalised selection matrices (eq. 17-18, Figure 2).

A task frame ``T`` (``rotation_task_to_world = R``) says along which of its axes
the end effector is motion-controlled and along which force-controlled.
``S = diag(motion_axes)`` in the task frame becomes, in world axes, the
generalised selection matrix (Khatib 1987, ``Omega = R^T S R`` written for a
frame-to-world R)::

    Omega     = blkdiag(R S_f R^T, R S_m R^T)   # (6, 6) motion-controlled subspace
    Omega_bar = I - Omega                       # (6, 6) force-controlled subspace

``S_f`` holds the three translational flags, ``S_m`` the three rotational ones.
Both matrices are symmetric orthogonal projectors and ``Omega Omega_bar = 0``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from cosmos.osc._types import FloatArray


class Selection(NamedTuple):
    """The pair of complementary world-axes projectors of Figure 2."""

    omega: FloatArray  # (6, 6) motion-controlled directions
    omega_bar: FloatArray  # (6, 6) force-controlled directions


def task_diagonal_to_world(values_task: FloatArray, rotation_task_to_world: FloatArray) -> FloatArray:
    """``blkdiag(R diag(v[:3]) R^T, R diag(v[3:]) R^T)``: a per-task-axis diagonal in world axes.

    Used for selection matrices, and for per-axis gains (stiffness, damping) given
    along the task frame's axes.

    Args:
        values_task: One value per task axis: x y z then rx ry rz. # (6,)
        rotation_task_to_world: The task frame's axes in world, as columns. # (3, 3)

    Returns:
        The world-axes matrix. # (6, 6)
    """
    r = rotation_task_to_world
    out = np.zeros((6, 6))
    out[:3, :3] = (r * values_task[:3]).dot(r.T)
    out[3:, 3:] = (r * values_task[3:]).dot(r.T)
    return out


def selection(motion_axes: Sequence[bool] | FloatArray, rotation_task_to_world: FloatArray) -> Selection:
    """Selection matrices Omega and Omega_bar in world axes for a task frame (Figure 2).

    Args:
        motion_axes: Per task axis (x y z rx ry rz), True where motion-controlled and
            False where force-controlled. # (6,)
        rotation_task_to_world: The task frame's axes in world, as columns. # (3, 3)

    Returns:
        ``(Omega, Omega_bar)`` with ``Omega + Omega_bar = I``.

    Raises:
        ValueError: If motion_axes does not have six entries.
    """
    flags = np.asarray(motion_axes, dtype=float).reshape(-1)
    if flags.shape != (6,):
        raise ValueError(f"selection: motion_axes needs 6 entries (x y z rx ry rz), got {flags.size}")
    omega = task_diagonal_to_world(flags, rotation_task_to_world)
    return Selection(omega, np.eye(6) - omega)
