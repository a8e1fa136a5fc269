"""The run log writer: one MCAP file per run, written as the run goes.

Times: every message's MCAP ``log_time`` and ``publish_time`` are the
simulated time of the sample in integer nanoseconds since the start of the
run, ``round(t * 1e9)``; ``t`` in a message is the same time in seconds.

Durability: every :data:`FLUSH_EVERY_S` of simulated time (checked at each
state sample) the chunk in progress is closed and handed to the operating
system, so a run killed with SIGKILL loses at most that much; :meth:`RunLog.flush`
(called by the executor at the end of a plan, and of a failed statement) does the same
at once. Each asks for an fsync, which a thread beside the run does at most once a second
of wall time (:meth:`cosmos.runlog.sink.LogSink.sync`: only the OS going down needs it).
A run killed after a flush leaves a file that :func:`cosmos.runlog.read_log`
reads up to that flush and :func:`cosmos.runlog.recover` completes.
:meth:`RunLog.close` writes the summary and footer; leaving the ``with`` block
closes, also on an exception, and so does the interpreter's exit.

The file is written by Foxglove's SDK (its Rust MCAP writer) through a
:class:`~cosmos.runlog.sink.LogSink`, so a write error (a full disk) is one
:class:`~cosmos.errors.UsageError` naming the file, raised at the next flush;
reading uses the ``mcap`` package, so every log is checked by a second implementation.
"""

from __future__ import annotations

import weakref
from collections.abc import Mapping, Sequence
from pathlib import Path
from types import TracebackType
from typing import Any, Final

from foxglove import Channel, Context, Schema, WebSocketServer, open_mcap
from foxglove.channels import FrameTransformsChannel, LogChannel, SceneUpdateChannel
from foxglove.mcap import MCAPCompression, MCAPWriteOptions
from mcap.well_known import MessageEncoding, SchemaEncoding
from numpy.typing import ArrayLike

from cosmos.errors import UsageError
from cosmos.runlog import foxglove, live
from cosmos.runlog.live import Pacer
from cosmos.runlog.messages import (
    event_kind,
    event_log_line,
    event_message,
    log_time_ns,
    metadata_record,
    segment_message,
)
from cosmos.runlog.output import default_log_path as default_log_path  # re-exported
from cosmos.runlog.output import open_output
from cosmos.runlog.ros2_channels import Ros2Channels
from cosmos.runlog.scene import Primitive, entity
from cosmos.runlog.schemas import (
    DEFAULT_JOINTS,
    EVENT_SCHEMA,
    EVENT_SCHEMA_NAME,
    EVENT_TOPIC,
    METADATA_NAME,
    SEGMENT_SCHEMA,
    SEGMENT_SCHEMA_NAME,
    SEGMENT_TOPIC,
    STATE_SCHEMA_NAME,
    STATE_TOPIC,
    schema_bytes,
    state_schema,
)
from cosmos.runlog.sink import LogSink, close_at_exit
from cosmos.runlog.state_batch import FLUSH_EVERY_S, StateBatches

DEFAULT_CHUNK_SIZE: Final = 256 * 1024
"""Bytes of messages per chunk; at most this much is lost past the last flush."""

# zstd level 1: on these logs both faster (about 15 % less CPU) and smaller than the
# compressor's default. Compression runs in the calling thread (compression_threads=0): the
# Rust writer holds the GIL while it compresses and waits for the chunk at every chunk end,
# so a worker thread saves no time in the loop (measured: more wall time on the 2-core machine).
_ZSTD_LEVEL: Final = 1


class RunLog(StateBatches):
    """The MCAP log of one run (or REPL session), open for writing.

    Args:
        path: File to write (a regular file; see :mod:`cosmos.runlog.output`).
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
        flush_every_s: Simulated time between flushes to the OS [s] (inf: only :meth:`flush`).
        overwrite: Replace an existing file (``cosmos run`` checks ``--force`` first).
        make_parents: Create missing parent directories.
        ros2_joints: The arm's joint names, to also write the ROS 2 channels
            (:mod:`cosmos.runlog.ros2`); None: not written.
        joints: The arm's number of joints: entries of q, qd and tau in ``/cosmos/state``,
            recorded in the metadata (``joints``); ``fingers``: the gripper's fields too (metadata).

    Raises:
        UsageError: If the file cannot be created, naming it and the reason.
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
        flush_every_s: float = FLUSH_EVERY_S,
        overwrite: bool = True,
        make_parents: bool = True,
        ros2_joints: Sequence[str] | None = None,
        joints: int = DEFAULT_JOINTS,
        fingers: bool = False,
    ):
        self.path = Path(path)
        self.program = program
        self._sink = LogSink(
            self.path,
            open_output(
                self.path, what="the log", force=overwrite, make_parents=make_parents, buffered=False
            ),
        )
        # Foxglove's SDK writes the MCAP (its Rust writer costs a few microseconds a message,
        # a third of the pure-Python one's); each log has its own context and channels.
        self._context = Context()
        options = MCAPWriteOptions(
            compression=MCAPCompression.Zstd,
            compression_level=_ZSTD_LEVEL,
            chunk_size=chunk_size,
            compression_threads=0,
        )
        self._writer = open_mcap(self._sink, context=self._context, writer_options=options)
        self._at_exit = weakref.finalize(self, close_at_exit, weakref.ref(self), self._writer, self._sink)
        self._channels: list[Channel] = []
        self._closed = False
        self._last_ns = 0
        self._flush_every_s = flush_every_s
        self._flush_due = flush_every_s

        channel = self._json_channel
        self._state = channel(STATE_TOPIC, STATE_SCHEMA_NAME, state_schema(joints, fingers))
        self._segment = channel(SEGMENT_TOPIC, SEGMENT_SCHEMA_NAME, SEGMENT_SCHEMA)
        self._event = channel(EVENT_TOPIC, EVENT_SCHEMA_NAME, EVENT_SCHEMA)
        # Foxglove's well-known messages: the SDK's typed channels encode protobuf (official schemas).
        context = self._context
        self._tf = FrameTransformsChannel(foxglove.TRANSFORMS_TOPIC, context=context)
        self._scene = SceneUpdateChannel(foxglove.SCENE_TOPIC, context=context)
        self._log = LogChannel(foxglove.LOG_TOPIC, context=context)
        self._typed_channels = (self._tf, self._scene, self._log)
        self._open_batches(self._state, self._tf, frames, joints, fingers)
        if ros2_joints is not None:
            self._ros2 = Ros2Channels(context, ros2_joints)
        self._shown: dict[str, Any] = {}  # the scene's entities by id (a live view repeats them)
        self.live_server: WebSocketServer | None = None
        """The live view's server (:meth:`pace`), stopped by :meth:`close`."""

        record = metadata_record(
            program=program,
            servo_hz=servo_hz,
            param_hz=param_hz,
            state_hz=state_hz,
            model=model,
            seed=seed,
            metadata={"joints": str(joints), **({"fingers": "2"} if fingers else {}), **(metadata or {})},
        )
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

    def _write(self, channel: Any, t_ns: int, data: Any) -> None:
        """Log ``data`` (JSON bytes, or a foxglove-sdk message on a typed channel) at ``t_ns``."""
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
        data = segment_message(
            t,
            segment=segment,
            line=line,
            statement=statement,
            kind=kind,
            frame=frame,
            motion_axes=motion_axes,
            force_setpoint=force_setpoint,
            stiffness=stiffness,
            damping=damping,
            goal=goal,
            speed_limit=speed_limit,
            timeout=timeout,
        )
        self._stage(self._segment, log_time_ns(t), data)

    def event(
        self, t: float, kind: str, *, line: int, statement: str, reason: str = "", context: str = ""
    ) -> None:
        """Record a change of outcome on ``/cosmos/event`` (and ``/log`` for Foxglove).

        Args:
            t: Simulated time [s].
            kind: One of start, done, stopped, failed, contact, collision, warning.
            line: Source line of the statement concerned (0: none).
            statement: Its source text.
            reason: Why, in words.
            context: Where an expanded statement came from ("PROC p called at line 7"; "": top level).

        Raises:
            ValueError: If ``kind`` is not an event kind.
        """
        event = event_kind(kind)
        t_ns = log_time_ns(t)
        self._stage(self._event, t_ns, event_message(t, event, line, statement, reason, context))
        level, text = event_log_line(event, statement, reason, context)
        self._stage(self._log, t_ns, foxglove.log_message(t_ns, level, text, self.program, line))

    def scene(self, t: float, add: Sequence[Primitive] = (), remove: Sequence[str] = ()) -> None:
        """Show, move or remove fixtures and obstacles on ``/scene`` (``foxglove.SceneUpdate``).

        Args:
            t: Simulated time [s].
            add: Primitives to show; one whose id is shown already replaces it.
            remove: Ids of primitives to delete.
        """
        t_ns = log_time_ns(t)
        entities = [entity(p, t_ns) for p in add]
        for name in remove:
            self._shown.pop(name, None)
        self._shown.update((p.id, e) for p, e in zip(add, entities, strict=True))
        self._stage(self._scene, t_ns, foxglove.scene_update(t_ns, entities, remove))

    def _repeat_scene(self, t: float) -> None:
        """Send every entity shown again, for a live viewer that connected after it was sent."""
        self._write_states()
        self._write(
            self._scene, log_time_ns(t), foxglove.scene_update(log_time_ns(t), [*self._shown.values()])
        )

    def pace(self, rate: float, live_port: int | None = None) -> WebSocketServer | None:
        """Hold the run to ``rate`` times real time; with ``live_port``, also stream it: return the server.

        Args:
            rate: Simulated seconds per wall-clock second.
            live_port: Start foxglove-sdk's WebSocket server on 127.0.0.1 at this port (0: any free
                port), streaming every channel as the run goes (the caller stops it); None: none.

        Raises:
            UsageError: If the server cannot start (the port is taken), naming the port.
        """
        if live_port is None:
            self._pacer = Pacer(rate)
            return None
        try:
            server = live.serve(self._context, live_port, f"cosmos {Path(self.program).name}")
        except RuntimeError as error:  # the SDK's error for a port it cannot bind
            raise UsageError(f"127.0.0.1:{live_port}: cannot serve the live view ({error})") from None
        self._pacer = Pacer(rate, self._write_states, self._repeat_scene)
        self._pacer.on_time = server.broadcast_time
        self.live_server = server
        return server

    def flush(self) -> None:
        """Hand everything so far to the OS (pending states, the open chunk) and ask for an fsync.

        Raises:
            UsageError: If a write to the file failed (since the last check).
        """
        self._flush_states()

    def _flush_states(self) -> None:
        """Hand pending states and the open chunk to the OS (what a SIGKILL keeps); ask for an fsync."""
        if self._closed:
            raise ValueError(f"{self.path}: the run log is closed")
        self._write_states()
        self._writer.flush()
        self._flush_due = self._last_ns / 1e9 + self._flush_every_s
        self._sink.sync()
        self._sink.check()

    def close(self) -> None:
        """Write the summary and footer and close the file; later calls do nothing.

        Raises:
            UsageError: If a write to the file failed and no flush has said so yet.
        """
        if self._closed:
            return
        if self.live_server is not None:
            self.live_server.stop()
        try:
            self._write_states()
            self._writer.close()
            self._sink.sync()
        finally:
            self._closed = True
            self._at_exit.detach()
            for channel in self._channels:
                channel.close()
            for typed in self._typed_channels:
                typed.close()
            if self._ros2 is not None:
                self._ros2.close()
            self._sink.close()
        if not self._sink.reported:
            self._sink.check()

    def __enter__(self) -> RunLog:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self.close()
