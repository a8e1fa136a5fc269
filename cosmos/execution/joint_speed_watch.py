"""A joint beyond its speed limit: a protective stop (:mod:`cosmos.execution.supervision`).

Franka's controller aborts with a reflex when a joint exceeds its speed limit; UR's protective
stop and ABB's supervision do the same. The workcell declares each joint's limit
(:attr:`cosmos.robots.Robot.joint_speed_limits_rad_s`), the goal motion keeps the joints within
a share of it and each joint's speed brake holds them under it (:mod:`cosmos.osc.joint_speed`);
a joint that still runs :data:`OVER_FRACTION` of its limit for :data:`OVER_S` is a hazard the
controller did not ask for, and the statement ends.

The margin: the limits are the drives' rated speeds (Franka's datasheet, the PUMA's published
table), not where they break; the speed brake reaches the drive's whole torque at the limit, so
a joint beyond it by 10 % is one the controller could not hold. The duration: 20 servo ticks is
longer than a contact's or a landing's jolt on a light joint (a few milliseconds), and a joint
10 % over its limit for 20 ms has turned only 0.2 % of a radian more than allowed.

The speed read is the plant's (MuJoCo's joint velocities, as a drive's own speed measurement
would be); the run log's ``qd`` is the controller's estimate of it, the same to the encoders'
resolution. Looked at in the supervision's compiled tick
(:func:`cosmos.execution.supervision_kernel.supervise_tick`, :func:`first_over_speed`), no allocation.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel

FloatArray = np.ndarray

OVER_FRACTION = 1.1
"""A joint faster than this fraction of its speed limit is over it."""
OVER_S = 0.02
"""... for this long, in [s]: a protective stop."""


@kernel
def first_over_speed(qd: FloatArray, watch: FloatArray) -> int:
    """The first joint over its threshold for long enough, else -1; its ticks over counted in ``watch``.

    Args:
        qd: The joints' speeds now, in [rad/s]. # (n,)
        watch: How many ticks in a row make a stop; each joint's speed beyond which it is over
            [rad/s] (inf: none); each joint's ticks over in a row so far, stepped in place. # (1 + 2 n,)
    """
    n = qd.shape[0]
    for i in range(n):
        if abs(qd[i]) > watch[1 + i]:
            watch[1 + n + i] += 1.0
            if watch[1 + n + i] >= watch[0]:
                return i
        else:
            watch[1 + n + i] = 0.0
    return -1


class JointSpeedWatch:
    """What the supervision's tick reads to watch the joints' speeds (module docstring), and its words.

    Args:
        qd_rad_s: The joints' speeds, a live view the plant rewrites every step. # (n,)
        limits_rad_s: Their speed limits, in [rad/s] (0: none). # (n,)
        servo_dt_s: Servo period, in [s].
    """

    def __init__(self, qd_rad_s: FloatArray, limits_rad_s: FloatArray, servo_dt_s: float):
        limits = np.asarray(limits_rad_s, dtype=float)
        self.qd = qd_rad_s
        """The joints' speeds, the live view :func:`first_over_speed` reads. # (n,)"""
        self._limits = limits
        ticks = float(max(1, round(OVER_S / servo_dt_s)))  # one array: a compiled call's arguments cost
        threshold = np.where(limits > 0.0, OVER_FRACTION * limits, math.inf)
        self.watch = np.concatenate(((ticks,), threshold, np.zeros(limits.shape[0])))
        """:func:`first_over_speed`'s ``watch``, stepped in place. # (1 + 2 n,)"""
        self._counts = self.watch[1 + limits.shape[0] :]

    def stop_text(self, joint: int, t_s: float) -> str:
        """The stop's message for ``joint``, over its limit long enough now; its count starts again."""
        self._counts[:] = 0.0
        return (
            f"protective stop: joint {joint + 1} at {abs(float(self.qd[joint])):.2f} rad/s, over its "
            f"limit of {self._limits[joint]:g} rad/s, at {t_s:.2f} s"
        )
