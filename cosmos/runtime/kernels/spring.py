"""A COMPLY spring held to its law in the servo tick, compiled (numba).

:func:`spring_law_into` mirrors :func:`cosmos.osc.integral_action.observe_spring_disturbance` and
:func:`spring_intent_into` :func:`cosmos.osc.integral_action.spring_intent`, against which
``tests/runtime/test_spring_kernel.py`` checks them on seeded random inputs. Their rows in the servo
kernel's packed arrays (:mod:`cosmos.runtime.kernels.servo`) are laid out here.
"""

from __future__ import annotations

import numpy as np

from cosmos.jit import kernel
from cosmos.osc.integral_action import SPRING_OBSERVER
from cosmos.runtime.kernels.cruise import CRUISE
from cosmos.runtime.kernels.linear import rotate_blocks

FloatArray = np.ndarray

SPRING_LAW = CRUISE + 1
"""First of two rows of the servo's ``state``, task axes: the springs' disturbance estimate
[m/s^2, rad/s^2] and the velocity it predicts [m/s, rad/s]. Rows 0 and 2 are the servo's wrench
and twist, world (kernels.servo's WRENCH, VELOCITY)."""
SPRING_ROWS = 2
SPRINGS = 17
"""Row of the servo's ``vectors``: each task axis's effective mass where COMPLY ... STIFFNESS makes
it a spring, else 0 [kg, kg m^2]."""


@kernel
def spring_law_into(
    motion: FloatArray,
    state: FloatArray,
    vectors: FloatArray,
    rotation_task: FloatArray,
    dt_s: float,
) -> None:
    """Step the rows at :data:`SPRING_LAW`; take the estimate off ``motion`` on the spring axes (in place).

    Args:
        motion: F*_m, world. # (6,)
        state: The servo's state: the wrench and twist (rows 0, 2) read, the rows at
            :data:`SPRING_LAW` stepped, zeroed off the springs. # (rows, >= 6)
        vectors: The servo's vectors: :data:`SPRINGS` read. # (rows, >= 6)
        rotation_task: The task frame (top-left (3, 3)).
        dt_s: Servo period, in [s].
    """
    springs, estimate, predicted = vectors[SPRINGS], state[SPRING_LAW], state[SPRING_LAW + 1]
    sprung = False
    for i in range(6):
        if springs[i] > 0.0:
            sprung = True
        else:
            estimate[i] = predicted[i] = 0.0
    if not sprung:
        return
    rate, force_limit, moment_limit = SPRING_OBSERVER
    wrench = rotate_blocks(rotation_task, state[0], True)
    velocity = rotate_blocks(rotation_task, state[2], True)
    command = rotate_blocks(rotation_task, motion, True)
    for i in range(6):
        mass = springs[i]
        if mass > 0.0:
            limit = (force_limit if i < 3 else moment_limit) / mass
            estimate[i] = min(max(estimate[i] + rate * (velocity[i] - predicted[i]), -limit), limit)
            predicted[i] = velocity[i] + dt_s * (command[i] - wrench[i] / mass)
            command[i] -= estimate[i]
    out = rotate_blocks(rotation_task, command, False)
    for i in range(6):
        motion[i] = out[i]


@kernel
def spring_intent_into(
    acceleration: FloatArray, state: FloatArray, vectors: FloatArray, rotation_task: FloatArray
) -> None:
    """Take each spring axis's ``f / lambda`` off the Coulomb compensation's acceleration (in place).

    Args:
        acceleration: What the joints' friction is compensated toward, world. # (6,)
        state: The servo's state: the wrench (row 0) read. # (rows, >= 6)
        vectors: The servo's vectors: :data:`SPRINGS` read. # (rows, >= 6)
        rotation_task: The task frame (top-left (3, 3)).
    """
    springs = vectors[SPRINGS]
    sprung = False
    for i in range(6):
        sprung = sprung or springs[i] > 0.0
    if not sprung:
        return
    pushed = rotate_blocks(rotation_task, state[0], True)
    for i in range(6):
        pushed[i] = pushed[i] / springs[i] if springs[i] > 0.0 else 0.0
    out = rotate_blocks(rotation_task, pushed, False)
    for i in range(6):
        acceleration[i] -= out[i]
