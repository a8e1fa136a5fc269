"""The parameter level's folding, compiled (numba): one call per evaluation or new selection.

From the joint-space model at one configuration it forms the operational
dynamics of eq. 27-28 (with section 5's blended inverse near singular
directions) and folds them with the selection (Figure 2) and the gains into the
matrices the servo multiplies every tick (eq. 29 and 34). The readable
reference is :func:`cosmos.osc.dynamics.operational_dynamics` (on the controlled rows:
:func:`cosmos.osc.null_space.task_lambda_inverse`), :func:`cosmos.osc.unified.servo_matrices` and
:func:`cosmos.osc.dynamics.null_space_damping`;
``tests/runtime/test_parameter_kernel.py`` checks this against them.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel
from cosmos.osc.dynamics import SINGULAR_GIVE_UP_RATE
from cosmos.osc.null_space import FREE_AXIS_INVERSE_MASS
from cosmos.osc.orientation import NEAR_PI_SIN, SMALL_ANGLE_RAD
from cosmos.runtime.kernels import evaluation as ek
from cosmos.runtime.kernels import servo as sk
from cosmos.runtime.kernels.limits import LIMITS_OFFSET as LIMITS_OFFSET  # refold's constants' layout
from cosmos.runtime.kernels.limits import limit_task_into, remove_direction
from cosmos.runtime.kernels.linear import matmul, matvec, scaled_into, scaled_matrix_into

FloatArray = np.ndarray


@kernel
def lambda_and_projection(
    lambda_inv: FloatArray,
    max_effective_mass_kg: float,
    blend_width: float,
    length_scale_m: float,
    projection: FloatArray,
) -> FloatArray:
    """Lambda from Lambda^-1, singular directions removed (section 5), and the task projection. # (6, 6).

    Mirrors :func:`cosmos.osc.dynamics.operational_dynamics` (its ``lambda_``, by
    :func:`cosmos.osc.dynamics.blend_weights`) and :func:`cosmos.osc.dynamics.singular_task_projection`.

    The plain inverse where the trace of Lambda (row-scaled: rotations count as
    masses at ``length_scale_m``) proves every effective mass is below
    ``max / (1 + blend_width)``; otherwise the eigen-directions of the scaled
    Lambda^-1 are inverted with a smoothstep weight that drops the heavy ones.
    ``projection`` receives :func:`cosmos.osc.dynamics.singular_task_projection`
    (the identity in the exact zone).
    """
    scale = np.array((1.0, 1.0, 1.0, length_scale_m, length_scale_m, length_scale_m))
    limit = max_effective_mass_kg / (1.0 + blend_width)
    lambda_ = np.empty((6, 6))
    projection[:, :] = 0.0
    for i in range(6):
        projection[i, i] = 1.0
    if ek.spd_inverse_into(lambda_, lambda_inv):  # False unless positive definite
        trace = 0.0
        for i in range(6):
            trace += lambda_[i, i] / (scale[i] * scale[i])
        if 0.0 < trace <= limit:
            return lambda_
    scaled = np.empty((6, 6))  # Lambda^-1 scaled: lambda_inv * outer(scale, scale)
    for i in range(6):
        for k in range(6):
            scaled[i, k] = lambda_inv[i, k] * (scale[i] * scale[k])
    eigenvalues, eigenvectors = np.linalg.eigh(scaled)
    s_lo = 1.0 / max_effective_mass_kg
    weights = np.empty(6)
    for i in range(6):
        u = min(max((eigenvalues[i] - s_lo) / (blend_width * s_lo), 0.0), 1.0)
        blend = u * u * (3.0 - 2.0 * u)
        weights[i] = blend / max(eigenvalues[i], s_lo)
        if blend < 1.0:  # one factor of singular_task_projection
            weight = min(1.0, SINGULAR_GIVE_UP_RATE * (1.0 - blend))
            direction = np.empty(6)
            for k in range(6):
                direction[k] = scale[k] * eigenvectors[k, i]
            remove_direction(projection, direction, weight)
    lambda_ = np.empty((6, 6))  # (eigenvectors * weights) @ eigenvectors.T, unscaled
    for i in range(6):
        for k in range(6):
            acc = 0.0
            for m in range(6):
                acc += eigenvectors[i, m] * weights[m] * eigenvectors[k, m]
            lambda_[i, k] = acc * (scale[i] * scale[k])
    return lambda_


@kernel
def lambda_from_inverse(
    lambda_inv: FloatArray, max_effective_mass_kg: float, blend_width: float, length_scale_m: float
) -> FloatArray:
    """:func:`lambda_and_projection` without the projection. # (6, 6)."""
    return lambda_and_projection(
        lambda_inv, max_effective_mass_kg, blend_width, length_scale_m, np.empty((6, 6))
    )


@kernel
def fold_servo(
    inertia: FloatArray,
    inertia_inv: FloatArray,
    jacobian: FloatArray,
    task_jacobian: FloatArray,
    bias: FloatArray,
    gravity: FloatArray,
    jdot_qdot: FloatArray,
    held_torque: FloatArray,
    omega: FloatArray,
    omega_bar: FloatArray,
    k_vf: float,
    xi_q: float,
    viscous: FloatArray,
    lookahead_s: float,
    max_effective_mass_kg: float,
    blend_width: float,
    length_scale_m: float,
    stacked: FloatArray,
    force_to_acceleration: FloatArray,
    jbar_lookahead: FloatArray,
    projection: FloatArray,
    limit_projection: FloatArray,
    null_space_t: FloatArray,
) -> None:
    """Eq. 27-29 and 34 folded for the servo; results written into the ``Out`` arrays.

    The task controls the axes ``C = Omega + Omega_bar`` (world): all six, or, under
    ORIENTATION FREE, only the translations; Lambda is then eq. 27's Lambda_r of the
    controlled rows (:func:`cosmos.osc.null_space.task_lambda_inverse`), which leaves
    the null space ``N^T`` (eq. 28, 34) its dimensions. Near a joint limit a redundant
    arm's task acts through ``J' = J N_c`` (:func:`cosmos.osc.limits.joint_limit_constraint`):
    torques ``J'^T F``, ``Lambda^-1 = J A^-1 J'^T`` (the tool's response to them) and
    ``N^T = I - J'^T Lambda J A^-1``, the torques that leave the tool alone; ``J' = J`` gives
    eq. 27-28 and 34 themselves.

    Args:
        inertia: A(q). # (n, n)
        inertia_inv: A^-1. # (n, n)
        jacobian: J(q), world axes. # (6, n)
        task_jacobian: J' through which the task acts: J, or J N_c near a joint limit. # (6, n)
        bias: b(q, qd), in [N m]. # (n,)
        gravity: g(q), in [N m]. # (n,)
        jdot_qdot: h = Jdot qd (eq. 14). # (6,)
        held_torque: Joint torques held until the next evaluation (potentials), [N m]. # (n,)
        omega: Motion-controlled projector, world. # (6, 6)
        omega_bar: Force-controlled projector, world. # (6, 6)
        k_vf: Velocity damping of the force-controlled axes, in [1/s].
        xi_q: Null-space damping of eq. 34, in [1/s].
        viscous: Viscous friction per joint, compensated, in [N m s/rad]. # (n,)
        lookahead_s: Look-ahead of the Coulomb compensation, in [s].
        max_effective_mass_kg: Section 5's threshold (SingularityPolicy).
        blend_width: Section 5's blend width (SingularityPolicy).
        length_scale_m: Section 5's length scale (SingularityPolicy).
        stacked: Out: ``[J^T Lambda P Omega | J^T Omega_bar | -k_vf J^T Omega_bar Lambda
            Omega_bar | b + g - J^T Lambda h + held | -xi_q (A - J^T Lambda J) + diag(viscous)]``.
            # (n, 19 + n)
        force_to_acceleration: Out: ``Lambda^-1 Omega_bar``. # (6, 6)
        jbar_lookahead: Out: ``lookahead_s Jbar P``: joint motion a command asks for. # (n, 6)
        projection: Out: the task projection P, section 5's times ``limit_projection``
            (motion commands enter as ``J^T Lambda P Omega``). # (6, 6)
        limit_projection: The joint limits' task projection
            (:func:`cosmos.osc.limits.joint_limit_task_projection`). # (6, 6)
        null_space_t: Out: ``N^T = I - J'^T Jbar^T`` of the task, ``Jbar = A^-1 J^T Lambda``. # (n, n)
    """
    j_t = task_jacobian.T.copy()
    a_inv_jt = matmul(inertia_inv, j_t)
    lambda_inv = matmul(jacobian, a_inv_jt)  # eq. 27
    controlled = np.empty((6, 6))
    trace = 0.0
    for i in range(6):
        for k in range(6):
            controlled[i, k] = omega[i, k] + omega_bar[i, k]
        trace += controlled[i, i]
    free = 6.0 - trace > 0.5  # ORIENTATION FREE: Lambda_r of the controlled rows
    lambda_task = lambda_inv
    if free:
        lambda_task = matmul(matmul(controlled, lambda_inv), controlled)
        for i in range(6):
            for k in range(6):
                lambda_task[i, k] += FREE_AXIS_INVERSE_MASS * ((1.0 if i == k else 0.0) - controlled[i, k])
    lambda_ = lambda_and_projection(
        lambda_task, max_effective_mass_kg, blend_width, length_scale_m, projection
    )
    if free:
        lambda_ = matmul(matmul(controlled, lambda_), controlled)
    scaled_matrix_into(projection, matmul(projection, limit_projection), 1.0)
    jbar = matmul(a_inv_jt, lambda_)  # eq. 28 (of J': the joints' share of a command)
    tool_jbar = matmul(matmul(inertia_inv, jacobian.T.copy()), lambda_)  # of J: what reaches the tool
    scaled_matrix_into(null_space_t, matmul(j_t, tool_jbar.T), -1.0)
    for i in range(null_space_t.shape[0]):  # n joints
        null_space_t[i, i] += 1.0
    force_to_torque = matmul(j_t, omega_bar)
    jt_lambda = matmul(j_t, lambda_)
    scaled_matrix_into(stacked[:, 0:6], matmul(matmul(jt_lambda, projection), omega), 1.0)
    scaled_matrix_into(stacked[:, 6:12], force_to_torque, 1.0)
    scaled_matrix_into(stacked[:, 12:18], matmul(matmul(force_to_torque, lambda_), omega_bar), -k_vf)
    h_torque = matvec(jt_lambda, jdot_qdot)
    joint_space = matmul(jt_lambda, jacobian)
    n = inertia.shape[0]
    for i in range(n):
        stacked[i, 18] = bias[i] + gravity[i] - h_torque[i] + held_torque[i]
        for k in range(n):
            stacked[i, 19 + k] = -xi_q * (inertia[i, k] - joint_space[i, k])
        stacked[i, 19 + i] += viscous[i]
    scaled_matrix_into(force_to_acceleration, matmul(lambda_inv, omega_bar), 1.0)
    scaled_matrix_into(jbar_lookahead, matmul(jbar, projection), lookahead_s)


@kernel
def rotation_log(r: FloatArray) -> FloatArray:
    """:func:`cosmos.osc.orientation.so3_log` of a rotation matrix: axis times angle in [0, pi]. # (3,)."""
    ax, ay, az = r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]
    c = 0.5 * (r[0, 0] + r[1, 1] + r[2, 2] - 1.0)
    s = 0.5 * math.sqrt(ax * ax + ay * ay + az * az)
    theta = math.atan2(s, c)
    out = np.empty(3)
    if theta < SMALL_ANGLE_RAD or s > NEAR_PI_SIN or c > 0.0:
        k = 0.5 + theta * theta / 12.0 if theta < SMALL_ANGLE_RAD else 0.5 * theta / s
        out[0], out[1], out[2] = k * ax, k * ay, k * az
        return out
    # Near pi the antisymmetric part vanishes; use (R + R^T)/2 = c I + (1 - c) n n^T from
    # its largest diagonal entry, and the sign of n from the antisymmetric part.
    d = 1.0 - c
    i = 0
    for j in (1, 2):
        if r[j, j] > r[i, i]:
            i = j
    n = np.empty(3)
    n[i] = math.sqrt(max((r[i, i] - c) / d, 0.0))
    for j in range(3):
        if j != i:
            n[j] = (r[i, j] + r[j, i]) / (2.0 * d * n[i])
    if n[0] * ax + n[1] * ay + n[2] * az < 0.0:
        theta = -theta
    return theta * n


@kernel(read_only=("evaluation", "goal_rotation_to_world"))
def refold(
    evaluation: FloatArray,
    held_torque: FloatArray,
    omega: FloatArray,
    omega_bar: FloatArray,
    goal_position: FloatArray,
    goal_rotation_to_world: FloatArray,
    constants: FloatArray,
    viscous: FloatArray,
    stacked: FloatArray,
    vectors: FloatArray,
    matrices: FloatArray,
    jacobian_out: FloatArray,
    jbar_lookahead: FloatArray,
    null_space_t: FloatArray,
) -> None:
    """Everything the servo kernel needs from one evaluation and the segment's selection and goal.

    ``evaluation`` is an evaluation's packed values (:mod:`cosmos.runtime.kernels.evaluation`).
    :func:`fold_servo` into ``stacked`` and ``matrices``, the evaluation's J, q, g and
    wrist geometry copied into the servo's blocks, and the reference error
    ``x_e - x_d = (p - p_d, log(R R_d^T))`` (eq. 19, 21), its rotation unwrapped
    against the previous one (the row's old content): a goal motion keeps turning
    the way it started, through 180 deg and beyond. ``constants`` holds k_vf,
    xi_q, the Coulomb look-ahead and section 5's three policy values, in that order.
    Block layouts: :mod:`cosmos.runtime.kernels.servo`; the arm's n joints are ``stacked``'s rows.
    The task's ``N^T`` (n, n) goes to ``null_space_t``.
    """
    n = stacked.shape[0]
    jacobian_at, gravity_at = ek.jacobian_at(n), ek.gravity_at(n)
    jacobian = evaluation[jacobian_at : jacobian_at + 6 * n].reshape((6, n))
    gravity = evaluation[gravity_at : gravity_at + n]
    rotation_tool = evaluation[ek.ROTATION_TOOL : ek.ROTATION_TOOL + 9].reshape((3, 3))
    error = vectors[sk.REFERENCE_ERROR, :6]
    for i in range(3):
        error[i] = evaluation[ek.POSITION + i] - goal_position[i]
    rotation_error = rotation_log(matmul(rotation_tool, goal_rotation_to_world.T))
    scaled_into(error[3:], unwrapped_rotation_error(rotation_error, error[3:]), 1.0)
    inertia_at, inverse_at, bias_at = ek.inertia_at(n), ek.inertia_inv_at(n), ek.bias_at(n)
    inertia_inv = evaluation[inverse_at : inverse_at + n * n].reshape((n, n))
    toward_goal = np.empty(6)
    scaled_into(toward_goal, error, -1.0)
    limit_projection, given_up = np.eye(6), np.zeros(n)
    task_jacobian = limit_task_into(
        limit_projection, given_up, inertia_inv, jacobian, evaluation[ek.Q : ek.Q + n], constants, toward_goal
    )
    fold_servo(
        evaluation[inertia_at : inertia_at + n * n].reshape((n, n)),
        inertia_inv,
        jacobian,
        task_jacobian,
        evaluation[bias_at : bias_at + n],
        gravity,
        evaluation[ek.JDOT_QDOT : ek.JDOT_QDOT + 6],
        held_torque,
        omega,
        omega_bar,
        constants[0],
        constants[1],
        viscous,
        constants[2],
        constants[3],
        constants[4],
        constants[5],
        stacked,
        matrices[sk.FORCE_TO_ACCELERATION],
        jbar_lookahead,
        matrices[sk.SINGULAR_PROJECTION],
        limit_projection,
        null_space_t,
    )
    for i in range(n):  # eq. 34's damping for the motion the task gave up: joint i alone, g xi_q
        for k in range(n):
            stacked[k, 19 + i] -= given_up[i] * constants[1] * evaluation[inertia_at + k * n + i]
    scaled_matrix_into(jacobian_out, jacobian, 1.0)
    scaled_matrix_into(matrices[sk.OMEGA_BAR], omega_bar, 1.0)
    rotation_sensor = evaluation[ek.ROTATION_SENSOR : ek.ROTATION_SENSOR + 9].reshape((3, 3))
    scaled_matrix_into(matrices[sk.ROTATION_SENSOR, :3, :3], rotation_sensor, 1.0)
    scaled_into(vectors[sk.EVALUATION_Q, :n], evaluation[ek.Q : ek.Q + n], 1.0)
    scaled_into(vectors[sk.GRAVITY, :n], gravity, 1.0)
    scaled_into(vectors[sk.SENSOR_OFFSETS, :6], evaluation[ek.SENSOR_TO_TOOL : ek.SENSOR_TO_COM + 3], 1.0)


@kernel
def unwrapped_rotation_error(log: FloatArray, previous: FloatArray) -> FloatArray:
    """:func:`cosmos.osc.orientation.unwrap_rotation_vector`: the one nearest ``previous``. # (3,)."""
    angle = math.sqrt(log[0] ** 2 + log[1] ** 2 + log[2] ** 2)
    if angle < SMALL_ANGLE_RAD:
        return log
    other = log * (1.0 - 2.0 * math.pi / angle)  # the same rotation, the other way round
    near = 0.0
    far = 0.0
    for i in range(3):
        near += (log[i] - previous[i]) ** 2
        far += (other[i] - previous[i]) ** 2
    return other if far < near else log
