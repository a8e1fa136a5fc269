"""``cosmos replay LOG --topics /a,/b``: the messages of some channels, one JSON line each.

Like ``mcap cat --json --topics``, decoded: JSON channels as they are,
Foxglove's protobuf messages with Foxglove's published schemas, ROS 2 CDR
messages with ``mcap-ros2-support`` when it is installed (else their size).
Each line is ``{"t": s, "topic": ..., "message": {...}}`` in log-time order.
The log is untrusted: each message is size-capped and must decode, or the
command stops with one line naming it.
"""

from __future__ import annotations

import importlib
import json
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any, Final

from cosmos.errors import CosmosError, UsageError
from cosmos.runlog.limits import MAX_SCENE_MESSAGE_BYTES
from cosmos.runlog.printable import printable
from cosmos.runlog.scan import load_mcap
from cosmos.runlog.validate import Invalid, decode

_FOXGLOVE: Final = ("foxglove.FrameTransforms", "foxglove.SceneUpdate", "foxglove.Log")


def _protobuf(schema: str, data: bytes) -> dict[str, Any]:
    if schema not in _FOXGLOVE:
        raise Invalid(f"protobuf schema {printable(schema[:80])!r} is not one cosmos writes")
    from google.protobuf.json_format import MessageToDict
    from google.protobuf.message import DecodeError

    name = schema.removeprefix("foxglove.")
    message_class = getattr(importlib.import_module(f"foxglove_schemas_protobuf.{name}_pb2"), name)
    try:
        message = message_class.FromString(data)
    except (DecodeError, RecursionError) as error:
        raise Invalid(f"not a protobuf {schema} ({str(error)[:80]})") from None
    return MessageToDict(message, preserving_proto_field_name=True)


def _ros2(schema: str, schema_data: bytes, data: bytes) -> dict[str, Any]:
    try:
        from mcap_ros2.decoder import DecoderFactory
    except ImportError:
        return {"cdr_bytes": len(data), "note": "install mcap-ros2-support to decode"}
    from mcap.records import Schema

    decoder = DecoderFactory().decoder_for(
        "cdr", Schema(id=0, data=schema_data, encoding="ros2msg", name=schema)
    )
    if decoder is None:
        raise Invalid(f"no ROS 2 decoder for {printable(schema[:80])!r}")
    try:
        return _plain(decoder(data))
    except Exception as error:  # noqa: BLE001 - the decoder's own errors vary: one line says which
        raise Invalid(f"not CDR of {printable(schema[:80])} ({printable(str(error))[:80]})") from None


def _plain(value: Any) -> Any:
    """A decoded ROS 2 message as JSON values."""
    if hasattr(value, "__slots__"):
        return {name: _plain(getattr(value, name)) for name in value.__slots__}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, bytes):
        return list(value)
    return value


def topic_lines(path: Path, topics: Sequence[str]) -> Iterator[str]:
    """One JSON line per message on ``topics``, in log-time order.

    Raises:
        UsageError: If a topic is not in the log (naming the ones it has).
        CosmosError: If a message does not decode, naming it.
    """
    contents = load_mcap(path)
    channels = {cid: c for cid, c in contents.channels.items() if c.topic in topics}
    missing = set(topics) - {c.topic for c in channels.values()}
    if missing:
        have = ", ".join(sorted({printable(c.topic) for c in contents.channels.values()}))
        names = ", ".join(sorted(printable(m) for m in missing))
        raise UsageError(f"{path}: no channel {names} (it has {have})")
    wanted = sorted(
        (m for m in contents.messages if m.channel_id in channels), key=lambda m: (m.log_time, m.channel_id)
    )
    counts: dict[int, int] = {}
    for message in wanted:
        channel = channels[message.channel_id]
        counts[message.channel_id] = n = counts.get(message.channel_id, 0) + 1
        schema = contents.schemas.get(channel.schema_id)
        name = schema.name if schema is not None else ""
        try:
            if len(message.data) > MAX_SCENE_MESSAGE_BYTES:
                raise Invalid(f"{len(message.data):,} bytes, more than {MAX_SCENE_MESSAGE_BYTES:,}")
            if channel.message_encoding == "json":
                decoded: Any = decode(message.data, MAX_SCENE_MESSAGE_BYTES)
            elif channel.message_encoding == "protobuf":
                decoded = _protobuf(name, message.data)
            elif channel.message_encoding == "cdr" and schema is not None:
                decoded = _ros2(name, schema.data, message.data)
            else:
                raise Invalid(
                    f"message encoding {printable(channel.message_encoding[:40])!r} is not readable"
                )
        except Invalid as error:
            raise CosmosError(f"{path}: {printable(channel.topic)} message {n}: {error}") from None
        line = {"t": message.log_time / 1e9, "topic": channel.topic, "message": decoded}
        yield printable(json.dumps(line, separators=(",", ":"), default=str))
