"""A free hold's disturbance observer, compiled (numba), for the servo tick.

It mirrors :func:`cosmos.osc.integral_action.observe_hold_disturbance`, against which
``tests/runtime/test_servo_kernel.py`` checks it.
"""

from __future__ import annotations

import numpy as np

from cosmos.jit import kernel

FloatArray = np.ndarray


@kernel
def hold_observer_into(
    motion: FloatArray,
    hold: FloatArray,
    started: FloatArray,
    known: FloatArray,
    error: FloatArray,
    velocity: FloatArray,
    wrench: FloatArray,
    gate: FloatArray,
    dt_s: float,
) -> None:
    """:func:`cosmos.osc.integral_action.observe_hold_disturbance` in place.

    Args:
        motion: F*_m, world; its translation loses the estimate. # (6,)
        hold: ``[d, v_pred]``: the estimate [m/s^2] and the velocity it predicts for this
            tick [m/s], world. # (>= 6,)
        started: ``started[0]`` is 0 on a segment's first tick (which only takes the
            velocity), then 1. # (>= 1,)
        known: The acceleration the potentials give the tool by design, world, [m/s^2]. # (3,)
        error: ``x - x_d``, world, [m] then [rad]. # (6,)
        velocity: Tool twist, world, [m/s] then [rad/s]. # (6,)
        wrench: The wrench the tool applies, world, [N] then [N m]. # (6,)
        gate: ``(L [1/s], bound [m/s^2], band [m], quiet [N])``. # (4,)
        dt_s: Servo period, in [s].
    """
    gain, bound, band, quiet = gate[0], gate[1], gate[2], gate[3]
    e2 = error[0] ** 2 + error[1] ** 2 + error[2] ** 2
    f2 = wrench[0] ** 2 + wrench[1] ** 2 + wrench[2] ** 2
    if started[0] != 0.0 and e2 < band**2 and f2 < quiet**2:
        for i in range(3):
            hold[i] = min(max(hold[i] + gain * (velocity[i] - hold[3 + i]), -bound), bound)
    for i in range(3):
        hold[3 + i] = velocity[i] + dt_s * (motion[i] + known[i])
        motion[i] -= hold[i]
    started[0] = 1.0
