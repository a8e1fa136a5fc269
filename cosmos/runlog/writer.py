"""The run log writer: one MCAP file per run, written as the run goes.

Times: every message's MCAP ``log_time`` and ``publish_time`` are the
simulated time of the sample in integer nanoseconds since the start of the
run, ``round(t * 1e9)``; ``t`` in a message is the same time in seconds.

Durability: :meth:`RunLog.flush` (called by the runtime at statement
boundaries) closes the chunk in progress, hands everything to the operating
system and fsyncs it, so a run killed after a flush leaves a file that
:func:`cosmos.runlog.read_log` reads up to that flush and
:func:`cosmos.runlog.recover` completes. :meth:`RunLog.close` writes the
summary and footer; leaving the ``with`` block closes, also on an exception.

The file is written by Foxglove's SDK (its Rust MCAP writer); reading uses the
``mcap`` package, so every log is checked by a second implementation.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping, Sequence
from datetime import UTC, datetime
from pathlib import Path
from types import TracebackType
from typing import Any, Final

import numpy as np
from foxglove import Channel, Context, Schema, open_mcap
from foxglove.mcap import MCAPCompression, MCAPWriteOptions
from mcap.well_known import MessageEncoding, SchemaEncoding
from numpy.typing import ArrayLike

from cosmos import __version__
from cosmos.runlog import foxglove
from cosmos.runlog.foxglove import LogLevel
from cosmos.runlog.scene import Primitive, entity
from cosmos.runlog.schemas import (
    EVENT_SCHEMA,
    EVENT_SCHEMA_NAME,
    EVENT_TOPIC,
    METADATA_NAME,
    SEGMENT_SCHEMA,
    SEGMENT_SCHEMA_NAME,
    SEGMENT_TOPIC,
    STATE_SCHEMA,
    STATE_SCHEMA_NAME,
    STATE_TOPIC,
    STATE_VECTORS,
    STATE_WIDTH,
    EventKind,
    schema_bytes,
)
from cosmos.runlog.text_template import STATE_NOT_EXACT, STATE_WRITTEN, Template

DEFAULT_CHUNK_SIZE: Final = 256 * 1024
"""Bytes of messages per chunk; at most this much is lost past the last flush."""

_BATCH: Final = 64  # state samples encoded together

# zstd level 1: on these logs both faster (about 15 % less CPU) and smaller than the
# compressor's default. Compression runs in the calling thread (compression_threads=0): the
# Rust writer holds the GIL while it compresses and waits for the chunk at every chunk end,
# so a worker thread saves no time in the loop (measured: more wall time on the 2-core machine).
_ZSTD_LEVEL: Final = 1

# JSON text of a state message. Vector components are written as integers with
# a fixed exponent (125730e-6 is 0.125730): plain JSON, and much cheaper to
# format than floats. The compiled kernels write it (cosmos.runlog.text_kernel);
# this format string is its definition.
_STATE_TEMPLATE: Final = (
    '{"t":%.9f,'
    + ",".join(f'"{name}":[' + ",".join(["%de-6"] * n) + "]" for name, n in STATE_VECTORS)
    + ',"segment":%d,"line":%d}'
)
_STATE_TEXT: Final = Template.from_format(_STATE_TEMPLATE.replace("%.9f", "%d"))  # t: first hole

_EVENT_LEVELS: Final = {
    EventKind.FAILED: LogLevel.ERROR,
    EventKind.COLLISION: LogLevel.WARNING,
    EventKind.WARNING: LogLevel.WARNING,
}


def default_log_path(program: Path, now: datetime) -> Path:
    """``logs/<program stem>-<UTC time>.mcap``, e.g. ``logs/peg-20261122T031500Z.mcap``.

    Args:
        program: Path of the program file.
        now: Time of the run; a naive datetime is taken as UTC.
    """
    utc = now.replace(tzinfo=UTC) if now.tzinfo is None else now.astimezone(UTC)
    return Path("logs") / f"{program.stem}-{utc:%Y%m%dT%H%M%SZ}.mcap"


def _exact(value: float) -> str:
    """The shortest text that reads back as exactly ``value`` (``1000``, ``333.3333``)."""
    short = f"{value:g}"
    return short if float(short) == value else repr(float(value))


def _fsync(path: Path) -> None:
    """Ask the OS to put the file's written data on disk (any descriptor of it will do)."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _ns(t: float) -> int:
    return round(t * 1e9)


def _vector(value: ArrayLike, n: int, name: str) -> list[float]:
    array = np.asarray(value, dtype=float).reshape(-1)
    if array.shape != (n,):
        raise ValueError(f"{name} must have {n} components, got {array.size}")
    return array.tolist()


def _optional(value: float | None) -> float | None:
    return None if value is None or not np.isfinite(value) else float(value)


class RunLog:
    """The MCAP log of one run (or REPL session), open for writing.

    Args:
        path: File to write; missing parent directories are created.
        program: The program's path as the user named it (``<repl>`` for a session).
        source: The program text, stored as an attachment named after the
            program file; None to attach it later with :meth:`attach_source`.
        servo_hz: Servo (torque) rate [Hz].
        param_hz: Parameter-evaluation (dynamics) rate [Hz].
        state_hz: Rate at which :meth:`state` is called [Hz of simulated time].
        model: Name of the arm model.
        seed: Seed of the sensor noise.
        metadata: More ``name: value`` pairs for the ``cosmos`` metadata record.
        chunk_size: Bytes per MCAP chunk (compressed with zstd).
        frames: Child frames of :meth:`transforms`, in the order poses are given.
    """

    def __init__(
        self,
        path: Path | str,
        *,
        program: str,
        source: str | None,
        servo_hz: float,
        param_hz: float,
        state_hz: float,
        model: str,
        seed: int,
        metadata: Mapping[str, str] | None = None,
        chunk_size: int = DEFAULT_CHUNK_SIZE,
        frames: Sequence[str] = foxglove.ARM_FRAMES,
    ):
        self.path = Path(path)
        self.program = program
        self.path.parent.mkdir(parents=True, exist_ok=True)
        # Foxglove's SDK writes the MCAP (its Rust writer costs a few microseconds a message,
        # a third of the pure-Python one's); each log has its own context and channels.
        self._context = Context()
        options = MCAPWriteOptions(
            compression=MCAPCompression.Zstd,
            compression_level=_ZSTD_LEVEL,
            chunk_size=chunk_size,
            compression_threads=0,
        )
        self._writer = open_mcap(
            self.path, allow_overwrite=True, context=self._context, writer_options=options
        )
        self._channels: list[Channel] = []
        self._closed = False
        self._last_ns = 0

        channel = self._json_channel
        self._state = channel(STATE_TOPIC, STATE_SCHEMA_NAME, STATE_SCHEMA)
        self._segment = channel(SEGMENT_TOPIC, SEGMENT_SCHEMA_NAME, SEGMENT_SCHEMA)
        self._event = channel(EVENT_TOPIC, EVENT_SCHEMA_NAME, EVENT_SCHEMA)
        self._tf = channel(
            foxglove.TRANSFORMS_TOPIC,
            foxglove.FRAME_TRANSFORMS_SCHEMA_NAME,
            foxglove.FRAME_TRANSFORMS_SCHEMA,
        )
        self._scene = channel(
            foxglove.SCENE_TOPIC, foxglove.SCENE_UPDATE_SCHEMA_NAME, foxglove.SCENE_UPDATE_SCHEMA
        )
        self._log = channel(foxglove.LOG_TOPIC, foxglove.LOG_SCHEMA_NAME, foxglove.LOG_SCHEMA)
        # Rust-side log calls of the channels (the Python wrapper re-checks the type per message).
        self._log_state = self._state.base.log
        self._log_tf = self._tf.base.log
        # The compiled kernels load numba (about a second): imported here, so that reading logs
        # does not. The staging kernels take contiguous float64 arrays only and raise TypeError
        # for anything else; the callers try them with what they were given, convert on that error.
        from cosmos.runlog import text_kernel

        self._stage_state: Any = text_kernel.stage_state
        self._stage_transform: Any = text_kernel.stage_transform
        self._render_states = text_kernel.render_states
        self._render_transforms = text_kernel.render_transforms

        # State samples wait here and are encoded _BATCH at a time.
        self._rows = np.empty((_BATCH, STATE_WIDTH))  # (batch, 37)
        self._times = np.empty(_BATCH)  # (batch,) s
        self._labels = np.empty((_BATCH, 2), dtype=np.int64)  # (batch, 2): segment, line
        self._pending = 0
        self._status = np.empty(_BATCH, dtype=np.int64)  # (batch,): STATE_WRITTEN or why not
        self._offsets = np.empty(_BATCH + 1, dtype=np.int64)
        self._times_ns = np.empty(_BATCH, dtype=np.int64)
        # /tf samples wait with the states, in micro-units; the buffers grow if a batch holds more.
        self._tf_text = Template.from_format(foxglove.frame_transforms_format(frames))
        self._frame_rows = np.arange(len(frames), dtype=np.int64)  # (frames,)
        self._tf_poses = np.empty((_BATCH, len(frames), 7), dtype=np.int64)  # (capacity, frames, 7)
        self._tf_ns = np.empty(_BATCH, dtype=np.int64)
        self._tf_offsets = np.empty(_BATCH + 1, dtype=np.int64)
        self._pending_tf = 0
        self._text = np.empty(0, dtype=np.uint8)  # JSON text of a batch, grown as needed

        record = {
            "program": program,
            "cosmos_version": __version__,
            "servo_hz": _exact(servo_hz),
            "param_hz": _exact(param_hz),
            "state_hz": _exact(state_hz),
            "model": model,
            "seed": str(seed),
            "time": "simulated time since the start of the run; log_time = round(t * 1e9)",
            "started_utc": f"{datetime.now(UTC):%Y-%m-%dT%H:%M:%SZ}",
        }
        for key, value in (metadata or {}).items():
            if not isinstance(key, str) or not isinstance(value, str):
                raise TypeError(f"metadata must map str to str, got {key!r}: {value!r}")
            record[key] = value
        self._writer.write_metadata(METADATA_NAME, record)
        if source is not None:
            self.attach_source(source)
        self.flush()

    def _json_channel(self, topic: str, schema_name: str, schema: dict[str, Any]) -> Channel:
        channel = Channel(
            topic,
            message_encoding=MessageEncoding.JSON,
            schema=Schema(name=schema_name, encoding=SchemaEncoding.JSONSchema, data=schema_bytes(schema)),
            context=self._context,
        )
        self._channels.append(channel)
        return channel

    def _write(self, channel: Channel, t_ns: int, data: bytes) -> None:
        if self._closed:
            raise ValueError(f"{self.path}: the run log is closed")
        channel.log(data, log_time=t_ns)
        self._last_ns = t_ns

    @property
    def closed(self) -> bool:
        """Whether :meth:`close` has run."""
        return self._closed

    def attach_source(self, text: str, name: str | None = None) -> None:
        """Store program text as a ``text/plain`` attachment.

        Args:
            text: The program source.
            name: Attachment name; defaults to the program's file name.
        """
        self._writer.attach(
            create_time=0,
            log_time=self._last_ns,
            name=name or Path(self.program).name,
            media_type="text/plain",
            data=text.encode(),
        )

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
            q: Joint positions [rad]. # (6,)
            qd: Joint velocities [rad/s]. # (6,)
            tau: Joint torques [N m]. # (6,)
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
        if i + 1 == _BATCH:
            self._write_states()

    def _write_states(self) -> None:
        """Encode and write the pending states and /tf samples, each /tf right after its state."""
        n, m = self._pending, self._pending_tf
        if n == 0 and m == 0:
            return
        if self._closed:
            raise ValueError(f"{self.path}: the run log is closed")
        self._pending = self._pending_tf = 0
        size = n * _STATE_TEXT.max_bytes + m * self._tf_text.max_bytes
        if len(self._text) < size:
            self._text = np.empty(2 * size, dtype=np.uint8)
        text, state_text, tf_text = self._text, _STATE_TEXT, self._tf_text
        end = self._render_states(
            text,
            self._rows,
            self._times,
            self._labels,
            n,
            state_text.literals,
            state_text.bounds,
            self._status,
            self._offsets,
            self._times_ns,
        )
        end = self._render_transforms(
            text, end, self._tf_poses, self._tf_ns, m, tf_text.literals, tf_text.bounds, self._tf_offsets
        )
        blob = text[:end].tobytes()
        offsets = self._offsets[: n + 1].tolist()
        times_ns = self._times_ns[:n].tolist()
        tf_offsets = self._tf_offsets[: m + 1].tolist()
        tf_ns = self._tf_ns[:m].tolist()
        status = self._status[:n].tolist()
        log_state, log_tf = self._log_state, self._log_tf
        tf_next = 0
        t_ns = 0
        for i in range(n):
            t_ns = times_ns[i]
            if status[i] == STATE_WRITTEN:
                log_state(blob[offsets[i] : offsets[i + 1]], t_ns, None)
            else:
                log_state(self._python_state_text(i, status[i]), t_ns, None)
            while tf_next < m and tf_ns[tf_next] <= t_ns:
                log_tf(blob[tf_offsets[tf_next] : tf_offsets[tf_next + 1]], tf_ns[tf_next], None)
                tf_next += 1
        for k in range(tf_next, m):
            log_tf(blob[tf_offsets[k] : tf_offsets[k + 1]], tf_ns[k], None)
            t_ns = max(t_ns, tf_ns[k])
        self._last_ns = t_ns

    def _python_state_text(self, i: int, status: int) -> bytes:
        """State message of row ``i`` that the kernel left to Python (see ``render_states``)."""
        t, row = float(self._times[i]), self._rows[i]
        segment, line = self._labels[i].tolist()
        if status == STATE_NOT_EXACT:
            return self._state_json(t, row, segment, line).encode()
        micro = np.rint(row * 1e6).astype(np.int64).tolist()
        return (_STATE_TEMPLATE % (t, *micro, segment, line)).encode()

    @staticmethod
    def _state_json(t: float, row: np.ndarray, segment: int, line: int) -> str:
        """A state message with a non-finite or huge value: slow path, nulls for non-finite."""
        values = [round(v, 6) if np.isfinite(v) else None for v in row.tolist()]
        message: dict[str, Any] = {"t": t}
        start = 0
        for name, n in STATE_VECTORS:
            message[name] = values[start : start + n]
            start += n
        message["segment"] = segment
        message["line"] = line
        return json.dumps(message, separators=(",", ":"))

    def segment(
        self,
        t: float,
        *,
        segment: int,
        line: int,
        statement: str,
        kind: str,
        frame: ArrayLike,
        motion_axes: Sequence[int],
        force_setpoint: ArrayLike,
        stiffness: ArrayLike,
        damping: ArrayLike,
        goal: ArrayLike | None = None,
        speed_limit: float | None = None,
        timeout: float | None = None,
    ) -> None:
        """Record the start of a segment on ``/cosmos/segment``.

        Args:
            t: Simulated time at which the segment starts [s].
            segment: Index of the segment in order of execution.
            line: Source line of its statement.
            statement: Source text of its statement.
            kind: What it does (move, contact, slide, insert, wait, ...).
            frame: Task frame orientation in the world frame, w x y z. # (4,)
            motion_axes: 1 motion-controlled, 0 force-controlled, per task axis. # (6,)
            force_setpoint: Force [N] and moment [N m] applied to the environment,
                task axes. # (6,)
            stiffness: Per task axis [N/m, N m/rad]. # (6,)
            damping: Per task axis [N s/m, N m s/rad]. # (6,)
            goal: World position [m] (3,) or pose with quaternion w x y z (7,); None if none.
            speed_limit: Tool speed limit [m/s]; None (or inf) if none.
            timeout: Time allowed [s]; None (or inf) if none.

        Raises:
            ValueError: If a vector has the wrong length or a value is not finite.
        """
        axes = [int(a) for a in motion_axes]
        if len(axes) != 6 or not set(axes) <= {0, 1}:
            raise ValueError(f"motion_axes must be six 0/1 values, got {axes}")
        goal_list = None if goal is None else np.asarray(goal, dtype=float).reshape(-1).tolist()
        if goal_list is not None and len(goal_list) not in (3, 7):
            raise ValueError(f"goal must have 3 or 7 components, got {len(goal_list)}")
        message = {
            "t": t,
            "segment": segment,
            "line": line,
            "statement": statement,
            "kind": kind,
            "frame": _vector(frame, 4, "frame"),
            "motion_axes": axes,
            "force_setpoint": _vector(force_setpoint, 6, "force_setpoint"),
            "stiffness": _vector(stiffness, 6, "stiffness"),
            "damping": _vector(damping, 6, "damping"),
            "goal": goal_list,
            "speed_limit": _optional(speed_limit),
            "timeout": _optional(timeout),
        }
        self._write_states()
        self._write(self._segment, _ns(t), json.dumps(message, allow_nan=False).encode())

    def event(self, t: float, kind: str, *, line: int, statement: str, reason: str = "") -> None:
        """Record a change of outcome on ``/cosmos/event`` (and ``/log`` for Foxglove).

        Args:
            t: Simulated time [s].
            kind: One of start, done, stopped, failed, contact, collision, warning.
            line: Source line of the statement concerned (0: none).
            statement: Its source text.
            reason: Why, in words.

        Raises:
            ValueError: If ``kind`` is not an event kind.
        """
        try:
            kind = EventKind(kind)
        except ValueError:
            known = ", ".join(k.value for k in EventKind)
            raise ValueError(f"event kind must be one of {known}; got {kind!r}") from None
        message = {
            "t": t,
            "kind": kind.value,
            "line": line,
            "statement": statement,
            "reason": reason,
        }
        t_ns = _ns(t)
        self._write_states()
        self._write(self._event, t_ns, json.dumps(message).encode())
        text = f"{kind.value}: {statement}" + (f": {reason}" if reason else "")
        level = _EVENT_LEVELS.get(kind, LogLevel.INFO)
        self._write(self._log, t_ns, foxglove.log_message(t_ns, level, text, self.program, line))

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
        t_ns = _ns(t)
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
        self._tf_offsets = np.empty(len(self._tf_ns) + 1, dtype=np.int64)

    def scene(self, t: float, add: Sequence[Primitive] = (), remove: Sequence[str] = ()) -> None:
        """Show, move or remove fixtures and obstacles on ``/scene`` (``foxglove.SceneUpdate``).

        Args:
            t: Simulated time [s].
            add: Primitives to show; one whose id is shown already replaces it.
            remove: Ids of primitives to delete.
        """
        t_ns = _ns(t)
        data = foxglove.scene_update(t_ns, [entity(p, t_ns) for p in add], remove)
        self._write_states()
        self._write(self._scene, t_ns, data)

    def flush(self) -> None:
        """Write everything so far to disk: pending states, the open chunk, an fsync."""
        if self._closed:
            raise ValueError(f"{self.path}: the run log is closed")
        self._write_states()
        self._writer.flush()
        _fsync(self.path)

    def close(self) -> None:
        """Write the summary and footer and close the file; later calls do nothing."""
        if self._closed:
            return
        try:
            self._write_states()
            self._writer.close()
            _fsync(self.path)
        finally:
            self._closed = True
            for channel in self._channels:
                channel.close()

    def __enter__(self) -> RunLog:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self.close()
