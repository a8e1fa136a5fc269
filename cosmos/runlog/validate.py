"""Messages of the cosmos channels checked against their schemas before anything uses them.

Every ``/cosmos/state``, ``/cosmos/segment`` and ``/cosmos/event`` message is
decoded as JSON (size capped; nesting bounded by the parser's recursion limit
and then by the schema, which allows two levels) and each field is checked for
its type and range (docs/log-format.md). A message that fails names itself in
one line: ``run.mcap: /cosmos/state message 1204: line is not an integer``
(messages count from 1 per channel, in file order). Text fields are returned
with control characters replaced (:func:`cosmos.runlog.printable.printable`).

State messages, the many, are checked in bulk with NumPy; a batch that does
not pass the bulk check is checked message by message, which finds the first
bad one (or reads non-finite values written as ``null``).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from typing import Any, Final, NoReturn

import numpy as np

from cosmos.errors import CosmosError
from cosmos.runlog import limits
from cosmos.runlog.printable import printable
from cosmos.runlog.schemas import DEFAULT_JOINTS, state_vectors, state_width

Json = dict[str, Any]

_BATCH: Final = 50_000  # state messages decoded together (bounds the memory of the dicts)
_NON_JSON: Final = (b"true", b"false", b"NaN", b"Infinity")  # never in a valid state message


class Invalid(Exception):
    """A field that does not match its schema; the message says which and why."""


def _reject_constant(name: str) -> NoReturn:
    raise ValueError(f"{name} is not a JSON number")


def decode(data: bytes, cap: int = limits.MAX_MESSAGE_BYTES) -> Json:
    """One message as a JSON object.

    Raises:
        Invalid: If it is larger than ``cap`` bytes, not JSON, nested too deeply, or not an object.
    """
    if len(data) > cap:
        raise Invalid(f"{len(data):,} bytes, more than the {cap:,} a message may have")
    try:
        value = json.loads(data, parse_constant=_reject_constant)
    except RecursionError:
        raise Invalid("JSON nested too deeply") from None
    except ValueError as error:  # UnicodeDecodeError and too many digits included
        raise Invalid(f"not JSON ({printable(str(error))[:120]})") from None
    if not isinstance(value, dict):
        raise Invalid("not a JSON object")
    return value


def _field(m: Json, name: str) -> Any:
    try:
        return m[name]
    except KeyError:
        raise Invalid(f"has no field '{name}'") from None


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def number(m: Json, name: str, low: float = -math.inf, high: float = math.inf) -> float:
    """A finite number in ``[low, high]``."""
    value = _field(m, name)
    if not _is_number(value):
        raise Invalid(f"{name} is not a number")
    try:
        as_float = float(value)
    except OverflowError:
        raise Invalid(f"{name} is not a finite number") from None
    if not math.isfinite(as_float):
        raise Invalid(f"{name} is not a finite number")
    if not low <= as_float <= high:
        raise Invalid(f"{name} is {as_float:g}, outside {low:g} .. {high:g}")
    return as_float


def optional_number(m: Json, name: str, low: float = 0.0) -> float | None:
    """``None`` (null or absent) or a finite number >= ``low``."""
    return None if m.get(name) is None else number(m, name, low)


def time(m: Json) -> float:
    """The message's ``t`` [s]."""
    return number(m, "t", 0.0, limits.MAX_TIME_S)


def count(m: Json, name: str, high: int) -> int:
    """An integer in ``[0, high]``."""
    value = _field(m, name)
    if not isinstance(value, int) or isinstance(value, bool):
        raise Invalid(f"{name} is not an integer")
    if not 0 <= value <= high:
        raise Invalid(f"{name} is outside 0 .. {high:,}")
    return value


def text(m: Json, name: str, default: str | None = None) -> str:
    """A string of at most ``MAX_TEXT_CHARS`` characters, control characters replaced."""
    value = m.get(name, default) if default is not None else _field(m, name)
    if not isinstance(value, str):
        raise Invalid(f"{name} is not a string")
    if len(value) > limits.MAX_TEXT_CHARS:
        raise Invalid(f"{name} is longer than {limits.MAX_TEXT_CHARS:,} characters")
    return printable(value)


def vector(m: Json, name: str, sizes: Sequence[int], nulls: bool = False) -> tuple[float, ...]:
    """A list of finite numbers of one of ``sizes`` lengths (``null`` read as NaN if ``nulls``)."""
    value = _field(m, name)
    if not isinstance(value, list) or len(value) not in sizes:
        expected = " or ".join(str(n) for n in sizes)
        raise Invalid(f"{name} is not a list of {expected} numbers")
    out = []
    for k, item in enumerate(value):
        if item is None and nulls:
            out.append(math.nan)
            continue
        if not _is_number(item):
            raise Invalid(f"{name}[{k}] is not a number")
        try:
            as_float = float(item)
        except OverflowError:
            as_float = math.inf
        if not math.isfinite(as_float):
            raise Invalid(f"{name}[{k}] is not a finite number")
        out.append(as_float)
    return tuple(out)


def axes(m: Json, name: str) -> tuple[int, ...]:
    """Six selection values, each 0 or 1."""
    value = _field(m, name)
    if (
        not isinstance(value, list)
        or len(value) != 6
        or any(type(v) is not int or v not in (0, 1) for v in value)
    ):
        raise Invalid(f"{name} is not a list of six 0/1 values")
    return tuple(value)


def records(
    where: Callable[[int], str], data: Sequence[bytes], build: Callable[[Json], Any], cap: int
) -> list[Any]:
    """Decode and check every message of a channel with ``build``.

    Args:
        where: ``where(n)`` names message ``n`` (from 1) in an error.
        data: The messages, in file order.
        build: Turns a decoded message into a record; raises :class:`Invalid`.
        cap: Most messages accepted.

    Raises:
        CosmosError: Naming the first message that fails, and why.
    """
    if len(data) > cap:
        raise CosmosError(f"{where(cap + 1)}: more than {cap:,} messages on this channel")
    out = []
    for n, item in enumerate(data, start=1):
        try:
            out.append(build(decode(item)))
        except Invalid as error:
            raise CosmosError(f"{where(n)}: {error}") from None
    return out


def state_row(
    m: Json, joints: int = DEFAULT_JOINTS, fingers: bool = False
) -> tuple[float, list[float], int, int]:
    """Time, the 3 joints + 19 vector components (+ 4 of the fingers; null as NaN), segment and line."""
    t = time(m)
    row: list[float] = []
    for name, n in state_vectors(joints, fingers):
        row += vector(m, name, (n,), nulls=True)
    return t, row, count(m, "segment", limits.MAX_SEGMENT), count(m, "line", limits.MAX_LINE)


StateArrays = tuple[np.ndarray, np.ndarray, np.ndarray]  # t (n,), rows (n, 3 joints + 19), labels (n, 2)


def _bulk(messages: list[Any], joints: int, fingers: bool) -> StateArrays | None:
    """The arrays of a batch of decoded state messages if all pass the bulk check, else None."""
    n = len(messages)
    vectors = state_vectors(joints, fingers)
    if not all(type(m) is dict for m in messages):
        return None
    try:
        t = np.array([m["t"] for m in messages])
        columns = [np.array([m[name] for m in messages]) for name, _ in vectors]
        labels = np.array([[m["segment"], m["line"]] for m in messages])
    except (KeyError, ValueError, TypeError, OverflowError):
        return None
    if t.shape != (n,) or t.dtype.kind not in "fi" or labels.shape != (n, 2) or labels.dtype.kind != "i":
        return None
    for column, (_, size) in zip(columns, vectors, strict=True):
        if column.shape != (n, size) or column.dtype.kind not in "fi":
            return None
    rows = np.concatenate(columns, axis=1).astype(float) if n else np.empty((0, state_width(joints, fingers)))
    t = t.astype(float)
    if not (np.isfinite(rows).all() and np.isfinite(t).all()):
        return None
    if n and not (0 <= t.min() and t.max() <= limits.MAX_TIME_S):
        return None
    if n and not (
        labels.min() >= 0
        and labels[:, 0].max() <= limits.MAX_SEGMENT
        and labels[:, 1].max() <= limits.MAX_LINE
    ):
        return None
    return t, rows, labels.astype(np.int64)


def _one_by_one(
    where: Callable[[int], str], first: int, data: Sequence[bytes], joints: int, fingers: bool
) -> StateArrays:
    n = len(data)
    width = state_width(joints, fingers)
    t, rows, labels = np.empty(n), np.empty((n, width)), np.empty((n, 2), dtype=np.int64)
    for k, item in enumerate(data):
        try:
            t[k], rows[k], *label = state_row(decode(item), joints, fingers)
        except Invalid as error:
            raise CosmosError(f"{where(first + k)}: {error}") from None
        labels[k] = label
    return t, rows, labels


def state_arrays(
    where: Callable[[int], str], data: Sequence[bytes], joints: int = DEFAULT_JOINTS, fingers: bool = False
) -> StateArrays:
    """Times [s], vector rows and (segment, line) labels of every state message, in file order.

    ``joints`` is the arm's number of joints (the log's metadata ``joints``); ``fingers``: the
    messages have the gripper's fields (metadata ``fingers``).

    Raises:
        CosmosError: Naming the first message that fails, and why.
    """
    parts = []
    for first in range(0, len(data), _BATCH):
        batch = data[first : first + _BATCH]
        arrays = None
        if max(map(len, batch)) <= limits.MAX_MESSAGE_BYTES:
            blob = b"[" + b",".join(batch) + b"]"
            if not any(word in blob for word in _NON_JSON):
                try:
                    arrays = _bulk(json.loads(blob), joints, fingers)
                except (ValueError, RecursionError):
                    arrays = None
                if arrays is not None and len(arrays[0]) != len(batch):
                    arrays = None  # a message held more than one value (``1],[2``)
        parts.append(arrays if arrays is not None else _one_by_one(where, first + 1, batch, joints, fingers))
    if not parts:
        return np.empty(0), np.empty((0, state_width(joints, fingers))), np.empty((0, 2), dtype=np.int64)
    t_parts, row_parts, label_parts = zip(*parts, strict=True)
    return np.concatenate(t_parts), np.concatenate(row_parts), np.concatenate(label_parts)
