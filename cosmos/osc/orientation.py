"""Orientation: so(3) exp/log, the orientation error, quaternions and roll-pitch-yaw.

The orientation part of the operational coordinates ``x`` (seed eq. 1) is not a
vector, so ``x - x_d`` in eq. 19 and eq. 21 needs a definition. cosmos uses the
rotation vector of the relative rotation, in world axes::

    e_o = log(R R_d^T)        # (3,) rad; R = rotation_tool_to_world

``exp(e_o) R_d = R``: ``e_o`` is the rotation, about a fixed world axis, that
takes the desired orientation to the current one. Why this choice:

* Exact and linear in the angle up to pi: ``|e_o|`` is the geodesic angle. The
  alternative, the vector part of the error quaternion (``2 sin(theta/2) n``),
  saturates: at 90 deg it is 10 % short, at 179 deg it is 36 % short and its
  slope (the rotational stiffness) has fallen to 1 % of its small-angle value,
  so a large re-orientation starts slowly and the stiffness seen by a contact
  depends on how far the wrist has already turned.
* Singularity-free: the log below is closed-form and well conditioned all the
  way to pi (a separate branch near pi); Euler/RPY errors have gimbal lock.
* Consistent with the geometric Jacobian: its angular rows give the world
  angular velocity ``w``, and with R_d fixed ``d e_o/dt = J_l^{-1}(e_o) w``
  where ``J_l^{-1}(e) e = e``. So the goal-position command of eq. 20-21 with
  ``w_d`` parallel to ``-e_o`` turns the tool about a fixed axis (the rotational
  "straight line", a geodesic) at the speed limit, exactly.

All functions work on plain Python floats internally: for 3x3 matrices that is
several times faster than small numpy calls (about 1 us each).
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.osc._types import FloatArray

SMALL_ANGLE_RAD = 1e-4  # rad: below it, Taylor series replace sin(t)/t and friends
NEAR_PI_SIN = 1e-2  # sin(theta) below it (with cos < 0): the log uses the symmetric part

_Rows = tuple[tuple[float, float, float], ...] | list[list[float]]


def _exp_rows(x: float, y: float, z: float) -> tuple[float, ...]:
    """Rodrigues' formula R = I + A [v]x + B [v]x^2, row-major, from a rotation vector."""
    t2 = x * x + y * y + z * z
    if t2 < SMALL_ANGLE_RAD * SMALL_ANGLE_RAD:
        a = 1.0 - t2 / 6.0
        b = 0.5 - t2 / 24.0
    else:
        t = math.sqrt(t2)
        a = math.sin(t) / t
        b = (1.0 - math.cos(t)) / t2
    bxy, bxz, byz = b * x * y, b * x * z, b * y * z
    return (
        1.0 - b * (y * y + z * z), bxy - a * z, bxz + a * y,
        bxy + a * z, 1.0 - b * (x * x + z * z), byz - a * x,
        bxz - a * y, byz + a * x, 1.0 - b * (x * x + y * y),
    )  # fmt: skip


def _log_rows(r: _Rows) -> tuple[float, float, float]:
    """Rotation vector of a rotation matrix given as rows; theta in [0, pi]."""
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = r
    # 2 sin(theta) n from the antisymmetric part, cos(theta) from the trace.
    ax, ay, az = r21 - r12, r02 - r20, r10 - r01
    c = 0.5 * (r00 + r11 + r22 - 1.0)
    s = 0.5 * math.sqrt(ax * ax + ay * ay + az * az)
    theta = math.atan2(s, c)
    if theta < SMALL_ANGLE_RAD:
        k = 0.5 + theta * theta / 12.0  # theta / (2 sin theta)
        return k * ax, k * ay, k * az
    if s > NEAR_PI_SIN or c > 0.0:
        k = 0.5 * theta / s
        return k * ax, k * ay, k * az
    # Near pi the antisymmetric part vanishes; use (R + R^T)/2 = c I + (1 - c) n n^T
    # from its largest diagonal entry, and the sign of n from the antisymmetric part.
    d = 1.0 - c
    i = max(range(3), key=(r00, r11, r22).__getitem__)
    if i == 0:
        nx = math.sqrt(max((r00 - c) / d, 0.0))
        ny, nz = (r01 + r10) / (2.0 * d * nx), (r02 + r20) / (2.0 * d * nx)
    elif i == 1:
        ny = math.sqrt(max((r11 - c) / d, 0.0))
        nx, nz = (r01 + r10) / (2.0 * d * ny), (r12 + r21) / (2.0 * d * ny)
    else:
        nz = math.sqrt(max((r22 - c) / d, 0.0))
        nx, ny = (r02 + r20) / (2.0 * d * nz), (r12 + r21) / (2.0 * d * nz)
    if nx * ax + ny * ay + nz * az < 0.0:
        theta = -theta
    return theta * nx, theta * ny, theta * nz


def so3_exp(rotation_vector: FloatArray) -> FloatArray:
    """Rotation matrix of a rotation vector (Rodrigues' formula).

    Args:
        rotation_vector: Axis times angle, in [rad]. # (3,)

    Returns:
        The rotation matrix exp([v]x). # (3, 3)
    """
    x, y, z = rotation_vector.tolist()
    return np.array(_exp_rows(x, y, z)).reshape(3, 3)


def so3_log(rotation: FloatArray) -> FloatArray:
    """Rotation vector of a rotation matrix, angle in [0, pi].

    Closed form, accurate over the whole range (at pi the sign of the axis is
    arbitrary: both answers are the same rotation).

    Args:
        rotation: A rotation matrix. # (3, 3)

    Returns:
        Axis times angle, in [rad], with ``so3_exp(v) == rotation``. # (3,)
    """
    return np.array(_log_rows(rotation.tolist()))


def unwrap_rotation_vector(log: FloatArray, previous: FloatArray) -> FloatArray:
    """The rotation vector of ``log``'s rotation nearest ``previous``: ``log`` or the other way round.

    ``log`` (angle in [0, pi]) and ``log (1 - 2 pi / |log|)`` are the same rotation,
    turned the short and the long way about the same axis. Choosing at every
    evaluation the one nearest the last makes the orientation error of a goal
    motion continuous: eq. 20-21 then keeps turning in the direction it started
    (chosen to keep the joints in their ranges), through 180 deg, instead of
    reversing where the shortest way flips.

    Args:
        log: From :func:`so3_log`, in [rad]. # (3,)
        previous: The error at the last evaluation, in [rad]. # (3,)

    Returns:
        The representative nearer ``previous``, in [rad]. # (3,)
    """
    angle = float(np.linalg.norm(log))
    if angle < SMALL_ANGLE_RAD:
        return log
    other = log * (1.0 - 2.0 * math.pi / angle)
    return other if np.sum((other - previous) ** 2) < np.sum((log - previous) ** 2) else log


def pose_error(
    position: FloatArray,
    rotation_to_world: FloatArray,
    position_desired: FloatArray,
    rotation_desired_to_world: FloatArray,
) -> FloatArray:
    """The operational error ``x - x_d`` of eq. 19 and 21: ``(p - p_d, log(R R_d^T))``.

    Args:
        position: Tool point in world, in [m]. # (3,)
        rotation_to_world: Tool orientation. # (3, 3)
        position_desired: Desired tool point in world, in [m]. # (3,)
        rotation_desired_to_world: Desired tool orientation. # (3, 3)

    Returns:
        Position error in [m] then orientation error in [rad], world axes. # (6,)
    """
    dx, dy, dz = (position - position_desired).tolist()
    ex, ey, ez = _log_rows(rotation_to_world.dot(rotation_desired_to_world.T).tolist())
    return np.array((dx, dy, dz, ex, ey, ez))


def matrix_to_quat(rotation: FloatArray) -> FloatArray:
    """Unit quaternion (w, x, y, z) of a rotation matrix, with w >= 0 (Shepperd's method).

    Args:
        rotation: A rotation matrix. # (3, 3)

    Returns:
        The quaternion, scalar part first. # (4,)
    """
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = rotation.tolist()
    trace = r00 + r11 + r22
    # Divide by the largest of 4w^2, 4x^2, 4y^2, 4z^2 for accuracy.
    if trace >= max(r00, r11, r22):
        k = math.sqrt(1.0 + trace) * 2.0  # 4 w
        q = (0.25 * k, (r21 - r12) / k, (r02 - r20) / k, (r10 - r01) / k)
    elif r00 >= r11 and r00 >= r22:
        k = math.sqrt(1.0 + r00 - r11 - r22) * 2.0  # 4 x
        q = ((r21 - r12) / k, 0.25 * k, (r01 + r10) / k, (r02 + r20) / k)
    elif r11 >= r22:
        k = math.sqrt(1.0 + r11 - r00 - r22) * 2.0  # 4 y
        q = ((r02 - r20) / k, (r01 + r10) / k, 0.25 * k, (r12 + r21) / k)
    else:
        k = math.sqrt(1.0 + r22 - r00 - r11) * 2.0  # 4 z
        q = ((r10 - r01) / k, (r02 + r20) / k, (r12 + r21) / k, 0.25 * k)
    return np.array(q) if q[0] >= 0.0 else -np.array(q)


def rpy_to_matrix(roll: float, pitch: float, yaw: float) -> FloatArray:
    """Fixed-axis roll-pitch-yaw: ``R = Rz(yaw) Ry(pitch) Rx(roll)``.

    Roll about world x first, then pitch about world y, then yaw about world z.

    Args:
        roll: Angle about x, in [rad].
        pitch: Angle about y, in [rad].
        yaw: Angle about z, in [rad].

    Returns:
        The rotation matrix (frame to world). # (3, 3)
    """
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return np.array(
        (
            cy * cp,
            cy * sp * sr - sy * cr,
            cy * sp * cr + sy * sr,
            sy * cp,
            sy * sp * sr + cy * cr,
            sy * sp * cr - cy * sr,
            -sp,
            cp * sr,
            cp * cr,
        )  # fmt: skip
    ).reshape(3, 3)
