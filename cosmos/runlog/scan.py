"""Read the records of an MCAP file, complete or cut short.

A complete file (footer and summary present) is read through its summary with
``mcap.reader``. A file without a usable footer (a run killed before it could
close its log) is walked record by record from the start; every record that
lies wholly within the file and parses (chunk CRCs checked) is kept, and the
walk stops at the first one that does not: what was flushed before the cut is
read, what was being written is dropped.
"""

from __future__ import annotations

import io
import struct
from dataclasses import dataclass, field
from pathlib import Path
from typing import Final

from mcap.exceptions import McapError
from mcap.opcode import Opcode
from mcap.reader import make_reader
from mcap.records import (
    Attachment,
    Channel,
    Chunk,
    Footer,
    Header,
    McapRecord,
    Message,
    Metadata,
    Schema,
)
from mcap.stream_reader import StreamReader, breakup_chunk

from cosmos.errors import CosmosError, UsageError

MAGIC: Final = b"\x89MCAP0\r\n"
_RECORD_PREFIX: Final = struct.Struct("<BQ")  # opcode, body length
_FOOTER_RECORD_SIZE: Final = _RECORD_PREFIX.size + 8 + 8 + 4


@dataclass
class McapContents:
    """What could be read from an MCAP file.

    Attributes:
        header: The header record, if read.
        schemas: Schema records by id.
        channels: Channel records by id (channels whose schema is missing are dropped).
        messages: Message records, in file order.
        attachments: Attachment records, in file order.
        metadata: Metadata records, in file order.
        complete: Whether the file ends with a footer and was read through its summary.
        readable_bytes: Length of the prefix of the file that was read.
        total_bytes: Size of the file.
    """

    header: Header | None = None
    schemas: dict[int, Schema] = field(default_factory=dict)
    channels: dict[int, Channel] = field(default_factory=dict)
    messages: list[Message] = field(default_factory=list)
    attachments: list[Attachment] = field(default_factory=list)
    metadata: list[Metadata] = field(default_factory=list)
    complete: bool = False
    readable_bytes: int = 0
    total_bytes: int = 0


def load_mcap(path: Path) -> McapContents:
    """Read every record of the MCAP file at ``path`` that can be read.

    Raises:
        UsageError: If there is no such file.
        CosmosError: If the file cannot be read or is not an MCAP file.
    """
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise UsageError(f"{path}: no such file") from None
    except OSError as error:
        raise CosmosError(f"{path}: cannot read: {error.strerror}") from None
    if not data.startswith(MAGIC):
        what = "empty" if not data else "does not start with the MCAP magic bytes"
        raise CosmosError(f"{path}: not an MCAP file ({what})")
    if _has_footer(data):
        contents = _read_through_summary(data)
        if contents is not None:
            return contents
    return _scan(data)


def _has_footer(data: bytes) -> bool:
    start = len(data) - len(MAGIC) - _FOOTER_RECORD_SIZE
    return (
        start >= len(MAGIC)
        and data.endswith(MAGIC)
        and data[start] == Opcode.FOOTER
        and _RECORD_PREFIX.unpack_from(data, start)[1] == _FOOTER_RECORD_SIZE - 9
    )


def _read_through_summary(data: bytes) -> McapContents | None:
    """The contents of a complete file, or None if its summary cannot be used."""
    try:
        reader = make_reader(io.BytesIO(data), validate_crcs=True)
        summary = reader.get_summary()
        if summary is None or not summary.chunk_indexes:
            return None
        contents = McapContents(
            header=reader.get_header(),
            schemas=dict(summary.schemas),
            channels=dict(summary.channels),
            messages=[m for _, _, m in reader.iter_messages(log_time_order=False)],
            attachments=list(reader.iter_attachments()),
            metadata=list(reader.iter_metadata()),
            complete=True,
            readable_bytes=len(data),
            total_bytes=len(data),
        )
    except Exception:  # noqa: BLE001 - a damaged summary or chunk: walk the file instead
        return None
    return contents


def _scan(data: bytes) -> McapContents:
    contents = McapContents(readable_bytes=len(MAGIC), total_bytes=len(data))
    position = len(MAGIC)
    while position + _RECORD_PREFIX.size <= len(data):
        _, length = _RECORD_PREFIX.unpack_from(data, position)
        end = position + _RECORD_PREFIX.size + length
        if end > len(data):
            break  # the record was being written when the file was cut
        try:
            records = _parse_record(data[position:end])
        except Exception:  # noqa: BLE001 - any failure to parse means a damaged record
            break
        for record in records:
            _keep(contents, record)
        position = end
        contents.readable_bytes = position
        if any(isinstance(r, Footer) for r in records):
            contents.complete = data[position:] == MAGIC
            break
    return contents


def _parse_record(raw: bytes) -> list[McapRecord]:
    """The records in one whole top-level record (a chunk holds several)."""
    reader = StreamReader(io.BytesIO(raw), skip_magic=True, emit_chunks=True, validate_crcs=True)
    records = reader.records
    try:
        record = next(records)
    except McapError:  # a record type this reader does not know: skipped
        return []
    if isinstance(record, Chunk):
        return breakup_chunk(record, validate_crc=True)
    return [record]


def _keep(contents: McapContents, record: McapRecord) -> None:
    match record:
        case Header():
            contents.header = record
        case Schema():
            contents.schemas[record.id] = record
        case Channel() if record.schema_id == 0 or record.schema_id in contents.schemas:
            contents.channels[record.id] = record
        case Message() if record.channel_id in contents.channels:
            contents.messages.append(record)
        case Attachment():
            contents.attachments.append(record)
        case Metadata():
            contents.metadata.append(record)
