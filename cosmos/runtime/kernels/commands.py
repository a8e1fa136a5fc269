"""The servo tick's sensing, motion command and saturation, compiled (numba).

Each mirrors a readable reference, against which ``tests/runtime/test_servo_kernel.py``
checks it on seeded random inputs:

* :func:`environment_wrench_into`: :func:`cosmos.runtime.wrench.environment_wrench`
  (the wrench the tool applies to the environment, from the wrist sensor);
* :func:`unit_mass_command_into`: :func:`cosmos.osc.motion.goal_command` (eq. 20-21, the
  speed limit applied to translation and rotation separately) and
  :func:`cosmos.osc.motion.tracking_command` (eq. 19);
* :func:`saturate_about`: :func:`cosmos.osc.limits.saturate_torque`.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel

FloatArray = np.ndarray

# Values of the servo's ``scalars[MODE]`` (cosmos.runtime.kernels.servo).
MODE_HOLD, MODE_GOAL, MODE_TRAJECTORY = 0.0, 1.0, 2.0


@kernel(read_only=("sensor", "rotation_sensor_to_world", "sensor_to_tool_m", "sensor_to_com_m"))
def environment_wrench_into(
    out: FloatArray,
    sensor: FloatArray,
    rotation_sensor_to_world: FloatArray,
    sensor_to_tool_m: FloatArray,
    sensor_to_com_m: FloatArray,
    weight_z_n: float,
) -> None:
    """:func:`cosmos.runtime.wrench.environment_wrench`, written into ``out``. # (6,)."""
    r = rotation_sensor_to_world
    fx, fy, fz, mx, my, mz = sensor[0], sensor[1], sensor[2], sensor[3], sensor[4], sensor[5]
    ex = r[0, 0] * fx + r[0, 1] * fy + r[0, 2] * fz
    ey = r[1, 0] * fx + r[1, 1] * fy + r[1, 2] * fz
    ez = r[2, 0] * fx + r[2, 1] * fy + r[2, 2] * fz + weight_z_n
    sx = r[0, 0] * mx + r[0, 1] * my + r[0, 2] * mz
    sy = r[1, 0] * mx + r[1, 1] * my + r[1, 2] * mz
    sz = r[2, 0] * mx + r[2, 1] * my + r[2, 2] * mz
    tx, ty, tz = sensor_to_tool_m[0], sensor_to_tool_m[1], sensor_to_tool_m[2]
    cx, cy = sensor_to_com_m[0], sensor_to_com_m[1]
    out[0], out[1], out[2] = ex, ey, ez
    out[3] = sx - (ty * ez - tz * ey) + cy * weight_z_n
    out[4] = sy - (tz * ex - tx * ez) - cx * weight_z_n
    out[5] = sz - (tx * ey - ty * ex)


@kernel
def unit_mass_command_into(
    command: FloatArray,
    mode: float,
    error: FloatArray,
    velocity: FloatArray,
    velocity_desired: FloatArray,
    acceleration_desired: FloatArray,
    kp: FloatArray,
    kv: FloatArray,
    max_speed: float,
    max_angular_speed: float,
    line: FloatArray,
) -> None:
    """F*_m of a unit mass, into ``command``. # (6,).

    Eq. 20-21 (GOAL, :func:`cosmos.osc.motion.goal_command`, the translation kept on
    ``line`` by :func:`cosmos.osc.motion.on_the_line`, # (3,) in the same frame, zeros:
    none), eq. 19 (TRAJECTORY, :func:`cosmos.osc.motion.tracking_command`) or eq. 19 with
    x_d fixed (HOLD); gains are per axis of the frame ``error`` and ``velocity`` are
    written in.
    """
    if mode == MODE_GOAL:
        # Eq. 21's nu, applied to the linear and the angular part separately.
        for o, limit in ((0, max_speed), (3, max_angular_speed)):
            d0 = -kp[o] / kv[o] * error[o]
            d1 = -kp[o + 1] / kv[o + 1] * error[o + 1]
            d2 = -kp[o + 2] / kv[o + 2] * error[o + 2]
            norm = math.sqrt(d0**2 + d1**2 + d2**2)
            if norm > limit and o == 0 and (line[0] != 0.0 or line[1] != 0.0 or line[2] != 0.0):
                along = d0 * line[0] + d1 * line[1] + d2 * line[2]
                a0, a1, a2 = d0 - along * line[0], d1 - along * line[1], d2 - along * line[2]
                width = math.sqrt(a0**2 + a1**2 + a2**2)
                if width >= limit:  # (a zero limit, at the start of the speed's ramp, included)
                    scale = limit / width if width > 0.0 else 0.0
                    d0, d1, d2 = a0 * scale, a1 * scale, a2 * scale
                else:
                    rest = math.copysign(math.sqrt(limit**2 - width**2), along)
                    d0, d1, d2 = a0 + rest * line[0], a1 + rest * line[1], a2 + rest * line[2]
                norm = limit
            nu = 1.0 if norm <= limit else limit / norm
            command[o] = kv[o] * (nu * d0 - velocity[o])
            command[o + 1] = kv[o + 1] * (nu * d1 - velocity[o + 1])
            command[o + 2] = kv[o + 2] * (nu * d2 - velocity[o + 2])
    elif mode == MODE_TRAJECTORY:
        for i in range(6):
            command[i] = (
                acceleration_desired[i] - kp[i] * error[i] - kv[i] * (velocity[i] - velocity_desired[i])
            )
    else:
        for i in range(6):
            command[i] = -kp[i] * error[i] - kv[i] * velocity[i]


@kernel
def saturate_about(torque: FloatArray, torque_max: FloatArray, keep: FloatArray) -> None:
    """:func:`cosmos.osc.limits.saturate_torque` in place: scale ``torque - keep`` into the limits."""
    n = torque.shape[0]
    inside = True
    for i in range(n):
        if abs(torque[i]) > torque_max[i]:
            inside = False
    if inside:
        return
    scale = 1.0
    kept = np.empty(n)
    for i in range(n):
        kept[i] = min(max(keep[i], -torque_max[i]), torque_max[i])
        delta = torque[i] - kept[i]
        if delta != 0.0:
            scale = min(scale, (math.copysign(torque_max[i], delta) - kept[i]) / delta)
    scale = max(0.0, scale)
    for i in range(n):
        torque[i] = kept[i] + scale * (torque[i] - kept[i])


@kernel
def slide_integral_into(
    motion: FloatArray,
    acceleration: FloatArray,
    motion_integral: FloatArray,
    error: FloatArray,
    omega_bar: FloatArray,
    gains: FloatArray,
) -> None:
    """A SLIDE whose reference has stopped: :func:`cosmos.osc.integral_action.integrate_motion_error`.

    Eq. 19 plus integral action on the motion axes' translation error, its part pushing the
    tool on past its goal dropped first; ``motion`` and ``acceleration`` lose ``k_i integral``.

    Args:
        motion: F*_m, world. # (6,)
        acceleration: The Coulomb intent's acceleration, world. # (6,)
        motion_integral: The integral, world, [m s]; stepped in place. # (>= 3,)
        error: ``x - x_d``, world. # (6,)
        omega_bar: Force-controlled projector, world. # (6, 6)
        gains: ``(k_i [1/s^3], bound [m s], dt [s])``. # (3,)
    """
    ki, bound, dt = gains[0], gains[1], gains[2]
    along = np.empty(3)
    for i in range(3):
        along[i] = error[i]
        for k in range(3):
            along[i] -= omega_bar[i, k] * error[k]
    past = along[0] * motion_integral[0] + along[1] * motion_integral[1] + along[2] * motion_integral[2]
    if past < 0.0:
        past /= along[0] ** 2 + along[1] ** 2 + along[2] ** 2
    for i in range(3):
        if past < 0.0:
            motion_integral[i] -= past * along[i]
        motion_integral[i] = min(max(motion_integral[i] + along[i] * dt, -bound), bound)
        motion[i] -= ki * motion_integral[i]
        acceleration[i] -= ki * motion_integral[i]
