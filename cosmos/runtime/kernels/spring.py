"""A COMPLY spring held to its law in the servo tick, compiled (numba).

:func:`spring_law_into` mirrors :func:`cosmos.osc.integral_action.hold_spring_law`, against
which ``tests/runtime/test_spring_kernel.py`` checks it on seeded random inputs. Its rows in
the servo kernel's packed arrays (:mod:`cosmos.runtime.kernels.servo`) are laid out here.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel
from cosmos.osc.integral_action import SPRING_LIMIT, SPRING_OBSERVER, SPRING_RATE
from cosmos.runtime.kernels.cruise import CRUISE
from cosmos.runtime.kernels.linear import rotate_blocks

FloatArray = np.ndarray

SPRING_LAW = CRUISE + 1
"""First of three rows of the servo's ``state``, task axes: the spring law's integral [m/s, rad/s],
the free spring's disturbance estimate [m/s^2, rad/s^2] and the velocity it predicts [m/s, rad/s].
Rows 0 and 2 are the servo's wrench and twist, world (kernels.servo's WRENCH, VELOCITY)."""
SPRING_ROWS = 3
SPRINGS = 17
"""Row of the servo's ``vectors``: each task axis's effective mass where COMPLY ... STIFFNESS makes
it a spring, else 0 [kg, kg m^2]. Rows 0 and 1 are the gains kp and kv, task axes (KP, KV)."""
_FORCE_LIMIT, _MOMENT_LIMIT = SPRING_LIMIT


@kernel
def spring_law_into(
    motion_task: FloatArray,
    error_task: FloatArray,
    state: FloatArray,
    vectors: FloatArray,
    rotation_task: FloatArray,
    dt_s: float,
) -> None:
    """Step the rows at :data:`SPRING_LAW`; add ``k_I integral - d`` to ``motion_task`` (in place).

    Args:
        motion_task: F*_m, task axes. # (6,)
        error_task: ``x - x_d``, task axes. # (6,)
        state: The servo's state: the wrench and twist (rows 0, 2) read, the rows at
            :data:`SPRING_LAW` stepped, zeroed off the springs. # (rows, >= 6)
        vectors: The servo's vectors: kp, kv (rows 0, 1) and :data:`SPRINGS` read. # (rows, >= 6)
        rotation_task: The task frame (top-left (3, 3)).
        dt_s: Servo period, in [s].
    """
    integral, springs, kp, kv = state[SPRING_LAW], vectors[SPRINGS], vectors[0], vectors[1]
    estimate, predicted = state[SPRING_LAW + 1], state[SPRING_LAW + 2]
    sprung = False
    for i in range(6):
        if springs[i] > 0.0:
            sprung = True
        else:
            integral[i] = estimate[i] = predicted[i] = 0.0
    if not sprung:
        return
    wrench_task = rotate_blocks(rotation_task, state[0], True)
    velocity_task = rotate_blocks(rotation_task, state[2], True)
    rate, quiet_n, quiet_nm = SPRING_OBSERVER
    force = math.sqrt(state[0, 0] ** 2 + state[0, 1] ** 2 + state[0, 2] ** 2)
    moment = math.sqrt(state[0, 3] ** 2 + state[0, 4] ** 2 + state[0, 5] ** 2)
    free = force < quiet_n and moment < quiet_nm
    for i in range(6):
        mass = springs[i]
        if mass > 0.0:
            gain = SPRING_RATE * kv[i]
            limit = (_FORCE_LIMIT if i < 3 else _MOMENT_LIMIT) / mass
            law = -kp[i] * error_task[i] - wrench_task[i] / mass
            integral[i] = min(max(integral[i] + law * dt_s, -limit / gain), limit / gain)
            motion_task[i] += gain * integral[i]
            if free:
                step = rate * (velocity_task[i] - predicted[i])
                estimate[i] = min(max(estimate[i] + step, -limit), limit)
            predicted[i] = velocity_task[i] + dt_s * motion_task[i]
            motion_task[i] -= estimate[i]
