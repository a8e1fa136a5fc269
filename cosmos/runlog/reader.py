"""Read a run log back: :func:`read_log` turns an MCAP file into a :class:`RunRecord`."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from cosmos.errors import CosmosError
from cosmos.runlog import limits, validate
from cosmos.runlog.messages import LOG_FORMAT
from cosmos.runlog.printable import printable
from cosmos.runlog.scan import McapContents, load_mcap
from cosmos.runlog.schemas import (
    DEFAULT_JOINTS,
    EVENT_TOPIC,
    METADATA_NAME,
    SEGMENT_TOPIC,
    STATE_TOPIC,
    state_vectors,
)

R = TypeVar("R")
Json = dict[str, Any]

_MAX_KIND_CHARS = 64  # an event kind is a short word; new kinds are read, not refused


@dataclass(frozen=True)
class SegmentRecord:
    """A segment as logged when it started (see docs/log-format.md for units and frames)."""

    t: float
    segment: int
    line: int
    statement: str
    kind: str
    frame: tuple[float, ...]  # (4,) w x y z
    motion_axes: tuple[int, ...]  # (6,) 1 motion, 0 force
    force_setpoint: tuple[float, ...]  # (6,)
    stiffness: tuple[float, ...]  # (6,)
    damping: tuple[float, ...]  # (6,)
    goal: tuple[float, ...] | None  # (3,) or (7,)
    speed_limit: float | None
    timeout: float | None

    @property
    def force_controlled_translation(self) -> bool:
        """Whether a translational axis of the task frame is force-controlled."""
        return 0 in self.motion_axes[:3]


@dataclass(frozen=True)
class EventRecord:
    """An event as logged: a statement starts or ends, a contact, a collision, a warning."""

    t: float
    kind: str
    line: int
    statement: str
    reason: str
    context: str = ""
    """Where an expanded statement came from (``"PROC probe called at line 5"``); "" at top level."""


@dataclass(frozen=True)
class StateSeries:
    """The state samples of a run, in time order; arrays are read-only.

    Values that were not finite when logged are NaN.
    """

    t: np.ndarray  # (n,) [s]
    q: np.ndarray  # (n, joints) [rad]
    qd: np.ndarray  # (n, joints) [rad/s]
    tau: np.ndarray  # (n, joints) [N m]
    x: np.ndarray  # (n, 3) world [m]
    quat: np.ndarray  # (n, 4) world, w x y z
    v: np.ndarray  # (n, 6) world, linear [m/s] then angular [rad/s]
    wrench: np.ndarray  # (n, 6) applied by the tool, world, [N] then [N m]
    segment: np.ndarray  # (n,) int
    line: np.ndarray  # (n,) int
    fingers: np.ndarray | None = None  # (n, 2) each pad from the gripper's centre [m]; None: no gripper
    finger_force: np.ndarray | None = None  # (n, 2) the pads' forces, left and right [N]; None: no gripper

    def __len__(self) -> int:
        return int(self.t.shape[0])

    @property
    def force_magnitude(self) -> np.ndarray:
        """Magnitude of the force the tool applies [N], one per sample (inf past the largest float)."""
        with np.errstate(over="ignore"):  # hypot: no overflow in the squares of a huge (logged) force
            return np.hypot(np.hypot(self.wrench[:, 0], self.wrench[:, 1]), self.wrench[:, 2])


@dataclass(frozen=True)
class ChannelInfo:
    """One channel of a log as ``mcap info`` lists it.

    Attributes:
        topic: Its topic.
        schema: Its schema's name ("" if none).
        encoding: Message encoding (json, protobuf, cdr).
        messages: Messages read.
        first_ns: Log time of the first [ns] (0 if none).
        last_ns: Log time of the last [ns] (0 if none).
    """

    topic: str
    schema: str
    encoding: str
    messages: int
    first_ns: int
    last_ns: int

    @property
    def rate_hz(self) -> float:
        """Messages per second of log time between the first and the last (0 if under two)."""
        span = self.last_ns - self.first_ns
        return (self.messages - 1) / (span / 1e9) if self.messages > 1 and span > 0 else 0.0


@dataclass(frozen=True)
class RunRecord:
    """Everything a run log holds that cosmos reads.

    Attributes:
        path: The file read.
        metadata: The ``cosmos`` metadata record (program, versions, rates, model, seed, ...).
        source: Program text from the attachment, if present.
        source_name: Name of that attachment.
        segments: Segments in order of start.
        events: Events in time order.
        state: State samples.
        message_counts: Messages read per topic.
        truncated: True if the file was cut short (no footer) or damaged; what
            precedes the cut was read.
        readable_bytes: Bytes of the file that were read.
        total_bytes: Size of the file.
        channels: Every channel read, with its schema, encoding, count and times.
        chunks: Per compression, the chunks read: count, compressed and uncompressed bytes.
    """

    path: Path
    metadata: Mapping[str, str]
    source: str | None
    source_name: str | None
    segments: tuple[SegmentRecord, ...]
    events: tuple[EventRecord, ...]
    state: StateSeries
    message_counts: Mapping[str, int]
    truncated: bool
    readable_bytes: int
    total_bytes: int
    channels: tuple[ChannelInfo, ...] = ()
    chunks: Mapping[str, tuple[int, int, int]] = field(default_factory=dict)

    @property
    def end_time(self) -> float:
        """Simulated time of the last state, segment or event [s] (0 if none)."""
        times = [0.0]
        if len(self.state):
            times.append(float(self.state.t[-1]))
        times += [s.t for s in self.segments[-1:]] + [e.t for e in self.events[-1:]]
        return max(times)


def read_log(path: Path | str) -> RunRecord:
    """Read a cosmos run log, complete or cut short, checking every message it uses.

    A file without a footer (a killed run) is read up to its last complete
    record and flagged ``truncated``. The file is untrusted: its size, records
    and messages are capped (:mod:`cosmos.runlog.limits`) and every cosmos
    message is checked against its schema (:mod:`cosmos.runlog.validate`).

    Raises:
        UsageError: If the file does not exist.
        CosmosError: If it is not an MCAP file, not a cosmos log, past a cap, or
            holds a message that does not match its schema (one line naming it).
    """
    path = Path(path)
    return run_record(path, load_mcap(path))


def run_record(path: Path, contents: McapContents) -> RunRecord:
    """The :class:`RunRecord` of what :func:`~cosmos.runlog.scan.load_mcap` read from ``path``.

    Raises:
        CosmosError: As :func:`read_log`.
    """
    topics = {cid: channel.topic for cid, channel in contents.channels.items()}
    records = [m for m in contents.metadata if m.name == METADATA_NAME]
    if not records and STATE_TOPIC not in topics.values():
        if not contents.complete and not contents.messages:
            raise CosmosError(
                f"{path}: cut short before any cosmos data was written "
                f"({contents.readable_bytes} of {contents.total_bytes} bytes readable)"
            )
        raise CosmosError(
            f"{path}: not a cosmos run log (no '{METADATA_NAME}' metadata and no {STATE_TOPIC} channel)"
        )
    metadata = _metadata(path, records[0].metadata if records else {})
    _check_format(path, metadata)
    by_topic: dict[str, list[bytes]] = {}
    for message in contents.messages:
        by_topic.setdefault(topics[message.channel_id], []).append(message.data)
    source, source_name = _source(contents, metadata)
    events = _checked(path, EVENT_TOPIC, by_topic, _event)
    segments = _checked(path, SEGMENT_TOPIC, by_topic, _segment)
    return RunRecord(
        path=path,
        metadata=metadata,
        source=source,
        source_name=source_name,
        segments=tuple(sorted(segments, key=lambda s: s.t)),
        events=tuple(sorted(events, key=lambda e: e.t)),
        state=_state(
            path, by_topic.get(STATE_TOPIC, []), _joints(path, metadata), metadata.get("fingers") == "2"
        ),
        message_counts={topic: len(data) for topic, data in by_topic.items()},
        truncated=not contents.complete,
        readable_bytes=contents.readable_bytes,
        total_bytes=contents.total_bytes,
        channels=_channels(contents),
        chunks=dict(contents.chunks),
    )


def _channels(contents: McapContents) -> tuple[ChannelInfo, ...]:
    """Per channel with messages, its schema, encoding, count and first and last log times."""
    times: dict[int, list[int]] = {}
    for message in contents.messages:
        span = times.setdefault(message.channel_id, [message.log_time, message.log_time, 0])
        span[0], span[1], span[2] = (
            min(span[0], message.log_time),
            max(span[1], message.log_time),
            span[2] + 1,
        )
    out = []
    for cid, (first, last, count) in times.items():
        channel = contents.channels[cid]
        schema = contents.schemas.get(channel.schema_id)
        name = printable(schema.name[:200]) if schema is not None else ""
        out.append(
            ChannelInfo(
                printable(channel.topic[:200]),
                name,
                printable(channel.message_encoding[:40]),
                count,
                first,
                last,
            )
        )
    return tuple(sorted(out, key=lambda c: c.topic))


def _check_format(path: Path, metadata: Mapping[str, str]) -> None:
    """Refuse a log of a newer format than this cosmos reads, saying which cosmos wrote it."""
    written = metadata.get("log_format", "1")
    if not (written.isdigit() and int(written) <= LOG_FORMAT):
        version = metadata.get("cosmos_version", "a newer cosmos")
        raise CosmosError(
            f"{path}: log format {written[:20]} (written by cosmos {version[:40]}); this cosmos "
            f"reads formats 1 to {LOG_FORMAT}: read it with a cosmos of that version or later"
        )


def _metadata(path: Path, metadata: Mapping[str, str]) -> dict[str, str]:
    """The ``cosmos`` metadata record, lengths checked and control characters replaced."""
    for key, value in metadata.items():
        if len(key) > limits.MAX_TEXT_CHARS or len(value) > limits.MAX_TEXT_CHARS:
            name = repr(printable(key[:40]))
            raise CosmosError(
                f"{path}: metadata '{METADATA_NAME}': {name} is longer than "
                f"{limits.MAX_TEXT_CHARS:,} characters"
            )
    return {printable(key): printable(value) for key, value in metadata.items()}


def _source(contents: McapContents, metadata: Mapping[str, str]) -> tuple[str | None, str | None]:
    """The program text attached (raw: it is compiled, never printed as is) and its name."""
    texts = [a for a in contents.attachments if a.media_type.startswith("text/")]
    program_name = Path(metadata.get("program", "")).name
    chosen = next((a for a in texts if printable(a.name) == program_name), texts[0] if texts else None)
    if chosen is None:
        return None, None
    return chosen.data.decode(errors="replace"), printable(chosen.name[: limits.MAX_TEXT_CHARS])


def _checked(
    path: Path, topic: str, by_topic: Mapping[str, Sequence[bytes]], build: Callable[[Json], R]
) -> list[R]:
    return validate.records(
        _where(path, topic), by_topic.get(topic, []), build, limits.MAX_STATEMENT_MESSAGES
    )


def _where(path: Path, topic: str) -> Callable[[int], str]:
    return lambda n: f"{path}: {topic} message {n}"


def _segment(m: Json) -> SegmentRecord:
    goal = None if m.get("goal") is None else validate.vector(m, "goal", (3, 7))
    return SegmentRecord(
        t=validate.time(m),
        segment=validate.count(m, "segment", limits.MAX_SEGMENT),
        line=validate.count(m, "line", limits.MAX_LINE),
        statement=validate.text(m, "statement"),
        kind=validate.text(m, "kind"),
        frame=validate.vector(m, "frame", (4,)),
        motion_axes=validate.axes(m, "motion_axes"),
        force_setpoint=validate.vector(m, "force_setpoint", (6,)),
        stiffness=validate.vector(m, "stiffness", (6,)),
        damping=validate.vector(m, "damping", (6,)),
        goal=goal,
        speed_limit=validate.optional_number(m, "speed_limit"),
        timeout=validate.optional_number(m, "timeout"),
    )


def _event(m: Json) -> EventRecord:
    kind = validate.text(m, "kind")
    if len(kind) > _MAX_KIND_CHARS:
        raise validate.Invalid(f"kind is longer than {_MAX_KIND_CHARS} characters")
    return EventRecord(
        t=validate.time(m),
        kind=kind,
        line=validate.count(m, "line", limits.MAX_LINE),
        statement=validate.text(m, "statement"),
        reason=validate.text(m, "reason", default=""),
        context=validate.text(m, "context", default=""),  # "" in logs written before it was
    )


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


MAX_JOINTS = 12
"""The most joints a log's arm may have (metadata ``joints``)."""


def _joints(path: Path, metadata: Mapping[str, str]) -> int:
    """The arm's number of joints from the metadata (six if it does not say: logs before the Panda)."""
    text = metadata.get("joints", str(DEFAULT_JOINTS))
    if not (text.isdigit() and 1 <= int(text) <= MAX_JOINTS):
        raise CosmosError(
            f"{path}: metadata '{METADATA_NAME}': joints is {text[:20]!r}, not a count from 1 to {MAX_JOINTS}"
        )
    return int(text)


def _state(path: Path, data: Sequence[bytes], joints: int, fingers: bool) -> StateSeries:
    if len(data) > limits.MAX_MESSAGES:
        raise CosmosError(f"{path}: more than {limits.MAX_MESSAGES:,} {STATE_TOPIC} messages")
    t, rows, labels = validate.state_arrays(_where(path, STATE_TOPIC), data, joints, fingers)
    order = np.argsort(t, kind="stable")
    columns, start = {}, 0
    for name, n in state_vectors(joints, fingers):
        columns[name] = _read_only(np.ascontiguousarray(rows[order, start : start + n]))
        start += n
    return StateSeries(
        t=_read_only(t[order]),
        segment=_read_only(labels[order, 0].copy()),
        line=_read_only(labels[order, 1].copy()),
        **columns,
    )
