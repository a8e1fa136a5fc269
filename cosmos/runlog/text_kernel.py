"""The run log's JSON text written by compiled kernels (numba), and the staging of samples.

The kernels fill :class:`cosmos.runlog.text_template.Template` texts for a
whole batch of messages into one byte buffer, with the same digits Python's
``%d`` (and, for a state's time, ``%.9f``) writes: the template, read as a
``%``-format string, is the reference (checked in
``tests/runlog/test_runlog_text_kernel.py``).

The staging kernels copy one sample's vectors into the rows waiting for the
next batch: one compiled call where NumPy takes one call per vector.

Rounding: a value ``v`` becomes ``int64(rint(v * 1e6))`` (half to even), as
``np.rint(v * 1e6).astype(np.int64)`` does.

Importing this module loads numba (about a second): the writer imports it when
a log is opened for writing, so reading logs does not pay for it.
"""

from __future__ import annotations

from typing import Final

import numpy as np

from cosmos.jit import kernel
from cosmos.runlog.text_template import (
    POSE_LIMIT,
    STATE_MICRO_LIMIT,
    STATE_NOT_EXACT,
    STATE_TIME_OUTSIDE,
    STATE_WRITTEN,
    TIME_LIMIT_S,
)

FloatArray = np.ndarray
IntArray = np.ndarray
ByteArray = np.ndarray

_SPLIT: Final = 134217729.0  # 2**27 + 1, Dekker's splitting constant


@kernel
def _put_int(out: ByteArray, pos: int, value: int) -> int:
    """Write ``value`` in decimal (as ``%d``) at ``out[pos]``; return the position after it."""
    if value < 0:
        out[pos] = 45  # "-"
        pos += 1
        value = -value
    rest = np.uint64(value)  # unsigned: division without Python's floor fix-ups
    ten = np.uint64(10)
    digits = 1
    bound = np.uint64(10)
    while rest >= bound and digits < 19:
        digits += 1
        bound *= ten
    if rest >= bound:
        digits += 1
    end = pos + digits
    for k in range(end - 1, pos - 1, -1):
        out[k] = np.uint8(np.uint64(48) + rest % ten)
        rest //= ten
    return end


@kernel("int64(uint8[::1], int64, uint8[::1], int64[::1], int64)")  # once, not per literal index
def _put_literal(out: ByteArray, pos: int, literals: ByteArray, bounds: IntArray, index: int) -> int:
    """Write literal ``index`` of a template at ``out[pos]``; return the position after it."""
    for k in range(bounds[index], bounds[index + 1]):
        out[pos] = literals[k]
        pos += 1
    return pos


@kernel
def time_nanoseconds(t: float) -> int:
    """``t * 1e9`` rounded half to even from its exact value (what ``"%.9f" % t`` rounds).

    ``t * 1e9`` in floating point may round across a half; the exact product is
    ``p + err`` (Dekker's product: 1e9 has 21 significant bits, so the halves of
    ``t`` times 1e9 are exact). Only a tie of ``p`` can then round differently.

    Args:
        t: Time [s], in ``[0, TIME_LIMIT_S)``.
    """
    p = t * 1e9
    big = t * _SPLIT
    t_hi = big - (big - t)
    t_lo = t - t_hi
    err = (t_hi * 1e9 - p) + t_lo * 1e9
    n = np.rint(p)
    d = p - n  # exact; |d| <= 0.5, and a tie only if |d| == 0.5
    if d == 0.5 and err > 0.0:
        n += 1.0
    elif d == -0.5 and err < 0.0:
        n -= 1.0
    return int(n)


@kernel
def _put_time(out: ByteArray, pos: int, t: float) -> int:
    """Write ``"%.9f" % t`` for ``t`` in ``[0, TIME_LIMIT_S)``; return the position after it."""
    ns = time_nanoseconds(t)
    pos = _put_int(out, pos, ns // 1_000_000_000)
    out[pos] = 46  # "."
    frac = ns % 1_000_000_000
    for k in range(pos + 9, pos, -1):
        out[k] = 48 + frac % 10
        frac //= 10
    return pos + 10


@kernel
def _micro(value: float) -> int:
    """``value`` in integer micro-units, rounded half to even."""
    return int(np.rint(value * 1e6))


@kernel
def render_states(
    out: ByteArray,
    rows: FloatArray,
    times: FloatArray,
    labels: IntArray,
    count: int,
    literals: ByteArray,
    bounds: IntArray,
    status: IntArray,
    offsets: IntArray,
    times_ns: IntArray,
) -> int:
    """Write the first ``count`` state messages into ``out``; return the bytes written.

    A message is the template's holes filled with ``"%.9f"`` of the time, the
    row in micro-units, then segment and line. A row with a vector value that
    is not finite or not below :data:`STATE_MICRO_LIMIT`, or with a time
    outside ``[0, TIME_LIMIT_S)``, is not written (its ``status``, an empty
    range in ``offsets``): the caller writes it.

    Args:
        out: Output buffer, at least ``count`` messages long. # (capacity,) uint8
        rows: State vectors. # (batch, 37)
        times: The times [s]. # (batch,)
        labels: Segment and line. # (batch, 2) int64
        count: Messages to write.
        literals: The template's literals.
        bounds: Their bounds; holes are the time, 37 vector components, segment and line.
        status: Out: STATE_WRITTEN, STATE_NOT_EXACT or STATE_TIME_OUTSIDE per row. # (batch,) int64
        offsets: Out: message ``i`` is ``out[offsets[i]:offsets[i + 1]]``. # (batch + 1,) int64
        times_ns: Out: ``rint(t * 1e9)``, the MCAP log time (as ``round(t * 1e9)``). # (batch,) int64
    """
    width = rows.shape[1]
    pos = 0
    for i in range(count):
        offsets[i] = pos
        t = times[i]
        times_ns[i] = int(np.rint(t * 1e9))
        state = STATE_WRITTEN
        for j in range(width):
            if not abs(rows[i, j]) < STATE_MICRO_LIMIT:
                state = STATE_NOT_EXACT
                break
        if state == STATE_WRITTEN and not (0.0 <= t < TIME_LIMIT_S and np.copysign(1.0, t) > 0.0):
            state = STATE_TIME_OUTSIDE
        status[i] = state
        if state != STATE_WRITTEN:
            continue
        pos = _put_literal(out, pos, literals, bounds, 0)
        pos = _put_time(out, pos, t)
        pos = _put_literal(out, pos, literals, bounds, 1)
        for j in range(width):
            pos = _put_int(out, pos, _micro(rows[i, j]))
            pos = _put_literal(out, pos, literals, bounds, j + 2)
        pos = _put_int(out, pos, labels[i, 0])
        pos = _put_literal(out, pos, literals, bounds, width + 2)
        pos = _put_int(out, pos, labels[i, 1])
        pos = _put_literal(out, pos, literals, bounds, width + 3)
    offsets[count] = pos
    return pos


@kernel(
    "void(float64[:, ::1], float64[::1], int64[:, ::1], int64, float64, float64[::1], float64[::1],"
    " float64[::1], float64[::1], float64[::1], float64[::1], float64[::1], int64, int64)"
)
def stage_state(
    rows: FloatArray,
    times: FloatArray,
    labels: IntArray,
    i: int,
    t: float,
    q: FloatArray,
    qd: FloatArray,
    tau: FloatArray,
    x: FloatArray,
    quat: FloatArray,
    v: FloatArray,
    wrench: FloatArray,
    segment: int,
    line: int,
) -> None:
    """Copy one state sample into row ``i`` (vectors in message order), its time and labels.

    Compiled for contiguous float64 vectors only; other inputs raise TypeError
    at the call (the caller converts them).

    Raises:
        ValueError: If a vector has the wrong length (nothing is copied).
    """
    n = (rows.shape[1] - 19) // 3  # the arm's joints: rows are q qd tau (n each), x quat v wrench
    if len(q) != n or len(qd) != n or len(tau) != n:
        raise ValueError("q, qd and tau must have one component per joint of the log's arm")
    if len(v) != 6 or len(wrench) != 6:
        raise ValueError("v and wrench must have 6 components each")
    if len(x) != 3 or len(quat) != 4:
        raise ValueError("x must have 3 components and quat 4")
    row = rows[i]
    for k in range(n):
        row[k] = q[k]
        row[n + k] = qd[k]
        row[2 * n + k] = tau[k]
    for k in range(6):
        row[3 * n + 7 + k] = v[k]
        row[3 * n + 13 + k] = wrench[k]
    for k in range(3):
        row[3 * n + k] = x[k]
    for k in range(4):
        row[3 * n + 3 + k] = quat[k]
    times[i] = t
    labels[i, 0] = segment
    labels[i, 1] = line


@kernel("boolean(int64[:, :, ::1], int64[::1], int64, int64, float64[:, ::1], float64[:, ::1], int64[::1])")
def stage_transform(
    poses: IntArray,
    times_ns: IntArray,
    j: int,
    t_ns: int,
    positions: FloatArray,
    quats_wxyz: FloatArray,
    frame_rows: IntArray,
) -> bool:
    """Copy the poses of the frames (rows ``frame_rows`` of the inputs) into slot ``j`` in micro-units.

    Args:
        poses: Staged poses, x y z then quaternion x y z w. # (capacity, frames, 7) int64
        times_ns: Staged times [ns]. # (capacity,) int64
        j: Slot to fill.
        t_ns: Time of the sample [ns].
        positions: Frame origins [m]. # (m, 3)
        quats_wxyz: Frame orientations, w x y z. # (m, 4)
        frame_rows: Row of each frame in the inputs. # (frames,) int64

    Returns:
        False, and nothing staged, if a coordinate is not finite or not below :data:`POSE_LIMIT`.

    Raises:
        ValueError: If the shapes do not match or a row is out of range.
    """
    frames = poses.shape[1]
    if len(frame_rows) != frames or positions.shape[1] != 3 or quats_wxyz.shape[1] != 4:
        raise ValueError("the poses must be (n, 3) positions and (n, 4) quaternions, one per frame")
    for f in range(frames):
        r = frame_rows[f]
        if r < 0 or r >= positions.shape[0] or r >= quats_wxyz.shape[0]:
            raise ValueError("a frame's row is outside the pose arrays")
        for c in range(3):
            if not abs(positions[r, c]) < POSE_LIMIT:
                return False
        for c in range(4):
            if not abs(quats_wxyz[r, c]) < POSE_LIMIT:
                return False
    for f in range(frames):
        r = frame_rows[f]
        for c in range(3):
            poses[j, f, c] = _micro(positions[r, c])
        for c in range(3):
            poses[j, f, 3 + c] = _micro(quats_wxyz[r, 1 + c])  # x y z
        poses[j, f, 6] = _micro(quats_wxyz[r, 0])  # w
    times_ns[j] = t_ns
    return True
