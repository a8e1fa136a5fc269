"""Complete a cut run log: rewrite what can be read as a file with summary and index."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from mcap.writer import CompressionType, Writer

from cosmos.errors import UsageError
from cosmos.runlog.output import written
from cosmos.runlog.reader import RunRecord, run_record
from cosmos.runlog.scan import load_mcap
from cosmos.runlog.writer import DEFAULT_CHUNK_SIZE


@dataclass(frozen=True)
class Recovery:
    """What :func:`recover` wrote.

    Attributes:
        messages: Messages copied.
        attachments: Attachments copied.
        metadata: Metadata records copied.
        was_complete: Whether the input had a footer already (nothing was lost).
        readable_bytes: Bytes of the input that could be read.
        total_bytes: Size of the input.
        end_time_ns: Log time of the last message copied [ns] (0 if none).
        record: The input as :func:`cosmos.runlog.read_log` reads it (checked the same way).
    """

    messages: int
    attachments: int
    metadata: int
    was_complete: bool
    readable_bytes: int
    total_bytes: int
    end_time_ns: int
    record: RunRecord


def recover(cut_path: Path | str, out_path: Path | str, *, force: bool = False) -> Recovery:
    """Write everything readable in ``cut_path`` to a complete MCAP file ``out_path``.

    Schemas, channels, messages (in their order), attachments and metadata are
    copied; the output has chunk and message indexes, statistics, a summary and
    a footer. The input is not modified. It is read as :func:`cosmos.runlog.read_log`
    reads it, within the same caps and with every cosmos message checked: a log
    that ``cosmos replay`` refuses is not copied either.

    Args:
        cut_path: The log to recover.
        out_path: The complete copy to write (its directory must exist).
        force: Overwrite ``out_path`` if it exists.

    Raises:
        UsageError: If ``cut_path`` does not exist, is the same file as ``out_path``,
            or ``out_path`` cannot be written (see :mod:`cosmos.runlog.output`).
        CosmosError: If ``cut_path`` is not a cosmos log or holds a bad message.
    """
    cut_path, out_path = Path(cut_path), Path(out_path)
    if out_path.exists() and cut_path.exists() and out_path.samefile(cut_path):
        raise UsageError(f"{out_path}: recovering a log onto itself; choose another output path")
    contents = load_mcap(cut_path)
    run = run_record(cut_path, contents)
    with written(out_path, what="the log", force=force) as stream:
        writer = Writer(stream, chunk_size=DEFAULT_CHUNK_SIZE, compression=CompressionType.ZSTD)
        header = contents.header
        if header is None:
            writer.start()
        else:
            writer.start(profile=header.profile, library=header.library)
        for record in contents.metadata:
            writer.add_metadata(record.name, record.metadata)
        for attachment in contents.attachments:
            writer.add_attachment(
                create_time=attachment.create_time,
                log_time=attachment.log_time,
                name=attachment.name,
                media_type=attachment.media_type,
                data=attachment.data,
            )
        schema_ids = {
            old_id: writer.register_schema(schema.name, schema.encoding, schema.data)
            for old_id, schema in sorted(contents.schemas.items())
        }
        channel_ids = {
            old_id: writer.register_channel(
                channel.topic,
                channel.message_encoding,
                schema_ids.get(channel.schema_id, 0),
                dict(channel.metadata),
            )
            for old_id, channel in sorted(contents.channels.items())
        }
        end_time_ns = 0
        for message in contents.messages:
            writer.add_message(
                channel_ids[message.channel_id],
                log_time=message.log_time,
                data=message.data,
                publish_time=message.publish_time,
                sequence=message.sequence,
            )
            end_time_ns = max(end_time_ns, message.log_time)
        writer.finish()
    return Recovery(
        messages=len(contents.messages),
        attachments=len(contents.attachments),
        metadata=len(contents.metadata),
        was_complete=contents.complete,
        readable_bytes=contents.readable_bytes,
        total_bytes=contents.total_bytes,
        end_time_ns=end_time_ns,
        record=run,
    )
