"""A held contact's sliding friction, learnt and compensated, compiled: :mod:`cosmos.osc.surface_friction`.

``tests/osc/test_osc_surface_friction.py`` checks it against the readable reference on seeded
random inputs. Its row in the servo's state is kernels.servo's SURFACE: the coefficient
``mu_s``, whether the tool has slid on the contact (1) or not (0), then ``F_s`` (world, [N]).
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel
from cosmos.osc.surface_friction import SURFACE_FRICTION
from cosmos.runtime.kernels.spring import SPRING_LAW, SPRING_ROWS

FloatArray = np.ndarray

FULL_SPEED_MPS = SURFACE_FRICTION.full_speed_mps
SLIDING_MPS = SURFACE_FRICTION.sliding_mps
RATE_PER_S = SURFACE_FRICTION.rate_per_s
SHARE = SURFACE_FRICTION.share
MAX_COEFFICIENT = SURFACE_FRICTION.max_coefficient
FLOOR_N = SURFACE_FRICTION.floor_n
SURFACE = SPRING_LAW + SPRING_ROWS + 1
"""The row of the servo's ``state`` (kernels.servo's, after FRICTION_ERROR). Rows 0 and 2 are the
servo's wrench and twist (kernels.servo's WRENCH, VELOCITY), world."""
COEFFICIENT, SLID, FORCE = 0, 1, 2
"""Entries of the row: mu_s, the slid flag, F_s's three."""


@kernel
def surface_friction_into(
    torque: FloatArray,
    state: FloatArray,
    jacobian: FloatArray,
    omega_bar: FloatArray,
    motion: FloatArray,
    commanded_speed: FloatArray,
    force_goal: FloatArray,
    held: bool,
    slide: bool,
    adaption: FloatArray,
    blend: float,
) -> None:
    """Learn ``mu_s`` and add ``J^T F_s`` to ``torque`` (:mod:`cosmos.osc.surface_friction`).

    Args:
        torque: Gamma, in [N m]; ``J^T F_s`` is added. # (n,)
        state: The servo's state: rows 0 and 2 read, :data:`SURFACE` (``mu_s, slid, F_s``) stepped.
            # (rows, >= 6)
        jacobian: J at the evaluation, world (its translation rows used). # (6, n)
        omega_bar: Force-controlled projector, world. # (6, 6)
        motion: F*_m, world. # (6,)
        commanded_speed: The reference's xd_d off the force axes, world. # (6,)
        force_goal: F_d, world. # (6,)
        held: A contact is held (force-controlled axes); else the row is forgotten.
        slide: The segment slides on it (a tracked reference, no speed cap on the push, touching);
            else F_s restarts and nothing is added.
        adaption: The servo's gains for the joints' Coulomb levels (kernels.friction_adaptation):
            ``(kv, L [s], 1 / v_c, dt [s])``; L, the Coulomb look-ahead, and the servo period read. # (4,)
        blend: beta, the joints' Coulomb low-pass's share of its target per tick.
    """
    row, wrench, velocity = state[SURFACE], state[0], state[2]
    if not held:
        row[:] = 0.0
        return
    if not slide:
        row[FORCE : FORCE + 3] = 0.0
        return
    lookahead, dt = adaption[1], adaption[3]
    intent = np.empty(3)
    tangent = np.empty(3)
    sliding = np.empty(3)
    push = 0.0
    for i in range(3):
        s_along = 0.0
        w_along = 0.0
        v_along = 0.0
        f_along = 0.0
        for k in range(3):
            s_along += omega_bar[i, k] * (velocity[k] + lookahead * motion[k] + commanded_speed[k])
            w_along += omega_bar[i, k] * wrench[k]
            v_along += omega_bar[i, k] * velocity[k]
            f_along += omega_bar[i, k] * force_goal[k]
        intent[i] = velocity[i] + lookahead * motion[i] + commanded_speed[i] - s_along
        tangent[i] = wrench[i] - w_along
        sliding[i] = velocity[i] - v_along
        push += f_along * f_along
    push = math.sqrt(push)
    size = math.sqrt(intent[0] ** 2 + intent[1] ** 2 + intent[2] ** 2)
    if push > 0.0:
        ratio = math.sqrt(tangent[0] ** 2 + tangent[1] ** 2 + tangent[2] ** 2) / push
        coefficient = row[COEFFICIENT]
        if math.sqrt(sliding[0] ** 2 + sliding[1] ** 2 + sliding[2] ** 2) > SLIDING_MPS:
            coefficient += RATE_PER_S * dt * (ratio - coefficient)
            row[SLID] = 1.0
        elif row[SLID] == 0.0 and size >= FULL_SPEED_MPS:
            coefficient = max(coefficient, ratio)
        row[COEFFICIENT] = min(max(coefficient, 0.0), MAX_COEFFICIENT)
    level = 0.0
    if size > 0.0:
        level = SHARE * max(row[COEFFICIENT] * push - FLOOR_N, 0.0) * min(size / FULL_SPEED_MPS, 1.0) / size
    for i in range(3):
        row[FORCE + i] += blend * (level * intent[i] - row[FORCE + i])
    f0, f1, f2 = row[FORCE], row[FORCE + 1], row[FORCE + 2]
    for j in range(torque.shape[0]):
        torque[j] += jacobian[0, j] * f0 + jacobian[1, j] * f1 + jacobian[2, j] * f2
