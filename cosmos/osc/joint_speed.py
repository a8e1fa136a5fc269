"""The goal motion's speed limit kept within the joints' speed limits (seed eq. 20-21 and 28).

Eq. 21 bounds the goal motion at the tool: ``nu = min(1, V_max / |xd_d|)``. The joints turn at
``qd_d = Jbar v_d`` (eq. 28's dynamically consistent inverse, the controller's own, times eq.
21's desired velocity ``v_d = nu xd_d``), and nothing in eq. 21 bounds that: where the task's
Jacobian is nearly singular a modest tool speed asks for a fast joint. On the Panda, a 175 deg
roll at the tool's 1 rad/s, handed from joint 7 (at its limit, the task through ``J N_c``:
:func:`cosmos.osc.limits.joint_limit_constraint`) to joints 1 and 3 with the elbow nearly
straight (their axes 4 deg apart), turned them at 9.8 rad/s, 4.5 times the datasheet's 2.175.

The limit here is eq. 21 again, in joint space: the worst joint's ratio of its predicted speed
to its limit, ``r = max_i |qd_d,i| / (f qd_max,i)``, scales the desired velocity,
``v_d <- v_d / max(1, r)``. Scaling the whole twist (not clipping the joint) keeps the
motion's direction (the tool's line and its rotation axis), as eq. 21's ``nu`` does; it is
applied as eq. 21's limits themselves, ``V_max <- |v_d| / r`` for the translation and the rotation
alike, so the servo's velocity loop (eq. 20) brakes the tool down to it. ``f`` leaves room
for the loop's tracking error below the protective stop (:mod:`cosmos.execution.joint_speed_watch`).

A joint can still run fast where the task does not ask it to: the null space's own motion. At the
same hand-over, with the tool slowed to 0.16 rad/s by the limit above, joints 1 and 3 still turned
at 5.4 rad/s against each other (tool still, joint 7 pushed off its limit by the joint-limit
potential through ``N^T``, eq. 34's damping the only brake along that self-motion). So each joint
also has a speed brake, a one-sided viscous damper in joint space (the velocity form of eq. 34's
``-xi_q A qd``, acting on a joint's speed beyond :data:`BRAKE_FRACTION` of its limit only):
``Gamma_i = -b_i (qd_i - clip(qd_i, -f_b qd_max,i, f_b qd_max,i))``, with ``b_i`` such that the brake
reaches the drive's torque limit at the speed limit itself. It is added after the servo's
saturation and the sum clipped to the drive: the brake keeps its authority. Braking from 0.9 of the
limit to the whole torque at 1.1 let joint 1 reach 2.39 rad/s (1.10x) at the hand-over above, and
the joint chattered against the brake; from 0.8 to the whole torque at 1.0 it peaked at 2.11 rad/s
(0.97x); 0.85-0.95, 0.9-1.0 and 0.6-1.0 did no better. The brake acts on the joint whole: through
the null space (eq. 34's damping on the speed beyond the share, 10 or 30 times ``xi_q``, read off
the folded matrix) it changed nothing there, the controller's ``N^T`` seeing that motion as the
task's. The price at the hand-over: the tool tilted 1.2 deg and its point strayed 5.5 mm (0.34 deg
and 1.8 mm without the joints' limits) while the task took the brake's torque back.

The compiled servo tick runs the same arithmetic (:mod:`cosmos.runtime.kernels.joint_speed`).
"""

from __future__ import annotations

import numpy as np

from cosmos.osc._types import FloatArray
from cosmos.osc.motion import goal_velocity

JOINT_SPEED_FRACTION = 0.8
"""The goal motion keeps every joint's predicted speed within this fraction of its limit: the
velocity loop (eq. 20, kv = 40 /s) lags a braking command and the prediction is the last
evaluation's ``Jbar``; 20 % is the room for both below the limit."""

BRAKE_FRACTION = 0.8
"""A joint's speed brake acts beyond this fraction of its limit."""
FULL_BRAKE_FRACTION = 1.0
"""The brake reaches the drive's torque limit at this fraction of the speed limit."""


def joint_speed_ratio(predicted_rad_s: FloatArray, limits_rad_s: FloatArray, fraction: float) -> float:
    """The worst joint's ``|qd_i| / (f qd_max,i)``; joints without a limit (0) are left out.

    Args:
        predicted_rad_s: The joints' speeds, in [rad/s]. # (n,)
        limits_rad_s: Their limits, in [rad/s] (0: none). # (n,)
        fraction: f, the share of the limit that is allowed, in (0, 1].
    """
    limits = np.asarray(limits_rad_s, dtype=float)
    limited = limits > 0.0
    if not limited.any():
        return 0.0
    return float(np.max(np.abs(np.asarray(predicted_rad_s)[limited]) / (fraction * limits[limited])))


def joint_speed_limits(
    error: FloatArray,
    kp: FloatArray,
    kv: FloatArray,
    limits: tuple[float, float],
    jbar: FloatArray,
    joint_limits_rad_s: FloatArray,
    fraction: float = JOINT_SPEED_FRACTION,
) -> tuple[float, float]:
    """Eq. 21's ``(V_max, W_max)`` lowered so that ``Jbar v_d`` keeps every joint within ``f`` of its limit.

    Args:
        error: ``x - x_d``, world, in [m] then [rad]. # (6,)
        kp: Position gains, in [1/s^2] (uniform: the world's axes). # (6,)
        kv: Velocity gains, in [1/s]. # (6,)
        limits: Eq. 21's ``(V_max [m/s], W_max [rad/s])`` now.
        jbar: The joints' share of a twist, ``Jbar P`` (eq. 28, section 5's P), in [rad/m]. # (n, 6)
        joint_limits_rad_s: The joints' speed limits, in [rad/s] (0: none). # (n,)
        fraction: f (:data:`JOINT_SPEED_FRACTION`).

    Returns:
        ``(V_max, W_max)``: unchanged while every joint is within ``f`` of its limit, else the
        speeds of ``v_d / r``.
    """
    desired = goal_velocity(np.asarray(error, dtype=float), kp, kv, limits[0], limits[1])
    ratio = joint_speed_ratio(np.asarray(jbar) @ desired, joint_limits_rad_s, fraction)
    if ratio <= 1.0:
        return limits
    return (
        min(limits[0], float(np.linalg.norm(desired[:3])) / ratio),
        min(limits[1], float(np.linalg.norm(desired[3:])) / ratio),
    )


def speed_brake(qd_rad_s: FloatArray, limits_rad_s: FloatArray, torque_max_nm: FloatArray) -> FloatArray:
    """Each joint's speed brake (module docstring): ``-b_i`` times its speed beyond ``f_b qd_max,i``, [N m].

    ``b_i = tau_max,i / ((f_s - f_b) qd_max,i)``: zero up to :data:`BRAKE_FRACTION` of the limit, the
    drive's whole torque at :data:`FULL_BRAKE_FRACTION` of it. Joints without a limit (0) get none.

    Args:
        qd_rad_s: The joints' speeds, in [rad/s]. # (n,)
        limits_rad_s: Their speed limits, in [rad/s] (0: none). # (n,)
        torque_max_nm: The drives' torque limits, in [N m]. # (n,)
    """
    qd, limits = np.asarray(qd_rad_s, dtype=float), np.asarray(limits_rad_s, dtype=float)
    free = BRAKE_FRACTION * limits
    beyond = qd - np.clip(qd, -free, free)
    gain = np.divide(
        torque_max_nm,
        (FULL_BRAKE_FRACTION - BRAKE_FRACTION) * limits,
        out=np.zeros_like(limits),
        where=limits > 0.0,
    )
    return -gain * beyond
