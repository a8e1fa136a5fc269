"""Read the records of an MCAP file, complete or cut short, within the caps of :mod:`limits`.

The file is walked record by record from the start, complete or not: every
record that lies wholly within the file and parses (chunk CRCs checked) is
kept, and the walk stops at the footer or at the first record that does not
parse: what was flushed before a cut is read, what was being written is
dropped. The walk is bounded: a chunk is decompressed only up to its declared
size and only if that size is within :data:`~limits.MAX_CHUNK_BYTES`, and the
counts of records, messages and decompressed bytes are capped; a file past a
cap is refused with one line naming it, never read without end.
"""

from __future__ import annotations

import os
import stat
import struct
import zlib
from collections.abc import Callable
from dataclasses import dataclass, field
from io import BytesIO
from pathlib import Path
from typing import Final

from mcap.data_stream import ReadDataStream
from mcap.opcode import Opcode
from mcap.records import Attachment, Channel, Footer, Header, McapRecord, Message, Metadata, Schema

from cosmos.errors import CosmosError, UsageError
from cosmos.runlog import limits

MAGIC: Final = b"\x89MCAP0\r\n"
_PREFIX: Final = struct.Struct("<BQ")  # opcode, body length
_MESSAGE_HEAD: Final = struct.Struct("<HIQQ")  # channel id, sequence, log time, publish time
_CHUNK_HEAD: Final = struct.Struct("<QQQI")  # start time, end time, uncompressed size, crc
_U32: Final = struct.Struct("<I")
_U64: Final = struct.Struct("<Q")


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
        complete: Whether the file ends with a footer (and the magic after it).
        readable_bytes: Length of the prefix of the file that was read.
        total_bytes: Size of the file.
        chunks: Per compression (``zstd``, ``lz4``, ``none``), the chunks read: count,
            compressed bytes, uncompressed bytes.
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
    chunks: dict[str, tuple[int, int, int]] = field(default_factory=dict)


class _Damaged(Exception):
    """A record that does not parse: the walk stops before it."""


class _Walk:
    """The walk over one file: what was kept, and the counts that the caps bound."""

    def __init__(self, path: Path, data: bytes):
        self.path = path
        self.data = data
        self.contents = McapContents(readable_bytes=len(MAGIC), total_bytes=len(data))
        self.records = 0
        self.decompressed = 0

    def refuse(self, what: str) -> CosmosError:
        return CosmosError(f"{self.path}: {what}: not read")

    def count_record(self) -> None:
        self.records += 1
        if self.records > limits.MAX_RECORDS:
            raise self.refuse(f"more than {limits.MAX_RECORDS:,} MCAP records")

    def keep_message(self, message: Message) -> None:
        if message.channel_id in self.contents.channels:
            messages = self.contents.messages
            if len(messages) >= limits.MAX_MESSAGES:
                raise self.refuse(f"more than {limits.MAX_MESSAGES:,} messages")
            messages.append(message)

    def keep(self, record: McapRecord) -> None:
        contents = self.contents
        match record:
            case Header():
                contents.header = record
            case Schema():
                contents.schemas[record.id] = record
            case Channel() if record.schema_id == 0 or record.schema_id in contents.schemas:
                contents.channels[record.id] = record
            case Message():
                self.keep_message(record)
            case Attachment():
                if len(record.data) > limits.MAX_ATTACHMENT_BYTES:
                    raise self.refuse(
                        f"attachment of {len(record.data):,} bytes, more than {limits.MAX_ATTACHMENT_BYTES:,}"
                    )
                contents.attachments.append(record)
            case Metadata():
                if len(contents.metadata) >= limits.MAX_METADATA_ENTRIES:
                    raise self.refuse(f"more than {limits.MAX_METADATA_ENTRIES} metadata records")
                if len(record.metadata) > limits.MAX_METADATA_ENTRIES:
                    raise self.refuse(
                        f"metadata record {_quoted(record.name)} has more than "
                        f"{limits.MAX_METADATA_ENTRIES} entries"
                    )
                contents.metadata.append(record)

    def run(self) -> McapContents:
        data, contents = self.data, self.contents
        position = len(MAGIC)
        while position + _PREFIX.size <= len(data):
            opcode, length = _PREFIX.unpack_from(data, position)
            start = position + _PREFIX.size
            end = start + length
            if end > len(data):
                break  # the record was being written when the file was cut
            self.count_record()
            try:
                if opcode == Opcode.CHUNK:
                    self.chunk(position, start, end)
                elif opcode == Opcode.MESSAGE:
                    self.keep_message(_message(data, start, end))
                else:
                    record = _record(opcode, data[start:end])
                    if record is not None:
                        self.keep(record)
            except _Damaged:
                break
            position = end
            contents.readable_bytes = position
            if opcode == Opcode.FOOTER:
                contents.complete = data[position:] == MAGIC
                if contents.complete:
                    contents.readable_bytes = len(data)
                break
        return contents

    def chunk(self, offset: int, start: int, end: int) -> None:
        """Decompress the chunk in ``data[start:end]`` (within the caps) and keep its records."""
        data = self.data
        if end - start < _CHUNK_HEAD.size + 4:
            raise _Damaged
        _, _, size, crc = _CHUNK_HEAD.unpack_from(data, start)
        position = start + _CHUNK_HEAD.size
        (name_length,) = _U32.unpack_from(data, position)
        position += 4
        if position + name_length + 8 > end:
            raise _Damaged
        compression = data[position : position + name_length]
        position += name_length
        (records_length,) = _U64.unpack_from(data, position)
        position += 8
        if position + records_length != end:
            raise _Damaged
        if size > limits.MAX_CHUNK_BYTES:
            raise self.refuse(
                f"the chunk at byte {offset} decompresses to {size:,} bytes, "
                f"more than the cap of {limits.MAX_CHUNK_BYTES:,}"
            )
        self.decompressed += size
        if self.decompressed > limits.MAX_DECOMPRESSED_BYTES:
            raise self.refuse(f"chunks decompress to more than {limits.MAX_DECOMPRESSED_BYTES:,} bytes")
        records = _decompress(compression, data[position:end], size)
        if crc != 0 and zlib.crc32(records) != crc:
            raise _Damaged
        self.chunk_records(records)
        name = compression.decode("ascii", "replace") or "none"
        count, packed, unpacked = self.contents.chunks.get(name, (0, 0, 0))
        self.contents.chunks[name] = (count + 1, packed + records_length, unpacked + size)

    def chunk_records(self, records: bytes) -> None:
        """Keep the schemas, channels and messages of a decompressed chunk."""
        position = 0
        while position < len(records):
            if position + _PREFIX.size > len(records):
                raise _Damaged
            opcode, length = _PREFIX.unpack_from(records, position)
            start = position + _PREFIX.size
            end = start + length
            if end > len(records):
                raise _Damaged
            self.count_record()
            if opcode == Opcode.MESSAGE:
                self.keep_message(_message(records, start, end))
            elif opcode in (Opcode.SCHEMA, Opcode.CHANNEL):
                record = _record(opcode, records[start:end])
                if record is not None:
                    self.keep(record)
            elif opcode in _TOP_LEVEL_ONLY:
                raise _Damaged  # a chunk holds schemas, channels and messages only
            position = end


_TOP_LEVEL_ONLY: Final = frozenset(
    (
        Opcode.HEADER,
        Opcode.FOOTER,
        Opcode.CHUNK,
        Opcode.MESSAGE_INDEX,
        Opcode.CHUNK_INDEX,
        Opcode.ATTACHMENT,
        Opcode.ATTACHMENT_INDEX,
        Opcode.STATISTICS,
        Opcode.METADATA,
        Opcode.METADATA_INDEX,
        Opcode.SUMMARY_OFFSET,
        Opcode.DATA_END,
    )
)


def _quoted(text: str) -> str:
    from cosmos.runlog.printable import printable

    return repr(printable(text[:60]))


def _message(data: bytes, start: int, end: int) -> Message:
    if end - start < _MESSAGE_HEAD.size:
        raise _Damaged
    channel_id, sequence, log_time, publish_time = _MESSAGE_HEAD.unpack_from(data, start)
    return Message(
        channel_id=channel_id,
        sequence=sequence,
        log_time=log_time,
        publish_time=publish_time,
        data=data[start + _MESSAGE_HEAD.size : end],
    )


_READERS: Final[dict[int, Callable[[ReadDataStream], McapRecord]]] = {
    Opcode.HEADER: Header.read,
    Opcode.FOOTER: Footer.read,
    Opcode.SCHEMA: Schema.read,
    Opcode.CHANNEL: Channel.read,
    Opcode.ATTACHMENT: Attachment.read,
    Opcode.METADATA: Metadata.read,
}


class _Exact(ReadDataStream):
    """A record's fields, read from its body; a field that runs past the body is damage."""

    def read(self, length: int) -> bytes:
        data = super().read(length) if length else b""
        if len(data) != length:
            raise _Damaged
        return data


def _record(opcode: int, body: bytes) -> McapRecord | None:
    """The record of a kind cosmos reads, parsed from its whole body; None for other kinds."""
    read = _READERS.get(opcode)
    if read is None:
        return None
    stream = _Exact(BytesIO(body))
    try:
        record = read(stream)
    except _Damaged:
        raise
    except Exception as error:  # noqa: BLE001 - a malformed or mis-encoded record
        raise _Damaged from error
    if opcode == Opcode.ATTACHMENT:
        # The last four bytes are the CRC of the fields before them (0: none).
        if stream.count != len(body):
            raise _Damaged
        (crc,) = _U32.unpack_from(body, len(body) - 4)
        if crc != 0 and zlib.crc32(body[:-4]) != crc:
            raise _Damaged
    return record


def _decompress(compression: bytes, data: bytes, size: int) -> bytes:
    """The chunk's records, decompressed to exactly ``size`` bytes (never more is produced)."""
    try:
        if compression == b"":
            out = data
        elif compression == b"zstd":
            import zstandard

            with zstandard.ZstdDecompressor().stream_reader(BytesIO(data)) as reader:
                out = reader.read(size + 1)
        elif compression == b"lz4":
            import lz4.frame

            out = lz4.frame.LZ4FrameDecompressor().decompress(data, max_length=size + 1)
        else:
            raise _Damaged
    except _Damaged:
        raise
    except Exception as error:  # noqa: BLE001 - corrupt compressed data
        raise _Damaged from error
    if len(out) != size:
        raise _Damaged
    return out


def read_file(path: Path, what: str, cap: int) -> bytes:
    """The bytes of a regular file of at most ``cap`` bytes, read without blocking on a FIFO.

    Raises:
        UsageError: If there is no such file.
        CosmosError: If it is not a regular file, is larger than ``cap``, or cannot be read.
    """
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise UsageError(f"{path}: no such file") from None
    except OSError as error:
        raise CosmosError(f"{path}: cannot read: {error.strerror}") from None
    info = os.fstat(fd)
    problem = None
    if stat.S_ISDIR(info.st_mode):
        problem = f"is a directory, not a {what}"
    elif not stat.S_ISREG(info.st_mode):
        problem = f"not a regular file, so not a {what}"
    elif info.st_size > cap:
        problem = f"{info.st_size:,} bytes, more than the {cap:,} a {what} may have"
    if problem is not None:
        os.close(fd)
        raise CosmosError(f"{path}: {problem}")
    with os.fdopen(fd, "rb") as stream:
        try:
            data = stream.read(cap + 1)
        except OSError as error:
            raise CosmosError(f"{path}: cannot read: {error.strerror}") from None
    if len(data) > cap:
        raise CosmosError(f"{path}: more than the {cap:,} bytes a {what} may have")
    return data


def load_mcap(path: Path) -> McapContents:
    """Read every record of the MCAP file at ``path`` that can be read, within the caps.

    Raises:
        UsageError: If there is no such file.
        CosmosError: If the file cannot be read, is not an MCAP file, or is past a cap.
    """
    data = read_file(path, "run log", limits.MAX_LOG_BYTES)
    if not data.startswith(MAGIC):
        what = "empty" if not data else "does not start with the MCAP magic bytes"
        raise CosmosError(f"{path}: not an MCAP file ({what})")
    return _Walk(path, data).run()
