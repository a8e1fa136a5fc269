"""State and /tf batching of the run log: samples staged in arrays, written 64 at a time.

:class:`StateBatches` is the part of :class:`cosmos.runlog.writer.RunLog` that
records ``/cosmos/state`` and ``/tf``: the per-sample methods copy a sample into
staging arrays through the compiled kernels (:mod:`cosmos.runlog.text_kernel`),
and :meth:`StateBatches._write_states` renders a batch of states as JSON text,
builds each /tf sample as a ``foxglove.FrameTransforms`` (protobuf, through the
SDK's typed channel) and hands each message to its channel, each /tf sample
right after its state. A segment, an event or a scene update logged while samples
wait (:meth:`StateBatches._stage`) waits with them and is written in its place among
them: the file's order is the order things were logged in, and the samples are still
encoded a batch at a time (an event no longer makes the executor encode the samples
before it: 10 to 60 per statement). It is a
base class rather than a member so that the hot per-sample methods stay one
call with no indirection.
"""

from __future__ import annotations

import functools
import json
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, Final

import numpy as np
from foxglove import Channel
from foxglove.channels import FrameTransformsChannel
from numpy.typing import ArrayLike

from cosmos.runlog import foxglove
from cosmos.runlog.live import Pacer
from cosmos.runlog.messages import log_time_ns
from cosmos.runlog.ros2_channels import Ros2Channels
from cosmos.runlog.schemas import DEFAULT_JOINTS, state_vectors, state_width
from cosmos.runlog.text_template import STATE_NOT_EXACT, STATE_WRITTEN, Template

_BATCH: Final = 64  # state samples encoded together

FLUSH_EVERY_S: Final = 0.24
"""Simulated time between flushes of the log to the OS [s]. A SIGKILL loses at most this plus
one state period (0.244 s at the default 250 Hz, 0.25 s at the slowest state rate, 100 Hz), even
when it lands during a flush. As long as that allows: each flush closes a chunk, about 100 us."""


@functools.cache
def state_template(joints: int, fingers: bool = False) -> str:
    """JSON text of a state message, as a format string: its definition.

    Vector components are written as integers with a fixed exponent (125730e-6 is
    0.125730): plain JSON, and much cheaper to format than floats. The compiled
    kernels write it (cosmos.runlog.text_kernel).
    """
    vectors = state_vectors(joints, fingers)
    return (
        '{"t":%.9f,'
        + ",".join(f'"{name}":[' + ",".join(["%de-6"] * n) + "]" for name, n in vectors)
        + ',"segment":%d,"line":%d}'
    )


@functools.cache
def _state_text(joints: int, fingers: bool) -> Template:
    return Template.from_format(state_template(joints, fingers).replace("%.9f", "%d"))  # t: first hole


class StateBatches:
    """Staging and batched writing of ``/cosmos/state`` and ``/tf`` samples.

    The subclass sets ``path``, ``_closed``, ``_last_ns`` and ``_flush_due``, defines
    ``_flush_states`` (called when a sample's time reaches ``_flush_due``) and calls
    :meth:`_open_batches` once its channels exist.
    """

    path: Path
    _closed: bool
    _last_ns: int
    _flush_due: float

    def _flush_states(self) -> None:
        raise NotImplementedError

    def _open_batches(
        self,
        state: Channel,
        tf: FrameTransformsChannel,
        frames: Sequence[str],
        joints: int = DEFAULT_JOINTS,
        fingers: bool = False,
    ) -> None:
        """Set up the kernels and staging arrays.

        Args:
            state: The ``/cosmos/state`` channel.
            tf: The ``/tf`` channel (protobuf ``foxglove.FrameTransforms``).
            frames: Child frames of :meth:`transforms`, in the order poses are given.
            joints: The arm's number of joints (entries of q, qd and tau).
            fingers: The state has the gripper's fields (:meth:`fingers` stages them).
        """
        self._joints = joints
        self._fingers = fingers
        self._state_template = state_template(joints, fingers)
        self._state_text = _state_text(joints, fingers)
        # Rust-side log calls of the channels (the Python wrapper re-checks the type per message).
        self._log_state = state.base.log
        self._log_tf = tf.log
        self._frames = tuple(frames)
        # The compiled kernels load numba (about a second): imported here, so that reading logs
        # does not. The staging kernels take contiguous float64 arrays only and raise TypeError
        # for anything else; the callers try them with what they were given, convert on that error.
        from cosmos.runlog import text_kernel

        self._stage_state: Any = text_kernel.stage_state
        self._stage_transform: Any = text_kernel.stage_transform
        self._render_states = text_kernel.render_states

        # State samples wait here and are encoded _BATCH at a time.
        self._rows = np.empty((_BATCH, state_width(joints)))  # (batch, 3 joints + 19)
        # The gripper's fields wait apart (the staging kernel reads the joints from the rows' width).
        self._finger_rows = np.zeros((_BATCH, state_width(joints, fingers) - state_width(joints)))
        self._times = np.empty(_BATCH)  # (batch,) s
        self._labels = np.empty((_BATCH, 2), dtype=np.int64)  # (batch, 2): segment, line
        self._pending = 0
        self._status = np.empty(_BATCH, dtype=np.int64)  # (batch,): STATE_WRITTEN or why not
        self._offsets = np.empty(_BATCH + 1, dtype=np.int64)
        self._times_ns = np.empty(_BATCH, dtype=np.int64)
        # /tf samples wait with the states, in micro-units; the buffers grow if a batch holds more.
        self._frame_rows = np.arange(len(frames), dtype=np.int64)  # (frames,)
        self._tf_poses = np.empty((_BATCH, len(frames), 7), dtype=np.int64)  # (capacity, frames, 7)
        self._tf_ns = np.empty(_BATCH, dtype=np.int64)
        self._pending_tf = 0
        self._text = np.empty(0, dtype=np.uint8)  # JSON text of a batch, grown as needed
        # Messages logged while samples wait: (samples and /tf samples before it, log, time [ns], message).
        self._staged: list[tuple[int, int, Callable[..., None], int, Any]] = []
        self._ros2: Ros2Channels | None = None  # the ROS 2 channels, if logged
        self._pacer: Pacer | None = None  # real-time pacing and live hand-over (cosmos.runlog.live)

    def fingers(self, left_m: float, right_m: float, force_left_n: float, force_right_n: float) -> None:
        """The gripper's fields of the next state sample (call just before :meth:`state`).

        Args:
            left_m: The left pad's distance from the gripper's centre plane [m].
            right_m: The right pad's [m].
            force_left_n: The left pad's normal force, as its sensor reads it [N].
            force_right_n: The right pad's [N].
        """
        row = self._finger_rows[self._pending]
        row[0], row[1], row[2], row[3] = left_m, right_m, force_left_n, force_right_n

    def state(
        self,
        t: float,
        q: ArrayLike,
        qd: ArrayLike,
        tau: ArrayLike,
        x: ArrayLike,
        quat: ArrayLike,
        v: ArrayLike,
        wrench: ArrayLike,
        segment: int,
        line: int,
    ) -> None:
        """Record one state sample on ``/cosmos/state`` (call at the state rate).

        Vectors are copied, rounded to 1e-6 of their unit, and written in
        batches; :meth:`flush` and :meth:`close` write what is pending.

        Args:
            t: Simulated time since the start [s], >= 0.
            q: Joint positions [rad]. # (joints,)
            qd: Joint velocities [rad/s]. # (joints,)
            tau: Joint torques [N m]. # (joints,)
            x: Tool point position, world frame [m]. # (3,)
            quat: Tool orientation, world frame, w x y z. # (4,)
            v: Tool twist, world axes: linear [m/s] then angular [rad/s]. # (6,)
            wrench: Force [N] then moment [N m] the tool applies to the
                environment, world axes. # (6,)
            segment: Index of the segment being executed.
            line: Source line of the statement being executed.
        """
        i = self._pending
        try:
            self._stage_state(
                self._rows, self._times, self._labels, i, t, q, qd, tau, x, quat, v, wrench, segment, line
            )
        except TypeError:  # not writable contiguous float64 vectors: copy, then the same kernel
            vectors = [np.array(a, dtype=float).reshape(-1) for a in (q, qd, tau, x, quat, v, wrench)]
            self._stage_state(
                self._rows, self._times, self._labels, i, float(t), *vectors, int(segment), int(line)
            )
        self._pending = i + 1
        if t >= self._flush_due:
            self._flush_states()
        elif i + 1 == _BATCH:
            self._write_states()
        if self._pacer is not None:
            self._pacer.tick(t)

    def _stage(self, channel: Any, t_ns: int, message: Any) -> None:
        """Log ``message`` on ``channel`` at ``t_ns``, after the samples waiting now: at once if none wait."""
        if self._closed:
            raise ValueError(f"{self.path}: the run log is closed")
        if self._pending == 0 and self._pending_tf == 0:
            channel.log(message, log_time=t_ns)
            self._last_ns = t_ns
        else:
            self._staged.append((self._pending, self._pending_tf, channel.log, t_ns, message))

    def _write_states(self) -> None:
        """Encode and write the pending states and /tf samples, each /tf right after its state.

        A message staged among them (:meth:`_stage`) goes right after the samples that were
        waiting when it was logged.
        """
        n, m = self._pending, self._pending_tf
        if n == 0 and m == 0:
            return
        if self._closed:
            raise ValueError(f"{self.path}: the run log is closed")
        self._pending = self._pending_tf = 0
        staged, self._staged = self._staged, []
        staged.append((n + 1, m, self._log_state, 0, None))  # a sentinel: never reached
        state_text = self._state_text
        size = n * state_text.max_bytes
        if len(self._text) < size:
            self._text = np.empty(2 * size, dtype=np.uint8)
        text = self._text
        rows = np.hstack((self._rows, self._finger_rows)) if self._fingers else self._rows
        end = self._render_states(
            text,
            rows,
            self._times,
            self._labels,
            n,
            state_text.literals,
            state_text.bounds,
            self._status,
            self._offsets,
            self._times_ns,
        )
        blob = text[:end].tobytes()
        offsets = self._offsets[: n + 1].tolist()
        times_ns = self._times_ns[:n].tolist()
        tf_ns = self._tf_ns[:m].tolist()
        tf_poses = self._tf_poses[:m] / 1e6  # (m, frames, 7) translation [m], rotation x y z w
        frames = self._frames
        tf_message = foxglove.frame_transforms
        status = self._status[:n].tolist()
        log_state, log_tf, ros2 = self._log_state, self._log_tf, self._ros2
        tf_next = 0
        t_ns = 0
        next_staged = 0
        for i in range(n + 1):
            while staged[next_staged][0] == i:  # logged after sample i - 1 was staged
                _, before_tf, log, t_ns, message = staged[next_staged]
                while tf_next < before_tf:
                    log_tf(tf_message(tf_ns[tf_next], frames, tf_poses[tf_next]), log_time=tf_ns[tf_next])
                    if ros2 is not None:
                        ros2.transforms(tf_ns[tf_next], frames, tf_poses[tf_next])
                    tf_next += 1
                log(message, log_time=t_ns)
                next_staged += 1
            if i == n:
                break
            t_ns = times_ns[i]
            if status[i] == STATE_WRITTEN:
                log_state(blob[offsets[i] : offsets[i + 1]], t_ns, None)
            else:
                log_state(self._python_state_text(rows[i], float(self._times[i]), i, status[i]), t_ns, None)
            if ros2 is not None:
                ros2.state(t_ns, self._rows[i])
            while tf_next < m and tf_ns[tf_next] <= t_ns:
                log_tf(tf_message(tf_ns[tf_next], frames, tf_poses[tf_next]), log_time=tf_ns[tf_next])
                if ros2 is not None:
                    ros2.transforms(tf_ns[tf_next], frames, tf_poses[tf_next])
                tf_next += 1
        for k in range(tf_next, m):
            log_tf(tf_message(tf_ns[k], frames, tf_poses[k]), log_time=tf_ns[k])
            if ros2 is not None:
                ros2.transforms(tf_ns[k], frames, tf_poses[k])
            t_ns = max(t_ns, tf_ns[k])
        self._last_ns = t_ns

    def _python_state_text(self, row: np.ndarray, t: float, i: int, status: int) -> bytes:
        """State message of ``row`` (staged row ``i``) that the kernel left to Python (``render_states``)."""
        segment, line = self._labels[i].tolist()
        if status == STATE_NOT_EXACT:
            return self._state_json(t, row, segment, line).encode()
        micro = np.rint(row * 1e6).astype(np.int64).tolist()
        return (self._state_template % (t, *micro, segment, line)).encode()

    def _state_json(self, t: float, row: np.ndarray, segment: int, line: int) -> str:
        """A state message with a non-finite or huge value: slow path, nulls for non-finite."""
        values = [round(v, 6) if np.isfinite(v) else None for v in row.tolist()]
        message: dict[str, Any] = {"t": t}
        start = 0
        for name, n in state_vectors(self._joints, self._fingers):
            message[name] = values[start : start + n]
            start += n
        message["segment"] = segment
        message["line"] = line
        return json.dumps(message, separators=(",", ":"))

    def transforms(
        self, t: float, positions: ArrayLike, quats_wxyz: ArrayLike, rows: np.ndarray | None = None
    ) -> None:
        """Record the poses of the arm's frames on ``/tf`` (``foxglove.FrameTransforms``).

        A sample with a non-finite value is skipped. Samples wait with the
        states and are written with them.

        Args:
            t: Simulated time [s].
            positions: Origins of the frames given at construction, world frame [m]. # (n, 3)
            quats_wxyz: Their orientations, world frame, w x y z. # (n, 4)
            rows: Where the frames are in ``positions`` and ``quats_wxyz``
                (e.g. body ids in MuJoCo's ``xpos``, ``xquat``); None: rows 0..n-1.
                # (frames,) int64

        Raises:
            ValueError: If the arrays do not hold one pose per frame.
        """
        t_ns = log_time_ns(t)
        j = self._pending_tf
        if j == len(self._tf_ns):
            self._grow_transforms()
        try:
            staged = self._stage_transform(
                self._tf_poses,
                self._tf_ns,
                j,
                t_ns,
                positions,
                quats_wxyz,
                self._frame_rows if rows is None else rows,
            )
        except TypeError:  # not writable contiguous float64 arrays: copy, then the same kernel
            staged = self._stage_converted(j, t_ns, positions, quats_wxyz, rows)
        if staged:
            if self._closed:
                raise ValueError(f"{self.path}: the run log is closed")
            self._pending_tf = j + 1

    def _stage_converted(
        self, j: int, t_ns: int, positions: ArrayLike, quats_wxyz: ArrayLike, rows: ArrayLike | None
    ) -> bool:
        if rows is None:
            n = len(self._frame_rows)
            positions = np.broadcast_to(np.asarray(positions, dtype=float), (n, 3))
            quats_wxyz = np.broadcast_to(np.asarray(quats_wxyz, dtype=float), (n, 4))
            rows = self._frame_rows
        return bool(
            self._stage_transform(
                self._tf_poses,
                self._tf_ns,
                j,
                t_ns,
                np.array(positions, dtype=float),  # copies: writable and contiguous
                np.array(quats_wxyz, dtype=float),
                np.array(rows, dtype=np.int64),
            )
        )

    def _grow_transforms(self) -> None:
        """Twice the room for /tf samples waiting in this batch."""
        self._tf_poses = np.concatenate((self._tf_poses, np.empty_like(self._tf_poses)))
        self._tf_ns = np.concatenate((self._tf_ns, np.empty_like(self._tf_ns)))
