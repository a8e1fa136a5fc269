"""Message builders of the run log: metadata record, segment, event and its ``/log`` line.

Also :func:`log_time_ns`, the time stamp of every message.

Each builder checks its inputs and returns what :class:`cosmos.runlog.writer.RunLog`
writes; none of them touches the file.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from datetime import UTC, datetime
from typing import Final

import numpy as np
from numpy.typing import ArrayLike

from cosmos import __version__
from cosmos.plan.context import origin
from cosmos.runlog.foxglove import LogLevel
from cosmos.runlog.schemas import EventKind

_EVENT_LEVELS: Final = {
    EventKind.FAILED: LogLevel.ERROR,
    EventKind.COLLISION: LogLevel.WARNING,
    EventKind.WARNING: LogLevel.WARNING,
    EventKind.PROTECTIVE_STOP: LogLevel.ERROR,
    EventKind.INTERRUPTED: LogLevel.WARNING,
    EventKind.RECOVERY: LogLevel.WARNING,
}


def log_time_ns(t: float) -> int:
    """MCAP ``log_time`` of simulated time ``t`` [s]: ``round(t * 1e9)`` ns since the start."""
    return round(t * 1e9)


def _exact(value: float) -> str:
    """The shortest text that reads back as exactly ``value`` (``1000``, ``333.3333``)."""
    short = f"{value:g}"
    return short if float(short) == value else repr(float(value))


def _vector(value: ArrayLike, n: int, name: str) -> list[float]:
    array = np.asarray(value, dtype=float).reshape(-1)
    if array.shape != (n,):
        raise ValueError(f"{name} must have {n} components, got {array.size}")
    return array.tolist()


def _optional(value: float | None) -> float | None:
    return None if value is None or not np.isfinite(value) else float(value)


LOG_FORMAT = 2
"""Version of what the log holds (docs/log-format.md): 2 writes the Foxglove channels as protobuf;
1 (no ``log_format`` key) wrote them as JSON. The reader reads both and refuses a newer one."""


def metadata_record(
    *,
    program: str,
    servo_hz: float,
    param_hz: float,
    state_hz: float,
    model: str,
    seed: int,
    metadata: Mapping[str, str] | None,
) -> dict[str, str]:
    """The ``cosmos`` metadata record of a run (arguments as for ``RunLog``).

    Raises:
        TypeError: If ``metadata`` holds a key or value that is not a str.
    """
    record = {
        "program": program,
        "cosmos_version": __version__,
        "log_format": str(LOG_FORMAT),
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
    return record


def segment_message(
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
    goal: ArrayLike | None,
    speed_limit: float | None,
    timeout: float | None,
) -> bytes:
    """JSON of a ``/cosmos/segment`` message (arguments as for ``RunLog.segment``).

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
    return json.dumps(message, allow_nan=False).encode()


def event_kind(kind: str) -> EventKind:
    """``kind`` as an :class:`EventKind`.

    Raises:
        ValueError: If ``kind`` is not an event kind.
    """
    try:
        return EventKind(kind)
    except ValueError:
        known = ", ".join(k.value for k in EventKind)
        raise ValueError(f"event kind must be one of {known}; got {kind!r}") from None


def event_message(
    t: float, kind: EventKind, line: int, statement: str, reason: str, context: str = ""
) -> bytes:
    """JSON of a ``/cosmos/event`` message."""
    message = {
        "t": t,
        "kind": kind.value,
        "line": line,
        "statement": statement,
        "reason": reason,
        "context": context,
    }
    return json.dumps(message).encode()


def event_log_line(kind: EventKind, statement: str, reason: str, context: str = "") -> tuple[LogLevel, str]:
    """Level and text of the ``/log`` line that shows an event in Foxglove."""
    text = f"{kind.value}: {statement}" + (f": {reason}" if reason else "") + origin(context)
    return _EVENT_LEVELS.get(kind, LogLevel.INFO), text
