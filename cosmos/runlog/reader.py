"""Read a run log back: :func:`read_log` turns an MCAP file into a :class:`RunRecord`."""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from cosmos.errors import CosmosError
from cosmos.runlog.scan import McapContents, load_mcap
from cosmos.runlog.schemas import (
    EVENT_TOPIC,
    METADATA_NAME,
    SEGMENT_TOPIC,
    STATE_TOPIC,
    STATE_VECTORS,
)

R = TypeVar("R")
Json = dict[str, Any]


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


@dataclass(frozen=True)
class StateSeries:
    """The state samples of a run, in time order; arrays are read-only.

    Values that were not finite when logged are NaN.
    """

    t: np.ndarray  # (n,) [s]
    q: np.ndarray  # (n, 6) [rad]
    qd: np.ndarray  # (n, 6) [rad/s]
    tau: np.ndarray  # (n, 6) [N m]
    x: np.ndarray  # (n, 3) world [m]
    quat: np.ndarray  # (n, 4) world, w x y z
    v: np.ndarray  # (n, 6) world, linear [m/s] then angular [rad/s]
    wrench: np.ndarray  # (n, 6) applied by the tool, world, [N] then [N m]
    segment: np.ndarray  # (n,) int
    line: np.ndarray  # (n,) int

    def __len__(self) -> int:
        return int(self.t.shape[0])

    @property
    def force_magnitude(self) -> np.ndarray:
        """Magnitude of the force the tool applies [N], one per sample."""
        return np.linalg.norm(self.wrench[:, :3], axis=1)


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

    @property
    def end_time(self) -> float:
        """Simulated time of the last state, segment or event [s] (0 if none)."""
        times = [0.0]
        if len(self.state):
            times.append(float(self.state.t[-1]))
        times += [s.t for s in self.segments[-1:]] + [e.t for e in self.events[-1:]]
        return max(times)


def read_log(path: Path | str) -> RunRecord:
    """Read a cosmos run log, complete or cut short.

    A complete file is read through its summary; a file without one (a killed
    run) is read up to its last complete record and flagged ``truncated``.

    Raises:
        UsageError: If the file does not exist.
        CosmosError: If it is not an MCAP file, not a cosmos log, or holds a
            message that does not decode.
    """
    path = Path(path)
    contents = load_mcap(path)
    topics = {cid: channel.topic for cid, channel in contents.channels.items()}
    metadata = next((m.metadata for m in contents.metadata if m.name == METADATA_NAME), None)
    if metadata is None and STATE_TOPIC not in topics.values():
        if not contents.complete and not contents.messages:
            raise CosmosError(
                f"{path}: cut short before any cosmos data was written "
                f"({contents.readable_bytes} of {contents.total_bytes} bytes readable)"
            )
        raise CosmosError(
            f"{path}: not a cosmos run log (no '{METADATA_NAME}' metadata and no {STATE_TOPIC} channel)"
        )
    by_topic: dict[str, list[bytes]] = {}
    for message in contents.messages:
        by_topic.setdefault(topics[message.channel_id], []).append(message.data)
    source, source_name = _source(contents, metadata or {})
    events = _records(path, EVENT_TOPIC, by_topic.get(EVENT_TOPIC, []), _event)
    segments = _records(path, SEGMENT_TOPIC, by_topic.get(SEGMENT_TOPIC, []), _segment)
    return RunRecord(
        path=path,
        metadata=dict(metadata or {}),
        source=source,
        source_name=source_name,
        segments=tuple(sorted(segments, key=lambda s: s.t)),
        events=tuple(sorted(events, key=lambda e: e.t)),
        state=_state(path, _decode(path, STATE_TOPIC, by_topic.get(STATE_TOPIC, []))),
        message_counts={topic: len(data) for topic, data in by_topic.items()},
        truncated=not contents.complete,
        readable_bytes=contents.readable_bytes,
        total_bytes=contents.total_bytes,
    )


def _source(contents: McapContents, metadata: Mapping[str, str]) -> tuple[str | None, str | None]:
    texts = [a for a in contents.attachments if a.media_type.startswith("text/")]
    program_name = Path(metadata.get("program", "")).name
    chosen = next((a for a in texts if a.name == program_name), texts[0] if texts else None)
    if chosen is None:
        return None, None
    return chosen.data.decode(errors="replace"), chosen.name


def _decode_one(path: Path, topic: str, index: int, data: bytes) -> Any:
    try:
        return json.loads(data)
    except ValueError as error:
        raise CosmosError(f"{path}: message {index} on {topic} is not JSON: {error}") from None


def _decode(path: Path, topic: str, data: Sequence[bytes]) -> list[Json]:
    """JSON-decode the messages of one topic (all at once; one by one to find a bad one)."""
    try:
        decoded = json.loads(b"[" + b",".join(data) + b"]")
    except ValueError:
        decoded = [_decode_one(path, topic, i, item) for i, item in enumerate(data)]
    if not all(isinstance(m, dict) for m in decoded):
        raise CosmosError(f"{path}: a message on {topic} is not a JSON object")
    return decoded


def _records(path: Path, topic: str, data: Sequence[bytes], build: Callable[[Json], R]) -> list[R]:
    try:
        return [build(m) for m in _decode(path, topic, data)]
    except KeyError as error:
        raise CosmosError(f"{path}: a {topic} message has no field {error}") from None
    except (TypeError, ValueError) as error:
        raise CosmosError(f"{path}: a {topic} message is malformed: {error}") from None


def _floats(values: Sequence[Any] | None) -> tuple[float, ...] | None:
    return None if values is None else tuple(float(v) for v in values)


def _segment(m: dict[str, Any]) -> SegmentRecord:
    return SegmentRecord(
        t=float(m["t"]),
        segment=int(m["segment"]),
        line=int(m["line"]),
        statement=str(m["statement"]),
        kind=str(m["kind"]),
        frame=tuple(float(v) for v in m["frame"]),
        motion_axes=tuple(int(v) for v in m["motion_axes"]),
        force_setpoint=tuple(float(v) for v in m["force_setpoint"]),
        stiffness=tuple(float(v) for v in m["stiffness"]),
        damping=tuple(float(v) for v in m["damping"]),
        goal=_floats(m.get("goal")),
        speed_limit=None if m.get("speed_limit") is None else float(m["speed_limit"]),
        timeout=None if m.get("timeout") is None else float(m["timeout"]),
    )


def _event(m: dict[str, Any]) -> EventRecord:
    return EventRecord(
        t=float(m["t"]),
        kind=str(m["kind"]),
        line=int(m["line"]),
        statement=str(m["statement"]),
        reason=str(m.get("reason", "")),
    )


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


def _state(path: Path, messages: list[dict[str, Any]]) -> StateSeries:
    try:
        t = np.array([m["t"] for m in messages], dtype=float)
        order = np.argsort(t, kind="stable")
        columns = {
            name: np.array([m[name] for m in messages], dtype=float).reshape(-1, n)[order]
            for name, n in STATE_VECTORS
        }
        segment = np.array([m["segment"] for m in messages], dtype=np.int64)[order]
        line = np.array([m["line"] for m in messages], dtype=np.int64)[order]
    except KeyError as error:
        raise CosmosError(f"{path}: a {STATE_TOPIC} message has no field {error}") from None
    except (TypeError, ValueError) as error:
        raise CosmosError(f"{path}: a {STATE_TOPIC} message is malformed: {error}") from None
    return StateSeries(
        t=_read_only(t[order]),
        segment=_read_only(segment),
        line=_read_only(line),
        **{name: _read_only(array) for name, array in columns.items()},
    )
