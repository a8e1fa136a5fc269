"""One parameter evaluation from Pinocchio's ``computeAllTerms``, compiled (numba).

``computeAllTerms`` fills, in its data, the joint-space inertia A (upper
triangle), the nonlinear effects ``nle = b + g``, the joints' Jacobians and
their time variation at the world origin, the centre-of-mass Jacobian and the
joint placements. The parameter level holds those arrays as views and this
kernel turns them, in one call, into everything an evaluation holds, packed in
one flat array (offsets below):

- the tool point's pose and its Jacobian, world axes (``J_p = J_o + J_w x p``
  column by column: the velocity of the point ``p`` is ``v_o + w x p``);
- A made whole and A^-1 (Cholesky);
- ``g = -m J_com^T g_vec`` (the gradient of the potential energy), ``b = nle - g``
  (eq. 12) and ``h = Jdot qd`` of eq. 14: the classical acceleration of the
  tool point at zero joint acceleration, ``a_o + alpha x p + w x v_p``;
- the wrist sensor's orientation and its offsets to the tool point and the
  tool's centre of mass (constant on link 6, so constant in tool axes);
- the smallest distance of a joint to its limits (the joint-limit field of
  section 6 is zero beyond its range of influence).

``tests/runtime/test_parameter_kernel.py`` checks the result against
Pinocchio's own frame, Jacobian, gravity and classical-acceleration functions.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel
from cosmos.runtime.kernels.linear import (
    NEW_VECTOR,
    VECTOR,
    matmul,
    matvec,
    scaled_into,
    scaled_matrix_into,
)

FloatArray = np.ndarray

# Offsets in an evaluation's values (one flat array): the task-space entries first, at fixed
# offsets, then those whose size is the arm's number of joints n (offsets from the functions below).
POSITION = 0  # (3,) tool point, world
ROTATION_TOOL = 3  # (3, 3) tool axes in world
ROTATION_SENSOR = 12  # (3, 3) sensor axes in world
SENSOR_TO_TOOL = 21  # (3,) tool point minus sensor origin, world
SENSOR_TO_COM = 24  # (3,) tool centre of mass minus sensor origin, world
JDOT_QDOT = 27  # (6,) h
LIMIT_MARGIN = 33  # () smallest distance of a joint to a limit, [rad]
Q = 34  # (n,) joint positions


@kernel
def jacobian_at(n: int) -> int:
    """Offset of the (6, n) tool-point Jacobian, rows [linear; angular], world axes."""
    return Q + n


@kernel
def inertia_at(n: int) -> int:
    """Offset of A, (n, n)."""
    return Q + 7 * n


@kernel
def inertia_inv_at(n: int) -> int:
    """Offset of A^-1, (n, n)."""
    return Q + 7 * n + n * n


@kernel
def gravity_at(n: int) -> int:
    """Offset of g, (n,)."""
    return Q + 7 * n + 2 * n * n


@kernel
def bias_at(n: int) -> int:
    """Offset of b, (n,)."""
    return Q + 8 * n + 2 * n * n


@kernel
def size(n: int) -> int:
    """Length of an evaluation's values for an arm of n joints."""
    return Q + 9 * n + 2 * n * n


# Offsets in the constants (one flat array, fixed for a robot and tool).
C_ROTATION_TOOL_IN_JOINT = 0  # (3, 3) tool frame in the last joint's frame
C_TOOL_IN_JOINT = 9  # (3,)
C_ROTATION_SENSOR_TO_TOOL = 12  # (3, 3)
C_TOOL_FROM_SENSOR = 21  # (3,) tool axes
C_COM_FROM_SENSOR = 24  # (3,) tool axes
C_WEIGHT = 27  # (3,) -m g_vec: the whole arm's weight, reversed, [N]
C_Q_LOWER = 30  # (n,), then the upper limits (n,): 30 + 2 n constants in all


@kernel
def symmetric_from_upper(upper: FloatArray) -> FloatArray:
    """The symmetric matrix whose upper triangle is given (Pinocchio fills only that). # (n, n)."""
    n = upper.shape[0]
    full = np.empty((n, n))
    for i in range(n):
        for j in range(i, n):
            full[i, j] = full[j, i] = upper[i, j]
    return full


@kernel
def spd_inverse_into(out: FloatArray, a: FloatArray) -> bool:
    """``out = a^-1`` for a symmetric positive definite ``a``, by Cholesky (``a = L L^T``). # (n, n).

    Returns:
        False, with ``out`` unspecified, if a pivot is not positive (``a`` is not positive definite).
    """
    n = a.shape[0]
    lower = np.zeros((n, n))
    for j in range(n):
        s = a[j, j]
        for k in range(j):
            s -= lower[j, k] * lower[j, k]
        if not s > 0.0:  # also NaN
            return False
        lower[j, j] = math.sqrt(s)
        for i in range(j + 1, n):
            s = a[i, j]
            for k in range(j):
                s -= lower[i, k] * lower[j, k]
            lower[i, j] = s / lower[j, j]
    inv_lower = np.zeros((n, n))  # L^-1, lower triangular
    for j in range(n):
        inv_lower[j, j] = 1.0 / lower[j, j]
        for i in range(j + 1, n):
            s = 0.0
            for k in range(j, i):
                s -= lower[i, k] * inv_lower[k, j]
            inv_lower[i, j] = s / lower[i, i]
    for i in range(n):  # a^-1 = L^-T L^-1
        for j in range(i, n):
            s = 0.0
            for k in range(j, n):
                s += inv_lower[k, i] * inv_lower[k, j]
            out[i, j] = out[j, i] = s
    return True


@kernel(NEW_VECTOR(VECTOR, VECTOR))
def _cross(a: FloatArray, b: FloatArray) -> FloatArray:
    return np.array((a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]))


@kernel
def evaluation_values(
    q: FloatArray,
    qd: FloatArray,
    inertia_upper: FloatArray,
    nle: FloatArray,
    joint_jacobian: FloatArray,
    joint_jacobian_dot: FloatArray,
    com_jacobian: FloatArray,
    joint_rotation: FloatArray,
    joint_translation: FloatArray,
    constants: FloatArray,
) -> FloatArray:
    """An evaluation's values (offsets in this module) from ``computeAllTerms``' outputs. # (size(n),).

    Args:
        q: Joint positions, in [rad]. # (n,)
        qd: Joint velocities, in [rad/s]. # (n,)
        inertia_upper: ``data.M``, A with its upper triangle filled. # (n, n)
        nle: ``data.nle``: b + g, in [N m]. # (n,)
        joint_jacobian: ``data.J``: the joints' motion at the world origin, world axes. # (6, n)
        joint_jacobian_dot: ``data.dJ``, its time variation. # (6, n)
        com_jacobian: ``data.Jcom``. # (3, n)
        joint_rotation: The last joint's orientation in world (``data.oMi[n]``). # (3, 3)
        joint_translation: The last joint's origin in world, in [m]. # (3,)
        constants: The robot's and tool's constants (``C_*`` offsets). # (30 + 2 n,)
    """
    n = q.shape[0]
    values = np.empty(size(n))
    scaled_into(values[Q : Q + n], q, 1.0)
    tool_rotation = matmul(
        joint_rotation, constants[C_ROTATION_TOOL_IN_JOINT : C_ROTATION_TOOL_IN_JOINT + 9].reshape((3, 3))
    )
    p = matvec(joint_rotation, constants[C_TOOL_IN_JOINT : C_TOOL_IN_JOINT + 3])
    for i in range(3):
        p[i] += joint_translation[i]
    scaled_into(values[POSITION : POSITION + 3], p, 1.0)
    scaled_into(values[ROTATION_TOOL : ROTATION_TOOL + 9], tool_rotation.ravel(), 1.0)
    sensor_rotation = matmul(
        tool_rotation, constants[C_ROTATION_SENSOR_TO_TOOL : C_ROTATION_SENSOR_TO_TOOL + 9].reshape((3, 3))
    )
    scaled_into(values[ROTATION_SENSOR : ROTATION_SENSOR + 9], sensor_rotation.ravel(), 1.0)
    scaled_into(
        values[SENSOR_TO_TOOL : SENSOR_TO_TOOL + 3],
        matvec(tool_rotation, constants[C_TOOL_FROM_SENSOR : C_TOOL_FROM_SENSOR + 3]),
        1.0,
    )
    scaled_into(
        values[SENSOR_TO_COM : SENSOR_TO_COM + 3],
        matvec(tool_rotation, constants[C_COM_FROM_SENSOR : C_COM_FROM_SENSOR + 3]),
        1.0,
    )

    jacobian_start = jacobian_at(n)
    jacobian = values[jacobian_start : jacobian_start + 6 * n].reshape((6, n))
    v_origin = np.zeros(6)  # J qd at the world origin: (v_o, w)
    a_origin = np.zeros(6)  # Jdot qd there: (a_o, alpha)
    for k in range(n):
        angular = joint_jacobian[3:, k]
        moment = _cross(angular, p)
        for i in range(3):
            jacobian[i, k] = joint_jacobian[i, k] + moment[i]
            jacobian[3 + i, k] = angular[i]
        for i in range(6):
            v_origin[i] += joint_jacobian[i, k] * qd[k]
            a_origin[i] += joint_jacobian_dot[i, k] * qd[k]
    w, alpha = v_origin[3:], a_origin[3:]
    w_p = _cross(w, p)
    v_point = np.empty(3)
    for i in range(3):
        v_point[i] = v_origin[i] + w_p[i]
    alpha_p, w_v = _cross(alpha, p), _cross(w, v_point)
    for i in range(3):
        values[JDOT_QDOT + i] = a_origin[i] + alpha_p[i] + w_v[i]
        values[JDOT_QDOT + 3 + i] = alpha[i]

    inertia_start, inverse_start = inertia_at(n), inertia_inv_at(n)
    inertia = values[inertia_start : inertia_start + n * n].reshape((n, n))
    scaled_matrix_into(inertia, symmetric_from_upper(inertia_upper), 1.0)
    if not spd_inverse_into(values[inverse_start : inverse_start + n * n].reshape((n, n)), inertia):
        values[inverse_start : inverse_start + n * n] = np.nan  # only for a non-finite q
    weight = constants[C_WEIGHT : C_WEIGHT + 3]
    margin = math.inf
    gravity, bias = gravity_at(n), bias_at(n)
    for k in range(n):
        g = com_jacobian[0, k] * weight[0] + com_jacobian[1, k] * weight[1] + com_jacobian[2, k] * weight[2]
        values[gravity + k] = g
        values[bias + k] = nle[k] - g
        margin = min(margin, q[k] - constants[C_Q_LOWER + k], constants[C_Q_LOWER + n + k] - q[k])
    values[LIMIT_MARGIN] = margin
    return values
