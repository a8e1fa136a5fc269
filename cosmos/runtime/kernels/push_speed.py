"""An INSERT's push held to its speed reference, compiled (numba): :mod:`cosmos.osc.push_speed`.

``tests/runtime/test_push_speed_kernel.py`` checks each against its readable reference.
"""

from __future__ import annotations

import numpy as np

from cosmos.jit import kernel
from cosmos.runtime.kernels.contact import push_axis, speed_limited_push_into

FloatArray = np.ndarray


@kernel
def speed_reference(reference: FloatArray, aim: float, along: float, rate: float, dt_s: float) -> float:
    """:func:`cosmos.osc.push_speed.speed_reference_step` in place; returns ``a_r`` [m/s^2].

    ``reference``: ``(v_r [m/s], started)``; ``started`` 0 on a segment's first tick. # (2,)
    """
    if reference[1] == 0.0:
        reference[0] = min(max(along, 0.0), aim)
        reference[1] = 1.0
    step = min(rate * aim * dt_s, max(aim - reference[0], 0.0))
    reference[0] = min(reference[0] + step, aim)
    return step / dt_s


@kernel
def push_at_speed_into(
    feedback: FloatArray,
    force_goal: FloatArray,
    force_sensed: FloatArray,
    velocity: FloatArray,
    force_to_acceleration: FloatArray,
    gains: FloatArray,
    rate: float,
    cruise: FloatArray,
    dt_s: float,
) -> bool:
    """The push's cap (:func:`speed_limited_push_into`) on the speed reference; returns whether it binds.

    Args:
        feedback: F_fb in, capped along the push out, world. # (6,)
        force_goal: F_d (not ramped), world. # (6,)
        force_sensed: F_s, world. # (6,)
        velocity: Tool twist, world. # (6,)
        force_to_acceleration: ``Lambda^-1 Omega_bar``. # (6, 6)
        gains: ``(k_vf [1/s], kv [1/s], aim [m/s])``. # (>= 3,)
        rate: The reference's rise, in aims per second [1/s].
        cruise: The servo's cruise row: ``(v_r, started)`` at 2 and 3; ``v_r`` follows the tool
            while the cap does not bind. # (>= 4,)
        dt_s: Servo period, in [s].
    """
    k_vf, kv, aim, reference = gains[0], gains[1], gains[2], cruise[2:4]
    n0, n1, n2, inverse_mass = push_axis(force_goal, force_to_acceleration)
    if not inverse_mass > 0.0:
        return False
    along = n0 * velocity[0] + n1 * velocity[1] + n2 * velocity[2]
    feedforward = speed_reference(reference, aim, along, rate, dt_s)
    limited, _ = speed_limited_push_into(
        feedback,
        force_goal,
        force_sensed,
        velocity,
        force_to_acceleration,
        reference[0],
        kv,
        k_vf,
        feedforward,
    )
    if not limited:
        reference[0] = min(max(along, 0.0), aim)
    return limited
