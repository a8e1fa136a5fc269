"""The rotation plan's inverse-kinematics step at a point of its path, compiled (numba).

:func:`cosmos.runtime.rotation_plan.plan_rotation` follows a goal motion's path in 46 to 250
points, two damped least-squares steps a point; in NumPy each step cost 15 to 25 us of small
products and a LAPACK call (the plan 1.2 to 2.6 ms a goal motion, in the executor's time between
two ticks). Here the step after Pinocchio's Jacobian is one call: the path's pose at ``s``, the
pose error (translation, ``log(R_d R^T)``), and ``q += J^T (J J^T + d I)^-1 e``.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel
from cosmos.osc.orientation import SMALL_ANGLE_RAD
from cosmos.runtime.kernels.parameter import rotation_log

FloatArray = np.ndarray


@kernel
def path_step_into(
    jacobian: FloatArray,
    pose: FloatArray,
    s: float,
    position: FloatArray,
    displacement: FloatArray,
    rotation_vector: FloatArray,
    rotation: FloatArray,
    q: FloatArray,
    damping: float,
) -> None:
    """One damped least-squares step of ``q`` toward the path's pose at ``s`` (``q`` rewritten).

    The path's pose at ``s``: the tool point ``position + s displacement``, the orientation
    ``exp(s rotation_vector) rotation`` (:func:`cosmos.osc.orientation.so3_exp`, Rodrigues).

    Args:
        jacobian: The tool frame's Jacobian at ``q``, world-aligned (linear rows first). # (6, n)
        pose: The tool frame's pose at ``q``, homogeneous. # (4, 4)
        s: Where on the path, 0 (its start) to 1 (its end).
        position: The path's start point, world, in [m]. # (3,)
        displacement: Its end minus its start, in [m]. # (3,)
        rotation_vector: The rotation it makes, world axes, in [rad]. # (3,)
        rotation: The orientation it starts from, tool to world. # (3, 3)
        q: The configuration, in [rad], rewritten. # (n,)
        damping: Added to the diagonal of ``J J^T``.
    """
    x, y, z = s * rotation_vector[0], s * rotation_vector[1], s * rotation_vector[2]
    t2 = x * x + y * y + z * z
    if t2 < SMALL_ANGLE_RAD * SMALL_ANGLE_RAD:
        a = 1.0 - t2 / 6.0
        b = 0.5 - t2 / 24.0
    else:
        t = math.sqrt(t2)
        a = math.sin(t) / t
        b = (1.0 - math.cos(t)) / t2
    turn = np.empty((3, 3))
    turn[0, 0], turn[0, 1], turn[0, 2] = 1.0 - b * (y * y + z * z), b * x * y - a * z, b * x * z + a * y
    turn[1, 0], turn[1, 1], turn[1, 2] = b * x * y + a * z, 1.0 - b * (x * x + z * z), b * y * z - a * x
    turn[2, 0], turn[2, 1], turn[2, 2] = b * x * z - a * y, b * y * z + a * x, 1.0 - b * (x * x + y * y)
    target = np.zeros((3, 3))  # exp(s phi) R
    for i in range(3):
        for j in range(3):
            for k in range(3):
                target[i, j] += turn[i, k] * rotation[k, j]
    relative = np.zeros((3, 3))  # R_d R^T
    for i in range(3):
        for j in range(3):
            for k in range(3):
                relative[i, j] += target[i, k] * pose[j, k]
    error = np.empty(6)
    for i in range(3):
        error[i] = position[i] + s * displacement[i] - pose[i, 3]
    log = rotation_log(relative)
    error[3], error[4], error[5] = log[0], log[1], log[2]
    n = q.shape[0]
    # J J^T + d I, then Cholesky (it is symmetric positive definite) and the two triangular solves.
    m = np.zeros((6, 6))
    for i in range(6):
        for j in range(i + 1):
            total = 0.0
            for k in range(n):
                total += jacobian[i, k] * jacobian[j, k]
            m[i, j] = total
        m[i, i] += damping
    low = np.zeros((6, 6))
    for j in range(6):
        diagonal = m[j, j]
        for k in range(j):
            diagonal -= low[j, k] * low[j, k]
        low[j, j] = math.sqrt(diagonal)
        for i in range(j + 1, 6):
            total = m[i, j]
            for k in range(j):
                total -= low[i, k] * low[j, k]
            low[i, j] = total / low[j, j]
    solved = np.empty(6)
    for i in range(6):
        total = error[i]
        for k in range(i):
            total -= low[i, k] * solved[k]
        solved[i] = total / low[i, i]
    for i in range(5, -1, -1):
        total = solved[i]
        for k in range(i + 1, 6):
            total -= low[k, i] * solved[k]
        solved[i] = total / low[i, i]
    for k in range(n):
        total = 0.0
        for i in range(6):
            total += jacobian[i, k] * solved[i]
        q[k] += total
