"""Eq. 21's limits within the joints' speed limits, compiled (numba): :mod:`cosmos.osc.joint_speed`.

``tests/runtime/test_joint_speed_kernel.py`` checks it against the readable reference. Its row
in the servo kernel's ``vectors`` (:mod:`cosmos.runtime.kernels.servo`) is laid out here.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel
from cosmos.osc.joint_speed import BRAKE_FRACTION, FULL_BRAKE_FRACTION, JOINT_SPEED_FRACTION
from cosmos.runtime.kernels.linear import rotate_blocks
from cosmos.runtime.kernels.spring import SPRINGS

FloatArray = np.ndarray

JOINT_SPEED_MAX = SPRINGS + 1
"""Row of the servo's ``vectors``: each joint's speed limit [rad/s] (0: none; the arm's
``Robot.joint_speed_limits_rad_s``), its first n entries."""


@kernel
def joint_speed_limited(
    max_speed: float,
    max_angular_speed: float,
    error: FloatArray,
    kp: FloatArray,
    kv: FloatArray,
    rotation_task: FloatArray,
    uniform: bool,
    jbar_lookahead: FloatArray,
    lookahead_s: float,
    joint_limits: FloatArray,
) -> tuple[float, float]:
    """:func:`cosmos.osc.joint_speed.joint_speed_limits`: eq. 21's ``(V_max, W_max)`` within the joints'.

    Args:
        max_speed: Eq. 21's V_max now, in [m/s].
        max_angular_speed: Its W_max now, in [rad/s].
        error: ``x - x_d``, world. # (6,)
        kp: Position gains (per-axis ones along the task frame's axes). # (6,)
        kv: Velocity gains, likewise. # (6,)
        rotation_task: The task frame's rotation to world (used where the gains are not uniform). # (6, 6)
        uniform: Whether the gains are the same on every axis.
        jbar_lookahead: ``L Jbar P``, the joints' share of a twist over the look-ahead L. # (n, 6)
        lookahead_s: L, in [s] (0: no prediction, the limits are kept).
        joint_limits: The joints' speed limits, in [rad/s] (0: none). # (n,)
    """
    if not lookahead_s > 0.0:
        return max_speed, max_angular_speed
    task_error = error if uniform else rotate_blocks(rotation_task, error, True)
    desired = np.empty(6)
    for i in range(6):
        desired[i] = -kp[i] / kv[i] * task_error[i]  # eq. 21's xd_d
    linear = math.sqrt(desired[0] ** 2 + desired[1] ** 2 + desired[2] ** 2)
    angular = math.sqrt(desired[3] ** 2 + desired[4] ** 2 + desired[5] ** 2)
    nu = 1.0 if linear <= max_speed else max_speed / linear
    nu_w = 1.0 if angular <= max_angular_speed else max_angular_speed / angular
    for i in range(3):
        desired[i] *= nu
        desired[3 + i] *= nu_w
    if not uniform:
        desired = rotate_blocks(rotation_task, desired, False)
    worst = 0.0
    for i in range(jbar_lookahead.shape[0]):
        if joint_limits[i] > 0.0:
            speed = 0.0
            for k in range(6):
                speed += jbar_lookahead[i, k] * desired[k]
            worst = max(worst, abs(speed) / (lookahead_s * JOINT_SPEED_FRACTION * joint_limits[i]))
    if worst <= 1.0:
        return max_speed, max_angular_speed
    return min(max_speed, nu * linear / worst), min(max_angular_speed, nu_w * angular / worst)


@kernel
def speed_brake_into(torque: FloatArray, qd: FloatArray, limits: FloatArray, torque_max: FloatArray) -> None:
    """:func:`cosmos.osc.joint_speed.speed_brake` added to ``torque`` in place, the sum within the drives.

    Args:
        torque: The servo's saturated torque, in [N m]; the brake is added. # (n,)
        qd: The joints' speeds, in [rad/s]. # (n,)
        limits: Their speed limits, in [rad/s] (0: none). # (n,)
        torque_max: The drives' torque limits, in [N m]. # (n,)
    """
    for i in range(torque.shape[0]):
        free = BRAKE_FRACTION * limits[i]
        if limits[i] > 0.0 and abs(qd[i]) > free:
            beyond = qd[i] - math.copysign(free, qd[i])
            brake = torque_max[i] / ((FULL_BRAKE_FRACTION - BRAKE_FRACTION) * limits[i]) * beyond
            torque[i] = min(max(torque[i] - brake, -torque_max[i]), torque_max[i])
