"""Foxglove protobuf messages decoded with Foxglove's published compiled schemas.

``foxglove-schemas-protobuf`` is Foxglove's own ``protoc`` output of its
``.proto`` files, a different implementation from the SDK (Rust) that writes
the logs: a message that decodes here and carries the expected values is a
well-formed official message. Decoded messages are given in the JSON shape of
the schema (field names as in the .proto, times as ``{sec, nsec}``, enums as
numbers), so tests compare them with what the JSON logs held.
"""

from __future__ import annotations

from typing import Any

from foxglove_schemas_protobuf.FrameTransforms_pb2 import FrameTransforms
from foxglove_schemas_protobuf.Log_pb2 import Log
from foxglove_schemas_protobuf.SceneUpdate_pb2 import SceneUpdate
from google.protobuf import descriptor_pb2
from google.protobuf.descriptor import FieldDescriptor
from google.protobuf.message import Message
from google.protobuf.unknown_fields import UnknownFieldSet

OFFICIAL = {
    "foxglove.FrameTransforms": FrameTransforms,
    "foxglove.SceneUpdate": SceneUpdate,
    "foxglove.Log": Log,
}


def _value(field: FieldDescriptor, value: Any) -> Any:
    if field.type == FieldDescriptor.TYPE_MESSAGE:
        return as_json(value)
    return value


def as_json(message: Message) -> dict[str, Any]:
    """The message in the JSON shape: every scalar and repeated field, set sub-messages."""
    name = message.DESCRIPTOR.full_name
    if name in ("google.protobuf.Timestamp", "google.protobuf.Duration"):
        return {"sec": message.seconds, "nsec": message.nanos}  # type: ignore[attr-defined]
    out: dict[str, Any] = {}
    for field in message.DESCRIPTOR.fields:
        value = getattr(message, field.name)
        if field.is_repeated:
            out[field.name] = [_value(field, v) for v in value]
        elif field.type == FieldDescriptor.TYPE_MESSAGE:
            if message.HasField(field.name):
                out[field.name] = as_json(value)
        else:
            out[field.name] = value
    return out


def decode(schema_name: str, data: bytes) -> dict[str, Any]:
    """Decode one message with the official class of ``schema_name`` (strict: no unknown fields)."""
    message = OFFICIAL[schema_name].FromString(data)
    assert len(UnknownFieldSet(message)) == 0, f"{schema_name}: fields the official schema lacks"
    return as_json(message)


def stored_schema_is_official(schema_name: str, schema_data: bytes) -> bool:
    """Whether an MCAP protobuf schema (a FileDescriptorSet) defines the message as Foxglove does."""
    stored = descriptor_pb2.FileDescriptorSet.FromString(schema_data)
    official = OFFICIAL[schema_name].DESCRIPTOR
    files = {f.name: f for f in stored.file}
    wanted = descriptor_pb2.FileDescriptorProto()
    official.file.CopyToProto(wanted)
    got = files.get(wanted.name)
    if got is None:
        return False
    got_message = next((m for m in got.message_type if m.name == official.name), None)
    want_message = next(m for m in wanted.message_type if m.name == official.name)
    return got_message is not None and _fields(got_message) == _fields(want_message)


def _fields(message: descriptor_pb2.DescriptorProto) -> list[tuple[str, int, int, str]]:
    return sorted((f.name, f.number, f.type, f.type_name.lstrip(".")) for f in message.field)
