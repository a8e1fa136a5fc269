"""Crafted run logs: a valid MCAP structure (written with the ``mcap`` package) around hostile content.

:func:`write_log` writes a small, valid cosmos log (a few state, segment and
event messages, the ``cosmos`` metadata, a program attachment) in which any
message can be replaced by arbitrary bytes. :data:`FAMILIES` lists the crafted
logs the reader must refuse (each with the one line it must print) and
:data:`READABLE` those it must read (hostile text, made printable).
:func:`raw_chunk_log` writes chunks whose declared and real sizes are chosen
freely (decompression bombs).

Run as a script to write the corpus into a directory: ``python crafted_logs.py DIR``.
"""

from __future__ import annotations

import json
import struct
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import zstandard
from mcap.writer import CompressionType, Writer

STATE_TOPIC, SEGMENT_TOPIC, EVENT_TOPIC = "/cosmos/state", "/cosmos/segment", "/cosmos/event"
PROGRAM = "MOVE BY (0, 0, 30 mm)\nWAIT 0.2 s\n"
ESCAPES = "\x1b]0;owned\x07\x1b[2J\x1b[31mred\x9b1m\u202eevil\r"  # title, clear, colour, C1, RTL, CR


def state(k: int, **changes: Any) -> dict[str, Any]:
    """A valid state message (sample ``k`` at 250 Hz), with fields changed or removed (None)."""
    message: dict[str, Any] = {
        "t": k / 250,
        "q": [0.1 * k, 0.2, 0.3, 0.4, 0.5, 0.6],
        "qd": [0.0] * 6,
        "tau": [1.0] * 6,
        "x": [0.5, 0.1, 0.3],
        "quat": [1.0, 0.0, 0.0, 0.0],
        "v": [0.0] * 6,
        "wrench": [0.0, 0.0, -1.0, 0.0, 0.0, 0.0],
        "segment": 0,
        "line": 1,
    }
    message.update(changes)
    return {key: value for key, value in message.items() if value is not None}


def segment(**changes: Any) -> dict[str, Any]:
    """A valid segment message, with fields changed."""
    message: dict[str, Any] = {
        "t": 0.0,
        "segment": 0,
        "line": 1,
        "statement": "MOVE BY (0, 0, 30 mm)",
        "kind": "move",
        "frame": [1.0, 0.0, 0.0, 0.0],
        "motion_axes": [1, 1, 1, 1, 1, 1],
        "force_setpoint": [0.0] * 6,
        "stiffness": [100.0] * 6,
        "damping": [10.0] * 6,
        "goal": [0.5, 0.1, 0.33],
        "speed_limit": None,
        "timeout": None,
    }
    message.update(changes)
    return message


def event(**changes: Any) -> dict[str, Any]:
    """A valid event message, with fields changed."""
    message: dict[str, Any] = {"t": 0.0, "kind": "start", "line": 1, "statement": "MOVE BY (0, 0, 30 mm)"}
    message.update(changes)
    message.setdefault("reason", "")
    return message


def encode(message: dict[str, Any] | bytes) -> bytes:
    """JSON bytes of a message (bytes are taken as they are)."""
    return message if isinstance(message, bytes) else json.dumps(message).encode()


def metadata(**changes: str) -> dict[str, str]:
    """A valid ``cosmos`` metadata record, with entries changed."""
    record = {
        "program": "tiny.cos",
        "cosmos_version": "0.1.0",
        "servo_hz": "1000",
        "param_hz": "125",
        "state_hz": "250",
        "model": "puma560",
        "seed": "0",
    }
    record.update(changes)
    return record


def write_log(
    path: Path,
    *,
    states: Sequence[dict[str, Any] | bytes] | None = None,
    segments: Sequence[dict[str, Any] | bytes] | None = None,
    events: Sequence[dict[str, Any] | bytes] | None = None,
    scene: Sequence[dict[str, Any] | bytes] = (),
    meta: dict[str, str] | None = None,
    program: str | bytes = PROGRAM,
    compression: CompressionType = CompressionType.ZSTD,
    scene_encoding: str = "json",
) -> Path:
    """Write a complete cosmos-shaped log with the given messages (defaults: a valid run)."""
    states = [state(k) for k in range(20)] if states is None else states
    segments = [segment()] if segments is None else segments
    events = [event(), event(t=0.076, kind="done")] if events is None else events
    with open(path, "wb") as stream:
        writer = Writer(stream, compression=compression, chunk_size=64 * 1024)
        writer.start(profile="", library="crafted")
        writer.add_metadata("cosmos", meta if meta is not None else metadata())
        data = program if isinstance(program, bytes) else program.encode()
        writer.add_attachment(create_time=0, log_time=0, name="tiny.cos", media_type="text/plain", data=data)
        for topic, messages in (
            (SEGMENT_TOPIC, segments),
            (EVENT_TOPIC, events),
            (STATE_TOPIC, states),
            ("/scene", scene),
        ):
            encoding = scene_encoding if topic == "/scene" else "json"
            schema_encoding = "jsonschema" if encoding == "json" else encoding
            schema = writer.register_schema(name=topic, encoding=schema_encoding, data=b"{}")
            channel = writer.register_channel(topic=topic, message_encoding=encoding, schema_id=schema)
            for k, message in enumerate(messages):
                writer.add_message(channel, log_time=k * 4_000_000, data=encode(message), publish_time=0)
        writer.finish()
    return path


def raw_chunk_log(path: Path, declared: int, real: int, compression: bytes = b"zstd") -> Path:
    """A log whose one chunk declares ``declared`` bytes and decompresses to ``real`` zero bytes.

    The zeros are compressed as a stream, so a bomb of gigabytes takes little time and memory here.
    """
    header = struct.pack("<BQ", 0x01, 8) + struct.pack("<I", 0) + struct.pack("<I", 0)
    compressor = zstandard.ZstdCompressor(level=3).compressobj()
    block = bytes(1 << 20)
    parts = [compressor.compress(block) for _ in range(real >> 20)]
    parts.append(compressor.compress(bytes(real & ((1 << 20) - 1))))
    parts.append(compressor.flush())
    body = b"".join(parts)
    chunk = struct.pack("<QQQI", 0, 0, declared, 0)
    chunk += struct.pack("<I", len(compression)) + compression + struct.pack("<Q", len(body)) + body
    record = struct.pack("<BQ", 0x06, len(chunk)) + chunk
    path.write_bytes(b"\x89MCAP0\r\n" + header + record)
    return path


@dataclass(frozen=True)
class Family:
    """A crafted log the reader must refuse, and what its one line must say."""

    name: str
    write: Callable[[Path], Path]
    says: str  # after "<path>: "


def _bad_state(at: int, message: dict[str, Any] | bytes, n: int = 30) -> Callable[[Path], Path]:
    return lambda p: write_log(p, states=[message if k == at else state(k) for k in range(n)])


DEEP = b'{"t": 0.0, "q": ' + b"[" * 100_000 + b"]" * 100_000 + b"}"

FAMILIES: tuple[Family, ...] = (
    Family(
        "state-1204-line-1e400",
        _bad_state(1203, encode(state(1203)).replace(b'"line": 1', b'"line": 1e400'), 1300),
        "/cosmos/state message 1204: line is not an integer",
    ),
    Family(
        "state-line-true",
        _bad_state(5, state(5, line=True)),
        "/cosmos/state message 6: line is not an integer",
    ),
    Family(
        "state-q-1e400",
        _bad_state(5, encode(state(5)).replace(b'"q": [0.5', b'"q": [1e400')),
        "/cosmos/state message 6: q[0] is not a finite number",
    ),
    Family(
        "state-line-1e400",
        _bad_state(5, encode(state(5)).replace(b'"line": 1', b'"line": 1e400')),
        "/cosmos/state message 6: line is not an integer",
    ),
    Family(
        "state-line-10**30",
        _bad_state(5, state(5, line=10**30)),
        "/cosmos/state message 6: line is outside 0 .. 10,000,000",
    ),
    Family(
        "state-t-1e400",
        _bad_state(0, encode(state(0)).replace(b'"t": 0.0', b'"t": 1e400')),
        "/cosmos/state message 1: t is not a finite number",
    ),
    Family("state-t-negative", _bad_state(2, state(2, t=-1.0)), "/cosmos/state message 3: t is -1, outside"),
    Family(
        "state-q-string",
        _bad_state(3, state(3, q=["1", 0, 0, 0, 0, 0])),
        "/cosmos/state message 4: q[0] is not a number",
    ),
    Family(
        "state-q-bool",
        _bad_state(3, state(3, q=[True, 0, 0, 0, 0, 0])),
        "/cosmos/state message 4: q[0] is not a number",
    ),
    Family(
        "state-q-short",
        _bad_state(7, state(7, q=[0.0] * 5)),
        "/cosmos/state message 8: q is not a list of 6 numbers",
    ),
    Family(
        "state-q-nested",
        _bad_state(7, state(7, q=[[0.0]] * 6)),
        "/cosmos/state message 8: q[0] is not a number",
    ),
    Family(
        "state-no-wrench",
        _bad_state(9, state(9, wrench=None)),
        "/cosmos/state message 10: has no field 'wrench'",
    ),
    Family(
        "state-nan-literal",
        _bad_state(4, encode(state(4)).replace(b'"t": 0.016', b'"t": NaN')),
        "/cosmos/state message 5: not JSON",
    ),
    Family(
        "state-huge-digits",
        _bad_state(4, encode(state(4)).replace(b'"line": 1', b'"line": 1' + b"0" * 5000)),
        "/cosmos/state message 5: not JSON",
    ),
    Family("state-deep-json", _bad_state(6, DEEP), "/cosmos/state message 7: JSON nested too deeply"),
    Family("state-not-object", _bad_state(6, b"[1, 2, 3]"), "/cosmos/state message 7: not a JSON object"),
    Family(
        "state-two-values",
        _bad_state(6, encode(state(6)) + b"," + encode(state(7))),
        "/cosmos/state message 7: not JSON",
    ),
    Family("state-not-utf8", _bad_state(6, b'{"t": "\xff"}'), "/cosmos/state message 7: not JSON"),
    Family(
        "state-huge-message",
        _bad_state(1, encode(state(1, pad="x" * 1_100_000))),
        "/cosmos/state message 2: 1,100,",
    ),
    Family(
        "event-line-10**30",
        lambda p: write_log(p, events=[event(), event(line=10**30)]),
        "/cosmos/event message 2: line is outside 0 .. 10,000,000",
    ),
    Family(
        "event-line-1e400",
        lambda p: write_log(p, events=[b'{"t":0,"kind":"start","line":1e400,"statement":""}']),
        "/cosmos/event message 1: line is not an integer",
    ),
    Family(
        "event-kind-long",
        lambda p: write_log(p, events=[event(kind="k" * 100)]),
        "/cosmos/event message 1: kind is longer than 64 characters",
    ),
    Family(
        "event-deep-json",
        lambda p: write_log(p, events=[DEEP]),
        "/cosmos/event message 1: JSON nested too deeply",
    ),
    Family(
        "event-statement-number",
        lambda p: write_log(p, events=[event(statement=5)]),
        "/cosmos/event message 1: statement is not a string",
    ),
    Family(
        "segment-line-1e400",
        lambda p: write_log(p, segments=[b'{"t":0,"segment":0,"line":1e400}']),
        "/cosmos/segment message 1: line is not an integer",
    ),
    Family(
        "segment-axes",
        lambda p: write_log(p, segments=[segment(motion_axes=[2, 1, 1, 1, 1, 1])]),
        "/cosmos/segment message 1: motion_axes is not a list of six 0/1 values",
    ),
    Family(
        "segment-goal-inf",
        lambda p: write_log(p, segments=[encode(segment()).replace(b"0.33", b"1e999")]),
        "/cosmos/segment message 1: goal[2] is not a finite number",
    ),
    Family(
        "segment-timeout-negative",
        lambda p: write_log(p, segments=[segment(timeout=-1.0)]),
        "/cosmos/segment message 1: timeout is -1, outside",
    ),
    Family(
        "segment-statement-huge",
        lambda p: write_log(p, segments=[segment(statement="x" * 70_000)]),
        "/cosmos/segment message 1: statement is longer than 65,536 characters",
    ),
    Family(
        "metadata-value-huge",
        lambda p: write_log(p, meta=metadata(model="m" * 70_000)),
        "metadata 'cosmos': 'model' is longer than 65,536 characters",
    ),
    Family(
        "metadata-many",
        lambda p: write_log(p, meta={f"k{i}": "v" for i in range(1500)}),
        "metadata record 'cosmos' has more than 1000 entries",
    ),
    Family(
        "chunk-declares-1.5-GB",
        lambda p: raw_chunk_log(p, declared=1_500_000_000, real=1000),
        "the chunk at byte 25 decompresses to 1,500,000,000 bytes, more than the cap of 67,108,864",
    ),
)

READABLE_ESCAPES: Callable[[Path], Path] = lambda p: write_log(  # noqa: E731
    p,
    meta=metadata(program="tiny" + ESCAPES + ".cos", model=ESCAPES, cosmos_version=ESCAPES),
    segments=[segment(statement=ESCAPES, kind=ESCAPES)],
    events=[
        event(statement=ESCAPES, kind="start"),
        event(t=0.076, kind="failed", statement=ESCAPES, reason=ESCAPES),
    ],
)
"""A log whose metadata, statements, kinds and reasons carry escape sequences: read, made printable."""


def main(directory: str) -> None:
    """Write every crafted log of the corpus into ``directory``."""
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    for family in FAMILIES:
        family.write(out / f"{family.name}.mcap")
    READABLE_ESCAPES(out / "escapes.mcap")
    raw_chunk_log(out / "chunk-lies-about-its-size.mcap", declared=1000, real=200 * 1024**2)
    print(f"wrote {len(FAMILIES) + 2} crafted logs into {out}")


if __name__ == "__main__":
    main(sys.argv[1])
