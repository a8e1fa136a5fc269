"""What the task gives up near a joint limit and near a singular direction, compiled (numba).

Folded by :func:`cosmos.runtime.kernels.parameter.refold` at each parameter
evaluation. A joint driven into a limit leaves the task: on the six-joint arm
the task gives up what needs it (:func:`cosmos.osc.limits.joint_limit_task_projection`,
a factor of the task projection, as section 5 removes a singular direction);
on a redundant arm the task goes on without it (the Jacobian ``J N_c`` of
:func:`cosmos.osc.limits.joint_limit_constraint`) and gives up only what the
other joints cannot do. ``tests/runtime/test_joint_limit_projection.py`` compares
these with their references.
"""

from __future__ import annotations

import numpy as np

from cosmos.jit import kernel
from cosmos.osc.dynamics import TRANSLATION_GIVE_UP
from cosmos.runtime.kernels.linear import matmul, matvec

FloatArray = np.ndarray

LIMITS_OFFSET = 6
"""refold's constants: k_vf, xi_q, look-ahead, section 5's three; then (optional) the joints'
lower and upper limits (n each) and the joint-limit projection's two margins (ServoLevel)."""


@kernel
def remove_direction(projection: FloatArray, wrench: FloatArray, weight: float) -> None:
    """``projection <- (I - g d u^T / (u^T d)) projection``, ``d`` u with its translation weighted."""
    d = wrench.copy()
    for i in range(3):
        d[i] *= TRANSLATION_GIVE_UP
    ud = 0.0
    for i in range(6):
        ud += wrench[i] * d[i]
    if not ud > 0.0:
        return
    row = np.zeros(6)  # u^T projection
    for k in range(6):
        for i in range(6):
            row[k] += wrench[i] * projection[i, k]
    for i in range(6):
        factor = weight * d[i] / ud
        for k in range(6):
            projection[i, k] -= factor * row[k]


@kernel
def _limit_weight(
    q: float, lower: float, upper: float, rate: float, margin_rad: float, whole_rad: float
) -> float:
    """How wholly a joint turning at ``rate`` toward one limit counts as at it: 0 outside ``margin_rad``."""
    distance = q - lower if rate < 0.0 else upper - q
    if rate == 0.0 or distance >= margin_rad:
        return 0.0
    return min(1.0, (margin_rad - distance) / (margin_rad - whole_rad))


@kernel
def _near_a_limit(q: FloatArray, q_lower: FloatArray, q_upper: FloatArray, margin_rad: float) -> bool:
    """Whether a joint is within ``margin_rad`` of either limit (else nothing to compute)."""
    for i in range(q.shape[0]):
        if q[i] - q_lower[i] < margin_rad or q_upper[i] - q[i] < margin_rad:
            return True
    return False


@kernel
def joint_limit_projection_into(
    out: FloatArray,
    jacobian: FloatArray,
    q: FloatArray,
    q_lower: FloatArray,
    q_upper: FloatArray,
    goal_direction: FloatArray,
    margin_rad: float,
    whole_rad: float,
    weights: FloatArray,
) -> None:
    """:func:`cosmos.osc.limits.joint_limit_task_projection` into ``out`` (the identity there). # (6, 6).

    The six-joint arm's (J square, J^-1 = Jbar). Each joint's weight g goes to ``weights``. # (6,)
    """
    if not _near_a_limit(q, q_lower, q_upper, margin_rad):
        return
    square = jacobian.copy()  # writable: numba's det and inv compile once
    if abs(np.linalg.det(square)) < 1e-12:
        return
    inverse = np.linalg.inv(square)
    rates = matvec(inverse, goal_direction)
    for i in range(6):
        weight = _limit_weight(q[i], q_lower[i], q_upper[i], rates[i], margin_rad, whole_rad)
        weights[i] = weight
        if weight > 0.0:
            remove_direction(out, inverse[i, :].copy(), weight)


@kernel
def joint_limit_constraint_into(
    out: FloatArray,
    inertia_inv: FloatArray,
    jacobian: FloatArray,
    q: FloatArray,
    q_lower: FloatArray,
    q_upper: FloatArray,
    goal_direction: FloatArray,
    margin_rad: float,
    whole_rad: float,
) -> bool:
    """:func:`cosmos.osc.limits.joint_limit_constraint`'s ``N_c`` into ``out`` (the identity there). # (n, n).

    Returns:
        Whether a joint is constrained (``out`` differs from the identity).
    """
    n = q.shape[0]
    if not _near_a_limit(q, q_lower, q_upper, margin_rad):
        return False
    a_inv_jt = matmul(inertia_inv, jacobian.T.copy())
    lambda_inv = matmul(jacobian, a_inv_jt)  # eq. 27
    if abs(np.linalg.det(lambda_inv)) < 1e-24:
        return False
    rates = matvec(a_inv_jt, np.linalg.solve(lambda_inv, goal_direction))  # Jbar toward the goal
    joints = np.empty(n, dtype=np.int64)
    softness = np.empty(n)
    k = 0
    for i in range(n):
        weight = _limit_weight(q[i], q_lower[i], q_upper[i], rates[i], margin_rad, whole_rad)
        if weight > 0.0:
            joints[k] = i
            softness[k] = inertia_inv[i, i] * (1.0 - weight) / weight
            k += 1
    if k == 0:
        return False
    block = np.empty((k, k))  # J_c A^-1 J_c^T + D
    coupling = np.empty((n, k))  # A^-1 J_c^T
    for a in range(k):
        for b in range(k):
            block[a, b] = inertia_inv[joints[a], joints[b]]
        block[a, a] += softness[a]
        for i in range(n):
            coupling[i, a] = inertia_inv[i, joints[a]]
    gain = matmul(coupling, np.linalg.inv(block))  # (n, k)
    for i in range(n):
        for a in range(k):
            out[i, joints[a]] -= gain[i, a]
    return True


@kernel
def limit_task_into(
    limit_projection: FloatArray,
    given_up: FloatArray,
    inertia_inv: FloatArray,
    jacobian: FloatArray,
    q: FloatArray,
    constants: FloatArray,
    goal_direction: FloatArray,
) -> FloatArray:
    """The task's Jacobian near the joint limits of refold's ``constants`` (and its projection).

    Six joints: J, and :func:`joint_limit_projection_into` in ``limit_projection`` (the identity
    there), each joint's share given up (its weight g) in ``given_up``. More: ``J N_c``
    (:func:`joint_limit_constraint_into`). Without limits in ``constants`` (see LIMITS_OFFSET): J.
    # (6, n)
    """
    n = q.shape[0]
    task_jacobian = jacobian.copy()
    if constants.shape[0] <= LIMITS_OFFSET:
        return task_jacobian
    lower = constants[LIMITS_OFFSET : LIMITS_OFFSET + n]
    upper = constants[LIMITS_OFFSET + n : LIMITS_OFFSET + 2 * n]
    margin_rad, whole_rad = constants[LIMITS_OFFSET + 2 * n], constants[LIMITS_OFFSET + 2 * n + 1]
    if n == 6:
        joint_limit_projection_into(
            limit_projection, jacobian, q, lower, upper, goal_direction, margin_rad, whole_rad, given_up
        )
        return task_jacobian
    constraint = np.eye(n)
    if joint_limit_constraint_into(
        constraint, inertia_inv, jacobian, q, lower, upper, goal_direction, margin_rad, whole_rad
    ):
        task_jacobian = matmul(jacobian, constraint)
    return task_jacobian
