"""The servo tick on the plant's live signals, and the flat workspace it works in (numba).

The servo level's buffers live in one flat ``workspace``, so that a tick is a call with few
arguments (:func:`servo_tick_live`): the blocks of :mod:`cosmos.runtime.kernels.servo` (scalars,
vectors, matrices, J, the look-ahead, the folded matrix, the state), then what the tick sensed
(rows of ``w = max(6, n)``: joint positions, joint velocities, the wrist sensor's reading), at the
offsets :func:`workspace_layout` gives for an arm of n joints.
"""

from __future__ import annotations

import numpy as np
from numba.core import types

from cosmos.jit import kernel
from cosmos.runtime.kernels.joint_speed import JOINT_SPEED_MAX, speed_brake_into
from cosmos.runtime.kernels.servo import (
    MATRICES,
    SCALARS,
    STATE_ROWS,
    TORQUE,
    TORQUE_MAX,
    VECTORS,
    servo_tick,
)

FloatArray = np.ndarray

SENSED_Q, SENSED_QD, SENSED_WRENCH = range(3)
SENSED_ROWS = 3
STACKED_COLUMNS = 19  # plus n: stacked is (n, 19 + n)


@kernel
def workspace_layout(n: int) -> tuple[int, int, int, int, int, int, int, int, int]:
    """Offsets of the workspace's blocks for an arm of n joints, and its length.

    Returns:
        ``(vectors, matrices, jacobian, jbar_lookahead, stacked, state, sensed, end, w)``: the
        scalars start at 0; ``w = max(6, n)`` is the length of a row of vectors, state and sensed.
    """
    w = max(6, n)
    vectors = SCALARS
    matrices = vectors + VECTORS * w
    jacobian = matrices + MATRICES * 36
    jbar_lookahead = jacobian + 6 * n
    stacked = jbar_lookahead + 6 * n
    state = stacked + n * (STACKED_COLUMNS + n)
    sensed = state + STATE_ROWS * w
    return vectors, matrices, jacobian, jbar_lookahead, stacked, state, sensed, sensed + SENSED_ROWS * w, w


_SIGNAL = types.Array(types.float64, 1, "C", readonly=True)  # the plant's live buffers (read-only views)
_BUFFER = types.Array(types.float64, 1, "C")


# Declared (the types the servo level passes, so one compilation serves every arm): on a first run
# this, the longest kernel to compile, is compiled in a second process beside the others.
@kernel(
    types.void(
        types.float64,
        _SIGNAL,
        _SIGNAL,
        _SIGNAL,
        types.Array(types.float64, 2, "C", readonly=True),
        types.int64,
        _BUFFER,
        _BUFFER,
    ),
    beside=True,
)
def servo_tick_live(
    t_s: float,
    positions: FloatArray,
    velocities: FloatArray,
    wrench_raw: FloatArray,
    noise: FloatArray,
    noise_row: int,
    ctrl: FloatArray,
    workspace: FloatArray,
) -> None:
    """:func:`servo_tick` on the plant's live signals: sense, command, drive, in one call.

    The encoders and the wrist sensor (its noiseless signal plus row ``noise_row`` of
    ``noise``) are copied into the workspace's sensed rows, :func:`servo_tick` runs on
    them, and its torque goes to the drives (``ctrl``) as well as to the TORQUE row.

    Args:
        t_s: Simulated time, in [s].
        positions: The joint encoders, in [rad]. # (n,)
        velocities: The joint velocities, in [rad/s]. # (n,)
        wrench_raw: The wrist sensor's noiseless reading, sensor frame, [N, N m]. # (6,)
        noise: The sensor's noise samples, [N, N m]. # (rows, 6)
        noise_row: The row of ``noise`` this reading takes.
        ctrl: The drives' torque commands, in [N m]. # (n,)
        workspace: The blocks at :func:`workspace_layout`'s offsets. # (end,)
    """
    n = positions.shape[0]
    vectors, matrices, jacobian, jbar, stacked, state_at, sensed_at, end, w = workspace_layout(n)
    sensed = workspace[sensed_at:end].reshape((SENSED_ROWS, w))
    q, qd, sensor = sensed[SENSED_Q, :n], sensed[SENSED_QD, :n], sensed[SENSED_WRENCH, :6]
    for i in range(n):
        q[i] = positions[i]
        qd[i] = velocities[i]
    for i in range(6):
        sensor[i] = wrench_raw[i] + noise[noise_row, i]
    state = workspace[state_at:sensed_at].reshape((STATE_ROWS, w))
    vector_rows = workspace[vectors:matrices].reshape((VECTORS, w))
    servo_tick(
        t_s,
        q,
        qd,
        sensor,
        workspace[:vectors],
        vector_rows,
        workspace[matrices:jacobian].reshape((MATRICES, 6, 6)),
        workspace[jacobian:jbar].reshape((6, n)),
        workspace[jbar:stacked].reshape((n, 6)),
        workspace[stacked:state_at].reshape((n, STACKED_COLUMNS + n)),
        state,
    )
    # Each joint's speed brake beyond its share of its speed limit (cosmos.osc.joint_speed).
    speed_brake_into(state[TORQUE, :n], qd, vector_rows[JOINT_SPEED_MAX, :n], vector_rows[TORQUE_MAX, :n])
    for i in range(n):
        ctrl[i] = state[TORQUE, i]
