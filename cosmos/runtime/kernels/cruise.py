"""A goal motion's cruise-speed integral, compiled (numba): :mod:`cosmos.osc.cruise_speed`.

``tests/osc/test_osc_cruise_speed.py`` checks it against the readable reference on seeded
random inputs and at its gates. Its slots in the servo kernel's packed arrays
(:mod:`cosmos.runtime.kernels.servo`) are laid out here.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

FloatArray = np.ndarray

CRUISE = 10
"""Row of the servo's ``state``: the integral ``a`` [m/s^2] and the model speed ``v_m`` [m/s].
Rows 0-2 are the servo's wrench, error ``x - x_d`` and twist (kernels.servo's WRENCH, ERROR,
VELOCITY), world."""
CRUISE_INTEGRAL = 49
"""First of the last seven ``scalars`` (kernels.servo's SCALARS is 56), set per segment
(:func:`cruise_gains`): limit [m/s^2], moving [1], quiet [N], dt [s], k_c [1/s^2] (0: no
cruise integral), the smallest ``kp / kv`` [1/s] and ``kv`` [1/s]."""
CRUISE_SLOTS = 7


def cruise_gains(
    gains: tuple[float, float, float, float], dt_s: float, setpoint: ServoSetpoint
) -> FloatArray:
    """A segment's seven slots at :data:`CRUISE_INTEGRAL`; k_c 0 unless a goal motion with no force axis.

    Args:
        gains: ``ServoGains.cruise_integral``: ``(k_c [1/s^2], limit [m/s^2], moving [1], quiet [N])``.
        dt_s: Servo period, in [s].
        setpoint: The segment.
    """
    k_c, limit, moving, quiet = gains
    free_goal = setpoint.mode is MotionMode.GOAL and all(setpoint.motion_axes[:3])
    free_goal = free_goal and setpoint.cruise_integral
    kp, kv = np.asarray(setpoint.kp_task[:3]), np.asarray(setpoint.kv_task[:3])
    ratio, rate = float(np.min(kp / kv)), float(np.min(kv))
    return np.array((limit, moving, quiet, dt_s, k_c if free_goal else 0.0, ratio, rate))


@kernel
def cruise_into(
    motion: FloatArray,
    commanded_speed: FloatArray,
    state: FloatArray,
    line: FloatArray,
    max_speed: float,
    scalars: FloatArray,
) -> bool:
    """Step ``cruise = (a, v_m)`` (:func:`cosmos.osc.cruise_speed.cruise_integral_step`), add ``a u``.

    ``commanded_speed`` is set to zeros or, while a cruise's limit binds, to
    ``max(V_max - u . xd, 0) u``: the speed along ``u`` the Coulomb intent takes in place of the
    sensed one (:func:`cosmos.osc.cruise_speed.cruise_intent`); returns whether it binds.

    Args:
        motion: F*_m, world; ``a u`` is added. # (6,)
        commanded_speed: Written, world, [m/s]. # (6,)
        state: The servo's state: rows 0-2 read, ``(a, v_m)`` at :data:`CRUISE` stepped. # (rows, >= 6)
        line: Unit line from the motion's start to its goal (zeros: none). # (3,)
        max_speed: Eq. 21's V_max now (ramped), in [m/s].
        scalars: The servo's scalars; the seven at :data:`CRUISE_INTEGRAL` are read. # (SCALARS,)
    """
    commanded_speed[:] = 0.0
    g = scalars[CRUISE_INTEGRAL : CRUISE_INTEGRAL + CRUISE_SLOTS]
    limit, moving, quiet, dt_s, k_c, ratio, kv = g[0], g[1], g[2], g[3], g[4], g[5], g[6]
    if k_c == 0.0 or (line[0] == 0.0 and line[1] == 0.0 and line[2] == 0.0):
        return False
    force, error, velocity, cruise = state[0], state[1], state[2], state[CRUISE]
    binds = ratio * math.sqrt(error[0] ** 2 + error[1] ** 2 + error[2] ** 2) > max_speed
    along = velocity[0] * line[0] + velocity[1] * line[1] + velocity[2] * line[2]
    push = math.sqrt(force[0] ** 2 + force[1] ** 2 + force[2] ** 2)
    if not binds:
        cruise[0] *= max(0.0, 1.0 - ratio * dt_s)
        cruise[1] = along
    elif along > moving * max_speed and push < quiet:
        cruise[0] = min(max(cruise[0] + k_c * (cruise[1] - along) * dt_s, -limit), limit)
        cruise[1] += kv * (max_speed - cruise[1]) * dt_s
    else:  # stalled, blocked or touching: a held back only lets go (it may be what stalled the tool)
        if cruise[0] < 0.0 and push < quiet:
            cruise[0] = min(cruise[0] + k_c * (max_speed - along) * dt_s, 0.0)
        # The model runs on, drawn down at kp / kv toward the tool in a lasting stall.
        cruise[1] += kv * (max_speed - cruise[1]) * dt_s
        floor = along + moving * max_speed
        if cruise[1] > floor:
            cruise[1] += ratio * (floor - cruise[1]) * dt_s
    for i in range(3):
        motion[i] += cruise[0] * line[i]
        if binds:
            commanded_speed[i] = max(max_speed - along, 0.0) * line[i]
    return binds
